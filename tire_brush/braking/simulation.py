"""Fixed-step simulation of a quarter-car stop under a brake controller.

Integrator: the two-stage Rosenbrock method ROS2 (Verwer, Spee, Blom & Hundsdorfer, SIAM J.
Sci. Comput. 20 (1999) 1456-1480, eq. (2.3), gamma = 1 + 1/sqrt(2)): second order for any
approximation of the Jacobian (a W-method) and L-stable, so the step is set by accuracy, not by
the stiff wheel mode. That mode has the eigenvalue
``-R^2 Fz (d mu / d kappa) / (J v)``, about -1e4 1/s at 1 m/s for a passenger tire: an
explicit Runge-Kutta step would have to stay below ~0.2 ms near the end of a stop. The
Jacobian used is the exact one of the (v, omega) block with ``d mu / d kappa`` from a forward
difference, ``dx'/dv = 1`` and the thermal cooling term; the remaining couplings are left out
(allowed by the W-method property).

Per controller sample the brake torque rate is the controller's command, held until the next
sample; the controller samples at its own fixed period, which is a whole number of the largest
integration steps, so its decisions fall on the same instants whatever the step. The torque is
clamped to ``[0, T_b,max]`` after each step. A wheel whose spin would turn negative is locked:
``omega`` is clamped to 0, which is the brake acting as a static friction torque (it holds the
wheel while the tire torque is below the brake torque); while it holds, the step integrates
the locked mode (``omega' = 0``, its Jacobian without the wheel row), so that the infeasible
wheel deceleration does not leak into the speed through the W-matrix (it did: the locked
wheel's distance was first order in the step). The stop ends when ``v`` reaches ``v_stop``;
distance and time are interpolated linearly in ``v`` within the last step.

Step control. ``settings.dt`` is the largest step; within a controller period the step is
shortened where one step would not resolve the tire, by two tests (Hairer & Wanner, *Solving
Ordinary Differential Equations II*, 2nd ed., Springer 1996, sec. IV.8, step-size control):

* the local error of the car's speed and of the wheel's peripheral speed ``omega R``,
  estimated by ROS2's embedded first-order solution ``y + h k1`` (Verwer et al. 1999, sec. 2:
  the difference is ``h (k1 + k2) / 2``), must stay below ``settings.speed_tol`` (1e-4 m/s:
  the ABS reads the wheel acceleration as the difference of two samples 5 ms apart, where
  1e-4 m/s is 0.02 m/s^2, a thousandth of its thresholds; a threshold ABS is a discontinuous
  map of the state, and a looser tolerance (1e-3 m/s) flipped one release decision of the
  realistic ABS at 0.5 ms steps and lengthened its stop by 1.8 %);
* past the friction peak ``d mu / d |kappa| < 0`` and the wheel mode is unstable, with a
  positive eigenvalue ``lambda`` of the (v, omega) Jacobian. ROS2's stability function has its
  pole at ``h lambda = 1 / gamma``: near it the step amplifies the slip without bound (measured:
  with fixed steps the wheel of the 0 C brush tire overshot to ``kappa = +4`` at 1.3 m/s, the
  reference-speed estimate of the realistic ABS then read the overspeed as the car's speed and
  released the brake for seconds: 78.5 m at 1 ms, 123.1 m at 0.5 ms, 60.5 m at 0.25 ms). The
  step keeps ``gamma h lambda <= 1/2``.

A rejected step is retried with a shorter one; after an accepted step the next may grow again
up to ``dt``. The largest step is ``dt`` exactly, so a smooth stop, whose steps are never
shortened, is integrated as with a fixed step.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tirefric.errors import ConvergenceError, InputError

from .abs_control import BrakeController
from .force_map import FxOverFz
from .quarter_car import QuarterCar
from .results import Trajectory

GAMMA_ROS2 = 1.0 + 1.0 / math.sqrt(2.0)


@dataclass(frozen=True)
class SimSettings:
    """Fixed-step integration settings.

    Attributes
    ----------
    dt : float
        Largest integration step [s]; rounded down so that the controller period is a whole
        number of steps. Steps are shortened where the wheel needs it (module doc).
    t_max : float
        Give up after this time [s] (a stop that takes longer is an input error: too little
        brake torque).
    record_every : int
        Keep every n-th step in the trajectory.
    speed_tol : float
        Largest local error per step of the car's speed and of the wheel's peripheral speed
        ``omega R`` [m/s] (step control, module doc).
    """

    dt: float = 5e-4
    t_max: float = 60.0
    record_every: int = 1
    speed_tol: float = 1e-4

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and 0 < self.dt <= 0.01):
            raise InputError("must be in (0, 0.01] s", field="simulation.dt", value=self.dt)
        if not (math.isfinite(self.speed_tol) and 0 < self.speed_tol <= 0.1):
            raise InputError("must be in (0, 0.1] m/s", field="simulation.speed_tol",
                             value=self.speed_tol)
        if not (math.isfinite(self.t_max) and self.t_max > 0):
            raise InputError("must be > 0 s", field="simulation.t_max", value=self.t_max)
        if self.record_every < 1:
            raise InputError("must be >= 1", field="simulation.record_every",
                             value=self.record_every)


@dataclass(frozen=True, kw_only=True)
class SimResult(Trajectory):
    """A simulated stop: the time histories of :class:`.results.Trajectory` at the recorded
    steps (the last point is at ``v_stop``) and the step control's report.

    Attributes
    ----------
    T_tread : numpy.ndarray
        Tread temperature [K].
    phase : numpy.ndarray
        Controller phase code per point (:data:`.abs_control.PHASES`).
    dt : float
        Largest step used [s] (steps are shorter where the step control shortened them).
    n_rejected : int
        Steps rejected by the step control (retried shorter).
    """

    T_tread: np.ndarray
    phase: np.ndarray
    dt: float
    n_rejected: int = 0


def simulate_braking(
    car: QuarterCar,
    fx_over_fz: FxOverFz,
    controller: BrakeController,
    v0: float,
    v_stop: float,
    T_ambient: float,
    *,
    settings: SimSettings | None = None,
    brake_torque_initial: float = 0.0,
    road: Callable[[float], float] | None = None,
) -> SimResult:
    """Simulate a straight-line stop from ``v0`` to ``v_stop`` [m/s] under ``controller``.

    Parameters
    ----------
    car
        Quarter car (its ``thermal`` switches the tread-temperature state on).
    fx_over_fz
        Friction ``Fx/Fz(kappa, vx, Fz, T_K)`` (e.g. the study's :class:`.ForceMap`, so the
        simulation and the OCP see identical friction).
    controller
        Brake controller, reset at the start.
    v0, v_stop
        Initial and final speed [m/s], ``v0 > v_stop > 0``.
    T_ambient
        Ambient and initial tread temperature [K].
    settings
        Step and limits.
    brake_torque_initial
        Brake torque at t = 0 [N m]; the wheel starts free rolling (``omega = v0 / R``).
    road
        Friction factor against travelled distance [m] (:class:`.road.MuProfile`): a road
        whose friction changes along the stop. None: uniform.
    """
    settings = settings or SimSettings()
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    Tc = controller.control_period
    n_sub = max(1, math.ceil(Tc / settings.dt - 1e-9))
    h = Tc / n_sub
    R, Fz, m, J = car.radius, car.Fz, car.mass, car.wheel_inertia
    th = car.thermal
    Tmax = car.brake_torque_max
    d_kappa = 1e-6

    def mu_of(kappa: float, v: float, T: float, x: float = 0.0) -> float:
        mu = float(fx_over_fz(kappa, v, Fz, T))
        return mu if road is None else mu * road(x)

    heat = None if th is None else (th.heat_fraction, th.cooling, th.heat_capacity)

    # The state is five Python floats (x, v, omega, T_b, T_tread): the step is the one of the
    # five-vector formulation, component by component, the same floating-point operations
    # in the same order without array set-up per step (the screen's stops, docs/screening.md).
    def f_and_jac(x: float, v: float, w: float, Tb: float, T: float, u: float,
                  need_jac: bool):
        kappa = (w * R - v) / v
        mu = mu_of(kappa, v, T, x)
        Fx = Fz * mu
        f1 = Fx / m
        f2 = (-R * Fx - Tb) / J
        locked = w <= 0.0 and f2 <= 0.0      # the brake holds the wheel: omega stays 0
        if locked:
            f2 = 0.0
        f4 = 0.0 if heat is None else (
            heat[0] * Fx * (w * R - v) - heat[1] * (T - T_ambient)) / heat[2]
        f = (v, f1, f2, u, f4)
        if not need_jac:
            return f, mu, None
        mu_k = (mu_of(kappa + d_kappa, v, T, x) - mu) / d_kappa
        dk_dv, dk_dw = -w * R / v**2, R / v
        a, b = Fz / m * mu_k, -R * Fz / J * mu_k
        if locked:                             # the locked mode's Jacobian: omega' = 0
            return f, mu, (a * dk_dv, a * dk_dw, 0.0, 0.0)
        return f, mu, (a * dk_dv, a * dk_dw, b * dk_dv, b * dk_dw)

    def solve_w(r0: float, r1: float, r2: float, r3: float, r4: float, jac, cool: float,
                gh: float) -> tuple[float, float, float, float, float]:
        jvv, jvw, jwv, jww = jac
        m11, m12, m21, m22 = 1.0 - gh * jvv, -gh * jvw, -gh * jwv, 1.0 - gh * jww
        det = m11 * m22 - m12 * m21
        k1 = (m22 * r1 - m12 * r2) / det
        k2 = (m11 * r2 - m21 * r1) / det
        return (r0 + gh * k1, k1, k2, r3, r4 / (1.0 + gh * cool))

    def unstable_rate(jac) -> float:
        """Largest real part of the (v, omega) block's eigenvalues [1/s]."""
        jvv, jvw, jwv, jww = jac
        half_tr = 0.5 * (jvv + jww)
        disc = half_tr * half_tr - (jvv * jww - jvw * jwv)
        return half_tr + math.sqrt(disc) if disc > 0.0 else half_tr

    cool = 0.0 if th is None else th.cooling / th.heat_capacity
    y = (0.0, float(v0), float(v0 / R), float(brake_torque_initial), float(T_ambient))
    controller.reset()
    t = 0.0
    rec: list[tuple] = []
    n_steps = 0
    n_rejected = 0
    u = 0.0
    phase = controller.phase
    stop = None
    h_min = h * 1e-4
    h_try = h
    n_period = 0
    while t < settings.t_max:
        u = controller.torque_rate(t, y[1], y[2], y[3])
        phase = controller.phase
        t_end = (n_period + 1) * Tc        # the next sample, exactly (no drift of t)
        n_period += 1
        while stop is None and t_end - t > 1e-12 * Tc:
            y0, y1, y2, y3, y4 = y
            f, mu, jac = f_and_jac(y0, y1, y2, y3, y4, u, True)
            if n_steps % settings.record_every == 0:
                rec.append((t, *y, (y2 * R - y1) / y1, mu, phase))
            lam = unstable_rate(jac)
            h_wanted = h_try
            while True:
                hs = min(h_try, t_end - t)
                if lam > 0.0:                  # keep off ROS2's pole at h lambda = 1/gamma
                    hs = min(hs, max(0.5 / (GAMMA_ROS2 * lam), h_min))
                gh = GAMMA_ROS2 * hs
                k1 = solve_w(*f, jac, cool, gh)
                f2, _, _ = f_and_jac(y0 + hs * k1[0], y1 + hs * k1[1], y2 + hs * k1[2],
                                     y3 + hs * k1[3], y4 + hs * k1[4], u, False)
                k2 = solve_w(*(a - 2.0 * b for a, b in zip(f2, k1, strict=True)), jac,
                             cool, gh)
                c1, c2 = 1.5 * hs, 0.5 * hs
                n0, n1, n2, n3, n4 = (a + c1 * b + c2 * c for a, b, c in
                                      zip(y, k1, k2, strict=True))
                n2 = max(n2, 0.0)              # clamp
                n3 = min(max(n3, 0.0), Tmax)
                low1, low2 = y1 + hs * k1[1], max(y2 + hs * k1[2], 0.0)
                # local error: embedded first-order solution y + h k1
                err = max(R * abs(n2 - low2), abs(n1 - low1))
                err /= settings.speed_tol
                if err <= 1.0 or hs <= h_min:
                    break
                n_rejected += 1
                h_try = max(hs * max(0.2, 0.9 / math.sqrt(err)), h_min)
            # next step: grow (the error is second order in h), never beyond dt; a step cut
            # short by the sample instant alone does not shrink the next one
            h_try = min(h, hs * min(2.0, 0.9 / math.sqrt(max(err, 1e-12))))
            if hs == t_end - t and h_try < h_wanted and err <= 0.25:
                h_try = h_wanted
            n_steps += 1
            y_new = (n0, n1, n2, n3, n4)
            if n1 <= v_stop:
                s = (y1 - v_stop) / (y1 - n1)
                stop = [a + s * (b - a) for a, b in zip(y, y_new, strict=True)]
                stop[1] = v_stop
                t_stop = t + s * hs
                break
            y = y_new
            t = t_end if t_end - (t + hs) <= 1e-12 * Tc else t + hs
        if stop is not None:
            break
    if stop is None:
        raise ConvergenceError(f"the car did not reach {v_stop:g} m/s within "
                               f"{settings.t_max:g} s (v = {y[1]:.3g} m/s): too little brake "
                               "torque or friction")
    kappa_stop = (stop[2] * R - v_stop) / v_stop
    rec.append((t_stop, *stop, kappa_stop, mu_of(kappa_stop, v_stop, stop[4], stop[0]),
                phase))
    arr = np.array(rec, dtype=float)
    return SimResult(
        t=arr[:, 0], x=arr[:, 1], v=arr[:, 2], omega=arr[:, 3], brake_torque=arr[:, 4],
        T_tread=arr[:, 5], kappa=arr[:, 6], mu=arr[:, 7], phase=arr[:, 8].astype(int),
        stopping_distance=float(stop[0]), stop_time=float(t_stop), dt=h,
        n_rejected=n_rejected,
    )
