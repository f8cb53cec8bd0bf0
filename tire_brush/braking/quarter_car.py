"""Quarter-car braking model: parameters and equations of motion (numpy and CasADi alike).

States: travelled distance ``x`` [m], vehicle speed ``v`` [m/s], wheel spin ``omega`` [rad/s],
brake torque ``T_b`` [N m] (an actuator state, so that its rate can be bounded) and, when the
thermal state is on, the lumped tread temperature ``T_tread`` [K].

Equations (e.g. Savaresi & Tanelli, *Active Braking Control Systems Design for Vehicles*,
Springer 2010, eq. (2.1)-(2.3); Kiencke & Nielsen 2005, wheel dynamics)::

    x'     = v
    m v'   = Fx,                      Fx = Fz mu(kappa, v, Fz, T)
    J w'   = -R Fx - T_b              (omega >= 0: the brake opposes the spin)
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

from lookup.config import Table
from lookup.errors import InputError

from .reference import G_STANDARD


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
    """

    mass: float
    wheel_inertia: float
    radius: float
    brake_torque_max: float
    brake_torque_rate_max: float
    g: float = G_STANDARD
    thermal: ThermalParams | None = None
    name: str = "quarter_car"

    def __post_init__(self) -> None:
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
    domega = (-car.radius * Fx - T_b) / car.wheel_inertia
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
