"""The two-track car through the FMU (fmu_src.host.cosim.simulate_two_track_fmu: one FMU
instance per wheel) and against the same car on the steady force map.

The fast tests use the synthetic grid of :mod:`fmu_support` (coupling, symmetry, conservation,
split-mu); the slow one compares the FMU run with the map run on the shipped default grid.
"""

from __future__ import annotations

import numpy as np
import pytest
from fmu_support import build_test_fmu

from fmu_src.host.cosim import simulate_two_track_fmu
from tire_brush.braking import ABSParams, LockedWheel, MuProfile, RuleBasedABS
from tire_brush.braking.two_axle import TwoAxleCar, simulate_two_track, wheel_rates

T = 293.15


@pytest.fixture(scope="module")
def fmu(tmp_path_factory):
    return build_test_fmu(tmp_path_factory.mktemp("two_track_fmu"))


def car(balance: float = 0.65) -> TwoAxleCar:
    """1600 kg, wheelbase 2.7 m, CG 1.2 m behind the front axle at 0.55 m, track 1.55 m;
    radius 0.31 m, the passenger tire's R_e (the FMU computes the slip from it)."""
    return TwoAxleCar(mass=1600.0, wheelbase=2.7, cg_to_front=1.2, cg_height=0.55,
                      wheel_inertia=1.2, radius=0.31, brake_balance=balance,
                      brake_torque_max=9000.0, brake_torque_rate_max=4e4)


def abs_per_wheel(c: TwoAxleCar):
    return [RuleBasedABS(ABSParams(), c.radius, r) for r in wheel_rates(c)]


def test_two_track_fmu_uniform_road_is_symmetric_and_conserves_momentum(fmu):
    """Same road both sides, ABS per wheel: the left and right FMU instances see the same
    inputs and give bit-identical forces (no yaw moment at all); the loads sum to m g at
    every step (the transfer moves load between the axles, adds none) with the front loaded
    more while braking; the car's momentum loss is the impulse of the four FMU forces (1e-3:
    the last, partial step) and the distance the integral of the speed (trapezoidal, exact
    for the scheme but in the last, interpolated step: 1e-6)."""
    c = car()
    res = simulate_two_track_fmu(fmu, c, abs_per_wheel(c), 8.0, T, v_stop=1.0)
    assert res.Fx[:, 0].tobytes() == res.Fx[:, 1].tobytes()
    assert res.Fx[:, 2].tobytes() == res.Fx[:, 3].tobytes()
    assert np.all(res.yaw_moment == 0.0)
    np.testing.assert_allclose(res.Fz.sum(axis=1), c.mass * c.g, rtol=1e-12)
    braking = res.a < -1.0
    assert braking.any() and np.all(res.Fz[braking, 0] > res.Fz[braking, 2])
    impulse = np.sum(res.Fx[1:].sum(axis=1) * np.diff(res.t))
    assert c.mass * (res.v[-1] - res.v[0]) == pytest.approx(impulse, rel=1e-3)
    assert res.x[-1] == pytest.approx(np.trapezoid(res.v, res.t), rel=1e-6)
    assert (res.omega[:-1] > 0).all(), "the ABS keeps every wheel turning"


def test_two_track_fmu_split_mu_pulls_towards_the_high_side(fmu):
    """Right side at 0.3 of the friction (8 -> 1 m/s): the left tires brake harder all along
    (their mean force is more than twice the right ones'), the yaw moment turns the car left
    (> 0) on average and stays below w m g mu_pk / 4 (left forces at most their loads times
    the tire's peak friction mu_pk, right ones at least 0; mu_pk: the largest friction either
    side used, the right one's divided by its road factor); loads and momentum as on the
    uniform road."""
    c = car()
    res = simulate_two_track_fmu(fmu, c, abs_per_wheel(c), 8.0, T, v_stop=1.0,
                                 road_right=MuProfile.uniform(0.3))
    mu_pk = max(float(np.max(-res.mu[:, [0, 2]])), float(np.max(-res.mu[:, [1, 3]])) / 0.3)
    left, right = (-res.Fx[:, [0, 2]].sum(axis=1)), (-res.Fx[:, [1, 3]].sum(axis=1))
    assert left.mean() > 2.0 * right.mean()
    mz = res.summary()["yaw_moment_mean_Nm"]
    assert 0.0 < mz < c.track * c.mass * c.g * mu_pk / 4, mz
    assert np.max(res.yaw_moment) < c.track * c.mass * c.g * mu_pk / 4
    np.testing.assert_allclose(res.Fz.sum(axis=1), c.mass * c.g, rtol=1e-12)
    impulse = np.sum(res.Fx[1:].sum(axis=1) * np.diff(res.t))
    assert c.mass * (res.v[-1] - res.v[0]) == pytest.approx(impulse, rel=1e-3)


