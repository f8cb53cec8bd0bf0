"""The FMU's unit definitions against SI, derived here from the unit names alone.

FMI 2.0 (sec. 2.2.2) defines a unit by its exponents of the SI base units
(kg, m, s, A, K, mol, cd, rad) and a display unit by ``display = factor * value + offset``.
The exponents below come from parsing the unit's name with N = kg m s^-2, J = N m and
W = J/s, not from the package's table, so that a wrong exponent in the table is caught.
"""

from __future__ import annotations

import math
import re
from collections import Counter

import pytest

from fmu_src.runtime.interface import DISPLAY_UNITS, UNITS

_DERIVED = {"N": {"kg": 1, "m": 1, "s": -2}, "J": {"kg": 1, "m": 2, "s": -2},
            "W": {"kg": 1, "m": 2, "s": -3}, "Pa": {"kg": 1, "m": -1, "s": -2}}
_BASE = {"kg", "m", "s", "A", "K", "mol", "cd", "rad"}


def _si_exponents(name: str) -> dict[str, int]:
    """Exponents of a Modelica-style unit name such as ``N.s/m3`` (``.`` multiplies, one
    ``/`` divides, a trailing integer is a power)."""
    if name == "1":
        return {}
    num, _, den = name.partition("/")
    out: Counter[str] = Counter()
    for part, sign in ((num, 1), (den, -1)):
        for factor in filter(None, part.split(".")):
            sym, power = re.fullmatch(r"([A-Za-z]+?)(\d*)", factor).groups()
            p = sign * int(power or 1)
            for base, e in (_DERIVED[sym].items() if sym in _DERIVED else [(sym, 1)]):
                assert base in _BASE, f"unknown symbol {sym!r} in unit {name!r}"
                out[base] += p * e
    return {k: v for k, v in out.items() if v}


@pytest.mark.parametrize("name", sorted(UNITS))
def test_unit_exponents_are_si(name: str) -> None:
    assert UNITS[name] == _si_exponents(name), f"base-unit exponents of {name}"


def test_parser_on_hand_values() -> None:
    """The parser itself, on values written out by hand."""
    assert _si_exponents("N.m") == {"kg": 1, "m": 2, "s": -2}
    assert _si_exponents("rad/s") == {"rad": 1, "s": -1}
    assert _si_exponents("N.s/m3") == {"kg": 1, "m": -2, "s": -1}
    assert _si_exponents("W/K") == {"kg": 1, "m": 2, "s": -3, "K": -1}


@pytest.mark.parametrize("unit,display,si_value,shown", [
    ("K", "degC", 273.15, 0.0),          # 0 degC is 273.15 K
    ("K", "degC", 373.15, 100.0),
    ("rad", "deg", math.pi, 180.0),
    ("m/s", "km/h", 10.0, 36.0),
    ("rad/s", "rpm", 2.0 * math.pi, 60.0),  # one turn per second is 60 rpm
    ("N", "kN", 2500.0, 2.5),
])
def test_display_units(unit: str, display: str, si_value: float, shown: float) -> None:
    """display = factor * value + offset (FMI 2.0 DisplayUnit), against hand conversions."""
    (factor, offset), = [(f, o) for n, f, o in DISPLAY_UNITS[unit] if n == display]
    assert factor * si_value + offset == pytest.approx(shown, abs=1e-9), f"{unit} -> {display}"
