"""Benchmarks of the friction grids: query speed and build throughput.

Run ``python benchmarks/bench_grid.py [--json] [--build-slices N] [--full-build]
[--wet [--wet-repeats N] [--wet-slices N] [--workers N]]``.

* query: median time of ``FrictionGrid.interpolate`` (mu_cold, mu_hot, dT_flash) for one
  batched call of 1e5 random points [us/point] and for one call of 100 points [us/call]
  (targets: <= 1 us/point, <= 20 us/call), on a grid of the default spec's shape; the same
  with the optional monotone cubic along log10 v (``v_interp="pchip"``);
* build: grid nodes (cold and hot) per second per core of the real engine on a subset of the
  default spec's slip-speed slices (serial, so that one core is measured), and the implied
  time of the full default grid on this machine's cores; ``--full-build`` builds the whole
  default grid with all cores into a temporary file and reports its wall time;
* wet (``--wet``): the shipped wet-grip grid ``models/grids/r117_wet.toml`` built through
  :func:`lookup.grid.build.build_grid` (the ``tirefric grid build`` path) with and without its
  ``[wet]`` table, ``--wet-repeats`` times each (alternating), on ``--workers`` processes:
  medians of the dry build's wall time, of the wet branch's (the ``wall_s`` the build stores
  in the file's wet metadata: engine setup, sealed spectra, the wet solves) and of the whole
  build with the branch, and the ratio wet branch / dry build (target <= 2). With one worker
  (the default) also the CPU times (``time.process_time``; wet branch = build with it minus
  build without it), which a loaded machine distorts far less than wall times. ``--wet-slices
  N`` keeps N of the spec's slip-speed slices (spread over the axis) for a quicker run.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import numpy as np
from timing import median_time

from lookup.grid.reader import VARIABLES, FrictionGrid


def default_shaped_grid() -> FrictionGrid:
    """A grid with the default spec's axes and smooth random content."""
    from lookup.grid.spec import load_spec

    spec = load_spec("default")
    rng = np.random.default_rng(1)
    shape = spec.shape
    variables = {n: 1.0 + 0.1 * rng.standard_normal(shape) for n in VARIABLES}
    return FrictionGrid(np.log10(spec.v), spec.T, np.log10(spec.p), variables,
                        {"s0_m": 2e-4, "D_m": 1e-3})


def bench_query() -> dict:
    g = default_shaped_grid()
    rng = np.random.default_rng(2)

    def points(n):
        return (10 ** rng.uniform(-6, np.log10(40), n), rng.uniform(253.15, 393.15, n),
                10 ** rng.uniform(np.log10(5e4), np.log10(2e6), n))

    v, T, p = points(100_000)
    t_batch = median_time(lambda: g.interpolate(v, T, p), repeats=7, number=5)
    v1, T1, p1 = points(100)
    t_100 = median_time(lambda: g.interpolate(v1, T1, p1), repeats=7, number=2000)
    t_1 = median_time(lambda: g.interpolate(0.5, 300.0, 2e5), repeats=7, number=2000)
    v1[:10] = 0.0  # standstill elements (floored at v_min)
    t_100_pchip = median_time(lambda: g.interpolate(v1, T1, p1, v_interp="pchip"), repeats=7,
                              number=2000)
    t_batch_pchip = median_time(lambda: g.interpolate(v, T, p, v_interp="pchip"), repeats=7,
                                number=5)
    t_100_clamp = median_time(lambda: g.interpolate(v1, T1 + 200.0, p1), repeats=7,
                               number=2000)
    return {"grid_shape": list(g.shape),
            "batched_1e5_us_per_point": t_batch / 1e5 * 1e6,
            "call_100_points_us": t_100 * 1e6,
            "call_1_point_us": t_1 * 1e6,
            "pchip_batched_1e5_us_per_point": t_batch_pchip / 1e5 * 1e6,
            "pchip_call_100_points_us": t_100_pchip * 1e6,
            "call_100_points_all_T_clamped_us": t_100_clamp * 1e6,
            "targets": {"batched_1e5_us_per_point": 1.0, "call_100_points_us": 20.0}}


def bench_build(n_slices: int, full: bool) -> dict:
    from lookup.grid.build import build_grid, make_model
    from lookup.grid.spec import load_spec

    spec = load_spec("default")
    idx = np.unique(np.round(np.linspace(0, spec.v.size - 1, n_slices)).astype(int))
    sub = spec.with_axes(v=spec.v[idx])
    model = make_model(sub)
    with tempfile.TemporaryDirectory() as d:
        _, rep = build_grid(sub, Path(d) / "sub.nc", workers=1, model=model, progress=False)
    cores = os.cpu_count() or 1
    pps = rep.points_per_s_per_core
    out = {"slices": int(idx.size), "points": int(idx.size * sub.shape[1] * sub.shape[2]),
           "serial_wall_s": rep.wall_s, "points_per_s_per_core": pps, "cores": cores,
           "default_grid_points": spec.n_points,
           "default_grid_estimate_s": spec.n_points / (pps * cores),
           "target_default_grid_s": 600.0}
    if full:
        with tempfile.TemporaryDirectory() as d:
            _, rep = build_grid(spec, Path(d) / "default.nc", progress=True)
        out["full_build"] = rep.as_dict()
    return out


