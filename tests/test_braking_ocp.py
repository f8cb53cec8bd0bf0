"""Braking OCP, rule-based ABS and locked wheel on analytic friction.

Ordering on identical physics: point-mass bound <= OCP < rule-based ABS < locked wheel.
"""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush.braking import (
    ABSParams,
    ForceMap,
    LockedWheel,
    OCPSettings,
    QuarterCar,
    RuleBasedABS,
    SimSettings,
    ThermalParams,
    default_axes,
    simulate_braking,
    solve_braking_ocp,
)
from tire_brush.braking.quarter_car import ramp_limited_stopping_distance
from tire_brush.braking.reference import (
    burckhardt_road,
    magic_formula_road,
    point_mass_stopping_distance,
)
from tirefric.errors import ConvergenceError

pytest.importorskip("casadi")

V0, V_STOP, T_AMB = 100 / 3.6, 1.0, 293.15
# a fast actuator isolates the tire: the bound has no brake build-up time
FAST = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                  brake_torque_rate_max=1e6)
# the shipped passenger car's actuator (20 kN m/s)
REAL = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                  brake_torque_rate_max=2e4)


def force_map(curve, car):
    return ForceMap.build(curve, **default_axes(V0, V_STOP, car.Fz, T_AMB))


@pytest.fixture(scope="module")
def dry_map():
    return force_map(burckhardt_road("asphalt_dry"), FAST)


def test_ocp_reproduces_point_mass_bound(dry_map):
    curve = burckhardt_road("asphalt_dry")
    bound = point_mass_stopping_distance(V0, curve.peak_mu(), V_STOP, FAST.g)
    r = solve_braking_ocp(FAST, dry_map, V0, V_STOP, T_AMB, settings=OCPSettings(intervals=60))
    # >= bound - 0.1 %: no stop beats mu_max g (the 0.1 % is the spline's error at the peak
    # plus the collocation error); <= bound + 2 %: the torque ramp spans the first of 60
    # intervals (v0 h / 2 ~ 0.5 m of 34 m)
    assert bound * 0.999 <= r.stopping_distance <= bound * 1.02, (
        f"OCP {r.stopping_distance:.3f} m vs point-mass bound {bound:.3f} m")
    hold = r.v < 0.9 * V0
    # 1e-3: the optimal slip holds the peak of mu(kappa) (closed form) along the stop
    np.testing.assert_allclose(r.kappa[hold], -curve.peak_slip(), atol=1e-3,
                               err_msg="OCP slip trajectory vs Burckhardt peak slip")
    assert not r.kappa_bound_active, "the slip bound must not be active at the optimum"


def test_ocp_failure_reports_the_solver_status(dry_map):
    """An OCP that cannot converge (two IPOPT iterations allowed) raises a ConvergenceError
    that names IPOPT's status (the failure handler itself must not raise instead)."""
    with pytest.raises(ConvergenceError, match="Maximum_Iterations_Exceeded"):
        solve_braking_ocp(FAST, dry_map, V0, V_STOP, T_AMB,
                          settings=OCPSettings(intervals=20, max_iter=2))


def test_ordering_ocp_abs_locked(dry_map):
    """Same car, same force map: OCP < rule-based ABS < locked wheel."""
    fm = force_map(burckhardt_road("asphalt_wet"), REAL)
    ocp = solve_braking_ocp(REAL, fm, V0, V_STOP, T_AMB, settings=OCPSettings(intervals=60))
    abs_ = simulate_braking(REAL, fm, RuleBasedABS(ABSParams(), REAL.radius,
                                                   REAL.brake_torque_rate_max),
                            V0, V_STOP, T_AMB, settings=SimSettings(dt=1e-3))
    locked = simulate_braking(REAL, fm, LockedWheel(REAL.brake_torque_rate_max), V0, V_STOP,
                              T_AMB, settings=SimSettings(dt=1e-3))
    d = (ocp.stopping_distance, abs_.stopping_distance, locked.stopping_distance)
    assert d[0] < d[1] < d[2], f"distances OCP, ABS, locked: {d}"
    # the ABS keeps within 10 % of the optimum (measured ~3 %), the locked wheel loses ~50 %
    assert d[1] < 1.10 * d[0], f"ABS {d[1]:.2f} m vs OCP {d[0]:.2f} m"


