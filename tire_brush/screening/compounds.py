"""Compounds of a screening: files as they are, or designed variants of a base compound.

A *compound description* is a small JSON-able dict, all a worker needs to rebuild the
compound (no arrays are shipped):

* ``{"name": ..., "file": "/abs/path.toml"}``: a compound file, read as
  :func:`lookup.compound.load_compound` reads it;
* ``{"name": ..., "base": "/abs/path.toml", "params": {parameter: value}}``: the base
  compound with the design parameters of :data:`PARAMETERS` applied to its TOML table
  (:func:`variant_table`), then read by the same loader, so that every check of a compound
  file holds for the variant too.

Design parameters (:data:`PARAMETERS`; each a change of the base's own numbers):

``T_g_shift`` [K]
    Moves the compound's glass transition by ``dT``: the variant at temperature ``T``
    behaves as the base at ``T - dT`` (time-temperature superposition, Ferry, *Viscoelastic
    Properties of Polymers*, 3rd ed., ch. 11). With the base's WLF law (review eq. 5) at
    ``T_ref`` with constants ``C1, C2``, the base's law about ``T_ref + dT`` written at
    ``T_ref`` (Ferry's change of reference, as in models/compounds/summer.toml) is
    ``C2' = C2 - dT``, ``C1' = C1 C2 / (C2 - dT)``; the master curve at ``T_ref`` is the
    base's at ``T_ref - dT``, i.e. every relaxation time (the spectrum's centres, or the
    Prony times) is multiplied by ``a_T(T_ref - dT) = 10^(C1 dT / (C2 - dT))``; an eq. (21)
    adhesion shifted with the bulk a_T moves with it (``v* / a_T(T_ref - dT)``), one with its
    own Arrhenius shift (eq. 22) is left alone. Needs a WLF shift.
``breadth_scale`` [1]
    Multiplies the width (decades) of the glass-transition component of a log-normal
    spectrum (:class:`lookup.modulus.LogNormalSpectrum`; the component named ``alpha``, else
    the first; ``width_decades`` of a one-component ``Prony.lognormal``): a broader or
    narrower transition with the same strength and centre.
``E_inf_scale`` [1]
    Multiplies the rubbery (equilibrium) modulus ``E_inf`` of a log-normal spectrum.
``softening_strain`` [1]
    The strain at which the softening law is applied (``[softening] strain``, review eq. 6):
    more strain, more filler softening.
``sigma_f0_scale`` [1]
    Multiplies the adhesive shear stress ``sigma_f0`` of review eq. (21).
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tirefric.errors import InputError
from tirefric.units import parse_quantity


@dataclass(frozen=True)
class Parameter:
    """A design parameter: its unit dimension (tirefric.units) and what it changes."""

    name: str
    dimension: str
    neutral: float
    doc: str


#: The design parameters a sweep may vary (module docstring).
PARAMETERS: dict[str, Parameter] = {p.name: p for p in (
    Parameter("T_g_shift", "temperature_difference", 0.0,
              "glass temperature shift [K] (spectrum centres and WLF together)"),
    Parameter("breadth_scale", "dimensionless", 1.0,
              "width of the glass-transition component [x base]"),
    Parameter("E_inf_scale", "dimensionless", 1.0, "rubbery modulus E_inf [x base]"),
    Parameter("softening_strain", "dimensionless", math.nan,
              "strain of the softening law [1]"),
    Parameter("sigma_f0_scale", "dimensionless", 1.0, "adhesive shear stress sigma_f0 "
                                                       "[x base]"),
)}

#: Keys of a compound TOML that name a file relative to the compound's folder.
_FILE_KEYS = ("file",)


def _absolute_files(d: Any, folder: Path) -> Any:
    """A copy of a TOML table with every ``file`` entry made absolute (relative to
    ``folder``), so that the table can be written anywhere and read back."""
    if isinstance(d, dict):
        out = {}
        for k, v in d.items():
            if k in _FILE_KEYS and isinstance(v, str) and not Path(v).is_absolute():
                out[k] = str((folder / v).resolve())
            else:
                out[k] = _absolute_files(v, folder)
        return out
    if isinstance(d, list):
        return [_absolute_files(v, folder) for v in d]
    return d


def _si(value: Any, dimension: str, where: str, source: str) -> float:
    """A TOML quantity (number or ``"<number> <unit>"``) in SI."""

    def err(msg: str) -> InputError:
        return InputError(msg, source=source, field=where, value=value)

    return float(parse_quantity(value, dimension, err))


def _need(table: dict, key: str, source: str, why: str) -> Any:
    if key not in table:
        raise InputError(f"the base compound has no '{key}': {why}", source=source,
                         field=key)
    return table[key]


def variant_table(base: dict[str, Any], params: dict[str, float], source: str
                  ) -> dict[str, Any]:
    """The TOML table of the base compound with the design parameters applied.

    Parameters
    ----------
    base : dict
        The base compound's TOML table (file references absolute).
    params : dict
        Design parameter -> value (:data:`PARAMETERS`).
    source : str
        The base file (for error messages).

    Raises
    ------
    InputError
        An unknown parameter, or one the base compound's models cannot take (a ``T_g_shift``
        without a WLF shift, a ``breadth_scale`` without a log-normal spectrum, ...), naming
        the base file, the field and the value.
    """
    d = copy.deepcopy(base)
    for name, value in params.items():
        if name not in PARAMETERS:
            raise InputError(f"unknown design parameter (known: {', '.join(PARAMETERS)})",
                             source=source, field=f"sweep.parameters.{name}", value=name)
        if not math.isfinite(value):
            raise InputError("must be finite", source=source, field=name, value=value)
    mod = _need(d, "modulus", source, "the design parameters change the master curve")
    if "T_g_shift" in params and params["T_g_shift"] != 0.0:
        dT = float(params["T_g_shift"])
        sh = _need(d, "shift", source, "T_g_shift moves the WLF law")
        if sh.get("model") != "wlf":
            raise InputError("T_g_shift needs a WLF shift (review eq. 5)", source=source,
                             field="shift.model", value=sh.get("model"))
        C1 = _si(sh["C1"], "dimensionless", "shift.C1", source)
        C2 = _si(sh["C2"], "temperature_difference", "shift.C2", source)
        T_ref_shift = _si(sh["T_ref"], "temperature", "shift.T_ref", source)
        T_ref = _si(mod.get("T_ref", sh["T_ref"]), "temperature", "modulus.T_ref", source)
        if not dT < 0.9 * C2:
            raise InputError(f"a glass-temperature shift of {dT:g} K leaves no WLF law "
                             f"(C2 = {C2:g} K)", source=source, field="T_g_shift", value=dT)
        # the base law read about T_ref_shift + dT, re-referenced (Ferry ch. 11)
        sh["C1"] = C1 * C2 / (C2 - dT)
        sh["C2"] = C2 - dT
        # master curve at T_ref = the base's at T_ref - dT: times x a_T(T_ref - dT)
        x = T_ref - dT - T_ref_shift
        x0 = T_ref - T_ref_shift
        log_a = -C1 * x / (C2 + x) + C1 * x0 / (C2 + x0)
        factor = 10.0 ** log_a
        if "component" in mod:
            for c in mod["component"]:
                c["tau_center"] = _si(c["tau_center"], "time", "modulus.component.tau_center",
                                      source) * factor
        elif "tau_center" in mod:
            mod["tau_center"] = _si(mod["tau_center"], "time", "modulus.tau_center",
                                    source) * factor
        elif "tau_k" in mod:
            mod["tau_k"] = [_si(t, "time", "modulus.tau_k", source) * factor
                            for t in mod["tau_k"]]
        elif "tau" in mod:
            mod["tau"] = _si(mod["tau"], "time", "modulus.tau", source) * factor
        else:
            raise InputError("T_g_shift needs relaxation times in the master curve (a "
                             "log-normal spectrum, Prony times or a single relaxation)",
                             source=source, field="modulus.model", value=mod.get("model"))
        ad = d.get("adhesion", {})
        if ad.get("model", "none") == "eq21" and ad.get("shift") == "bulk":
            ad["v_star"] = _si(ad["v_star"], "velocity", "adhesion.v_star", source) / factor
    if "breadth_scale" in params:
        k = float(params["breadth_scale"])
        if not k > 0:
            raise InputError("must be > 0", source=source, field="breadth_scale", value=k)
        if "component" in mod:
            comps = mod["component"]
            i = next((j for j, c in enumerate(comps) if c.get("name") == "alpha"), 0)
            comps[i]["width_decades"] = float(comps[i]["width_decades"]) * k
        elif mod.get("spectrum") == "lognormal":
            mod["width_decades"] = float(mod["width_decades"]) * k
        else:
            raise InputError("breadth_scale needs a log-normal spectrum", source=source,
                             field="modulus.spectrum", value=mod.get("spectrum"))
    if "E_inf_scale" in params:
        k = float(params["E_inf_scale"])
        if not k > 0:
            raise InputError("must be > 0", source=source, field="E_inf_scale", value=k)
        mod["E_inf"] = _si(_need(mod, "E_inf", source, "E_inf_scale scales it"), "pressure",
                           "modulus.E_inf", source) * k
    if "softening_strain" in params:
        s = float(params["softening_strain"])
        if not s > 0:
            raise InputError("must be > 0", source=source, field="softening_strain", value=s)
        _need(d, "softening", source, "softening_strain sets its strain")["strain"] = s
    if "sigma_f0_scale" in params:
        k = float(params["sigma_f0_scale"])
        if not k >= 0:
            raise InputError("must be >= 0", source=source, field="sigma_f0_scale", value=k)
        ad = _need(d, "adhesion", source, "sigma_f0_scale scales eq. (21)'s sigma_f0")
        if ad.get("model") != "eq21":
            raise InputError("sigma_f0_scale needs the eq. (21) adhesion", source=source,
                             field="adhesion.model", value=ad.get("model"))
        ad["sigma_f0"] = _si(ad["sigma_f0"], "pressure", "adhesion.sigma_f0", source) * k
    return d


def read_table(path: str | Path) -> dict[str, Any]:
    """A compound TOML as a dict with its file references made absolute."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise InputError("file not found", source=str(path)) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", source=str(path)) from None
    return _absolute_files(data, path.parent)


