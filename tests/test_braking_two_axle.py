"""Two-axle braking (tire_brush/braking/two_axle.py): load transfer, brake balance, ABS per
axle, against the closed forms of the rigid two-axle car."""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush.braking import ABSParams, LockedWheel, RuleBasedABS, TorqueRamp
from tire_brush.braking.reference import burckhardt_road
from tire_brush.braking.two_axle import TwoAxleCar, axle_rates, simulate_two_axle

V0, VS, T = 25.0, 1.0, 293.15
CURVE = burckhardt_road("asphalt_dry")


def mu_load_free(kappa, vx, Fz, T_K):
    """The Burckhardt dry curve, the same at every load (closed forms hold exactly)."""
    return float(CURVE(kappa, vx))


def car(balance: float, rate: float = 4e4, torque: float = 12000.0) -> TwoAxleCar:
    """A compact passenger car: 1600 kg, wheelbase 2.7 m, CG 1.2 m behind the front axle at
    0.55 m height."""
    return TwoAxleCar(mass=1600.0, wheelbase=2.7, cg_to_front=1.2, cg_height=0.55,
                      wheel_inertia=1.2, radius=0.31, brake_balance=balance,
                      brake_torque_max=torque, brake_torque_rate_max=rate)


def test_wheel_loads_static_split_and_transfer():
    c = car(0.6)
    f0, r0 = c.wheel_loads(0.0)
    assert 2 * (f0 + r0) == pytest.approx(c.mass * c.g, rel=1e-12)
    assert f0 / r0 == pytest.approx(1.5 / 1.2, rel=1e-12), "static split l_r : l_f"
    f, r = c.wheel_loads(-8.0)
    assert f - f0 == pytest.approx(c.mass * 8.0 * 0.55 / (2 * 2.7), rel=1e-12)
    assert f + r == pytest.approx(f0 + r0, rel=1e-12), "the transfer moves load, adds none"


@pytest.mark.slow
def test_locked_wheels_stop_at_the_sliding_bound_with_transfer_consistent():
    """Both axles locked at once (a brake rate 100x the car's): the car slides to a stop at
    the locked friction (point-mass distance within 0.5 %: the first ~20 ms of build-up),
    the deceleration equals the load-weighted friction at every instant, and the loads obey
    the transfer formula at that deceleration."""
    c = car(0.6, rate=4e6, torque=40000.0)
    rf, rr = axle_rates(c)
    res = simulate_two_axle(c, mu_load_free, (LockedWheel(rf), LockedWheel(rr)), V0, VS, T)
    mu_lock = -float(CURVE(-1.0, 10.0))
    bound = (V0**2 - VS**2) / (2 * mu_lock * c.g)
    assert res.stopping_distance == pytest.approx(bound, rel=5e-3)
    late = res.t[:-1] > 0.2
    assert np.allclose(res.kappa[late], -1.0)
    for k in np.flatnonzero(late)[::500]:
        f, r = c.wheel_loads(res.a[k])
        assert res.Fz[k, 0] == pytest.approx(f, rel=1e-9) and res.Fz[k, 1] == pytest.approx(r)
        assert res.a[k] == pytest.approx(2 * np.sum(res.Fz[k] * res.mu[k]) / c.mass, rel=1e-9)


@pytest.mark.slow
def test_brake_balance_decides_which_axle_locks_first():
    """A slow pedal ramp without ABS (15 -> 3 m/s): a rear-heavy balance (0.55) takes the rear
    past its peak slip first, a front-heavy one (0.95) the front (the rear never gets
    there), and the ideal balance for the peak friction brings the two closest together.
    Not simultaneous even there: once the first axle passes its peak, the deceleration
    stops growing, and so does the load the other axle needs (slow)."""
    mu_pk = CURVE.peak_mu()
    s_pk = -CURVE.peak_slip()

    def first_peak_times(balance):
        c = car(balance)
        rf, rr = axle_rates(c)
        ramp = [TorqueRamp(12000.0 * s / 2, 0.0, 2.0, rate_max=r, control_period=1e-3)
                for s, r in ((balance, rf), (1 - balance, rr))]
        res = simulate_two_axle(c, mu_load_free, tuple(ramp), 15.0, 3.0, T, dt=2e-4)
        past = res.kappa < s_pk
        return [res.t[np.argmax(past[:, i])] if past[:, i].any() else np.inf
                for i in range(2)]

    rear_heavy, ideal, front_heavy = (first_peak_times(b) for b in
                                      (0.55, car(0.5).ideal_brake_balance(mu_pk), 0.95))
    assert rear_heavy[1] < rear_heavy[0]
    assert front_heavy[0] < front_heavy[1]
    gap = [abs(a - b) for a, b in (rear_heavy, ideal, front_heavy)]
    assert gap[1] < gap[0] and gap[1] < gap[2], gap


