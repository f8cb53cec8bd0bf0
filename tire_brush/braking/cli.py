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
    r = abs_sub.add_parser(
        "roads", help="split-mu and mu-jumps: the four-wheel car on the map and the FMU",
        description="Brake the four-wheel car (load transfer, brake balance) on roads whose "
                    "friction differs left and right or changes along the stop (roads spec, "
                    "TOML, or the name of a shipped one under models/studies), with the "
                    "rule-based ABS and locked wheels, on the brush tire's force map and "
                    "through four instances of its FMU; writes results.csv, results.json, "
                    "trajectories/ and plots/ to the output folder.")
    r.add_argument("spec", metavar="SPEC.toml", nargs="?", default="roads_default",
                   help="roads spec file or shipped name (default roads_default)")
    r.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder")
    r.add_argument("--no-fmu", action="store_true", help="the force map only")
    r.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    r.add_argument("--json", action="store_true",
                   help="print the results document (as results.json) on stdout")
    r.set_defaults(func=_run_roads, simulator_factory=simulator_factory)
    w = abs_sub.add_parser(
        "wet-grip", help="UN R117 / ISO 23671 wet-grip test: BFC, G and label class",
        description="The wet-grip braking test of UN R117 Annex 5 / ISO 23671 on the brush "
                    "tire: ABS braking 80 -> 20 km/h on the wet reference road (BFC), the "
                    "trailer method's peak Fx/Fz at 65 km/h, the wet grip index G against the "
                    "reference tire (SRTT) and the EU label class; wet and dry.")
    w.add_argument("--tire", default="passenger", metavar="NAME",
                   help="candidate tire (TOML file or shipped name; default passenger)")
    w.add_argument("--reference", default=None, metavar="NAME",
                   help="reference tire (default: the spec's, srtt)")
    w.add_argument("--spec", default="wet_grip", metavar="SPEC.toml",
                   help="test spec (default models/studies/wet_grip.toml)")
    w.add_argument("--temperature", type=float, default=None, metavar="C",
                   help="wetted-surface temperature [C] (default: the spec's, 20)")
    w.add_argument("--water-depth", type=float, default=None, metavar="MM",
                   help="water film depth [mm] (default: the spec's, 1.0)")
    w.add_argument("--json", action="store_true", help="print the results as JSON")
    w.add_argument("--plot", metavar="FILE.png", default=None,
                   help="mu dry/wet against speed, deceleration and distance against time")
    w.set_defaults(func=_run_wet_grip)


def _run_roads(args: argparse.Namespace) -> int:
    import dataclasses

    from tirefric.cli import dump_json

    from .roads import load_roads_spec, print_roads, run_roads, write_roads

    spec = load_roads_spec(args.spec)
    if args.no_fmu:
        spec = dataclasses.replace(spec, fmu=False)
    progress = None if args.json else (lambda msg: print(f"# {msg}", file=sys.stderr))
    doc, runs = run_roads(spec, simulator_factory=getattr(args, "simulator_factory", None),
                          work_dir=args.output, progress=progress)
    write_roads(doc, runs, args.output, plots=not args.no_plots)
    if args.json:
        dump_json(doc)
    else:
        print_roads(doc)
    return 0


def _run_wet_grip(args: argparse.Namespace) -> int:
    import dataclasses

    from tirefric.cli import dump_json

    from .wet_grip_test import load_wet_grip_spec, plot_wet_grip, run_wet_grip

    spec = load_wet_grip_spec(args.spec)
    if args.reference is not None:
        spec = dataclasses.replace(spec, reference_tire=args.reference)
    depth = None if args.water_depth is None else args.water_depth * 1e-3
    doc, runs = run_wet_grip(spec, args.tire, args.temperature, depth)
    if args.plot:
        plot_wet_grip(doc, runs, args.plot, doc["T_C"] + 273.15)
        doc["plot"] = args.plot
    if args.json:
        dump_json(doc)
        return 0
    c, r = doc["candidate"], doc["reference"]
    print(f"# wet grip test (UN R117 Annex 5 / ISO 23671) on grid {doc['road_grid']}, "
          f"water {doc['water_depth_m'] * 1e3:g} mm, {doc['T_C']:g} C")
    print(f"# {'tire':>12s} {'BFC wet':>8s} {'BFC dry':>8s} {'peak wet':>9s} {'peak dry':>9s}"
          "   (BFC 80->20 km/h; peak Fx/Fz at 65 km/h)")
    for row in (c, r):
        print(f"  {row['tire']:>12s} {row['bfc_wet']:8.3f} {row['bfc_dry']:8.3f} "
              f"{row['peak_wet']:9.3f} {row['peak_dry']:9.3f}")
    print(f"G = {doc['G']:.3f} (trailer method {doc['G_trailer']:.3f}), EU label class "
          f"{doc['label_class']}; reference windows BFC 0.57-0.79: "
          f"{'in' if doc['reference_in_windows']['bfc'] else 'OUT'}, peak 0.65-0.90: "
          f"{'in' if doc['reference_in_windows']['peak'] else 'OUT'}")
    for note in doc["notes"]:
        print(f"# note: {note}")
    return 0


def _run_study(args: argparse.Namespace) -> int:
    from tirefric.cli import dump_json, print_table

    from .results import CaseFailure
    from .study import load_study, run_study, write_results

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
