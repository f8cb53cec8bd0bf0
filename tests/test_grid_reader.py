"""Tests of the numpy-only grid reader (:mod:`lookup.grid.reader`).

Tolerances: 1e-12 (relative to the field's scale) where linear interpolation is exact up to
rounding (multilinear fields, node values); 1e-12 against scipy's RegularGridInterpolator,
which implements the same interpolant.
"""

from __future__ import annotations

import subprocess
import sys
import zipfile

import numpy as np
import pytest

from lookup.grid.reader import AXES, VARIABLES, FrictionGrid, content_hash, pchip_slopes
from tirefric.errors import GridError

RNG_SEED = 20240611


def multilinear(lv, T, lp, k=1.0):
    """A field multilinear in (log10 v, T, log10 p): trilinear interpolation reproduces it."""
    return k * (0.3 + 0.1 * lv) * (1.0 + 0.004 * (T - 300.0)) * (2.0 - 0.25 * lp) + 0.05 * lv * lp


def make_grid(uniform: bool | str = True, names=VARIABLES) -> FrictionGrid:
    if uniform == "mixed":  # equally spaced v and p, unequally spaced T
        lv = np.linspace(-6.0, np.log10(40.0), 31)
        T = np.array([253.15, 260.0, 270.0, 290.0, 320.0, 393.15])
        lp = np.linspace(np.log10(5e4), np.log10(2e6), 4)
    elif uniform:
        lv = np.linspace(-6.0, np.log10(40.0), 61)
        T = np.linspace(253.15, 393.15, 15)
        lp = np.linspace(np.log10(5e4), np.log10(2e6), 6)
    else:
        rng = np.random.default_rng(RNG_SEED)
        lv = np.sort(np.r_[-6.0, rng.uniform(-6, 1.6, 20), 1.6])
        T = np.sort(np.r_[253.15, rng.uniform(253.15, 393.15, 7), 393.15])
        lp = np.array([4.7, 5.0, 5.6, 6.0, 6.3])
    LV, TT, LP = np.meshgrid(lv, T, lp, indexing="ij")
    variables = {n: multilinear(LV, TT, LP, k=1.0 + i) for i, n in enumerate(names)}
    return FrictionGrid(lv, T, lp, variables, {"s0_m": 2e-4, "D_m": 1e-3, "note": "test"})


def random_queries(g: FrictionGrid, n: int, seed: int = RNG_SEED):
    rng = np.random.default_rng(seed)
    lv = rng.uniform(g.log10_v[0], g.log10_v[-1], n)
    T = rng.uniform(g.T[0], g.T[-1], n)
    lp = rng.uniform(g.log10_p[0], g.log10_p[-1], n)
    return lv, T, lp


@pytest.mark.parametrize("uniform", [True, False, "mixed"],
                         ids=["uniform-axes", "nonuniform-axes", "mixed-axes"])
def test_exact_on_multilinear_field(uniform):
    g = make_grid(uniform)
    lv, T, lp = random_queries(g, 20000)
    out = g.interpolate(10**lv, T, 10**lp, names=VARIABLES)
    for i, n in enumerate(VARIABLES):
        exact = multilinear(lv, T, lp, k=1.0 + i)
        err = np.max(np.abs(out[n] - exact))
        assert err < 1e-12 * (1 + i) * 10, f"{n}: linear interpolation of a multilinear field " \
                                            f"must be exact, max error {err:.3g}"
    assert sum(g.out_of_range_count.values()) == 0, "in-range queries must not be counted"


@pytest.mark.parametrize("uniform", [True, False, "mixed"],
                         ids=["uniform-axes", "nonuniform-axes", "mixed-axes"])
def test_nodes_reproduced_exactly(uniform):
    g = make_grid(uniform)
    LV, TT, LP = np.meshgrid(g.log10_v, g.T, g.log10_p, indexing="ij")
    out = g.interpolate(10**LV, TT, 10**LP, names=("mu_cold", "dT_flash"))
    for n in ("mu_cold", "dT_flash"):
        np.testing.assert_allclose(out[n], g[n], rtol=1e-13, atol=1e-13,
                                   err_msg=f"{n}: values at the nodes must be the node values")
    assert sum(g.out_of_range_count.values()) == 0, "node queries (incl. axis ends) are in range"


