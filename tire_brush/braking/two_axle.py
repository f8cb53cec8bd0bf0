"""Two-axle straight-line braking: longitudinal load transfer, brake balance, one ABS per axle;
and the two-track (four-wheel) car on a split-mu road with its yaw moment.

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
    J w_i' = -R Fx_i - T_b,i - My_i,   T_b,i' = u_i (rate-limited, 0 <= T_b,i <= T_max,i)

``My_i = f_r Fz_i R`` is the tire's rolling resistance moment (smoothly zero on a locked
wheel, :func:`.quarter_car.rolling_resistance_moment`; ``f_r = 0`` by default), as the FMU's
``My`` output puts it on the wheel of the FMU-driven car. ``l_f``, ``l_r`` are the
distances of the centre of gravity from the front and rear axle
(``L = l_f + l_r``), ``h`` its height. ``a`` appears on both sides (the loads depend on the
deceleration they produce); it is solved at every evaluation by fixed-point iteration, which
contracts because ``h |dmu/dFz| / L << 1``. The load dependence of the friction comes from the
force map's ``Fz`` axis. The tread temperature is held at ambient (isothermal: the thermal
state is the quarter car's business).

The closed form that checks it: with a friction independent of load and the *ideal* brake
balance ``phi = (l_r + mu h) / L`` both axles reach their peak together and the stop
approaches the point-mass bound ``v0^2 / (2 mu g)``; any other balance locks (or, with ABS,
cycles) one axle first and stops longer.

**Two-track model, split-mu** (:func:`simulate_two_track`). Four wheels FL, FR, RL, RR, each
with its own spin, brake torque, controller and road: the friction of the left and the right
wheels is scaled by the road of their side (:class:`.road.MuProfile` against the travelled
distance), which makes split-mu (one side on ice) and a mu-jump on one side. The loads are
those of the two-axle model split equally left-right (a straight stop has no lateral
acceleration, so no lateral load transfer). Unequal braking forces left and right give the
car a yaw moment about its centre of gravity (x forward, y left, z up)::

    M_z = -(w / 2) (Fx_FL + Fx_RL - Fx_FR - Fx_RR)        (w: track width)

positive (turning left) when the left wheels brake harder. The car itself is held on a
straight line: the model has no lateral or yaw degree of freedom, as if the driver's steering
cancelled ``M_z`` with lateral forces that cost no longitudinal friction. ``M_z`` is reported
(per time, its peak) as what the steering must hold; it is the quantity split-mu ABS logic
(select-low on the rear axle, yaw-moment build-up delay on the front) limits (Bosch,
*Automotive Handbook*, "Antilock braking system": yaw-moment build-up delay). Closed form
that checks it: all wheels locked on a road of friction ``mu_L`` left, ``mu_R`` right, with a
friction independent of load, decelerate at ``g (mu_L + mu_R) / 2`` with
``M_z = w m g (mu_L - mu_R) / 4`` at every instant (each side carries half the weight,
whatever the front-rear transfer).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tirefric.errors import ConvergenceError, InputError

from .abs_control import BrakeController
from .quarter_car import rolling_resistance_moment
from .reference import G_STANDARD
from .results import Trajectory

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
    track : float
        Track width [m] (distance between the left and right wheels of an axle; the
        two-track model's lever of the yaw moment, :func:`simulate_two_track`).
    rolling_resistance : float
        Rolling resistance coefficient ``f_r`` of every tire [1] (module docstring).
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
    track: float = 1.55
    rolling_resistance: float = 0.0

    def __post_init__(self) -> None:
        for name in ("mass", "wheelbase", "cg_to_front", "cg_height", "wheel_inertia",
                     "radius", "brake_torque_max", "brake_torque_rate_max", "g", "track"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise InputError("must be a finite number > 0", field=f"car.{name}",
                                 value=val)
        if not self.cg_to_front < self.wheelbase:
            raise InputError("must be shorter than the wheelbase", field="car.cg_to_front",
                             value=self.cg_to_front)
        if not (math.isfinite(self.rolling_resistance) and 0 <= self.rolling_resistance < 1):
            raise InputError("must be a finite number in [0, 1)",
                             field="car.rolling_resistance", value=self.rolling_resistance)
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


@dataclass(frozen=True, kw_only=True)
class TwoAxleResult(Trajectory):
    """A two-axle stop: the time histories of :class:`.results.Trajectory` with one column
    per axle (0 front, 1 rear) for the wheel's quantities, and:

    Attributes
    ----------
    Fz : numpy.ndarray
        Axle loads per wheel [N].
    a : numpy.ndarray
        The car's acceleration [m/s^2].
    """

    Fz: np.ndarray
    a: np.ndarray



def _sample_controllers(controllers, t: float, next_sample: np.ndarray, u: np.ndarray,
                        v: float, omega: np.ndarray, torque: np.ndarray) -> None:
    """Update the torque rates ``u`` of the controllers whose sample time has come (each at
    its own ``control_period``; ``next_sample`` advances in place)."""
    for i, c in enumerate(controllers):
        if t >= next_sample[i] - 1e-12:
            u[i] = c.torque_rate(t, v, omega[i], torque[i])
            next_sample[i] += c.control_period


def _rk4(rhs, y: np.ndarray, u: np.ndarray, dt: float) -> np.ndarray:
    """One classical Runge-Kutta step of ``y' = rhs(y, u)`` with ``u`` held."""
    k1 = rhs(y, u)
    k2 = rhs(y + 0.5 * dt * k1, u)
    k3 = rhs(y + 0.5 * dt * k2, u)
    k4 = rhs(y + dt * k3, u)
    return y + dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)


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

    a_last = [0.0]     # the fixed point starts from the last deceleration (1-2 iterations)

    def forces(v: float, w: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
        a = a_last[0]
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
        a_last[0] = a
        return a, Fz, kappa, mu

    def rhs(y: np.ndarray, u: np.ndarray) -> np.ndarray:
        _, v, wf, wr, Tf, Tr = y
        w = np.array([wf, wr])
        a, Fz, _, mu = forces(v, w)
        Fx = Fz * mu
        My = rolling_resistance_moment(car.rolling_resistance, Fz, R, w)
        dw = (-R * Fx - np.array([Tf, Tr]) - My) / J
        return np.array([v, a, dw[0], dw[1], u[0], u[1]])

    y = np.array([0.0, v0, v0 / R, v0 / R, 0.0, 0.0])
    for c in controllers:
        c.reset()
    next_sample = np.zeros(2)
    u = np.zeros(2)
    t = 0.0
    rec = []
    while t < t_max:
        _sample_controllers(controllers, t, next_sample, u, y[1], y[2:4], y[4:6])
        a, Fz, kappa, mu = forces(y[1], y[2:4])
        rec.append((t, y[0], y[1], y[2], y[3], y[4], y[5], *kappa, *mu, *Fz, a))
        y_new = _rk4(rhs, y, u, dt)
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


#: Wheel names of the two-track model, in array order.
WHEELS = ("FL", "FR", "RL", "RR")
#: Lateral side of each wheel (+1 left, -1 right) and its axle (0 front, 1 rear).
WHEEL_SIDE = np.array([1.0, -1.0, 1.0, -1.0])
WHEEL_AXLE = np.array([0, 0, 1, 1])


@dataclass(frozen=True, kw_only=True)
class TwoTrackResult(Trajectory):
    """A two-track stop: the time histories of :class:`.results.Trajectory` with the
    per-wheel quantities in the columns :data:`WHEELS` (``mu`` is the force ratio of the
    tire on that wheel's road), and:

    Attributes
    ----------
    a : numpy.ndarray
        The car's acceleration [m/s^2].
    Fz, Fx, road : numpy.ndarray
        Per wheel: load [N], longitudinal force [N], road friction factor [1].
    yaw_moment : numpy.ndarray
        ``M_z`` about the centre of gravity [N m] (module docstring), positive turning left.
    """

    a: np.ndarray
    Fz: np.ndarray
    Fx: np.ndarray
    road: np.ndarray
    yaw_moment: np.ndarray

    def summary(self) -> dict[str, float]:
        """Stopping distance and time, peak |yaw moment| and its mean over the stop."""
        dt = np.diff(self.t)
        mz = 0.5 * (self.yaw_moment[1:] + self.yaw_moment[:-1])
        return {"stopping_distance": self.stopping_distance, "stop_time": self.stop_time,
                "yaw_moment_peak_Nm": float(np.max(np.abs(self.yaw_moment))),
                "yaw_moment_mean_Nm": float(np.sum(mz * dt) / np.sum(dt))}


def yaw_moment(track: float, Fx: np.ndarray) -> np.ndarray:
    """``M_z = -(w / 2) sum_i side_i Fx_i`` [N m] for forces ``Fx`` [..., 4] in the order of
    :data:`WHEELS` (module docstring)."""
    return -0.5 * track * np.sum(np.asarray(Fx) * WHEEL_SIDE, axis=-1)


def wheel_load_split(car: TwoAxleCar, a: float) -> np.ndarray:
    """Loads of the four wheels [N] at the acceleration ``a`` (order :data:`WHEELS`)."""
    f, r = car.wheel_loads(a)
    return np.array([f, f, r, r])


def simulate_two_track(car: TwoAxleCar, fx_over_fz, controllers, v0: float, v_stop: float,
                       T_ambient: float, *, road_left=None, road_right=None,
                       dt: float = 2e-4, t_max: float = 30.0) -> TwoTrackResult:
    """Brake the four-wheel car from ``v0`` to ``v_stop`` [m/s], one controller per wheel.

    Parameters
    ----------
    car
        The car (its ``track`` is the yaw moment's lever).
    fx_over_fz
        Friction ``Fx/Fz(kappa, vx, Fz, T_K)`` broadcasting over numpy arrays (a
        :class:`.ForceMap`, or a function of the kind), evaluated for the four wheels at once.
    controllers
        Four brake controllers in the order :data:`WHEELS` (rate per wheel: its axle's
        share, :func:`axle_rates`); a wheel's torque is capped at its axle's share of
        ``brake_torque_max``.
    road_left, road_right
        Friction factor against travelled distance of each side (:class:`.road.MuProfile`);
        None: 1. Split-mu: ``road_left=MuProfile.uniform(1.0), road_right=MuProfile.uniform(
        0.3)``.
    dt
        RK4 step [s]. The stiffest wheel mode, ``R^2 Fz (d mu/d kappa) / (J v)``, stays
        below ~1e4 1/s down to 1 m/s for a passenger car, inside RK4's limit ``2.8 / dt``
        at the default 0.2 ms.
    t_max
        Give up after this time [s].

    The loads depend on the deceleration they produce: at each evaluation the friction is
    taken at the loads of the current estimate of ``a`` and the linear equation
    ``m a = sum_i Fz_i(a) mu_i`` solved for the new ``a``, until it settles (two or three
    map calls; one more than the load dependence of the friction needs).
    """
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    controllers = tuple(controllers)
    if len(controllers) != 4:
        raise InputError("need four controllers (FL, FR, RL, RR)", field="controllers",
                         value=len(controllers))
    R, J, m = car.radius, car.wheel_inertia, car.mass
    phi = car.brake_balance
    cap = car.brake_torque_max / 2.0 * np.array([phi, phi, 1.0 - phi, 1.0 - phi])
    L, h = car.wheelbase, car.cg_height
    dFz = m * h / (2.0 * L) * np.array([-1.0, -1.0, 1.0, 1.0])   # dFz_i / da
    left, right = road_left, road_right

    def factors(x: float) -> np.ndarray:
        fl = 1.0 if left is None else float(left(x))
        fr = 1.0 if right is None else float(right(x))
        return np.array([fl, fr, fl, fr])

    a_last = [0.0]     # the fixed point starts from the last deceleration (1-2 iterations)

    def forces(x: float, v: float, w: np.ndarray):
        f = factors(x)
        kappa = (w * R - v) / v
        a = a_last[0]
        for _ in range(30):
            Fz = wheel_load_split(car, a)
            mu = np.asarray(fx_over_fz(kappa, v, Fz, T_ambient), dtype=float) * f
            # m a = sum (Fz_i(a_k) + dFz_i (a - a_k)) mu_i, linear in a
            a_new = float(np.sum((Fz - dFz * a) * mu) / (m - np.sum(dFz * mu)))
            if abs(a_new - a) <= 1e-10 * (1.0 + abs(a)):
                a = a_new
                break
            a = a_new
        else:
            raise ConvergenceError("load transfer did not converge")
        a_last[0] = a
        Fz = wheel_load_split(car, a)
        return a, Fz, kappa, mu, f

    def rhs(y: np.ndarray, u: np.ndarray) -> np.ndarray:
        w = np.maximum(y[2:6], 0.0)
        a, Fz, _, mu, _ = forces(y[0], y[1], w)
        My = rolling_resistance_moment(car.rolling_resistance, Fz, R, w)
        dw = (-R * Fz * mu - y[6:10] - My) / J
        # the brake is a friction torque: it holds a stopped wheel, never turns it backwards
        dw[(w <= 0.0) & (dw < 0.0)] = 0.0
        return np.concatenate(([y[1], a], dw, u))

    y = np.concatenate(([0.0, v0], np.full(4, v0 / R), np.zeros(4)))
    for c in controllers:
        c.reset()
    next_sample = np.zeros(4)
    u = np.zeros(4)
    t = 0.0
    rec = []
    while t < t_max:
        _sample_controllers(controllers, t, next_sample, u, y[1], y[2:6], y[6:10])
        a, Fz, kappa, mu, f = forces(y[0], y[1], y[2:6])
        rec.append(np.concatenate(([t, y[0], y[1], a], y[2:6], y[6:10], kappa, mu, Fz, f)))
        y_new = _rk4(rhs, y, u, dt)
        y_new[2:6] = np.maximum(y_new[2:6], 0.0)
        y_new[6:10] = np.clip(y_new[6:10], 0.0, cap)
        if y_new[1] <= v_stop:
            s = (y[1] - v_stop) / (y[1] - y_new[1])
            stop = y + s * (y_new - y)
            stop[1] = v_stop
            t_stop = t + s * dt
            a, Fz, kappa, mu, f = forces(stop[0], v_stop, stop[2:6])
            rec.append(np.concatenate(([t_stop, stop[0], v_stop, a], stop[2:6], stop[6:10],
                                       kappa, mu, Fz, f)))
            arr = np.array(rec)
            Fx = arr[:, 20:24] * arr[:, 16:20]
            return TwoTrackResult(
                t=arr[:, 0], x=arr[:, 1], v=arr[:, 2], a=arr[:, 3], omega=arr[:, 4:8],
                brake_torque=arr[:, 8:12], kappa=arr[:, 12:16], mu=arr[:, 16:20],
                Fz=arr[:, 20:24], Fx=Fx, road=arr[:, 24:28],
                yaw_moment=yaw_moment(car.track, Fx),
                stopping_distance=float(stop[0]), stop_time=float(t_stop))
        y = y_new
        t += dt
    raise ConvergenceError(f"the car did not reach {v_stop:g} m/s within {t_max:g} s")


def wheel_rates(car: TwoAxleCar) -> tuple[float, float, float, float]:
    """Brake torque rate of each wheel [N m/s] in the order :data:`WHEELS`."""
    f, r = axle_rates(car)
    return (f, f, r, r)
