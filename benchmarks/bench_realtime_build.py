"""Build cost of the real-time fidelity's patch table (docs/realtime.md, "The table").

Run:  OMP_NUM_THREADS=1 python benchmarks/bench_realtime_build.py [--tire passenger]
      [--grid default|r117_wet] [--processes 2] [--layers] [--repeat 1]

Builds the table of the tire on the grid (with a layer per water depth when the grid has a
wet branch) without the cache, as ``cached_patch_table`` does on a miss, and prints the wall
time and the CPU time of the build (this process and its workers: the figure that does not
depend on what else the machine runs; on idle cores the wall time is about the CPU time over
the workers, the layers being independent), medians over ``--repeat`` builds. ``--layers``
also marches each (depth, inclination, temperature) layer alone and prints its CPU time, and
the depth law's (the profile of the build).
"""

from __future__ import annotations

import argparse
import resource
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from lookup.grid.store import load_grid, resolve_grid_path
from lookup.grid.wet import load_wet
from tire_brush import realtime_build as rb
from tire_brush.friction import as_table
from tire_brush.params import load_tire
from tire_brush.steady import N_STEADY, TOL
from tirefric.errors import GridError


def cpu_seconds() -> float:
    """CPU time [s] of this process and of its children that have been waited for."""
    a = resource.getrusage(resource.RUSAGE_SELF)
    b = resource.getrusage(resource.RUSAGE_CHILDREN)
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tire", default="passenger")
    ap.add_argument("--grid", default="default")
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--layers", action="store_true")
    args = ap.parse_args(argv)
    tp, grid = load_tire(args.tire), load_grid(args.grid)
    try:
        wet = load_wet(resolve_grid_path(args.grid))
    except GridError:                          # a grid without the wet branch: a dry table
        wet = None
    walls, cpus = [], []
    for _ in range(args.repeat):
        c0, w0 = cpu_seconds(), time.perf_counter()
        pt = rb.build_patch_table(tp, grid, processes=args.processes, wet=wet)
        walls.append(time.perf_counter() - w0)
        cpus.append(cpu_seconds() - c0)
    print(f"{args.grid}: table {tuple(pt.values.shape)}, {len(pt.to_bytes()) / 1e6:.1f} MB; "
          f"{args.processes} processes: wall {statistics.median(walls):.1f} s, CPU "
          f"{statistics.median(cpus):.1f} s (median of {args.repeat})")
    if args.layers:
        table = as_table(grid)
        ax = rb.default_axes(np.asarray(table.T, float))
        depths = [0.0] if wet is None else [float(d) for d in wet.axes["water_depth"]]
        total: dict[tuple[float, float], float] = {}
        for d in depths:
            extra: tuple = ()
            if d > 0.0:
                extra = ((*rb._wet_layer_arrays(table, wet, d),
                          np.asarray(wet.axes["log10_t_drain"], float), 1.0),)
            for g in ax["gamma"]:
                for T in ax["T"]:
                    job = (tp, table, N_STEADY, TOL, float(g), float(T), ax["Fz"],
                           ax["log10_v"], ax["theta"], ax["rho"], *extra)
                    t0 = time.process_time()
                    rb._layer(job)
                    dt = time.process_time() - t0
                    total[(d, float(g))] = total.get((d, float(g)), 0.0) + dt
                    print(f"  depth {1e3 * d:.2f} mm, gamma {g:.2f} rad, T {T - 273.15:6.1f} C:"
                          f" {dt:.2f} s")
        for (d, g), t in total.items():
            print(f"  depth {1e3 * d:.2f} mm, gamma {g:.2f} rad: {t:.1f} s of CPU")
        if len(depths) > 1:
            t0 = time.process_time()
            rb.depth_law(tp, wet, depths, ax)
            print(f"  the depth law: {time.process_time() - t0:.2f} s of CPU")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