def test_matches_scipy_regular_grid_interpolator():
    from scipy.interpolate import RegularGridInterpolator

    g = make_grid(uniform=False)
    rng = np.random.default_rng(RNG_SEED + 1)
    field = rng.normal(size=g.shape)
    g2 = FrictionGrid(g.log10_v, g.T, g.log10_p,
                      {"mu_cold": field, "mu_hot": field * 2, "dT_flash": field * 3},
                      {"s0_m": 2e-4, "D_m": 1e-3})
    lv, T, lp = random_queries(g2, 5000)
    ref = RegularGridInterpolator((g2.log10_v, g2.T, g2.log10_p), field)(np.c_[lv, T, lp])
    got = g2.interpolate(10**lv, T, 10**lp)["mu_cold"]
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12,
                               err_msg="trilinear interpolation must equal scipy's")


def test_axis_end_in_range_despite_rounding():
    """On T = linspace(253.15, 373.15, 32), (T_max - T_min) * (31 / (T_max - T_min)) rounds to
    just above 31: a query at T_max must still be in range (not counted) and give the node."""
    T = np.linspace(253.15, 373.15, 32)
    assert (T[-1] - T[0]) * (31 / (T[-1] - T[0])) > 31, "the example must show the rounding"
    lv = np.linspace(-6.0, 1.6, 5)
    lp = np.array([4.7, 6.3])
    LV, TT, LP = np.meshgrid(lv, T, lp, indexing="ij")
    field = multilinear(LV, TT, LP)
    g = FrictionGrid(lv, T, lp, {"mu_cold": field, "mu_hot": field, "dT_flash": field},
                     {"s0_m": 2e-4, "D_m": 1e-3})
    out = g.interpolate(1.0, T[-1], 1e5, names=("mu_cold",))["mu_cold"]
    assert g.out_of_range_count["T"] == 0, "a query on the last node is in range"
    np.testing.assert_allclose(out, multilinear(0.0, T[-1], 5.0), rtol=1e-13)


def test_broadcasting_and_shapes():
    g = make_grid()
    v = np.logspace(-5, 1, 7)[:, None]
    T = np.linspace(260, 380, 4)[None, :]
    out = g.interpolate(v, T, 3e5, names=("mu_cold", "mu_hot"))
    assert out["mu_cold"].shape == (7, 4), "result has the broadcast shape of v, T, p"
    lv = np.log10(v) + 0 * T
    exact = multilinear(lv, T + 0 * lv, np.log10(3e5))
    np.testing.assert_allclose(out["mu_cold"], exact, rtol=0, atol=1e-12,
                               err_msg="broadcast query equals the exact multilinear field")
    scalar = g.interpolate(0.01, 300.0, 3e5)
    assert scalar["mu_cold"].shape == (), "scalar query gives 0-d results"
    assert list(scalar) == ["mu_cold", "mu_hot", "dT_flash"], "default names"
    empty = g.interpolate(np.array([]), np.array([]), np.array([]))
    assert empty["mu_cold"].shape == (0,), "an empty query gives empty results"


def test_sign_of_v_ignored_and_standstill_floor():
    g = make_grid()
    a = g.interpolate([0.3, -0.3], 300.0, 1e5)["mu_cold"]
    assert a[0] == a[1], "mu depends on |v| only"
    lo = g.interpolate([0.0, 1e-12, 10 ** g.log10_v[0]], 300.0, 1e5)["mu_cold"]
    assert lo[0] == lo[1] == lo[2], "speeds below v_min are read at v_min"
    assert g.out_of_range_count == {"log10_v": 0, "T": 0, "log10_p": 0}, \
        "the standstill floor is documented as not counted"


