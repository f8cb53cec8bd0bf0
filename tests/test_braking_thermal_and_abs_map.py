"""Study physics fixes: tread-temperature coverage of the map, point-mass bounds over the
tread temperatures, ABS release slips from the slip map, OCP starts, steady-brush resolution."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from tire_brush.braking.abs_control import ABSParams, LockedWheel, RuleBasedABS, TorqueRamp
from tire_brush.braking.force_map import ForceMap
from tire_brush.braking.quarter_car import (
    QuarterCar,
    ThermalParams,
    load_quarter_car,
    tread_temperature_rise_bound,
)
from tire_brush.braking.reference import burckhardt_road
from tire_brush.braking.simulation import simulate_braking
from tire_brush.braking.slip_map import SlipMap, optimal_slip
from tire_brush.braking.study import (
    abs_slip_schedule,
    case_temperatures,
    load_study,
    point_mass_bound,
    solve_ocp_from_starts,
)
from tirefric.errors import InputError, InputErrors
from tirefric.paths import models_dir

VEHICLE = models_dir() / "studies" / "vehicles" / "passenger.toml"


def snow_map(**kw) -> ForceMap:
    curve = burckhardt_road("snow")
    return ForceMap.build(curve, kappa=np.linspace(-1, 0.05, 41), vx=np.geomspace(0.5, 30, 5),
                          Fz=np.array([4413.0]), T_K=np.array([293.15]), **kw)


def test_tread_rise_bound_is_the_energy_balance_of_a_locked_stop():
    """No cooling: the tread rise is eta times the friction work ``int Fx (omega R - v) dt``
    (energy balance of the thermal state), and that work is below the kinetic energy."""
    car = load_quarter_car(VEHICLE)
    car = replace(car, thermal=ThermalParams(heat_capacity=4500.0, cooling=0.0,
                                             heat_fraction=0.5))
    v0, v_stop = 25.0, 1.0
    res = simulate_braking(car, burckhardt_road("asphalt_dry"),
                           LockedWheel(car.brake_torque_rate_max), v0, v_stop, 293.15)
    rise = res.T_tread[-1] - 293.15
    power = car.Fz * res.mu * (res.omega * car.radius - res.v)
    work = np.trapezoid(power, res.t)
    assert rise == pytest.approx(0.5 * work / 4500.0, rel=0.02), \
        "tread heat = eta x friction work (2 %: the step in which the wheel locks is clamped " \
        "to omega = 0, its stages see a negative spin; the recorded points miss it)"
    bound = tread_temperature_rise_bound(car, v0)
    assert rise <= bound, "the bound bounds"
    assert rise > 0.85 * bound, "a locked stop turns most of the kinetic energy into tread heat"
    assert tread_temperature_rise_bound(replace(car, thermal=None), v0) == 0.0


def test_map_temperatures_cover_the_tread_rise():
    spec = load_study("abs_default")
    case = spec.cases[0]
    T = case_temperatures(spec, case)
    rise = tread_temperature_rise_bound(spec.car, spec.v0)
    assert T.max() - case.T_K >= rise > 15.0, "the map reaches the hottest tread"
    assert np.allclose(np.diff(T[2:]), spec.maps.temperature_step), "extension spacing"
    assert (np.diff(T) > 0).all()
    assert list(case_temperatures(spec, case, temperature_dependent=False) - case.T_K) == \
        list(spec.maps.temperatures_rel), "no extension for temperature-free sources"


def test_point_mass_bound_takes_the_best_friction_over_the_columns():
    v = np.array([1.0, 30.0])
    one = SlipMap(v, np.array([4000.0]), np.array([293.15]), -0.1 * np.ones((2, 1, 1)),
                  0.8 * np.ones((2, 1, 1)), 0.6 * np.ones((2, 1, 1)))
    two = replace(one, T_K=np.array([293.15, 303.15]), kappa_opt=-0.1 * np.ones((2, 1, 2)),
                  mu_max=np.stack([0.8 * np.ones((2, 1)), 1.0 * np.ones((2, 1))], axis=-1),
                  mu_locked=0.6 * np.ones((2, 1, 2)))
    g = 9.80665
    exact = (30.0**2 - 1.0) / (2 * g)
    assert point_mass_bound(one, 30.0, 1.0, g) == pytest.approx(exact / 0.8, rel=1e-9)
    assert point_mass_bound(two, 30.0, 1.0, g) == pytest.approx(exact / 1.0, rel=1e-9)


def test_abs_release_slips_follow_the_slip_map():
    snow = burckhardt_road("snow")
    sm = optimal_slip(snow, np.geomspace(1.0, 30.0, 6), [4413.0], [293.15])
    speeds, slips = abs_slip_schedule(sm)
    assert speeds == tuple(sm.vx) and np.allclose(slips, -sm.kappa_opt.ravel())
    k_star = np.log(snow.c1 * snow.c2 / snow.c3) / snow.c2
    assert np.allclose(slips, k_star, atol=1e-6), "Burckhardt's closed-form peak, all speeds"
    ctrl = RuleBasedABS(ABSParams(), 0.31, 2e4, slip_schedule=((5.0, 25.0), (0.1, 0.2)))
    assert ctrl.slip_threshold(15.0) == pytest.approx(0.15)
    assert ctrl.slip_threshold(1.0) == 0.1 and ctrl.slip_threshold(40.0) == 0.2
    assert RuleBasedABS(ABSParams(), 0.31, 2e4).slip_threshold(15.0) == 0.2
    for bad in (((5.0, 5.0), (0.1, 0.2)), ((5.0,), (0.1, 0.2)), ((5.0, 6.0), (0.0, 0.2))):
        with pytest.raises(InputError, match="slip_schedule"):
            RuleBasedABS(ABSParams(), 0.31, 2e4, slip_schedule=bad)


def test_torque_ramp_tracks_its_target():
    ramp = TorqueRamp(1000.0, 0.1, 0.3, rate_max=1e4, control_period=0.01)
    assert ramp.target(0.05) == 0.0 and ramp.target(1.0) == 1000.0
    assert ramp.target(0.2) == pytest.approx(500.0)
    assert ramp.torque_rate(0.2, 10.0, 30.0, 500.0) == pytest.approx(5000.0)
    assert ramp.torque_rate(0.0, 10.0, 30.0, 0.0) == 0.0
    assert ramp.torque_rate(0.5, 10.0, 30.0, 0.0) == 1e4, "bounded by the actuator rate"
    with pytest.raises(InputError):
        TorqueRamp(100.0, 0.3, 0.1)


def test_ocp_from_the_locked_start_finds_the_same_optimum_on_a_fixed_curve(tmp_path):
    """Without a temperature dependence the problem has one optimum near the peak: both
    starts must reach it (1e-3: two IPOPT solutions of the same NLP to its tolerance and the
    slightly different slip bounds)."""
    spec = load_study("abs_analytic")
    spec = replace(spec, v0=50 / 3.6, ocp=replace(spec.ocp, intervals=60),
                   ocp_starts=("deceleration", "locked"))
    case = next(c for c in spec.cases if c.road == "snow")
    fmap = snow_map()
    locked = simulate_braking(spec.car, fmap, LockedWheel(spec.car.brake_torque_rate_max),
                              spec.v0, spec.v_stop, case.T_K)
    best, start, tried = solve_ocp_from_starts(spec, case, fmap, locked)
    d = {k: v["stopping_distance"] for k, v in tried.items()}
    assert set(d) == {"deceleration", "locked"}, tried
    assert d["locked"] == pytest.approx(d["deceleration"], rel=1e-3)
    assert best.stopping_distance == min(d.values()) and start in d
    assert best.stopping_distance < locked.stopping_distance


def test_starts_after_a_verified_optimum_are_skipped():
    """``[ocp] stop_when_verified``: once a start's optimum passes the optimality checks the
    remaining starts are not solved (listed as skipped). (Without the setting every start is
    solved: test_ocp_from_the_locked_start_finds_the_same_optimum_on_a_fixed_curve.)"""
    spec = load_study("abs_analytic")
    spec = replace(spec, v0=50 / 3.6, ocp=replace(spec.ocp, intervals=20, coarse_intervals=0),
                   ocp_starts=("deceleration", "locked"))
    case = next(c for c in spec.cases if c.road == "snow")
    fmap = snow_map()
    calls = []

    def verify(res):
        calls.append(res.stopping_distance)
        return True

    on = replace(spec, ocp_stop_when_verified=True)
    # no locked-wheel simulation: the locked start is never solved
    best, start, tried = solve_ocp_from_starts(on, case, fmap, None, verify=verify)
    assert start == "deceleration" and tried["deceleration"]["verified"]
    assert "skipped" in tried["locked"] and len(calls) == 1, tried
    assert best.stopping_distance == tried["deceleration"]["stopping_distance"]
    text = (models_dir() / "studies" / "abs_default.toml").read_text()
    assert load_study("abs_default").ocp_stop_when_verified == (
        "stop_when_verified = true" in text)


def test_spec_reads_the_new_keys_and_refuses_misuse(tmp_path):
    spec = load_study("abs_default")
    assert spec.abs_slip_from_map and spec.fmu_abs and spec.ocp_starts == (
        "locked", "deceleration", "abs")
    assert spec.ocp.jit, "the OCP's functions are compiled unless a spec says otherwise"
    assert "dt_internal" not in spec.fmu, "the FMU runs at its own (converged) defaults"
    assert spec.fmu["step"] == pytest.approx(1e-3)
    text = (models_dir() / "studies" / "abs_analytic.toml").read_text().replace(
        'vehicle = "vehicles/passenger.toml"', f'vehicle = "{VEHICLE.as_posix()}"\nfmu_abs = true')
    text += '\n[fmu]\ndt_intern = "1 ms"\n'
    text = text.replace("degree = 3", 'degree = 3\nstarts = ["locked", "sideways"]')
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(InputErrors) as info:
        load_study(p)
    msg = str(info.value)
    assert "friction.source = 'brush'" in msg, "the FMU runs the brush tire only"
    assert "fmu.dt_intern" in msg and "ocp.starts" in msg, msg


def test_steady_cells_do_not_change_the_force():
    """The braking maps' steady brush: the force is the patch integral of the friction, so
    the default cell count gives the 1024-cell force (eq. (28)'s blending length s0 = 0.2 mm
    is resolved by the element integration, not by the cells)."""
    from tire_brush.braking.friction import steady_cells
    from tire_brush.params import load_tire
    from tire_brush.steady import SteadyBrush

    tire = load_tire("passenger")
    n = steady_cells(tire, 2e-4)
    from lookup.grid.store import load_grid

    grid = load_grid()
    F = [float(SteadyBrush(tire, grid, n_elements=m).solve(-0.2, 0.0, 4.0, 4400.0, 293.15).Fx)
         for m in (n, 1024)]
    assert F[0] == pytest.approx(F[1], rel=2e-3), f"{n} cells vs 1024: {F}"


def test_ocp_optimality_check_names_what_beats_it():
    """The optimality report: verified when the OCP is no longer than any simulated strategy
    and not below the bound (slack 0.2 %); otherwise the strategy and the numbers."""
    from tire_brush.braking.study import ocp_optimality

    assert ocp_optimality(40.0, 39.0, {"abs": 41.0, "locked": 50.0}) == "verified"
    assert ocp_optimality(40.0, 39.0, {"abs": 40.05}) == "verified", "inside the slack"
    msg = ocp_optimality(49.43, 47.0, {"abs": 48.58, "locked": 49.5})
    assert msg.startswith("not proven") and "abs stops in 48.580 m" in msg
    assert "locked" not in msg
    assert "below the lower bound 33.000 m" in ocp_optimality(30.0, 33.0, {"abs": 35.0})


def test_tread_heating_along_a_stop_closed_forms():
    """with_tread_heating (the isothermal start's temperature): without cooling the rise is
    eta / C times the friction work (trapezoidal, exact for the rule: 1e-12); with cooling and
    a constant friction power P it follows P / G (1 - exp(-G t / C)) (1e-6 at 2000 steps:
    second order)."""
    from tire_brush.braking.ocp import OCPResult
    from tire_brush.braking.study import with_tread_heating

    n = 2001
    t = np.linspace(0.0, 3.0, n)
    v = 25.0 - 8.0 * t
    R, Fz = 0.31, 4413.0
    kappa = np.full(n, -0.1)
    omega = v * (1 + kappa) / R
    mu = np.full(n, -0.9)
    stop = OCPResult(t=t, x=np.zeros(n), v=v, omega=omega, brake_torque=np.zeros(n),
                     kappa=kappa, mu=mu, T_tread=np.full(n, 273.15), torque_rate=np.zeros(n - 1),
                     stopping_distance=0.0, stop_time=3.0, solve_time_s=0.0, setup_time_s=0.0,
                     iterations=0, status="")
    base = QuarterCar(mass=Fz / 9.80665, wheel_inertia=1.2, radius=R, brake_torque_max=3000.0,
                      brake_torque_rate_max=2e4,
                      thermal=ThermalParams(heat_capacity=4500.0, cooling=0.0,
                                            heat_fraction=0.5))
    power = Fz * mu * (omega * R - v)
    T = with_tread_heating(base, stop, 273.15).T_tread
    assert T[-1] - 273.15 == pytest.approx(0.5 * np.trapezoid(power, t) / 4500.0, rel=1e-12)
    # constant power: the speed held, P = Fz mu kappa v
    const = OCPResult(**{**stop.__dict__, "v": np.full(n, 20.0),
                         "omega": np.full(n, 20.0 * 0.9 / R)})
    cool = QuarterCar(**{**base.__dict__,
                         "thermal": ThermalParams(heat_capacity=4500.0, cooling=1500.0,
                                                  heat_fraction=0.5)})
    P = 0.5 * Fz * 0.9 * 0.1 * 20.0
    T = with_tread_heating(cool, const, 273.15).T_tread
    np.testing.assert_allclose(T - 273.15, P / 1500.0 * (1 - np.exp(-1500.0 * t / 4500.0)),
                               rtol=1e-6, atol=1e-9)
