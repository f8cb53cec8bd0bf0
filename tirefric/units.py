"""The one unit vocabulary of tirefric: unit strings, their dimensions and SI conversions.

Data files, command-line options and the FMU's variables write quantities in the units of
this table (``"6 MPa"``, ``"20 degC"``, ``"N s/m^3"``); :func:`to_si` converts them to SI, the
only units inside the code (docs/design.md, "Units"). An unknown unit is an error, and a unit
that could mean two things (``1/s``) is refused with the reason.

Each dimension has one SI unit (:data:`SI_UNITS`), written as the FMU's model description
writes it: the Modelica unit syntax of FMI 2.0 (``"N.s/m3"``, ``"N.m/rad"``; products with a
dot, powers as digits). That spelling is what a tire parameter, an FMU input or output and a
generated C header call the unit (:func:`si_unit`); the FMU's unit definitions are derived
from its base-unit exponents (:func:`base_units`). Data files may write either spelling
(``"N s/m^3"`` and ``"N.s/m3"`` are the same entry of :data:`UNITS`).
"""

from __future__ import annotations

import math
from typing import Any

#: Unit conversions to SI, by dimension: unit -> (factor, offset); SI = value * factor + offset.
UNITS: dict[str, dict[str, tuple[float, float]]] = {
    "pressure": {"Pa": (1.0, 0.0), "kPa": (1e3, 0.0), "MPa": (1e6, 0.0), "GPa": (1e9, 0.0)},
    "length": {
        "m": (1.0, 0.0), "cm": (1e-2, 0.0), "mm": (1e-3, 0.0), "um": (1e-6, 0.0),
        "nm": (1e-9, 0.0),
    },
    "wavenumber": {"1/m": (1.0, 0.0), "1/mm": (1e3, 0.0), "1/um": (1e6, 0.0)},
    # "1/s" is refused as ambiguous (rad/s or cycles/s?): see AMBIGUOUS_UNITS
    "angular_frequency": {"rad/s": (1.0, 0.0), "Hz": (2.0 * math.pi, 0.0)},
    "time": {"s": (1.0, 0.0), "ms": (1e-3, 0.0), "us": (1e-6, 0.0)},
    "temperature": {"K": (1.0, 0.0), "degC": (1.0, 273.15), "C": (1.0, 273.15),
                    "\u00b0C": (1.0, 273.15)},
    "temperature_difference": {"K": (1.0, 0.0), "degC": (1.0, 0.0), "C": (1.0, 0.0),
                               "\u00b0C": (1.0, 0.0)},
    "velocity": {
        "m/s": (1.0, 0.0), "cm/s": (1e-2, 0.0), "mm/s": (1e-3, 0.0), "um/s": (1e-6, 0.0),
        "km/h": (1.0 / 3.6, 0.0),
    },
    "psd": {"m^4": (1.0, 0.0)},
    "psd_1d": {"m^3": (1.0, 0.0)},
    "conductivity": {"W/(m K)": (1.0, 0.0), "W/m/K": (1.0, 0.0)},
    "heat_capacity": {"J/(kg K)": (1.0, 0.0), "J/kg/K": (1.0, 0.0)},
    "density": {"kg/m^3": (1.0, 0.0), "g/cm^3": (1e3, 0.0)},
    "diffusivity": {"m^2/s": (1.0, 0.0)},
    "energy": {"J": (1.0, 0.0), "eV": (1.602176634e-19, 0.0)},
    "force": {"N": (1.0, 0.0), "kN": (1e3, 0.0)},
    "moment": {"N m": (1.0, 0.0), "kN m": (1e3, 0.0)},
    "stiffness_per_area": {"N/m^3": (1.0, 0.0), "N/mm^3": (1e9, 0.0)},
    "stiffness": {"N/m": (1.0, 0.0), "N/mm": (1e3, 0.0)},
    "rotational_stiffness": {"N m/rad": (1.0, 0.0), "N m/deg": (180.0 / math.pi, 0.0)},
    "rotational_damping": {"N m s/rad": (1.0, 0.0)},
    # tire parameters (tire_brush/params.py)
    "mass_per_area": {"kg/m^2": (1.0, 0.0), "": (1.0, 0.0)},
    "damping_per_area": {"N s/m^3": (1.0, 0.0), "Pa s/m": (1.0, 0.0), "": (1.0, 0.0)},
    "damping": {"N s/m": (1.0, 0.0), "kN s/m": (1e3, 0.0), "": (1.0, 0.0)},
    "heat_capacity_total": {"J/K": (1.0, 0.0), "kJ/K": (1e3, 0.0), "": (1.0, 0.0)},
    "conductance": {"W/K": (1.0, 0.0), "": (1.0, 0.0)},
    "mass": {"kg": (1.0, 0.0)},
    "inertia": {"kg m^2": (1.0, 0.0)},
    "bending_stiffness": {"N m^2": (1.0, 0.0), "N mm^2": (1e-6, 0.0)},
    "angle": {"rad": (1.0, 0.0), "deg": (math.pi / 180.0, 0.0)},
    "dimensionless": {"1": (1.0, 0.0), "": (1.0, 0.0)},
    # a strain amplitude: a fraction or a percentage; without a unit it is refused as
    # ambiguous (see AMBIGUOUS_UNITS): strain sweeps are written both ways
    "strain": {"1": (1.0, 0.0), "%": (1e-2, 0.0)},
}