def bench_wet(repeats: int, n_slices: int | None, workers: int) -> dict:
    import dataclasses
    import statistics
    import time

    from lookup.grid.build import build_grid
    from lookup.grid.spec import load_spec
    from lookup.grid.wet import load_wet

    spec = load_spec("r117_wet")
    if n_slices:
        idx = np.unique(np.round(np.linspace(0, spec.v.size - 1, n_slices)).astype(int))
        spec = spec.with_axes(v=spec.v[idx])
    dry_spec = dataclasses.replace(spec, wet=None)
    rec: dict[str, list[float]] = {k: [] for k in ("dry_wall", "dry_cpu", "total_wall",
                                                    "total_cpu", "wet_wall")}

    def timed(s, path):
        c0, w0 = time.process_time(), time.perf_counter()
        build_grid(s, path, workers=workers, progress=False)
        return time.perf_counter() - w0, time.process_time() - c0

    with tempfile.TemporaryDirectory() as d:
        for k in range(repeats):
            w, c = timed(dry_spec, Path(d) / f"dry{k}.nc")
            rec["dry_wall"].append(w)
            rec["dry_cpu"].append(c)
            w, c = timed(spec, Path(d) / f"wet{k}.nc")
            rec["total_wall"].append(w)
            rec["total_cpu"].append(c)
            rec["wet_wall"].append(float(load_wet(Path(d) / f"wet{k}.nc").meta["build"]
                                         ["wall_s"]))
    med = {k: statistics.median(x) for k, x in rec.items()}
    out = {"spec": "r117_wet", "shape": list(spec.shape), "workers": workers,
           "repeats": repeats, **{f"{k}_s": x for k, x in rec.items()},
           **{f"median_{k}_s": x for k, x in med.items()},
           "ratio_wet_branch_to_dry_wall": med["wet_wall"] / med["dry_wall"],
           "target_ratio_wet_branch_to_dry": 2.0}
    if workers == 1:  # one process: its CPU time is the whole build's, robust to load
        wet_cpu = [t - dd for t, dd in zip(rec["total_cpu"], rec["dry_cpu"], strict=True)]
        out["wet_cpu_s"] = wet_cpu
        out["median_wet_cpu_s"] = statistics.median(wet_cpu)
        out["ratio_wet_branch_to_dry_cpu"] = out["median_wet_cpu_s"] / med["dry_cpu"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    ap.add_argument("--build-slices", type=int, default=12,
                    help="slip-speed slices of the default spec for the throughput run")
    ap.add_argument("--no-build", action="store_true", help="query benchmark only")
    ap.add_argument("--full-build", action="store_true", help="also build the full default grid")
    ap.add_argument("--wet", action="store_true",
                    help="only the wet-branch build benchmark (r117_wet with and without [wet])")
    ap.add_argument("--wet-repeats", type=int, default=3, help="builds of each kind")
    ap.add_argument("--wet-slices", type=int, default=None,
                    help="slip-speed slices of r117_wet to keep (default: all)")
    ap.add_argument("--workers", type=int, default=1,
                    help="processes of the wet benchmark (1: also CPU times, robust to load)")
    args = ap.parse_args()
    if args.wet:
        w = bench_wet(args.wet_repeats, args.wet_slices, args.workers)
        if args.json:
            print(json.dumps({"wet": w}, indent=2))
            return
        print(f"wet branch build, grid {w['spec']} {tuple(w['shape'])}, {w['workers']} "
              f"worker(s), median of {w['repeats']}:")
        print(f"  dry build               {w['median_dry_wall_s']:7.2f} s wall")
        print(f"  wet branch              {w['median_wet_wall_s']:7.2f} s wall   ratio "
              f"{w['ratio_wet_branch_to_dry_wall']:.2f} (target <= 2)")
        print(f"  build with wet branch   {w['median_total_wall_s']:7.2f} s wall")
        if "ratio_wet_branch_to_dry_cpu" in w:
            print(f"  CPU: dry {w['median_dry_cpu_s']:.2f} s, wet branch "
                  f"{w['median_wet_cpu_s']:.2f} s, ratio {w['ratio_wet_branch_to_dry_cpu']:.2f}")
        return
    res = {"query": bench_query()}
    if not args.no_build:
        res["build"] = bench_build(args.build_slices, args.full_build)
    if args.json:
        print(json.dumps(res, indent=2))
        return
    q = res["query"]
    print(f"query, grid {tuple(q['grid_shape'])}:")
    print(f"  batched 1e5 points   {q['batched_1e5_us_per_point']:8.3f} us/point  (target 1)")
    print(f"  one call, 100 points {q['call_100_points_us']:8.2f} us         (target 20)")
    print(f"  one call, 1 point    {q['call_1_point_us']:8.2f} us")
    print(f"  100 points, clamped  {q['call_100_points_all_T_clamped_us']:8.2f} us")
    print(f"  pchip along v: batched {q['pchip_batched_1e5_us_per_point']:.3f} us/point, "
          f"100 points {q['pchip_call_100_points_us']:.2f} us")
    if "build" in res:
        b = res["build"]
        print(f"build (real engine, {b['slices']} slices = {b['points']} nodes, serial):")
        print(f"  {b['points_per_s_per_core']:.1f} points/s/core; default grid "
              f"({b['default_grid_points']} nodes) on {b['cores']} cores: "
              f"~{b['default_grid_estimate_s']:.0f} s (target 600 s)")
        if "full_build" in b:
            print(f"  full default build: {b['full_build']['wall_s']:.1f} s wall")


if __name__ == "__main__":
    main()
