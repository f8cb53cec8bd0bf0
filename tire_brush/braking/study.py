"""Braking study runner: OCP, rule-based ABS and locked wheel over roads, compounds, temperatures.

A study spec (TOML, e.g. ``models/studies/abs_analytic.toml``) names the quarter car, the
friction source, the cases and the settings. For each case the runner

1. builds the friction source (:mod:`.friction`) and tabulates it into a B-spline force map
   (:mod:`.force_map`) over slip, speed, load and temperature. With the thermal state on, the
   temperature axis reaches up to the largest tread-temperature rise a stop can cause
   (:func:`case_temperatures`), so no strategy reads a frozen edge of the map;
2. computes the optimal slip map (:mod:`.slip_map`) and point-mass bounds
   ``int_{v_stop}^{v0} v / (g mu_max(v)) dv`` (``v0^2 / (2 g mu_max)`` for a speed-independent
   peak) at the static load, with ``mu_max(v)`` the peak friction maximised over a range of
   tread temperatures (a warming tread changes the friction): ``point_mass_bound`` over the
   temperatures the OCP's tread passes through (the OCP cannot beat it),
   ``point_mass_bound_T0`` at the case temperature (the isothermal bound), and
   ``point_mass_bound_reachable`` over every temperature a stop can reach (bounds every
   strategy); and the same with the brake torque's build-up at its rate limit
   (:func:`ramp_bound`: ``ramp_bound``, ``ramp_bound_reachable``), tighter and as valid;
   and the bound that follows the tread's heating (:mod:`.thermal_dp`: the global optimum
   of the stop with a quasi-steady wheel by dynamic programming over speed and tread
   temperature, with the brake's build-up: ``thermal_bound``), against the best of which
   the OCP's optimum is checked (``ocp_optimality``, ``ocp_bound_gap``);
3. solves the minimum-distance OCP (:mod:`.ocp`) and simulates the rule-based ABS and the
   locked wheel (:mod:`.simulation`) on the same quarter car with the same force map, so the
   three stopping distances compare on identical physics. With ``[abs] slip_threshold =
   "slip_map"`` the ABS releases at the case's optimal slip per speed
   (:func:`abs_slip_schedule`). With ``[study] fmu_abs = true`` the same ABS also brakes the
   car through the brush-tire FMU (the transient model), with the simulator factory handed
   to :func:`run_study` by the top layer (``stopping_distance_abs_fmu``);
4. returns a :class:`CaseResult`; :func:`write_results` writes the table (CSV, JSON), the
   trajectories, the slip maps and the plots.

Cases run one after the other, or on a Dask cluster when a scheduler address is given (each
case is one task; the spec, the case and the FMU simulator are plain picklable data).
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.config import Table
from tirefric.errors import InputError, InputErrors
from tirefric.paths import resolve_model_file

from .abs_control import (
    HOLD_RECOVER,
    PHASES,
    REAPPLY,
    ABSParams,
    LockedWheel,
    RealisticABS,
    RuleBasedABS,
)
from .force_map import ForceMap, default_axes
from .friction import (
    FRICTION_KEYS,
    FRICTION_SOURCES,
    Case,
    brush_rolling_resistance,
    make_friction_source,
)
from .ocp import OCPResult, OCPSettings, solve_braking_ocp
from .quarter_car import (
    QuarterCar,
    load_quarter_car,
    ramp_limited_stopping_distance,
    tread_temperature_rise_bound,
)
from .results import CaseFailure, CaseResult
from .simulation import SimResult, SimSettings, simulate_braking
from .slip_map import SlipMap, optimal_slip
from .thermal_dp import describe as describe_thermal_bound
from .thermal_dp import thermal_ramp_bound

#: Columns of the results table, in order (the product interface first: the three stopping
#: distances and the optimal slip).
RESULT_KEYS = (
    "case", "road", "compound", "T_C",
    "stopping_distance_ocp", "stopping_distance_abs", "stopping_distance_locked",
    "optimal_slip", "point_mass_bound", "mu_max", "mu_locked", "ocp_mean_slip",
    "stop_time_ocp", "stop_time_abs", "stop_time_locked", "ocp_solve_time_s",
    "ocp_iterations", "map_build_time_s", "T_tread_max_ocp_K",
    "stopping_distance_abs_fmu", "stop_time_abs_fmu", "point_mass_bound_T0",
    "point_mass_bound_reachable",
    "mu_max_reachable", "T_tread_rise_bound_K", "T_tread_max_abs_K", "T_tread_max_locked_K",
    "T_tread_max_abs_fmu_K", "abs_mean_slip", "abs_fmu_mean_slip",
    "stopping_distance_abs_realistic", "stop_time_abs_realistic", "abs_realistic_cycle_hz",
    "abs_cycle_hz", "T_tread_max_abs_realistic_K", "ocp_optimality",
    "ramp_bound", "ramp_bound_reachable", "ocp_bound_gap",
    "thermal_bound", "thermal_bound_error", "slip_dp_distance", "thermal_bound_split_s",
    "slip_dp_coast_ratio",
)

#: Initial guesses the OCP can start from (``[ocp] starts``, :func:`solve_ocp_from_starts`).
OCP_STARTS = ("deceleration", "locked", "abs", "isothermal")



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
    temperature_step : float
        Spacing [K] of the temperature nodes the study adds above ``temperatures_rel`` until
        the map covers the largest tread-temperature rise of a stop
        (:func:`.quarter_car.tread_temperature_rise_bound`; thermal state on and a
        temperature-dependent friction source only). Beyond its last node the map is
        constant, which would freeze the friction of a tread that heats further.
    """

    n_kappa: int = 61
    n_v: int = 9
    loads_rel: tuple[float, ...] = (1.0,)
    temperatures_rel: tuple[float, ...] = (0.0,)
    slip_map_speeds: tuple[float, ...] = (2.0, 5.0, 10.0, 20.0, 30.0)
    temperature_step: float = 2.0


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
    abs_slip_from_map: bool = False
    fmu_abs: bool = False
    fmu: dict[str, Any] = field(default_factory=dict)
    ocp_starts: tuple[str, ...] = ("deceleration",)
    ocp_stop_when_verified: bool = False


