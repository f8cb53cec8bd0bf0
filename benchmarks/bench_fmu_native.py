"""Benchmark of the native (C) brush-tire FMU: doStep through fmpy and through a C host.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_fmu_native.py [--grid default]
      [--json]

Builds the native FMU (``tirefric fmu build --native``; shipped tire ``passenger`` on the
shipped grid ``default`` unless told otherwise) at the converged defaults and steps it at a
1 ms communication step at one operating point (braking at 20 m/s with 5 % slip and a slip
angle of ~1 deg at 4 kN, 20 C; part of the patch sliding):

* through fmpy's ``FMU2Slave`` (Python host, ctypes; ``timing.fmpy_times``, shared with
  ``bench_fmu.py``): median ``fmi2DoStep`` and full cycle (setReal, doStep, getReal,
  getInteger), one instance, and four instances in lockstep (real-time factor);
* through the C host ``fmu_src/runtime/native/host_example.c`` (dlopen, no Python): median
  doStep per tire for one and for four tires, and the real-time factor of four tires;
* the wrapper's overhead (input guard, value copies, FMI calls) separately: doStep with a
  communication step of 0 (the core returns at once), from C and through fmpy; and, for
  reference, the core alone from C (``benchmarks/core_step.c``, steady inputs from rest).

The FMU is built with the real-time fidelity's table (``--fidelity realtime``, its
parameter ``fidelity`` starting at 1, docs/realtime.md): fmpy and the C host step the
real-time fidelity, and the C host the full one (``fidelity`` 0) of the same build side by
side. Targets: <= 10 us per 1 ms step, >= 25x real time for four tires, at the real-time
fidelity; the full one is ~0.4 ms per step at the defaults (docs/tire-core.md, "Cost").
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from timing import DT, fmpy_times, fmu_arguments, fmu_under_test, operating_inputs  # noqa: E402

#: The operating point as an input vector (the C host example steps the same point).
U = operating_inputs()
TARGET_US, TARGET_RTF4 = 10.0, 25.0


def c_host_times(fmu: Path, unzipdir: str, n_tires: int, steps: int, tmp: Path,
                 h: float = DT, fidelity: int | None = None) -> dict:
    """Median doStep per tire [us] and real-time factor (1 ms per step) from the C host (at
    the parameter ``fidelity`` given, else at its start value)."""
    import fmpy

    from fmu_src.make.native_build import MODEL_IDENTIFIER, NATIVE_DIR

    exe = tmp / "host"
    if not exe.exists():
        subprocess.run([shutil.which("cc") or "gcc", "-std=c99", "-O2", "-I",
                        str(Path(unzipdir) / "sources"), "-o", str(exe),
                        str(NATIVE_DIR / "host_example.c"), "-ldl", "-lm"], check=True)
    guid = fmpy.read_model_description(str(fmu)).guid
    lib = Path(unzipdir) / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so"
    md = fmpy.read_model_description(str(fmu))
    extra = [] if fidelity is None else [
        str(next(v.valueReference for v in md.modelVariables if v.name == "fidelity")),
        str(int(fidelity))]
    out = subprocess.run([str(exe), str(lib), (Path(unzipdir) / "resources").as_uri(), guid,
                          str(steps), str(n_tires), repr(h), *extra], check=True,
                         capture_output=True, text=True).stdout.splitlines()[1].split()
    d = dict(zip(out[::2], map(float, out[1::2]), strict=True))
    return {"doStep_median_us": d["median_us"], "doStep_mean_us": d["mean_us"],
            "real_time_factor": d["rtf"]}


def core_alone_us(tire: str, grid: str) -> float | None:
    """Median of tf_tire_step alone from C at the operating point [us] (bench_brush)."""
    sys.path.insert(0, str(HERE))
    from bench_brush import c_driver_times

    from lookup.grid import load_grid
    from tire_brush.params import load_tire
    from tire_brush.transient import TransientBrushTire

    model = TransientBrushTire(load_tire(tire), load_grid(grid))
    r = c_driver_times(model, U, 1, n_steps=2000, n_warm=200)
    return None if r is None else r[0]


def main(argv: list[str] | None = None) -> int:
    args = fmu_arguments(__doc__.splitlines()[0], steps=2000, warmup=200).parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmu_native_") as tmp_s:
        tmp = Path(tmp_s)
        fmu, unzipdir = fmu_under_test(args, tmp, native=True, fidelity="realtime")
        import fmpy

        start = {v.name: v.start for v in fmpy.read_model_description(str(fmu)).modelVariables}
        rt = start.get("fidelity") == "1"
        res = {"fmu": str(args.fmu or "built from --tire/--grid"), "grid": args.grid,
               "communication_step_s": DT, "steps": args.steps, "inputs": U,
               "fmpy_1": fmpy_times(str(fmu), unzipdir, 1, args.steps, args.warmup),
               "fmpy_4": fmpy_times(str(fmu), unzipdir, 4, args.steps // 2, args.warmup),
               "c_host_1": c_host_times(fmu, unzipdir, 1, args.steps, tmp),
               "c_host_4": c_host_times(fmu, unzipdir, 4, args.steps, tmp),
               "fidelity": 1 if rt else 0,
               # h = 0: the core returns at once; what remains is the FMI layers
               "c_host_h0": c_host_times(fmu, unzipdir, 1, 20 * args.steps, tmp, 0.0),
               "fmpy_h0": fmpy_times(str(fmu), unzipdir, 1, 5 * args.steps, args.warmup, 0.0)}
        if rt:    # the full fidelity of the same build, side by side
            n_full = max(50, args.steps // 10)
            res["c_host_full_1"] = c_host_times(fmu, unzipdir, 1, n_full, tmp, fidelity=0)
            res["c_host_full_4"] = c_host_times(fmu, unzipdir, 4, n_full, tmp, fidelity=0)
    core = core_alone_us(args.tire, args.grid)
    res["core_alone_median_us"] = core
    res["wrapper_overhead_us"] = res["c_host_h0"]["doStep_median_us"]
    res["fmpy_plus_wrapper_overhead_us"] = res["fmpy_h0"]["doStep_median_us"]
    res["targets"] = {"doStep_us": TARGET_US, "real_time_factor_4_tires": TARGET_RTF4}
    res["meets_targets"] = (res["c_host_1"]["doStep_median_us"] <= TARGET_US and
                            res["c_host_4"]["real_time_factor"] >= TARGET_RTF4)
    if args.json:
        json.dump(res, sys.stdout, indent=2)
        print()
        return 0
    f1, f4, c1, c4 = res["fmpy_1"], res["fmpy_4"], res["c_host_1"], res["c_host_4"]
    print(f"native FMU, 1 ms communication step, {args.steps} steps, grid {args.grid}, "
          f"fidelity {res['fidelity']} ({'real-time' if res['fidelity'] else 'full'})")
    print(f"  fmpy    doStep median {f1['doStep_median_us']:8.1f} us   cycle "
          f"{f1['cycle_median_us']:8.1f} us   4 tires: {f4['real_time_factor']:.2f}x real time")
    print(f"  C host  doStep median {c1['doStep_median_us']:8.1f} us   4 tires: "
          f"{c4['doStep_median_us']:.1f} us per tire, {c4['real_time_factor']:.2f}x real time")
    if "c_host_full_1" in res:
        g1, g4 = res["c_host_full_1"], res["c_host_full_4"]
        print(f"  full fidelity, C host  doStep median {g1['doStep_median_us']:8.1f} us   4 "
              f"tires: {g4['doStep_median_us']:.1f} us per tire, "
              f"{g4['real_time_factor']:.2f}x real time")
    if core is not None:
        print(f"  core alone, full fidelity (tf_tire_step from C, steady inputs) {core:8.1f} us")
    print(f"  overhead (doStep with h = 0): wrapper {res['wrapper_overhead_us']:.3f} us from "
          f"C, {res['fmpy_plus_wrapper_overhead_us']:.2f} us through fmpy")
    print(f"  targets: <= {TARGET_US:.0f} us per step, >= {TARGET_RTF4:.0f}x real time for 4 "
          f"tires: {'met' if res['meets_targets'] else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