def test_locked_wheel_matches_sliding_bound(dry_map):
    curve = burckhardt_road("asphalt_dry")
    bound = point_mass_stopping_distance(V0, -float(curve(-1.0)), V_STOP, FAST.g)
    r = simulate_braking(FAST, dry_map, LockedWheel(FAST.brake_torque_rate_max), V0, V_STOP,
                         T_AMB)
    # 1 %: the wheel takes a few ms to lock, during which it brakes harder than when sliding
    assert r.stopping_distance == pytest.approx(bound, rel=0.01), "locked vs mu(-1) bound"
    assert np.all(r.omega[r.t > 0.2] == 0.0), "the wheel stays locked"


def test_simulation_converges_in_dt():
    fm = force_map(burckhardt_road("asphalt_dry"), REAL)
    d = [simulate_braking(REAL, fm, RuleBasedABS(ABSParams(), REAL.radius,
                                                 REAL.brake_torque_rate_max),
                          V0, V_STOP, T_AMB, settings=SimSettings(dt=dt)).stopping_distance
         for dt in (1e-3, 5e-4)]
    # 0.5 %: ROS2 is second order; the ABS switching instants are sampled at 5 ms either way
    assert d[1] == pytest.approx(d[0], rel=5e-3), f"dt 1 ms vs 0.5 ms: {d}"


def test_no_brake_no_stop(dry_map):
    class Off:
        control_period = 0.005
        phase = 0

        def reset(self):
            pass

        def torque_rate(self, t, v, omega, brake_torque):
            return 0.0

    with pytest.raises(ConvergenceError, match="did not reach"):
        simulate_braking(FAST, dry_map, Off(), V0, V_STOP, T_AMB,
                         settings=SimSettings(t_max=0.5))


@pytest.mark.slow
@pytest.mark.parametrize("curve", [burckhardt_road("asphalt_dry"), burckhardt_road("snow"),
                                   magic_formula_road("asphalt_dry"),
                                   magic_formula_road("asphalt_wet")],
                         ids=lambda c: f"{type(c).__name__}-{c.name}")
def test_ordering_all_curves_200_intervals(curve):
    fm = force_map(curve, REAL)
    bound = point_mass_stopping_distance(V0, curve.peak_mu(), V_STOP, REAL.g)
    ocp = solve_braking_ocp(REAL, fm, V0, V_STOP, T_AMB, settings=OCPSettings(intervals=200))
    abs_ = simulate_braking(REAL, fm, RuleBasedABS(ABSParams(), REAL.radius,
                                                   REAL.brake_torque_rate_max),
                            V0, V_STOP, T_AMB)
    locked = simulate_braking(REAL, fm, LockedWheel(REAL.brake_torque_rate_max), V0, V_STOP,
                              T_AMB)
    # <= bound + 5 %: with the 20 kN m/s actuator the torque build-up takes ~80 ms
    assert bound <= ocp.stopping_distance * 1.001 and ocp.stopping_distance < 1.05 * bound, (
        f"OCP {ocp.stopping_distance:.2f} m vs bound {bound:.2f} m")
    # the bound with the torque's build-up holds too (-0.1 %: the spline's error at the peak
    # and the collocation error) and is within 2 % of the optimum: what it leaves out is the
    # wheel's spin-down to the peak slip (measured 0.3-0.5 % on asphalt, 1.3 % on snow)
    ramp = ramp_limited_stopping_distance(REAL, V0, V_STOP,
                                          lambda v: np.full_like(v, curve.peak_mu()))
    assert ramp * 0.999 <= ocp.stopping_distance < 1.02 * ramp, (
        f"OCP {ocp.stopping_distance:.3f} m vs ramp-aware bound {ramp:.3f} m")
    d = (ocp.stopping_distance, abs_.stopping_distance, locked.stopping_distance)
    assert d[0] < d[1] < d[2], f"distances OCP, ABS, locked: {d}"


