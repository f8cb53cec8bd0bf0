"""``tirefric label``: the EU tyre label classes of a tire from the physics (docs/label.md).

Registered as a top-level command through the ``tirefric.commands`` entry points
(:func:`register`); :func:`main` runs it. The model is :mod:`tire_brush.label`.
"""

from __future__ import annotations

import argparse

from tirefric.cli import dump_json


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric label``."""
    p = sub.add_parser(
        "label", help="EU tyre label (2020/740): wet grip index and class, rolling resistance "
                      "and class, from the physics",
        description="The EU tyre label of a C1 tire before it is built: the wet grip index G "
                    "(UN R117 Annex 5, vehicle method, against the reference tire on the wet "
                    "reference road) and its class, the rolling-resistance coefficient at the "
                    "ISO 28580 conditions and its class; the noise class is not modelled. "
                    "Prints a table, or JSON with --json; --svg draws the label (needs the "
                    "optional package tyre-energy-label: pip install 'tirefric[label]').")
    p.add_argument("--tire", default="passenger",
                   help="tire TOML file or shipped name (default passenger)")
    p.add_argument("--grid", default=None,
                   help="friction grid with a wet branch on the reference road (default: the "
                        "wet grip spec's, r117_wet); its compound is the tread compound")
    p.add_argument("--compound", default=None,
                   help="tread compound (default: the grid's; another compound needs its own "
                        "grid on the reference road)")
    p.add_argument("--temperature", type=float, default=None,
                   help="wetted-surface temperature of the wet grip test [C] (default 20)")
    p.add_argument("--spec", default="wet_grip", help="wet grip test spec (default wet_grip)")
    p.add_argument("--json", action="store_true", help="print the document as JSON")
    p.add_argument("--svg", default=None, metavar="FILE",
                   help="draw the label as SVG into FILE (package tyre-energy-label)")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Run ``tirefric label``; returns the exit code."""
    from .label import draw_label, tyre_label_document

    doc = tyre_label_document(args.tire, args.grid, args.compound, args.spec,
                              args.temperature)
    if args.svg:
        written = draw_label(doc, args.svg)
        doc["label_svg"] = written
        if written is None:
            doc["notes"].append("label not drawn: the package tyre-energy-label is not "
                                "installed (pip install 'tirefric[label]')")
    if args.json:
        dump_json(doc)
        return 0
    w, r = doc["wet_grip"], doc["rolling_resistance"]
    print(f"EU tyre label ({doc['regulation']}): tire {doc['tire']} ({doc['size']}), "
          f"compound {doc['compound']}, road grid {doc['grid']}")
    print(f"  {'quantity':<34s}{'value':>12s}  class")
    print(f"  {'wet grip index G (vehicle)':<34s}{w['G']:12.3f}  {w['class']}")
    print(f"  {'wet grip index G (trailer)':<34s}{w['G_trailer']:12.3f}  {w['class_trailer']}")
    print(f"  {'rolling resistance [N/kN]':<34s}{r['rrc_N_per_kN']:12.2f}  {r['class']}")
    print(f"  {'external rolling noise [dB]':<34s}{'-':>12s}  not modelled")
    print(f"  wet: BFC {w['bfc_candidate']:.3f} against the reference tire's "
          f"{w['bfc_reference']:.3f} at {w['T_C']:g} C, {w['water_depth_m'] * 1e3:g} mm water")
    print(f"  rolling: {r['load_N']:.0f} N, {r['inflation_Pa'] / 1e3:.0f} kPa, "
          f"{r['speed_m_per_s'] * 3.6:.0f} km/h, {r['T_C']:g} C ambient, tread at "
          f"{r['T_tire_C']:.1f} C (thermal equilibrium); change {100 * r['per_K']:+.2f} %/K "
          f"of the ambient ({100 * r['per_K_isothermal']:+.2f} %/K isothermal at "
          f"{r['T_C']:g} C)")
    for n in doc["notes"]:
        print(f"  note: {n}")
    if doc["label_svg"]:
        print(f"  label drawn: {doc['label_svg']}")
    return 0
