"""Friction adapters of the brush model: the table reproduces the grid reader exactly, eq. (28)
limits, input checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from brush_cases import peaked_grid

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
from tirefric.errors import InputError


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


def test_core_table_arithmetic_reproduces_grid_interpolation(rng) -> None:
    """The tire core's own table lookup (bilinear in T and log10 p at the two speed nodes,
    linear in log10 v between them, clamped; written out in tire_brush.element and equal to
    the C) against the grid reader's multilinear interpolation: equal to rounding."""
    from tire_brush.element import RefTable

    grid = _random_grid(rng)
    table = as_table(grid)
    t = RefTable(table.log10_v, table.T, table.log10_p, table.values, table.inv_s0)
    n = 300
    v = 10 ** rng.uniform(np.log10(table.v_floor) + 1e-9, table.log10_v[-1] - 1e-9, n)
    T = rng.uniform(table.T[0], table.T[-1], n)
    p = 10 ** rng.uniform(table.log10_p[0], table.log10_p[-1], n)
    expect = grid.interpolate(v, T, p)
    for i in range(n):
        iT, fT = t.locate(1, float(T[i]))
        q = t.prep(iT, fT, float(p[i]))
        j, f = t.locate(0, float(np.log10(v[i])))
        a, b = t.node(q, j), t.node(q, j + 1)
        for k, name in enumerate(("mu_cold", "mu_hot", "dT_flash")):
            assert a[k] + (b[k] - a[k]) * f == pytest.approx(expect[name][i], abs=1e-12)


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
