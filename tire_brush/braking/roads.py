"""Braking on roads that change: split-mu and mu-jumps with the two-track car, on the force map
of the brush tire and through its FMU (``tirefric abs roads``).

A roads spec (TOML, e.g. ``models/studies/roads_default.toml``) names the four-wheel car
(:class:`.two_axle.TwoAxleCar`: load transfer, brake balance), the tire and grid, the
temperature, the roads and the brake controllers. Each road gives the left and the right
wheels a friction factor against the travelled distance (:class:`.road.MuProfile`): a number
(the whole stop), or a patch ``{from_m, to_m, factor}`` (a mu-jump from high to low and
back). Every road is braked with every controller (``abs``: the rule-based ABS on every
wheel; ``locked``: every wheel locked)

* on the steady brush tire's force map (:func:`.two_axle.simulate_two_track`), with the
  map's load axis over the loads the stop can reach, the tread at the case temperature
  (isothermal, as the two-track model is) and the tire's rolling resistance moment on the
  wheels (:func:`.friction.brush_rolling_resistance`);
* and, with ``fmu = true``, through four instances of the brush-tire FMU (the transient model;
  the top layer hands in the simulator factory, :func:`fmu_src.host.cosim.braking_simulator`,
  whose simulator has ``two_track``).

The results are the stopping distance, the stop time and the yaw moment the steering must
hold (peak and mean; :func:`.two_axle.yaw_moment`) per road, controller and model.
"""

from __future__ import annotations

import csv
import json
import sys
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.config import Table
from tirefric.errors import InputError, InputErrors

from .abs_control import ABSParams, LockedWheel, RuleBasedABS
from .force_map import ForceMap, default_axes
from .road import MuProfile
from .study import jsonable, read_stop_spec
from .two_axle import (
    WHEELS,
    TwoAxleCar,
    TwoTrackResult,
    simulate_two_track,
    wheel_load_split,
    wheel_rates,
)

#: Brake controllers a roads spec can name.
CONTROLLERS = ("abs", "locked")
#: Columns of the results table.
RESULT_KEYS = ("road", "controller", "model", "stopping_distance", "stop_time",
               "yaw_moment_peak_Nm", "yaw_moment_mean_Nm", "mean_deceleration")


@dataclass(frozen=True)
class RoadCase:
    """One road: the friction factor of the left and the right wheels against distance."""

    name: str
    left: MuProfile
    right: MuProfile


@dataclass(frozen=True)
class RoadsSpec:
    """A validated roads spec (module doc)."""

    name: str
    v0: float
    v_stop: float
    T_K: float
    car: TwoAxleCar
    tire: str
    grid: str
    roads: tuple[RoadCase, ...]
    controllers: tuple[str, ...]
    fmu: bool
    fmu_step: float
    abs_params: ABSParams
    n_kappa: int
    n_v: int
    n_loads: int
    base_dir: str
    source: str


def _profile(t: Table, key: str) -> MuProfile:
    """A side's friction factor: absent (1), a number (the whole stop) or a patch table."""
    raw = t.raw(key, None)
    if raw is None:
        return MuProfile.uniform()
    if isinstance(raw, dict):
        p = t.table(key)
        start = p.quantity("from_m", "length", positive=True)
        end = p.quantity("to_m", "length", positive=True)
        factor = p.quantity("factor", "dimensionless", positive=True)
        p.check_unknown()
        if not end > start:
            raise p.error("to_m", "must be beyond from_m", p.raw("to_m"))
        return MuProfile.patch(start, end, factor)
    return MuProfile.uniform(t.quantity(key, "dimensionless", positive=True))


