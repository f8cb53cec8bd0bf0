"""Braking study runner: OCP, rule-based ABS and locked wheel over roads, compounds, temperatures.

A study spec (TOML, e.g. ``models/studies/abs_analytic.toml``) names the quarter car, the
friction source, the cases and the settings. For each case the runner

1. builds the friction source (:mod:`.friction`) and tabulates it into a B-spline force map
   (:mod:`.force_map`) over slip, speed, load and temperature;
2. computes the optimal slip map (:mod:`.slip_map`) and the point-mass bound
   ``int_{v_stop}^{v0} v / (g mu_max(v)) dv`` (``v0^2 / (2 g mu_max)`` for a speed-independent
   peak) at the static load and the case temperature. It bounds every stop only while the
   tread stays at that temperature: with the thermal state on and a temperature-dependent
   map, a warming tread can raise friction and the OCP can end below it;
3. solves the minimum-distance OCP (:mod:`.ocp`) and simulates the rule-based ABS and the
   locked wheel (:mod:`.simulation`) on the same quarter car with the same force map, so the
   three stopping distances compare on identical physics;
4. returns a :class:`CaseResult`; :func:`write_results` writes the table (CSV, JSON), the
   trajectories, the slip maps and the plots.

Cases run one after the other, or on a Dask cluster when a scheduler address is given (each
case is one task; the spec and the case are plain picklable data).
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lookup.config import Table
from lookup.errors import InputError, InputErrors
from lookup.paths import resolve_model_file

from .abs_control import PHASES, ABSParams, LockedWheel, RuleBasedABS
from .force_map import ForceMap, default_axes
from .friction import FRICTION_KEYS, FRICTION_SOURCES, Case, make_friction_source
from .ocp import OCPResult, OCPSettings, solve_braking_ocp
from .quarter_car import QuarterCar, load_quarter_car
from .simulation import SimResult, SimSettings, simulate_braking
from .slip_map import SlipMap, optimal_slip

#: Columns of the results table, in order (the product interface named in issue 6 first).
RESULT_KEYS = (
    "case", "road", "compound", "T_C",
    "stopping_distance_ocp", "stopping_distance_abs", "stopping_distance_locked",
    "optimal_slip", "point_mass_bound", "mu_max", "mu_locked", "ocp_mean_slip",
    "stop_time_ocp", "stop_time_abs", "stop_time_locked", "ocp_solve_time_s",
    "ocp_iterations", "map_build_time_s", "T_tread_max_ocp_K",
)


@dataclass(frozen=True)
class MapSettings:
    """Force-map and slip-map axes.

    Attributes
    ----------
    n_kappa : int
        Slip nodes on [-1, 0] (graded towards 0, see :func:`.force_map.default_axes`).
    n_v : int
        Speed nodes (log-spaced from v_stop / 2 to 1.2 v0).
    loads_rel : tuple of float
        Loads as multiples of the static wheel load [1]; must contain 1.
    temperatures_rel : tuple of float
        Temperatures as offsets from the case temperature [K]; must contain 0. With the
        thermal state on, cover the tread's temperature rise.
    slip_map_speeds : tuple of float
        Speeds of the exported slip map [m/s].
    """

    n_kappa: int = 61
    n_v: int = 9
    loads_rel: tuple[float, ...] = (1.0,)
    temperatures_rel: tuple[float, ...] = (0.0,)
    slip_map_speeds: tuple[float, ...] = (2.0, 5.0, 10.0, 20.0, 30.0)


@dataclass(frozen=True)
class StudySpec:
    """A braking study as read from its TOML file (:func:`load_study`)."""

    name: str
    source: str
    v0: float
    v_stop: float
    car: QuarterCar
    friction: dict[str, Any]
    cases: tuple[Case, ...]
    abs_params: ABSParams = field(default_factory=ABSParams)
    ocp: OCPSettings = field(default_factory=OCPSettings)
    simulation: SimSettings = field(default_factory=SimSettings)
    maps: MapSettings = field(default_factory=MapSettings)
    brake_torque_initial: float = 0.0
    base_dir: str = "."


def load_study(path: str | Path) -> StudySpec:
    """Read and validate a study spec (file or shipped name under ``models/studies``).

    All problems found are reported together (:class:`~lookup.errors.InputErrors`).
    """
    path = resolve_model_file(path, "studies")
    root = Table.load(path)
    errors: list[InputError] = []

    def located(exc: InputError, rename: dict[str, str]) -> InputError:
        """The error with this file as its source (dataclass validators know no file)."""
        if exc.source is not None:
            return exc
        fld = rename.get(exc.field or "", exc.field)
        return InputError(exc.message, source=path, field=fld, value=exc.value)

    def collect(fn, *args, rename: dict[str, str] | None = None, **kw):
        try:
            return fn(*args, **kw)
        except InputErrors as exc:
            errors.extend(located(e, rename or {}) for e in exc.errors)
        except InputError as exc:
            errors.append(located(exc, rename or {}))
        return None

    root.raw("provenance", "")
    st = root.table("study")
    name = collect(st.string, "name", path.stem)
    v0 = collect(st.quantity, "v0", "velocity", positive=True)
    v_stop = collect(st.quantity, "v_stop", "velocity", 1.0, positive=True)
    Tb0 = collect(st.quantity, "brake_torque_initial_Nm", "dimensionless", 0.0, nonnegative=True)
    vehicle_file = collect(st.path, "vehicle")
    car = collect(load_quarter_car, vehicle_file) if vehicle_file else None
    collect(st.check_unknown)
    if v0 is not None and v_stop is not None and not v0 > v_stop:
        errors.append(st.error("v_stop", "must be below study.v0", st.raw("v_stop")))

    fr = root.table("friction")
    source = collect(fr.string, "source", "analytic", choices=FRICTION_SOURCES) or "analytic"
    friction: dict[str, Any] = {"source": source}
    for key in FRICTION_KEYS.get(source, ()):
        if fr.has(key):
            friction[key] = fr.raw(key)
    collect(fr.check_unknown)

    cs = root.table("cases")
    roads = collect(_string_list, cs, "roads", required=True) or []
    compounds = collect(_string_list, cs, "compounds", required=False) or [""]
    temps = collect(cs.array, "temperatures", "temperature")
    collect(cs.check_unknown)
    if temps is not None and (temps <= 0).any():
        errors.append(cs.error("temperatures", "below absolute zero", cs.raw("temperatures")))
    cases = tuple(Case(r, c, float(T)) for r, c, T in
                  itertools.product(roads, compounds, [] if temps is None else temps))

    if source == "analytic":      # cheap to build: check road names and parameters now
        rename = {"road": "cases.roads", "c4": "friction.c4", "mu_scale": "friction.mu_scale"}
        seen: set[str] = set()
        for case in cases:
            n = len(errors)
            collect(make_friction_source, friction, case, path.parent, rename=rename)
            # one message per problem, not one per case
            for e in errors[n:]:
                if str(e) in seen:
                    errors.remove(e)
                seen.add(str(e))

    def sub(key: str) -> Table | None:
        return root.table(key, required=False)

    abs_params = ABSParams()
    if (t := sub("abs")) is not None:
        kw = {}
        for k in ("slip_threshold", "reapply_fraction"):
            if t.has(k):
                kw[k] = collect(t.quantity, k, "dimensionless", positive=True)
        for k in ("decel_threshold", "accel_threshold", "accel_threshold_high"):
            if t.has(k):
                kw[k] = collect(t.quantity, f"{k}", "dimensionless", positive=True)
        if t.has("control_period"):
            kw["control_period"] = collect(t.quantity, "control_period", "time", positive=True)
        collect(t.check_unknown)
        abs_params = collect(ABSParams, **{k: v for k, v in kw.items() if v is not None}) \
            or ABSParams()

    ocp = OCPSettings()
    if (t := sub("ocp")) is not None:
        kw = {}
        for k in ("intervals", "degree", "max_iter"):
            if t.has(k):
                kw[k] = collect(t.integer, k, minimum=1)
        if t.has("rate_penalty"):
            kw["rate_penalty"] = collect(t.quantity, "rate_penalty", "dimensionless",
                                         nonnegative=True)
        if t.has("kappa_min"):
            kw["kappa_min"] = collect(t.quantity, "kappa_min", "dimensionless", minimum=-1.0,
                                      maximum=-1e-3)
        collect(t.check_unknown)
        ocp = collect(OCPSettings, **{k: v for k, v in kw.items() if v is not None}) \
            or OCPSettings()

    sim = SimSettings()
    if (t := sub("simulation")) is not None:
        kw = {}
        if t.has("dt"):
            kw["dt"] = collect(t.quantity, "dt", "time", positive=True)
        if t.has("t_max"):
            kw["t_max"] = collect(t.quantity, "t_max", "time", positive=True)
        collect(t.check_unknown)
        sim = collect(SimSettings, **{k: v for k, v in kw.items() if v is not None}) \
            or SimSettings()

    maps = MapSettings()
    if (t := sub("map")) is not None:
        kw = {}
        for k in ("n_kappa", "n_v"):
            if t.has(k):
                kw[k] = collect(t.integer, k, minimum=4)
        if t.has("loads_rel"):
            a = collect(t.array, "loads_rel", positive=True, increasing=True)
            if a is not None and not np.isclose(a, 1.0).any():
                errors.append(t.error("loads_rel", "must contain 1 (the static load)",
                                      t.raw("loads_rel")))
            kw["loads_rel"] = None if a is None else tuple(a.tolist())
        if t.has("temperatures_rel"):
            a = collect(t.array, "temperatures_rel", "temperature_difference", increasing=True)
            if a is not None and not np.isclose(a, 0.0).any():
                errors.append(t.error("temperatures_rel", "must contain 0 (the case "
                                      "temperature)", t.raw("temperatures_rel")))
            kw["temperatures_rel"] = None if a is None else tuple(a.tolist())
        if t.has("slip_map_speeds"):
            a = collect(t.array, "slip_map_speeds", "velocity", positive=True, increasing=True)
            kw["slip_map_speeds"] = None if a is None else tuple(a.tolist())
        collect(t.check_unknown)
        maps = MapSettings(**{k: v for k, v in kw.items() if v is not None})
    collect(root.check_unknown)
    if not cases and not errors:
        errors.append(cs.error("roads", "no cases (need roads and temperatures)"))
    if errors:
        raise InputErrors(errors)
    return StudySpec(name=name, source=source, v0=v0, v_stop=v_stop, car=car,
                     friction=friction, cases=cases, abs_params=abs_params, ocp=ocp,
                     simulation=sim, maps=maps, brake_torque_initial=Tb0,
                     base_dir=str(path.parent))


def _string_list(t: Table, key: str, required: bool) -> list[str]:
    value = t.raw(key, ... if required else [])
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise t.error(key, "expected a list of names", value)
    if required and not value:
        raise t.error(key, "expected at least one name", value)
    return list(value)


# -- one case ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CaseResult:
    """Everything a case produced (numbers for the table, trajectories for the plots)."""

    case: Case
    summary: dict[str, Any]
    ocp: OCPResult
    abs_sim: SimResult
    locked: SimResult
    slip_map: SlipMap
    force_map: ForceMap
    provenance: dict[str, Any]


def case_force_map(spec: StudySpec, case: Case) -> tuple[ForceMap, dict[str, Any], str]:
    """Friction source of ``case`` tabulated as a force map over the study's axes."""
    src = make_friction_source(spec.friction, case, Path(spec.base_dir))
    ax = default_axes(spec.v0, spec.v_stop, spec.car.Fz, case.T_K, n_kappa=spec.maps.n_kappa,
                      n_v=spec.maps.n_v)
    ax["Fz"] = spec.car.Fz * np.asarray(spec.maps.loads_rel)
    ax["T_K"] = case.T_K + np.asarray(spec.maps.temperatures_rel)
    fmap = ForceMap.build(src.fx_over_fz, **ax, label=src.label)
    return fmap, src.provenance, src.label


