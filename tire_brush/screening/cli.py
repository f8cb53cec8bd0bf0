"""``tirefric screen``: rank many tread compounds by label classes, stopping distances and
peak friction (docs/screening.md).

Registered through the ``tirefric.commands`` entry points (:func:`register`).
"""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric screen``."""
    p = sub.add_parser(
        "screen", help="screen tread compounds: wet grip and rolling resistance classes, "
                       "dry and wet stops, peak friction; Pareto front and sensitivities",
        description="Evaluate every compound of a screening spec (compound files and/or a "
                    "designed sweep around a base compound) at the screening resolution: "
                    "wet grip index and class, rolling resistance and class, ABS and locked "
                    "stops dry and wet, peak friction. Writes results.csv, results.json, "
                    "results.nc, pareto.png, sensitivity.png and report.md. Finished "
                    "compounds are kept under OUT/compounds and not recomputed on a rerun.")
    p.add_argument("spec", help="screening spec (TOML file or shipped study name)")
    p.add_argument("-o", "--out", default=None,
                   help="output folder (default: screen_<spec name>)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=1,
                   help="local worker processes (default 1)")
    g.add_argument("--scheduler", default=None,
                   help="address of a Dask distributed scheduler (e.g. tcp://host:8786)")
    p.add_argument("--keep-grids", action="store_true",
                   help="keep each compound's file and grids under OUT/work")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Run ``tirefric screen``; exit status 1 if a compound failed."""
    from .run import cost_per_compound, run_screen
    from .spec import load_screen_spec

    spec = load_screen_spec(args.spec)
    out = args.out or f"screen_{spec.name}"
    res = run_screen(spec, out, workers=args.workers, scheduler=args.scheduler,
                     progress=not args.no_progress, keep_grids=args.keep_grids)
    rows = res.rows()
    print(f"screen {spec.name}: {len(rows)} compounds ({len(res.computed)} tasks computed, "
          f"{len(res.reused)} reused), {res.wall_s:.1f} s ({res.where}), "
          f"median {cost_per_compound(res):.1f} s per compound")
    print(f"  {'compound':<16s}{'G':>7s} cls{'RRC':>8s} cls{'dry ABS':>9s}{'wet ABS':>9s}  Pareto")
    for r in rows:
        if r["status"] != "ok":
            print(f"  {r['name']:<16s}failed: {r['error']}")
            continue
        print(f"  {r['name']:<16s}{r['G']:7.3f}  {r['wet_class'] or '-'}{r['rrc_N_per_kN']:8.2f}"
              f"  {r['rr_class']}{r['stop_dry_abs_m']:9.2f}{r['stop_wet_abs_m']:9.2f}  "
              f"{'*' if r['pareto'] else ''}")
    if res.reference["status"] != "ok":
        print(f"  reference tire failed: {res.reference.get('error')}")
    for k, v in res.files.items():
        print(f"  {k}: {v}")
    return 1 if res.failed or res.reference["status"] != "ok" else 0
