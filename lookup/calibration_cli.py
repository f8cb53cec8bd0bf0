"""``tirefric fit``: calibrate the friction model against measured friction (a thin shell over
:mod:`lookup.calibration` and :mod:`lookup.calibration_files`)."""

from __future__ import annotations

import argparse
import json

from tirefric.cli import dump_json


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric fit``."""
    p = sub.add_parser(
        "fit", help="fit the adhesive law, q1 and D to measured friction (calibration)",
        description="Fit the friction model's open parameters (the adhesive law of review "
                    "eqs. 21-22 per compound or shared, the road's q1 or xi1, D) to measured "
                    "mu(v, T, p) tables named by a fit spec (TOML; layout in "
                    "lookup/calibration_files.py and docs/calibration.md). Prints the fitted "
                    "values with standard uncertainties and correlations, the RMS log10 "
                    "error on the fitted and on the held-out points and the per-point table; "
                    "with -o writes the report (text, JSON, CSV) and the calibrated compound "
                    "and surface files.")
    p.add_argument("spec", help="fit spec (TOML)")
    p.add_argument("-o", "--output", default=None,
                   help="folder for fit.txt, fit.json, points.csv and the calibrated "
                        "compound and surface TOML files")
    p.add_argument("--predict-only", action="store_true",
                   help="no fitting: compare the model with the start values (the model "
                        "files' own, or the spec's start values) against the tables")
    p.add_argument("--json", action="store_true",
                   help="print the result as JSON instead of the text report")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    from .calibration import fit, predict
    from .calibration_files import load_fit_spec, report, write_models, write_outputs

    spec = load_fit_spec(args.spec)
    result = predict(spec) if args.predict_only else fit(spec)
    written = {}
    if args.output:
        written = write_outputs(result, args.output)
        if result.mode == "fit":
            written.update(write_models(result, args.output))
    if args.json:
        out = result.to_dict()
        out["written"] = {k: str(v) for k, v in written.items()}
        dump_json(json.loads(json.dumps(out, allow_nan=False)))
    else:
        print(report(result), end="")
        for k, v in written.items():
            print(f"wrote {v} ({k})")
    return 0