@pytest.mark.parametrize("curve", [burckhardt_road("asphalt_dry"), burckhardt_road("snow")],
                         ids=["dry", "snow"])
def test_ramp_bound_closed_form(curve):
    """At a speed-independent peak the ramp-aware bound has a closed form: the torque ramps
    from zero at u_max until the brake impulse can decelerate the car and the wheel
    (effective mass m + J / R^2) at g mu_max, t* = g mu_max R (m + J / R^2) / u_max, covering
    v0 t* - g mu t*^2 / 6 and losing g mu t* / 2 of speed; then the point mass at g mu_max.
    1e-5: the bound's O(dt^2) time stepping (measured 3e-7 to 7e-7 at dt = 1 ms). Without a
    rate limit it is the point-mass bound; with it, it is longer by about v0 t* / 2."""
    mu = curve.peak_mu()
    g = REAL.g
    m_eff = REAL.mass + REAL.wheel_inertia / REAL.radius**2
    t_star = g * mu * REAL.radius * m_eff / REAL.brake_torque_rate_max
    v1 = V0 - 0.5 * g * mu * t_star
    closed = V0 * t_star - g * mu * t_star**2 / 6 + (v1**2 - V_STOP**2) / (2 * g * mu)
    flat = lambda v: np.full_like(v, mu)          # noqa: E731
    ramp = ramp_limited_stopping_distance(REAL, V0, V_STOP, flat)
    assert ramp == pytest.approx(closed, rel=1e-5)
    point_mass = point_mass_stopping_distance(V0, mu, V_STOP, g)
    assert ramp - point_mass == pytest.approx(0.5 * V0 * t_star, rel=0.05), \
        "the ramp costs about half its duration at v0 (5 %: the speed lost meanwhile)"
    instant = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                         brake_torque_rate_max=1e12)
    # 1e-6: a 1e12 N m/s ramp lasts 2 ns, and the time step (1 ms) is first order there
    assert ramp_limited_stopping_distance(instant, V0, V_STOP, flat) == pytest.approx(
        point_mass, rel=1e-6)


@pytest.mark.slow
def test_ocp_thermal_state_energy_balance():
    """Without cooling the tread heats by heat_fraction x friction work / heat capacity."""
    th = ThermalParams(heat_capacity=4500.0, cooling=0.0, heat_fraction=0.5)
    car = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                     brake_torque_rate_max=2e4, thermal=th)

    def warm_weakening(kappa, vx, Fz, T_K):        # friction falls 0.2 %/K above 20 C
        return burckhardt_road("asphalt_dry")(kappa) * (1.0 - 2e-3 * (T_K - T_AMB))

    ax = default_axes(V0, V_STOP, car.Fz, T_AMB)
    ax["T_K"] = T_AMB + np.array([0.0, 10.0, 20.0, 40.0])
    fm = ForceMap.build(warm_weakening, **ax)
    r = solve_braking_ocp(car, fm, V0, V_STOP, T_AMB, settings=OCPSettings(intervals=100))
    power = car.Fz * r.mu * (r.omega * car.radius - r.v)
    heat = np.trapezoid(power, r.t) * th.heat_fraction / th.heat_capacity
    # 2 %: trapezoidal quadrature of the power on the interval boundaries
    assert r.T_tread[-1] - T_AMB == pytest.approx(heat, rel=0.02), "tread energy balance"
    assert r.T_tread[-1] > T_AMB + 1.0, "the tread warms during the stop"


@pytest.mark.parametrize("curve", [burckhardt_road("asphalt_dry"), burckhardt_road("asphalt_wet"),
                                   magic_formula_road("asphalt_dry")],
                         ids=["burckhardt-dry", "burckhardt-wet", "mf-dry"])