@pytest.mark.parametrize("uniform", [True, False, "mixed"],
                         ids=["uniform-axes", "nonuniform-axes", "mixed-axes"])
def test_clamping_and_counting(uniform):
    g = make_grid(uniform)
    T_hi, p_lo = g.T[-1], 10 ** g.log10_p[0]
    out = g.interpolate([100.0, 1.0, 1.0, 1.0], [300.0, 500.0, 100.0, 300.0],
                        [1e5, 1e5, 1e5, 1.0], names=("mu_cold",))["mu_cold"]
    assert np.isfinite(out).all(), "clamped queries never give NaN"
    np.testing.assert_allclose(
        out,
        [multilinear(g.log10_v[-1], 300.0, 5.0), multilinear(0.0, T_hi, 5.0),
         multilinear(0.0, g.T[0], 5.0), multilinear(0.0, 300.0, np.log10(p_lo))],
        rtol=0, atol=1e-12, err_msg="out-of-range coordinates are clamped to the axis ends")
    assert g.out_of_range_detail == {"log10_v": {"below": 0, "above": 1},
                                     "T": {"below": 1, "above": 1},
                                     "log10_p": {"below": 1, "above": 0}}, "counts per side"
    assert g.out_of_range_count == {"log10_v": 1, "T": 2, "log10_p": 1}, "totals per axis"
    g.reset_out_of_range_count()
    assert sum(g.out_of_range_count.values()) == 0, "reset clears the counters"


def test_nan_query_refused():
    g = make_grid()
    with pytest.raises(GridError, match="'T' is NaN"):
        g.interpolate([1.0, 1.0], [300.0, np.nan], 1e5)


def test_negative_pressure_refused():
    g = make_grid()
    with pytest.warns(RuntimeWarning), pytest.raises(GridError, match="p must be > 0 Pa"):
        g.interpolate([1.0, 1.0], 300.0, [1e5, -2.0])


@pytest.mark.parametrize("uniform", [True, "mixed"], ids=["uniform-axes", "mixed-axes"])
def test_chunked_query_equals_small_queries(uniform):
    """A query longer than one chunk gives bit-identical values and the same clamp counts as
    the same points asked for in calls of 100 (the brush's size), including clamped points."""
    g = make_grid(uniform)
    n = 2 * FrictionGrid._CHUNK + 37
    lv, T, lp = random_queries(g, n, seed=RNG_SEED + 7)
    T[::50] += 200.0  # some above the T axis
    lp[7::90] -= 2.0  # some below the p axis
    big = g.interpolate(10**lv, T, 10**lp, names=("mu_hot", "dT_flash"))
    counts_big = g.out_of_range_detail
    g.reset_out_of_range_count()
    parts = [g.interpolate(10**lv[s:s + 100], T[s:s + 100], 10**lp[s:s + 100],
                           names=("mu_hot", "dT_flash")) for s in range(0, n, 100)]
    for name in ("mu_hot", "dT_flash"):
        small = np.concatenate([q[name] for q in parts])
        assert np.array_equal(big[name], small), f"{name}: chunking must not change values"
    assert g.out_of_range_detail == counts_big, "chunking must not change the clamp counts"
    assert counts_big["T"]["above"] == len(range(0, n, 50)), "every clamped T is counted"


def test_small_query_constants_stay_bounded():
    """Per-size constants are cached for small queries (a brush asks for varying sizes); the
    cache is bounded and the values do not depend on it."""
    g = make_grid()
    fresh = make_grid()
    lv, T, lp = random_queries(g, 300, seed=RNG_SEED + 3)
    for n in range(1, 300):
        got = g.interpolate(10**lv[:n], T[:n], 10**lp[:n], names=("mu_cold",))["mu_cold"]
        assert len(g._affine_small) <= FrictionGrid._SMALL_SIZES, "cache must stay bounded"
    ref = fresh.interpolate(10**lv[:299], T[:299], 10**lp[:299], names=("mu_cold",))["mu_cold"]
    assert np.array_equal(got, ref), "values must not depend on the cache state"


