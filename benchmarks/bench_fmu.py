"""Benchmark of the brush-tire FMU through fmpy: cost of one doStep, real-time factor.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_fmu.py [--grid default] [--json]

Builds the FMU (shipped tire ``passenger`` on the shipped grid ``default`` unless told
otherwise) at the default settings (those of ``tire_brush.transient``: the compiled tire core
at its converged defaults) and drives it with
fmpy's ``FMU2Slave`` step by step at a 1 ms communication step, as a vehicle simulator would:
set the six inputs, ``doStep``, get the outputs. The operating point is braking at 20 m/s with
5 % slip and a 1 deg slip angle at 4 kN (part of the patch sliding).

Reports (target: doStep <= 40 us, i.e. the FMU layers add <= 30 us to a <= 10 us core):

* median and 90th percentile of ``fmi2DoStep`` alone, and of the whole cycle (setReal,
  doStep, getReal, getInteger) for one instance;
* the same model stepped in Python directly, and the difference: what the FMU layers
  (pythonfmu, the slave, the input guard) add to the core;
* four instances (the four wheels) stepped in lockstep: wall-clock time per simulated second
  (real-time factor; below 1 is faster than real time).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

INPUTS = ("vx", "vy", "omega", "Fz", "T_surface", "mu_scale", "gamma", "water_depth")
OUTPUTS = ("Fx", "Fy", "Mz", "kappa", "alpha", "mu_eff", "mu_slide", "sliding_fraction",
           "dT_flash_max", "T_tread")
R_E = 0.31
DT = 1e-3
TARGET_US = 40.0


def operating_point() -> list[float]:
    """Braking at 20 m/s, kappa = -0.05, alpha = 1 deg, 4 kN, 20 C."""
    vx = 20.0
    return [vx, -vx * math.tan(math.radians(1.0)), vx * 0.95 / R_E, 4000.0, 293.15, 1.0, 0.0,
            0.0]


class Instance:
    """One FMU instance (fmpy FMU2Slave) initialised and ready to step."""

    def __init__(self, fmu: Path, unzipdir: str, name: str) -> None:
        import fmpy
        from fmpy.fmi2 import FMU2Slave

        md = fmpy.read_model_description(str(fmu))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                             modelIdentifier=md.coSimulation.modelIdentifier,
                             instanceName=name)
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.vin = [vr[n] for n in INPUTS]
        self.vout = [vr[n] for n in OUTPUTS]
        self.vstatus = [vr["input_status"]]
        self.t = 0.0

    def cycle(self, u: list[float]) -> tuple[float, float]:
        """One communication step; returns (doStep time, cycle time) [s]."""
        c0 = time.perf_counter()
        self.fmu.setReal(self.vin, u)
        t0 = time.perf_counter()
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=DT)
        t1 = time.perf_counter()
        self.fmu.getReal(self.vout)
        self.fmu.getInteger(self.vstatus)
        c1 = time.perf_counter()
        self.t += DT
        return t1 - t0, c1 - c0

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def bench_python_model(tire: str, grid: str, steps: int, warmup: int) -> float:
    """Median time of TransientBrushTire.step at the operating point [s]."""
    from lookup.grid import load_grid
    from tire_brush.params import load_tire
    from tire_brush.transient import TransientBrushTire

    model = TransientBrushTire(load_tire(tire), load_grid(grid))
    u = operating_point()
    times = []
    for k in range(warmup + steps):
        t0 = time.perf_counter()
        model.step(DT, *u)
        if k >= warmup:
            times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tire", default="passenger", help="tire TOML file or shipped name")
    ap.add_argument("--grid", default="default", help="grid file or shipped name")
    ap.add_argument("--fmu", default=None, help="use this FMU instead of building one")
    ap.add_argument("--steps", type=int, default=3000, help="timed steps per instance")
    ap.add_argument("--warmup", type=int, default=300, help="untimed steps first")
    ap.add_argument("--json", action="store_true", help="print JSON")
    args = ap.parse_args(argv)

    import fmpy

    with tempfile.TemporaryDirectory(prefix="bench_fmu_") as tmp:
        if args.fmu:
            fmu = Path(args.fmu)
        else:
            from fmu_src.make.build import build_fmu

            fmu = build_fmu(args.tire, args.grid, Path(tmp) / "BrushTire.fmu").path
        unzipdir = fmpy.extract(str(fmu), str(Path(tmp) / "unzipped"))
        u = operating_point()

        one = Instance(fmu, unzipdir, "one")
        do, cyc = [], []
        for k in range(args.warmup + args.steps):
            a, b = one.cycle(u)
            if k >= args.warmup:
                do.append(a)
                cyc.append(b)
        one.close()

        four = [Instance(fmu, unzipdir, f"wheel{w}") for w in range(4)]
        for _ in range(args.warmup):
            for inst in four:
                inst.cycle(u)
        do4 = []
        w0 = time.perf_counter()
        for _ in range(args.steps):
            for inst in four:
                do4.append(inst.cycle(u)[0])
        wall = time.perf_counter() - w0
        for inst in four:
            inst.close()

    py = bench_python_model(args.tire, args.grid, args.steps, args.warmup)
    res = {
        "fmu": str(args.fmu or "built from --tire/--grid"), "grid": args.grid,
        "communication_step_s": DT, "steps": args.steps,
        "doStep_median_us": 1e6 * statistics.median(do),
        "doStep_p90_us": 1e6 * float(np.percentile(do, 90)),
        "cycle_median_us": 1e6 * statistics.median(cyc),
        "python_model_step_median_us": 1e6 * py,
        "fmu_layers_us": 1e6 * (statistics.median(do) - py),
        "four_instances_doStep_median_us": 1e6 * statistics.median(do4),
        "four_instances_wall_per_simulated_s": wall / (args.steps * DT),
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
