"""Interpolation error of grids against direct engine evaluation at random off-node points.

The bound is stated here (aim: < 1 % in mu). Measured with the default spec's
node spacing (61 x 81 x 15; ``models/grids/default.toml``), on a window of it and, once it has
been built, on the shipped default grid:

* window v 10^-3.5 ... 10^-1 m/s, T -20 ... 2 C, 4 pressures (20 x 12 x 4 nodes, 200
  points): |mu_grid / mu_engine - 1| median 0.21-0.23 %, 95th percentile 0.8 %, max 1.3 %
  (cold and hot);
* the shipped default grid (400 points over all of it): median 0.14 %, p95 0.5 %,
  max 1.4 % (cold and hot); with ``v_interp="pchip"`` see the last test. Two of the 400
  points lie in cells across the fold of the hot branch (15 m/s at -19 C and 0.14 MPa,
  4.4 m/s at -5 C and 0.7 MPa: there the flash temperature jumps from 13 to 57 K between two
  speed nodes,
  docs/physics.md sec. 3), where the grid is 2 % and 9 % off; such cells (at most 1 % of
  the points) are left out of the hot branch's bounds.

The assertions below are those bounds with a margin: median < 0.5 %, 95th percentile < 1 %,
max < 3 %. The largest errors sit where mu(v) turns fastest (the low-temperature flank of the
friction maximum: the WLF shift is steepest there).
"""

from __future__ import annotations

import numpy as np
import pytest

from lookup.grid import load_grid
from lookup.grid.build import build_grid, make_model
from lookup.grid.spec import load_spec
from tirefric.errors import InputError

pytest.importorskip("lookup.friction")

SEED = 31


def relative_errors(grid, model, n, rng, box=None, points=False):
    lo = [grid.log10_v[0], grid.T[0], grid.log10_p[0]] if box is None else box[0]
    hi = [grid.log10_v[-1], grid.T[-1], grid.log10_p[-1]] if box is None else box[1]
    lv, T, lp = (rng.uniform(lo[k], hi[k], n) for k in range(3))
    v, p = 10**lv, 10**lp
    got = grid.interpolate(v, T, p, names=("mu_cold", "mu_hot"))
    cold = model.cold(v, T, p).mu
    hot = model.hot(v, T, p).mu
    errors = {"mu_cold": np.abs(got["mu_cold"] / cold - 1),
              "mu_hot": np.abs(got["mu_hot"] / hot - 1)}
    return (errors, (v, T, p)) if points else errors


def fold_cells(grid, v, T, p):
    """Points whose grid cell straddles the fold of the hot branch: the flash temperature at
    the cell's 8 corner nodes jumps (max - min > 20 K and max > 2 min), docs/physics.md sec. 3
    (S-shaped response, thermal runaway). No interpolation of node values follows a jump
    inside a cell."""
    dT = grid["dT_flash"]
    idx = [np.clip(np.searchsorted(ax, x) - 1, 0, ax.size - 2)
           for ax, x in ((grid.log10_v, np.log10(v)), (grid.T, T), (grid.log10_p, np.log10(p)))]
    corners = np.stack([dT[idx[0] + a, idx[1] + b, idx[2] + c]
                        for a in (0, 1) for b in (0, 1) for c in (0, 1)])
    hi, lo = corners.max(axis=0), corners.min(axis=0)
    return (hi - lo > 20.0) & (hi > 2.0 * lo)


def check_bounds(errors, where):
    for name, e in errors.items():
        med, p95, mx = np.median(e), np.percentile(e, 95), e.max()
        print(f"{where} {name}: median {med:.2%}, p95 {p95:.2%}, max {mx:.2%}")
        assert med < 0.005, f"{where}: median relative error of {name} {med:.3%} >= 0.5 %"
        assert p95 < 0.01, f"{where}: 95th percentile of {name} error {p95:.3%} >= 1 %"
        assert mx < 0.03, f"{where}: max relative error of {name} {mx:.3%} >= 3 %"


def test_default_spacing_on_a_window(tmp_path):
    """A block of the default spec (its node spacing), where mu(v, T) changes fastest."""
    spec = load_spec("default")
    lv = np.log10(spec.v)
    iv = np.flatnonzero((lv >= -3.5) & (lv <= -1.0))
    iT = np.flatnonzero((spec.T >= 253.15) & (spec.T <= 275.0))
    sub = spec.with_axes(v=spec.v[iv], T=spec.T[iT], p=spec.p[3:7])
    model = make_model(sub)
    grid, _ = build_grid(sub, tmp_path / "window.nc", model=model, workers=1, progress=False)
    errors = relative_errors(grid, model, 200, np.random.default_rng(SEED))
    check_bounds(errors, f"window {sub.shape}")