def load_roads_spec(path: str | Path) -> RoadsSpec:
    """Read and validate a roads spec (file or shipped name under ``models/studies``).

    All problems found are reported together (:class:`~tirefric.errors.InputErrors`), each
    naming the file, the field and the value.
    """
    path, root, collect, st, name, v0, v_stop = read_stop_spec(path)
    errors = collect.errors
    T_K = collect(st.quantity, "temperature", "temperature", positive=True)
    fmu = bool(collect(st.boolean, "fmu", False))
    fmu_step = collect(st.quantity, "fmu_step", "time", 1e-3, positive=True)
    ctrl = st.raw("controllers", list(CONTROLLERS))
    if not (isinstance(ctrl, list) and ctrl and all(c in CONTROLLERS for c in ctrl)):
        errors.append(st.error("controllers", f"expected a list of {list(CONTROLLERS)}", ctrl))
        ctrl = []
    collect(st.check_unknown)
    if v0 is not None and v_stop is not None and not v0 > v_stop:
        errors.append(st.error("v_stop", "must be below study.v0", st.raw("v_stop")))

    c = root.table("car")
    kw = {k: collect(c.quantity, k, dim, positive=True) for k, dim in (
        ("mass", "mass"), ("wheelbase", "length"), ("cg_to_front", "length"),
        ("cg_height", "length"), ("wheel_inertia", "inertia"), ("radius", "length"),
        ("track", "length"))}
    kw["brake_balance"] = collect(c.quantity, "brake_balance", "dimensionless",
                                  minimum=0.0, maximum=1.0)
    kw["brake_torque_max"] = collect(c.quantity, "brake_torque_max_Nm", "dimensionless",
                                     positive=True)
    kw["brake_torque_rate_max"] = collect(c.quantity, "brake_torque_rate_max_Nm_per_s",
                                          "dimensionless", positive=True)
    collect(c.check_unknown)
    car = None
    if all(v is not None for v in kw.values()):
        car = collect(TwoAxleCar, **kw)

    fr = root.table("friction")
    tire = collect(fr.string, "tire", "passenger")
    grid = collect(fr.string, "grid", "default")
    collect(fr.check_unknown)

    mp = root.table("map", required=False) or Table({}, path, "map")
    n_kappa = collect(mp.integer, "n_kappa", 41, minimum=5)
    n_v = collect(mp.integer, "n_v", 7, minimum=2)
    n_loads = collect(mp.integer, "n_loads", 6, minimum=2)
    collect(mp.check_unknown)

    abs_params = ABSParams()
    if (t := root.table("abs", required=False)) is not None:
        akw = {k: collect(t.quantity, k, "dimensionless", positive=True)
               for k in ("slip_threshold", "decel_threshold", "accel_threshold",
                         "accel_threshold_high", "reapply_fraction") if t.has(k)}
        if t.has("control_period"):
            akw["control_period"] = collect(t.quantity, "control_period", "time",
                                            positive=True)
        collect(t.check_unknown)
        abs_params = collect(ABSParams, **{k: v for k, v in akw.items() if v is not None}) \
            or ABSParams()

    roads: list[RoadCase] = []
    raw_roads = root.raw("roads")
    if not (isinstance(raw_roads, list) and raw_roads and
            all(isinstance(r, dict) for r in raw_roads)):
        errors.append(root.error("roads", "expected one or more [[roads]] tables", raw_roads))
        raw_roads = []
    for i, raw in enumerate(raw_roads):
        t = Table(raw, path, f"roads[{i}]")
        rname = collect(t.string, "name")
        left = collect(_profile, t, "left")
        right = collect(_profile, t, "right")
        collect(t.check_unknown)
        if rname is not None and left is not None and right is not None:
            roads.append(RoadCase(rname, left, right))
    names = [r.name for r in roads]
    if len(set(names)) != len(names):
        errors.append(root.error("roads", "road names must differ", names))
    collect(root.check_unknown)
    if errors:
        raise InputErrors(errors)
    return RoadsSpec(name=name, v0=v0, v_stop=v_stop, T_K=T_K, car=car, tire=tire, grid=grid,
                     roads=tuple(roads), controllers=tuple(ctrl), fmu=fmu, fmu_step=fmu_step,
                     abs_params=abs_params, n_kappa=n_kappa, n_v=n_v, n_loads=n_loads,
                     base_dir=str(path.parent), source=str(path))