class ErrorCollector:
    """Calls a spec's readers and keeps their errors, so that a spec file's problems are
    reported together (:class:`~tirefric.errors.InputErrors`).

    ``collect(fn, *args, rename=None, **kw)`` returns ``fn(*args, **kw)``, or None after
    adding its error(s) to :attr:`errors`; an error without a file (a dataclass validator's)
    gets ``path`` as its source and its field renamed by ``rename``.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self.errors: list[InputError] = []

    def located(self, exc: InputError, rename: dict[str, str]) -> InputError:
        """The error with this file as its source (dataclass validators know no file)."""
        if exc.source is not None:
            return exc
        fld = rename.get(exc.field or "", exc.field)
        return InputError(exc.message, source=self.path, field=fld, value=exc.value)

    def __call__(self, fn, *args, rename: dict[str, str] | None = None, **kw):
        try:
            return fn(*args, **kw)
        except InputErrors as exc:
            self.errors.extend(self.located(e, rename or {}) for e in exc.errors)
        except InputError as exc:
            self.errors.append(self.located(exc, rename or {}))
        return None


def read_stop_spec(path: str | Path) -> tuple[Path, Table, ErrorCollector, Table, Any, Any,
                                              Any]:
    """The part every stop spec shares (a braking study, a roads spec): the file (a path or
    a shipped name under ``models/studies``), its root table, an :class:`ErrorCollector`, the
    ``[study]`` table and its ``name``, ``v0`` and ``v_stop`` [m/s] (None where refused; the
    collector holds why)."""
    path = resolve_model_file(path, "studies")
    root = Table.load(path)
    collect = ErrorCollector(path)
    root.raw("provenance", "")
    st = root.table("study")
    name = collect(st.string, "name", path.stem)
    v0 = collect(st.quantity, "v0", "velocity", positive=True)
    v_stop = collect(st.quantity, "v_stop", "velocity", 1.0, positive=True)
    return path, root, collect, st, name, v0, v_stop


def load_study(path: str | Path) -> StudySpec:
    """Read and validate a study spec (file or shipped name under ``models/studies``).

    All problems found are reported together (:class:`~tirefric.errors.InputErrors`).
    """
    path, root, collect, st, name, v0, v_stop = read_stop_spec(path)
    errors = collect.errors
    Tb0 = collect(st.quantity, "brake_torque_initial_Nm", "dimensionless", 0.0, nonnegative=True)
    vehicle_file = collect(st.path, "vehicle")
    car = collect(load_quarter_car, vehicle_file) if vehicle_file else None
    fmu_abs = bool(collect(st.boolean, "fmu_abs", False))
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
    abs_slip_from_map = False
    if (t := sub("abs")) is not None:
        kw = {}
        if t.raw("slip_threshold", None) == "slip_map":
            abs_slip_from_map = True
        elif t.has("slip_threshold"):
            kw["slip_threshold"] = collect(t.quantity, "slip_threshold", "dimensionless",
                                           positive=True)
        if t.has("reapply_fraction"):
            kw["reapply_fraction"] = collect(t.quantity, "reapply_fraction", "dimensionless",
                                             positive=True)
        for k in ("decel_threshold", "accel_threshold", "accel_threshold_high"):
            if t.has(k):
                kw[k] = collect(t.quantity, f"{k}", "dimensionless", positive=True)
        if t.has("control_period"):
            kw["control_period"] = collect(t.quantity, "control_period", "time", positive=True)
        collect(t.check_unknown)
        abs_params = collect(ABSParams, **{k: v for k, v in kw.items() if v is not None}) \
            or ABSParams()

    ocp = OCPSettings()
    ocp_starts: tuple[str, ...] = ("deceleration",)
    ocp_stop_when_verified = False
    if (t := sub("ocp")) is not None:
        kw = {}
        if t.has("stop_when_verified"):
            ocp_stop_when_verified = bool(collect(t.boolean, "stop_when_verified", False))
        if t.has("jit"):
            kw["jit"] = collect(t.boolean, "jit", True)
        for k in ("intervals", "degree", "max_iter"):
            if t.has(k):
                kw[k] = collect(t.integer, k, minimum=1)
        if t.has("rate_penalty"):
            kw["rate_penalty"] = collect(t.quantity, "rate_penalty", "dimensionless",
                                         nonnegative=True)
        if t.has("kappa_min"):
            kw["kappa_min"] = collect(t.quantity, "kappa_min", "dimensionless", minimum=-1.0,
                                      maximum=-1e-3)
        if t.has("starts"):
            starts = t.raw("starts")
            if not isinstance(starts, list) or not starts or \
                    not set(starts) <= set(OCP_STARTS) or len(set(starts)) != len(starts):
                errors.append(t.error("starts", f"expected a list of distinct starts out of "
                                      f"{', '.join(OCP_STARTS)}", starts))
            else:
                ocp_starts = tuple(starts)
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
        if t.has("temperature_step"):
            kw["temperature_step"] = collect(t.quantity, "temperature_step",
                                             "temperature_difference", positive=True)
        collect(t.check_unknown)
        maps = MapSettings(**{k: v for k, v in kw.items() if v is not None})

    fmu: dict[str, Any] = {}
    if (t := sub("fmu")) is not None:
        if not fmu_abs:
            errors.append(t.error("step", "an [fmu] table needs study.fmu_abs = true"))
        for k in ("step", "t_max", "dt_internal"):
            if t.has(k):
                fmu[k] = collect(t.quantity, k, "time", positive=True)
        if t.has("n_elements"):
            fmu["n_elements"] = collect(t.integer, "n_elements", minimum=2)
        if t.has("thermal"):
            fmu["thermal"] = collect(t.string, "thermal", choices=("vehicle", "fmu"))
        collect(t.check_unknown)
        fmu = {k: v for k, v in fmu.items() if v is not None}
    if fmu_abs and source != "brush":
        errors.append(st.error("fmu_abs", "the FMU runs the brush tire: needs "
                               "friction.source = 'brush'", True))
    collect(root.check_unknown)
    if not cases and not errors:
        errors.append(cs.error("roads", "no cases (need roads and temperatures)"))
    if errors:
        raise InputErrors(errors)
    return StudySpec(name=name, source=source, v0=v0, v_stop=v_stop, car=car,
                     friction=friction, cases=cases, abs_params=abs_params, ocp=ocp,
                     simulation=sim, maps=maps, brake_torque_initial=Tb0,
                     base_dir=str(path.parent), abs_slip_from_map=abs_slip_from_map,
                     fmu_abs=fmu_abs, fmu=fmu, ocp_starts=ocp_starts,
                     ocp_stop_when_verified=ocp_stop_when_verified)


def _string_list(t: Table, key: str, required: bool) -> list[str]:
    value = t.raw(key, ... if required else [])
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise t.error(key, "expected a list of names", value)
    if required and not value:
        raise t.error(key, "expected at least one name", value)
    return list(value)


# -- one case ------------------------------------------------------------------------------------
#: Relative slack of the optimality checks (:func:`ocp_optimality`): the OCP's transcription
#: error at 200 intervals and the simulations' step error are below it.
OPTIMALITY_SLACK = 2e-3


def ocp_optimality(distance: float, bound: float, simulated: dict[str, float]) -> str:
    """Whether the OCP's stop is shown optimal by the checks that are at hand.

    "verified" when it is no longer than every simulated strategy and no shorter than the
    lower ``bound`` (each within :data:`OPTIMALITY_SLACK`; the study hands in the larger of
    :func:`ramp_bound`, the point-mass bound with the brake torque's build-up, and the
    bound that follows the tread's heating, :func:`.thermal_dp.thermal_ramp_bound`); otherwise
    the reason, with the numbers: a simulated strategy that stops shorter proves that IPOPT
    found a local optimum only (start it from that strategy: ``[ocp] starts``); a stop below
    the bound cannot be proven against it (an error of the transcription, or a bound that
    does not hold for this model). How close the optimum comes to the bound over every
    temperature a stop can reach is reported apart (``ocp_bound_gap``: the optimum is at
    most this fraction longer than the best possible stop); a gap shows what the bound
    leaves out (the wheel's spin-down, the time the tread takes to heat), not a failure.
    """
    why = []
    for name, d in sorted(simulated.items(), key=lambda kv: kv[1]):
        if d < distance * (1.0 - OPTIMALITY_SLACK):
            why.append(f"{name} stops in {d:.3f} m, shorter than the OCP's {distance:.3f} m: "
                       "a local optimum")
    if distance < bound * (1.0 - OPTIMALITY_SLACK):
        why.append(f"the OCP's {distance:.3f} m is below the lower bound {bound:.3f} m")
    return "verified" if not why else "not proven: " + "; ".join(why)


def abs_cycle_frequency(sim: SimResult) -> float:
    """ABS control cycles per second of a simulated stop [Hz]: completed recoveries (a
    ``hold_recover`` phase followed by the re-apply) over the stop time (production ABS
    cycle at 4-10 Hz on asphalt)."""
    ph = np.asarray(sim.phase)
    n = int(np.sum((ph[:-1] == HOLD_RECOVER) & (ph[1:] == REAPPLY)))
    return n / sim.stop_time if sim.stop_time > 0 else math.nan


def run_case_or_failure(spec: StudySpec, case: Case,
                        fmu_simulator: Any = None) -> CaseResult | CaseFailure:
    """:func:`run_case`, or the :class:`CaseFailure` that says why it failed."""
    try:
        return run_case(spec, case, fmu_simulator)
    except Exception as exc:  # one case must not end the study
        return CaseFailure(case=case, error=f"{type(exc).__name__}: {exc}")


def case_temperatures(spec: StudySpec, case: Case, temperature_dependent: bool = True
                      ) -> np.ndarray:
    """Temperature nodes of the force map of ``case`` [K].

    The case temperature plus ``maps.temperatures_rel``; with the thermal state on and a
    temperature-dependent source, nodes every ``maps.temperature_step`` above the largest
    offset until the tread-temperature rise bound of the stop is covered
    (:func:`.quarter_car.tread_temperature_rise_bound`): the tread of every strategy stays
    inside the map, none reads a frozen edge value.
    """
    rel = np.asarray(spec.maps.temperatures_rel, dtype=float)
    rise = tread_temperature_rise_bound(spec.car, spec.v0) if temperature_dependent else 0.0
    top = float(rel.max())
    if rise > top:
        step = spec.maps.temperature_step
        n = math.ceil((rise - top) / step - 1e-9)
        rel = np.concatenate([rel, top + step * np.arange(1, n + 1)])
    return case.T_K + rel


def case_force_map(spec: StudySpec, case: Case) -> tuple[ForceMap, dict[str, Any], str]:
    """Friction source of ``case`` tabulated as a force map over the study's axes."""
    src = make_friction_source(spec.friction, case, Path(spec.base_dir))
    ax = default_axes(spec.v0, spec.v_stop, spec.car.Fz, case.T_K, n_kappa=spec.maps.n_kappa,
                      n_v=spec.maps.n_v)
    ax["Fz"] = spec.car.Fz * np.asarray(spec.maps.loads_rel)
    ax["T_K"] = case_temperatures(spec, case, src.temperature_dependent)
    fmap = ForceMap.build(src.fx_over_fz, **ax, label=src.label)
    return fmap, src.provenance, src.label


def point_mass_bound(slip_map_v: SlipMap, v0: float, v_stop: float, g: float) -> float:
    """``int_{v_stop}^{v0} v / (g mu_max(v)) dv`` [m] with ``mu_max(v)`` from a slip map.

    ``mu_max`` is interpolated linearly in ``log v`` between the map's speeds; with several
    loads or temperatures in the map, the largest over them is taken at each speed (the
    bound of a stop whose load or temperature may be any of them). For a speed-independent
    peak this is ``(v0^2 - v_stop^2) / (2 g mu_max)``.
    """
    v = np.linspace(v_stop, v0, 401)
    mu_v = slip_map_v.mu_max.reshape(slip_map_v.vx.size, -1).max(axis=1)
    mu = np.interp(np.log(v), np.log(slip_map_v.vx), mu_v)
    return float(np.trapezoid(v / (g * mu), v))


def ramp_bound(slip_map_v: SlipMap, car: QuarterCar, v0: float, v_stop: float,
               brake_torque_initial: float = 0.0) -> float:
    """Lower bound [m] on the stop from ``v0`` to ``v_stop`` with the brake torque's rate
    limit (:func:`.quarter_car.ramp_limited_stopping_distance`): the point-mass bound of
    :func:`point_mass_bound` (same ``mu_max(v)``: linear in ``log v`` between the slip map's
    speeds, the largest over its loads and temperatures) plus what the car covers while
    the torque builds up at its rate limit and cannot yet hold the peak friction."""
    mu_v = slip_map_v.mu_max.reshape(slip_map_v.vx.size, -1).max(axis=1)
    log_vx = np.log(slip_map_v.vx)

    def mu_max(v: np.ndarray) -> np.ndarray:
        return np.interp(np.log(v), log_vx, mu_v)

    return ramp_limited_stopping_distance(car, v0, v_stop, mu_max, brake_torque_initial)


def _mean_slip(r: OCPResult | SimResult | Any) -> float:
    """Distance-weighted mean slip of a stop [1]."""
    dx = np.diff(r.x)
    k_mid = 0.5 * (r.kappa[1:] + r.kappa[:-1])
    return float(np.sum(k_mid * dx) / np.sum(dx))


def abs_slip_schedule(slip_map_v: SlipMap) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Release slips of the rule-based ABS from a slip map at one load and temperature.

    The release threshold at each speed is the slip of maximum braking force ``|kappa*(v)|``:
    below it ``d mu / d |kappa| > 0`` and the wheel is stable under a held torque; beyond it
    the slope turns negative, the wheel is unstable and runs towards lock (Savaresi & Tanelli
    2010, sec. 2.2: wheel dynamics linearised about the slip). Releasing there is the
    calibration per tire and road a production ABS carries; it needs no margin tuned on
    another curve, whatever the width of the peak.
    """
    speeds = tuple(float(v) for v in slip_map_v.vx)
    slips = tuple(float(-k) for k in slip_map_v.kappa_opt.reshape(len(speeds), -1)[:, 0])
    return speeds, slips


def solve_ocp_from_starts(spec: StudySpec, case: Case, fmap: ForceMap, locked: SimResult,
                          abs_sim: SimResult | None = None, verify: Any = None
                          ) -> tuple[OCPResult, str, dict[str, Any]]:
    """The OCP from each of ``spec.ocp_starts``; the shortest converged stop is kept.

    IPOPT finds a local optimum, and with the tread temperature as a state the problem has
    more than one: braking at the peak of a cold tire, or sliding first to heat a tread whose
    friction rises with temperature (a compound near its glass transition). The starts:

    ``deceleration``
        Constant deceleration at the optimal slip (:func:`.ocp.solve_braking_ocp`), slip
        bounded near the peak (``spec.ocp.kappa_min``).
    ``locked``
        The locked-wheel simulation of the case, over the full slip range ``[-1, 0]``: a
        feasible point on the sliding side from which IPOPT improves.
    ``abs``
        The rule-based ABS simulation of the case (``abs_sim``), over the full slip range:
        a feasible point near the peak slip, on the other side of the sliding optimum.
    ``isothermal``
        Homotopy in the tread heating: the OCP of the same car with the tread held at the
        case temperature (a smaller problem without the temperature's local optima), its
        tread temperature then integrated along that stop (:func:`with_tread_heating`), as
        the start of the full problem. The same as ``deceleration`` without a thermal state.

    With ``verify`` (a function of an :class:`.ocp.OCPResult` that returns True when the
    checks at hand show it optimal, :func:`ocp_optimality`) and ``spec.ocp_stop_when_verified``
    the remaining starts are skipped after the first verified result (listed in ``tried`` as
    ``{"skipped": ...}``). "Verified" means no simulated strategy stops shorter and the point
    -mass bound holds; another local optimum can still be shorter (measured on an earlier
    passenger tire at 20 C: the locked start's optimum 0.3 % below the peak-slip start's).

    Returns the best result, its start and per start the distance or the failure.
    """

    from tirefric.errors import ConvergenceError

    results: dict[str, OCPResult] = {}
    tried: dict[str, Any] = {}
    for start in spec.ocp_starts:
        done = next((k for k in results if tried[k].get("verified")), None)
        if done is not None:
            tried[start] = {"skipped": f"the {done} start's optimum is verified"}
            continue
        try:
            if start == "isothermal" and spec.car.thermal is not None:
                from dataclasses import replace as _replace

                iso = solve_braking_ocp(_replace(spec.car, thermal=None), fmap, spec.v0,
                                        spec.v_stop, case.T_K, settings=spec.ocp,
                                        brake_torque_initial=spec.brake_torque_initial)
                res = solve_braking_ocp(spec.car, fmap, spec.v0, spec.v_stop, case.T_K,
                                        settings=replace(spec.ocp, kappa_min=-1.0),
                                        brake_torque_initial=spec.brake_torque_initial,
                                        initial_guess=with_tread_heating(spec.car, iso,
                                                                         case.T_K))
                res = replace(res, solve_time_s=res.solve_time_s + iso.solve_time_s,
                              iterations=res.iterations + iso.iterations)
            elif start in ("locked", "abs"):
                guess = locked if start == "locked" else abs_sim
                if guess is None:
                    tried[start] = {"failed": "no simulation to start from"}
                    continue
                res = solve_braking_ocp(spec.car, fmap, spec.v0, spec.v_stop, case.T_K,
                                        settings=replace(spec.ocp, kappa_min=-1.0),
                                        brake_torque_initial=spec.brake_torque_initial,
                                        initial_guess=guess)
            else:
                res = solve_braking_ocp(spec.car, fmap, spec.v0, spec.v_stop, case.T_K,
                                        settings=spec.ocp,
                                        brake_torque_initial=spec.brake_torque_initial)
        except ConvergenceError as exc:
            tried[start] = {"failed": str(exc)}
            continue
        results[start] = res
        tried[start] = {"stopping_distance": res.stopping_distance,
                        "iterations": res.iterations, "solve_time_s": res.solve_time_s,
                        "setup_time_s": res.setup_time_s}
        if spec.ocp_stop_when_verified and verify is not None and verify(res):
            tried[start]["verified"] = True
    if not results:
        raise ConvergenceError(f"case {case.label}: the braking OCP did not converge from any "
                               f"start: {tried}")
    best = min(results, key=lambda k: results[k].stopping_distance)
    return results[best], best, tried


def with_tread_heating(car: QuarterCar, stop: OCPResult, T_ambient: float) -> OCPResult:
    """``stop`` with its tread temperature integrated along it: ``C T' = eta Fx (omega R -
    v) - G (T - T_ambient)`` (:mod:`.quarter_car`) by the trapezoidal rule on its time grid,
    from ``T_ambient`` (the friction of the stop as it was, the temperature's effect on it
    left out: a start for the thermal OCP, not a solution of it)."""

    th = car.thermal
    if th is None:
        return stop
    power = car.Fz * stop.mu * (stop.omega * car.radius - stop.v) * th.heat_fraction
    T = np.empty_like(stop.t)
    T[0] = T_ambient
    k = th.cooling / th.heat_capacity
    for i in range(stop.t.size - 1):
        h = stop.t[i + 1] - stop.t[i]
        rhs = 0.5 * (power[i] + power[i + 1]) / th.heat_capacity - k * (T[i] - T_ambient)
        T[i + 1] = T[i] + h * rhs / (1.0 + 0.5 * h * k)
    return replace(stop, T_tread=T)


def run_case(spec: StudySpec, case: Case, fmu_simulator: Any = None) -> CaseResult:
    """Run one case: force map, slip maps, OCP, ABS and locked-wheel simulations, and with
    ``fmu_simulator`` (from :func:`fmu_simulators`) the ABS through the FMU."""
    fmap, prov, label = case_force_map(spec, case)
    # the tire's rolling resistance moment on the wheel (brush source): f_r at half the
    # initial speed (the time mean of a uniform stop) and the case temperature; over a stop
    # it changes by some 15 % (docs/rolling.md), on a moment of ~2 % of the brake torque
    f_r, f_r_why = brush_rolling_resistance(prov, 0.5 * spec.v0, spec.car.Fz, case.T_K)
    spec = replace(spec, car=replace(spec.car, rolling_resistance=f_r))
    car = spec.car
    v_bound = np.geomspace(spec.v_stop, spec.v0, 25)
    sm_line = optimal_slip(fmap, v_bound, [car.Fz], [case.T_K], label=label)
    bound_T0 = point_mass_bound(sm_line, spec.v0, spec.v_stop, car.g)

    def bound_up_to(T_top: float) -> tuple[float, float, float]:
        """Point-mass bound, peak friction and the bound with the brake torque's ramp
        (:func:`ramp_bound`) with the tread anywhere in [T0, T_top]."""
        rise = min(T_top, float(fmap.axes["T_K"].max())) - case.T_K
        if rise <= 1e-9:
            sm_T = sm_line
        else:
            T_range = np.linspace(case.T_K, case.T_K + rise, math.ceil(rise / 0.5) + 1)
            sm_T = optimal_slip(fmap, v_bound, [car.Fz], T_range, label=label)
        return (point_mass_bound(sm_T, spec.v0, spec.v_stop, car.g), float(sm_T.mu_max.max()),
                ramp_bound(sm_T, car, spec.v0, spec.v_stop, spec.brake_torque_initial))

    # every stop keeps its tread between T0 and T0 + rise bound (heating >= 0, cooling
    # towards T0): the best friction over those temperatures bounds every strategy
    bound_any, mu_reach, ramp_any = bound_up_to(
        case.T_K + tread_temperature_rise_bound(car, spec.v0))
    sm = optimal_slip(fmap, np.asarray(spec.maps.slip_map_speeds), fmap.axes["Fz"],
                      fmap.axes["T_K"], label=label)
    sm0 = optimal_slip(fmap, [spec.v0], [car.Fz], [case.T_K], label=label)
    schedule = abs_slip_schedule(sm_line) if spec.abs_slip_from_map else None

    locked = simulate_braking(car, fmap, LockedWheel(car.brake_torque_rate_max,
                                                     spec.abs_params.control_period),
                              spec.v0, spec.v_stop, case.T_K, settings=spec.simulation,
                              brake_torque_initial=spec.brake_torque_initial)

    def abs_controller() -> RuleBasedABS:
        return RuleBasedABS(spec.abs_params, car.radius, car.brake_torque_rate_max,
                            slip_schedule=schedule)

    abs_sim = simulate_braking(car, fmap, abs_controller(), spec.v0, spec.v_stop, case.T_K,
                               settings=spec.simulation,
                               brake_torque_initial=spec.brake_torque_initial)
    abs_real = simulate_braking(car, fmap,
                                RealisticABS(spec.abs_params, car.radius,
                                             car.brake_torque_rate_max, car.mass,
                                             slip_schedule=schedule),
                                spec.v0, spec.v_stop, case.T_K, settings=spec.simulation,
                                brake_torque_initial=spec.brake_torque_initial)
    simulated = {"abs": abs_sim.stopping_distance,
                 "abs_realistic": abs_real.stopping_distance,
                 "locked": locked.stopping_distance}

    # the global optimum of the stop with a quasi-steady wheel over speed and tread
    # temperature, with the brake's build-up: a lower bound that knows how the tread heats
    # (the full slip range, as the locked and ABS starts have)
    thermal = thermal_ramp_bound(car, fmap, spec.v0, spec.v_stop, case.T_K,
                                 brake_torque_initial=spec.brake_torque_initial)

    def verified(res: OCPResult) -> bool:
        _, _, b = bound_up_to(float(np.max(res.T_tread)))
        return ocp_optimality(res.stopping_distance, max(b, thermal.distance),
                              simulated) == "verified"

    ocp, ocp_start, ocp_tried = solve_ocp_from_starts(spec, case, fmap, locked, abs_sim,
                                                      verify=verified)
    # the bounds of the temperatures the optimal stop's tread actually passes through: the
    # OCP cannot beat them (a check of the transcription), whatever heating does; the check
    # uses the tighter one, with the brake torque's ramp
    bound, _, ramp = bound_up_to(float(np.max(ocp.T_tread)))
    optimality = ocp_optimality(ocp.stopping_distance, max(ramp, thermal.distance), simulated)
    abs_fmu = None
    if fmu_simulator is not None:
        abs_fmu = fmu_simulator(car, abs_controller(), spec.v0, spec.v_stop, case.T_K,
                                brake_torque_initial=spec.brake_torque_initial)
    nan = math.nan
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
        "ocp_mean_slip": _mean_slip(ocp),
        "stop_time_ocp": ocp.stop_time, "stop_time_abs": abs_sim.stop_time,
        "stop_time_locked": locked.stop_time,
        "ocp_solve_time_s": ocp.solve_time_s, "ocp_iterations": ocp.iterations,
        "map_build_time_s": fmap.build_time_s,
        "rolling_resistance": f_r,
        **({"rolling_resistance_why": f_r_why} if f_r_why else {}),
        "T_tread_max_ocp_K": float(np.max(ocp.T_tread)),
        "stopping_distance_abs_fmu": nan if abs_fmu is None else abs_fmu.stopping_distance,
        "stop_time_abs_fmu": nan if abs_fmu is None else abs_fmu.stop_time,
        "point_mass_bound_T0": bound_T0,
        "point_mass_bound_reachable": bound_any,
        "mu_max_reachable": mu_reach,
        "T_tread_rise_bound_K": tread_temperature_rise_bound(car, spec.v0),
        "T_tread_max_abs_K": float(np.max(abs_sim.T_tread)),
        "T_tread_max_locked_K": float(np.max(locked.T_tread)),
        "T_tread_max_abs_fmu_K": nan if abs_fmu is None else float(np.max(abs_fmu.T_tread)),
        "abs_mean_slip": _mean_slip(abs_sim),
        "abs_fmu_mean_slip": nan if abs_fmu is None else _mean_slip(abs_fmu),
        "stopping_distance_abs_realistic": abs_real.stopping_distance,
        "stop_time_abs_realistic": abs_real.stop_time,
        "abs_realistic_cycle_hz": abs_cycle_frequency(abs_real),
        "abs_cycle_hz": abs_cycle_frequency(abs_sim),
        "T_tread_max_abs_realistic_K": float(np.max(abs_real.T_tread)),
        "ocp_optimality": optimality,
        "ramp_bound": ramp, "ramp_bound_reachable": ramp_any,
        **describe_thermal_bound(thermal),
        # no stop beats ramp_any (its tread may reach any temperature a stop can cause) nor
        # the thermal bound: the optimum is within this fraction of the best possible stop
        "ocp_bound_gap": ocp.stopping_distance / max(ramp_any, thermal.distance) - 1.0,
        "Fz_N": car.Fz, "radius_m": car.radius,
    }
    provenance = {"friction": prov, "friction_label": label, "ocp_status": ocp.status,
                  "ocp_start": ocp_start, "ocp_starts": ocp_tried,
                  "ocp_kappa_bound": ocp.kappa_bound,
                  "ocp_kappa_bound_active": ocp.kappa_bound_active,
                  "map_T_K": fmap.axes["T_K"].tolist(),
                  "abs_slip_schedule": None if schedule is None else
                  {"vx_m_per_s": list(schedule[0]), "slip": list(schedule[1])}}
    if abs_fmu is not None:
        provenance["abs_fmu"] = {"simulator": getattr(fmu_simulator, "label", ""),
                                 **getattr(abs_fmu, "fmu", {})}
    return CaseResult(case=case, summary=summary, ocp=ocp, abs_sim=abs_sim, locked=locked,
                      slip_map=sm, force_map=fmap, provenance=provenance, abs_fmu=abs_fmu,
                      abs_realistic=abs_real, slip_dp=thermal.dp.trajectory(car, fmap))


def fmu_simulators(spec: StudySpec, work_dir: str | Path,
                   simulator_factory: Any) -> dict[str, Any]:
    """One FMU simulator per case label, built once per (tire, grid) into ``work_dir``.

    ``simulator_factory`` is called as ``factory(tire, grid, work_dir, options)`` and returns a
    picklable simulator ``sim(car, controller, v0, v_stop, T_ambient, *,
    brake_torque_initial)`` whose result has the attributes of :class:`.simulation.SimResult`
    (``t``, ``x``, ``v``, ``omega``, ``brake_torque``, ``kappa``, ``mu``, ``T_tread``,
    ``phase``, ``stopping_distance``, ``stop_time``, ``dt``). The FMU's host side hands in
    :func:`fmu_src.host.cosim.braking_simulator`; this package never imports it.
    """
    from .friction import brush_inputs

    built: dict[tuple[str, str], Any] = {}
    out = {}
    for case in spec.cases:
        key = brush_inputs(spec.friction, case, Path(spec.base_dir))
        if key not in built:
            built[key] = simulator_factory(*key, Path(work_dir), dict(spec.fmu))
        out[case.label] = built[key]
    return out


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the platform has one)."""
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:                     # not on Linux
        return os.cpu_count() or 1


def run_study(spec: StudySpec, scheduler: str | None = None, progress=None,
              work_dir: str | Path | None = None,
              simulator_factory: Any = None, jobs: int = 1) -> list[CaseResult | CaseFailure]:
    """Run every case, locally or as Dask tasks on ``scheduler`` (an address).

    Locally the cases run in ``jobs`` processes at once (1: one after the other in this
    process; 0: as many as :func:`available_cores`, at most one per case). A case is
    independent of the others (its own force map, OCPs, simulations), so the results do not
    depend on ``jobs``. A case that fails is returned as a :class:`CaseFailure` (with
    ``progress``, reported at once) and the study goes on.

    ``simulator_factory`` builds the FMU simulators of a study with ``[study] fmu_abs``
    (:func:`fmu_simulators`; ``tirefric abs`` and the demo hand in
    :func:`fmu_src.host.cosim.braking_simulator`). ``work_dir`` receives what they build
    (with a scheduler it must be a folder the workers can read); None: a temporary folder,
    removed when the study ends.
    """
    if spec.fmu_abs and simulator_factory is None:
        raise InputError("the study asks for the ABS through the FMU but no FMU simulator was "
                         "handed to it: run it with `tirefric abs study`, or pass "
                         "simulator_factory=fmu_src.host.cosim.braking_simulator",
                         field="study.fmu_abs", value=spec.fmu_abs)
    if spec.fmu_abs and work_dir is None:
        import tempfile

        with tempfile.TemporaryDirectory(prefix="tirefric_study_") as tmp:
            return run_study(spec, scheduler, progress, tmp, simulator_factory, jobs)
    sims: dict[str, Any] = {}
    if spec.fmu_abs:
        if progress is not None:
            progress(f"FMU build into {work_dir}")
        sims = fmu_simulators(spec, work_dir, simulator_factory)
    if jobs < 0:
        raise InputError("must be >= 0 (0: all available cores)", field="jobs", value=jobs)
    n_jobs = min(jobs or available_cores(), len(spec.cases))
    if scheduler is None and n_jobs > 1:
        return _run_parallel(spec, sims, progress, n_jobs)
    if scheduler is None:
        out = []
        for case in spec.cases:
            if progress is not None:
                progress(f"case {case.label}")
            r = run_case_or_failure(spec, case, sims.get(case.label))
            if isinstance(r, CaseFailure) and progress is not None:
                progress(f"case {case.label} FAILED: {r.error}")
            out.append(r)
        return out
    from dask.distributed import Client

    with Client(scheduler) as client:
        futures = [client.submit(run_case_or_failure, spec, case, sims.get(case.label),
                                 pure=False)
                   for case in spec.cases]
        return client.gather(futures)


def _run_parallel(spec: StudySpec, sims: dict[str, Any], progress, n_jobs: int
                  ) -> list[CaseResult | CaseFailure]:
    """The cases in ``n_jobs`` worker processes (spawned: a fresh interpreter each, nothing
    of this process' solver or thread state is inherited); results in the cases' order."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    if progress is not None:
        progress(f"{len(spec.cases)} case(s) in {n_jobs} processes")
    with ProcessPoolExecutor(max_workers=n_jobs,
                             mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {pool.submit(run_case_or_failure, spec, case, sims.get(case.label)): i
                   for i, case in enumerate(spec.cases)}
        out: list[Any] = [None] * len(spec.cases)
        for fut in as_completed(futures):
            i = futures[fut]
            case = spec.cases[i]
            try:
                r = fut.result()
            except Exception as exc:  # the worker itself died: still one case only
                r = CaseFailure(case=case, error=f"{type(exc).__name__}: {exc}")
            out[i] = r
            if progress is not None:
                progress(f"case {case.label} FAILED: {r.error}" if isinstance(r, CaseFailure)
                         else f"case {case.label} done")
    return out


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


def write_results(spec: StudySpec, results: list[CaseResult | CaseFailure],
                  out_dir: str | Path, *, plots: bool = True,
                  spec_path: str | Path | None = None) -> dict[str, Any]:
    """Write ``results.csv``, ``results.json``, trajectories, slip maps and plots to ``out_dir``.

    Failed cases (:class:`CaseFailure`) are listed in ``results.json`` (``failed``) and as
    comment lines of ``results.csv``; the other cases are written as usual. Returns the JSON
    document.
    """
    failed = [r for r in results if isinstance(r, CaseFailure)]
    results = [r for r in results if not isinstance(r, CaseFailure)]
    out = Path(out_dir)
    (out / "trajectories").mkdir(parents=True, exist_ok=True)
    (out / "slip_maps").mkdir(parents=True, exist_ok=True)
    rows = [r.summary for r in results]
    with open(out / "results.csv", "w", newline="") as fh:
        fh.write(f"# braking study {spec.name}: v0 = {spec.v0:g} m/s, v_stop = "
                 f"{spec.v_stop:g} m/s; distances [m] from v0 to v_stop, slips [1] "
                 "(negative in braking), times [s], temperatures T_C [Celsius]\n")
        for f in failed:
            fh.write(f"# case {f.case.label} FAILED: {f.error}\n")
        w = csv.writer(fh)
        w.writerow(RESULT_KEYS)
        for row in rows:
            w.writerow([f"{row[k]:.8g}" if isinstance(row[k], float) else row[k]
                        for k in RESULT_KEYS])
    for r in results:
        with open(out / "trajectories" / f"{r.case.label}.csv", "w", newline="") as fh:
            fh.write("# strategy: ocp (optimal control, interval boundaries), abs (rule-based), "
                     "locked (no ABS), abs_fmu (rule-based ABS through the FMU), "
                     "abs_realistic (estimated speed, valve pulses, hydraulic delay)\n")
            w = csv.writer(fh)
            w.writerow(["strategy", "t [s]", "x [m]", "v [m/s]", "omega [rad/s]",
                        "brake_torque [N m]", "kappa [1]", "mu [1]", "T_tread [K]", "phase"])
            stride = max(1, round(0.001 / r.abs_sim.dt))      # 1 ms in the simulations
            runs = [("ocp", r.ocp, 1), ("abs", r.abs_sim, stride),
                    ("locked", r.locked, stride)]
            if r.abs_realistic is not None:
                runs.append(("abs_realistic", r.abs_realistic, stride))
            if r.abs_fmu is not None:
                runs.append(("abs_fmu", r.abs_fmu, max(1, round(0.001 / r.abs_fmu.dt))))
            for name, res, s in runs:
                for row in _trajectory_rows(name, res, s):
                    w.writerow([row[0], *(f"{x:.8g}" for x in row[1:9]), row[9]])
        r.slip_map.to_csv(out / "slip_maps" / f"{r.case.label}.csv")
        r.slip_map.to_json(out / "slip_maps" / f"{r.case.label}.json")
    doc = {
        "study": spec.name,
        "spec": None if spec_path is None else str(spec_path),
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "units": {"stopping_distance_*": "m", "point_mass_bound*": "m", "ramp_bound*": "m",
                  "thermal_bound": "m", "thermal_bound_error": "m", "slip_dp_distance": "m",
                  "thermal_bound_split_s": "s", "slip_dp_coast_ratio": "1",
                  "ocp_bound_gap": "1", "optimal_slip": "1",
                  "T_C": "Celsius", "stop_time_*": "s", "mu_*": "1", "T_tread_*": "K",
                  "*_mean_slip": "1"},
        "v0_m_per_s": spec.v0, "v_stop_m_per_s": spec.v_stop,
        "vehicle": jsonable(asdict(spec.car)),
        "abs": dict(asdict(spec.abs_params),
                    **({"slip_threshold": "slip_map"} if spec.abs_slip_from_map else {})),
        "fmu_abs": spec.fmu_abs, "fmu": spec.fmu,
        "ocp": dict(asdict(spec.ocp), starts=list(spec.ocp_starts),
                    stop_when_verified=spec.ocp_stop_when_verified),
        "simulation": asdict(spec.simulation), "map": asdict(spec.maps),
        "friction": spec.friction,
        "cases": [dict(r.summary, provenance=jsonable(r.provenance),
                       ocp_trajectory={"t": r.ocp.t.tolist(), "kappa": r.ocp.kappa.tolist(),
                                       "v": r.ocp.v.tolist()})
                  for r in results],
        "failed": [{"case": f.case.label, "error": f.error} for f in failed],
    }
    with open(out / "results.json", "w") as fh:
        json.dump(jsonable(doc), fh, indent=2)
    if plots:
        from . import plots as plotting

        (out / "plots").mkdir(exist_ok=True)
        for r in results:
            plotting.plot_time_histories(r, out / "plots" / f"{r.case.label}_time.png")
            plotting.plot_mu_slip(r, out / "plots" / f"{r.case.label}_mu_slip.png")
        if results:
            plotting.plot_distances(results, out / "plots" / "distances.png")
    return doc


def jsonable(obj: Any) -> Any:
    """``obj`` with numpy scalars and arrays as plain numbers and lists, and non-finite
    floats as None (JSON has no NaN): for the results documents of the studies."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj
