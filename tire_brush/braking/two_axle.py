"""Two-axle straight-line braking: longitudinal load transfer, brake balance, one ABS per axle.

The quarter car (:mod:`.quarter_car`) has a constant wheel load. A real car pitches forward
as it brakes: the front axle gains the load the rear loses, and the brake balance (the share
of the brake torque on the front axle) decides which axle reaches its friction limit first.
This model keeps the car rigid (no suspension dynamics; the load transfer is instantaneous)
and symmetric left-right (each axle is one wheel carrying half the axle load, with the axle's
brake torque shared equally), which is the classic brake-proportioning model (e.g. Limpert,
*Brake Design and Safety*, 3rd ed., SAE 2011, ch. 7; Wong, *Theory of Ground Vehicles*,
4th ed., Wiley 2008, sec. 3.3). Equations, with ``a = dv/dt`` (negative when braking)::

    Fz_f = m (g l_r - a h) / (2 L),    Fz_r = m (g l_f + a h) / (2 L)   (per wheel)
    m a  = 2 (Fx_f + Fx_r),            Fx_i = Fz_i mu(kappa_i, v, Fz_i, T)
    J w_i' = -R Fx_i - T_b,i,          T_b,i' = u_i (rate-limited, 0 <= T_b,i <= T_max,i)

``l_f``, ``l_r`` are the distances of the centre of gravity from the front and rear axle
(``L = l_f + l_r``), ``h`` its height. ``a`` appears on both sides (the loads depend on the
deceleration they produce); it is solved at every evaluation by fixed-point iteration, which
contracts because ``h |dmu/dFz| / L << 1``. The load dependence of the friction comes from the
force map's ``Fz`` axis. The tread temperature is held at ambient (isothermal: the thermal
state is the quarter car's business).

The closed form that checks it: with a friction independent of load and the *ideal* brake
balance ``phi = (l_r + mu h) / L`` both axles reach their peak together and the stop
approaches the point-mass bound ``v0^2 / (2 mu g)``; any other balance locks (or, with ABS,
cycles) one axle first and stops longer.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lookup.errors import ConvergenceError, InputError

from .abs_control import BrakeController
from .reference import G_STANDARD

FxOverFz = Callable[[float, float, float, float], float]


@dataclass(frozen=True)
class TwoAxleCar:
    """A rigid two-axle car braking in a straight line (module docstring).

    Attributes
    ----------
    mass : float
        Vehicle mass [kg].
    wheelbase : float
        ``L`` [m].
    cg_to_front : float
        ``l_f``, centre of gravity behind the front axle [m], ``0 < l_f < L``.
    cg_height : float
        ``h`` [m].
    wheel_inertia : float
        Per wheel [kg m^2].
    radius : float
        Rolling radius [m].
    brake_balance : float
        Front share of the total brake torque [1], 0 to 1.
    brake_torque_max : float
        Total brake torque of the car at full pedal [N m] (all four wheels).
    brake_torque_rate_max : float
        Total brake torque rate [N m/s].
    g : float
        Gravity [m/s^2].
    """

    mass: float
    wheelbase: float
    cg_to_front: float
    cg_height: float
    wheel_inertia: float
    radius: float
    brake_balance: float
    brake_torque_max: float
    brake_torque_rate_max: float
    g: float = G_STANDARD

    def __post_init__(self) -> None:
        for name in ("mass", "wheelbase", "cg_to_front", "cg_height", "wheel_inertia",
                     "radius", "brake_torque_max", "brake_torque_rate_max", "g"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise InputError("must be a finite number > 0", field=f"car.{name}",
                                 value=val)
        if not self.cg_to_front < self.wheelbase:
            raise InputError("must be shorter than the wheelbase", field="car.cg_to_front",
                             value=self.cg_to_front)
        if not 0.0 <= self.brake_balance <= 1.0:
            raise InputError("must be in [0, 1]", field="car.brake_balance",
                             value=self.brake_balance)

    def wheel_loads(self, a: float) -> tuple[float, float]:
        """Front and rear load per wheel [N] at the acceleration ``a`` [m/s^2]."""
        m, L, h = self.mass, self.wheelbase, self.cg_height
        lf = self.cg_to_front
        lr = L - lf
        return m * (self.g * lr - a * h) / (2 * L), m * (self.g * lf + a * h) / (2 * L)

    def ideal_brake_balance(self, mu: float) -> float:
        """Front share of the brake torque with which both axles reach the friction ``mu``
        together [1].

        At that moment ``a = -mu g`` and each wheel's torque is ``R mu Fz_i(a) + J mu g / R``
        (its road force plus what decelerates its own inertia), so ``phi = (R^2 m (l_r +
        mu h) / (2 L) + J) / (R^2 m / 2 + 2 J)``; without wheel inertia this is the textbook
        ``(l_r + mu h) / L`` (Limpert 2011, ch. 7).
        """
        R2m = self.radius**2 * self.mass
        lr = self.wheelbase - self.cg_to_front
        J = self.wheel_inertia
        return (R2m * (lr + mu * self.cg_height) / (2 * self.wheelbase) + J) / (R2m / 2 + 2 * J)


@dataclass
class TwoAxleResult:
    """Time histories of a two-axle stop (arrays; index 0 front, 1 rear where two)."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    omega: np.ndarray
    brake_torque: np.ndarray
    kappa: np.ndarray
    mu: np.ndarray
    Fz: np.ndarray
    a: np.ndarray
    stopping_distance: float
    stop_time: float