#: SI unit of each dimension that has one: (unit in the Modelica syntax of FMI 2.0, exponents of
#: the SI base units, FMI 2.0 ``BaseUnit``, where ``rad`` counts as a base unit).
SI_UNITS: dict[str, tuple[str, dict[str, int]]] = {
    "pressure": ("Pa", {"kg": 1, "m": -1, "s": -2}),
    "length": ("m", {"m": 1}),
    "wavenumber": ("1/m", {"m": -1}),
    "angular_frequency": ("rad/s", {"rad": 1, "s": -1}),
    "time": ("s", {"s": 1}),
    "temperature": ("K", {"K": 1}),
    "temperature_difference": ("K", {"K": 1}),
    "velocity": ("m/s", {"m": 1, "s": -1}),
    "psd": ("m4", {"m": 4}),
    "psd_1d": ("m3", {"m": 3}),
    "conductivity": ("W/(m.K)", {"kg": 1, "m": 1, "s": -3, "K": -1}),
    "heat_capacity": ("J/(kg.K)", {"m": 2, "s": -2, "K": -1}),
    "density": ("kg/m3", {"kg": 1, "m": -3}),
    "diffusivity": ("m2/s", {"m": 2, "s": -1}),
    "energy": ("J", {"kg": 1, "m": 2, "s": -2}),
    "force": ("N", {"kg": 1, "m": 1, "s": -2}),
    "moment": ("N.m", {"kg": 1, "m": 2, "s": -2}),
    "stiffness_per_area": ("N/m3", {"kg": 1, "m": -2, "s": -2}),
    "stiffness": ("N/m", {"kg": 1, "s": -2}),
    "rotational_stiffness": ("N.m/rad", {"kg": 1, "m": 2, "s": -2, "rad": -1}),
    "rotational_damping": ("N.m.s/rad", {"kg": 1, "m": 2, "s": -1, "rad": -1}),
    "mass_per_area": ("kg/m2", {"kg": 1, "m": -2}),
    "damping_per_area": ("N.s/m3", {"kg": 1, "m": -2, "s": -1}),
    "damping": ("N.s/m", {"kg": 1, "s": -1}),
    "heat_capacity_total": ("J/K", {"kg": 1, "m": 2, "s": -2, "K": -1}),
    "conductance": ("W/K", {"kg": 1, "m": 2, "s": -3, "K": -1}),
    "mass": ("kg", {"kg": 1}),
    "inertia": ("kg.m2", {"kg": 1, "m": 2}),
    "bending_stiffness": ("N.m2", {"kg": 1, "m": 3, "s": -2}),
    "angle": ("rad", {"rad": 1}),
    "dimensionless": ("1", {}),
    "strain": ("1", {}),
}

# every SI spelling is also a key of its dimension's table (factor 1): a data file may write it
for _dim, (_unit, _) in SI_UNITS.items():
    UNITS.setdefault(_dim, {}).setdefault(_unit, (1.0, 0.0))


def si_unit(dimension: str) -> str:
    """The SI unit of ``dimension`` in the FMI/Modelica spelling (``"N.s/m3"``).

    Raises
    ------
    KeyError
        ``dimension`` is not a dimension of :data:`SI_UNITS`.
    """
    return SI_UNITS[dimension][0]


def base_units(unit: str) -> dict[str, int]:
    """Exponents of the SI base units of an SI unit of :data:`SI_UNITS` (FMI ``BaseUnit``).

    Raises
    ------
    KeyError
        ``unit`` is not the SI unit of any dimension.
    """
    for u, exps in SI_UNITS.values():
        if u == unit:
            return dict(exps)
    raise KeyError(f"'{unit}' is not an SI unit of tirefric.units.SI_UNITS")


#: Units refused for a dimension because they are ambiguous, with the explanation.
AMBIGUOUS_UNITS: dict[str, dict[str, str]] = {
    "angular_frequency": {
        "1/s": "ambiguous frequency unit '1/s': write 'rad/s' for an angular frequency "
               "omega or 'Hz' for a cyclic frequency f (omega = 2 pi f)",
        "s^-1": "ambiguous frequency unit 's^-1': write 'rad/s' for an angular frequency "
                "omega or 'Hz' for a cyclic frequency f (omega = 2 pi f)",
    },
    "strain": {
        "": "a strain without a unit is ambiguous: write '%' for a percentage (10 % = 0.1) "
            "or '1' for a fraction",
    },
}

def to_si(value: float, unit: str, dimension: str) -> float:
    """Convert ``value`` given in ``unit`` to SI for ``dimension``; KeyError if unknown."""
    factor, offset = UNITS[dimension][unit]
    return value * factor + offset


def parse_quantity(value: Any, dimension: str, err) -> float:
    """Turn a TOML value (number, or ``"<number> <unit>"``) into a float in SI units."""
    if isinstance(value, bool):
        raise err("expected a number")
    if isinstance(value, int | float):
        return float(value)
    if isinstance(value, str):
        text = value.strip()
        parts = text.split(None, 1)
        try:
            number = float(parts[0])
        except (ValueError, IndexError):
            raise err("expected a number or '<number> <unit>'") from None
        unit = parts[1].strip() if len(parts) > 1 else ""
        known = UNITS.get(dimension, {})
        if unit in AMBIGUOUS_UNITS.get(dimension, {}):
            raise err(AMBIGUOUS_UNITS[dimension][unit])
        if unit not in known:
            raise err(f"unknown unit '{unit}' for a {dimension.replace('_', ' ')} "
                      f"(known: {', '.join(u for u in known if u)})")
        return to_si(number, unit, dimension)
    raise err("expected a number or '<number> <unit>'")