def load_axis(car: TwoAxleCar, n: int) -> np.ndarray:
    """Wheel loads [N] a stop can reach: from half the lightest (rear wheel at 1.5 g of
    braking) to 1.2 times the heaviest (front wheel at 1.5 g; the map clamps beyond)."""
    Fz = wheel_load_split(car, -1.5 * car.g)
    return np.linspace(0.5 * float(Fz.min()), 1.2 * float(Fz.max()), n)


def roads_force_map(spec: RoadsSpec) -> tuple[ForceMap, dict[str, Any], str]:
    """The brush tire's force map on the spec's grid at its temperature, with a load axis
    (:func:`load_axis`); the grid's own compound and road name the case."""
    from lookup.grid import load_grid

    from .friction import Case, brush_source

    meta = getattr(load_grid(spec.grid), "meta", {}) or {}
    case = Case(str(meta.get("surface_name", "")), str(meta.get("compound_name", "")),
                spec.T_K)
    src = brush_source({"tire": spec.tire, "grid": spec.grid}, case, Path(spec.base_dir))
    Fz_static = float(np.mean(wheel_load_split(spec.car, 0.0)))
    ax = default_axes(spec.v0, spec.v_stop, Fz_static, spec.T_K, n_kappa=spec.n_kappa,
                      n_v=spec.n_v)
    ax["Fz"] = load_axis(spec.car, spec.n_loads)
    fmap = ForceMap.build(src.fx_over_fz, **ax, label=src.label)
    return fmap, src.provenance, src.label


def _controllers(spec: RoadsSpec, car: TwoAxleCar, which: str) -> list[Any]:
    rates = wheel_rates(car)
    if which == "abs":
        return [RuleBasedABS(spec.abs_params, car.radius, r) for r in rates]
    return [LockedWheel(r, spec.abs_params.control_period) for r in rates]


def _row(road: str, controller: str, model: str, res: TwoTrackResult,
         v0: float, v_stop: float) -> dict[str, Any]:
    s = res.summary()
    return {"road": road, "controller": controller, "model": model, **s,
            "mean_deceleration": (v0 - v_stop) / res.stop_time}


def run_roads(spec: RoadsSpec, *, simulator_factory: Any = None, work_dir: str | Path = ".",
              progress: Callable[[str], None] | None = None
              ) -> tuple[dict[str, Any], dict[tuple[str, str, str], TwoTrackResult]]:
    """Brake every road with every controller on the map and (``spec.fmu``) through the FMU.

    ``simulator_factory(tire, grid, work_dir, options)`` builds the FMU and returns a
    simulator with ``two_track(car, controllers, v0, v_stop, T_ambient, road_left=,
    road_right=)``; a spec with ``fmu = true`` and no factory is refused.

    Returns the results document (rows of :data:`RESULT_KEYS`, the car, the roads and the
    provenance) and the runs by ``(road, controller, model)``.
    """
    from .friction import brush_rolling_resistance

    say = progress or (lambda _msg: None)
    if spec.fmu and simulator_factory is None:
        raise InputError("this command has no FMU simulator (run it as 'tirefric abs roads')",
                         source=spec.source, field="study.fmu", value=True)
    fmap, prov, label = roads_force_map(spec)
    say(f"force map: {fmap.n_nodes} nodes in {fmap.build_time_s:.1f} s ({label})")
    Fz_static = float(np.mean(wheel_load_split(spec.car, 0.0)))
    f_r, f_r_why = brush_rolling_resistance(prov, 0.5 * spec.v0, Fz_static, spec.T_K)
    car = replace(spec.car, rolling_resistance=f_r)
    fmap_T = fmap.fixed(T_K=spec.T_K)
    sim = None
    if spec.fmu:
        sim = simulator_factory(spec.tire, spec.grid, work_dir, {"step": spec.fmu_step})
        say(f"FMU: {getattr(sim, 'label', '')}")
    runs: dict[tuple[str, str, str], TwoTrackResult] = {}
    rows = []
    for road in spec.roads:
        for ctrl in spec.controllers:
            res = simulate_two_track(car, fmap_T, _controllers(spec, car, ctrl), spec.v0,
                                     spec.v_stop, spec.T_K, road_left=road.left,
                                     road_right=road.right)
            runs[(road.name, ctrl, "map")] = res
            rows.append(_row(road.name, ctrl, "map", res, spec.v0, spec.v_stop))
            if sim is not None:
                res = sim.two_track(car, _controllers(spec, car, ctrl), spec.v0, spec.v_stop,
                                    spec.T_K, road_left=road.left, road_right=road.right)
                runs[(road.name, ctrl, "fmu")] = res
                rows.append(_row(road.name, ctrl, "fmu", res, spec.v0, spec.v_stop))
            say(f"road {road.name}, {ctrl}: " + ", ".join(
                f"{r['model']} {r['stopping_distance']:.2f} m" for r in rows
                if r["road"] == road.name and r["controller"] == ctrl))
    doc = {
        "study": spec.name, "source": spec.source,
        "v0_m_per_s": spec.v0, "v_stop_m_per_s": spec.v_stop, "T_K": spec.T_K,
        "car": asdict(car), "rolling_resistance": f_r,
        **({"rolling_resistance_why": f_r_why} if f_r_why else {}),
        "roads": [{"name": r.name, "left": r.left.describe(), "right": r.right.describe()}
                  for r in spec.roads],
        "wheels": list(WHEELS), "friction": {"label": label, "provenance": prov},
        "fmu": None if sim is None else getattr(sim, "label", str(sim)),
        "units": {"stopping_distance": "m", "stop_time": "s", "yaw_moment_*": "N m",
                  "mean_deceleration": "m/s^2"},
        "results": rows,
    }
    return doc, runs