@pytest.mark.parametrize("v,T_C,p", [(1.0, 20.0, 3e5), (0.1, 20.0, 1e6), (1.0, 40.0, 3e5)])
def test_default_grid_nodes_against_bruteforce(v, T_C, p):
    """The shipped grid against a reference that shares no code with the engine
    (:mod:`persson_reference`): eqs. (17)-(20) by direct quadrature with the summer compound's
    Prony arms (the arms sampling its relaxation spectrum), its WLF law and its softening
    factors written out here (C1 = 9.316, C2 = 96.6 K at 20 C; the table's row at strain 0.1:
    eta_R = 0.30, eta_I = 0.48) and the asphalt's roll-off
    spectrum (q0 = 200, q_r = 295 1/m, H = 0.65, h_rms = 0.7 mm) up to the grid's stored q1.
    At grid nodes the grid holds the engine's values; measured engine/reference - 1 is
    0.02-0.04 % in mu_visc_cold (default q and modulus-table resolution) and 0.03-0.05 % in
    area_cold; asserted: 0.5 % and 0.2 %. A wrong prefactor or exponent is tens of percent."""
    from persson_reference import mu_visc_general, prony_modulus, rolloff_C

    from lookup.compound import load_compound

    try:
        grid = load_grid("default")
    except InputError:
        pytest.skip("the default grid has not been built yet")
    iv = int(np.argmin(np.abs(grid.log10_v - np.log10(v))))
    iT = int(np.argmin(np.abs(grid.T - (T_C + 273.15))))
    ip = int(np.argmin(np.abs(grid.log10_p - np.log10(p))))
    v, T, p = 10 ** grid.log10_v[iv], grid.T[iT], 10 ** grid.log10_p[ip]
    prony = load_compound(grid.meta["compound_name"]).modulus.prony
    eta_R, eta_I = 0.30, 0.48
    la = -9.316 * (T - 293.15) / (96.6 + T - 293.15)

    def E(w):
        Z = prony_modulus(w * 10**la, prony.E_inf, prony.E_k, prony.tau_k)
        return eta_R * Z.real + 1j * eta_I * Z.imag

    def C(q):
        return rolloff_C(q, 200.0, 295.0, 0.65, 0.7e-3)

    mu, area = mu_visc_general(v, p, 0.5, E, C, 200.0, float(grid.meta["q1_per_m"]),
                               n_phi=1000)
    got = grid.interpolate(v, T, p, names=("mu_visc_cold", "area_cold"))
    assert float(got["mu_visc_cold"]) == pytest.approx(mu, rel=5e-3), "mu_visc_cold, eq. (17)"
    assert float(got["area_cold"]) == pytest.approx(area, rel=2e-3), "area_cold, eqs. (18)-(19)"


def test_default_grid_against_engine():
    """Golden comparison: the engine reproduces the shipped grid (which it built); the grid
    itself is pinned by the independent reference above."""
    try:
        grid = load_grid("default")
    except InputError:
        pytest.skip("the default grid has not been built yet (tirefric grid build default "
                    "-o models/grids/default.nc)")
    spec = load_spec("default")
    model = make_model(spec)
    errors, (v, T, p) = relative_errors(grid, model, 400, np.random.default_rng(SEED),
                                        points=True)
    fold = fold_cells(grid, v, T, p)
    assert fold.sum() <= 4, f"{fold.sum()} of 400 points in cells across the hot branch's fold"
    check_bounds({"mu_cold": errors["mu_cold"], "mu_hot": errors["mu_hot"][~fold]},
                 "default grid")


def test_default_grid_pchip_along_v():
    """The optional monotone cubic along log10 v removes most of the v part of the error.

    Points off-node in v only (T and p on nodes), cold branch. Measured on these 300 points:
    linear p95 0.28 %, max 0.34 %; pchip p95 0.005 %, max 0.027 % (on another 600-point
    sample, max 0.069 %). Asserted with margin:
    pchip p95 < 0.05 % and max < 0.3 %, and pchip below linear at p95 and max. (Off-node in all
    three axes the T part dominates: linear p95 0.51 %, max 1.9 %; pchip p95 0.46 %, max
    1.8 %.)
    """
    try:
        grid = load_grid("default")
    except InputError:
        pytest.skip("the default grid has not been built yet")
    model = make_model(load_spec("default"))
    rng = np.random.default_rng(SEED + 1)
    n = 300
    lv = rng.uniform(grid.log10_v[0], grid.log10_v[-1], n)
    T = grid.T[rng.integers(0, grid.T.size, n)]
    p = 10 ** grid.log10_p[rng.integers(0, grid.log10_p.size, n)]
    ref = model.cold(10**lv, T, p).mu
    err = {m: np.abs(grid.interpolate_one("mu_cold", 10**lv, T, p, v_interp=m) / ref - 1)
           for m in ("linear", "pchip")}
    for m, e in err.items():
        print(f"v off-node, {m}: median {np.median(e):.3%}, p95 {np.percentile(e, 95):.3%}, "
              f"max {e.max():.3%}")
    assert np.percentile(err["pchip"], 95) < 5e-4 and err["pchip"].max() < 3e-3
    assert np.percentile(err["pchip"], 95) < np.percentile(err["linear"], 95)
    assert err["pchip"].max() < err["linear"].max()

