"""Friction adapters of the brush model: the table reproduces the grid reader exactly, eq. (28)
limits, input checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from brush_cases import peaked_grid

from lookup.errors import InputError
from lookup.grid import FrictionGrid
from tire_brush.friction import (
    BranchTable,
    ConstantFriction,
    FrictionModel,
    GridFriction,
    as_table,
    blend,
    cold_weight,
)


def _random_grid(rng) -> FrictionGrid:
    v = np.logspace(-6, 1.6, 31)
    T = np.linspace(253.15, 393.15, 8)
    p = np.logspace(4.7, 6.3, 5)
    variables = {n: rng.random((31, 8, 5)) for n in ("mu_cold", "mu_hot", "dT_flash")}
    return FrictionGrid.from_arrays(v, T, p, variables, s0_m=2e-4, D_m=1e-3)


def test_table_reproduces_grid_interpolation(rng) -> None:
    """On the grid's own nodes the table is the grid's multilinear interpolant: equal to
    rounding (1e-12) for random queries, in range and clamped out of range."""
    grid = _random_grid(rng)
    table = as_table(grid)
    n = 2000
    v = 10 ** rng.uniform(-8, 3, n)
    T = rng.uniform(230, 420, n)
    p = 10 ** rng.uniform(3.5, 7, n)
    expect = grid.interpolate(v, T, p)
    got = table.evaluate(v, T, p)
    for k, name in enumerate(("mu_cold", "mu_hot", "dT_flash")):
        np.testing.assert_allclose(got[k], expect[name], rtol=0, atol=1e-12, err_msg=name)
    vals = table.evaluate_at(v[:50], 300.0, p[:50])
    ref = grid.interpolate(v[:50], 300.0, p[:50])
    np.testing.assert_allclose(vals[0], ref["mu_cold"], rtol=0, atol=1e-12)
    q = table.prepare(300.0, p[:50])
    low = table.evaluate(np.zeros(50), 300.0, p[:50])
    np.testing.assert_allclose(q.mu0, np.stack(low[0:2]), rtol=0, atol=1e-12,
                               err_msg="prepared v -> 0 branches (stick threshold)")


def test_table_slopes_match_finite_differences(rng) -> None:
    """d mu / d ln v of the table equals a centred difference inside a cell, 0 below v_min."""
    table = as_table(_random_grid(rng))
    v = np.array([3.3e-5, 0.02, 7.0])
    p = np.full(3, 2e5)
    _, d = table.evaluate_at(v, 300.0, p, slope=True)
    h = 1e-6
    up = table.evaluate_at(v * (1 + h), 300.0, p)
    dn = table.evaluate_at(v * (1 - h), 300.0, p)
    fd = (up[0:2] - dn[0:2]) / (np.log1p(h) - np.log1p(-h))
    np.testing.assert_allclose(d, fd, rtol=1e-5, atol=1e-9)
    _, d0 = table.evaluate_at(np.array([1e-9]), 300.0, np.array([2e5]), slope=True)
    assert np.all(d0 == 0), "constant below the first speed node"


def test_eq28_blend_limits() -> None:
    s = np.array([0.0, 1e-9, 1e-3, 1.0])
    assert np.array_equal(cold_weight(s, 0.0), [1.0, 0.0, 0.0, 0.0]), "s0 = 0: hot once slipped"
    assert np.array_equal(cold_weight(s, math.inf), np.ones(4)), "s0 = inf: always cold"
    np.testing.assert_allclose(blend(1.0, 0.6, 2e-4, 2e-4), 0.6 + 0.4 * math.exp(-1.0),
                               rtol=1e-15)


def test_providers() -> None:
    c = ConstantFriction(0.9)
    assert isinstance(c, FrictionModel)
    mc, mh, dT = c.branches(np.ones(3), 300.0, 2e5)
    assert np.all(mc == 0.9) and np.all(mh == 0.9) and np.all(dT == 0)
    sk = ConstantFriction.static_kinetic(1.2, 0.8)
    assert sk.s0 == 0.0 and sk.mu_cold == 1.2 and sk.mu_hot == 0.8
    g = GridFriction(peaked_grid(s0=3e-4))
    assert g.s0 == 3e-4 and GridFriction(peaked_grid(), s0=0.0).s0 == 0.0
    table = BranchTable.from_model(c)
    assert table.describe()["kind"] == "constant"
    assert as_table(table) is table
    with pytest.raises(InputError, match="s0"):
        ConstantFriction(1.0, s0=-1.0)
    with pytest.raises(InputError, match="mu_cold"):
        ConstantFriction(math.nan)
    with pytest.raises(InputError, match="friction provider"):
        as_table(object())
    with pytest.raises(InputError, match="NaN"):
        table.evaluate(np.nan, 300.0, 2e5)
