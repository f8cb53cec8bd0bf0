"""Quarter-car braking model: parameters and equations of motion (numpy and CasADi alike).

States: travelled distance ``x`` [m], vehicle speed ``v`` [m/s], wheel spin ``omega`` [rad/s],
brake torque ``T_b`` [N m] (an actuator state, so that its rate can be bounded) and, when the
thermal state is on, the lumped tread temperature ``T_tread`` [K].

Equations (e.g. Savaresi & Tanelli, *Active Braking Control Systems Design for Vehicles*,
Springer 2010, eq. (2.1)-(2.3); Kiencke & Nielsen 2005, wheel dynamics)::

    x'     = v
    m v'   = Fx,                      Fx = Fz mu(kappa, v, Fz, T)
    J w'   = -R Fx - T_b - f_r Fz R   (omega >= 0: the brake opposes the spin; f_r Fz R the
                                       rolling resistance moment My of the tire)
    T_b'   = u                        (|u| <= brake_torque_rate_max, 0 <= T_b <= T_b,max)
    C T'   = eta Fx (omega R - v) - h (T - T_amb)     (thermal state, optional)

with ``kappa = (omega R - v) / v`` (Pacejka 2012 sec. 2.2; negative in braking) and the static
wheel load ``Fz = m g`` (a quarter car has no load transfer, no aerodynamic drag and no rolling
resistance: only the tire force brakes the car, which is what the point-mass bound
``v0^2 / (2 g mu_max)`` assumes). ``Fx (omega R - v)`` is the friction power in the contact
(>= 0), of which the fraction ``eta`` heats the tread.

Slip is singular at ``v = 0``: studies brake from ``v0`` down to a small end speed ``v_stop``
(1 m/s in the shipped specs) and report the distance travelled until then. From 1 m/s a car at
mu ~ 1 stops within another ~5 cm, well below the differences the study compares.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tirefric.config import Table
from tirefric.errors import InputError

from .reference import G_STANDARD

#: Rolling speed [m/s] below which the rolling resistance moment vanishes (the creep limit
#: of :data:`tire_brush.rolling_resistance.V_CREEP`, the first speed node of the core's table).
V_CREEP = 0.1


@dataclass(frozen=True)
class ThermalParams:
    """Lumped tread-temperature state (optional).

    Attributes
    ----------
    heat_capacity : float
        Heat capacity of the tread layer that the friction power heats [J/K].
    cooling : float
        Conductance of the heat loss towards ambient (road, air, carcass) [W/K].
    heat_fraction : float
        Share of the contact friction power that goes into the tread [1], 0 to 1.
    """

    heat_capacity: float
    cooling: float
    heat_fraction: float = 0.5

    def __post_init__(self) -> None:
        for name in ("heat_capacity", "cooling", "heat_fraction"):
            val = getattr(self, name)
            if not math.isfinite(val) or val < 0:
                raise InputError("must be a finite number >= 0", field=f"thermal.{name}",
                                 value=val)
        if self.heat_capacity <= 0:
            raise InputError("must be > 0", field="thermal.heat_capacity",
                             value=self.heat_capacity)
        if self.heat_fraction > 1:
            raise InputError("must be <= 1", field="thermal.heat_fraction",
                             value=self.heat_fraction)


@dataclass(frozen=True)
class QuarterCar:
    """Quarter-car parameters (one corner of the vehicle).

    Attributes
    ----------
    mass : float
        Quarter of the vehicle mass, wheel included [kg].
    wheel_inertia : float
        Polar moment of inertia of the wheel, brake disc and drive line share [kg m^2].
    radius : float
        Effective rolling radius R [m].
    brake_torque_max : float
        Largest brake torque the actuator gives [N m].
    brake_torque_rate_max : float
        Largest rate of change of the brake torque, apply and release alike [N m/s].
    g : float
        Gravitational acceleration [m/s^2].
    thermal : ThermalParams or None
        Tread-temperature state; None leaves the tread at the ambient temperature.
    name : str
        Label.
    rolling_resistance : float
        Rolling resistance coefficient f_r [1] of the tire: the moment ``f_r Fz R`` (the
        tire's ``My``) acts on the wheel against the spin. It brakes the wheel, not the car
        (only the tire force ``Fx`` does, as in MF-Tyre's convention), so the point-mass
        bound is unchanged. 0: none. A study sets it from the brush tire's rolling-resistance
        model (:func:`tire_brush.braking.friction.brush_rolling_resistance`). The moment
        vanishes with the rolling speed ``V_r = omega R`` as
        ``V_r / sqrt(V_r^2 + V_CREEP^2)``: a smooth form (the OCP needs one) of the tire
        core's creep limit, ``My`` proportional to ``V_r`` below ``V_CREEP`` (a viscoelastic
        solid's loss modulus is linear in frequency at low frequency); 0.5 % below the full
        value at 1 m/s. A locked wheel has none.
    """

    mass: float
    wheel_inertia: float
    radius: float
    brake_torque_max: float
    brake_torque_rate_max: float
    g: float = G_STANDARD
    thermal: ThermalParams | None = None
    name: str = "quarter_car"
    rolling_resistance: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.rolling_resistance) and 0 <= self.rolling_resistance < 1):
            raise InputError("must be a finite number in [0, 1)", field="rolling_resistance",
                             value=self.rolling_resistance)
        for name in ("mass", "wheel_inertia", "radius", "brake_torque_max",
                     "brake_torque_rate_max", "g"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise InputError("must be a finite number > 0", field=name, value=val)

    @property
    def Fz(self) -> float:
        """Static wheel load ``m g`` [N]."""
        return self.mass * self.g


def load_quarter_car(path: str | Path) -> QuarterCar:
    """Read a quarter car from TOML (see ``models/studies/vehicles/passenger.toml``).

    Keys of ``[quarter_car]``: ``mass`` (mass), ``wheel_inertia`` (kg m^2), ``radius``
    (length), ``brake_torque_max_Nm``, ``brake_torque_rate_max_Nm_per_s``; optional
    ``[quarter_car.thermal]`` with ``heat_capacity_J_per_K``, ``cooling_W_per_K``,
    ``heat_fraction``. Errors name the file, the field and the value.
    """
    root = Table.load(path)
    root.raw("provenance", "")
    t = root.table("quarter_car")
    thermal = None
    th = t.table("thermal", required=False)
    if th is not None:
        thermal = ThermalParams(
            heat_capacity=th.quantity("heat_capacity_J_per_K", "dimensionless", positive=True),
            cooling=th.quantity("cooling_W_per_K", "dimensionless", nonnegative=True),
            heat_fraction=th.quantity("heat_fraction", "dimensionless", minimum=0.0,
                                      maximum=1.0),
        )
        th.check_unknown()
    car = QuarterCar(
        mass=t.quantity("mass", "mass", positive=True),
        wheel_inertia=t.quantity("wheel_inertia", "inertia", positive=True),
        radius=t.quantity("radius", "length", positive=True),
        brake_torque_max=t.quantity("brake_torque_max_Nm", "dimensionless", positive=True),
        brake_torque_rate_max=t.quantity("brake_torque_rate_max_Nm_per_s", "dimensionless",
                                         positive=True),
        thermal=thermal,
        name=t.string("name", Path(path).stem),
    )
    t.check_unknown()
    root.check_unknown()
    return car


def slip(v, omega, radius: float):
    """Longitudinal slip ``kappa = (omega R - v) / v`` [1] (Pacejka 2012 sec. 2.2), ``v > 0``."""
    return (omega * radius - v) / v


def rolling_resistance_moment(f_r, Fz, radius, omega):
    """Rolling resistance moment on the wheel [N m], against its spin: ``f_r Fz R`` times
    ``V_r / sqrt(V_r^2 + V_CREEP^2)`` with ``V_r = omega R`` (the smooth creep limit of
    :attr:`QuarterCar.rolling_resistance`; a locked wheel has none). Floats, numpy arrays
    and CasADi expressions alike."""
    Vr = omega * radius
    return f_r * Fz * radius * Vr / (Vr * Vr + V_CREEP**2) ** 0.5


def rhs(car: QuarterCar, mu, v, omega, T_b, u, T_tread, T_ambient: float):
    """Time derivatives ``(x', v', omega', T_b', T_tread')`` of the quarter car.

    Works on floats, numpy arrays and CasADi expressions alike (plain arithmetic only).

    Parameters
    ----------
    car
        Quarter-car parameters.
    mu
        Force ratio ``Fx/Fz`` [1] at the current state (negative in braking).
    v, omega, T_b, T_tread
        Speed [m/s], wheel spin [rad/s], brake torque [N m], tread temperature [K].
    u
        Brake torque rate [N m/s].
    T_ambient
        Ambient (background) temperature the tread cools towards [K].
    """
    Fx = car.Fz * mu
    dx = v
    dv = Fx / car.mass
    # rolling resistance moment, vanishing with the rolling speed (creep limit below)
    My = rolling_resistance_moment(car.rolling_resistance, car.Fz, car.radius, omega)
    domega = (-car.radius * Fx - T_b - My) / car.wheel_inertia
    if car.thermal is None:
        dT = 0.0 * T_tread
    else:
        th = car.thermal
        power = Fx * (omega * car.radius - v)
        dT = (th.heat_fraction * power - th.cooling * (T_tread - T_ambient)) / th.heat_capacity
    return dx, dv, domega, u, dT


def tread_temperature_rise_bound(car: QuarterCar, v0: float) -> float:
    """Largest tread-temperature rise a stop from ``v0`` [m/s] can cause [K].

    The friction work in the contact, ``int Fx (omega R - v) dt``, is at most the kinetic
    energy the stop removes, ``E = m v0^2 / 2 + J (v0 / R)^2 / 2`` (the brake dissipates
    the rest); the tread receives the fraction ``eta`` of it and cooling only lowers the
    temperature: ``dT <= eta E / C``. Zero without the thermal state.
    """
    th = car.thermal
    if th is None:
        return 0.0
    energy = 0.5 * car.mass * v0**2 + 0.5 * car.wheel_inertia * (v0 / car.radius) ** 2
    return th.heat_fraction * energy / th.heat_capacity


def ramp_limited_stopping_distance(
    car: QuarterCar,
    v0: float,
    v_stop: float,
    mu_max,
    brake_torque_initial: float = 0.0,
    dt: float = 1e-3,
) -> float:
    """Lower bound on the distance from ``v0`` to ``v_stop`` [m] with the brake torque's rate
    limit: no stop of the quarter car (module doc) that starts free rolling and keeps
    ``kappa <= 0`` is shorter.

    Two limits hold along every such stop:

    * friction: ``v' = g mu >= -g mu_max(v)`` (the tire force never exceeds the peak);
    * brake impulse: eliminating ``Fx`` between ``m v' = Fx`` and ``J omega' = -R Fx - T_b``
      and integrating from t = 0 (free rolling, ``omega(0) = v0 / R``) gives
      ``m (v0 - v) = [J (omega - v0 / R) + I(t)] / R`` with ``I(t) = int_0^t T_b``; braking
      slip means ``omega <= v / R``, so ``(m + J / R^2) (v0 - v(t)) <= I(t) / R``, and the
      torque, ramped at its rate limit from ``T_b(0)`` and capped at ``T_b,max``, bounds
      ``I(t) <= int_0^t min(T_b(0) + u_max s, T_b,max) ds``. Before the torque has built
      up, the car cannot decelerate at ``g mu_max``.

    The lowest speed that obeys both is found on a time grid of step ``dt``:
    ``w_{k+1} = max(r(t_{k+1}), Phi_dt(w_k))``, with ``r`` the impulse limit and ``Phi`` the
    flow of ``w' = -g mu_max(w)`` (classical Runge-Kutta); by the comparison principle for
    that flow every stop has ``v(t_k) >= w_k``, so it reaches ``v_stop`` no earlier and has
    covered at least ``int w dt`` by then. The bound is that integral (trapezoidal rule,
    the last step cut at ``v_stop``). Without the ramp (``u_max -> inf``) it is the point
    -mass bound ``int_{v_stop}^{v0} v / (g mu_max(v)) dv``.

    Parameters
    ----------
    car
        Quarter car (mass, wheel inertia, radius, brake torque limits, g).
    v0, v_stop
        Initial and final speed [m/s], ``v0 > v_stop > 0``.
    mu_max
        Peak braking friction as a function of speed, ``mu_max(v) > 0`` [1] (numpy arrays
        in and out); over every load and tread temperature the stop can reach.
    brake_torque_initial
        Brake torque at t = 0 [N m].
    dt
        Time step [s]. The discretisation error is O(dt^2): on the Burckhardt dry-asphalt
        curve with the shipped actuator (20 kN m/s) 34.7197 m at 0.5 ms and at 0.1 ms.
    """
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    g, R, u = car.g, car.radius, car.brake_torque_rate_max
    m_eff = car.mass + car.wheel_inertia / R**2
    T0, T_max = float(brake_torque_initial), car.brake_torque_max

    def impulse(t: float) -> float:
        """``int_0^t min(T0 + u s, T_max) ds`` [N m s]."""
        t_cap = max(T_max - T0, 0.0) / u
        if t <= t_cap:
            return T0 * t + 0.5 * u * t * t
        return T0 * t_cap + 0.5 * u * t_cap**2 + T_max * (t - t_cap)

    def decel(w: float) -> float:
        return -g * float(mu_max(np.asarray([max(w, v_stop)]))[0])

    t, w, x = 0.0, v0, 0.0
    t_end = 100.0 * (v0 - v_stop) / (g * float(mu_max(np.asarray([v0]))[0])) + 10.0
    while t < t_end:
        k1 = decel(w)
        k2 = decel(w + 0.5 * dt * k1)
        k3 = decel(w + 0.5 * dt * k2)
        k4 = decel(w + dt * k3)
        w_fric = w + dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0
        w_new = max(v0 - impulse(t + dt) / (R * m_eff), w_fric)
        if w_new <= v_stop:
            h = dt * (w - v_stop) / (w - w_new)     # the step cut where w reaches v_stop
            return x + 0.5 * (w + v_stop) * h
        x += 0.5 * (w + w_new) * dt
        t, w = t + dt, w_new
    raise InputError("the speed bound does not reach v_stop (no friction?)", field="mu_max")
