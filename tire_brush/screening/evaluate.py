"""One compound of a screening, evaluated as a pure function of its description and the
screening's settings (the same numbers wherever and alongside whatever it runs).

For a compound (:mod:`.compounds`) :func:`evaluate_compound`:

1. writes the compound file and reads it with :func:`lookup.compound.load_compound` (every
   check of a compound file applies: a missing table, a T_ref that is not where the shift
   factor is 1, ...);
2. builds its two friction grids at the screening resolution (:class:`Settings`,
   :mod:`lookup.grid.build`, serially, in a scratch folder of its own): the dry road's
   (dry stop, peak friction) and the wet reference road's with its wet branch (wet grip,
   wet stop). The temperature axes hold exactly the temperatures the outputs read (the
   force maps' nodes and the peak temperatures), so the temperature axis adds no
   interpolation error; the slip-speed and pressure axes are coarser than the shipped
   grids' (docs/screening.md gives the tolerance this costs, measured);
3. computes the rolling-resistance coefficient at the ISO 28580 conditions
   (:func:`tire_brush.rolling_resistance.iso28580`, no grid);
4. runs the wet grip test's candidate part (UN R117 Annex 5 vehicle method BFC and trailer
   peak, :func:`tire_brush.braking.wet_grip_test.tire_result`); the wet grip index is formed
   later against the reference tire (:func:`evaluate_reference`);
5. brakes the quarter car of the braking study from ``v0`` to ``v_stop`` on the force maps of
   the dry and the wet road with the rule-based ABS and a locked wheel (the steps of
   :func:`tire_brush.braking.study.run_case` without the OCP), at the screening's braking
   resolution (:func:`screen_study`: fewer force-map temperatures, a longer largest step;
   the maps read one point at a time by the compiled tire core,
   :meth:`~tire_brush.braking.force_map.ForceMap.point_evaluator`);
6. the peak braking |Fx/Fz| of the steady brush on the dry road at the peak temperatures
   (:func:`tire_brush.wet_friction.peak_fx_over_fz`).

A failure anywhere is caught and returned as ``{"status": "failed", "error": ...}``: one bad
compound does not end a screen.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

#: Output columns of one compound (units in the names), in the results' order.
OUTPUTS: tuple[str, ...] = (
    "rrc_N_per_kN", "bfc_wet", "peak_wet_trailer", "stop_dry_abs_m", "stop_dry_locked_m",
    "stop_wet_abs_m", "stop_wet_locked_m",
)


@dataclass(frozen=True)
class Settings:
    """What every compound of a screening shares (sent to each worker once).

    Attributes
    ----------
    tire : str
        Tire file (resolved path) of the candidate.
    dry_spec, wet_spec : GridSpec
        Templates of the two grids at the screening resolution (their compound is replaced by
        each candidate's); ``wet_spec`` has a ``[wet]`` branch.
    wet_grip_spec : str
        The wet grip test spec (resolved path), its ``grid`` replaced by the candidate's.
    study : str
        The braking study spec (resolved path) whose car, ABS, map and simulation settings the
        dry and wet stops use (``abs_default``).
    v0, v_stop : float
        Speeds of the stops [m/s].
    T_K : float
        Temperature of the stops [K].
    peak_T_K : tuple of float
        Temperatures of the peak friction [K].
    peak_speed : float
        Vehicle speed of the peak friction [m/s].
    keep : str or None
        Folder to keep each compound's grids and file in (None: a temporary folder, removed).
    version : str
        The package version (enters the cache key).
    stop_T_step : float
        Spacing [K] of the dry stop's force-map temperature nodes, from the case temperature
        up to the tread's heating bound (:func:`screen_study`); 0: the study's own nodes.
    stop_dt : float
        Largest step [s] of the quarter car in the stops and the wet grip test; 0: the
        study's and the test's own.
    """

    tire: str
    dry_spec: Any
    wet_spec: Any
    wet_grip_spec: str
    study: str
    v0: float
    v_stop: float
    T_K: float
    peak_T_K: tuple[float, ...]
    peak_speed: float
    keep: str | None = None
    version: str = field(default="")
    stop_T_step: float = 0.0
    stop_dt: float = 0.0

    def describe(self) -> dict[str, Any]:
        """JSON-able form (the results' provenance and the cache key)."""
        return {"tire": self.tire, "dry_grid": self.dry_spec.to_dict(),
                "wet_grid": self.wet_spec.to_dict(), "wet_grip_spec": self.wet_grip_spec,
                "study": self.study, "v0_m_s": self.v0, "v_stop_m_s": self.v_stop,
                "T_K": self.T_K, "peak_T_K": list(self.peak_T_K),
                "peak_speed_m_s": self.peak_speed, "version": self.version,
                "stop_T_step_K": self.stop_T_step, "stop_dt_s": self.stop_dt}


def _study(settings: Settings, grid: str, thermal: bool):
    """The braking study spec with the brush on ``grid`` at load 1 (the stops' load), at the
    screening's braking resolution (:func:`screen_study`)."""
    from tire_brush.braking.study import load_study

    st = load_study(settings.study)
    car = st.car if thermal else dataclasses.replace(st.car, thermal=None)
    return screen_study(dataclasses.replace(
        st, v0=settings.v0, v_stop=settings.v_stop, car=car,
        friction={"source": "brush", "tire": settings.tire, "grid": grid},
        maps=dataclasses.replace(st.maps, loads_rel=(1.0,))), settings)


def screen_study(study, settings: Settings):
    """The study at the screening's braking resolution.

    ``settings.stop_T_step`` > 0: the force map's temperature nodes are the case temperature
    and every ``stop_T_step`` above it until the tread's heating bound is covered
    (:func:`tire_brush.braking.study.case_temperatures` with offsets ``(0, stop_T_step)``).
    The study's node 4 K below the case temperature is for its OCP, whose slip maps compare
    a cold and a warm tread; in a stop the tread starts at the case temperature and only
    heats (the quarter car's tread-temperature state: friction heating in, cooling towards
    the ambient, :mod:`tire_brush.braking.quarter_car`), so no stop reads below it.
    ``settings.stop_dt`` > 0: the quarter car's largest step (the step control keeps the
    local error of the speeds below the study's tolerance and shortens steps where the wheel
    needs it, :mod:`tire_brush.braking.simulation`). docs/screening.md gives what both
    cost in the stopping distances, measured.
    """
    maps, sim = study.maps, study.simulation
    if settings.stop_T_step > 0.0:
        maps = dataclasses.replace(maps, temperatures_rel=(0.0, settings.stop_T_step),
                                   temperature_step=settings.stop_T_step)
    if settings.stop_dt > 0.0:
        sim = dataclasses.replace(sim, dt=settings.stop_dt)
    return dataclasses.replace(study, maps=maps, simulation=sim)


def screen_wet_grip_spec(settings: Settings, grid: str):
    """The wet grip test spec on ``grid``, with the quarter car's largest step
    ``settings.stop_dt`` (> 0; :func:`screen_study`)."""
    from tire_brush.braking.wet_grip_test import load_wet_grip_spec

    spec = dataclasses.replace(load_wet_grip_spec(settings.wet_grip_spec), grid=str(grid))
    if settings.stop_dt > 0.0:
        spec = dataclasses.replace(spec, simulation=dataclasses.replace(
            spec.simulation, dt=settings.stop_dt))
    return spec


def dry_temperatures(settings: Settings) -> np.ndarray:
    """Temperatures [K] the dry outputs read: the dry stop's force-map nodes (the case
    temperature, the study's offsets and the nodes up to the tread's heating bound,
    :func:`tire_brush.braking.study.case_temperatures`) and the peak temperatures."""
    from tire_brush.braking.friction import Case
    from tire_brush.braking.study import case_temperatures

    st = _study(settings, "", thermal=True)
    T = case_temperatures(st, Case("", "", settings.T_K))
    return np.unique(np.round(np.concatenate([T, settings.peak_T_K]), 9))


def wet_temperatures(settings: Settings) -> np.ndarray:
    """Temperatures [K] the wet outputs read: the wet grip test's and the wet stop's (one
    force-map node each: no tread heating on a wet road, the water holds the tread at the
    wetted-surface temperature, models/studies/wet_grip.toml)."""
    from tire_brush.braking.wet_grip_test import load_wet_grip_spec

    wg = load_wet_grip_spec(settings.wet_grip_spec)
    T = np.unique(np.round([settings.T_K, wg.T_K], 9))
    # an axis needs two nodes: a second one that nothing reads (the tables there are
    # computed but not interpolated towards: every read is at a node)
    return T if T.size > 1 else np.array([T[0], T[0] + 2.0])


def stops(study, source, case, compound, params, f_r: float | None = None
          ) -> dict[str, float]:
    """ABS and locked-wheel stops of the study's quarter car on the force map of ``source``
    (the steps of :func:`tire_brush.braking.study.run_case` without the OCP).

    Parameters
    ----------
    study : StudySpec
    source : callable
        ``fx_over_fz(kappa, vx, Fz, T_K)``.
    case : Case
    compound : Compound
        The tread compound (the wheel's rolling-resistance moment, f_r at half the initial
        speed and the case temperature as in ``run_case``).
    params : TireParams
    f_r : float, optional
        The wheel's rolling-resistance coefficient if the caller has it (the same number:
        the dry and the wet stop share the car, the speed and the case temperature).
    """
    from tire_brush.braking.abs_control import LockedWheel, RuleBasedABS
    from tire_brush.braking.force_map import ForceMap, default_axes
    from tire_brush.braking.simulation import simulate_braking
    from tire_brush.braking.slip_map import optimal_slip
    from tire_brush.braking.study import abs_slip_schedule, case_temperatures
    from tire_brush.rolling_resistance import rolling_resistance

    ax = default_axes(study.v0, study.v_stop, study.car.Fz, case.T_K,
                      n_kappa=study.maps.n_kappa, n_v=study.maps.n_v)
    ax["Fz"] = study.car.Fz * np.asarray(study.maps.loads_rel)
    # without the tread's thermal state the stop reads the map at the case temperature only
    ax["T_K"] = (case_temperatures(study, case, True) if study.car.thermal is not None
                 else np.array([case.T_K]))
    fmap = ForceMap.build(source, **ax, label=case.label)
    if f_r is None:
        f_r = float(rolling_resistance(params, compound, 0.5 * study.v0, study.car.Fz,
                                       case.T_K).f_r)
    car = dataclasses.replace(study.car, rolling_resistance=f_r)
    v_line = np.geomspace(study.v_stop, study.v0, 25)
    sm_line = optimal_slip(fmap, v_line, [car.Fz], [case.T_K], label=case.label)
    schedule = abs_slip_schedule(sm_line) if study.abs_slip_from_map else None
    point = fmap.point_evaluator()      # the map's spline, one point per call, in C
    locked = simulate_braking(car, point, LockedWheel(car.brake_torque_rate_max,
                                                     study.abs_params.control_period),
                              study.v0, study.v_stop, case.T_K, settings=study.simulation,
                              brake_torque_initial=study.brake_torque_initial)
    abs_sim = simulate_braking(car, point, RuleBasedABS(study.abs_params, car.radius,
                                                       car.brake_torque_rate_max,
                                                       slip_schedule=schedule),
                               study.v0, study.v_stop, case.T_K, settings=study.simulation,
                               brake_torque_initial=study.brake_torque_initial)
    return {"abs": float(abs_sim.stopping_distance),
            "locked": float(locked.stopping_distance), "f_r": f_r,
            "mu_max": float(sm_line.mu_max.ravel()[-1])}


def evaluate_on_grids(settings: Settings, compound_file: str | Path, dry_grid: str | Path,
                      wet_grid: str | Path, name: str) -> dict[str, Any]:
    """The outputs of one compound from its file and its two grid files (steps 3-6 of the
    module docstring); also what a check against the single-compound commands calls."""
    from lookup.compound import load_compound
    from lookup.grid import load_grid
    from lookup.grid.wet import load_wet
    from tire_brush.braking.friction import Case
    from tire_brush.braking.wet_grip_test import (
        friction_source,
        tire_result,
    )
    from tire_brush.params import load_tire
    from tire_brush.rolling_resistance import iso28580, load_rolling_params
    from tire_brush.steady import SteadyBrush
    from tire_brush.wet_friction import peak_fx_over_fz

    t = {}
    t0 = time.perf_counter()
    compound = load_compound(compound_file)
    params = load_tire(settings.tire)
    iso = iso28580(params, compound, rr=load_rolling_params(params))
    t["rolling_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    wspec = screen_wet_grip_spec(settings, str(wet_grid))
    grids = (load_grid(str(wet_grid)), load_wet(str(wet_grid)))
    cand, _ = tire_result(wspec, settings.tire, wspec.T_K, wspec.water_depth, grids,
                          with_dry=False, point_evaluation=True)
    t["wet_grip_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    dry_g = load_grid(str(dry_grid))
    road = str(dry_g.meta.get("surface_name", ""))
    st_dry = _study(settings, str(dry_grid), thermal=True)
    brush = SteadyBrush(params, dry_g)
    dry = stops(st_dry, brush.fx_over_fz, Case(road, name, settings.T_K), compound, params)
    st_wet = _study(settings, str(wet_grid), thermal=False)
    wsrc = friction_source(wspec, settings.tire, wspec.water_depth, grids)
    # the wheel's f_r is the dry stop's: the same load, speed and case temperature
    same = (st_wet.car.Fz, st_wet.v0) == (st_dry.car.Fz, st_dry.v0)
    wet = stops(st_wet, wsrc, Case("wet", name, settings.T_K), compound, params,
                f_r=dry["f_r"] if same else None)
    t["stops_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    peaks = {}
    for T in settings.peak_T_K:
        mu, _ = peak_fx_over_fz(brush.fx_over_fz, settings.peak_speed, st_dry.car.Fz, T)
        peaks[f"mu_peak_{T - 273.15:g}C"] = float(mu)
    t["peaks_s"] = time.perf_counter() - t0
    out = {
        "rrc_N_per_kN": float(iso.rrc_N_per_kN), "rr_class": iso.label_class,
        "bfc_wet": float(cand["bfc_wet"]), "peak_wet_trailer": float(cand["peak_wet"]),
        "stop_dry_abs_m": dry["abs"], "stop_dry_locked_m": dry["locked"],
        "stop_wet_abs_m": wet["abs"], "stop_wet_locked_m": wet["locked"],
        **peaks,
        "f_r_dry": dry["f_r"], "mu_max_dry_v0": dry["mu_max"], "mu_max_wet_v0": wet["mu_max"],
    }
    return {"outputs": out, "seconds": t}


def _grid_spec(template, compound_file: str, name: str, T: np.ndarray):
    return dataclasses.replace(template.with_axes(T=T), name=name, compound=str(compound_file),
                               source=f"tirefric screen ({template.source})")


def build_grids(settings: Settings, compound_file: str | Path, folder: Path, name: str
                ) -> tuple[Path, Path, dict[str, float]]:
    """The compound's dry and wet grids at the screening resolution, built serially
    (:func:`lookup.grid.build.build_grid`) into ``folder``."""
    from lookup.grid.build import build_grid

    t = {}
    out = []
    for kind, template, T in (("dry", settings.dry_spec, dry_temperatures(settings)),
                              ("wet", settings.wet_spec, wet_temperatures(settings))):
        t0 = time.perf_counter()
        path = folder / f"{kind}.nc"
        build_grid(_grid_spec(template, str(compound_file), f"{name}_{kind}", T), path,
                   workers=1, progress=False, resume=False)
        t[f"grid_{kind}_s"] = time.perf_counter() - t0
        out.append(path)
    return out[0], out[1], t


def evaluate_compound(settings: Settings, desc: dict[str, Any], key: str) -> dict[str, Any]:
    """Evaluate one compound (module docstring); a JSON-able record, never raises.

    Parameters
    ----------
    settings : Settings
    desc : dict
        Compound description (:mod:`.compounds`).
    key : str
        Its cache key (:func:`tire_brush.screening.store.compound_key`), carried along.
    """
    from .compounds import compound_table, write_compound

    t_start = time.perf_counter()
    t_epoch = time.time()
    cpu0 = time.process_time()
    record: dict[str, Any] = {"name": desc["name"], "key": key, "description": desc,
                              "status": "ok", "error": None}
    folder = Path(tempfile.mkdtemp(prefix="tirefric-screen-")) if settings.keep is None \
        else Path(settings.keep) / f"{desc['name']}-{key[:12]}"
    folder.mkdir(parents=True, exist_ok=True)
    try:
        from tirefric.toml_writer import dumps

        path = write_compound(desc, folder / "compound.toml")
        record["compound_toml"] = dumps(compound_table(desc))
        dry, wet, t_grids = build_grids(settings, path, folder, desc["name"])
        res = evaluate_on_grids(settings, path, dry, wet, desc["name"])
        record["outputs"] = res["outputs"]
        record["seconds"] = {**t_grids, **res["seconds"]}
    except Exception as exc:  # one compound must not end the screen: reported, not raised
        record["status"] = "failed"
        record["error"] = f"{type(exc).__name__}: {exc}"
        record["traceback"] = traceback.format_exc(limit=6)
    finally:
        if settings.keep is None:
            shutil.rmtree(folder, ignore_errors=True)
    record.setdefault("seconds", {})
    record["seconds"]["total_s"] = time.perf_counter() - t_start
    record["seconds"]["cpu_s"] = time.process_time() - cpu0
    record["worker"] = _worker(t_epoch)
    return record


def _worker(t_epoch: float) -> dict[str, Any]:
    """Where and when a task ran (the benchmark's overhead accounting; not an output)."""
    import os
    import socket

    return {"host": socket.gethostname(), "pid": os.getpid(), "start_epoch_s": t_epoch,
            "end_epoch_s": time.time()}


def evaluate_reference(settings: Settings, desc: dict[str, Any], key: str) -> dict[str, Any]:
    """The reference tire of the wet grip test (the wet grip spec's, the SRTT) on the wet
    road grid of the reference compound at the screening resolution: its BFC and trailer
    peak, against which every candidate's wet grip index is formed (UN R117 Annex 5)."""
    from lookup.grid import load_grid
    from lookup.grid.build import build_grid
    from lookup.grid.wet import load_wet
    from tire_brush.braking.wet_grip_test import tire_result

    from .compounds import write_compound

    t_start = time.perf_counter()
    t_epoch = time.time()
    cpu0 = time.process_time()
    record: dict[str, Any] = {"name": desc["name"], "key": key, "description": desc,
                              "status": "ok", "error": None, "reference": True}
    folder = Path(tempfile.mkdtemp(prefix="tirefric-screen-ref-"))
    try:
        path = write_compound(desc, folder / "compound.toml")
        wet = folder / "wet.nc"
        build_grid(_grid_spec(settings.wet_spec, str(path), f"{desc['name']}_wet",
                              wet_temperatures(settings)), wet, workers=1, progress=False,
                   resume=False)
        wspec = screen_wet_grip_spec(settings, str(wet))
        ref, _ = tire_result(wspec, wspec.reference_tire, wspec.T_K, wspec.water_depth,
                             (load_grid(str(wet)), load_wet(str(wet))), with_dry=False,
                             point_evaluation=True)
        record["outputs"] = {"bfc_wet": float(ref["bfc_wet"]),
                             "peak_wet_trailer": float(ref["peak_wet"]),
                             "tire": wspec.reference_tire, "T_C": wspec.T_K - 273.15}
    except Exception as exc:
        record["status"] = "failed"
        record["error"] = f"{type(exc).__name__}: {exc}"
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    record["seconds"] = {"total_s": time.perf_counter() - t_start,
                         "cpu_s": time.process_time() - cpu0}
    record["worker"] = _worker(t_epoch)
    return record


def run_task(settings: Settings, kind: str, desc: dict[str, Any], key: str
             ) -> dict[str, Any]:
    """A task of :func:`lookup.grid.build.run_tasks`: ``kind`` ``"compound"`` or
    ``"reference"``."""
    if kind == "reference":
        return evaluate_reference(settings, desc, key)
    return evaluate_compound(settings, desc, key)


def finite(x: Any) -> bool:
    """Whether ``x`` is a finite number."""
    return isinstance(x, int | float) and math.isfinite(x)
