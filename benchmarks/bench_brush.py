"""Benchmarks of the brush tire (issue 4): steady-state point and transient step cost.

Run ``python benchmarks/bench_brush.py [--json] [--grid GRID]``.

* steady: median wall time of one operating point (``SteadyBrush.solve`` with scalars, the
  default 64 cells; target <= 2 ms) and the cost per point of a 50-point curve solved in one
  call (what ``tirefric tire curve`` and the braking force maps do);
* transient: median wall time of one ``TransientBrushTire.step`` of 1 ms (one internal step)
  at the default discretisation (100 elements on the patch, 1 ms internal step; target
  <= 100 us), during combined braking and cornering with the thermal state and the compliant
  belt on.

The friction is the shipped default grid when it exists (``--grid`` chooses another grid
file or name), else a synthetic grid of the default spec's shape.
"""

from __future__ import annotations

import argparse
import json

import numpy as np
from timing import median_time

from lookup.grid import FrictionGrid
from tire_brush.friction import BranchTable, GridFriction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire


def synthetic_grid() -> FrictionGrid:
    """A smooth grid shaped like the default spec (61 speeds, 15 temperatures, 6 pressures)."""
    v = np.logspace(-6, np.log10(40.0), 61)
    T = np.linspace(253.15, 393.15, 15)
    p = np.logspace(np.log10(5e4), np.log10(2e6), 6)
    x = np.log10(v / 0.01)[:, None, None] - 0.05 * (T[None, :, None] - 293.15)
    mu_c = 0.4 + 0.8 * np.exp(-0.1 * x * x) + 0.0 * p[None, None, :]
    mu_h = mu_c * (1.0 - 0.3 * (v * v / (v * v + 0.01))[:, None, None])
    dT = 60.0 * (v / (v + 1.0))[:, None, None] + 0.0 * mu_c
    return FrictionGrid.from_arrays(v, T, p, {"mu_cold": mu_c, "mu_hot": mu_h, "dT_flash": dT},
                                    s0_m=2e-4, D_m=1e-3)


def load_friction(name: str | None) -> tuple[BranchTable, str]:
    """The benchmark's friction table and a label."""
    from lookup.grid import load_grid

    if name is None:
        try:
            return BranchTable.from_model(GridFriction(load_grid("default"))), "default grid"
        except Exception:  # no shipped grid yet: any failure falls back to the synthetic one
            return BranchTable.from_model(GridFriction(synthetic_grid())), "synthetic grid"
    return BranchTable.from_model(GridFriction(load_grid(name))), name


def run(grid: str | None = None) -> dict:
    """Measure; returns the numbers (times in microseconds)."""
    tire = load_tire("passenger")
    table, label = load_friction(grid)
    T = 293.15
    steady = SteadyBrush(tire, table)
    steady.solve(-0.05, 0.0, 20.0, 4000.0, T)
    point = median_time(lambda: steady.solve(-0.05, 0.01, 20.0, 4000.0, T), 11, 5)
    kappa = np.linspace(-0.3, 0.0, 50)
    curve = median_time(lambda: steady.solve(kappa, 0.0, 20.0, 4000.0, T), 7, 2)

    model = TransientBrushTire(tire, table)
    omega = 20.0 * 0.95 / tire.R_e
    for _ in range(200):
        model.step(1e-3, 20.0, 0.4, omega, 4000.0, T)
    step = median_time(lambda: model.step(1e-3, 20.0, 0.4, omega, 4000.0, T), 15, 200)
    return {"friction": label, "steady_point_us": point * 1e6,
            "steady_curve_per_point_us": curve / kappa.size * 1e6,
            "steady_n_elements": steady.n_elements,
            "transient_step_us": step * 1e6, "transient_n_elements": model.n_elements,
            "transient_dt_internal_s": model.dt_internal,
            "targets_us": {"steady_point": 2000.0, "transient_step": 100.0}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    ap.add_argument("--grid", default=None, help="grid file or name (default: shipped)")
    args = ap.parse_args()
    res = run(args.grid)
    if args.json:
        print(json.dumps(res, indent=2))
        return
    print(f"friction: {res['friction']}")
    print(f"steady point ({res['steady_n_elements']} cells): {res['steady_point_us']:.0f} us "
          f"(target <= 2000 us); per point of a 50-point curve: "
          f"{res['steady_curve_per_point_us']:.0f} us")
    print(f"transient step ({res['transient_n_elements']} elements, dt = 1 ms): "
          f"{res['transient_step_us']:.0f} us (target <= 100 us)")


if __name__ == "__main__":
    main()
