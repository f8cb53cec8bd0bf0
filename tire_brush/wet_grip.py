"""Wet-grip bookkeeping of UN Regulation No. 117 (Annex 5) / ISO 23671 and the EU label class.

* Braking force coefficient from a braking run between v1 and v2 over the distance d:
  BFC = (v1^2 - v2^2) / (2 g d) (mean fully developed deceleration over g; the regulation's
  vehicle method brakes from 80 to 20 km/h); the trailer method's peak BFC = max Fx / Fz.
* Temperature correction: a BFC measured at the wetted-surface temperature T is brought to
  20 C by adding ``TEMPERATURE_COEFFICIENT * (T - 20 C)``, a = 0.002 per K about 20 C (UN
  Regulation No. 117, 04 series, Annex 5: the reference tire's peak braking force
  coefficient corrected with a = 0.002 /degC).
* Wet grip index of a candidate tire against the standard reference test tire (SRTT), whose
  index is 1.25 by definition: G = 1.25 BFC_candidate / BFC_reference, both corrected to
  20 C.
* EU tire label (Regulation (EU) 2020/740, C1 tires): A >= 1.55, B 1.40-1.54, C 1.25-1.39,
  D 1.10-1.24, E <= 1.09; the classes are given to two decimals, so G is rounded to 0.01
  before it is classed.
"""

from __future__ import annotations

import math

from tirefric.errors import InputError

G_ACCEL = 9.80665  # standard gravity [m/s^2]
REFERENCE_INDEX = 1.25
TEMPERATURE_COEFFICIENT = 0.002  # per K, module docstring
#: (lowest G of the class, class) from the best class down.
LABEL_CLASSES: tuple[tuple[float, str], ...] = (
    (1.55, "A"), (1.40, "B"), (1.25, "C"), (1.10, "D"), (-math.inf, "E"))


def _positive(name: str, x: float) -> float:
    if not (math.isfinite(x) and x > 0):
        raise InputError("must be finite and > 0", field=name, value=x)
    return float(x)


def braking_force_coefficient(v1: float, v2: float, distance: float) -> float:
    """BFC = (v1^2 - v2^2) / (2 g d) for speeds [m/s] v1 > v2 >= 0 and distance d [m]."""
    _positive("v1", v1)
    if not (math.isfinite(v2) and 0 <= v2 < v1):
        raise InputError("must be finite, >= 0 and below v1", field="v2", value=v2)
    return (v1 * v1 - v2 * v2) / (2.0 * G_ACCEL * _positive("distance", distance))


def temperature_corrected(bfc: float, T_C: float) -> float:
    """BFC brought to 20 C: bfc + TEMPERATURE_COEFFICIENT (T - 20) (module docstring)."""
    if not math.isfinite(T_C):
        raise InputError("must be finite [C]", field="T_C", value=T_C)
    return _positive("bfc", bfc) + TEMPERATURE_COEFFICIENT * (T_C - 20.0)


def wet_grip_index(bfc_candidate: float, bfc_reference: float, T_candidate_C: float = 20.0,
                   T_reference_C: float = 20.0) -> float:
    """G = 1.25 BFC_candidate / BFC_reference, each corrected to 20 C."""
    return REFERENCE_INDEX * (temperature_corrected(bfc_candidate, T_candidate_C)
                              / temperature_corrected(bfc_reference, T_reference_C))


def label_class(G: float) -> str:
    """EU label wet-grip class of index G (rounded to 0.01 first; module docstring)."""
    if not math.isfinite(G):
        raise InputError("must be finite", field="G", value=G)
    g = round(G + 1e-12, 2)
    for lo, cls in LABEL_CLASSES:
        if g >= lo - 1e-9:
            return cls
    return "E"
