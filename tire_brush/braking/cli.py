"""``tirefric abs``: braking studies (a thin shell over :mod:`tire_brush.braking.study`)."""

from __future__ import annotations

import argparse
import sys

SUMMARY_KEYS = ("case", "stopping_distance_ocp", "stopping_distance_abs",
                "stopping_distance_locked", "point_mass_bound", "optimal_slip")


def register(sub: argparse._SubParsersAction, simulator_factory=None) -> None:
    """Register ``tirefric abs`` and its sub-commands.

    ``simulator_factory`` is handed to :func:`~tire_brush.braking.study.run_study` for the
    studies that ask for the ABS through the FMU (the top layer, :mod:`fmu_src.host.abs_cli`,
    passes it; without it such a study is refused with a message)."""
    p = sub.add_parser("abs", help="braking studies: optimal control, rule-based ABS, locked",
                       description="Braking studies on a quarter car: minimum stopping "
                                   "distance by optimal control (CasADi/IPOPT), a rule-based "
                                   "ABS and a locked wheel on the same friction.")
    abs_sub = p.add_subparsers(dest="abs_command", required=True, metavar="SUBCOMMAND")
    s = abs_sub.add_parser("study", help="run a study spec over its cases",
                           description="Run a braking study (TOML spec, or the name of a "
                                       "shipped spec under models/studies) and write "
                                       "results.csv, results.json, trajectories/, slip_maps/ "
                                       "and plots/ to the output folder.")
    s.add_argument("spec", metavar="SPEC.toml", help="study spec file or shipped name")
    s.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder")
    s.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="Dask scheduler address (e.g. tcp://host:8786); cases run as tasks")
    s.add_argument("--jobs", "-j", type=int, default=0, metavar="N",
                   help="cases at once in N local processes (default 0: one per available "
                        "core, at most one per case; 1: in this process, one after another)")
    s.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    s.add_argument("--json", action="store_true",
                   help="print the results document (as results.json) on stdout")
    s.set_defaults(func=_run_study, simulator_factory=simulator_factory)


def _run_study(args: argparse.Namespace) -> int:
    from lookup.cli import dump_json, print_table

    from .study import CaseFailure, load_study, run_study, write_results

    spec = load_study(args.spec)
    progress = None if args.json else (lambda msg: print(f"# {msg}", file=sys.stderr))
    results = run_study(spec, scheduler=args.scheduler, progress=progress,
                        work_dir=args.output,
                        simulator_factory=getattr(args, "simulator_factory", None),
                        jobs=args.jobs)
    doc = write_results(spec, results, args.output, plots=not args.no_plots,
                        spec_path=args.spec)
    if args.json:
        dump_json(doc)
    else:
        print(f"# study {spec.name}: {len(results)} case(s), v0 = {spec.v0:g} m/s to "
              f"v_stop = {spec.v_stop:g} m/s; distances [m], slip [1]; written to "
              f"{args.output}")
        keys = SUMMARY_KEYS
        if spec.fmu_abs:
            keys = (*SUMMARY_KEYS[:3], "stopping_distance_abs_fmu", *SUMMARY_KEYS[3:])
        print_table([r.summary for r in results if not isinstance(r, CaseFailure)], keys)
    failed = [r for r in results if isinstance(r, CaseFailure)]
    for f in failed:
        print(f"# case {f.case.label} FAILED: {f.error}", file=sys.stderr)
    return 1 if failed else 0
