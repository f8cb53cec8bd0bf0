"""Global slip optimum with a heating tread (tire_brush.braking.thermal_dp) against closed forms.

The dynamic programme is a relaxation of the quarter car's stop (quasi-steady wheel); each
test compares it with a case whose answer is known in closed form, so a wrong step distance,
sliding power, heat share or bound construction fails one of them.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from tire_brush.braking import ForceMap, QuarterCar, default_axes
from tire_brush.braking.quarter_car import ThermalParams, ramp_limited_stopping_distance
from tire_brush.braking.reference import burckhardt_road
from tire_brush.braking.thermal_dp import slip_dp, thermal_ramp_bound

V0, V_STOP, T_AMB = 100 / 3.6, 1.0, 293.15
CAR = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                 brake_torque_rate_max=2e4)


def _map(source, T_nodes=(T_AMB,)):
    ax = default_axes(V0, V_STOP, CAR.Fz, T_AMB)
    ax["T_K"] = np.asarray(T_nodes, dtype=float)
    return ForceMap.build(source, **ax)


def _peak(fmap, T=T_AMB):
    """Largest braking friction of the map at the car's load [1], on a dense slip grid."""
    k = -np.linspace(0.0, 1.0, 20001)[1:]
    return float(np.max(-fmap.on_grid(k, [10.0], [CAR.Fz], [T])))


def test_on_grid_is_the_same_spline_as_pointwise():
    """Tensor-grid evaluation (basis matrices) equals the pointwise spline, clamping and
    single-node axes included: the same coefficients, summed in another order (rounding)."""
    curve = burckhardt_road("asphalt_dry", c4=0.02)

    def source(k, v, f, t):
        return curve(k, v) * (1.0 + 1e-5 * (f - 4000.0)) * (1.0 - 3e-3 * (t - 293.0))

    ax = default_axes(V0, V_STOP, CAR.Fz, T_AMB)
    ax["Fz"] = np.array([3000.0, 4400.0, 6000.0])
    ax["T_K"] = T_AMB + np.array([-4.0, 0.0, 4.0, 8.0])
    fm = ForceMap.build(source, **ax)
    k = np.array([-1.2, -0.6, -0.13, -0.01, 0.0, 0.2])          # beyond both ends too
    v = np.array([0.1, 3.0, 27.0, 50.0])
    f = np.array([2000.0, 4413.0, 7000.0])
    T = np.array([280.0, 293.15, 299.0, 310.0])
    grid = fm.on_grid(k, v, f, T)
    assert grid.shape == (6, 4, 3, 4)
    np.testing.assert_allclose(grid, fm(*np.meshgrid(k, v, f, T, indexing="ij")),
                               rtol=0, atol=1e-13)
    one = fm.fixed(Fz=4413.0)                                    # load axis inactive
    np.testing.assert_allclose(one.on_grid(k, v, [1.0, 9.0], T)[:, :, 1, :],
                               fm.on_grid(k, v, [4413.0], T)[:, :, 0, :], atol=1e-13)


def test_isothermal_dp_is_the_point_mass_stop():
    """Without a thermal state and with a speed-independent curve the best stop of the
    relaxation holds the peak all the way: (v0^2 - v_stop^2) / (2 g mu_max). The mid-speed
    step is exact for a constant deceleration; what is left is the candidate grid missing
    the exact peak (relative error ~ (d kappa / 2)^2 |mu''| / mu ~ 1e-5 at 480 candidates)."""
    fm = _map(burckhardt_road("asphalt_dry"))
    dp = slip_dp(CAR, fm, V0, V_STOP, T_AMB)
    mu = _peak(fm)
    exact = (V0**2 - V_STOP**2) / (2 * CAR.g * mu)
    assert dp.distance == pytest.approx(exact, rel=1e-4)
    # the policy is the peak slip at every speed
    k_peak = burckhardt_road("asphalt_dry").peak_slip()
    np.testing.assert_allclose(np.abs(dp.policy), k_peak, atol=0.01)