def write_roads(doc: dict[str, Any], runs: dict[tuple[str, str, str], TwoTrackResult],
                out_dir: str | Path, *, plots: bool = True) -> Path:
    """``results.csv``, ``results.json``, one trajectory CSV per run and (``plots``) one
    figure per road into ``out_dir``; returns the folder."""
    out = Path(out_dir)
    (out / "trajectories").mkdir(parents=True, exist_ok=True)
    with open(out / "results.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(RESULT_KEYS)
        for r in doc["results"]:
            w.writerow([r[k] for k in RESULT_KEYS])
    with open(out / "results.json", "w") as fh:
        json.dump(jsonable(doc), fh, indent=2)
    for (road, ctrl, model), res in runs.items():
        with open(out / "trajectories" / f"{road}_{ctrl}_{model}.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["t_s", "x_m", "v_m_per_s", "a_m_per_s2", "yaw_moment_Nm"]
                       + [f"{q}_{wh}" for q in ("kappa", "mu", "Fz_N", "road")
                          for wh in WHEELS])
            for i in range(res.t.size):
                w.writerow([res.t[i], res.x[i], res.v[i], res.a[i], res.yaw_moment[i],
                            *res.kappa[i], *res.mu[i], *res.Fz[i], *res.road[i]])
    if plots:
        from .plots import plot_road
        (out / "plots").mkdir(exist_ok=True)
        for road in doc["roads"]:
            sel = {k: v for k, v in runs.items() if k[0] == road["name"]}
            plot_road(road["name"], sel, out / "plots" / f"{road['name']}.png")
    return out


def print_roads(doc: dict[str, Any], file=sys.stdout) -> None:
    """The results table, one line per road, controller and model."""
    print(f"# roads {doc['study']}: {doc['v0_m_per_s']:g} -> {doc['v_stop_m_per_s']:g} m/s at "
          f"{doc['T_K'] - 273.15:g} C; f_r = {doc['rolling_resistance']:.4f}", file=file)
    print(f"# {'road':16s} {'controller':10s} {'model':5s} {'distance':>9s} {'time':>7s} "
          f"{'|Mz| peak':>10s} {'Mz mean':>9s}", file=file)
    for r in doc["results"]:
        print(f"  {r['road']:16s} {r['controller']:10s} {r['model']:5s} "
              f"{r['stopping_distance']:8.2f}m {r['stop_time']:6.2f}s "
              f"{r['yaw_moment_peak_Nm']:9.0f}Nm {r['yaw_moment_mean_Nm']:8.0f}Nm", file=file)