@pytest.mark.slow
def test_abs_on_both_axles_approaches_the_peak_bound_at_the_ideal_balance():
    """ABS on each axle at the ideal balance: within 12 % of v0^2/(2 mu_max g) (the ABS's own
    margin on the quarter car is 3-7 %, module doc of abs_control, and the load swings
    between the axles as each cycles: 9 % measured); a rear-heavy balance whose front torque
    cannot reach the front's peak stops longer."""
    mu_pk = CURVE.peak_mu()
    bound = (V0**2 - VS**2) / (2 * mu_pk * 9.80665)

    def stop(balance, torque):
        c = car(balance, torque=torque)
        rf, rr = axle_rates(c)
        ctl = (RuleBasedABS(ABSParams(), c.radius, rf), RuleBasedABS(ABSParams(), c.radius, rr))
        return simulate_two_axle(c, mu_load_free, ctl, V0, VS, T).stopping_distance

    ideal = stop(car(0.5).ideal_brake_balance(mu_pk), 9000.0)
    assert bound < ideal < 1.12 * bound, (ideal, bound)
    assert stop(0.3, 9000.0) > ideal * 1.1


def test_ideal_balance_closed_form():
    """Without wheel inertia the ideal front share is the textbook (l_r + mu h) / L; with it,
    the torque that decelerates each wheel's inertia (J mu g / R, the same on every wheel)
    moves the share towards 1/2."""
    from dataclasses import replace

    c = car(0.5)
    light = replace(c, wheel_inertia=1e-12)
    assert light.ideal_brake_balance(1.0) == pytest.approx((1.5 + 0.55) / 2.7, rel=1e-9)
    assert 0.5 < c.ideal_brake_balance(1.0) < light.ideal_brake_balance(1.0)


# -- two-track car, split-mu ----------------------------------------------------------------
def mu_vec(kappa, vx, Fz, T_K):
    """The Burckhardt dry curve (no velocity term) at every load, written out for four
    wheels at once (the curve object's call costs 10x more, which these RK4 runs feel)."""
    s = -np.asarray(kappa, dtype=float)
    return -(CURVE.c1 * (1.0 - np.exp(-CURVE.c2 * s)) - CURVE.c3 * s)


def test_mu_vec_is_the_burckhardt_curve():
    k = np.linspace(-1.0, 0.0, 41)
    np.testing.assert_allclose(mu_vec(k, 10.0, 4000.0, T), CURVE(k, 10.0), rtol=1e-12,
                               atol=1e-15)


