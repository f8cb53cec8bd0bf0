"""``tirefric grid build|info|query|plot``: a thin shell over :mod:`lookup.grid`.

Wherever a grid is asked for, a path works as well as the name of a shipped grid
(``default``); wherever a spec is asked for, a path or the name of a shipped spec.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from tirefric.cli import (
    dump_json,
    parse_float,
    parse_float_list,
    parse_quantity_option,
    parse_temperature_option,
    print_table,
)
from tirefric.errors import InputError

from ..cli import MU_KEYS
from .reader import P_INTERPOLATIONS, T_INTERPOLATIONS, V_INTERPOLATIONS

KELVIN = 273.15


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric grid`` and its sub-commands."""
    g = sub.add_parser("grid", help="friction grids: build, inspect, query, plot",
                       description="Precomputed friction grids (cold and hot mu, flash "
                                   "temperature) over slip speed, temperature and pressure.")
    gs = g.add_subparsers(dest="grid_command", required=True, metavar="GRID_COMMAND")

    b = gs.add_parser("build", help="build a grid from a spec (parallel, resumable)",
                      description="Build a grid from a spec TOML (models/grids/*.toml). "
                                  "Finished slip-speed slices are checkpointed to "
                                  "OUTPUT.partial.npz; running the same command again resumes.")
    b.add_argument("spec", help="grid spec TOML file or shipped spec name (e.g. default)")
    b.add_argument("-o", "--output", required=True, help="grid file to write (.nc or .npz)")
    b.add_argument("--workers", type=int, default=None,
                   help="local worker processes (default: all cores; 1 = in-process)")
    b.add_argument("--scheduler", default=None,
                   help="address of a Dask distributed scheduler (e.g. tcp://host:8786)")
    b.add_argument("--no-resume", action="store_true",
                   help="ignore (and delete) a checkpoint of an earlier run")
    b.add_argument("--quiet", action="store_true", help="no progress bar")
    b.add_argument("--json", action="store_true", help="print a JSON build report")
    b.set_defaults(func=_run_build)

    i = gs.add_parser("info", help="axes, ranges, metadata and hash of a grid")
    i.add_argument("grid", help="grid file or shipped grid name (e.g. default)")
    i.add_argument("--json", action="store_true", help="print JSON")
    i.set_defaults(func=_run_info)

    q = gs.add_parser("query", help="interpolated values (same keys as `tirefric mu`)",
                      description="Interpolate a grid at slip speed(s) v, one background "
                                  "temperature and one nominal pressure. Out-of-range inputs "
                                  "are clamped to the grid's axes and reported.")
    q.add_argument("grid", help="grid file or shipped grid name (e.g. default)")
    q.add_argument("--v", required=True, help="slip speed(s) [m/s], comma separated")
    q.add_argument("--T", required=True,
                   help="background temperature: a bare number is Celsius, or '293.15 K'")
    q.add_argument("--p", required=True,
                   help="nominal contact pressure: a bare number is Pa, or '0.3 MPa'")
    q.add_argument("--T-interp", choices=T_INTERPOLATIONS, default="linear",
                   help="across T: linear at fixed v (default) or reduced_speed (linear in T at "
                        "fixed log10(v a_T), time-temperature superposition)")
    q.add_argument("--v-interp", choices=V_INTERPOLATIONS, default="linear",
                   help="interpolation along log10 v: linear (default, as the tire model and "
                        "FMU) or pchip (monotone cubic)")
    q.add_argument("--p-interp", choices=P_INTERPOLATIONS, default="linear",
                   help="interpolation along log10 p: linear (default) or pchip (monotone "
                        "cubic); --v-interp pchip --T-interp reduced_speed --p-interp pchip is "
                        "the most accurate (docs/engine-inputs.md)")
    q.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
    q.set_defaults(func=_run_query)

    pl = gs.add_parser("plot", help="overview figure: mu(v) cold/hot, dT_flash, ratio map")
    pl.add_argument("grid", help="grid file or shipped grid name (e.g. default)")
    pl.add_argument("-o", "--output", required=True, help="image file (.png, .pdf, .svg)")
    pl.add_argument("--p", default=None,
                    help="nominal pressure of the curves [Pa] (default: node nearest 0.3 MPa)")
    pl.set_defaults(func=_run_plot)


def _run_build(args: argparse.Namespace) -> int:
    from .build import Checkpoint, build_grid

    try:
        grid, report = build_grid(args.spec, args.output, workers=args.workers,
                                  scheduler=args.scheduler, progress=not args.quiet,
                                  resume=not args.no_resume)
    except KeyboardInterrupt:
        ckpt = Checkpoint.for_output(Path(args.output))
        where = f"finished slices are in {ckpt}; " if ckpt.exists() else ""
        print(f"tirefric grid build: interrupted; {where}run the same command again to resume",
              file=sys.stderr)
        return 130
    if args.json:
        dump_json({**report.as_dict(), "hash": grid.hash, "shape": list(grid.shape)})
    else:
        print(f"wrote {report.output}  shape {grid.shape}  {grid.hash}")
        print(f"slices: {report.n_computed} computed, {report.n_reused} reused from checkpoint; "
              f"wall {report.wall_s:.1f} s; {report.points_per_s_per_core:.1f} points/s/core")
    return 0


