"""Benchmarks of the brush tire: the compiled core against its Python reference.

Run ``OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_brush.py [--json] [--grid G]``.

Reports medians (one core):

* transient, one 1 ms step at the converged defaults (:data:`N_TRANSIENT` elements,
  :data:`DT_INTERNAL` outer step, :data:`TOL`), braking at kappa -0.06, 27.8 m/s, 4 kN,
  0 C (the case whose old answer depended on the solver): the core from C (no Python in
  the loop: ``core_step.c``, compiled here), the core through ctypes
  (``TransientBrushTire.step_array``), and the Python reference (same algorithm in Python
  floats) with the ratio; plus the work (element sub-steps per 1 ms step);
* four tires at 1 kHz from C: the real-time factor (simulated time / wall time);
* steady: one operating point and the cost per point of a 50-point curve (one call).

Targets: the core at <= 10 us per 1 ms step and >= 25x real time for four tires (not met:
see docs/tire-core.md, "cost"). The friction is the shipped default grid (``--grid`` names
another).
"""

from __future__ import annotations

import argparse
import json
import shutil
import struct
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from timing import median_time

from tire_brush import ccore
from tire_brush.friction import BranchTable, GridFriction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush
from tire_brush.transient import DT_INTERNAL, N_TRANSIENT, TOL, TransientBrushTire

HERE = Path(__file__).parent
#: The benchmark's operating point: vx [m/s], kappa, Fz [N], T [K].
CASE = (27.8, -0.06, 4000.0, 273.15)


def c_driver_times(model: TransientBrushTire, inputs: list[float], n_tires: int,
                   n_steps: int = 400, n_warm: int = 200) -> tuple[float, float] | None:
    """Median and 90th percentile [us] of stepping ``n_tires`` tires by 1 ms from C, or
    None without a C compiler."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return None
    t = model.table
    with tempfile.TemporaryDirectory() as d:
        exe = Path(d) / "core_step"
        subprocess.run([cc, *ccore.CORE_CFLAGS, "-I",
                        str(ccore.SOURCE_DIR), "-o", str(exe), str(HERE / "core_step.c"),
                        *(str(ccore.SOURCE_DIR / s) for s in ccore.SOURCES), "-lm"],
                       check=True)
        blob = struct.pack("3i", t.log10_v.size, t.T.size, t.log10_p.size)
        for a in (t.log10_v, t.T, t.log10_p, t.values.reshape(-1), np.array([t.inv_s0])):
            blob += np.ascontiguousarray(a, dtype=np.float64).tobytes()
        blob += bytes(model._P)
        blob += struct.pack("3i", n_warm, n_steps, n_tires)
        blob += np.array([*inputs, 1e-3], dtype=np.float64).tobytes()
        (Path(d) / "in.bin").write_bytes(blob)
        out = subprocess.run([str(exe), str(Path(d) / "in.bin")], check=True,
                             capture_output=True, text=True).stdout.split()
    return float(out[0]), float(out[1])


def run(grid: str | None = None) -> dict:
    """Measure; times in microseconds."""
    from lookup.grid import load_grid

    tire = load_tire("passenger")
    table = BranchTable.from_model(GridFriction(load_grid(grid or "default")))
    vx, kappa, Fz, T = CASE
    u = [vx, 0.0, vx * (1.0 + kappa) / tire.R_e, Fz, T, 1.0, 0.0, 0.0]
    res: dict = {"grid": grid or "default", "case": {"vx": vx, "kappa": kappa, "Fz": Fz,
                                                     "T_K": T},
                 "defaults": {"n_elements": N_TRANSIENT, "dt_internal_s": DT_INTERNAL,
                              "tol": TOL}}
    model = TransientBrushTire(tire, table)
    for _ in range(200):
        model.step_array(1e-3, *u)
    w0 = model.work()
    step = median_time(lambda: model.step_array(1e-3, *u), 15, 40)
    res["substeps_per_step"] = (model.work() - w0) / (15 * 40 + 40)
    res["core_ctypes_us"] = step * 1e6
    c1 = c_driver_times(model, u, 1)
    c4 = c_driver_times(model, u, 4)
    if c1 is not None:
        res["core_c_us"], res["core_c_p90_us"] = c1
        res["four_tires_us"] = c4[0]
        res["four_tires_realtime_factor"] = 1e3 / c4[0]
    refm = TransientBrushTire(tire, table, backend="reference")
    for _ in range(20):
        refm.step_array(1e-3, *u)
    res["reference_us"] = median_time(lambda: refm.step_array(1e-3, *u), 3, 2) * 1e6
    res["reference_over_core"] = res["reference_us"] / res.get("core_c_us", step * 1e6)
    steady = SteadyBrush(tire, table)
    point = median_time(lambda: steady.solve(-0.05, 0.01, 20.0, 4000.0, 293.15), 11, 5)
    k = np.linspace(-0.3, 0.0, 50)
    curve = median_time(lambda: steady.solve(k, 0.0, 20.0, 4000.0, 293.15), 5, 2)
    res["steady_point_us"] = point * 1e6
    res["steady_curve_per_point_us"] = curve / k.size * 1e6
    res["targets"] = {"core_us_per_step": 10.0, "four_tires_realtime_factor": 25.0}
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print JSON")
    ap.add_argument("--grid", default=None, help="grid file or name (default: shipped)")
    args = ap.parse_args()
    r = run(args.grid)
    if args.json:
        print(json.dumps(r, indent=2))
        return
    d = r["defaults"]
    print(f"transient 1 ms step, {d['n_elements']} elements, outer step "
          f"{d['dt_internal_s'] * 1e3:g} ms, tol {d['tol']:g} (0 C, kappa -0.06, 27.8 m/s):")
    print(f"  element sub-steps per step: {r['substeps_per_step']:.0f}")
    if "core_c_us" in r:
        print(f"  core from C:      {r['core_c_us']:.0f} us (p90 {r['core_c_p90_us']:.0f}; "
              f"target <= 10 us)")
        print(f"  four tires from C: {r['four_tires_us']:.0f} us per 1 ms: "
              f"{r['four_tires_realtime_factor']:.2f}x real time (target >= 25x)")
    print(f"  core via ctypes:  {r['core_ctypes_us']:.0f} us")
    print(f"  Python reference: {r['reference_us']:.0f} us ({r['reference_over_core']:.0f}x "
          f"the core)")
    print(f"steady point: {r['steady_point_us']:.0f} us; per point of a 50-point curve: "
          f"{r['steady_curve_per_point_us']:.0f} us")


if __name__ == "__main__":
    main()
