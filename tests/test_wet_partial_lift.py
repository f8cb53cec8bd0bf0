"""The partial lift of the entering water film below full hydroplaning (Horne & Dreher's
(V / V_p)^2 with Gallaway's V_p, tire_brush.hydroplaning) and the wet locked wheel's speed
gradient (docs/physics.md sec. 7a)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from tire_brush.hydroplaning import gallaway_speed, lifted_share, load_lift, partial_lift
from tirefric.errors import InputError

P, TD, TXD = 230e3, 8e-3, 0.7e-3  # the passenger tire, new tread, the R117 road


def _gallaway_us(wd_in: float, p_psi: float, td_32: float, txd_in: float, sd: float) -> float:
    """Gallaway et al. (FHWA-RD-79-31) in its own units: V [mph] from spin-down [%], P [psi],
    TD [1/32 in], WD and TXD [in] (written out here independently of the module's SI code)."""
    a = max(10.409 / wd_in ** 0.06 + 3.507, (28.952 / wd_in ** 0.06 - 7.817) * txd_in ** 0.14)
    return sd ** 0.04 * p_psi ** 0.3 * (td_32 + 1.0) ** 0.06 * a


@pytest.mark.parametrize("wd_in, p_psi, td_32, txd_in", [
    (0.02, 30.0, 10.0, 0.02), (0.1, 24.0, 2.0, 0.05), (0.4, 35.0, 6.0, 0.0),
    (0.01, 40.0, 0.0, 0.08)])
def test_gallaway_speed_is_the_report_formula_in_si(wd_in, p_psi, td_32, txd_in):
    """The SI function against the formula in the report's units (mph, psi, 32nds of an inch,
    inches); tolerance: float rounding of the unit factors."""
    v = gallaway_speed(wd_in * 0.0254, p_psi * 6894.757293168, td_32 / 32 * 0.0254,
                       txd_in * 0.0254)
    assert v == pytest.approx(_gallaway_us(wd_in, p_psi, td_32, txd_in, 10.0) * 0.44704,
                              rel=1e-12)


def test_gallaway_speed_near_horne_for_flooded_smooth_tire():
    """Deep water (0.4 in, the report's upper end) on a smooth tire (TD 0) on a smooth road:
    Gallaway's V_p lies between 0.6 and 1 of Horne's 6.35 sqrt(p / kPa) km/h (NASA TN D-2056;
    0.72 at these pressures): the two hydroplaning speeds of the literature for that case
    agree in size, Gallaway's passenger tires hydroplaning below Horne's speed, which came
    from aircraft and truck tires (the known "light-load" shortfall, module docstring)."""
    for p in (180e3, 230e3, 300e3):
        vh = 6.35 * math.sqrt(p / 1e3) / 3.6
        vg = gallaway_speed(0.4 * 0.0254, p, 0.0, 0.0)
        assert 0.6 < vg / vh < 1.0


def test_partial_lift_limits():
    """0 at rest, 0 while the water stays within the texture (no film above it: V_p
    infinite), (V / V_p)^2 below V_p, the whole load at and above V_p."""
    d = np.array([0.0, 0.5e-3, TXD, 1e-3, 3e-3])
    assert np.all(partial_lift(0.0, d, P, TD, TXD) == 0.0)
    assert np.all(partial_lift(40.0, d[:3], P, TD, TXD) == 0.0)
    vp = gallaway_speed(1e-3 - TXD, P, TD, TXD)
    assert partial_lift(0.5 * vp, 1e-3, P, TD, TXD) == pytest.approx(0.25, rel=1e-12)
    assert partial_lift(vp, 1e-3, P, TD, TXD) == pytest.approx(1.0, rel=1e-12)
    assert partial_lift(1.5 * vp, 1e-3, P, TD, TXD) == 1.0
    assert gallaway_speed(0.0, P, TD, TXD) == math.inf


def test_partial_lift_monotonic():
    """Rises with speed and water depth; falls with tread depth, texture depth and inflation
    (Gallaway's exponents are all of that sign)."""
    V = np.linspace(0.0, 40.0, 81)
    d = np.linspace(0.0, 10e-3, 101)
    VV, DD = np.meshgrid(V, d, indexing="ij")
    L = partial_lift(VV, DD, P, TD, TXD)
    assert np.all(np.diff(L, axis=0) >= 0) and np.all(np.diff(L, axis=1) >= 0)
    assert L.max() == 1.0
    v, dd = 20.0, 2e-3
    assert partial_lift(v, dd, P, 2e-3, TXD) > partial_lift(v, dd, P, 8e-3, TXD)
    assert partial_lift(v, dd, 180e3, TD, TXD) > partial_lift(v, dd, 300e3, TD, TXD)
    assert partial_lift(v, dd, P, TD, 0.3e-3) > partial_lift(v, dd, P, TD, 1.2e-3)


def test_load_lift_is_the_larger_of_both_laws():
    """load_lift = max(partial, Horne's flooded lift), elementwise."""
    V = np.linspace(0.0, 35.0, 15)[:, None]
    d = np.array([0.0, 1e-3, 3e-3, 6e-3, 12e-3])[None, :]
    L = load_lift(V, d, P, TD, 0.3, TXD)
    ref = np.maximum(partial_lift(V, d, P, TD, TXD), lifted_share(V, d, P, TD, 0.3, TXD))
    assert np.array_equal(L, ref)
    assert np.all(L >= lifted_share(V, d, P, TD, 0.3, TXD))


@pytest.mark.parametrize("kw", [{"water_film": -1e-3}, {"p_inflation": 0.0},
                                {"tread_depth": -1e-3}, {"texture_depth": float("nan")},
                                {"spin_down": 0.0}])
def test_gallaway_speed_refuses_bad_input(kw):
    args = {"water_film": 1e-3, "p_inflation": P, "tread_depth": TD, "texture_depth": TXD,
            **kw}
    with pytest.raises(InputError):
        gallaway_speed(**args)


@pytest.fixture(scope="module")
def spec_grids():
    from tire_brush.braking.wet_grip_test import _grids, load_wet_grip_spec

    spec = load_wet_grip_spec()
    return spec, _grids(spec.grid)


def _locked_ratio(spec, grids, T_C: float, partial: bool) -> float:
    from tire_brush.braking.wet_grip_test import friction_source

    src = friction_source(spec, "passenger", spec.water_depth, grids, partial_lift=partial)
    mu = [-float(src(np.array([-1.0]), v / 3.6, spec.car.Fz, T_C + 273.15)[0])
          for v in (20.0, 100.0)]
    return mu[1] / mu[0]


def test_friction_never_rises_with_water_depth_with_partial_lift(spec_grids):
    """With the partial lift on, the steady brush's Fx/Fz at fixed slip, speed and
    temperature does not rise with the water depth (0 ... 6 mm)."""
    from tire_brush.braking.wet_grip_test import friction_source

    spec, grids = spec_grids
    depths = (0.0, 0.25e-3, 0.5e-3, 1e-3, 2e-3, 4e-3, 6e-3)
    for vx in (8.0, 22.2, 27.8):
        for kappa in (-0.06, -1.0):
            mu = [-float(friction_source(spec, "passenger", d, grids, partial_lift=True)(
                np.array([kappa]), vx, spec.car.Fz, 293.15)[0]) for d in depths]
            # float32 tables: a rise below 1e-6 is rounding, not physics
            assert all(b <= a + 1e-6 for a, b in itertools.pairwise(mu)), (vx, kappa, mu)


def test_partial_lift_gives_the_locked_wheel_a_speed_gradient(spec_grids):
    """With the partial lift the locked wheel's wet mu(100 km/h)/mu(20 km/h) at 20 C falls
    below the target 0.75 (PIARC IFI: exp(-80/Sp) = 0.32 for MPD 0.63 mm): the mechanism can
    carry the gradient; it overshoots (0.10), docs/physics.md sec. 7a."""
    spec, grids = spec_grids
    assert _locked_ratio(spec, grids, 20.0, True) <= 0.75


@pytest.mark.xfail(strict=True, reason="the model's wet locked wheel falls too little with "
                   "speed: mu(100)/mu(20) = 0.923 at 20 C (target <= 0.75); the sourced "
                   "partial lift that reaches it breaks the reference tire's R117 windows "
                   "and is a study option (docs/physics.md sec. 7a)")
def test_wet_locked_wheel_speed_ratio_target(spec_grids):
    spec, grids = spec_grids
    assert _locked_ratio(spec, grids, 20.0, False) <= 0.75
