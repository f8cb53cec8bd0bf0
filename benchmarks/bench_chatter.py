"""Chatter of the transient tire at held inputs, and the steady peak, with and without the
contact age (docs/tire-core.md, "contact age").

Run ``python benchmarks/bench_chatter.py [--json] [--ageing on|off|both]``.

Transient: the shipped passenger tire (thermal state off, so the inputs are truly held) on the
default grid at 0 and 20 C, 10 and 20 m/s, 4 kN, kappa -0.02 / -0.05 / -0.1, stepped at 1 ms
for 0.6 s from rest; over the last 0.4 s the mean, the standard deviation and the largest
step-to-step change of Fx, all in % of Fz (a tire at held inputs should give a constant
force: what remains is stick-slip of the tread). Steady: the steady brush's peak
``max |Fx| / Fz`` over kappa 0 .. -1 (1001 points) at 0 / 20 / 50 C, 10 m/s, 4 kN, and the
kappa of the peak. Wall time of each part is printed (one core, ~1-2 min in all).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time

import numpy as np

TEMPS_C = (0.0, 20.0)
SPEEDS = (10.0, 20.0)
KAPPAS = (-0.02, -0.05, -0.1)
FZ = 4000.0
DT, T_END, T_TAIL = 1e-3, 0.6, 0.4
PEAK_TEMPS_C = (0.0, 20.0, 50.0)


def _tire(ageing: bool):
    from tire_brush.params import load_tire

    tire = load_tire("passenger")
    tire = dataclasses.replace(tire, thermal=dataclasses.replace(tire.thermal, enabled=False))
    return dataclasses.replace(tire, tread=dataclasses.replace(tire.tread,
                                                               contact_ageing=ageing))


def chatter(ageing: bool, grid) -> list[dict]:
    """One row per held operating point: mean, std and largest step of Fx [% Fz]."""
    from tire_brush.transient import TransientBrushTire

    tire = _tire(ageing)
    rows = []
    n, tail = round(T_END / DT), round(T_TAIL / DT)
    for T_C in TEMPS_C:
        for v in SPEEDS:
            for kappa in KAPPAS:
                tr = TransientBrushTire(tire, grid)
                om = v * (1.0 + kappa) / tire.R_e
                fx = np.array([tr.step_array(DT, v, 0.0, om, FZ, 273.15 + T_C)[0]
                               for _ in range(n)])[-tail:] / FZ * 100.0
                rows.append({"T_C": T_C, "v": v, "kappa": kappa, "mean": float(fx.mean()),
                             "std": float(fx.std()),
                             "max_step": float(np.abs(np.diff(fx)).max())})
    return rows


def peaks(ageing: bool, grid) -> list[dict]:
    """Steady peak |Fx| / Fz and its kappa at 10 m/s, 4 kN."""
    from tire_brush.steady import SteadyBrush

    brush = SteadyBrush(_tire(ageing), grid)
    kappa = -np.linspace(0.0, 1.0, 1001)
    rows = []
    for T_C in PEAK_TEMPS_C:
        mu = np.abs(brush.solve(kappa, 0.0, 10.0, FZ, 273.15 + T_C).Fx) / FZ
        i = int(np.argmax(mu))
        rows.append({"T_C": T_C, "peak": float(mu[i]), "kappa": float(kappa[i]),
                     "locked": float(mu[-1])})
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--ageing", choices=("on", "off", "both"), default="both")
    args = ap.parse_args()
    from lookup.grid import load_grid
    from tire_brush.friction import GridFriction

    grid = GridFriction(load_grid("default"))
    out = {}
    for label in (("off", "on") if args.ageing == "both" else (args.ageing,)):
        t0 = time.perf_counter()
        ch = chatter(label == "on", grid)
        t1 = time.perf_counter()
        pk = peaks(label == "on", grid)
        t2 = time.perf_counter()
        out[label] = {"chatter": ch, "peaks": pk, "seconds": [t1 - t0, t2 - t1]}
    if args.json:
        print(json.dumps(out))
        return 0
    for label, r in out.items():
        print(f"contact age {label}: transient {r['seconds'][0]:.0f} s, "
              f"steady {r['seconds'][1]:.0f} s")
        print("  T_C    v  kappa   mean Fx   std    largest step   [% Fz]")
        for c in r["chatter"]:
            print(f"  {c['T_C']:3.0f} {c['v']:4.0f} {c['kappa']:6.2f}  {c['mean']:8.2f} "
                  f"{c['std']:6.2f}  {c['max_step']:8.2f}")
        print("  T_C  steady peak |Fx|/Fz  at kappa   locked")
        for p in r["peaks"]:
            print(f"  {p['T_C']:3.0f}  {p['peak']:8.3f}          {p['kappa']:7.3f}  "
                  f"{p['locked']:7.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