def test_pchip_slopes_match_scipy():
    """The Fritsch-Butland slopes equal scipy's PchipInterpolator derivatives at the nodes
    (same formulas; 1e-12 relative is rounding), on unequal spacing with extrema and flats."""
    from scipy.interpolate import PchipInterpolator

    rng = np.random.default_rng(RNG_SEED + 11)
    x = np.cumsum(rng.uniform(0.2, 1.0, 25))
    y = np.c_[np.sin(x), np.cumsum(rng.uniform(0, 1, 25)), rng.normal(size=25),
              np.r_[np.zeros(10), np.ones(15)]]
    ref = PchipInterpolator(x, y, axis=0).derivative()(x)
    np.testing.assert_allclose(pchip_slopes(x, y), ref, rtol=1e-12, atol=1e-12)
    two = pchip_slopes(x[:2], y[:2])
    np.testing.assert_allclose(two, np.repeat((y[1:2] - y[:1]) / (x[1] - x[0]), 2, axis=0),
                               rtol=1e-14, err_msg="two nodes: the secant slope")


@pytest.mark.parametrize("uniform", [True, False], ids=["uniform-axes", "nonuniform-axes"])
def test_pchip_along_v_equals_scipy_on_node_lines(uniform):
    """With T and p on nodes, the v_interp="pchip" query is scipy's PCHIP along log10 v
    (1e-12: rounding of the monomial form)."""
    from scipy.interpolate import PchipInterpolator

    g0 = make_grid(uniform)
    rng = np.random.default_rng(RNG_SEED + 12)
    field = rng.normal(size=g0.shape).cumsum(axis=0)
    g = FrictionGrid(g0.log10_v, g0.T, g0.log10_p,
                     {"mu_cold": field, "mu_hot": -field, "dT_flash": field**2},
                     {"s0_m": 2e-4, "D_m": 1e-3})
    j = rng.integers(0, g.shape[1], 400)
    k = rng.integers(0, g.shape[2], 400)
    lv = rng.uniform(g.log10_v[0], g.log10_v[-1], 400)
    got = g.interpolate(10**lv, g.T[j], 10**g.log10_p[k], v_interp="pchip")
    for name in ("mu_cold", "dT_flash"):
        spline = PchipInterpolator(g.log10_v, g[name], axis=0)
        ref = spline(lv)[np.arange(400), j, k]
        np.testing.assert_allclose(got[name], ref, rtol=0, atol=1e-12 * np.abs(g[name]).max(),
                                   err_msg=f"{name}: PCHIP along log10 v")


@pytest.mark.parametrize("uniform", [True, False, "mixed"],
                         ids=["uniform-axes", "nonuniform-axes", "mixed-axes"])
def test_pchip_exact_on_multilinear_field_and_nodes(uniform):
    """PCHIP reproduces data linear in log10 v, so a multilinear field stays exact; node values
    are reproduced (1e-12: rounding)."""
    g = make_grid(uniform)
    lv, T, lp = random_queries(g, 5000)
    out = g.interpolate(10**lv, T, 10**lp, names=("mu_cold", "mu_hot"), v_interp="pchip")
    np.testing.assert_allclose(out["mu_cold"], multilinear(lv, T, lp), rtol=0, atol=1e-12)
    np.testing.assert_allclose(out["mu_hot"], multilinear(lv, T, lp, k=2.0), rtol=0,
                               atol=2e-12)
    LV, TT, LP = np.meshgrid(g.log10_v, g.T, g.log10_p, indexing="ij")
    nodes = g.interpolate(10**LV, TT, 10**LP, names=("dT_flash",), v_interp="pchip")
    np.testing.assert_allclose(nodes["dT_flash"], g["dT_flash"], rtol=1e-13, atol=1e-13)
    assert sum(g.out_of_range_count.values()) == 0