def test_isothermal_bound_is_the_ramp_limited_bound():
    """Without heating the bound with the brake's build-up is the ramp-limited bound of the
    quarter car (the same impulse and friction limits; the step is 1 ms in both, O(dt^2))."""
    fm = _map(burckhardt_road("asphalt_dry"))
    mu = _peak(fm)
    b = thermal_ramp_bound(CAR, fm, V0, V_STOP, T_AMB)
    ref = ramp_limited_stopping_distance(CAR, V0, V_STOP, lambda v: np.full_like(v, mu))
    assert b.distance_fine == pytest.approx(ref, rel=1e-3)
    assert b.distance <= ref * (1 + 1e-3)
    # the build-up costs a metre: the bound is well above the point-mass stop
    assert b.distance > (V0**2 - V_STOP**2) / (2 * CAR.g * mu) + 0.5


def test_locked_wheel_heating_matches_its_closed_form():
    """Locked wheel (kappa = -1, sliding speed v), no cooling, friction a + b (T - T_amb):
    the tread takes eta of the car's lost kinetic energy, T - T_amb = eta m (v0^2 - v^2) /
    (2 C), so mu = A - c v^2 with c = b eta m / (2 C), A = a + c v0^2, and the distance is
    ln((A - c v_stop^2) / (A - c v0^2)) / (2 c g). Heating shortens this stop by ~25 %; the
    explicit temperature step of the programme is first order (0.3 % at 400 speed steps)."""
    a, b = 0.6, 0.03                                             # [1], [1/K]
    car = replace(CAR, thermal=ThermalParams(heat_capacity=4500.0, cooling=0.0,
                                             heat_fraction=0.5))

    def source(k, v, f, t):                                      # linear: the spline is exact
        return k * (a + b * (t - T_AMB)) + 0.0 * v + 0.0 * f

    fm = _map(source, T_AMB + np.linspace(0.0, 60.0, 7))
    dp = slip_dp(car, fm, V0, V_STOP, T_AMB, kappa=np.array([-1.0]))
    c = b * car.thermal.heat_fraction * car.mass / (2 * car.thermal.heat_capacity)
    A = a + c * V0**2
    exact = math.log((A - c * V_STOP**2) / (A - c * V0**2)) / (2 * c * car.g)
    cold = (V0**2 - V_STOP**2) / (2 * car.g * a)
    assert exact < 0.8 * cold
    assert dp.distance == pytest.approx(exact, rel=5e-3)
    tr = dp.trajectory(car, fm)
    rise = car.thermal.heat_fraction * car.mass * (V0**2 - V_STOP**2) / (
        2 * car.thermal.heat_capacity)
    assert tr["T_tread"][-1] - T_AMB == pytest.approx(rise, rel=5e-3)
    assert tr["x"][-1] == pytest.approx(exact, rel=5e-3)


def test_dp_chooses_heating_only_when_it_pays():
    """Friction that rises with temperature: the slip goes past the peak at speed (more
    sliding power for a little less friction, to heat the tread); friction that falls with
    temperature: it stays below the peak (less sliding power, a cooler tread). Neither stop
    beats the point-mass stop at the best friction the tread can reach (peak x (1 + 0.02
    K^-1 rise) or the cold peak)."""
    from tire_brush.braking.quarter_car import tread_temperature_rise_bound

    curve = burckhardt_road("asphalt_dry")
    nodes = T_AMB + np.linspace(0.0, 24.0, 13)
    car = replace(CAR, thermal=ThermalParams(heat_capacity=4500.0, cooling=150.0))
    k_peak = curve.peak_slip()
    rise = tread_temperature_rise_bound(car, V0)
    for sign in (+1.0, -1.0):
        fm = _map(lambda k, v, f, t, s=sign: curve(k, v) * (1 + s * 0.02 * (t - T_AMB)),
                  nodes)
        dp = slip_dp(car, fm, V0, V_STOP, T_AMB)
        k0 = dp.trajectory(car, fm)["kappa"][0]
        mu_best = _peak(fm) * (1 + 0.02 * rise if sign > 0 else 1.0)
        assert dp.distance >= (V0**2 - V_STOP**2) / (2 * car.g * mu_best) * (1 - 1e-4)
        if sign > 0:
            assert k0 < -(k_peak + 0.03)
        else:
            assert -(k_peak - 0.01) < k0 < 0.0
        assert dp.coast_ratio < 1.0
