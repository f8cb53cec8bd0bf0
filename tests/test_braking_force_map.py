"""Force map: tensor B-spline coefficients, CasADi's BSpline against scipy, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tire_brush.braking.force_map import ForceMap, default_axes, tensor_bspline_coefficients
from tire_brush.braking.reference import burckhardt_road
from tirefric.errors import InputError

casadi = pytest.importorskip("casadi")


def smooth(kappa, vx, Fz, T_K):
    """A smooth source depending on every input (no symmetry that could hide an axis swap)."""
    return (np.sin(3.0 * kappa + 0.2) * (1.0 + 0.1 * np.log(vx)) * (1.0 + Fz / 2e4)
            + 1e-3 * (T_K - 300.0) * kappa)


# deliberately different lengths per axis, so a C/Fortran-order mix-up cannot go unseen
AXES = {"kappa": np.linspace(-1.0, 0.05, 23), "vx": np.geomspace(0.5, 40.0, 7),
        "Fz": np.array([2000.0, 3500.0, 5000.0, 6500.0]), "T_K": np.array([270.0, 300.0, 340.0,
                                                                              360.0, 400.0])}


@pytest.fixture(scope="module")
def fmap():
    return ForceMap.build(smooth, **AXES)


def random_points(n: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(a[0], a[-1], n) for a in AXES.values()])


def test_interpolates_nodes(fmap):
    G = np.meshgrid(*AXES.values(), indexing="ij")
    # 1e-11: the interpolation conditions are solved exactly up to round-off
    np.testing.assert_allclose(fmap(*G), smooth(*G), atol=1e-11,
                               err_msg="spline vs source at the nodes")


def test_casadi_bspline_matches_scipy(fmap):
    """CasADi's BSpline (Fortran-ordered coefficients) against scipy's NdBSpline."""
    P = random_points(300)
    f = fmap.casadi_function()
    ca_vals = np.array(f.map(P.shape[0])(*P.T)).ravel()
    # 1e-12: the same tensor spline evaluated by two libraries, round-off only
    np.testing.assert_allclose(ca_vals, fmap(*P.T), rtol=0, atol=1e-12,
                               err_msg="casadi Function.bspline vs scipy NdBSpline")
    # and the bare bspline in spline coordinates (log10 speed)
    bs = fmap.casadi_bspline()
    X = P.copy()
    X[:, 1] = np.log10(X[:, 1])
    np.testing.assert_allclose(np.array(bs.map(X.shape[0])(X.T)).ravel(), fmap(*P.T),
                               atol=1e-12, err_msg="bare casadi bspline in (kappa, log10 v, ..)")


def test_cubic_reproduced_exactly():
    """A tensor cubic polynomial lies in the spline space: reproduced everywhere."""
    axes = [np.linspace(0, 1, 6), np.linspace(-1, 2, 5), np.linspace(3, 4, 4)]

    def poly(x, y, z):
        return (1 + x - 2 * x**3) * (y**2 - y**3 / 3) * (z**3 + 1)

    knots, c = tensor_bspline_coefficients(axes, poly(*np.meshgrid(*axes, indexing="ij")),
                                           [3, 3, 3])
    from scipy.interpolate import NdBSpline

    P = np.random.default_rng(2).uniform([0, -1, 3], [1, 2, 4], size=(200, 3))
    np.testing.assert_allclose(NdBSpline(tuple(knots), c, 3)(P), poly(*P.T), atol=1e-10,
                               err_msg="cubic polynomial reproduction")


def test_gradient_matches_finite_difference(fmap):
    f = fmap.casadi_function()
    k = casadi.MX.sym("k")
    df = casadi.Function("df", [k], [casadi.jacobian(f(k, 10.0, 4000.0, 300.0), k)])
    for kk in (-0.7, -0.2, -0.05):
        h = 1e-6
        fd = (fmap(kk + h, 10.0, 4000.0, 300.0) - fmap(kk - h, 10.0, 4000.0, 300.0)) / (2 * h)
        # 1e-6: central-difference truncation and round-off
        assert abs(float(df(kk)) - float(fd)) < 1e-6, "casadi derivative vs finite difference"


def test_clamped_outside_and_constant_axes():
    fm = ForceMap.build(burckhardt_road("asphalt_dry"), **default_axes(30.0, 1.0, 4000.0, 293.0))
    assert fm.active == ("kappa", "vx"), "single-node load and temperature axes are constants"
    f = fm.casadi_function()
    assert float(f(-0.1, 10.0, 1.0, 1.0)) == pytest.approx(float(fm(-0.1, 10.0, 4000.0, 293.0)),
                                                          abs=1e-12), "constant axes ignored"
    assert float(f(-3.0, 10.0, 4000.0, 293.0)) == pytest.approx(
        float(fm(-1.0, 10.0, 4000.0, 293.0)), abs=1e-12), "slip clamped to the axis"
    k = np.linspace(-1, 0, 2001)
    err = np.abs(fm(k, 10.0, 4000.0, 293.0) - burckhardt_road("asphalt_dry")(k)).max()
    # 1e-5: default slip axis (61 graded nodes) against the analytic curve
    assert err < 1e-5, f"default axes reproduce the Burckhardt curve (max error {err:.2g})"


def test_validation_names_the_axis():
    with pytest.raises(InputError, match="axis 'vx' must be strictly ascending"):
        ForceMap.build(smooth, kappa=[-1, 0], vx=[1.0, 3.0, 2.0], Fz=[4000.0], T_K=[300.0])
    with pytest.raises(InputError, match="non-finite"), np.errstate(all="ignore"):
        ForceMap.build(lambda k, v, f, t: np.log(k), kappa=[-1, 0, 0.1], vx=[1.0], Fz=[1.0],
                       T_K=[300.0])
    with pytest.raises(InputError, match="> 0"):
        ForceMap.build(smooth, kappa=[-1, 0], vx=[0.0, 1.0], Fz=[4000.0], T_K=[300.0])


def test_fixed_inputs_slice_the_spline_exactly(fmap):
    """Holding the load (and the temperature) fixed contracts the coefficients with that
    axis' basis functions: the slice equals the full spline wherever the fixed input takes its
    value (to rounding, 1e-12), has fewer spline axes, and clamps like the full map."""
    pts = random_points(500, seed=3)
    Fz0, T0 = 4100.0, 333.3
    f1 = fmap.fixed(Fz=Fz0)
    f2 = fmap.fixed(Fz=Fz0, T_K=T0)
    assert f1.active == ("kappa", "vx", "T_K") and f2.active == ("kappa", "vx")
    full = fmap(pts[:, 0], pts[:, 1], Fz0, pts[:, 3])
    np.testing.assert_allclose(f1(pts[:, 0], pts[:, 1], 0.0, pts[:, 3]), full, rtol=0,
                               atol=1e-12)
    np.testing.assert_allclose(f2(pts[:, 0], pts[:, 1], 0.0, 0.0),
                               fmap(pts[:, 0], pts[:, 1], Fz0, T0), rtol=0, atol=1e-12)
    # CasADi of the slice against scipy of the full map
    f = f2.casadi_function()
    got = np.array([float(f(k, v, 0.0, 0.0)) for k, v in pts[:20, :2]])
    np.testing.assert_allclose(got, fmap(pts[:20, 0], pts[:20, 1], Fz0, T0), atol=1e-12)
    # beyond the axis the value clamps to its end, as the full map's evaluation does
    np.testing.assert_allclose(fmap.fixed(Fz=1e5)(pts[:, 0], pts[:, 1], 0.0, pts[:, 3]),
                               fmap(pts[:, 0], pts[:, 1], AXES["Fz"][-1], pts[:, 3]),
                               atol=1e-12)
    with pytest.raises(InputError):
        fmap.fixed(kappa=-0.1)
    with pytest.raises(InputError):
        fmap.fixed(load=1.0)


@pytest.mark.parametrize("axes", [
    AXES,
    # Fz and T single nodes (inactive), as the stops' maps at one load and temperature
    {**AXES, "Fz": np.array([4000.0]), "T_K": np.array([293.15])},
    # a two-node axis (degree 1) next to cubic ones
    {**AXES, "Fz": np.array([4000.0]), "T_K": np.array([293.15, 313.15])},
])
@pytest.mark.parametrize("backend", ["python", "c"])
def test_point_evaluator_is_the_spline(axes, backend):
    """PointEvaluator (de Boor's recurrence at one point) and its compiled twin against the
    map's own evaluation (scipy NdBSpline), inside the axes, beyond them (clamped) and on
    knots and nodes. The same sum in another order: 1e-12 absolute on values of order 1
    (coefficient products of order 1, 4^4 terms at most, double rounding ~1e-16 each)."""
    fm = ForceMap.build(smooth, **axes)
    point = fm.point_evaluator(backend)
    rng = np.random.default_rng(4)
    pts = [tuple(rng.uniform(a[0] - 0.1 * (a[-1] - a[0]) - 1.0,
                             a[-1] + 0.1 * (a[-1] - a[0]) + 1.0) for a in axes.values())
           for _ in range(300)]
    pts += [tuple(a[i % a.size] for a in axes.values()) for i in range(30)]   # nodes, ends
    for p in pts:
        p = (p[0], max(p[1], 1e-3), p[2], p[3])         # speed > 0 (log axis)
        assert point(*p) == pytest.approx(float(fm(*p)), abs=1e-12, rel=0.0)


@pytest.mark.parametrize("axes", [
    AXES,
    {**AXES, "Fz": np.array([4000.0]), "T_K": np.array([293.15])},
    {**AXES, "Fz": np.array([4000.0]), "T_K": np.array([293.15, 313.15])},
])
def test_compiled_point_evaluator_is_the_python_one(axes):
    """The compiled point reader (tire_brush/csrc/bspline.c) against its readable reference,
    operation for operation except the contraction's order of summation (numpy's matrix
    product in the reference): equal to 4 ulps of values of order 1 (1e-15 absolute: a
    sum of at most 4^4 products, each rounded once; the recurrence is the same), and NaN
    in, NaN out. A wrong knot span, basis or stride moves values by ~1e-3 and more."""
    fm = ForceMap.build(smooth, **axes)
    pc, pp = fm.point_evaluator("c"), fm.point_evaluator("python")
    rng = np.random.default_rng(7)
    lo = [a[0] - 0.1 * (a[-1] - a[0]) - 1.0 for a in axes.values()]
    hi = [a[-1] + 0.1 * (a[-1] - a[0]) + 1.0 for a in axes.values()]
    pts = rng.uniform(lo, hi, size=(2000, 4))
    pts[:, 1] = np.maximum(pts[:, 1], 1e-3)             # speed > 0 (log axis)
    knots = [tuple(a[i % a.size] for a in axes.values()) for i in range(30)]
    for p in [*map(tuple, pts.tolist()), *knots]:
        assert pc(*p) == pytest.approx(pp(*p), abs=1e-15, rel=0.0)
    assert math.isnan(pc(math.nan, 10.0, 4000.0, 300.0))


def test_point_evaluator_backend_is_checked():
    fm = ForceMap.build(smooth, **AXES)
    with pytest.raises(InputError, match="backend"):
        fm.point_evaluator("fortran")