def test_pchip_keeps_monotone_data_monotone_without_overshoot():
    """Node values rising in v with steps of very different size (where a plain cubic spline
    overshoots) give a non-decreasing interpolant within the node range, at any T and p."""
    g0 = make_grid()
    rng = np.random.default_rng(RNG_SEED + 13)
    steps = rng.uniform(0, 1, g0.shape) * (rng.uniform(size=g0.shape) < 0.2)
    field = np.cumsum(steps, axis=0)
    g = FrictionGrid(g0.log10_v, g0.T, g0.log10_p,
                     {"mu_cold": field, "mu_hot": field, "dT_flash": field},
                     {"s0_m": 2e-4, "D_m": 1e-3})
    lv = np.linspace(g.log10_v[0], g.log10_v[-1], 4001)
    for T, lp in rng.uniform([g.T[0], g.log10_p[0]], [g.T[-1], g.log10_p[-1]], (20, 2)):
        mu = g.interpolate(10**lv, T, 10**lp, names=("mu_cold",), v_interp="pchip")["mu_cold"]
        assert np.all(np.diff(mu) >= -1e-12), "monotone nodes give a monotone interpolant"
        lin = g.interpolate(10**lv, T, 10**lp, names=("mu_cold",))["mu_cold"]
        assert mu.min() >= lin.min() - 1e-12 and mu.max() <= lin.max() + 1e-12, \
            "no overshoot beyond the node range"


def test_unknown_v_interp_refused():
    g = make_grid()
    with pytest.raises(GridError, match="unknown interpolation along log10 v 'cubic'"):
        g.interpolate(1.0, 300.0, 1e5, v_interp="cubic")


def test_unknown_name_refused():
    g = make_grid(names=("mu_cold", "mu_hot", "dT_flash"))
    with pytest.raises(GridError, match="no variable 'area_hot'"):
        g.interpolate(1.0, 300.0, 1e5, names=("area_hot",))


def test_constant_grid():
    g = FrictionGrid.constant(1.1, 0.7, D_m=2e-3)
    out = g.interpolate(np.logspace(-8, 3, 50), 300.0, 2e5, names=VARIABLES)
    assert np.all(out["mu_cold"] == 1.1) and np.all(out["mu_hot"] == 0.7), "flat everywhere"
    assert np.all(out["mu_cont_cold"] == 0.0), "a constant grid has no adhesive part"
    assert g.s0_m == pytest.approx(0.2 * 2e-3) and g.D_m == 2e-3, "s0 defaults to 0.2 D"
    assert g.meta["hash"].startswith("sha256:"), "the hash is set"


def test_from_arrays():
    v, T, p = np.logspace(-6, 1.6, 5), np.linspace(250, 390, 3), np.logspace(4.7, 6.3, 2)
    mu = np.ones((5, 3, 2))
    g = FrictionGrid.from_arrays(v, T, p, {"mu_cold": mu, "mu_hot": mu, "dT_flash": 0 * mu},
                                 s0_m=1e-4, D_m=5e-4, meta={"compound": "x"})
    np.testing.assert_allclose(g.v, v, rtol=1e-14, err_msg="v axis stored as log10 v")
    np.testing.assert_allclose(g.p, p, rtol=1e-14, err_msg="p axis stored as log10 p")
    assert g.meta["compound"] == "x"
    with pytest.raises(GridError, match="> 0"):
        FrictionGrid.from_arrays(-v, T, p, {"mu_cold": mu, "mu_hot": mu, "dT_flash": mu},
                                 s0_m=1e-4, D_m=5e-4)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda a: a.update(T=a["T"][::-1]), "axis 'T' must be strictly ascending"),
        (lambda a: a.update(log10_v=np.r_[a["log10_v"][:3], a["log10_v"][2:]]),
         "strictly ascending"),
        (lambda a: a["variables"].update(mu_hot=np.zeros((2, 2, 2))), "'mu_hot' has shape"),
        (lambda a: a["variables"]["mu_cold"].__setitem__((1, 2, 3), np.nan),
         "'mu_cold' has 1 non-finite"),
        (lambda a: a["variables"].pop("mu_hot"), "required variable"),
        (lambda a: a["variables"].update(mu_warm=a["variables"]["mu_hot"]), "unknown variable"),
        (lambda a: a["meta"].pop("D_m"), "'D_m' is missing"),
        (lambda a: a["meta"].update(s0_m=-1.0), "'s0_m' must be a positive"),
        (lambda a: a["meta"].update(hash="sha256:00"), "hash mismatch"),
    ],
)
def test_validation_refuses_bad_content(change, message):
    g = make_grid()
    args = {n: g.axes[n].copy() for n in AXES}
    args["variables"] = {n: a.copy() for n, a in g.variables.items()}
    args["meta"] = dict(g.meta)
    args["meta"].pop("hash")
    change(args)
    with pytest.raises(GridError, match=message):
        FrictionGrid(args["log10_v"], args["T"], args["log10_p"], args["variables"],
                     args["meta"])