def point_mass_bound(slip_map_v: SlipMap, v0: float, v_stop: float, g: float) -> float:
    """``int_{v_stop}^{v0} v / (g mu_max(v)) dv`` [m] with ``mu_max(v)`` from a slip map.

    ``mu_max`` is interpolated linearly in ``log v`` between the map's speeds (at one load and
    temperature); for a speed-independent peak this is ``(v0^2 - v_stop^2) / (2 g mu_max)``.
    """
    v = np.linspace(v_stop, v0, 401)
    mu = np.interp(np.log(v), np.log(slip_map_v.vx), slip_map_v.mu_max.ravel())
    return float(np.trapezoid(v / (g * mu), v))


def run_case(spec: StudySpec, case: Case) -> CaseResult:
    """Run one case: force map, slip maps, OCP, ABS and locked-wheel simulations."""
    car = spec.car
    fmap, prov, label = case_force_map(spec, case)
    v_bound = np.geomspace(spec.v_stop, spec.v0, 25)
    sm_line = optimal_slip(fmap, v_bound, [car.Fz], [case.T_K], label=label)
    bound = point_mass_bound(sm_line, spec.v0, spec.v_stop, car.g)
    sm = optimal_slip(fmap, np.asarray(spec.maps.slip_map_speeds), fmap.axes["Fz"],
                      fmap.axes["T_K"], label=label)
    sm0 = optimal_slip(fmap, [spec.v0], [car.Fz], [case.T_K], label=label)

    ocp = solve_braking_ocp(car, fmap, spec.v0, spec.v_stop, case.T_K, settings=spec.ocp,
                            brake_torque_initial=spec.brake_torque_initial)
    abs_ctrl = RuleBasedABS(spec.abs_params, car.radius, car.brake_torque_rate_max)
    abs_sim = simulate_braking(car, fmap, abs_ctrl, spec.v0, spec.v_stop, case.T_K,
                               settings=spec.simulation,
                               brake_torque_initial=spec.brake_torque_initial)
    locked = simulate_braking(car, fmap, LockedWheel(car.brake_torque_rate_max,
                                                     spec.abs_params.control_period),
                              spec.v0, spec.v_stop, case.T_K, settings=spec.simulation,
                              brake_torque_initial=spec.brake_torque_initial)
    # distance-weighted mean slip of the OCP (the slip the optimal stop holds)
    dx = np.diff(ocp.x)
    k_mid = 0.5 * (ocp.kappa[1:] + ocp.kappa[:-1])
    summary = {
        "case": case.label, "road": case.road, "compound": case.compound,
        "T_C": round(case.T_C, 6),
        "stopping_distance_ocp": ocp.stopping_distance,
        "stopping_distance_abs": abs_sim.stopping_distance,
        "stopping_distance_locked": locked.stopping_distance,
        "optimal_slip": float(sm0.kappa_opt.ravel()[0]),
        "point_mass_bound": bound,
        "mu_max": float(sm0.mu_max.ravel()[0]),
        "mu_locked": float(sm0.mu_locked.ravel()[0]),
        "ocp_mean_slip": float(np.sum(k_mid * dx) / np.sum(dx)),
        "stop_time_ocp": ocp.final_time, "stop_time_abs": abs_sim.stop_time,
        "stop_time_locked": locked.stop_time,
        "ocp_solve_time_s": ocp.solve_time_s, "ocp_iterations": ocp.iterations,
        "map_build_time_s": fmap.build_time_s,
        "T_tread_max_ocp_K": float(np.max(ocp.T_tread)),
        "Fz_N": car.Fz, "radius_m": car.radius,
    }
    return CaseResult(case=case, summary=summary, ocp=ocp, abs_sim=abs_sim, locked=locked,
                      slip_map=sm, force_map=fmap,
                      provenance={"friction": prov, "friction_label": label,
                                  "ocp_status": ocp.status,
                                  "ocp_kappa_bound": ocp.kappa_bound,
                                  "ocp_kappa_bound_active": ocp.kappa_bound_active})