def compound_table(desc: dict[str, Any]) -> dict[str, Any]:
    """The TOML table of a compound description (module docstring), named ``desc['name']``."""
    if "file" in desc:
        d = read_table(desc["file"])
    else:
        d = variant_table(read_table(desc["base"]), dict(desc.get("params", {})),
                          str(desc["base"]))
        prov = d.get("provenance", "")
        d["description"] = (f"designed variant of {Path(desc['base']).stem} "
                            f"({json.dumps(desc.get('params', {}), sort_keys=True)})")
        d["provenance"] = (f"tirefric screen: {Path(desc['base']).name} with the design "
                           f"parameters {json.dumps(desc.get('params', {}), sort_keys=True)} "
                           "applied (tire_brush.screening.compounds). Base provenance: "
                           + prov)
    d["name"] = desc["name"]
    return d


def write_compound(desc: dict[str, Any], path: str | Path) -> Path:
    """Write the compound of a description as a TOML file (readable by ``load_compound``)."""
    from tirefric.toml_writer import dumps

    path = Path(path)
    path.write_text(dumps(compound_table(desc), header=f"compound {desc['name']} of a "
                          "tirefric screen (tire_brush.screening.compounds)"),
                    encoding="utf-8")
    return path


def file_digest(path: str | Path) -> str:
    """SHA-256 of a file's bytes, or ``"missing"`` (a missing file is reported by the
    evaluation, not here)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return "missing"


def referenced_files(desc: dict[str, Any]) -> list[str]:
    """The files a compound description reads: its TOML and the tables that names."""
    main = desc.get("file") or desc.get("base")
    files = [str(main)]
    try:
        table = read_table(main)
    except InputError:
        return files

    def walk(d: Any) -> None:
        if isinstance(d, dict):
            for k, v in d.items():
                if k in _FILE_KEYS and isinstance(v, str):
                    files.append(v)
                else:
                    walk(v)
        elif isinstance(d, list):
            for v in d:
                walk(v)

    walk(table)
    return files
