"""Cost of the tire's extra channels: camber, the rolling-resistance moment and water.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_channels.py [--json]

Steps the transient tire (the compiled core through ctypes, as the FMUs run it; the FMU layers
add a constant ~1 us, ``bench_fmu_native.py``) at 1 ms steps, braking at 20 m/s with 5 % slip
and ~1 deg of slip angle at 4 kN, 20 C, and reports the median step time of:

* ``base``: no camber, no rolling-resistance table, dry road (what the core computed before
  the channels existed);
* ``camber``: gamma = 0.02 rad;
* ``rolling``: with the rolling-resistance table (My and the tread heating);
* ``all_dry``: both;
* on the grid of the wet reference road (``r117_wet``, which has a wet branch): ``dry`` at
  water_depth 0 and ``wet`` at 1 mm (the wet lookup of every step: the drainage time changes
  with the rolling speed).

Ratios: ``all_dry / base`` (target <= 1.1) and ``wet / dry`` (target <= 1.2). Medians of 15
repeats of 40 steps after 200 warm-up steps.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from timing import median_time  # noqa: E402

from lookup.grid import load_grid  # noqa: E402
from lookup.grid.store import resolve_grid_path  # noqa: E402
from lookup.grid.wet import load_wet  # noqa: E402
from tire_brush.params import load_tire  # noqa: E402
from tire_brush.rolling_resistance import rolling_table  # noqa: E402
from tire_brush.transient import TransientBrushTire  # noqa: E402

VX, KAPPA, FZ, T = 20.0, -0.05, 4000.0, 293.15


def _time(model: TransientBrushTire, gamma: float, water: float) -> float:
    """Median step time [us] at the benchmark's operating point."""
    R = model.params.R_e
    u = (VX, 0.35, VX * (1.0 + KAPPA) / R, FZ, T, 1.0, gamma, water)
    for _ in range(200):
        model.step_array(1e-3, *u)
    return 1e6 * median_time(lambda: model.step_array(1e-3, *u), 15, 40)


def run() -> dict:
    tire = load_tire("passenger")
    grid = load_grid("default")
    table, _ = rolling_table(tire, grid)
    res: dict = {"case": {"vx": VX, "kappa": KAPPA, "alpha_deg": 1.0, "Fz": FZ, "T_K": T}}

    def model(g=grid, rolling=None, wet=None):
        m = TransientBrushTire(tire, g)
        if rolling is not None:
            m.set_rolling(rolling)
        if wet is not None:
            m.set_wet(wet, texture_depth=7e-4)
        return m

    res["base_us"] = _time(model(), 0.0, 0.0)
    res["camber_us"] = _time(model(), 0.02, 0.0)
    res["rolling_us"] = _time(model(rolling=table), 0.0, 0.0)
    res["all_dry_us"] = _time(model(rolling=table), 0.02, 0.0)
    wgrid = load_grid("r117_wet")
    wet = load_wet(resolve_grid_path("r117_wet"))
    wtable, _ = rolling_table(tire, wgrid)
    res["wet_grid_dry_us"] = _time(model(wgrid, wtable, wet), 0.0, 0.0)
    res["wet_grid_wet_us"] = _time(model(wgrid, wtable, wet), 0.0, 1e-3)
    res["channels_over_base"] = res["all_dry_us"] / res["base_us"]
    res["wet_over_dry"] = res["wet_grid_wet_us"] / res["wet_grid_dry_us"]
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args()
    res = run()
    if args.json:
        print(json.dumps(res, indent=2))
        return
    print("transient tire step (1 ms, braking 20 m/s, 5 % slip, 1 deg), median us")
    for k in ("base", "camber", "rolling", "all_dry", "wet_grid_dry", "wet_grid_wet"):
        print(f"  {k:14s} {res[k + '_us']:9.1f}")
    print(f"  channels / base  {res['channels_over_base']:.3f}  (target <= 1.1)")
    print(f"  wet / dry        {res['wet_over_dry']:.3f}  (target <= 1.2)")


if __name__ == "__main__":
    main()
