"""Benchmark of the brush-tire FMU through fmpy: cost of one doStep, real-time factor.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_fmu.py [--grid default] [--json]

Builds the FMU (shipped tire ``passenger`` on the shipped grid ``default`` unless told
otherwise) at the default settings (those of ``tire_brush.transient``: the compiled tire core
at its converged defaults) and drives it with
fmpy's ``FMU2Slave`` step by step at a 1 ms communication step, as a vehicle simulator would:
set the inputs, ``doStep``, get the outputs. The operating point is that of
``bench_fmu_native.py`` (``timing.OPERATING_POINT``: braking at 20 m/s with 5 % slip and a slip
angle of 0.86 deg at 4 kN, part of the patch sliding).

Reports (target: doStep <= 40 us, i.e. the FMU layers add <= 30 us to a <= 10 us core):

* median and 90th percentile of ``fmi2DoStep`` alone, and of the whole cycle (setReal,
  doStep, getReal, getInteger) for one instance (``timing.fmpy_times``, shared with
  ``bench_fmu_native.py``);
* the same model stepped in Python directly, and the difference: what the FMU layers
  (pythonfmu, the slave, the input guard) add to the core;
* four instances (the four wheels) stepped in lockstep: wall-clock time per simulated second
  (real-time factor; below 1 is faster than real time).
"""

from __future__ import annotations

import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from timing import DT, fmpy_times, fmu_arguments, fmu_under_test, operating_inputs  # noqa: E402

TARGET_US = 40.0


def bench_python_model(tire: str, grid: str, steps: int, warmup: int) -> float:
    """Median time of TransientBrushTire.step at the operating point [s]."""
    from lookup.grid import load_grid
    from tire_brush.params import load_tire
    from tire_brush.transient import TransientBrushTire

    model = TransientBrushTire(load_tire(tire), load_grid(grid))
    u = operating_inputs()
    times = []
    for k in range(warmup + steps):
        t0 = time.perf_counter()
        model.step(DT, *u)
        if k >= warmup:
            times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    args = fmu_arguments(__doc__.splitlines()[0], steps=3000, warmup=300).parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmu_") as tmp:
        fmu, unzipdir = fmu_under_test(args, Path(tmp), native=False)
        one = fmpy_times(str(fmu), unzipdir, 1, args.steps, args.warmup)
        four = fmpy_times(str(fmu), unzipdir, 4, args.steps, args.warmup)

    py = bench_python_model(args.tire, args.grid, args.steps, args.warmup)
    res = {
        "fmu": str(args.fmu or "built from --tire/--grid"), "grid": args.grid,
        "communication_step_s": DT, "steps": args.steps,
        "doStep_median_us": one["doStep_median_us"],
        "doStep_p90_us": one["doStep_p90_us"],
        "cycle_median_us": one["cycle_median_us"],
        "python_model_step_median_us": 1e6 * py,
        "fmu_layers_us": one["doStep_median_us"] - 1e6 * py,
        "four_instances_doStep_median_us": four["doStep_median_us"],
        "four_instances_wall_per_simulated_s": 1.0 / four["real_time_factor"],
        "target_doStep_us": TARGET_US,
    }
    res["meets_target"] = res["doStep_median_us"] <= TARGET_US
    if args.json:
        json.dump(res, sys.stdout, indent=2)
        print()
        return 0
    print(f"FMU through fmpy, 1 ms communication step, {args.steps} steps, grid {args.grid}")
    print(f"  doStep       median {res['doStep_median_us']:7.1f} us   p90 "
          f"{res['doStep_p90_us']:7.1f} us   (target <= {TARGET_US:.0f} us: "
          f"{'met' if res['meets_target'] else 'NOT met'})")
    print(f"  full cycle   median {res['cycle_median_us']:7.1f} us   (setReal, doStep, getReal, "
          f"getInteger)")
    print(f"  Python model median {res['python_model_step_median_us']:7.1f} us   "
          f"(TransientBrushTire.step alone); the FMU layers add "
          f"{res['fmu_layers_us']:.1f} us")
    print(f"  4 instances  doStep median {res['four_instances_doStep_median_us']:7.1f} us; "
          f"{res['four_instances_wall_per_simulated_s']:.3f} s wall per simulated second "
          f"(real-time factor; < 1 is faster than real time)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