def test_two_track_locked_on_split_mu_matches_the_closed_forms():
    """All four wheels locked at once (a brake rate 100x the car's), left on dry asphalt,
    right at 0.3 of it: the car decelerates at g mu_lock (1 + 0.3) / 2 (stopping distance
    within 0.5 %: the ~20 ms of build-up), the yaw moment is w m g mu_lock (1 - 0.3) / 4
    (1e-9: algebra once locked) and turns the car towards the high side (left, > 0); the
    loads sum to m g at every instant and each side carries half of it; the uniform road has
    no yaw moment."""
    from tire_brush.braking import MuProfile
    from tire_brush.braking.two_axle import simulate_two_track, wheel_rates

    c = car(0.6, rate=4e6, torque=40000.0)
    ctl = [LockedWheel(r) for r in wheel_rates(c)]
    res = simulate_two_track(c, mu_vec, ctl, 15.0, VS, T, road_right=MuProfile.uniform(0.3),
                             dt=1e-3)
    mu_lock = -float(CURVE(-1.0, 10.0))
    bound = (15.0**2 - VS**2) / (2 * mu_lock * 0.65 * c.g)
    assert res.stopping_distance == pytest.approx(bound, rel=5e-3)
    late = res.t > 0.1
    assert np.allclose(res.kappa[late], -1.0)
    np.testing.assert_allclose(res.yaw_moment[late], c.track * c.mass * c.g * mu_lock * 0.7 / 4,
                               rtol=1e-9)
    np.testing.assert_allclose(res.Fz.sum(axis=1), c.mass * c.g, rtol=1e-12)
    np.testing.assert_allclose(res.Fz[:, 0] + res.Fz[:, 2], c.mass * c.g / 2, rtol=1e-12)
    np.testing.assert_allclose(res.a[late], -c.g * mu_lock * 0.65, rtol=1e-9)
    uni = simulate_two_track(c, mu_vec, [LockedWheel(r) for r in wheel_rates(c)], 15.0, VS, T,
                             dt=1e-3)
    assert np.max(np.abs(uni.yaw_moment)) < 1e-9 * c.mass * c.g
    assert uni.stopping_distance < res.stopping_distance


@pytest.mark.slow
def test_two_track_on_a_uniform_road_is_the_two_axle_car():
    """Same road on both sides, ABS per wheel: the two-track stop is the two-axle stop
    (each side of an axle does what that axle's wheel does; 1e-6: the same RK4 steps, the
    loads converged to 1e-10), with no yaw moment (6 -> 2 m/s; ~12 s, the two-axle
    reference calls the friction point by point)."""
    from tire_brush.braking.two_axle import simulate_two_track, wheel_rates

    c = car(c_bal := car(0.5).ideal_brake_balance(CURVE.peak_mu()), torque=9000.0)
    assert c.brake_balance == c_bal
    rf, rr = axle_rates(c)
    two = simulate_two_axle(c, mu_load_free, (RuleBasedABS(ABSParams(), c.radius, rf),
                                              RuleBasedABS(ABSParams(), c.radius, rr)),
                            6.0, 2.0, T, dt=2e-4)
    four = simulate_two_track(c, mu_vec, [RuleBasedABS(ABSParams(), c.radius, r)
                                          for r in wheel_rates(c)], 6.0, 2.0, T)
    assert four.stopping_distance == pytest.approx(two.stopping_distance, rel=1e-6)
    assert np.max(np.abs(four.yaw_moment)) < 1e-6


def test_rolling_resistance_coasts_both_cars_down_at_its_closed_form():
    """No brake, rolling resistance f_r on every tire: each wheel's moment f_r Fz R reaches
    the road through its slip, so the car coasts down at a = -f_r m g / (m + 4 J / R^2)
    (the loads sum to m g whatever the transfer; the wheels' inertia decelerates with the
    car). 1 %: the ~10 ms in which the wheels settle to their creep slip. Without f_r the
    car would not slow down at all (the check runs 20 -> 19.5 m/s)."""
    from tire_brush.braking.two_axle import simulate_two_track

    f_r = 0.015
    c = TwoAxleCar(mass=1600.0, wheelbase=2.7, cg_to_front=1.2, cg_height=0.55,
                   wheel_inertia=1.2, radius=0.31, brake_balance=0.6,
                   brake_torque_max=12000.0, brake_torque_rate_max=4e4, rolling_resistance=f_r)
    a = f_r * c.mass * c.g / (c.mass + 4 * c.wheel_inertia / c.radius**2)
    t_exact = 0.5 / a
    two = simulate_two_axle(c, mu_load_free, (LockedWheel(0.0), LockedWheel(0.0)), 20.0,
                            19.5, T, dt=2e-3)
    four = simulate_two_track(c, mu_vec, [LockedWheel(0.0) for _ in range(4)], 20.0, 19.5,
                              T, dt=2e-3)
    assert two.stop_time == pytest.approx(t_exact, rel=1e-2)
    assert four.stop_time == pytest.approx(t_exact, rel=1e-2)
    assert np.all(two.brake_torque == 0.0)
