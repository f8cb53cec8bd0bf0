"""Benchmarks of the friction grids: query speed and build throughput.

Run ``python benchmarks/bench_grid.py [--json] [--build-slices N] [--full-build]``.

* query: median time of ``FrictionGrid.interpolate`` (mu_cold, mu_hot, dT_flash) for one
  batched call of 1e5 random points [us/point] and for one call of 100 points [us/call]
  (targets: <= 1 us/point, <= 20 us/call), on a grid of the default spec's shape; the same
  with the optional monotone cubic along log10 v (``v_interp="pchip"``);
* build: grid nodes (cold and hot) per second per core of the real engine on a subset of the
  default spec's slip-speed slices (serial, so that one core is measured), and the implied
  time of the full default grid on this machine's cores; ``--full-build`` builds the whole
  default grid with all cores into a temporary file and reports its wall time.
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    ap.add_argument("--build-slices", type=int, default=12,
                    help="slip-speed slices of the default spec for the throughput run")
    ap.add_argument("--no-build", action="store_true", help="query benchmark only")
    ap.add_argument("--full-build", action="store_true", help="also build the full default grid")
    args = ap.parse_args()
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