def _run_info(args: argparse.Namespace) -> int:
    from .store import grid_summary, load_grid

    grid = load_grid(args.grid)
    s = grid_summary(grid)
    if args.json:
        dump_json(s)
        return 0
    m = grid.meta
    ax = s["axes"]
    print(f"grid      {grid.source}")
    print(f"hash      {grid.hash}")
    print(f"shape     {tuple(grid.shape)} = (v, T, p), {int(np.prod(grid.shape))} nodes")
    print(f"v         {ax['log10_v']['v_min_m_s']:.4g} .. {ax['log10_v']['v_max_m_s']:.4g} m/s, "
          f"{ax['log10_v']['n']} log-spaced nodes")
    print(f"T         {ax['T']['T_min_C']:.4g} .. {ax['T']['T_max_C']:.4g} C, "
          f"{ax['T']['n']} nodes")
    print(f"p         {ax['log10_p']['p_min_Pa']:.4g} .. {ax['log10_p']['p_max_Pa']:.4g} Pa, "
          f"{ax['log10_p']['n']} log-spaced nodes")
    for key, label in (("compound_name", "compound"), ("surface_name", "surface"),
                       ("q1_per_m", "q1 [1/m]"), ("q1_rule", "q1 rule"), ("D_m", "D [m]"),
                       ("s0_m", "s0 [m]"), ("engine_settings", "engine"),
                       ("package_version", "version"), ("created", "created")):
        if key in m:
            print(f"{label:9s} {m[key]}")
    print("variables " + ", ".join(f"{n} [{v['units']}] {v['min']:.4g}..{v['max']:.4g}"
                                   for n, v in s["variables"].items()))
    ob = m.get("outside_band")
    if isinstance(ob, dict):  # what the grid took from outside its measured master curve
        band = ob.get("measured_band_rad_s")
        if band is None:
            print("outside   analytic master curve: nothing extrapolated")
        else:
            worst = ", ".join(
                f"{b} {100 * ob[f'max_{b}']:.3g} %" for b in ("cold", "hot")
                if ob.get(f"max_{b}") is not None)
            above = sum(int(ob.get(f"nodes_above_warning_{b}", 0)) for b in ("cold", "hot"))
            print(f"outside   measured master curve {band[0]:.4g}..{band[1]:.4g} rad/s; "
                  f"largest share of a node's integrand from outside it: {worst}; "
                  f"{above} node values above {100 * ob['warning_share']:g} % "
                  "(variables outside_cold, outside_hot)")
    return 0


def _run_query(args: argparse.Namespace) -> int:
    from .store import load_grid

    v = parse_float_list(args.v, "--v")
    T_C = parse_temperature_option(args.T, "--T") - KELVIN
    p = parse_quantity_option(args.p, "--p", "pressure", "Pa")
    if any(x < 0 for x in v):
        raise InputError("slip speeds must be >= 0 m/s", source="--v", value=args.v)
    if p <= 0:
        raise InputError("nominal pressure must be > 0 Pa", source="--p", value=args.p)
    if T_C <= -KELVIN:
        raise InputError("temperature below absolute zero", source="--T", value=args.T)
    grid = load_grid(args.grid)
    names = tuple(k for k in MU_KEYS if k != "v")
    out = grid.interpolate(np.array(v), T_C + KELVIN, p, names=names, v_interp=args.v_interp,
                           T_interp=args.T_interp, p_interp=args.p_interp)
    rows = [{"v": vi, **{n: float(out[n][j]) for n in names}} for j, vi in enumerate(v)]
    clamped = {k: c for k, c in grid.out_of_range_detail.items() if c["below"] or c["above"]}
    if args.json:
        dump_json({"grid": grid.source, "hash": grid.hash,
                   "compound": grid.meta.get("compound_name"),
                   "surface": grid.meta.get("surface_name"), "T_C": T_C, "p_Pa": p,
                   "v_interp": args.v_interp, "T_interp": args.T_interp,
                   "p_interp": args.p_interp,
                   "points": rows, "clamped": clamped,
                   "outside_band": grid.meta.get("outside_band")})
    else:
        print(f"# grid {grid.source} ({grid.hash[:19]}), T = {T_C:g} C, p = {p:g} Pa")
        print_table(rows, MU_KEYS)
    if clamped:
        print(f"tirefric grid query: warning: inputs outside the grid were clamped to its axes: "
              f"{clamped}", file=sys.stderr)
    return 0


def _run_plot(args: argparse.Namespace) -> int:
    from .plots import plot_grid
    from .store import load_grid

    p = None if args.p is None else parse_float(args.p, "--p")
    if p is not None and not (math.isfinite(p) and p > 0):
        raise InputError("nominal pressure must be > 0 Pa", source="--p", value=args.p)
    path = plot_grid(load_grid(args.grid), args.output, p_Pa=p)
    print(f"wrote {path}")
    return 0
