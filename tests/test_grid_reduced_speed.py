"""Interpolation across T at fixed reduced speed log10(v a_T(T)).

The multilinear grid interpolation at fixed log10 v has its largest errors from the T axis
(default grid, cold branch, 600 random points off-node in all axes: max 1.7 %). By
time-temperature superposition the cold branch depends on v and T only through v a_T(T) (the
shipped summer compound's adhesive law shifts with the bulk a_T), so interpolating across T
at fixed reduced speed removes that part. Measured on the shipped default grid (cold branch,
pchip along v; ``T_interp="linear"`` -> ``"reduced_speed"``):

* T and v off-node, p on nodes (600 points): p95 0.33 % -> 0.006 %, max 1.82 % -> 0.067 %
  (next to v_min the upper T node alone is read, next to v_max the lower one, both at the
  query's reduced speed);
* all three axes off-node (600 points, linear along log10 p): median 0.064 % -> 0.011 %,
  p95 0.37 % -> 0.32 %, max 1.70 % -> 0.65 %: what remains is the pressure axis (15 nodes;
  above ~80 C and 1 MPa the compound nears full contact and mu bends in log p), which
  ``p_interp="pchip"`` removes (``tests/test_grid_interp_p.py``).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from grid_cases import default_grid, reduced_speed_linear_grid

from lookup.grid.reader import FrictionGrid, shift_from_meta
from lookup.shift import WLF, TabulatedShift
from tirefric.errors import GridError

pytest.importorskip("lookup.friction")


def test_shift_from_meta_matches_lookup_shift() -> None:
    """The numpy-only copy of the shift laws equals lookup.shift (WLF with its continuation
    below T_ref - 0.9 C2, and a table with its linear ends)."""
    T = np.linspace(150.0, 420.0, 300)
    w = WLF(15.0, 150.0, 293.15)
    f = shift_from_meta({"compound": {"shift": w.describe()}})
    np.testing.assert_allclose(f(T), w.log10_aT(T), rtol=0, atol=1e-12)
    t = TabulatedShift(np.array([250.0, 280.0, 300.0, 330.0]), np.array([4.0, 1.0, -0.2, -1.5]),
                       293.15)
    f = shift_from_meta({"compound": {"shift": t.describe()}})
    np.testing.assert_allclose(f(T), t.log10_aT(T), rtol=0, atol=1e-12)
    with pytest.raises(GridError, match="reduced_speed"):
        shift_from_meta({"compound": {"shift": {"model": "arrhenius"}}}, "g.nc")


def synthetic_grid(C1=8.0, C2=120.0, T_ref=293.15):
    """A grid of a function of reduced speed only: mu = f(log10 v + log10 a_T(T)) g(p)."""
    lv = np.linspace(-6, 1.6, 77)
    T = np.linspace(253.15, 393.15, 15)  # 10 K apart: far too coarse for fixed-v blending
    lp = np.linspace(4.7, 6.3, 5)
    w = WLF(C1, C2, T_ref)

    def mu(lv, T, lp):
        x = lv + w.log10_aT(T)
        return (0.6 + 0.9 * np.exp(-0.5 * ((x + 2.0) / 1.3) ** 2)) * (1.2 - 0.1 * lp / 6)

    V, TT, P = np.meshgrid(lv, T, lp, indexing="ij")
    vals = mu(V, TT, P)
    g = FrictionGrid(lv, T, lp, {"mu_cold": vals, "mu_hot": vals, "dT_flash": 0 * vals},
                     {"s0_m": 2e-4, "D_m": 1e-3, "compound": {"shift": w.describe()}})
    return g, mu


@pytest.mark.parametrize("v_interp", ["linear", "pchip"])
def test_reduced_speed_is_exact_for_a_function_of_reduced_speed(v_interp) -> None:
    """mu linear in the reduced speed x = log10(v a_T): every T node is interpolated exactly
    along v, so the blend at fixed x is exact to round-off; blending at fixed v is not
    (log10 a_T is not linear in T)."""
    g, w, _, _ = reduced_speed_linear_grid()
    rng = np.random.default_rng(5)
    Tq = rng.uniform(260.0, 385.0, 300)
    lpq = rng.uniform(4.7, 6.3, 300)
    lvq = rng.uniform(-2.5, -1.5, 300)  # shifted speeds stay inside the v axis
    ref = 1.0 + 0.05 * (lvq + w.log10_aT(Tq)) + 0.01 * lpq
    red = g.interpolate_one("mu_cold", 10**lvq, Tq, 10**lpq, v_interp=v_interp,
                            T_interp="reduced_speed")
    np.testing.assert_allclose(red, ref, rtol=1e-12)
    fixed = g.interpolate_one("mu_cold", 10**lvq, Tq, 10**lpq, v_interp=v_interp)
    assert np.abs(fixed / ref - 1).max() > 1e-4


@pytest.mark.parametrize("v_interp", ["linear", "pchip"])
def test_reduced_speed_beats_fixed_v_on_a_coarse_T_axis(v_interp) -> None:
    g, mu = synthetic_grid()
    rng = np.random.default_rng(6)
    lv, T, lp = rng.uniform(-3.0, 0.5, 400), rng.uniform(300.0, 385.0, 400), rng.uniform(
        4.7, 6.3, 400)
    ref = mu(lv, T, lp)
    e = {ti: np.abs(g.interpolate_one("mu_cold", 10**lv, T, 10**lp, v_interp=v_interp,
                                      T_interp=ti) / ref - 1)
         for ti in ("linear", "reduced_speed")}
    assert e["reduced_speed"].max() < 0.2 * e["linear"].max()


def test_reduced_speed_keeps_nodes_counts_and_errors() -> None:
    g, _ = synthetic_grid()
    V, TT, P = np.meshgrid(10**g.log10_v[10:60:7], g.T, 10**g.log10_p, indexing="ij")
    got = g.interpolate_one("mu_cold", V, TT, P, T_interp="reduced_speed")
    np.testing.assert_allclose(got, g["mu_cold"][10:60:7], rtol=1e-12)
    g.reset_out_of_range_count()
    g.interpolate_one("mu_cold", [1e-3, 1e-3], [200.0, 300.0], [3e5, 3e5],
                      T_interp="reduced_speed")
    assert g.out_of_range_detail["T"] == {"below": 1, "above": 0}
    with pytest.raises(GridError, match="NaN"):
        g.interpolate_one("mu_cold", [1e-3], [np.nan], [3e5], T_interp="reduced_speed")
    with pytest.raises(GridError, match="unknown interpolation across T"):
        g.interpolate_one("mu_cold", [1e-3], [300.0], [3e5], T_interp="cubic")
    plain = FrictionGrid(g.log10_v, g.T, g.log10_p, {k: g[k] for k in g.variables},
                         {"s0_m": 2e-4, "D_m": 1e-3})
    with pytest.raises(GridError, match="shift factor"):
        plain.interpolate_one("mu_cold", [1e-3], [300.0], [3e5], T_interp="reduced_speed")
    # the default stays the multilinear interpolation
    assert plain.interpolate_one("mu_cold", [1e-3], [300.0], [3e5])[0] == pytest.approx(
        g.interpolate_one("mu_cold", [1e-3], [300.0], [3e5])[0], rel=0)


def test_default_grid_reduced_speed_against_engine() -> None:
    """Shipped default grid: T and v off-node, p on nodes, cold branch. Measured (module
    docstring): pchip + reduced_speed p95 0.006 %, max 0.067 % (also within 0.2 decade of
    the v ends); asserted with margin."""
    from lookup.grid.build import make_model
    from lookup.grid.spec import load_spec

    g = default_grid()
    model = make_model(load_spec("default"))
    rng = np.random.default_rng(32)
    n = 600
    lv = rng.uniform(g.log10_v[0], g.log10_v[-1], n)
    T = rng.uniform(g.T[0], g.T[-1], n)
    p = 10 ** g.log10_p[rng.integers(0, g.log10_p.size, n)]
    ref = model.cold(10**lv, T, p).mu
    e = {ti: np.abs(g.interpolate_one("mu_cold", 10**lv, T, p, v_interp="pchip",
                                      T_interp=ti) / ref - 1)
         for ti in ("linear", "reduced_speed")}
    inner = (lv > g.log10_v[0] + 0.2) & (lv < g.log10_v[-1] - 0.2)
    for ti, err in e.items():
        print(f"{ti}: p95 {np.percentile(err, 95):.3%}, max {err.max():.3%}, "
              f"max inner {err[inner].max():.3%}")
    assert np.percentile(e["reduced_speed"], 95) < 5e-4
    assert e["reduced_speed"][inner].max() < 2e-3, "target: < 0.5 % off-node"
    assert e["reduced_speed"].max() < 0.01 and e["linear"].max() > 0.01


def test_grid_query_cli_T_interp() -> None:
    default_grid()
    r = [subprocess.run([sys.executable, "-m", "tirefric.cli", "grid", "query", "default", "--v",
                         "0.3", "--T", "21.3", "--p", "0.3 MPa", "--v-interp", "pchip",
                         "--T-interp", ti, "--json"], capture_output=True, text=True)
         for ti in ("linear", "reduced_speed")]
    assert all(x.returncode == 0 for x in r), r[0].stderr + r[1].stderr
    import json

    a, b = (json.loads(x.stdout)["points"][0]["mu_cold"] for x in r)
    assert a != b and a == pytest.approx(b, rel=0.02)