def test_realistic_abs_cycles_at_4_to_10_hz_between_the_bounds(curve):
    """The ABS with estimated speed, valve pulses and a 10 ms hydraulic delay on asphalt:
    cycles at 4-10 Hz (production ABS on asphalt), stops between the point-mass bound and
    the locked wheel, and at most 10 % behind the idealised ABS (which knows the speed and
    acts at once); its reference speed never exceeds the car's by more than one control
    period of the car's deceleration (it follows the wheel, never overtakes the car)."""
    from tire_brush.braking import RealisticABS
    from tire_brush.braking.study import abs_cycle_frequency

    fm = force_map(curve, REAL)
    bound = point_mass_stopping_distance(V0, curve.peak_mu(), V_STOP, REAL.g)
    ideal = simulate_braking(REAL, fm, RuleBasedABS(ABSParams(), REAL.radius,
                                                     REAL.brake_torque_rate_max),
                             V0, V_STOP, T_AMB)
    ctl = RealisticABS(ABSParams(), REAL.radius, REAL.brake_torque_rate_max, REAL.mass)
    over = []
    original = ctl.torque_rate

    def spy(t, v, omega, brake_torque):
        u = original(t, v, omega, brake_torque)
        over.append(ctl.reference_speed - v)
        return u

    ctl.torque_rate = spy
    real = simulate_braking(REAL, fm, ctl, V0, V_STOP, T_AMB)
    locked = simulate_braking(REAL, fm, LockedWheel(REAL.brake_torque_rate_max), V0, V_STOP,
                              T_AMB)
    assert bound < real.stopping_distance < locked.stopping_distance
    assert real.stopping_distance < 1.10 * ideal.stopping_distance, (
        f"realistic {real.stopping_distance:.2f} m vs idealised {ideal.stopping_distance:.2f} m")
    assert 4.0 <= abs_cycle_frequency(real) <= 10.0, abs_cycle_frequency(real)
    assert max(over) < curve.peak_mu() * REAL.g * ABSParams().control_period + 1e-9


def test_realistic_abs_hydraulics_refuse_bad_values():
    from tire_brush.braking import HydraulicsParams
    from tirefric.errors import InputError

    for bad in ({"delay": -0.01}, {"release_factor": 0.5}, {"reference_decel": 0.0}):
        with pytest.raises(InputError, match="hydraulics"):
            HydraulicsParams(**bad)


@pytest.mark.parametrize("controller", ["abs", "abs_realistic", "locked"])
def test_mu_jump_high_low_high_through_the_map(controller):
    """A patch of half the friction from 10 to 25 m on dry asphalt: the ABS (idealised and
    realistic) and the locked wheel stop longer than on the uniform road and shorter than on
    a road of half the friction throughout; inside the patch the braking friction stays below
    the patch's peak (0.5 mu_max, +0.1 %: the force map's spline error at the peak); after it
    the ABS has the wheel rolling again. (1 ms steps: 0.5 % from 0.5 ms, far below the
    differences compared.)"""
    from tire_brush.braking import MuProfile, RealisticABS

    curve = burckhardt_road("asphalt_dry")
    fm = force_map(curve, REAL)
    road = MuProfile.patch(10.0, 25.0, 0.5)
    make = {"abs": lambda: RuleBasedABS(ABSParams(), REAL.radius, REAL.brake_torque_rate_max),
            "abs_realistic": lambda: RealisticABS(ABSParams(), REAL.radius,
                                                  REAL.brake_torque_rate_max, REAL.mass),
            "locked": lambda: LockedWheel(REAL.brake_torque_rate_max)}[controller]
    d = {name: simulate_braking(REAL, fm, make(), V0, V_STOP, T_AMB, road=r,
                                settings=SimSettings(dt=1e-3))
         for name, r in (("high", None), ("jump", road), ("low", MuProfile.uniform(0.5)))}
    assert d["high"].stopping_distance < d["jump"].stopping_distance \
        < d["low"].stopping_distance, {k: r.stopping_distance for k, r in d.items()}
    jump = d["jump"]
    inside = (jump.x > 10.5) & (jump.x < 24.5)
    assert np.max(-jump.mu[inside]) <= 0.5 * curve.peak_mu() * 1.001
    if controller != "locked":
        after = (jump.x > 30.0) & (jump.v > 3.0)        # (below ~3 m/s the ABS may lock)
        assert np.min(jump.kappa[after]) > -0.5, "the wheel recovers after the patch"


