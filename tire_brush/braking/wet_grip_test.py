"""The wet-grip braking test of UN Regulation No. 117 Annex 5 / ISO 23671 on the brush tire.

Runs the test the spec (``models/studies/wet_grip.toml``) describes, for a candidate tire and
the reference tire (SRTT), on the wet reference road and, for comparison, on the same road
dry:

* vehicle method: a quarter car braked by the rule-based ABS (:mod:`.abs_control`, release
  slip per speed from the slip map, :func:`.study.abs_slip_schedule`) from ``v_start``; the
  braking force coefficient is BFC = (v1^2 - v2^2) / (2 g d), d the distance from v1 to v2
  (:func:`tire_brush.wet_grip.braking_force_coefficient`);
* trailer method: the peak Fx/Fz of the steady brush at ``trailer_speed`` and 75 % of the
  tire's load capacity (:func:`tire_brush.wet_friction.peak_fx_over_fz`);
* wet grip index G = 1.25 BFC_candidate / BFC_reference, both corrected to 20 C, and the EU
  label class (:mod:`tire_brush.wet_grip`).

The friction is the steady brush tire on the wet branch of the road's grid at the test's
water depth and each speed's footprint time, with Horne's hydroplaning lift
(:mod:`tire_brush.wet_friction`); the car brakes on its tabulated force map (:mod:`.force_map`,
the same spline the other braking studies use).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import InputError

from .abs_control import ABSParams, RuleBasedABS
from .force_map import ForceMap, default_axes
from .quarter_car import QuarterCar, load_quarter_car
from .simulation import SimResult, SimSettings, simulate_braking
from .slip_map import optimal_slip
from .study import abs_slip_schedule

#: The reference tire's windows of UN R117 Annex 5, temperature-corrected to 20 C: the
#: trailer method's peak braking force coefficient 0.65-0.90 (R117 Annex 5, 04 series);
#: the vehicle method's BFC 0.57-0.79 as quoted in models/studies/wet_grip.toml.
REFERENCE_WINDOWS: dict[str, tuple[float, float]] = {"bfc": (0.57, 0.79), "peak": (0.65, 0.90)}


@dataclass(frozen=True)
class TireEntry:
    """Test data of one tire that its brush parameters do not hold.

    Attributes
    ----------
    tread_depth : float
        Groove depth [m] (hydroplaning).
    load_capacity : float
        Load capacity of its load index [N] (the trailer method's test load).
    """

    tread_depth: float
    load_capacity: float


@dataclass(frozen=True)
class WetGripSpec:
    """The test (``models/studies/wet_grip.toml``); speeds [m/s], lengths [m], T [K]."""

    v_start: float
    v1: float
    v2: float
    trailer_speed: float
    trailer_load_share: float
    water_depth: float
    T_K: float
    grid: str
    texture_depth: float
    drainage_radius: float | None
    car: QuarterCar
    reference_tire: str
    tires: dict[str, TireEntry] = field(default_factory=dict)
    n_kappa: int = 41
    n_v: int = 7
    simulation: SimSettings = field(default_factory=SimSettings)
    source: str = ""

    def tire_entry(self, tire: str) -> TireEntry:
        """The [tires] entry of ``tire`` (its name, or a file's stem), else the default."""
        return self.tires.get(Path(tire).stem, self.tires["default"])


def load_wet_grip_spec(name_or_path: str | Path = "wet_grip") -> WetGripSpec:
    """Read the test spec (a TOML file or a shipped study name); errors name the field."""
    from tirefric.config import Table
    from tirefric.paths import resolve_model_file

    path = resolve_model_file(name_or_path, "studies")
    root = Table.load(path)
    root.raw("provenance", "")
    t = root.table("test")
    speeds = {k: t.quantity(k, "velocity", positive=True)
              for k in ("v_start", "v1", "v2", "trailer_speed")}
    if not speeds["v_start"] >= speeds["v1"] > speeds["v2"]:
        raise t.error("v1", "need v_start >= v1 > v2", (speeds["v_start"], speeds["v1"],
                                                         speeds["v2"]))
    share = t.quantity("trailer_load_share", "dimensionless", minimum=0.0, maximum=1.0)
    depth = t.quantity("water_depth", "length", nonnegative=True)
    T_K = t.quantity("temperature", "temperature", positive=True)
    t.check_unknown()
    r = root.table("road")
    grid = r.string("grid")
    texture = r.quantity("texture_depth", "length", nonnegative=True)
    drain = r.quantity("drainage_radius", "length", None, positive=True) if r.has(
        "drainage_radius") else None
    r.check_unknown()
    v = root.table("vehicle")
    vfile = v.string("file")
    vpath = path.parent / vfile if (path.parent / vfile).is_file() else Path(vfile)
    car = load_quarter_car(vpath)
    v.check_unknown()
    ref = root.table("reference")
    reference = ref.string("tire")
    ref.check_unknown()
    tt = root.table("tires")
    tires = {}
    for name in tt.data:
        e = tt.table(name)
        tires[name] = TireEntry(e.quantity("tread_depth", "length", nonnegative=True),
                                e.quantity("load_capacity", "mass", positive=True) * car.g)
        e.check_unknown()
    if "default" not in tires:
        raise tt.error("default", "a [tires.default] entry is required", None)
    m = root.table("map", required=False)
    n_kappa = m.integer("n_kappa", 41, minimum=5) if m else 41
    n_v = m.integer("n_v", 7, minimum=2) if m else 7
    if m:
        m.check_unknown()
    s = root.table("simulation", required=False)
    sim = SimSettings(dt=s.quantity("dt", "time", positive=True)) if s else SimSettings()
    if s:
        s.check_unknown()
    root.check_unknown()
    return WetGripSpec(speeds["v_start"], speeds["v1"], speeds["v2"], speeds["trailer_speed"],
                       share, depth, T_K, grid, texture, drain, car, reference, tires,
                       n_kappa, n_v, sim, str(path))


def _grids(name: str) -> tuple[Any, Any]:
    from lookup.grid import load_grid
    from lookup.grid.wet import load_wet

    return load_grid(name), load_wet(name)


def friction_source(spec: WetGripSpec, tire: str, water_depth: float, grids=None, *,
                    hydroplaning: bool = True, partial_lift: bool = False):
    """:class:`~tire_brush.wet_friction.WetTireFriction` of ``tire`` on the test road
    (``partial_lift``: the study option of :class:`~tire_brush.wet_friction.WetTireFriction`)."""
    from tire_brush.params import load_tire
    from tire_brush.wet_friction import WetRoad, WetTireFriction

    params = load_tire(tire)
    dry, wet = grids or _grids(spec.grid)
    road = WetRoad(water_depth, spec.texture_depth, spec.tire_entry(tire).tread_depth,
                   spec.drainage_radius)
    return WetTireFriction(params, dry, wet, road, hydroplaning=hydroplaning,
                           partial_lift=partial_lift)


@dataclass
class BrakingRun:
    """One ABS stop and its BFC."""

    bfc: float
    distance_v1_v2: float
    sim: SimResult
    force_map: ForceMap
    car: QuarterCar


def braking_run(spec: WetGripSpec, source, T_K: float, label: str = "",
                point_evaluation: bool = False) -> BrakingRun:
    """ABS stop from ``v_start`` to ``v2`` on the force map of ``source``; BFC over v1 -> v2.

    ``point_evaluation``: the quarter car reads the map through
    :meth:`~tire_brush.braking.force_map.ForceMap.point_evaluator` (the same spline, read by
    the compiled tire core, equal to rounding, cheaper per step; the compound screen uses
    it)."""
    from tire_brush.wet_grip import braking_force_coefficient

    car = dataclasses.replace(spec.car, radius=source.params.R_e, thermal=None)
    axes = default_axes(spec.v_start, spec.v2, car.Fz, T_K, n_kappa=spec.n_kappa,
                        n_v=spec.n_v)
    fmap = ForceMap.build(source, **axes, label=label)
    v_line = np.geomspace(spec.v2, spec.v_start, 25)
    schedule = abs_slip_schedule(optimal_slip(fmap, v_line, [car.Fz], [T_K], label=label))
    ctrl = RuleBasedABS(ABSParams(), car.radius, car.brake_torque_rate_max,
                        slip_schedule=schedule)
    sim = simulate_braking(car, fmap.point_evaluator() if point_evaluation else fmap, ctrl,
                           spec.v_start, spec.v2, T_K, settings=spec.simulation)
    d = bfc_distance(sim, spec.v1)
    return BrakingRun(braking_force_coefficient(spec.v1, spec.v2, d), d, sim, fmap, car)


def bfc_distance(sim: SimResult, v1: float) -> float:
    """Distance [m] from the moment the car passes ``v1`` to the end of the run (at v2).

    The vehicle speed falls monotonically in a braking run (the tire force never drives), so
    the passing point is interpolated linearly in v between the recorded steps."""
    v, x = sim.v, sim.x
    if not v[0] >= v1:
        raise InputError("the run starts below v1", field="v1", value=v1)
    i = int(np.flatnonzero(v < v1)[0])
    s = (v[i - 1] - v1) / (v[i - 1] - v[i])
    return float(sim.stopping_distance - (x[i - 1] + s * (x[i] - x[i - 1])))


def tire_result(spec: WetGripSpec, tire: str, T_K: float, water_depth: float, grids,
                with_dry: bool = True, partial_lift: bool = False,
                point_evaluation: bool = False) -> tuple[dict[str, Any], dict[str, Any]]:
    """BFC (vehicle method) and peak Fx/Fz (trailer method) of one tire, wet and dry
    (``partial_lift``: :func:`friction_source`'s study option; ``point_evaluation``:
    :func:`braking_run`)."""
    from tire_brush.wet_friction import peak_fx_over_fz

    entry = spec.tire_entry(tire)
    out: dict[str, Any] = {"tire": tire}
    runs = {}
    for name, depth in (("wet", water_depth), ("dry", 0.0)):
        if name == "dry" and not with_dry:
            break
        src = friction_source(spec, tire, depth, grids, partial_lift=partial_lift)
        run = braking_run(spec, src, T_K, label=f"{tire} {name}",
                          point_evaluation=point_evaluation)
        Fz_trailer = spec.trailer_load_share * entry.load_capacity
        peak, kpk = peak_fx_over_fz(src, spec.trailer_speed, Fz_trailer, T_K)
        out[f"bfc_{name}"] = run.bfc
        out[f"distance_v1_v2_{name}_m"] = run.distance_v1_v2
        out[f"peak_{name}"] = peak
        out[f"peak_slip_{name}"] = kpk
        out[f"hydroplaning_share_v1_{name}"] = float(src.lifted_share(spec.v1))
        runs[name] = (run, src)
    out["trailer_load_N"] = spec.trailer_load_share * entry.load_capacity
    out["car_load_N"] = runs["wet"][0].car.Fz
    out["tread_depth_m"] = entry.tread_depth
    return out, runs


def run_wet_grip(spec: WetGripSpec, tire: str = "passenger", T_C: float | None = None,
                 water_depth: float | None = None, *, partial_lift: bool = False
                 ) -> tuple[dict[str, Any], dict[str, Any]]:
    """The test for ``tire`` against the spec's reference tire (module docstring);
    ``partial_lift``: :func:`friction_source`'s study option, for both tires.

    Returns the results document (JSON-able) and the runs (for plots)."""
    from tire_brush.params import load_tire
    from tire_brush.wet_grip import (
        TEMPERATURE_COEFFICIENT,
        label_class,
        temperature_corrected,
        wet_grip_index,
    )

    T_K = spec.T_K if T_C is None else T_C + 273.15
    if not (math.isfinite(T_K) and T_K > 0):
        raise InputError("must be a finite temperature above absolute zero [C]",
                         field="temperature", value=T_C)
    depth = spec.water_depth if water_depth is None else water_depth
    if not (isinstance(depth, int | float) and math.isfinite(depth) and depth >= 0):
        raise InputError("water film depth must be finite and >= 0 [m]", field="water_depth",
                         value=depth)
    if depth == 0:
        raise InputError("the wet-grip test needs water on the road (> 0 m)",
                         field="water_depth", value=depth)
    for name in (tire, spec.reference_tire):
        load_tire(name)  # an unknown tire fails here, naming the field
    grids = _grids(spec.grid)
    wet_axis = grids[1].axes["water_depth"]
    T_ax = grids[0].axes["T"]
    if not T_ax[0] <= T_K <= T_ax[-1]:
        raise InputError(f"outside the grid's temperature axis ({T_ax[0] - 273.15:g} ... "
                         f"{T_ax[-1] - 273.15:g} C)", field="temperature", value=T_K - 273.15)
    T_C_ = T_K - 273.15
    cand, cand_runs = tire_result(spec, tire, T_K, depth, grids, partial_lift=partial_lift)
    if Path(tire).stem == Path(spec.reference_tire).stem:
        ref, ref_runs = cand, cand_runs
    else:
        ref, ref_runs = tire_result(spec, spec.reference_tire, T_K, depth, grids,
                                      partial_lift=partial_lift)
    G = wet_grip_index(cand["bfc_wet"], ref["bfc_wet"], T_C_, T_C_)
    notes = ([] if wet_axis[0] <= depth <= wet_axis[-1] and depth in wet_axis else
             [f"water depth {depth:g} m is not a node of the grid's wet branch "
              f"{wet_axis.tolist()}: friction interpolated linearly in depth, clamped "
              "above the last node"])
    in_windows = {}
    for key, name, value in (("bfc", "braking force coefficient (vehicle method)",
                              ref["bfc_wet"]), ("peak", "peak braking force coefficient "
                                                        "(trailer method)", ref["peak_wet"])):
        lo, hi = REFERENCE_WINDOWS[key]
        corrected = temperature_corrected(value, T_C_)
        in_windows[key] = bool(lo <= corrected <= hi)
        if not in_windows[key]:
            notes.append(f"the reference tire {spec.reference_tire!r} leaves the "
                         f"regulation's window of the {name}: {corrected:.3f} at 20 C "
                         f"(measured {value:.3f} at {T_C_:g} C) outside {lo:g} ... {hi:g}; "
                         "the test is not valid there (UN R117 Annex 5)")
    G_trailer = wet_grip_index(cand["peak_wet"], ref["peak_wet"], T_C_, T_C_)
    doc = {
        "test": "UN R117 Annex 5 / ISO 23671 wet grip (vehicle and trailer methods)",
        "road_grid": spec.grid, "water_depth_m": depth, "T_C": T_C_,
        "v1_m_per_s": spec.v1, "v2_m_per_s": spec.v2, "v_start_m_per_s": spec.v_start,
        "trailer_speed_m_per_s": spec.trailer_speed,
        "candidate": cand, "reference": ref, "reference_tire": spec.reference_tire,
        "bfc_candidate_20C": temperature_corrected(cand["bfc_wet"], T_C_),
        "bfc_reference_20C": temperature_corrected(ref["bfc_wet"], T_C_),
        "temperature_coefficient_per_K": TEMPERATURE_COEFFICIENT,
        "G": G, "G_trailer": G_trailer, "label_class": label_class(G),
        "reference_windows": {k: list(v) for k, v in REFERENCE_WINDOWS.items()},
        "reference_in_windows": in_windows,
        "notes": notes,
        "spec": spec.source,
    }
    return doc, {"candidate": cand_runs, "reference": ref_runs}


def plot_wet_grip(doc: dict[str, Any], runs: dict[str, Any], path: str | Path,
                  T_K: float) -> None:
    """mu_dry and mu_wet (peak Fx/Fz) against speed; deceleration and distance against time,
    dry and wet (candidate tire)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from tire_brush.wet_friction import peak_fx_over_fz

    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    cand = runs["candidate"]
    v = np.linspace(5.0, 30.0, 11)
    for name, style in (("dry", "-"), ("wet", "--")):
        run, src = cand[name]
        mu = [peak_fx_over_fz(src, float(x), run.car.Fz, T_K, n_scan=61)[0] for x in v]
        ax[0].plot(v * 3.6, mu, style, label=f"peak Fx/Fz, {name}")
        ax[0].plot(v * 3.6, [-float(run.force_map(-1.0, x, run.car.Fz, T_K)) for x in v],
                   style, alpha=0.5, label=f"locked, {name}")
        sim = run.sim
        dec = -np.gradient(sim.v, sim.t) / 9.80665
        ax[1].plot(sim.t, dec, style, lw=0.8,
                   label=f"{name}: BFC {doc['candidate']['bfc_' + name]:.3f}")
        ax[2].plot(sim.t, sim.x, style, label=name)
    ax[0].set_xlabel("speed [km/h]")
    ax[0].set_ylabel("|Fx/Fz| [1]")
    ax[0].set_title(f"{doc['candidate']['tire']}: dry and wet "
                    f"({doc['water_depth_m'] * 1e3:g} mm water)")
    ax[1].set_xlabel("time [s]")
    ax[1].set_ylabel("deceleration [g]")
    ax[1].set_title(f"ABS stop {doc['v_start_m_per_s'] * 3.6:g} -> "
                    f"{doc['v2_m_per_s'] * 3.6:g} km/h")
    ax[2].set_xlabel("time [s]")
    ax[2].set_ylabel("distance [m]")
    ax[2].set_title(f"G = {doc['G']:.2f} (class {doc['label_class']})")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
