"""Agreement and cost of the real-time fidelity against the full tire (docs/realtime.md).

Run:  OMP_NUM_THREADS=1 python benchmarks/bench_realtime.py [--tire passenger]
      [--grid default] [--sections steady,steps,lane,abs,cost] [--json]
      OMP_NUM_THREADS=1 python benchmarks/bench_realtime.py --grid r117_wet --sections wet

Prints, for the shipped tire on the shipped grid (the full model as it is in this checkout;
the patch table is built from its steady march, cached by its hash):

* ``steady``: Fx, Fy, Mz of the real-time tire held at each operating point until settled,
  against the full model's steady march (``SteadyBrush``: the full model's steady state with
  the belt's twist), over 0 / 20 / 50 C (``--temps``; these are nodes of the default table,
  5 / 25 / 45 C lie between them), 5 / 15 / 30 m/s, 2 / 4 / 6 kN, kappa 0 .. -1, alpha
  0 .. 15 deg and combined slip: the largest and the 95th-percentile difference of Fx, Fy
  over Fz (target 2 %), of Mz over the largest |Mz| of the full model at that temperature,
  speed and load (target 5 %), and the points beyond the targets;
* ``steps``: a step in slip angle (0 -> 2 deg) and in slip ratio (0 -> -3 %) at 10 / 20 /
  30 m/s, 4 kN, 20 C, both tires from the settled state before it: the relaxation length (the
  distance rolled until the force has made 63.2 % of its change; target within 10 %);
* ``lane``: a sine steer (slip angle 4 deg at 0.5 and 1 Hz, 20 m/s, 4 kN, 20 C): the RMS of
  the difference of Fy over the RMS of the full model's Fy (target 3 %);
* ``abs``: the rule-based ABS stop of the quarter car through the native FMU (fidelity 0 and
  1, the same build) from 27.8 m/s at 0 / 20 / 40 C: the stopping distances (target 2 %);
* ``cost``: median native doStep per 1 ms step of both fidelities through the C host example
  (one and four tires, the real-time factor of four), the core alone per step, and a
  callgrind instruction count per step of the core at both fidelities if valgrind is
  installed (the machine-independent figure; target <= 40 k instructions, 10 us);
* ``wet`` (a grid with a wet branch, e.g. r117_wet; its table has a layer per water depth):
  steady Fx, Fy, Mz of the real-time tire on water 0 / 0.5 / 1 mm (kappa -0.02 .. -1, alpha
  2 .. 10 deg, 20 C, 10 and 25 m/s, 4 kN) against the full model's steady march on the wet
  friction it reads there (the branch at the depth and the point's drainage time,
  :mod:`tire_brush.wet_friction`); one ABS stop at 1 mm through both fidelities of one
  native build, and the wet-grip test's stop (90 -> 20 km/h); and the core's cost per step
  at 0.5 mm (two depth layers read) and 1 mm. Its parts alone: ``wet-steady`` (at the depths
  of ``--wet-depths``, e.g. ``0.25,0.5,0.75`` between the layers), ``wet-cost``,
  ``wet-stops``; ``--linear-depth`` reads the table linearly between its layers (its depth
  law dropped, for comparison).
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from lookup.grid.store import load_grid  # noqa: E402
from tire_brush.params import load_tire  # noqa: E402
from tire_brush.realtime_build import cached_patch_table, settled  # noqa: E402
from tire_brush.steady import SteadyBrush  # noqa: E402
from tire_brush.transient import TransientBrushTire  # noqa: E402

C0 = 273.15
TEMPS = (0.0, 20.0, 50.0)
SPEEDS = (5.0, 15.0, 30.0)
LOADS = (2000.0, 4000.0, 6000.0)
KAPPAS = (-0.01, -0.02, -0.04, -0.07, -0.1, -0.15, -0.25, -0.5, -1.0)
ALPHAS_DEG = (0.5, 1.0, 2.0, 4.0, 6.0, 8.0, 11.0, 15.0)
COMBINED = ((-0.03, 2.0), (-0.05, 4.0), (-0.1, 8.0), (-0.2, 4.0), (-0.5, 10.0))


def slip_points() -> list[tuple[float, float]]:
    """(kappa, alpha [rad]) of the steady sweep: pure longitudinal, pure lateral, combined."""
    pts = [(k, 0.0) for k in KAPPAS] + [(0.0, math.radians(a)) for a in ALPHAS_DEG]
    return pts + [(k, math.radians(a)) for k, a in COMBINED]


def steady_sweep(tp, grid, table, temps=TEMPS, speeds=SPEEDS, loads=LOADS,
                 points=None) -> dict:
    """The steady agreement (module docstring): per case the full and real-time Fx, Fy, Mz."""
    points = slip_points() if points is None else points
    full = SteadyBrush(tp, grid)
    rt = TransientBrushTire(tp, grid, patch=table, thermal=False)
    rows = []
    for T in temps:
        for vx in speeds:
            for Fz in loads:
                k = np.array([p[0] for p in points])
                a = np.array([p[1] for p in points])
                st = full.solve(k, a, vx, Fz, T + C0)
                mz_peak = float(np.max(np.abs(st.Mz)))
                for i, (kap, al) in enumerate(points):
                    r = settled(rt, kap, al, vx, Fz, T + C0)[:3]
                    rows.append({"T": T, "vx": vx, "Fz": Fz, "kappa": kap,
                                 "alpha_deg": math.degrees(al),
                                 "full": [float(st.Fx[i]), float(st.Fy[i]), float(st.Mz[i])],
                                 "rt": r, "mz_peak": mz_peak})
    ex = np.array([(r["rt"][0] - r["full"][0]) / r["Fz"] for r in rows])
    ey = np.array([(r["rt"][1] - r["full"][1]) / r["Fz"] for r in rows])
    em = np.array([(r["rt"][2] - r["full"][2]) / max(r["mz_peak"], 1e-9) for r in rows])
    off = [r for r, x, y, m in zip(rows, ex, ey, em, strict=True)
           if abs(x) > 0.02 or abs(y) > 0.02 or abs(m) > 0.05]
    # where the two disagree, the full model's transient tire held at the point (its belt's
    # twist may settle on another of several steady states than the steady iteration's, and
    # at 0 C its tread stick-slips): the mean of its last 100 ms
    tr = TransientBrushTire(tp, grid, thermal=False)
    still = 0
    for r in off:
        f = settled(tr, r["kappa"], math.radians(r["alpha_deg"]), r["vx"], r["Fz"],
                    r["T"] + C0, distance=8.0, tail=100)[:3]
        r["full_transient"] = f
        d = np.abs(np.array(r["rt"]) - np.array(f))
        r["beyond_transient"] = bool(d[0] > 0.02 * r["Fz"] or d[1] > 0.02 * r["Fz"] or
                                     d[2] > 0.05 * r["mz_peak"])
        still += r["beyond_transient"]
    by_T = {T: sum(1 for r in off if r["T"] == T) for T in temps}
    by_T_tr = {T: sum(1 for r in off if r["T"] == T and r["beyond_transient"]) for T in temps}
    return {"n": len(rows), "beyond_by_T": by_T, "beyond_transient_by_T": by_T_tr,
            "beyond_transient": still, "Fx_max": float(np.abs(ex).max()),
            "Fx_p95": float(np.percentile(np.abs(ex), 95)), "Fy_max": float(np.abs(ey).max()),
            "Fy_p95": float(np.percentile(np.abs(ey), 95)), "Mz_max": float(np.abs(em).max()),
            "Mz_p95": float(np.percentile(np.abs(em), 95)), "off": off, "rows": rows}


def relaxation_length(tire: TransientBrushTire, vx: float, Fz: float, T: float,
                      before: tuple[float, float], after: tuple[float, float], which: int,
                      dt: float = 1e-4) -> float:
    """Distance [m] rolled after a step of (kappa, alpha) from ``before`` to ``after`` until
    output ``which`` (0 Fx, 1 Fy) has made 63.2 % of its change."""
    tire.reset()
    R = tire.params.R_e

    def run(kap: float, al: float, t: float) -> list[float]:
        out = []
        for _ in range(round(t / dt)):
            out.append(tire.step_array(dt, vx, -vx * math.tan(al), vx * (1 + kap) / R, Fz,
                                       T)[which])
        return out

    y0 = float(np.mean(run(*before, 0.4)[-200:]))
    t_after = max(0.3, 40.0 * 0.5 / vx)
    ys = np.array(run(*after, t_after))
    y1 = float(np.mean(ys[-int(0.02 / dt):]))
    target = y0 + (1.0 - math.exp(-1.0)) * (y1 - y0)
    k = int(np.argmax((ys - target) * np.sign(y1 - y0) >= 0.0))
    # linear interpolation between the samples around the crossing
    if k == 0:
        return 0.0
    f = (target - ys[k - 1]) / (ys[k] - ys[k - 1])
    return vx * dt * (k + f)


def step_responses(tp, grid, table) -> list[dict]:
    """Relaxation lengths of both fidelities (module docstring)."""
    full = TransientBrushTire(tp, grid, thermal=False)
    rt = TransientBrushTire(tp, grid, patch=table, thermal=False)
    out = []
    for vx in (10.0, 20.0, 30.0):
        for name, before, after, which in (
                ("alpha 0->2 deg", (0.0, 0.0), (0.0, math.radians(2.0)), 1),
                ("kappa 0->-3 %", (0.0, 0.0), (-0.03, 0.0), 0)):
            lf = relaxation_length(full, vx, 4000.0, 293.15, before, after, which)
            lr = relaxation_length(rt, vx, 4000.0, 293.15, before, after, which)
            out.append({"case": name, "vx": vx, "full_m": lf, "rt_m": lr,
                        "ratio": lr / lf})
    return out


def lane_change(tp, grid, table, vx: float = 20.0, amp_deg: float = 4.0,
                freqs: tuple[float, ...] = (0.5, 1.0), dt: float = 1e-3) -> list[dict]:
    """Sine steer of the slip angle; Fy of both fidelities (module docstring)."""
    out = []
    for f in freqs:
        ys = []
        for patch in (None, table):
            tire = TransientBrushTire(tp, grid, patch=patch, thermal=True)
            tire.reset()
            y = []
            n = round(2.0 / f / dt)
            for k in range(n):
                al = math.radians(amp_deg) * math.sin(2 * math.pi * f * (k + 0.5) * dt)
                y.append(tire.step_array(dt, vx, -vx * math.tan(al), vx / tp.R_e, 4000.0,
                                         293.15)[1])
            ys.append(np.array(y))
        d = ys[1] - ys[0]
        out.append({"freq_hz": f, "rms_rel": float(np.sqrt(np.mean(d ** 2)) /
                                                   np.sqrt(np.mean(ys[0] ** 2))),
                    "max_abs_N": float(np.abs(d).max())})
    return out


def abs_stops(tp_name: str, grid_name: str, temps=(0.0, 20.0, 40.0)) -> list[dict]:
    """The shipped ABS study's quarter car (models/studies/abs_default.toml: car, ABS
    thresholds, v0, v_stop, initial brake torque; the slip thresholds fixed, not from a slip
    map) stopped through the native FMU at both fidelities of one build, at 0 / 20 / 40 C,
    the tread temperature carried by the FMU."""
    from fmu_src.host.cosim import CosimSettings, simulate_braking_fmu
    from fmu_src.make.native_build import build_native_fmu
    from fmu_src.make.stage import BuildOptions
    from tire_brush.braking.abs_control import RuleBasedABS
    from tire_brush.braking.study import load_study

    spec = load_study("abs_default")
    car = spec.car
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        fmu = Path(tmp) / "tire.fmu"
        build_native_fmu(tp_name, grid_name, fmu, BuildOptions(fidelity="realtime"))
        for T in temps:
            row = {"T": T}
            for fid in (0, 1):
                ctrl = RuleBasedABS(spec.abs_params, car.radius, car.brake_torque_rate_max)
                s = CosimSettings(parameters={"fidelity": fid})
                t0 = time.perf_counter()
                res = simulate_braking_fmu(fmu, car, ctrl, spec.v0, T + C0,
                                           v_stop=spec.v_stop, settings=s,
                                           brake_torque_initial=spec.brake_torque_initial)
                row[f"distance_{fid}"] = float(res.stopping_distance)
                row[f"wall_s_{fid}"] = time.perf_counter() - t0
            row["diff_rel"] = row["distance_1"] / row["distance_0"] - 1.0
            out.append(row)
    return out


WET_KAPPAS = (-0.02, -0.05, -0.1, -0.2, -0.5, -1.0)
WET_ALPHAS_DEG = (2.0, 4.0, 6.0, 8.0, 10.0)


def wet_steady(tp, grid, wet, table, T: float = 20.0, speeds=(10.0, 25.0),
               Fz: float = 4000.0, depths=(0.0, 0.5e-3, 1e-3)) -> dict:
    """The steady agreement on water (module docstring, ``wet``): rows per depth, speed and
    slip with the full model's and the real-time tire's Fx, Fy, Mz."""
    from tire_brush.wet_friction import (
        drainage_time,
        entrainment_speed,
        footprint_time,
        wet_branch_table,
    )

    rt = TransientBrushTire(tp, grid, patch=table, thermal=False)
    rt.set_wet(wet)
    D = float(grid.meta["D_m"])
    pts = [(k, 0.0) for k in WET_KAPPAS] + [(0.0, math.radians(a)) for a in WET_ALPHAS_DEG]
    rows = []
    for d in depths:
        for vx in speeds:
            full = []
            for kap, al in pts:
                if d > 0.0:
                    U = entrainment_speed(vx, vx * (1.0 + kap))
                    t = drainage_time(footprint_time(tp, Fz, U), D)
                    sb = SteadyBrush(tp, wet_branch_table(grid, wet, d, t))
                else:
                    sb = SteadyBrush(tp, grid)
                st = sb.solve(kap, al, vx, Fz, T + C0)
                full.append([float(st.Fx), float(st.Fy), float(st.Mz)])
            mz_peak = max(abs(f[2]) for f in full)
            for (kap, al), f in zip(pts, full, strict=True):
                r = settled(rt, kap, al, vx, Fz, T + C0, water_depth=d)[:3]
                rows.append({"water_mm": 1e3 * d, "vx": vx, "Fz": Fz, "kappa": kap,
                             "alpha_deg": math.degrees(al), "full": f, "rt": r,
                             "mz_peak": mz_peak})
    for r in rows:
        r["dFx"] = (r["rt"][0] - r["full"][0]) / r["Fz"]
        r["dFy"] = (r["rt"][1] - r["full"][1]) / r["Fz"]
        r["dMz"] = (r["rt"][2] - r["full"][2]) / max(r["mz_peak"], 1e-9)
    return {"rows": rows}


def wet_abs_stop(tp_name: str, grid_name: str, water_depth: float = 1e-3,
                 T: float = 20.0) -> dict:
    """The ABS study's quarter car stopped on water through the native FMU at both
    fidelities of one build on a grid with a wet branch (as :func:`abs_stops`)."""
    from fmu_src.host.cosim import CosimSettings, simulate_braking_fmu
    from fmu_src.make.native_build import build_native_fmu
    from fmu_src.make.stage import BuildOptions
    from tire_brush.braking.abs_control import RuleBasedABS
    from tire_brush.braking.study import load_study

    spec = load_study("abs_default")
    car = spec.car
    row: dict = {"T": T, "water_mm": 1e3 * water_depth}
    with tempfile.TemporaryDirectory() as tmp:
        fmu = Path(tmp) / "tire.fmu"
        build_native_fmu(tp_name, grid_name, fmu, BuildOptions(fidelity="realtime"))
        for fid in (0, 1):
            ctrl = RuleBasedABS(spec.abs_params, car.radius, car.brake_torque_rate_max)
            t0 = time.perf_counter()
            res = simulate_braking_fmu(fmu, car, ctrl, spec.v0, T + C0, v_stop=spec.v_stop,
                                       settings=CosimSettings(parameters={"fidelity": fid}),
                                       brake_torque_initial=spec.brake_torque_initial,
                                       water_depth=water_depth)
            row[f"distance_{fid}"] = float(res.stopping_distance)
            row[f"wall_s_{fid}"] = time.perf_counter() - t0
    row["diff_rel"] = row["distance_1"] / row["distance_0"] - 1.0
    return row


def wet_grip_stops(tp_name: str) -> dict:
    """The wet-grip test's ABS stop (models/studies/wet_grip.toml: its quarter car without the
    tread-temperature state, 90 -> 20 km/h on 1 mm of water, 20 C, texture depth 0.7 mm)
    through the native FMU at both fidelities of one build on its grid; the ABS's slip
    thresholds fixed (the map-based test schedules them from the force map): the distance
    from 80 to 20 km/h and the braking force coefficient over it."""
    import dataclasses

    from fmu_src.host.cosim import CosimSettings, simulate_braking_fmu
    from fmu_src.make.native_build import build_native_fmu
    from fmu_src.make.stage import BuildOptions
    from tire_brush.braking.abs_control import ABSParams, RuleBasedABS
    from tire_brush.braking.wet_grip_test import bfc_distance, load_wet_grip_spec
    from tire_brush.wet_grip import braking_force_coefficient

    spec = load_wet_grip_spec("wet_grip")
    car = dataclasses.replace(spec.car, radius=load_tire(tp_name).R_e, thermal=None)
    row: dict = {"water_mm": 1e3 * spec.water_depth, "T": spec.T_K - C0}
    with tempfile.TemporaryDirectory() as tmp:
        fmu = Path(tmp) / "tire.fmu"
        build_native_fmu(tp_name, spec.grid, fmu,
                         BuildOptions(fidelity="realtime", texture_depth=spec.texture_depth))
        for fid in (0, 1):
            ctrl = RuleBasedABS(ABSParams(), car.radius, car.brake_torque_rate_max)
            t0 = time.perf_counter()
            res = simulate_braking_fmu(fmu, car, ctrl, spec.v_start, spec.T_K, v_stop=spec.v2,
                                       settings=CosimSettings(parameters={"fidelity": fid}),
                                       water_depth=spec.water_depth)
            d = bfc_distance(res, spec.v1)
            row[f"distance_{fid}"] = d
            row[f"bfc_{fid}"] = braking_force_coefficient(spec.v1, spec.v2, d)
            row[f"wall_s_{fid}"] = time.perf_counter() - t0
    row["diff_rel"] = row["distance_1"] / row["distance_0"] - 1.0
    return row


def _wet_file(model: TransientBrushTire, wet, texture_depth: float = 0.0) -> bytes:
    """The wet-branch file of benchmarks/core_step.c (its header comment)."""
    from tire_brush.hydroplaning import D_FULL

    v = wet.variables
    mu = np.stack([v["mu_wet_cold_w0"], v["mu_wet_cold_w1"], v["mu_wet_hot_w0"],
                   v["mu_wet_hot_w1"]], axis=-1)
    blob = struct.pack("2i", wet.axes["water_depth"].size, wet.axes["log10_t_drain"].size)
    for a in (wet.axes["water_depth"], wet.axes["log10_t_drain"], mu.reshape(-1),
              np.asarray(v["w_dry"]).reshape(-1), np.array([D_FULL, 1.0, texture_depth])):
        blob += np.ascontiguousarray(a, dtype=np.float64).tobytes()
    return blob


#: The wet cost's operating point: braking at 20 C, 20 m/s, kappa -0.1 on 0.5 mm (between
#: the r117_wet grid's depth nodes: two layers read) and on 1 mm (one).
WET_COST_CASES = {f"20 C, 20 m/s, kappa -0.1, water {d} mm":
                  [20.0, 0.0, 18.0 / 0.310, 4000.0, 293.15, 1.0, 0.0, d * 1e-3]
                  for d in (0.0, 0.5, 1.0)}


def _core_step_input(model: TransientBrushTire, inputs: list[float], n_warm: int,
                     n_steps: int, n_tires: int = 1) -> bytes:
    """The input file of benchmarks/core_step.c (the format of bench_brush.py)."""
    t = model.table
    blob = struct.pack("3i", t.log10_v.size, t.T.size, t.log10_p.size)
    for a in (t.log10_v, t.T, t.log10_p, t.values.reshape(-1), np.array([t.inv_s0])):
        blob += np.ascontiguousarray(a, dtype=np.float64).tobytes()
    blob += bytes(model._P)
    blob += struct.pack("3i", n_warm, n_steps, n_tires)
    return blob + np.array([*inputs, 1e-3], dtype=np.float64).tobytes()


#: The cost's operating points: the 0 C braking case of docs/tire-core.md ("Cost") and a
#: combined slip at 20 C (vx, vy, omega, Fz, T_surface, mu_scale, gamma, water_depth).
COST_CASES = {"0 C braking, 27.8 m/s, kappa -0.06":
              [27.8, 0.0, 27.8 * 0.94 / 0.310, 4000.0, 273.15, 1.0, 0.0, 0.0],
              "20 C, 20 m/s, kappa -0.05, alpha 1 deg":
              [20.0, -0.35, 19.0 / 0.310, 4000.0, 293.15, 1.0, 0.0, 0.0]}


def core_costs(tp, grid, table_path: Path, steps: int = 300, cases=None,
               wet=None) -> list[dict]:
    """Per 1 ms step of the core alone (benchmarks/core_step.c, one tire, thermal state on):
    the median wall time [us] and, with valgrind, callgrind's instruction count (the
    difference of two runs of ``steps`` and ``2 steps`` steps over ``steps``), both
    fidelities (``cases``: default :data:`COST_CASES`; ``wet``: the grid's wet branch,
    given to the tires)."""
    from tire_brush import ccore

    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return []
    model = TransientBrushTire(tp, grid)
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "core_step"
        subprocess.run([cc, *ccore.CORE_CFLAGS, "-I", str(ccore.SOURCE_DIR), "-o", str(exe),
                        str(HERE / "core_step.c"),
                        *(str(ccore.SOURCE_DIR / s) for s in ccore.SOURCES), "-lm"],
                       check=True)
        wet_arg: list[str] = []
        if wet is not None:
            wf = Path(tmp) / "wet.bin"
            wf.write_bytes(_wet_file(model, wet))
            wet_arg = [str(wf)]
        for case, u in (COST_CASES if cases is None else cases).items():
            for fid, extra in (("full", ["-", *wet_arg] if wet_arg else []),
                               ("realtime", [str(table_path), *wet_arg])):
                row = {"case": case, "fidelity": fid}
                f = Path(tmp) / "in.bin"
                f.write_bytes(_core_step_input(model, u, 200, 1000))
                res = subprocess.run([str(exe), str(f), *extra], check=True,
                                     capture_output=True, text=True).stdout.split()
                row["median_us"] = float(res[0])
                if shutil.which("valgrind"):
                    counts = []
                    for n in (steps, 2 * steps):
                        f.write_bytes(_core_step_input(model, u, 0, n))
                        cg = Path(tmp) / f"cg.{n}"
                        subprocess.run(["valgrind", "--tool=callgrind",
                                        f"--callgrind-out-file={cg}", str(exe), str(f),
                                        *extra], check=True, capture_output=True)
                        counts.append(int(next(ln.split()[1] for ln in
                                               cg.read_text().splitlines()
                                               if ln.startswith(("summary:", "totals:")))))
                    row["instructions"] = (counts[1] - counts[0]) / steps
                out.append(row)
    return out


def native_costs(tp_name: str, grid_name: str) -> dict:
    """Median native doStep per 1 ms step of both fidelities of one FMU build through the C
    host example (one and four tires), and the real-time factor of four."""
    import fmpy

    sys.path.insert(0, str(HERE))
    from bench_fmu_native import c_host_times

    from fmu_src.make.native_build import build_native_fmu
    from fmu_src.make.stage import BuildOptions

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        fmu = Path(tmp) / "tire.fmu"
        build_native_fmu(tp_name, grid_name, fmu, BuildOptions(fidelity="realtime"))
        unz = fmpy.extract(str(fmu))
        for fid in (0, 1):
            for n in (1, 4):
                out[f"{fid}_{n}"] = c_host_times(fmu, unz, n, 2000 if fid else 300,
                                                 Path(tmp), fidelity=fid)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tire", default="passenger")
    ap.add_argument("--grid", default="default")
    ap.add_argument("--sections", default="steady,steps,lane,abs,cost")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--temps", default="0,20,50",
                    help="temperatures [C] of the steady section (the default table has a "
                         "node every 10 K: e.g. 5,25,45 reads between them)")
    ap.add_argument("--wet-depths", default="0,0.5,1",
                    help="water depths [mm] of the wet section's steady rows (sections "
                         "wet, or wet-steady, wet-cost and wet-stops for those parts alone)")
    ap.add_argument("--linear-depth", action="store_true",
                    help="read the wet table linearly between its layers (its depth law "
                         "dropped: the chord, for comparison)")
    args = ap.parse_args(argv)
    sections = set(args.sections.split(","))
    tp, grid = load_tire(args.tire), load_grid(args.grid)
    t0 = time.perf_counter()
    table, path = cached_patch_table(tp, grid, processes=2)
    res: dict = {"table": {"seconds": time.perf_counter() - t0, "MB": path.stat().st_size / 1e6,
                           "shape": list(table.values.shape)}}
    print(f"patch table: {res['table']['MB']:.1f} MB, shape {tuple(table.values.shape)}, "
          f"{res['table']['seconds']:.1f} s (cached: {path})")
    if "steady" in sections:
        temps = tuple(float(x) for x in args.temps.split(","))
        s = steady_sweep(tp, grid, table, temps=temps)
        res["steady"] = {k: v for k, v in s.items() if k != "rows"}
        print(f"\nsteady, {s['n']} points ({'/'.join(f'{T:g}' for T in temps)} C, 5/15/30 "
              f"m/s, 2/4/6 kN, kappa, alpha, combined): |diff| max / p95")
        print(f"  Fx / Fz     {s['Fx_max']:.4f} / {s['Fx_p95']:.4f}   (target 0.02)")
        print(f"  Fy / Fz     {s['Fy_max']:.4f} / {s['Fy_p95']:.4f}   (target 0.02)")
        print(f"  Mz / peak   {s['Mz_max']:.4f} / {s['Mz_p95']:.4f}   (target 0.05)")
        n_T = s["n"] // len(temps)
        print(f"  beyond a target: {len(s['off'])} of {s['n']} ("
              + ", ".join(f"{T:.0f} C: {k} of {n_T}" for T, k in s["beyond_by_T"].items())
              + ")")
        print(f"  of these, beyond a target against the full transient tire held there: "
              f"{s['beyond_transient']} ("
              + ", ".join(f"{T:.0f} C: {k}" for T, k in s["beyond_transient_by_T"].items())
              + ")")
        for r in s["off"]:
            print(f"    {r['T']:4.0f} C {r['vx']:4.0f} m/s {r['Fz']:5.0f} N kappa "
                  f"{r['kappa']:6.3f} alpha {r['alpha_deg']:5.1f}: full steady "
                  f"{np.round(r['full'], 0)} transient {np.round(r['full_transient'], 0)} "
                  f"real-time {np.round(r['rt'], 0)}")
    if "steps" in sections:
        res["steps"] = step_responses(tp, grid, table)
        print("\nrelaxation lengths (63.2 % of a step's change), 4 kN, 20 C")
        print("  case              vx     full [m]   real-time [m]   ratio")
        for r in res["steps"]:
            print(f"  {r['case']:16s} {r['vx']:4.0f}   {r['full_m']:8.3f}   {r['rt_m']:8.3f}"
                  f"        {r['ratio']:.3f}")
    if "lane" in sections:
        res["lane"] = lane_change(tp, grid, table)
        print("\nsine steer, 4 deg, 20 m/s, 4 kN, 20 C: Fy difference RMS / RMS(Fy full)")
        for r in res["lane"]:
            print(f"  {r['freq_hz']:.1f} Hz: {r['rms_rel']:.4f} (max {r['max_abs_N']:.0f} N; "
                  f"target 0.03)")
    if "abs" in sections:
        res["abs"] = abs_stops(args.tire, args.grid)
        print("\nABS stop through the native FMU from 27.8 m/s (quarter car)")
        for r in res["abs"]:
            print(f"  {r['T']:4.0f} C: full {r['distance_0']:.2f} m ({r['wall_s_0']:.0f} s), "
                  f"real-time {r['distance_1']:.2f} m ({r['wall_s_1']:.1f} s): "
                  f"{100 * r['diff_rel']:+.2f} % (target 2 %)")
    if "cost" in sections:
        res["core"] = core_costs(tp, grid, path)
        print("\nthe core alone per 1 ms step (benchmarks/core_step.c; callgrind instructions, "
              "target 40000 = 10 us)")
        for r in res["core"]:
            ins = f"{r['instructions']:10.0f}" if "instructions" in r else "  (no valgrind)"
            print(f"  {r['case']:40s} {r['fidelity']:8s} {r['median_us']:9.2f} us {ins}")
        res["native"] = native_costs(args.tire, args.grid)
        print("\nnative FMU through the C host example, median doStep per tire per 1 ms step")
        for fid in (0, 1):
            one, four = res["native"][f"{fid}_1"], res["native"][f"{fid}_4"]
            print(f"  fidelity {fid}: one tire {one['doStep_median_us']:8.2f} us, four tires "
                  f"{four['doStep_median_us']:8.2f} us each, real-time factor of four "
                  f"{four['real_time_factor']:.1f}")
    wet_parts = {"wet-steady", "wet-cost", "wet-stops"} if "wet" in sections else \
        sections & {"wet-steady", "wet-cost", "wet-stops"}
    if wet_parts:
        from lookup.grid.store import resolve_grid_path
        from lookup.grid.wet import load_wet

        wet = load_wet(resolve_grid_path(args.grid))
        t0 = time.perf_counter()
        wtable, wpath = cached_patch_table(tp, grid, processes=2, wet=wet)
        if args.linear_depth:
            import dataclasses

            wtable = dataclasses.replace(wtable, depth_law=None)
            wpath = Path(tempfile.mkdtemp()) / "patch-linear.bin"
            wpath.write_bytes(wtable.to_bytes())
        res["wet_table"] = {"seconds": time.perf_counter() - t0,
                            "MB": wpath.stat().st_size / 1e6,
                            "shape": list(wtable.values.shape)}
        print(f"\nwet patch table: {res['wet_table']['MB']:.1f} MB, shape "
              f"{tuple(wtable.values.shape)} (water depths {wtable.depth.tolist()} m), "
              f"{res['wet_table']['seconds']:.1f} s (cached: {wpath})")
        ws = {"rows": []}
        if "wet-steady" in wet_parts:
            ws = wet_steady(tp, grid, wet, wtable,
                            depths=[1e-3 * float(x) for x in args.wet_depths.split(",")])
        res["wet_steady"] = ws
        print("\nsteady on water, 20 C, 4 kN: real-time - full, Fx and Fy over Fz, Mz over "
              "its peak")
        print("  water   vx   kappa  alpha    full Fx/Fz  rt Fx/Fz   dFx     dFy     dMz")
        for r in ws["rows"]:
            flag = " *" if abs(r["dFx"]) > 0.02 or abs(r["dFy"]) > 0.02 or \
                abs(r["dMz"]) > 0.05 else ""
            print(f"  {r['water_mm']:4.1f} {r['vx']:5.0f} {r['kappa']:7.2f} "
                  f"{r['alpha_deg']:5.1f}    {r['full'][0] / r['Fz']:8.3f}  "
                  f"{r['rt'][0] / r['Fz']:8.3f}  {r['dFx']:+.4f} {r['dFy']:+.4f} "
                  f"{r['dMz']:+.4f}{flag}")
        for d in sorted({r["water_mm"] for r in ws["rows"]}):
            sel = [r for r in ws["rows"] if r["water_mm"] == d]
            ok = sum(1 for r in sel if abs(r["dFx"]) <= 0.02 and abs(r["dFy"]) <= 0.02
                     and abs(r["dMz"]) <= 0.05)
            print(f"  {d:.1f} mm: max |dFx| {max(abs(r['dFx']) for r in sel):.4f}, max |dFy| "
                  f"{max(abs(r['dFy']) for r in sel):.4f}, max |dMz| "
                  f"{max(abs(r['dMz']) for r in sel):.4f}; within all targets "
                  f"{ok} of {len(sel)}")
        if "wet-cost" in wet_parts:
            res["wet_core"] = core_costs(tp, grid, wpath, cases=WET_COST_CASES, wet=wet)
        print("\nthe core alone per 1 ms step on water (callgrind instructions, target 40000)")
        for r in res.get("wet_core", []):
            ins = f"{r['instructions']:10.0f}" if "instructions" in r else "  (no valgrind)"
            print(f"  {r['case']:40s} {r['fidelity']:8s} {r['median_us']:9.2f} us {ins}")
        if "wet-stops" in wet_parts:
            res["wet_abs"] = wet_abs_stop(args.tire, args.grid)
            r = res["wet_abs"]
            print(f"\nABS stop on {r['water_mm']:.0f} mm of water at {r['T']:.0f} C through "
                  f"the native FMU: full {r['distance_0']:.2f} m ({r['wall_s_0']:.0f} s), "
                  f"real-time {r['distance_1']:.2f} m ({r['wall_s_1']:.1f} s): "
                  f"{100 * r['diff_rel']:+.2f} % (target 2 %)")
            res["wet_grip"] = wet_grip_stops(args.tire)
            r = res["wet_grip"]
            print(f"the wet-grip test's ABS stop (90 -> 20 km/h, {r['water_mm']:.0f} mm, "
                  f"{r['T']:.0f} C) through the native FMU: 80 -> 20 km/h in "
                  f"{r['distance_0']:.2f} m (BFC {r['bfc_0']:.3f}, {r['wall_s_0']:.0f} s) "
                  f"full, {r['distance_1']:.2f} m (BFC {r['bfc_1']:.3f}, "
                  f"{r['wall_s_1']:.1f} s) real-time: {100 * r['diff_rel']:+.2f} % "
                  f"(target 2 %)")
    if args.json:
        print(json.dumps(res, indent=1, default=float))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