def test_mu_profile_refuses_bad_sections():
    from tire_brush.braking import MuProfile
    from tirefric.errors import InputError

    assert MuProfile.patch(5.0, 8.0, 0.3)(6.0) == 0.3
    assert MuProfile.patch(5.0, 8.0, 0.3)(8.0) == 1.0
    for bad in (((1.0,), (1.0,)), ((0.0, 5.0, 5.0), (1.0, 0.5, 1.0)), ((0.0,), (0.0,))):
        with pytest.raises(InputError, match="road"):
            MuProfile(*bad)


def test_coarse_to_fine_continuation_finds_the_same_optimum(dry_map):
    """Solving first on 25 intervals and starting the 100-interval solve from that solution
    (OCPSettings.coarse_intervals) gives the stop of the direct solve: 2e-5 relative, the
    solver tolerance's order on a 34 m stop (both are the same local optimum, the peak-slip
    hold); the result sums both solves' iterations and names the coarse one."""
    fm = force_map(burckhardt_road("asphalt_wet"), REAL)
    direct = solve_braking_ocp(REAL, fm, V0, V_STOP, T_AMB,
                               settings=OCPSettings(intervals=100, coarse_intervals=0))
    cont = solve_braking_ocp(REAL, fm, V0, V_STOP, T_AMB,
                             settings=OCPSettings(intervals=100, coarse_intervals=25))
    assert cont.stopping_distance == pytest.approx(direct.stopping_distance, rel=2e-5)
    assert cont.t.size == 101
    assert cont.extra["coarse"]["intervals"] == 25
    assert cont.iterations > cont.extra["coarse"]["iterations"]


def test_one_transcription_serves_other_speeds_and_guesses(monkeypatch, tmp_path):
    """The NLP is built once per car, map and mesh and solved for other initial speeds, end
    speeds and slip bounds through its parameters and bounds: a stop solved on a reused
    transcription is the stop solved on a fresh one (1e-9: the same NLP and starting point
    give IPOPT the same iterates; what is left is rounding). Compiled to C (a C compiler on
    this machine) or interpreted, the NLP's functions are the same expressions: the stops
    agree to IPOPT's tolerance (1e-8 on the scaled distance)."""
    from tire_brush.braking import ocp as ocp_module

    monkeypatch.setenv("TIREFRIC_CACHE", str(tmp_path))
    fm = force_map(magic_formula_road("asphalt_wet"), REAL)
    plain = OCPSettings(intervals=30, coarse_intervals=0, jit=False)
    ocp_module._TRANSCRIPTIONS.clear()
    solve_braking_ocp(REAL, fm, V0, V_STOP, T_AMB, settings=plain)
    reused = solve_braking_ocp(REAL, fm, 20.0, 2.0, T_AMB, settings=plain)
    assert reused.extra["solver_reused"]
    ocp_module._TRANSCRIPTIONS.clear()
    fresh = solve_braking_ocp(REAL, fm, 20.0, 2.0, T_AMB, settings=plain)
    assert not fresh.extra["solver_reused"]
    assert reused.stopping_distance == pytest.approx(fresh.stopping_distance, rel=1e-9)
    assert reused.v[0] == pytest.approx(20.0) and reused.v[-1] == pytest.approx(2.0)

    compiled = solve_braking_ocp(REAL, fm, 20.0, 2.0, T_AMB,
                                 settings=OCPSettings(intervals=30, coarse_intervals=0))
    if compiled.extra["compiled"].startswith("not compiled"):
        pytest.skip(compiled.extra["compiled"])
    assert compiled.extra["compiled"].startswith(str(tmp_path))
    assert compiled.stopping_distance == pytest.approx(fresh.stopping_distance, rel=1e-7)