@pytest.mark.slow
def test_two_track_fmu_split_mu_between_the_uniform_roads(fmu):
    """From 12 m/s: high < split-mu < low road throughout (stopping distance)."""
    c = car()
    d = {name: simulate_two_track_fmu(fmu, c, abs_per_wheel(c), 12.0, T, v_stop=1.0,
                                      road_right=r, road_left=left).stopping_distance
         for name, left, r in (("high", None, None),
                               ("split", None, MuProfile.uniform(0.3)),
                               ("low", MuProfile.uniform(0.3), MuProfile.uniform(0.3)))}
    assert d["high"] < d["split"] < d["low"], d


def test_two_track_fmu_refuses_bad_inputs(fmu):
    from tirefric.errors import InputError

    c = car()
    with pytest.raises(InputError, match="four controllers"):
        simulate_two_track_fmu(fmu, c, abs_per_wheel(c)[:2], 12.0, T)
    from dataclasses import replace

    with pytest.raises(InputError, match="R_e"):
        simulate_two_track_fmu(fmu, replace(c, radius=0.3), abs_per_wheel(c), 12.0, T)


@pytest.mark.slow
def test_two_track_fmu_agrees_with_the_force_map_on_the_default_grid(tmp_path):
    """The default grid at 20 C from 20 m/s, split-mu (right 0.3), ABS per wheel and all
    wheels locked: through four FMU instances (transient brush) and on the steady force map
    (the study's brush map with its load axis): stopping distances within 5 % (the quarter
    car's ABS agrees within 3 %, test_fmu_braking_cosim; the load transfer and per-wheel
    cycling add to it), mean yaw moments within 15 %."""
    from fmu_src.host.cosim import braking_simulator
    from tire_brush.braking.study import case_force_map, load_study
    from tirefric.paths import models_dir

    if not (models_dir() / "grids" / "default.nc").is_file():
        pytest.skip("default grid not built")
    spec = load_study("abs_default")
    case = next(cs for cs in spec.cases if cs.T_C == pytest.approx(20.0))
    from dataclasses import replace

    spec = replace(spec, car=replace(spec.car, thermal=None))
    fmap, prov, _ = case_force_map(spec, case)
    fmap = fmap.fixed(T_K=case.T_K)
    sim = braking_simulator("passenger", "default", tmp_path, {})
    # the FMU puts its My on the wheels: the map car gets the same rolling resistance
    from tire_brush.braking.friction import brush_rolling_resistance

    f_r, _ = brush_rolling_resistance(prov, 10.0, spec.car.Fz, case.T_K)
    c = replace(car(), rolling_resistance=f_r)
    road = MuProfile.uniform(0.3)
    for make in (lambda: abs_per_wheel(c), lambda: [LockedWheel(r) for r in wheel_rates(c)]):
        m = simulate_two_track(c, fmap, make(), 20.0, 1.0, case.T_K, road_right=road)
        f = simulate_two_track_fmu(sim.fmu, c, make(), 20.0, case.T_K, v_stop=1.0,
                                   road_right=road)
        assert f.stopping_distance == pytest.approx(m.stopping_distance, rel=0.05)
        assert f.summary()["yaw_moment_mean_Nm"] == pytest.approx(
            m.summary()["yaw_moment_mean_Nm"], rel=0.15)
