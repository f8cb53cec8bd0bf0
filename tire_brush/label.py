"""The EU tyre label (Regulation (EU) 2020/740, C1 tires) from the physics, before a tire exists.

Two of the label's three graded quantities are computed:

* **wet grip**: the wet grip index G of UN Regulation No. 117 Annex 5 / ISO 23671 against the
  standard reference test tire, by the vehicle method (ABS braking 80 -> 20 km/h on the wet
  reference road; :mod:`tire_brush.braking.wet_grip_test`), and its class
  (:func:`tire_brush.wet_grip.label_class`: A >= 1.55, B 1.40-1.54, C 1.25-1.39,
  D 1.10-1.24, E <= 1.09, G taken to two decimals);
* **fuel efficiency**: the rolling-resistance coefficient at the ISO 28580 conditions (UN R117
  Annex 6; :func:`tire_brush.rolling_resistance.iso28580`) and its class
  (:func:`tire_brush.rolling_resistance.eu_label_class`: A <= 6.5, B 6.6-7.7, C 7.8-9.0,
  D 9.1-10.5, E >= 10.6 N/kN, the RRC taken to one decimal);
* **external rolling noise**: not modelled (class and dB level ``null``).

The document (:func:`tyre_label_document`) is the product interface of ``tirefric label
--json``; its keys are listed in :data:`JSON_KEYS` and documented in docs/label.md. The
label is drawn with the maintained package ``tyre-energy-label`` (PyPI, module
``tyre_label``, MIT; the optional extra ``tirefric[label]``), which renders the 2020/740 label
as SVG from the classes given to it; without it the numbers are computed all the same.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from tirefric.errors import InputError

#: The regulation whose classes are given.
REGULATION = "Regulation (EU) 2020/740, Annex I (C1 tires)"

#: Top-level keys of the document, in order (docs/label.md).
JSON_KEYS: tuple[str, ...] = ("regulation", "tire", "size", "tyre_class", "compound", "grid",
                              "wet_grip", "rolling_resistance", "noise", "notes", "label_svg")


def _grid_compound(grid_name: str, compound_arg: str | None) -> tuple[Any, list[str]]:
    """The tread compound: the one the grid was built from, checked against ``--compound``."""
    from lookup.compound import load_compound
    from lookup.grid import load_grid

    from .rolling_resistance import _same_compound, grid_compound

    grid = load_grid(grid_name)
    from_grid, why = grid_compound(grid)
    if compound_arg is None:
        if from_grid is None:
            raise InputError(f"the grid's tread compound is needed for the rolling resistance "
                             f"({why}); give --compound", field="grid", value=grid_name)
        return from_grid, []
    compound = load_compound(compound_arg)
    if from_grid is not None and not _same_compound(compound.describe(),
                                                    grid.meta["compound"]):
        raise InputError(f"the compound differs from the one the grid {grid_name!r} was built "
                         f"with ({grid.meta.get('compound_name')!r}): build a grid of this "
                         "compound on the reference road (copy models/grids/r117_wet.toml, "
                         "set its compound, `tirefric grid build`) and pass it with --grid",
                         field="compound", value=compound_arg)
    return compound, ([] if from_grid is not None else
                      [f"the grid records no usable compound ({why}); the rolling resistance "
                       f"uses {compound.name!r}"])


def tyre_label_document(tire: str = "passenger", grid: str | None = None,
                        compound: str | None = None, spec: str = "wet_grip",
                        T_C: float | None = None) -> dict[str, Any]:
    """The label's numbers for ``tire`` (module docstring).

    Parameters
    ----------
    tire : str
        Tire TOML file or shipped name (with a ``[rolling_resistance]`` table).
    grid : str, optional
        Friction grid with a wet branch on the regulation's reference road (default: the wet
        grip spec's, ``r117_wet``); its compound is the tread compound.
    compound : str, optional
        Tread compound; must be the grid's (checked), or stands in when the grid records none.
    spec : str
        The wet grip test spec (``models/studies/wet_grip.toml``).
    T_C : float, optional
        Wetted-surface temperature of the wet grip test [C] (default: the spec's, 20 C).

    Returns
    -------
    dict
        JSON-able; keys :data:`JSON_KEYS` (``label_svg`` is filled by :func:`draw_label`).
    """
    import dataclasses

    from .braking.wet_grip_test import load_wet_grip_spec, run_wet_grip
    from .params import load_tire
    from .rolling_resistance import iso28580, load_rolling_params
    from .wet_grip import label_class

    wspec = load_wet_grip_spec(spec)
    if grid is not None:
        wspec = dataclasses.replace(wspec, grid=str(grid))
    tread, notes = _grid_compound(wspec.grid, compound)
    params = load_tire(tire)
    rr = load_rolling_params(params)
    doc, _ = run_wet_grip(wspec, tire, T_C)
    iso = iso28580(params, tread, rr=rr)
    G = float(doc["G"])
    wet = {
        "G": G, "class": label_class(G),
        "method": "vehicle (ABS braking 80 -> 20 km/h), UN R117 Annex 5 / ISO 23671",
        "G_trailer": float(doc["G_trailer"]),
        "class_trailer": label_class(float(doc["G_trailer"])),
        "bfc_candidate": float(doc["candidate"]["bfc_wet"]),
        "bfc_reference": float(doc["reference"]["bfc_wet"]),
        "reference_tire": doc["reference_tire"],
        "reference_in_windows": doc["reference_in_windows"],
        "T_C": float(doc["T_C"]), "water_depth_m": float(doc["water_depth_m"]),
    }
    rrc = {
        "rrc_N_per_kN": float(iso.rrc_N_per_kN), "class": iso.label_class,
        "method": "ISO 28580 / UN R117 Annex 6 conditions at thermal equilibrium (the tread's "
                  "temperature from its losses and cooling), flat road (no drum correction)",
        "load_N": float(iso.load_N), "inflation_Pa": float(iso.inflation_Pa),
        "speed_m_per_s": float(iso.speed_m_s), "T_C": float(iso.T_K - 273.15),
        "per_K": float(iso.per_K), "per_K_isothermal": float(iso.per_K_isothermal),
        "T_tire_C": float(iso.T_tire_K - 273.15), "tread_share": float(iso.tread_share),
    }
    for k in ("rrc_N_per_kN", "per_K", "per_K_isothermal", "T_tire_C"):
        if not math.isfinite(rrc[k]):
            raise InputError("the rolling-resistance model gave a non-finite number",
                             field=k, value=rrc[k])
    return {"regulation": REGULATION, "tire": params.name, "size": rr.size,
            "tyre_class": "C1", "compound": tread.name, "grid": wspec.grid,
            "wet_grip": wet, "rolling_resistance": rrc,
            "noise": {"class": None, "level_dB": None, "modelled": False},
            "notes": notes + list(doc["notes"]), "label_svg": None}


def label_classes(doc: dict[str, Any]) -> dict[str, Any]:
    """The arguments of ``tyre_label.TyreEnergyLabel`` for a document: the classes, the size,
    the tyre class; the noise level left blank and its dB value shown as ``--`` (not
    modelled)."""
    return {"supplier": "tirefric (computed)", "type_identifier": str(doc["tire"]),
            "size": str(doc["size"] or doc["tire"]), "tyre_class": doc["tyre_class"],
            "fuel_efficiency": doc["rolling_resistance"]["class"],
            "wet_grip": doc["wet_grip"]["class"], "roll_noise": "--", "noise_level": "",
            "snow_grip": False, "ice_grip": False}


def draw_label(doc: dict[str, Any], path: str | Path) -> str | None:
    """Write the label as SVG with ``tyre-energy-label`` (module docstring); the path written,
    or None when the package is not installed (``pip install "tirefric[label]"``)."""
    try:
        from tyre_label import TyreEnergyLabel
    except ImportError:
        return None
    svg = TyreEnergyLabel(**label_classes(doc)).as_svg(embed_fonts=True, include_link=False)
    path = Path(path)
    path.write_text(svg, encoding="utf-8")
    return str(path)
