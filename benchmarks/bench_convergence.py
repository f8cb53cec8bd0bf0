"""Accuracy of the transient brush's discretisation over the shipped operating range.

Run ``python benchmarks/bench_convergence.py [--json] [--configs default,n16_tol0.1]``.

For every case of 0/20/50 C, 10/20/30 m/s, 2/4/6 kN and nine slip states (kappa -0.02,
-0.06, -0.15, -0.4, -1 at alpha 0; alpha 2, 6, 15 deg at kappa 0; kappa -0.05 with alpha
4 deg), 240 cases on the shipped default grid with the tread temperature held (thermal off),
the transient model runs 0.25 s of steady inputs at each discretisation; the result is the
mean (Fx, Fy) / Fz over the last 50 ms. Each setting is compared with a fine one (128
elements, 25 us outer step, tolerance 1e-4). Reported: cases off by more than 1 % of Fz, the
worst, and how many of the off cases fluctuate (the standard deviation of the force over
those 50 ms above 2 % of Fz: stick-slip, where a 50 ms mean is not a converged number) or
are quiet in both runs but differ (two steady branches: the discretisation picks one).
docs/tire-core.md ("Convergence") quotes the result. Takes ~5 min on one core.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))

SLIPS = [(-0.02, 0.0), (-0.06, 0.0), (-0.15, 0.0), (-0.4, 0.0), (-1.0, 0.0), (0.0, 2.0),
         (0.0, 6.0), (0.0, 15.0), (-0.05, 4.0)]
CONFIGS = {"fine": {"n_elements": 128, "dt_internal": 2.5e-5, "tol": 1e-4},
           "default": {},
           "n16_tol0.1": {"n_elements": 16, "tol": 0.1},
           "n16_tol0.03": {"n_elements": 16, "tol": 0.03},
           "n24_tol0.05": {"n_elements": 24, "tol": 0.05}}


def run(names: list[str]) -> dict:
    """Per case and setting: mean Fx/Fz, Fy/Fz and the largest standard deviation / Fz."""
    from brush_cases import without_thermal

    from lookup.grid import load_grid
    from tire_brush.friction import BranchTable, GridFriction
    from tire_brush.params import load_tire
    from tire_brush.transient import TransientBrushTire

    tire = without_thermal(load_tire("passenger"))
    table = BranchTable.from_model(GridFriction(load_grid("default")))
    out: dict = {}
    for T_C in (0.0, 20.0, 50.0):
        for vx in (10.0, 20.0, 30.0):
            for Fz in (2000.0, 4000.0, 6000.0):
                for kappa, alpha in SLIPS:
                    row = {}
                    for name in ["fine", *names]:
                        tr = TransientBrushTire(tire, table, **CONFIGS[name])
                        om = vx * (1.0 + kappa) / tire.R_e
                        vy = -vx * math.tan(math.radians(alpha))
                        o = np.array([tr.step_array(1e-3, vx, vy, om, Fz, 273.15 + T_C)
                                      for _ in range(250)])[-50:, :2] / Fz
                        row[name] = [*o.mean(axis=0).tolist(), float(o.std(axis=0).max())]
                    out[f"{T_C:g} C, {vx:g} m/s, {Fz:g} N, kappa {kappa:g}, "
                        f"alpha {alpha:g} deg"] = row
    return out


def summary(data: dict, names: list[str]) -> dict:
    """Off cases (> 1 % Fz from the fine run) per setting, split by kind."""
    res = {}
    for name in names:
        off = []
        for case, row in data.items():
            f, g = row["fine"], row[name]
            err = math.hypot(g[0] - f[0], g[1] - f[1])
            if err > 0.01:
                kind = "stick-slip" if max(f[2], g[2]) > 0.02 else "two branches"
                off.append({"case": case, "error_Fz": round(err, 4), "kind": kind})
        off.sort(key=lambda c: -c["error_Fz"])
        res[name] = {"cases": len(data), "off_by_more_than_1pc": len(off),
                     "stick_slip": sum(c["kind"] == "stick-slip" for c in off),
                     "two_branches": sum(c["kind"] == "two branches" for c in off),
                     "worst": off[:5]}
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--configs", default="default,n16_tol0.1,n16_tol0.03,n24_tol0.05")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    names = args.configs.split(",")
    res = summary(run(names), names)
    if args.json:
        print(json.dumps(res, indent=1))
        return
    for name, r in res.items():
        print(f"{name}: {r['off_by_more_than_1pc']} of {r['cases']} cases off by > 1 % Fz "
              f"({r['stick_slip']} stick-slip, {r['two_branches']} two branches)")
        for c in r["worst"]:
            print(f"    {c['error_Fz']:.3f} Fz  {c['case']}  ({c['kind']})")


if __name__ == "__main__":
    main()