def run_study(spec: StudySpec, scheduler: str | None = None,
              progress=None) -> list[CaseResult]:
    """Run every case, locally in order or as Dask tasks on ``scheduler`` (an address)."""
    if scheduler is None:
        out = []
        for case in spec.cases:
            if progress is not None:
                progress(f"case {case.label}")
            out.append(run_case(spec, case))
        return out
    from dask.distributed import Client

    with Client(scheduler) as client:
        futures = [client.submit(run_case, spec, case, pure=False) for case in spec.cases]
        return client.gather(futures)


# -- output ---------------------------------------------------------------------------------------
def _trajectory_rows(name: str, r: OCPResult | SimResult, stride: int = 1):
    phase = getattr(r, "phase", None)
    for i in range(0, r.t.size, stride):
        yield (name, r.t[i], r.x[i], r.v[i], r.omega[i], r.brake_torque[i], r.kappa[i],
               r.mu[i], r.T_tread[i], "" if phase is None else PHASES[int(phase[i])])
    if (r.t.size - 1) % stride:
        i = r.t.size - 1
        yield (name, r.t[i], r.x[i], r.v[i], r.omega[i], r.brake_torque[i], r.kappa[i],
               r.mu[i], r.T_tread[i], "" if phase is None else PHASES[int(phase[i])])


