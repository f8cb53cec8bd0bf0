"""Ripples of the steady force-slip curves over the operating range.

Run ``python benchmarks/bench_ripples.py [--json] [--points 401] [--ageing on|off]``.

For every case of 0/20/50 C, 5/10/20/30 m/s and 2/4/6 kN the steady brush (shipped passenger
tire, default grid) is swept over four curves: pure braking ``Fx(kappa)``, kappa 0 .. -1;
pure cornering ``Fy(alpha)``, alpha 0 .. 15 deg; combined ``Fx(kappa)`` and ``Fy(kappa)`` at
alpha 4 deg. Each curve is the force's magnitude along the sweep, ``points`` samples. A
ripple is a turning point other than the curve's maximum whose reversal exceeds
``threshold`` Fz (:func:`tire_brush.curves.ripples`). Reported per temperature, speed and
curve: the ripple counts at 0.2 % and 0.5 % of Fz (the latter is the criterion of
docs/tire-core.md, "smoothness"), the cases with any, and the largest reversal. Takes
~3-6 min on one core at 401 points. ``--ageing`` sets the tread's contact age
(docs/tire-core.md, "contact age"; default: the tire file's).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np

TEMPS_C = (0.0, 20.0, 50.0)
SPEEDS = (5.0, 10.0, 20.0, 30.0)
LOADS = (2000.0, 4000.0, 6000.0)
ALPHA_COMBINED = math.radians(4.0)
CURVES = ("Fx_pure", "Fy_pure", "Fx_comb", "Fy_comb")


def largest_reversal(y: np.ndarray) -> float:
    """Largest drop of ``y`` after a rise or rise after a drop other than the peak's fall: the
    largest amplitude a ripple of the curve has (0 for a single-maximum curve)."""
    from tire_brush.curves import turning_points

    tp = turning_points(y, 1e-9 * max(1.0, float(np.max(np.abs(y)))))
    top = int(np.argmax(y))
    worst = 0.0
    for j, i in enumerate(tp):
        if i == top:
            continue
        nxt = tp[j + 1] if j + 1 < len(tp) else y.size - 1
        prev = tp[j - 1] if j > 0 else 0
        worst = max(worst, min(abs(y[i] - y[nxt]), abs(y[i] - y[prev])))
    return worst


def curves(brush, T_C: float, v: float, Fz: float, n: int) -> dict[str, np.ndarray]:
    """The four curves of the module docstring, as |F| / Fz."""
    T = T_C + 273.15
    kappa = -np.linspace(0.0, 1.0, n)
    alpha = np.radians(np.linspace(0.0, 15.0, n))
    pure_x = brush.solve(kappa, 0.0, v, Fz, T)
    pure_y = brush.solve(0.0, alpha, v, Fz, T)
    comb = brush.solve(kappa, ALPHA_COMBINED, v, Fz, T)
    return {"Fx_pure": np.abs(pure_x.Fx) / Fz, "Fy_pure": np.abs(pure_y.Fy) / Fz,
            "Fx_comb": np.abs(comb.Fx) / Fz, "Fy_comb": np.abs(comb.Fy) / Fz}


def run(n: int, thresholds: tuple[float, ...], brush=None,
        ageing: bool | None = None) -> list[dict]:
    """One row per case and curve: counts at each threshold and the largest reversal
    (``ageing``: the contact age on or off, None: the tire file's)."""
    import dataclasses

    from lookup.grid import load_grid
    from tire_brush.curves import ripples
    from tire_brush.friction import GridFriction
    from tire_brush.params import load_tire
    from tire_brush.steady import SteadyBrush

    if brush is None:
        tire = load_tire("passenger")
        if ageing is not None:
            tire = dataclasses.replace(tire, tread=dataclasses.replace(
                tire.tread, contact_ageing=ageing))
        brush = SteadyBrush(tire, GridFriction(load_grid("default")))
    rows = []
    for T_C in TEMPS_C:
        for v in SPEEDS:
            for Fz in LOADS:
                for name, y in curves(brush, T_C, v, Fz, n).items():
                    rows.append({"T_C": T_C, "v": v, "Fz": Fz, "curve": name,
                                 "counts": [ripples(y, t) for t in thresholds],
                                 "largest": largest_reversal(y), "peak": float(y.max())})
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=401)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--ageing", choices=("on", "off"), default=None)
    args = ap.parse_args()
    thresholds = (0.002, 0.005)
    t0 = time.perf_counter()
    rows = run(args.points, thresholds,
               ageing=None if args.ageing is None else args.ageing == "on")
    wall = time.perf_counter() - t0
    if args.json:
        print(json.dumps({"thresholds": thresholds, "rows": rows, "seconds": wall}))
        return 0
    print(f"{len(rows)} curves, {args.points} points each, {wall:.0f} s")
    print("T_C   v   curve    ripples>0.2%Fz (2/4/6 kN)  >0.5%Fz (2/4/6 kN)  largest/Fz")
    for T_C in TEMPS_C:
        for v in SPEEDS:
            for name in CURVES:
                sel = [r for r in rows if r["T_C"] == T_C and r["v"] == v and r["curve"] == name]
                c2 = "/".join(str(r["counts"][0]) for r in sel)
                c5 = "/".join(str(r["counts"][1]) for r in sel)
                big = max(r["largest"] for r in sel)
                print(f"{T_C:4.0f} {v:4.0f}  {name:8s} {c2:>14s}             {c5:>10s}"
                      f"       {big:.4f}")
    bad = [r for r in rows if r["counts"][1] > 0]
    print(f"curves with a ripple above 0.5 % Fz: {len(bad)} of {len(rows)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