def simulate_two_axle(car: TwoAxleCar, fx_over_fz: FxOverFz,
                      controllers: tuple[BrakeController, BrakeController], v0: float,
                      v_stop: float, T_ambient: float, *, dt: float = 1e-4,
                      t_max: float = 30.0) -> TwoAxleResult:
    """Brake the car from ``v0`` to ``v_stop`` [m/s] with one controller per axle.

    Each controller commands the brake torque rate of one wheel of its axle (the
    controllers' ``rate_max`` should be that axle's share of the car's, see
    :func:`axle_rates`); the torque of a wheel is capped at its axle's share of
    ``brake_torque_max``. Classical RK4 with step ``dt`` [s] (the wheel dynamics at
    ``v >= v_stop`` stay well inside its stability limit at the default 0.1 ms), the
    controllers sampled at their own periods.
    """
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    R, J, m = car.radius, car.wheel_inertia, car.mass
    phi = car.brake_balance
    T_cap = (car.brake_torque_max * phi / 2.0, car.brake_torque_max * (1.0 - phi) / 2.0)

    def forces(v: float, w: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
        a = 0.0
        for _ in range(50):                     # loads <-> deceleration (module docstring)
            Fz = np.array(car.wheel_loads(a))
            kappa = (w * R - v) / v
            mu = np.array([float(fx_over_fz(float(kappa[i]), v, float(Fz[i]), T_ambient))
                           for i in range(2)])
            a_new = 2.0 * float(np.sum(Fz * mu)) / m
            if abs(a_new - a) <= 1e-10 * (1.0 + abs(a)):
                a = a_new
                break
            a = a_new
        else:
            raise ConvergenceError("load transfer did not converge")
        return a, Fz, kappa, mu

    def rhs(y: np.ndarray, u: np.ndarray) -> np.ndarray:
        _, v, wf, wr, Tf, Tr = y
        w = np.array([wf, wr])
        a, Fz, _, mu = forces(v, w)
        Fx = Fz * mu
        dw = (-R * Fx - np.array([Tf, Tr])) / J
        return np.array([v, a, dw[0], dw[1], u[0], u[1]])

    y = np.array([0.0, v0, v0 / R, v0 / R, 0.0, 0.0])
    for c in controllers:
        c.reset()
    periods = [c.control_period for c in controllers]
    next_sample = [0.0, 0.0]
    u = np.zeros(2)
    t = 0.0
    rec = []
    while t < t_max:
        for i, c in enumerate(controllers):
            if t >= next_sample[i] - 1e-12:
                u[i] = c.torque_rate(t, y[1], y[2 + i], y[4 + i])
                next_sample[i] += periods[i]
        a, Fz, kappa, mu = forces(y[1], y[2:4])
        rec.append((t, y[0], y[1], y[2], y[3], y[4], y[5], *kappa, *mu, *Fz, a))
        k1 = rhs(y, u)
        k2 = rhs(y + 0.5 * dt * k1, u)
        k3 = rhs(y + 0.5 * dt * k2, u)
        k4 = rhs(y + dt * k3, u)
        y_new = y + dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        y_new[2:4] = np.maximum(y_new[2:4], 0.0)
        y_new[4] = min(max(y_new[4], 0.0), T_cap[0])
        y_new[5] = min(max(y_new[5], 0.0), T_cap[1])
        if y_new[1] <= v_stop:
            s = (y[1] - v_stop) / (y[1] - y_new[1])
            stop = y + s * (y_new - y)
            t_stop = t + s * dt
            arr = np.array(rec)
            return TwoAxleResult(
                t=np.append(arr[:, 0], t_stop), x=np.append(arr[:, 1], stop[0]),
                v=np.append(arr[:, 2], v_stop), omega=arr[:, 3:5], brake_torque=arr[:, 5:7],
                kappa=arr[:, 7:9], mu=arr[:, 9:11], Fz=arr[:, 11:13], a=arr[:, 13],
                stopping_distance=float(stop[0]), stop_time=float(t_stop))
        y = y_new
        t += dt
    raise ConvergenceError(f"the car did not reach {v_stop:g} m/s within {t_max:g} s")


def axle_rates(car: TwoAxleCar) -> tuple[float, float]:
    """Brake torque rate per wheel of the front and rear axle [N m/s] (the balance applied
    to the car's total rate)."""
    phi = car.brake_balance
    return (car.brake_torque_rate_max * phi / 2.0,
            car.brake_torque_rate_max * (1.0 - phi) / 2.0)