def write_results(spec: StudySpec, results: list[CaseResult], out_dir: str | Path, *,
                  plots: bool = True, spec_path: str | Path | None = None) -> dict[str, Any]:
    """Write ``results.csv``, ``results.json``, trajectories, slip maps and plots to ``out_dir``.

    Returns the JSON document.
    """
    out = Path(out_dir)
    (out / "trajectories").mkdir(parents=True, exist_ok=True)
    (out / "slip_maps").mkdir(parents=True, exist_ok=True)
    rows = [r.summary for r in results]
    with open(out / "results.csv", "w", newline="") as fh:
        fh.write(f"# braking study {spec.name}: v0 = {spec.v0:g} m/s, v_stop = "
                 f"{spec.v_stop:g} m/s; distances [m] from v0 to v_stop, slips [1] "
                 "(negative in braking), times [s], temperatures T_C [Celsius]\n")
        w = csv.writer(fh)
        w.writerow(RESULT_KEYS)
        for row in rows:
            w.writerow([f"{row[k]:.8g}" if isinstance(row[k], float) else row[k]
                        for k in RESULT_KEYS])
    for r in results:
        with open(out / "trajectories" / f"{r.case.label}.csv", "w", newline="") as fh:
            fh.write("# strategy: ocp (optimal control, interval boundaries), abs (rule-based), "
                     "locked (no ABS)\n")
            w = csv.writer(fh)
            w.writerow(["strategy", "t [s]", "x [m]", "v [m/s]", "omega [rad/s]",
                        "brake_torque [N m]", "kappa [1]", "mu [1]", "T_tread [K]", "phase"])
            stride = max(1, round(0.001 / r.abs_sim.dt))      # 1 ms in the simulations
            for name, res, s in (("ocp", r.ocp, 1), ("abs", r.abs_sim, stride),
                                 ("locked", r.locked, stride)):
                for row in _trajectory_rows(name, res, s):
                    w.writerow([row[0], *(f"{x:.8g}" for x in row[1:9]), row[9]])
        r.slip_map.to_csv(out / "slip_maps" / f"{r.case.label}.csv")
    doc = {
        "study": spec.name,
        "spec": None if spec_path is None else str(spec_path),
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "units": {"stopping_distance_*": "m", "point_mass_bound": "m", "optimal_slip": "1",
                  "T_C": "Celsius", "stop_time_*": "s", "mu_*": "1"},
        "v0_m_per_s": spec.v0, "v_stop_m_per_s": spec.v_stop,
        "vehicle": _jsonable(asdict(spec.car)),
        "abs": asdict(spec.abs_params), "ocp": asdict(spec.ocp),
        "simulation": asdict(spec.simulation), "map": asdict(spec.maps),
        "friction": spec.friction,
        "cases": [dict(r.summary, provenance=_jsonable(r.provenance),
                       ocp_trajectory={"t": r.ocp.t.tolist(), "kappa": r.ocp.kappa.tolist(),
                                       "v": r.ocp.v.tolist()})
                  for r in results],
    }
    with open(out / "results.json", "w") as fh:
        json.dump(_jsonable(doc), fh, indent=2)
    if plots:
        from . import plots as plotting

        (out / "plots").mkdir(exist_ok=True)
        for r in results:
            plotting.plot_time_histories(r, out / "plots" / f"{r.case.label}_time.png")
            plotting.plot_mu_slip(r, out / "plots" / f"{r.case.label}_mu_slip.png")
        plotting.plot_distances(results, out / "plots" / "distances.png")
    return doc


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj
