"""The FMU's interface as data: variables, units, start values and dependencies.

One table describes every variable of the brush-tire FMU (name, causality, type, unit,
description, start value): the inputs and outputs are the tire's own
(:mod:`tire_brush.signals`), the tire parameters are the fields of
:class:`tire_brush.params.TireParams` with their metadata, and units are SI units of
:mod:`tirefric.units`. The slave (:mod:`fmu_src.runtime.slave`) registers its variables from it
and the build (:mod:`fmu_src.make.model_description`) writes units, unit definitions and the model
structure from the same table, so the two cannot disagree.

Conventions (``docs/design.md``, "Units" and "Conventions"): SI units, FMI structured names.
The tire parameters are the fields of :class:`tire_brush.params.TireParams` under ``tire.``
(``tire.tread.k_x``); every one of them needs an entry in :data:`TIRE_FIELDS`, the build refuses
a tire whose parameters are not all covered.

Inputs are held over a communication step (the transient model's "synchronize, then advance").
Outputs are those of the step just taken; setting an input does not change an output until the
next ``doStep`` (no direct feedthrough: ``ModelStructure/Outputs`` lists no dependencies).
Before the first step the outputs are those of the undeflected tire at the start inputs:
zero forces, ``kappa`` and ``alpha`` of the start kinematics, ``T_tread = T_surface``.

This module imports only the standard library and :mod:`tire_brush.params` (stdlib only): it
runs inside the FMU.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from tire_brush.axes import BRUSH_AXES, SIGNS
from tire_brush.params import GROUPS, TireParams, field_table
from tire_brush.signals import INPUT_NAMES as INPUT_NAMES
from tire_brush.signals import INPUTS, OUTPUTS
from tire_brush.signals import OUTPUT_NAMES as OUTPUT_NAMES
from tirefric.units import base_units

#: Model name and FMI model identifier (name of the binary inside the FMU).
MODEL_NAME = "BrushTire"

#: Display units offered to tools: unit -> (name, factor, offset) with
#: ``display = factor * value + offset`` (FMI 2.0 ``DisplayUnit``).
DISPLAY_UNITS: dict[str, tuple[tuple[str, float, float], ...]] = {
    "K": (("degC", 1.0, -273.15),),
    "rad": (("deg", 180.0 / math.pi, 0.0),),
    "m/s": (("km/h", 3.6, 0.0),),
    "rad/s": (("rpm", 30.0 / math.pi, 0.0),),
    "N": (("kN", 1e-3, 0.0),),
}

#: Bits of the output ``input_status`` (0: the step used the inputs as given).
STATUS_BITS: dict[str, int] = {
    "nonfinite": 1,        # a NaN/inf input was replaced by its last finite value
    "negative_load": 2,    # Fz < 0 was taken as lift-off (Fz = 0)
    "speed_clamped": 4,    # |vx|, |vy| > limit.v or |omega| > limit.omega: clamped
    "load_clamped": 8,     # Fz > limit.Fz: clamped
    "temperature_clamped": 16,  # T_surface outside [limit.T_min, limit.T_max]: clamped
    "mu_scale_clamped": 32,     # mu_scale < 0 or > limit.mu_scale: clamped
    "model_reset": 64,     # the model failed in this step and was reset to rest
    "camber_clamped": 128,  # |gamma| > limit.gamma: clamped
    "water_clamped": 256,   # water_depth < 0 or > limit.water_depth: clamped
    "no_wet_branch": 512,   # water_depth > 0 but the FMU's grid has no wet branch: dry road
    "work_budget": 1024,    # the element integrator's work budget of an outer step was spent:
                            # its remaining elements took one implicit Euler stage
    "temperature_range": 2048,  # the friction was read at a temperature outside the grid's
                                # temperature axis (at the axis' edge)
}
#: Flags of the tire core's last step (tirecore.h, TF_FLAG_*) -> STATUS_BITS key.
MODEL_FLAGS: dict[int, str] = {1: "work_budget", 2: "temperature_range"}


@dataclass(frozen=True)
class Variable:
    """One FMI variable.

    Attributes
    ----------
    name : str
        Structured FMI name.
    causality : str
        ``"input"``, ``"output"``, ``"parameter"`` or ``"local"``.
    type : str
        ``"Real"``, ``"Integer"``, ``"Boolean"`` or ``"String"``.
    unit : str or None
        Unit of a Real (a key of :data:`UNITS`); None for the other types.
    description : str
        What it is, with the unit.
    start : float, int, bool, str or None
        Start value (inputs, parameters, constants); None for calculated outputs.
    relative : bool
        A difference of the quantity (FMI ``relativeQuantity``: display offsets do not apply,
        e.g. a temperature rise in K).
    """

    name: str
    causality: str
    type: str
    unit: str | None
    description: str
    start: Any = None
    relative: bool = False


#: Tire parameters (fields of TireParams): dotted field path -> (unit, description), read from
#: the fields' metadata in tire_brush.params (one source of truth). Boolean fields have unit
#: None.
TIRE_FIELDS: dict[str, tuple[str | None, str]] = field_table()

#: TireParams fields that are text, not parameters.
_TEXT_FIELDS = ("name", "description", "provenance", "source")

#: Model options: name -> (type, unit, description). Start values come from the build.
OPTIONS: dict[str, tuple[str, str | None, str]] = {
    "n_elements": ("Integer", None,
                   "Tread elements on the contact patch at the nominal load (>= 2)"),
    "dt_internal": ("Real", "s", "Longest internal time step [s]; a communication step is "
                                 "split into equal sub-steps no longer than this"),
    "s0": ("Real", "m", "Blending slip length s0 of eq. (28) [m] (cold to hot friction); "
                        "start value from the grid (0.2 D)"),
    "v_floor": ("Real", "m/s", "Speed floor of the reported kappa and alpha [m/s]"),
    "axes": ("Integer", None, "Axis system of vy, Fy, Mz and alpha (docs/axes.md): 0 Pacejka's "
                              "adapted SAE (alpha > 0 gives Fy > 0, Mz < 0), 1 ISO-W (ISO 8855 "
                              "wheel axes, TYDEX W: y left, z up), 2 SAE J670 (y right, z "
                              "down); Fx, kappa and the load keep their sign in all three"),
    "texture_depth": ("Real", "m", "Mean texture depth of the road [m]: the water it holds "
                                   "below the tire, which does not lift the tire "
                                   "(hydroplaning; used with water_depth > 0)"),
    "fidelity": ("Integer", None, "0 the full tire (every tread element through the patch), 1 "
                                  "the real-time fidelity (the steady patch tabulated at build "
                                  "time on the belt's dynamics, docs/realtime.md; needs an FMU "
                                  "built with --fidelity realtime, whose start value it is, and "
                                  "the tire.patch, tire.tread, tire.R_e, "
                                  "tire.carcass.camber_reduction and s0 it was built with)"),
}

#: The axis systems of the ``axes`` option, by value.
AXES_OPTION: tuple[str, ...] = ("adapted-sae", "iso-w", "sae")


def axis_signs(axes: int) -> dict[str, int]:
    """Factors taking ``vy``, ``Fy``, ``Mz``, ``My`` and ``alpha`` from the brush model's own
    convention (Pacejka's adapted SAE) into the FMU's ``axes`` (and back: each is +-1; ``Mx``
    and the camber keep their sign in all of them).

    Raises
    ------
    ValueError
        ``axes`` is not 0, 1 or 2.
    """
    if isinstance(axes, bool) or axes not in range(len(AXES_OPTION)):
        raise ValueError(f"axes = {axes!r} must be 0 (adapted SAE), 1 (ISO-W) or 2 (SAE)")
    to, frm = SIGNS[AXES_OPTION[int(axes)]], SIGNS[BRUSH_AXES]
    return {q: to[q] * frm[q] for q in ("vy", "Fy", "Mz", "My", "alpha")}

#: Input envelope (:mod:`fmu_src.runtime.guard`): name -> (unit, description). Start values
#: come from :func:`default_limits`.
LIMITS: dict[str, tuple[str, str]] = {
    "limit.v": ("m/s", "Largest |vx| and |vy| passed to the model [m/s]; larger inputs are "
                       "clamped (input_status bit 4)"),
    "limit.omega": ("rad/s", "Largest |omega| passed to the model [rad/s]; larger inputs are "
                             "clamped (input_status bit 4)"),
    "limit.Fz": ("N", "Largest load passed to the model [N]; larger inputs are clamped "
                      "(input_status bit 8)"),
    "limit.T_min": ("K", "Lowest T_surface passed to the model [K] (input_status bit 16)"),
    "limit.T_max": ("K", "Highest T_surface passed to the model [K] (input_status bit 16)"),
    "limit.mu_scale": ("1", "Largest mu_scale passed to the model [1] (input_status bit 32)"),
    "limit.gamma": ("rad", "Largest |gamma| passed to the model [rad]; larger inputs are "
                           "clamped (input_status bit 128)"),
    "limit.water_depth": ("m", "Largest water_depth passed to the model [m]; larger and "
                               "negative inputs are clamped (input_status bit 256)"),
}

def _units() -> dict[str, dict[str, int]]:
    """Unit definitions of the FMU's variables: unit -> exponents of the SI base units (FMI
    2.0 ``BaseUnit``), from the one unit table :mod:`tirefric.units`, in order of first use."""
    used = [s.unit for s in (*INPUTS, *OUTPUTS)]
    used += [u for u, _ in TIRE_FIELDS.values() if u is not None]
    used += [u for _, u, _ in OPTIONS.values() if u is not None]
    used += [u for u, _ in LIMITS.values()]
    return {u: base_units(u) for u in dict.fromkeys(used)}


#: Unit definitions: name -> exponents of the SI base units (FMI 2.0 ``BaseUnit``; ``rad``
#: counts as a base unit there). Every unit of a variable is an SI unit of
#: :data:`tirefric.units.SI_UNITS` in its FMI spelling (one vocabulary).
UNITS: dict[str, dict[str, int]] = _units()

#: Constant strings that name what the FMU was built from.
INFO: dict[str, str] = {
    "info.tire": "Name of the tire parameter set the FMU was built with",
    "info.grid_hash": "Content hash of the friction grid inside the FMU",
    "info.build_id": "Hash of all build inputs (the FMU's GUID is derived from it)",
}

#: Dependencies of the initial outputs (InitialUnknowns) on inputs and parameters; outputs not
#: listed are zero before the first step (undeflected tire) and depend on nothing.
INITIAL_DEPENDENCIES: dict[str, tuple[str, ...]] = {
    "kappa": ("vx", "omega", "tire.R_e", "v_floor", "limit.v", "limit.omega"),
    "alpha": ("vx", "vy", "v_floor", "limit.v", "axes"),
    "T_tread": ("T_surface", "limit.T_min", "limit.T_max"),
    "input_status": (*INPUT_NAMES, *LIMITS),
}


def default_limits(tire: TireParams) -> dict[str, float]:
    """Start values of the input envelope [SI]: 150 m/s, 1000 rad/s (rim speed ~ 300 m/s),
    five times the patch law's Fz_max, 200..500 K, mu_scale <= 5 and |gamma| <= 0.5 rad (29
    deg; the model refuses pi/2) and water up to 0.1 m. They keep the model in a range where
    every number stays finite; they are not physical limits of a tire."""
    return {"limit.v": 150.0, "limit.omega": 1000.0, "limit.Fz": 5.0 * tire.patch.Fz_max,
            "limit.T_min": 200.0, "limit.T_max": 500.0, "limit.mu_scale": 5.0,
            "limit.gamma": 0.5, "limit.water_depth": 0.1}


# -- tire parameters as flat FMI parameters ---------------------------------------------------
def tire_field_paths() -> list[str]:
    """Dotted paths of every parameter field of :class:`TireParams`, in declaration order."""
    out = []
    for f in fields(TireParams):
        if f.name in _TEXT_FIELDS:
            continue
        if f.name in GROUPS:
            out += [f"{f.name}.{g.name}" for g in fields(GROUPS[f.name])]
        else:
            out.append(f.name)
    return out


def check_tire_fields() -> list[str]:
    """Problems: tire parameters without an FMU variable, or FMU variables without a field."""
    have = tire_field_paths()
    problems = [f"tire parameter '{p}' has no FMU variable: add it to "
                f"fmu_src.runtime.interface.TIRE_FIELDS" for p in have if p not in TIRE_FIELDS]
    problems += [f"fmu_src.runtime.interface.TIRE_FIELDS names '{p}', which TireParams does "
                 f"not have"
                 for p in TIRE_FIELDS if p not in have]
    return problems


def tire_to_dict(tire: TireParams) -> dict[str, Any]:
    """JSON-able dict of a tire: flat parameters by dotted path plus the text fields."""
    flat: dict[str, Any] = {}
    for path in tire_field_paths():
        obj: Any = tire
        for part in path.split("."):
            obj = getattr(obj, part)
        flat[path] = obj
    return {"name": tire.name, "description": tire.description,
            "provenance": tire.provenance, "parameters": flat}


def tire_from_parameters(name: str, parameters: dict[str, Any], *, description: str = "",
                         provenance: str = "") -> TireParams:
    """Build (and so validate) :class:`TireParams` from flat parameters by dotted path.

    Raises
    ------
    tirefric.errors.InputError
        A parameter is missing or out of range (the message names the field).
    """
    groups: dict[str, dict[str, Any]] = {g: {} for g in GROUPS}
    top: dict[str, Any] = {}
    for path, value in parameters.items():
        head, _, rest = path.partition(".")
        if rest:
            groups[head][rest] = value
        else:
            top[head] = value
    built = {g: cls(**groups[g]) for g, cls in GROUPS.items()}
    return TireParams(name=name, description=description, provenance=provenance, **top,
                      **built)


def realtime_parameters(names: Any) -> list[str]:
    """The parameters among ``names`` that the real-time fidelity's patch table was built from
    (the steady march's: the patch, the tread, the rolling radius and the camber reduction of
    the base's spin, the blend length s0): at ``fidelity`` = 1 they must keep their start
    values. The belt's stiffnesses and damping, the thermal parameters and the options run in
    the fidelity's own dynamics and may change."""
    return [n for n in names if n.startswith(("tire.patch.", "tire.tread.")) or
            n in ("tire.R_e", "tire.carcass.camber_reduction", "s0")]


def variables(tire: dict[str, Any], options: dict[str, Any],
              limits: dict[str, float], info: dict[str, str]) -> list[Variable]:
    """Every variable of the FMU in value-reference order.

    Parameters
    ----------
    tire
        From :func:`tire_to_dict` (start values of the tire parameters).
    options
        Start values of :data:`OPTIONS`.
    limits
        Start values of :data:`LIMITS`.
    info
        Values of :data:`INFO`.
    """
    p = tire["parameters"]
    out = [Variable(s.name, "input", "Real", s.unit, s.description,
                    p["Fz_nom"] if s.start is None else s.start) for s in INPUTS]
    out += [Variable(s.name, "output", "Real", s.unit, s.description,
                     relative=(s.dimension == "temperature_difference")) for s in OUTPUTS]
    bits = ", ".join(f"{b} {k}" for k, b in STATUS_BITS.items())
    out.append(Variable("input_status", "output", "Integer", None,
                        f"Sum of flags of the last step ({bits}); 0 = inputs used as given"))
    for path, (unit, desc) in TIRE_FIELDS.items():
        typ = "Boolean" if unit is None else "Real"
        out.append(Variable(f"tire.{path}", "parameter", typ, unit, desc, p[path]))
    for name, (typ, unit, desc) in OPTIONS.items():
        out.append(Variable(name, "parameter", typ, unit, desc, options[name]))
    for name, (unit, desc) in LIMITS.items():
        out.append(Variable(name, "parameter", "Real", unit, desc, limits[name]))
    for name, desc in INFO.items():
        out.append(Variable(name, "local", "String", None, desc, info[name]))
    return out
