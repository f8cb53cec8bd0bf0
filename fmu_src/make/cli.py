"""``tirefric fmu build|info``: a thin shell over :mod:`fmu_src.make.build`."""

from __future__ import annotations

import argparse

from tirefric.cli import dump_json, parse_float, parse_quantity_option


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric fmu`` and its sub-commands."""
    f = sub.add_parser("fmu", help="the brush tire as an FMI 2.0 co-simulation FMU",
                       description="Build and inspect the brush-tire FMU (pythonfmu: runs in "
                                   "the host's Python with numpy; --native: C, needs "
                                   "nothing on the host).")
    fs = f.add_subparsers(dest="fmu_command", required=True, metavar="FMU_COMMAND")

    b = fs.add_parser("build", help="build BrushTire.fmu from a tire and a grid",
                      description="Build the transient brush tire with its grid as an FMI 2.0 "
                                  "co-simulation FMU. The FMU is validated with fmpy; the same "
                                  "inputs give the same file (and GUID).")
    b.add_argument("--tire", default="passenger",
                   help="tire TOML file or shipped name (default: passenger)")
    b.add_argument("--grid", default="default",
                   help="grid file (.nc or .npz) or shipped grid name (default: default)")
    b.add_argument("-o", "--output", default="BrushTire.fmu", help="FMU file to write")
    b.add_argument("--n-elements", type=int, default=None,
                   help="start value of n_elements (tread elements on the patch at the "
                        "nominal load)")
    b.add_argument("--dt-internal", default=None,
                   help="start value of dt_internal, the longest internal step [s]")
    b.add_argument("--s0", default=None,
                   help="start value of s0, the blending length of eq. (28) [m] (default: "
                        "the grid's)")
    b.add_argument("--axes", choices=("adapted-sae", "iso-w", "sae"), default=None,
                   help="start value of the axes parameter, the axis system of vy, Fy, Mz and "
                        "alpha (default: adapted-sae, the brush's own; docs/axes.md)")
    b.add_argument("--texture-depth", default=None, metavar="LENGTH",
                   help="start value of the texture_depth parameter, the road's mean texture "
                        "depth for the hydroplaning model: metres or e.g. '0.7 mm' (default "
                        "0: the texture holds no water)")
    b.add_argument("--fidelity", choices=("full", "realtime"), default="full",
                   help="'realtime' also packs the real-time fidelity's patch table (the "
                        "steady patch of this tire on this grid, tabulated: built once per tire "
                        "and grid, about a minute on 2 cores, then cached) and starts the FMU's "
                        "fidelity parameter at 1; 'full' (default) the full tire only "
                        "(docs/realtime.md)")
    b.add_argument("--native", action="store_true",
                   help="build the Python-free flavour: the C core with an FMI 2.0 wrapper "
                        "(binaries for linux64, and win64 where a cross-compiler is found: "
                        "x86_64-w64-mingw32-gcc or the ziglang wheel)")
    b.add_argument("--json", action="store_true", help="print a JSON build report")
    b.set_defaults(func=_run_build)

    i = fs.add_parser("info", help="what an FMU was built from: tire, grid hash, options")
    i.add_argument("fmu", help="FMU file")
    i.add_argument("--json", action="store_true", help="print JSON")
    i.add_argument("--validate", action="store_true", help="also run fmpy's validation")
    i.set_defaults(func=_run_info)


def _run_build(args: argparse.Namespace) -> int:
    from .build import BuildOptions, build_fmu

    kw: dict = {}
    if args.n_elements is not None:
        kw["n_elements"] = args.n_elements
    if args.dt_internal is not None:
        kw["dt_internal"] = parse_float(args.dt_internal, "--dt-internal")
    if args.s0 is not None:
        kw["s0"] = parse_float(args.s0, "--s0")
    if args.texture_depth is not None:
        kw["texture_depth"] = parse_quantity_option(args.texture_depth, "--texture-depth",
                                                    "length", "m")
    if args.axes is not None:
        from fmu_src.runtime.interface import AXES_OPTION

        kw["axes"] = AXES_OPTION.index(args.axes)
    kw["fidelity"] = args.fidelity
    report = build_fmu(args.tire, args.grid, args.output, BuildOptions(**kw),
                       native=args.native)
    if args.json:
        dump_json(report.as_dict())
        return 0
    print(f"wrote {report.path} ({report.size_bytes / 1e6:.2f} MB) in {report.seconds:.1f} s")
    print(f"tire      {report.tire}")
    print(f"grid      {report.grid_source}  {report.grid_hash}")
    print(f"guid      {report.guid}")
    print(f"build id  {report.build_id}")
    if args.native:
        print(f"binaries  {report.runtime_package.strip('()')} (no Python needed on the host)")
    else:
        print(f"runtime   {report.runtime_package} (numpy + standard library)")
    print("validated with fmpy: no problems")
    return 0


def _run_info(args: argparse.Namespace) -> int:
    from .build import read_fmu_info

    info = read_fmu_info(args.fmu)
    if args.validate:
        from fmpy.validation import validate_fmu

        info["validation_problems"] = validate_fmu(args.fmu)
    if args.json:
        dump_json(info)
        return 0
    g = info["grid"]
    print(f"fmu       {info['file']}  ({info['modelName']} {info['version']})")
    print(f"guid      {info['guid']}")
    print(f"build id  {info['build_id']}")
    print(f"tire      {info['tire']} ({info['tire_file']})")
    print(f"grid      {g['source']}  {g['hash']}")
    for key in ("compound_name", "surface_name", "s0_m", "D_m", "created"):
        if key in g["meta"]:
            print(f"          {key} = {g['meta'][key]}")
    print("options   " + ", ".join(f"{k} = {v}" for k, v in info["options"].items()))
    for key, what in (("rolling", "My from the rolling-resistance table"),
                      ("wet", "water_depth through the grid's wet branch")):
        entry = info[key]
        has = entry.get("file") or entry.get("table")
        print(f"{key:9s} " + (what if has else f"none ({entry.get('why', '')})"))
    if info["flavour"] == "native":
        print(f"needs     nothing (native: {', '.join(info['native'].get('platforms', []))})")
    else:
        print(f"needs     Python >= 3.11 with {', '.join(info['requirements'])}")
    if args.validate:
        problems = info["validation_problems"]
        print("validation: " + ("no problems" if not problems else
                                "\n  - " + "\n  - ".join(problems)))
        return 1 if problems else 0
    return 0