def test_hash_covers_content():
    g = make_grid()
    h0 = content_hash(g.axes, g.variables)
    assert h0 == g.hash
    var = {n: a.copy() for n, a in g.variables.items()}
    var["dT_flash"][0, 0, 0] += 1e-12
    assert content_hash(g.axes, var) != h0, "a change of one value changes the hash"


def test_npz_round_trip(tmp_path):
    g = make_grid()
    path = g.save_npz(tmp_path / "g.npz")
    h = FrictionGrid.load_npz(path)
    assert h.hash == g.hash, "hash survives the round trip"
    assert h.names == g.names
    for n in AXES:
        np.testing.assert_array_equal(h.axes[n], g.axes[n], err_msg=f"axis {n}")
    for n in g.names:
        np.testing.assert_array_equal(h[n], g[n], err_msg=f"variable {n}")
    assert h.meta["note"] == "test" and h.s0_m == g.s0_m and h.D_m == g.D_m


def _corrupt_variants(path, tmp_path):
    data = path.read_bytes()
    truncated = tmp_path / "truncated.npz"
    truncated.write_bytes(data[: len(data) // 2])
    flipped = tmp_path / "flipped.npz"
    # flip bytes inside the stored (uncompressed) array data of mu_hot
    with zipfile.ZipFile(path) as z:
        info = z.getinfo("var_mu_hot.npy")
    start = info.header_offset + 30 + len(info.filename) + 200
    b = bytearray(data)
    for k in range(start, start + 16):
        b[k] ^= 0xFF
    flipped.write_bytes(bytes(b))
    missing = tmp_path / "missing.npz"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(missing, "w") as zout:
        for item in zin.infolist():
            if item.filename != "var_mu_cold.npy":
                zout.writestr(item, zin.read(item.filename))
    return {"truncated": truncated, "flipped": flipped, "missing": missing}


@pytest.mark.parametrize("kind", ["truncated", "flipped", "missing"])
def test_npz_corruption_refused(tmp_path, kind):
    g = make_grid()
    path = g.save_npz(tmp_path / "g.npz")
    bad = _corrupt_variants(path, tmp_path)[kind]
    with pytest.raises(GridError) as exc:
        FrictionGrid.load_npz(bad)
    assert str(bad) in str(exc.value), "the message names the file"


def test_npz_not_a_grid(tmp_path):
    p = tmp_path / "other.npz"
    np.savez(p, a=np.ones(3))
    with pytest.raises(GridError, match="not a tirefric grid"):
        FrictionGrid.load_npz(p)
    with pytest.raises(GridError, match="no such grid file"):
        FrictionGrid.load_npz(tmp_path / "nope.npz")


def test_reader_imports_numpy_only():
    code = ("import sys, lookup.grid, lookup.grid.reader; "
            "heavy = [m for m in ('scipy', 'h5py', 'h5netcdf', 'xarray', 'matplotlib', 'dask', "
            "'tqdm') if m in sys.modules]; print(','.join(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"the FMU-side reader must not import {out.stdout.strip()}"
