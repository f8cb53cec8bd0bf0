"""Timing helper shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``,
which puts this folder on ``sys.path``)."""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from pathlib import Path


def median_time(fn: Callable[[], object], repeats: int, number: int = 1) -> float:
    """Median over ``repeats`` of the mean time of ``number`` calls of ``fn`` [s]."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        times.append((time.perf_counter() - t0) / number)
    return statistics.median(times)


# -- stepping an FMU through fmpy (bench_fmu.py, bench_fmu_native.py) -------------------------
#: Communication step of the FMU benchmarks [s].
DT = 1e-3
#: Their operating point, in the order of the tire's inputs (tire_brush.signals): braking at
#: 20 m/s with 5 % slip (R_e 0.31 m) and a slip angle of 0.86 deg (vy 0.3 m/s) at 4 kN, 20 C,
#: dry, no camber: part of the patch slides. The C host example uses the same point
#: (fmu_src/runtime/native/host_example.c, after its first 20 ms).
OPERATING_POINT = {"vx": 20.0, "vy": 0.3, "omega": 20.0 * 0.95 / 0.31, "Fz": 4000.0,
                   "T_surface": 293.15, "mu_scale": 1.0, "gamma": 0.0, "water_depth": 0.0}


def operating_inputs() -> list[float]:
    """:data:`OPERATING_POINT` as an input vector (every input of the table, in order)."""
    from tire_brush.signals import INPUT_NAMES

    return [OPERATING_POINT[n] for n in INPUT_NAMES]


def fmpy_times(fmu: str, unzipdir: str, n_inst: int, steps: int, warmup: int,
               h: float = DT) -> dict:
    """Step ``n_inst`` instances in lockstep at :data:`OPERATING_POINT` through fmpy.

    Returns the median ``fmi2DoStep`` and whole-cycle (setReal, doStep, getReal, getInteger)
    times per instance [us] and the real-time factor (simulated over wall time, the
    communication clock advancing by :data:`DT` per step whatever ``h``)."""
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    from tire_brush.signals import INPUT_NAMES, OUTPUT_NAMES

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    vin, vout = [vr[n] for n in INPUT_NAMES], [vr[n] for n in OUTPUT_NAMES]
    vstatus = [vr["input_status"]]
    u = operating_inputs()
    inst = []
    for i in range(n_inst):
        f = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"w{i}")
        f.instantiate()
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.exitInitializationMode()
        inst.append(f)
    do, cyc, t, wall = [], [], 0.0, 0.0
    for k in range(warmup + steps):
        w0 = time.perf_counter()
        for f in inst:
            c0 = time.perf_counter()
            f.setReal(vin, u)
            t0 = time.perf_counter()
            f.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t1 = time.perf_counter()
            f.getReal(vout)
            f.getInteger(vstatus)
            c1 = time.perf_counter()
            if k >= warmup:
                do.append(t1 - t0)
                cyc.append(c1 - c0)
        if k >= warmup:
            wall += time.perf_counter() - w0
        t += DT
    for f in inst:
        f.terminate()
        f.freeInstance()
    do_sorted = sorted(do)
    return {"doStep_median_us": 1e6 * statistics.median(do),
            "doStep_p90_us": 1e6 * do_sorted[int(0.9 * (len(do_sorted) - 1))],
            "cycle_median_us": 1e6 * statistics.median(cyc),
            "real_time_factor": steps * DT / wall}


def fmu_arguments(description: str, steps: int, warmup: int) -> argparse.ArgumentParser:
    """The FMU benchmarks' common options: tire, grid, an FMU to use instead of a build, the
    number of timed and untimed steps, JSON output."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--tire", default="passenger", help="tire TOML file or shipped name")
    ap.add_argument("--grid", default="default", help="grid file or shipped name")
    ap.add_argument("--fmu", default=None, help="use this FMU instead of building one")
    ap.add_argument("--steps", type=int, default=steps, help="timed steps")
    ap.add_argument("--warmup", type=int, default=warmup, help="untimed steps first")
    ap.add_argument("--json", action="store_true", help="print JSON")
    return ap


def fmu_under_test(args: argparse.Namespace, tmp: Path, native: bool,
                   fidelity: str = "full") -> tuple[Path, str]:
    """The FMU named by ``--fmu``, or one built from ``--tire``/``--grid`` into ``tmp`` (the
    native flavour for this platform, or the pythonfmu one; ``fidelity="realtime"`` packs the
    real-time fidelity's table too), and its unzipped folder."""
    import fmpy

    if args.fmu:
        fmu = Path(args.fmu)
    elif native:
        from fmu_src.make.native_build import build_native_fmu
        from fmu_src.make.stage import BuildOptions

        fmu = build_native_fmu(args.tire, args.grid, tmp / "BrushTireNative.fmu",
                               BuildOptions(fidelity=fidelity), platforms=("linux64",)).path
    else:
        from fmu_src.make.build import build_fmu

        fmu = build_fmu(args.tire, args.grid, tmp / "BrushTire.fmu").path
    return fmu, fmpy.extract(str(fmu), str(tmp / "unzipped"))
