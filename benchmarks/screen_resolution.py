"""Screening resolution against full resolution on the shipped tread compounds.

    python benchmarks/screen_resolution.py [--workers 2] [--compounds summer,winter,racing]

Evaluates each compound at the screening resolution (tire_brush.screening.spec.
DEFAULT_RESOLUTION) and with the shipped grid specs' full speed and pressure axes (same
temperature nodes), and the summer tread on the shipped grid files (default.nc, r117_wet.nc:
what `tirefric label` and `tirefric abs study` read); prints the relative differences and the
largest per output. docs/screening.md quotes the result; tests/test_screening.py holds the
tolerance (slow).
"""

from __future__ import annotations

import argparse
import json
import math

from tire_brush.screening.resolution import compare, compare_shipped
from tire_brush.screening.spec import load_screen_spec, screen_settings
from tirefric.paths import resolve_model_file


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--compounds", default="summer,winter,racing")
    ap.add_argument("--spec", default="screen_example")
    ap.add_argument("--json", default=None, help="write the numbers to this file")
    args = ap.parse_args()
    spec = load_screen_spec(args.spec)
    settings = screen_settings(spec)
    descs = [{"name": c, "file": str(resolve_model_file(c, "compounds"))}
             for c in args.compounds.split(",")]
    res = compare(settings, descs, workers=args.workers)
    summer = str(resolve_model_file("summer", "compounds"))
    shipped = compare_shipped(settings, summer, str(resolve_model_file("default", "grids",
                                                                       ".nc")),
                              str(resolve_model_file("r117_wet", "grids", ".nc")))
    res["summer (shipped grids)"] = {"rel": shipped["rel"], "screen": shipped["screen"],
                                     "full": shipped["shipped"], "seconds": {}}
    keys = list(next(iter(res.values()))["rel"])
    print(f"{'compound':<24s}" + "".join(f"{k[:16]:>17s}" for k in keys))
    for name, v in res.items():
        print(f"{name:<24s}" + "".join(f"{100 * v['rel'][k]:+16.3f}%" for k in keys))
    worst = {k: max(abs(v["rel"][k]) for v in res.values()) for k in keys}
    print(f"{'largest |difference|':<24s}" + "".join(f"{100 * worst[k]:16.3f}%" for k in keys))
    for name, v in res.items():
        if v["seconds"]:
            print(f"{name}: {v['seconds']['screen']:.1f} s screening, "
                  f"{v['seconds']['full']:.1f} s full resolution (wall, one worker each)")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=1, default=lambda x: None if isinstance(x, float)
                      and not math.isfinite(x) else x)


if __name__ == "__main__":
    main()
