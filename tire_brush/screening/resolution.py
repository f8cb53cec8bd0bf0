"""How far the screening resolution moves the reported numbers (docs/screening.md).

:func:`compare` evaluates compounds twice with the same code (:func:`.evaluate.
evaluate_compound`): at the screening resolution and at the full one: the shipped grid
specs' speed and pressure axes (``default``: 61 speeds, 15 pressures; ``r117_wet``: 61 and 8)
and the braking study's and wet grip test's own force-map temperatures and quarter-car step
(:func:`full_settings`), both grids with the temperature nodes their outputs read. For the
shipped summer tread :func:`compare_shipped` also evaluates on the shipped grid files
themselves, which is what ``tirefric label`` and ``tirefric abs study`` read (their
temperature axes: every 1.75 K from -20 C on ``default``, so 20 C lies between nodes there;
every 2 K on ``r117_wet``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from .evaluate import Settings, evaluate_compound, evaluate_on_grids

#: Outputs whose relative difference is reported (the wet grip index is formed from
#: ``bfc_wet`` and the reference tire's BFC, which move together; RRC needs no grid).
COMPARED: tuple[str, ...] = ("bfc_wet", "peak_wet_trailer", "stop_dry_abs_m",
                             "stop_dry_locked_m", "stop_wet_abs_m", "stop_wet_locked_m")


def full_settings(settings: Settings) -> Settings:
    """The settings with the shipped grid specs' full speed and pressure axes and the
    braking study's and the wet grip test's own force-map temperatures and step
    (``stop_T_step = stop_dt = 0``)."""
    from lookup.grid.spec import load_spec

    dry = load_spec(settings.dry_spec.source)
    wet = load_spec(settings.wet_spec.source)
    return dataclasses.replace(settings, dry_spec=dry, wet_spec=wet, stop_T_step=0.0,
                               stop_dt=0.0)


def _task(shared: dict[str, Settings], which: str, desc: dict[str, Any]) -> tuple[str, str,
                                                                                   dict]:
    return which, desc["name"], evaluate_compound(shared[which], desc, which)


def relative_differences(a: dict[str, float], b: dict[str, float]) -> dict[str, float]:
    """(a - b) / b per output of :data:`COMPARED` and the peak friction."""
    keys = [k for k in a if k in COMPARED or k.startswith("mu_peak_")]
    return {k: (a[k] - b[k]) / b[k] if b.get(k) else math.nan for k in keys}


def compare(settings: Settings, descs: list[dict[str, Any]], workers: int = 1
            ) -> dict[str, dict[str, Any]]:
    """Screening against full resolution for each compound description.

    Returns ``{name: {"screen": outputs, "full": outputs, "rel": relative differences,
    "seconds": {"screen": s, "full": s}}}``.
    """
    from lookup.grid.build import run_tasks

    shared = {"screen": settings, "full": full_settings(settings)}
    tasks = [(w, d) for d in descs for w in ("full", "screen")]
    out: dict[str, dict[str, Any]] = {d["name"]: {"seconds": {}} for d in descs}
    for which, name, rec in run_tasks(_task, shared, tasks, workers=workers):
        if rec["status"] != "ok":
            raise RuntimeError(f"{name} ({which}): {rec['error']}")
        out[name][which] = rec["outputs"]
        out[name]["seconds"][which] = rec["seconds"]["total_s"]
    for v in out.values():
        v["rel"] = relative_differences(v["screen"], v["full"])
    return out


def compare_shipped(settings: Settings, compound_file: str, dry_grid: str, wet_grid: str
                    ) -> dict[str, dict[str, float]]:
    """The summer tread on the shipped grid files (what the single-compound commands read)
    against the screening resolution."""
    full = dataclasses.replace(settings, stop_T_step=0.0, stop_dt=0.0)
    shipped = evaluate_on_grids(full, compound_file, dry_grid, wet_grid, "shipped")
    screen = evaluate_compound(settings, {"name": "summer", "file": compound_file}, "s")
    return {"screen": screen["outputs"], "shipped": shipped["outputs"],
            "rel": relative_differences(screen["outputs"], shipped["outputs"])}
