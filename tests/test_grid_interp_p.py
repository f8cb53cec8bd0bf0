"""Monotone cubic along log10 p and the v-axis bands of the reduced speed.

After the reduced-speed interpolation across T (``tests/test_grid_reduced_speed.py``) the
off-node error of the default grid (cold branch, all three axes off-node) comes from the
pressure axis (linear in log10 p) and from the bands next to v_min and v_max, where the
shifted speed at one T node leaves the v axis. ``p_interp="pchip"`` (cubic Hermite along
log10 p with Fritsch-Carlson slopes; with ``v_interp="pchip"`` the bicubic Hermite patch) and
reading the other T node alone in those bands (the cold branch; the hot branch keeps fixed-v
interpolation next to v_max) bring it to, measured on the shipped default grid (summer on
asphalt, 61 x 81 x 15 nodes) on 2000 random points (seed 32):

==========  =======================  ==============================================
variable    default (multilinear)    v pchip + T reduced speed + p pchip
==========  =======================  ==============================================
mu_cold     0.143 / 0.45 / 2.03 %    0.003 / 0.07 / 0.34 %   (median / p95 / max)
mu_hot      0.144 / 0.45 / 2.03 %    0.006 / 0.11 / 0.52 %   (>= 4 nodes from the fold)
area_cold   0.49 / 1.39 / 3.39 %     0.013 / 0.08 / 0.18 %
==========  =======================  ==============================================

The engine test below asserts the issue's target (max < 0.5 % for mu_cold) on a smaller
sample of the same kind.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from grid_cases import default_grid, reduced_speed_linear_grid

from lookup.grid.reader import FrictionGrid, pchip_slopes
from lookup.shift import WLF
from tirefric.errors import GridError

pytest.importorskip("lookup.friction")

BEST = {"v_interp": "pchip", "T_interp": "reduced_speed", "p_interp": "pchip"}


def random_grid(seed=1, monotone_p=False):
    rng = np.random.default_rng(seed)
    lv = np.linspace(-4, 1, 21)
    T = np.linspace(260.0, 320.0, 7)
    lp = np.linspace(4.7, 6.3, 9)
    vals = 1.0 + 0.2 * rng.random((lv.size, T.size, lp.size))
    if monotone_p:
        vals = np.cumsum(vals, axis=2)
    w = WLF(8.0, 120.0, 293.15)
    g = FrictionGrid(lv, T, lp, {"mu_cold": vals, "mu_hot": vals, "dT_flash": 0 * vals},
                     {"s0_m": 2e-4, "D_m": 1e-3, "compound": {"shift": w.describe()}})
    return g, rng


def hermite_1d(x, y, xq):
    """1-D pchip of node values y (shape (n,)) at xq, written out independently."""
    d = pchip_slopes(x, y)
    i = np.clip(np.searchsorted(x, xq) - 1, 0, x.size - 2)
    h = x[i + 1] - x[i]
    t = (xq - x[i]) / h
    return ((2 * t**3 - 3 * t**2 + 1) * y[i] + (t**3 - 2 * t**2 + t) * h * d[i]
            + (-2 * t**3 + 3 * t**2) * y[i + 1] + (t**3 - t**2) * h * d[i + 1])


@pytest.mark.parametrize("v_interp", ["linear", "pchip"])
@pytest.mark.parametrize("T_interp", ["linear", "reduced_speed"])
def test_p_pchip_is_exact_for_data_linear_in_log_p(v_interp, T_interp) -> None:
    """Data = f(log10 v, T) + c log10 p: pchip reproduces linear data, so along p both
    interpolations are exact and agree to round-off whatever happens along v and T."""
    g0, rng = random_grid(2)
    vals = g0["mu_cold"][:, :, :1] + 0.3 * g0.log10_p
    g = FrictionGrid(g0.log10_v, g0.T, g0.log10_p,
                     {"mu_cold": vals, "mu_hot": vals, "dT_flash": 0 * vals},
                     g0.meta | {"hash": None})
    n = 300
    v, T = 10 ** rng.uniform(-4, 1, n), rng.uniform(260, 320, n)
    p = 10 ** rng.uniform(4.7, 6.3, n)
    a = g.interpolate_one("mu_cold", v, T, p, v_interp, T_interp, "pchip")
    b = g.interpolate_one("mu_cold", v, T, p, v_interp, T_interp, "linear")
    np.testing.assert_allclose(a, b, rtol=1e-12)


@pytest.mark.parametrize("v_interp", ["linear", "pchip"])
def test_p_pchip_reduces_to_1d_pchip_on_the_nodes(v_interp) -> None:
    """On v and T nodes the patch is the 1-D pchip along log10 p; on p nodes it is the
    interpolation along v without the p option; node values are reproduced."""
    g, rng = random_grid(3)
    y = g["mu_cold"]
    for iv, iT in [(0, 0), (7, 3), (20, 6), (13, 1)]:
        lpq = rng.uniform(g.log10_p[0], g.log10_p[-1], 50)
        got = g.interpolate_one("mu_cold", 10 ** g.log10_v[iv], g.T[iT], 10**lpq, v_interp,
                                p_interp="pchip")
        np.testing.assert_allclose(got, hermite_1d(g.log10_p, y[iv, iT], lpq), rtol=1e-12)
    n = 200
    v, T = 10 ** rng.uniform(-4, 1, n), rng.uniform(260, 320, n)
    p = 10 ** g.log10_p[rng.integers(0, g.log10_p.size, n)]
    for T_interp in ("linear", "reduced_speed"):
        np.testing.assert_allclose(
            g.interpolate_one("mu_cold", v, T, p, v_interp, T_interp, "pchip"),
            g.interpolate_one("mu_cold", v, T, p, v_interp, T_interp, "linear"), rtol=1e-12)
    V, TT, P = np.meshgrid(g.v, g.T, g.p, indexing="ij")
    np.testing.assert_allclose(g.interpolate_one("mu_cold", V, TT, P, v_interp, p_interp="pchip"),
                               y, rtol=1e-12)


def test_p_pchip_keeps_monotone_pressure_runs_monotone() -> None:
    g, rng = random_grid(4, monotone_p=True)
    lpq = np.linspace(g.log10_p[0], g.log10_p[-1], 400)
    for _ in range(10):
        iv = rng.integers(0, g.log10_v.size)
        T = rng.uniform(260, 320)
        got = g.interpolate_one("mu_cold", 10 ** g.log10_v[iv], T, 10**lpq, "pchip",
                                p_interp="pchip")
        assert (np.diff(got) >= 0).all()


def test_p_interp_errors_and_default_unchanged() -> None:
    g, _ = random_grid(5)
    with pytest.raises(GridError, match="unknown interpolation along log10 p"):
        g.interpolate_one("mu_cold", [1e-3], [300.0], [3e5], p_interp="cubic")
    with pytest.raises(GridError, match="NaN"):
        g.interpolate_one("mu_cold", [1e-3], [np.nan], [3e5], p_interp="pchip")
    # out-of-range queries are clamped and counted as with the default
    g.reset_out_of_range_count()
    g.interpolate_one("mu_cold", [1e-3, 1e-3], [300.0, 300.0], [1e3, 1e8], p_interp="pchip")
    assert g.out_of_range_detail["log10_p"] == {"below": 1, "above": 1}
    a = g.interpolate(np.full(5, 1e-2), 300.0, 3e5)
    b = g.interpolate(np.full(5, 1e-2), 300.0, 3e5, p_interp="linear")
    assert all((a[k] == b[k]).all() for k in a)
    out = g.interpolate(np.ones((2, 3)) * 1e-2, 300.0, 3e5, p_interp="pchip")
    assert out["mu_cold"].shape == (2, 3)


@pytest.mark.parametrize("v_interp", ["linear", "pchip"])
def test_reduced_speed_next_to_v_min_reads_the_upper_node(v_interp) -> None:
    """mu linear in the reduced speed: next to v_min (the lower T node's shifted speed below
    the axis) the upper node alone is read at the query's reduced speed, which is exact; the
    previous fixed-v fallback was not. Next to v_max the cold branch is read from the lower
    node alone at the reduced speed (exact), the hot branch across T at fixed v."""
    g, w, lv, T = reduced_speed_linear_grid()
    rng = np.random.default_rng(8)
    n = 300
    j = rng.integers(0, T.size - 1, n)
    Tq = T[j] + rng.uniform(3.0, 10.0, n)
    lvq = rng.uniform(-6.0, -5.9, n)
    band = lvq + w.log10_aT(Tq) - w.log10_aT(T[j]) < lv[0]  # the v_min band
    assert band.sum() > 200
    j, Tq, lvq = j[band], Tq[band], lvq[band]
    ref = 1.0 + 0.05 * (lvq + w.log10_aT(Tq)) + 0.01 * 5.5
    red = g.interpolate_one("mu_cold", 10**lvq, Tq, 10**5.5, v_interp=v_interp,
                            T_interp="reduced_speed", p_interp="pchip")
    np.testing.assert_allclose(red, ref, rtol=1e-12)
    lvq = rng.uniform(1.5, 1.6, Tq.size)
    band = lvq + w.log10_aT(Tq) - w.log10_aT(T[j + 1]) > lv[-1]  # the v_max band
    assert band.sum() > 200
    Tq, lvq = Tq[band], lvq[band]
    ref = 1.0 + 0.05 * (lvq + w.log10_aT(Tq)) + 0.01 * 5.5
    both = g.interpolate(10**lvq, Tq, 10**5.5, ("mu_cold", "mu_hot"), v_interp,
                         "reduced_speed")
    np.testing.assert_allclose(both["mu_cold"], ref, rtol=1e-12)
    fixed_v = g.interpolate_one("mu_hot", 10**lvq, Tq, 10**5.5, v_interp, "linear")
    np.testing.assert_allclose(both["mu_hot"], fixed_v, rtol=1e-12)
    assert np.abs(fixed_v / ref - 1).max() > 1e-4, "fixed v is not exact: the test can fail"


def fold_distance(g, lv, T, jump_K=10.0):
    """Distance of points from the hot branch's thermal-runaway fold, in node spacings.

    Fold nodes: both nodes of any neighbouring pair along log10 v or T whose flash
    temperature differs by more than ``jump_K`` (on the default grid smooth steps stay below
    9 K, the fold jumps by 13-110 K). Distance: the largest of the v and T index
    differences to the nearest fold node (any pressure).
    """
    d = g["dT_flash"]
    fold = np.zeros(d.shape, dtype=bool)
    for ax in (0, 1):
        jump = np.abs(np.diff(d, axis=ax)) > jump_K
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[ax], hi[ax] = slice(None, -1), slice(1, None)
        fold[tuple(lo)] |= jump
        fold[tuple(hi)] |= jump
    nodes = np.argwhere(fold)[:, :2]
    ti = np.stack([np.interp(lv, g.log10_v, np.arange(g.log10_v.size)),
                   np.interp(T, g.T, np.arange(g.T.size))], axis=1)
    return np.abs(ti[:, None, :] - nodes[None]).max(axis=2).min(axis=1)


def test_default_grid_best_scheme_against_engine() -> None:
    """Shipped default grid, all three axes off-node (uniform in log10 v, T, log10 p),
    against the engine with the grid's own settings (so the engine's resolution bias, 0.17 %,
    is common to both and not part of this error).

    mu_cold: the issue's target, max < 0.5 %, asserted as such; 1000 points (0.1 s of
    engine) measured max 0.33 %, p95 0.063 % (asserted < 0.1 %). The default
    multilinear interpolation exceeds 1 % on the same points (2.1 %). mu_hot: 300 points,
    those within 4 node spacings (0.34 decade of v, 7 K) of the thermal-runaway fold excluded
    (:func:`fold_distance`; at the fold the hot branch jumps and no interpolation helps);
    measured p95 0.10 %, max 0.39 %, asserted < 0.2 % and < 1.5 %. area_cold: measured max
    0.18 %, asserted < 1 %.
    """
    from lookup.grid.build import make_model
    from lookup.grid.spec import load_spec

    g = default_grid()
    model = make_model(load_spec("default"))
    rng = np.random.default_rng(33)
    n = 1000
    lv = rng.uniform(g.log10_v[0], g.log10_v[-1], n)
    T = rng.uniform(g.T[0], g.T[-1], n)
    lp = rng.uniform(g.log10_p[0], g.log10_p[-1], n)
    v, p = 10**lv, 10**lp
    cold = model.cold(v, T, p)
    got = g.interpolate(v, T, p, ("mu_cold", "area_cold", "mu_hot"), **BEST)
    e = np.abs(got["mu_cold"] / cold.mu - 1)
    ea = np.abs(got["area_cold"] / cold.area - 1)
    e0 = np.abs(g.interpolate_one("mu_cold", v, T, p) / cold.mu - 1)
    k = slice(0, 300)
    hot = model.hot(v[k], T[k], p[k]).mu
    away = fold_distance(g, lv[k], T[k]) >= 4.0
    eh = np.abs(got["mu_hot"][k] / hot - 1)[away]
    for name, x in (("mu_cold", e), ("mu_cold default", e0), ("area_cold", ea),
                    (f"mu_hot ({away.sum()} away from the fold)", eh)):
        print(f"{name}: median {np.median(x):.3%}, p95 {np.percentile(x, 95):.3%}, "
              f"max {x.max():.3%}")
    assert e.max() < 5e-3, "target: max < 0.5 % off-node for mu_cold"
    assert np.percentile(e, 95) < 1e-3
    assert e0.max() > 1e-2
    assert ea.max() < 1e-2
    assert away.sum() > 250
    assert np.percentile(eh, 95) < 2e-3 and eh.max() < 1.5e-2


def test_grid_query_cli_p_interp() -> None:
    default_grid()
    r = [subprocess.run([sys.executable, "-m", "tirefric.cli", "grid", "query", "default", "--v",
                         "0.3", "--T", "21.3", "--p", "0.73 MPa", "--v-interp", "pchip",
                         "--T-interp", "reduced_speed", "--p-interp", pi, "--json"],
                        capture_output=True, text=True) for pi in ("linear", "pchip")]
    assert all(x.returncode == 0 for x in r), r[0].stderr + r[1].stderr
    a, b = (json.loads(x.stdout) for x in r)
    assert b["p_interp"] == "pchip" and b["T_interp"] == "reduced_speed"
    ma, mb = a["points"][0]["mu_cold"], b["points"][0]["mu_cold"]
    assert ma != mb and ma == pytest.approx(mb, rel=0.02)
