"""The brush tire on the shipped default grid (summer compound on asphalt): the cold/hot effect
of eq. (28) in mu-slip curves, and the s0 limits."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lookup.grid import FrictionGrid, load_grid
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush

KAPPA = -np.array([0.005, 0.01, 0.02, 0.04, 0.08, 0.15, 0.3, 0.5])
VX, FZ = 20.0, 4000.0


@pytest.fixture(scope="module")
def grid() -> FrictionGrid:
    return load_grid("default")


def _one_branch(grid: FrictionGrid, branch: str) -> FrictionGrid:
    """The default grid with both branches set to one of them (the exact 'X-only' tire)."""
    mu = grid[branch]
    variables = {n: grid[n] for n in grid.variables}
    variables["mu_cold"] = mu
    variables["mu_hot"] = mu
    return FrictionGrid.from_arrays(grid.v, grid.T, grid.p, variables,
                                    s0_m=grid.meta["s0_m"], D_m=grid.meta["D_m"])


def _mu_curve(friction, T_C: float, ageing: bool | None = None) -> np.ndarray:
    """mu-slip curve of the shipped tire (``ageing``: its contact age on / off, None: the
    tire file's)."""
    tire = load_tire("passenger")
    if ageing is not None:
        tire = dataclasses.replace(tire, tread=dataclasses.replace(tire.tread,
                                                                   contact_ageing=ageing))
    out = SteadyBrush(tire, friction).solve(KAPPA, 0.0, VX, FZ, T_C + 273.15)
    return -out.Fx / FZ


@pytest.mark.parametrize("T_C", [20.0, 50.0, 80.0])
def test_s0_limits_recover_single_branch_tires(grid, T_C) -> None:
    """s0 -> 0: every element is on the hot branch at once; s0 -> infinity: it never leaves
    the cold branch. Both equal a tire on a grid holding only that branch. 1e-9 m and 1e6 m
    make exp(-s/s0) = 0 or 1 to round-off for the micrometre-to-centimetre slip distances in
    the patch, hence the tight tolerance (1e-6 of Fz). These are eq. (28)'s limits, with the
    friction read at the slip speed: the contact age is off (its length D = s0 / 0.2 would
    move with s0 to 5 nm and 5000 km; docs/tire-core.md, "contact age")."""
    hot_only = _mu_curve(GridFriction(_one_branch(grid, "mu_hot")), T_C, ageing=False)
    cold_only = _mu_curve(GridFriction(_one_branch(grid, "mu_cold")), T_C, ageing=False)
    np.testing.assert_allclose(_mu_curve(GridFriction(grid, s0=1e-9), T_C, ageing=False),
                               hot_only, atol=1e-6, err_msg="s0 -> 0 gives the hot-only tire")
    np.testing.assert_allclose(_mu_curve(GridFriction(grid, s0=1e6), T_C, ageing=False),
                               cold_only, atol=1e-6, err_msg="s0 -> inf gives the cold-only tire")


def test_cold_hot_effect_at_operating_temperature(grid) -> None:
    """At 50 C (the summer tread's operating temperature) the hot branch lies below the cold one
    at slip speeds above ~1 cm/s. With the surface's s0 = 0.2 D = 0.2 mm an element has slipped
    several s0 once the slip exceeds a few percent, so the curve follows the hot branch there,
    far below the cold-only tire; at small slip the elements are still (mostly) cold and the
    curve lies between the branches, closer to the cold-only tire. Measured: cold-only / hot-only
    1.26-1.29 at slips of 15-50 %, the peaks 1.68 against 1.32 (the bounds below: 1.2), cold
    share 0.69 at 2 % slip."""
    T_C = 50.0
    hot = _mu_curve(GridFriction(_one_branch(grid, "mu_hot")), T_C)
    cold = _mu_curve(GridFriction(_one_branch(grid, "mu_cold")), T_C)
    mu = _mu_curve(GridFriction(grid), T_C)
    assert grid.meta["s0_m"] == pytest.approx(0.2 * grid.meta["D_m"])
    large = np.abs(KAPPA) >= 0.15
    np.testing.assert_allclose(mu[large], hot[large], rtol=5e-3,
                               err_msg="large slip: elements on the hot branch")
    assert (cold[large] > 1.2 * hot[large]).all(), "hot branch clearly below cold at 50 C"
    assert cold.max() > 1.2 * mu.max(), "flash heating lowers the peak of the mu-slip curve"
    small = np.abs(KAPPA) == 0.02
    assert hot[small] < mu[small] < cold[small], "small slip: between the branches"
    w_cold = (mu[small] - hot[small]) / (cold[small] - hot[small])
    assert w_cold > 0.3, f"small slip: a large cold share remains ({w_cold[0]:.2f})"


def test_glassy_side_hot_above_cold(grid) -> None:
    """At 20 C the compound is glassy at slip speeds above ~1 cm/s (its friction maximum is at
    ~1 cm/s, review sec. 5.2): flash heating moves it towards its maximum, so the hot branch
    and the large-slip curve lie above the cold-only tire."""
    T_C = 20.0
    cold = _mu_curve(GridFriction(_one_branch(grid, "mu_cold")), T_C)
    mu = _mu_curve(GridFriction(grid), T_C)
    assert (mu[np.abs(KAPPA) >= 0.15] > cold[np.abs(KAPPA) >= 0.15]).all()
