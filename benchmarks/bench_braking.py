"""Benchmark of the braking studies: force-map build time and OCP solve time.

Targets: OCP solve <= 5 s for 200 collocation intervals. Run:

    python benchmarks/bench_braking.py [--repeat 5] [--json] [--study abs_default]
        [--variants compiled,interpreted] [--only-study]

Reports medians over the repeats: the B-spline force-map build (tabulation of an analytic
source + scipy coefficient fit + CasADi function) at three sizes, the OCP (IPOPT wall time and
NLP set-up) at 200 intervals for two road curves, one rule-based-ABS simulation, and per case
of a study (``--study``, default the brush-tire study ``abs_default``; ``--study none`` skips
it) the lower bound that follows the tread's heating (dynamic programming,
``thermal_dp.thermal_ramp_bound``) and the OCP from each of the study's starts on that
case's force map (median solve and
set-up time, iterations, distance; a start that fails is counted and named), with the NLP's
functions compiled to C and interpreted, and per case the median over the starts with its
ratio to the 5 s target and of compiled to interpreted.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time

import numpy as np

from tire_brush.braking import (
    ABSParams,
    ForceMap,
    OCPSettings,
    QuarterCar,
    RuleBasedABS,
    default_axes,
    simulate_braking,
    solve_braking_ocp,
)
from tire_brush.braking.reference import burckhardt_road, magic_formula_road

V0, V_STOP, T_AMB = 100 / 3.6, 1.0, 293.15
#: Target of the OCP solve time at 200 intervals [s].
TARGET_S = 5.0
CAR = QuarterCar(mass=450.0, wheel_inertia=1.2, radius=0.31, brake_torque_max=3000.0,
                 brake_torque_rate_max=2e4)


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def bench_maps(repeat: int) -> list[dict]:
    curve = burckhardt_road("asphalt_dry", c4=0.02)

    def source(k, v, f, t):           # depends on every axis, like a brush map would
        return curve(k, v) * (1.0 + 1e-5 * (f - 4000.0)) * (1.0 - 1e-3 * (t - 293.0))

    rows = []
    for label, n_k, n_v, n_f, n_t in (("61x9 (one load, one T)", 61, 9, 1, 1),
                                       ("61x9x3x5", 61, 9, 3, 5),
                                       ("101x17x5x9 (~7.7e4 nodes)", 101, 17, 5, 9)):
        ax = default_axes(V0, V_STOP, CAR.Fz, T_AMB, n_kappa=n_k, n_v=n_v)
        ax["Fz"] = CAR.Fz * np.linspace(0.5, 1.5, n_f) if n_f > 1 else ax["Fz"]
        ax["T_K"] = T_AMB + np.linspace(-20, 60, n_t) if n_t > 1 else ax["T_K"]

        def build(ax=ax):
            fm = ForceMap.build(source, **ax)
            fm.casadi_function()
            return fm

        build()  # warm-up (imports)
        t, fm = median_time(build, repeat)
        rows.append({"map": label, "nodes": fm.n_nodes, "build_s_median": t})
    return rows


def bench_ocp(repeat: int) -> list[dict]:
    rows = []
    for curve in (burckhardt_road("asphalt_dry"), magic_formula_road("asphalt_wet")):
        fm = ForceMap.build(curve, **default_axes(V0, V_STOP, CAR.Fz, T_AMB))
        solves, setups, iters, dist = [], [], [], []
        for _ in range(repeat):
            r = solve_braking_ocp(CAR, fm, V0, V_STOP, T_AMB, settings=OCPSettings(intervals=200))
            solves.append(r.solve_time_s)
            setups.append(r.setup_time_s)
            iters.append(r.iterations)
            dist.append(r.stopping_distance)
        rows.append({"curve": f"{type(curve).__name__} {curve.name}", "intervals": 200,
                     "solve_s_median": statistics.median(solves),
                     "setup_s_median": statistics.median(setups),
                     "iterations": int(statistics.median(iters)),
                     "stopping_distance_m": dist[-1]})
    return rows


def bench_abs(repeat: int) -> dict:
    fm = ForceMap.build(burckhardt_road("asphalt_dry"), **default_axes(V0, V_STOP, CAR.Fz, T_AMB))
    ctrl = RuleBasedABS(ABSParams(), CAR.radius, CAR.brake_torque_rate_max)
    t, r = median_time(lambda: simulate_braking(CAR, fm, ctrl, V0, V_STOP, T_AMB), repeat)
    return {"abs_simulation_s_median": t, "steps": r.t.size - 1, "dt_s": r.dt,
            "rejected_steps": r.n_rejected}


def bench_study_ocp(study: str, repeat: int, variants: tuple[str, ...] = ("compiled",),
                    cases: tuple[str, ...] = ()) -> tuple[list[dict], list[dict]]:
    """The study's OCPs per case and start (the brush-map OCPs of ``abs_default``).

    ``variants``: ``compiled`` (``[ocp] jit = true``: the NLP's functions as C code, built
    once per case and mesh and cached on disk) and/or ``interpreted`` (CasADi's virtual
    machine). Returns the rows per case, start and variant, and per case and variant the
    median over its starts and repeats, with the ratio to the 5 s target and of the
    compiled to the interpreted median. ``cases``: labels to time (empty: all).
    """
    from dataclasses import replace

    from tire_brush.braking.abs_control import LockedWheel, RuleBasedABS
    from tire_brush.braking.slip_map import optimal_slip
    from tire_brush.braking.study import (
        abs_slip_schedule,
        case_force_map,
        load_study,
        solve_ocp_from_starts,
    )
    from tire_brush.braking.thermal_dp import thermal_ramp_bound
    from tirefric.errors import ConvergenceError

    spec0 = load_study(study)
    rows, per_case = [], []
    for case in spec0.cases:
        if cases and case.label not in cases:
            continue
        car = spec0.car
        t0 = time.perf_counter()
        fmap, _, _ = case_force_map(spec0, case)
        t_map = time.perf_counter() - t0
        sm = optimal_slip(fmap, np.geomspace(spec0.v_stop, spec0.v0, 25), [car.Fz], [case.T_K])
        sched = abs_slip_schedule(sm) if spec0.abs_slip_from_map else None
        locked = simulate_braking(car, fmap, LockedWheel(car.brake_torque_rate_max,
                                                         spec0.abs_params.control_period),
                                  spec0.v0, spec0.v_stop, case.T_K, settings=spec0.simulation)
        abs_sim = simulate_braking(car, fmap, RuleBasedABS(spec0.abs_params, car.radius,
                                                           car.brake_torque_rate_max,
                                                           slip_schedule=sched),
                                   spec0.v0, spec0.v_stop, case.T_K, settings=spec0.simulation)
        # the lower bound that follows the tread's heating (dynamic programming, two
        # resolutions), once per case
        t_bound, bound = median_time(lambda c=car, f=fmap, T=case.T_K: thermal_ramp_bound(
            c, f, spec0.v0, spec0.v_stop, T, brake_torque_initial=spec0.brake_torque_initial),
            repeat)
        medians = {}
        for variant in variants:
            spec = replace(spec0, ocp=replace(spec0.ocp, jit=variant == "compiled"))
            per_start: dict[str, dict] = {}
            for _ in range(repeat):
                try:
                    _, _, tried = solve_ocp_from_starts(spec, case, fmap, locked, abs_sim)
                except ConvergenceError as exc:
                    tried = getattr(exc, "tried", {})
                for start, info in tried.items():
                    if "skipped" in info:
                        continue
                    d = per_start.setdefault(start, {"solve": [], "setup": [], "iter": [],
                                                     "dist": [], "failed": 0})
                    if "failed" in info:
                        d["failed"] += 1
                        continue
                    d["solve"].append(info["solve_time_s"])
                    d["setup"].append(info.get("setup_time_s", float("nan")))
                    d["iter"].append(info["iterations"])
                    d["dist"].append(info["stopping_distance"])
            every = []
            for start, d in per_start.items():
                ok = bool(d["solve"])
                every += d["solve"]
                rows.append({"case": case.label, "start": start, "variant": variant,
                             "intervals": spec.ocp.intervals, "map_build_s": t_map,
                             "solve_s_median": statistics.median(d["solve"]) if ok else None,
                             "setup_s_max": max(d["setup"]) if ok else None,
                             "iterations": int(statistics.median(d["iter"])) if ok else None,
                             "stopping_distance_m": d["dist"][-1] if ok else None,
                             "failed": d["failed"]})
            medians[variant] = statistics.median(every) if every else None
        row = {"case": case.label, **{f"solve_s_median_{v}": m for v, m in medians.items()},
               "thermal_bound_s_median": t_bound, "thermal_bound_m": bound.distance}
        for v, m in medians.items():
            row[f"ratio_to_target_{v}"] = None if m is None else m / TARGET_S
        if medians.get("compiled") and medians.get("interpreted"):
            row["ratio_compiled_to_interpreted"] = medians["compiled"] / medians["interpreted"]
        per_case.append(row)
    return rows, per_case


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--json", action="store_true")
    p.add_argument("--study", default="abs_default",
                   help="study whose OCPs are timed per case and start ('none': skip)")
    p.add_argument("--variants", default="compiled,interpreted",
                   help="OCP function evaluation to time: compiled, interpreted or both")
    p.add_argument("--cases", default="",
                   help="comma-separated case labels of the study to time (default: all)")
    p.add_argument("--only-study", action="store_true",
                   help="time the study's OCPs only (no maps, analytic OCPs, ABS)")
    args = p.parse_args(argv)
    out: dict = {}
    if not args.only_study:
        out = {"maps": bench_maps(args.repeat), "ocp": bench_ocp(args.repeat),
               "abs": bench_abs(max(1, args.repeat // 2))}
    if args.study != "none":
        out["study_ocp"], out["study_ocp_cases"] = bench_study_ocp(
            args.study, args.repeat, tuple(args.variants.split(",")),
            tuple(c for c in args.cases.split(",") if c))
    if args.json:
        json.dump(out, sys.stdout, indent=2)
        print()
        return 0
    if "maps" in out:
        print("force map build (tabulate + scipy tensor B-spline + CasADi function), median:")
        for r in out["maps"]:
            print(f"  {r['map']:28s} {r['nodes']:7d} nodes  "
                  f"{1e3 * r['build_s_median']:8.1f} ms")
        print("OCP, 200 intervals, Legendre degree 3, IPOPT (target <= 5 s), median:")
        for r in out["ocp"]:
            print(f"  {r['curve']:32s} solve {r['solve_s_median']:.2f} s  set-up "
                  f"{r['setup_s_median']:.2f} s  {r['iterations']} iterations  "
                  f"d = {r['stopping_distance_m']:.2f} m")
        a = out["abs"]
        print(f"rule-based ABS simulation: {a['abs_simulation_s_median']:.2f} s for "
              f"{a['steps']} steps of at most {1e3 * a['dt_s']:.2f} ms "
              f"({a['rejected_steps']} rejected)")
    if "study_ocp" in out:
        print(f"study {args.study}: OCP per case, start and variant, {args.repeat} repeat(s), "
              f"median (target <= {TARGET_S:g} s; set-up: the largest, the first build and "
              "compilation included):")
        for r in out["study_ocp"]:
            head = f"  {r['case']:20s} {r['start']:13s} {r['variant']:11s}"
            if r["solve_s_median"] is None:
                print(f"{head} failed {r['failed']}x")
                continue
            print(f"{head} solve {r['solve_s_median']:6.2f} s  set-up {r['setup_s_max']:5.2f} s"
                  f"  {r['iterations']:4d} iterations  d = {r['stopping_distance_m']:.3f} m"
                  + (f"  ({r['failed']} failed)" if r["failed"] else ""))
        print("per case: median over starts and repeats, ratio to the target, compiled over "
              "interpreted:")
        for r in out["study_ocp_cases"]:
            parts = [f"{k.removeprefix('solve_s_median_')} {v:.2f} s" if v is not None
                     else f"{k.removeprefix('solve_s_median_')} all failed"
                     for k, v in r.items() if k.startswith("solve_s_median_")]
            parts += [f"{k.removeprefix('ratio_to_target_')}/target {v:.2f}"
                      for k, v in r.items() if k.startswith("ratio_to_target_") and v]
            if "ratio_compiled_to_interpreted" in r:
                parts.append(f"compiled/interpreted {r['ratio_compiled_to_interpreted']:.2f}")
            parts.append(f"thermal bound {r['thermal_bound_m']:.3f} m in "
                         f"{r['thermal_bound_s_median']:.2f} s")
            print(f"  {r['case']:20s} " + "  ".join(parts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
