"""Step control of the quarter-car simulation: a stop must not depend on the step.

The friction curve of these tests has the shape of the brush tire on the default grid at 0 C
(docs/physics.md, braking section): a sharp peak at 4 % slip, a steep drop to a trough at 6 %,
a second, higher maximum at 20 % and the sliding friction at lock. Past the first peak the
wheel mode is unstable; with the fixed-step ROS2 of before, the step ran into the pole of the
method's stability function at low speed, the wheel overshot to a driving slip and the
realistic ABS, reading that overspeed as the car's speed, released the brake for seconds.
"""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush.braking import (
    ABSParams,
    ForceMap,
    QuarterCar,
    RealisticABS,
    SimSettings,
    default_axes,
    simulate_braking,
)
from tire_brush.braking.slip_map import optimal_slip
from tire_brush.braking.study import abs_slip_schedule

V0, V_STOP, T_AMB = 60 / 3.6, 1.0, 273.15
CAR = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                 brake_torque_rate_max=2e4)
#: |mu| at braking slips |kappa| (knots of a monotone cubic): the 0 C brush tire's shape
SLIPS = np.array([0.0, 0.01, 0.02, 0.04, 0.06, 0.1, 0.2, 0.4, 1.0])
MUS = np.array([0.0, 0.22, 0.42, 0.75, 0.69, 0.74, 0.77, 0.70, 0.60])


def two_peak(kappa, vx, Fz, T_K):
    """Fx/Fz of the two-peak curve, odd in the slip (driving side mirrored)."""
    from scipy.interpolate import PchipInterpolator

    s = np.abs(np.asarray(kappa, dtype=float))
    mu = PchipInterpolator(SLIPS, MUS)(np.minimum(s, 1.0))
    return np.broadcast_to(np.sign(kappa) * mu, np.broadcast_shapes(
        np.shape(kappa), np.shape(vx), np.shape(Fz), np.shape(T_K)))


@pytest.fixture(scope="module")
def fmap():
    return ForceMap.build(two_peak, **default_axes(V0, V_STOP, CAR.Fz, T_AMB, n_kappa=81,
                                                   n_v=4))


def stop(fmap, make, dt):
    return simulate_braking(CAR, fmap, make(), V0, V_STOP, T_AMB, settings=SimSettings(dt=dt))


def test_realistic_abs_distance_independent_of_the_step(fmap):
    """The realistic ABS (release at the slip map's peak slip) from 60 km/h: the stop at 1 ms
    steps within 1 % of the stop at 0.25 ms (measured: 20.770 m at 1, 0.5 and 0.25 ms; with
    the fixed-step integrator 35.06, 55.83 and 20.77 m, the wheel at up to 2.2 driving slip),
    and the wheel never turns faster than the car rolls (no driving slip in a braking stop)."""
    sm = optimal_slip(fmap, np.geomspace(V_STOP, V0, 9), [CAR.Fz], [T_AMB])
    sched = abs_slip_schedule(sm)

    def make():
        return RealisticABS(ABSParams(), CAR.radius, CAR.brake_torque_rate_max, CAR.mass,
                            slip_schedule=sched)

    runs = {dt: stop(fmap, make, dt) for dt in (1e-3, 2.5e-4)}
    d = {dt: r.stopping_distance for dt, r in runs.items()}
    assert d[1e-3] == pytest.approx(d[2.5e-4], rel=0.01), f"distance per step [s]: {d}"
    for dt, r in runs.items():
        assert r.kappa.max() < 1e-3, f"driving slip {r.kappa.max():.3g} at dt = {dt} s"
