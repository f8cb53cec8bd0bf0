"""Cost of a step at the input envelope's edges and in the adversarial fuzz, against an
ordinary step (docs/tire-core.md, "belt coupling at high rolling speed" and "work budget").

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_hang.py [--repro-steps 10000]
      [--fuzz-steps 10000] [--seeds 1000-1009] [--flavours core,pythonfmu,native,wet]
      [--json out.json]

Two measurements, for the compiled core alone (``TransientBrushTire``) and through fmpy for
the pythonfmu and the native FMU (the shipped tire on the FMU tests' synthetic grid) and the
native FMU on the wet reference road (``r117_wet``: wet branch and rolling resistance):

* **the repro** of the runaway: a fresh tire at 37.09 m/s, 150 m/s sideways (``limit.v``),
  1000 rad/s (``limit.omega``), 7320 N, 268 K, ``mu_scale`` 0.05, 1 ms steps, thermal state
  on; CPU time per doStep (median, 99th percentile, largest) over ``--repro-steps`` steps and its
  ratio to the ordinary step, the largest tread temperature and the steps whose status had a
  model bit (1024: work budget spent, 2048: friction read outside the grid's temperature range);
* **the fuzz** of ``tests/test_fmu_fuzz.py`` (its input generator, through the FMU's input
  guard; no misuse or rollbacks here), seeds ``--seeds``, ``--fuzz-steps`` steps each, long
  steps up to 0.3 s: CPU per doStep and per 0.25 ms of step (median, 99th percentile,
  largest; a step at the envelope's edge may take a few more, shorter outer steps), the
  largest over all seeds against 0.25 ms of the ordinary step.

The ordinary step: braking at 5 % slip, 20 m/s, 4 kN, 20 C, 1 ms steps (the median of 2000).
CPU is the process's (``time.process_time``), so other work on the machine does not count,
but a shared core's caches and clock do: run pinned and compare medians and ratios.
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

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent / "tests"))

REPRO = [37.09, 150.0, 1000.0, 7320.0, 268.0, 0.05, 0.0, 0.0]
ORDINARY = [20.0, 0.0, 20.0 * 0.95 / 0.31, 4000.0, 293.15, 1.0, 0.0, 0.0]


class Core:
    """The compiled core behind the FMU's input guard, stepped like an FMU."""

    def __init__(self, thermal: bool) -> None:
        from fmu_support import synthetic_grid

        from fmu_src.runtime.guard import InputGuard
        from fmu_src.runtime.interface import default_limits
        from tire_brush.params import load_tire
        from tire_brush.transient import TransientBrushTire

        tire = load_tire("passenger")
        self.tr = TransientBrushTire(tire, synthetic_grid(), thermal=thermal)
        self.guard = InputGuard(default_limits(tire), list(ORDINARY))
        self.out = None

    def step(self, u: list[float], dt: float) -> tuple[float, int]:
        x, bits, _ = self.guard.apply(u)
        t0 = time.process_time()
        self.out = self.tr.step_array(dt, *x)
        cpu = time.process_time() - t0
        return cpu, bits | 1024 * bool(self.tr.flags & 1) | 2048 * bool(self.tr.flags & 2)

    def T(self) -> float:
        return self.out[9]


class Fmu:
    """An FMU instance through fmpy (tests/fmu_support.py)."""

    def __init__(self, path: Path, thermal: bool) -> None:
        from fmu_support import FmuDriver

        self.d = FmuDriver(path, None, "bench", logging=False,
                           start_values={"tire.thermal.enabled": thermal})

    def step(self, u: list[float], dt: float) -> tuple[float, int]:
        d = self.d
        d.fmu.setReal(d._vin, u)
        t0 = time.process_time()
        try:
            d.fmu.fmi2DoStep(d.fmu.component, d.time, dt, 1)
        except Exception:                       # fmpy raises above fmi2Warning (refused steps)
            pass
        cpu = time.process_time() - t0
        if math.isfinite(dt) and dt > 0:
            d.time += dt
        return cpu, d.status()

    def T(self) -> float:
        return float(self.d.outputs()[9])


def _build(flavour: str, tmp: Path) -> Path | None:
    from fmu_support import build_test_fmu, synthetic_grid

    from fmu_src.make.native_build import build_native_fmu

    if flavour == "pythonfmu":
        return build_test_fmu(tmp)
    if flavour == "native":
        return build_native_fmu("passenger", synthetic_grid(), tmp / "BrushTireNative.fmu",
                                platforms=("linux64",)).path
    if flavour == "wet":
        return build_native_fmu("passenger", "r117_wet", tmp / "BrushTireWet.fmu",
                                platforms=("linux64",)).path
    return None


def _make(flavour: str, fmus: dict, thermal: bool):
    return Core(thermal) if flavour == "core" else Fmu(fmus[flavour], thermal)


def _quantiles(x: list[float]) -> dict[str, float]:
    q = np.quantile(x, [0.5, 0.99, 1.0])
    return {"median": float(q[0]), "p99": float(q[1]), "max": float(q[2])}


def ordinary(flavour: str, fmus: dict) -> float:
    """Median CPU [s] of an ordinary 1 ms doStep."""
    t = _make(flavour, fmus, thermal=True)
    cpu = [t.step(ORDINARY, 1e-3)[0] for _ in range(2000)]
    return statistics.median(cpu[200:])


def repro(flavour: str, fmus: dict, steps: int, base: float) -> dict:
    t = _make(flavour, fmus, thermal=True)
    cpu, T, flagged = [], [], 0
    for _ in range(steps):
        c, bits = t.step(REPRO, 1e-3)
        cpu.append(c)
        T.append(t.T())
        flagged += bits >= 1024
    q = _quantiles(cpu)
    return {**q, "max_over_ordinary": q["max"] / base, "p99_over_ordinary": q["p99"] / base,
            "T_tread_max": max(T), "steps_with_model_bits": flagged}


def fuzz(flavour: str, fmus: dict, seeds: list[int], steps: int, base: float) -> dict:
    from fmu_support import FUZZ_STEPS, fuzz_inputs

    per_step, per_outer = [], []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        t = _make(flavour, fmus, thermal=False)
        for _ in range(steps):
            u = fuzz_inputs(rng, wet=flavour == "wet")
            dt = float(rng.choice(FUZZ_STEPS))
            if flavour == "core" and not (math.isfinite(dt) and dt >= 0.0):
                continue                        # the FMU refuses these before the core
            c, _ = t.step(u, dt)
            per_step.append(c)
            if math.isfinite(dt) and dt >= 1e-9:
                per_outer.append(c / math.ceil(dt / 2.5e-4 - 1e-9))
    qs, qo = _quantiles(per_step), _quantiles(per_outer)
    return {"per_step": qs, "per_quarter_ms": qo,
            "max_quarter_ms_over_ordinary": qo["max"] / (base / 4.0)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repro-steps", type=int, default=10_000)
    ap.add_argument("--fuzz-steps", type=int, default=10_000)
    ap.add_argument("--seeds", default="1000-1009")
    ap.add_argument("--flavours", default="core,pythonfmu,native,wet")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    lo, _, hi = a.seeds.partition("-")
    seeds = list(range(int(lo), int(hi or lo) + 1))
    flavours = a.flavours.split(",")
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        fmus = {}
        for f in flavours:
            if f != "core":
                (Path(tmp) / f).mkdir()
                fmus[f] = _build(f, Path(tmp) / f)
        for f in flavours:
            base = ordinary(f, fmus)
            r = {"ordinary_step": base, "repro": repro(f, fmus, a.repro_steps, base),
                 "fuzz": fuzz(f, fmus, seeds, a.fuzz_steps, base)}
            results[f] = r
            print(f"{f}: ordinary 1 ms step {base * 1e3:.3f} ms")
            rp = r["repro"]
            print(f"  repro ({a.repro_steps} x 1 ms): CPU per step median "
                  f"{rp['median'] * 1e3:.3f} ms, p99 {rp['p99'] * 1e3:.3f} ms, "
                  f"max {rp['max'] * 1e3:.3f} ms "
                  f"({rp['max_over_ordinary']:.1f}x ordinary); T_tread max "
                  f"{rp['T_tread_max']:.1f} K; steps with model bits "
                  f"{rp['steps_with_model_bits']}")
            fz = r["fuzz"]
            print(f"  fuzz seeds {seeds[0]}-{seeds[-1]} x {a.fuzz_steps}: per doStep median "
                  f"{fz['per_step']['median'] * 1e3:.3f} ms, p99 {fz['per_step']['p99'] * 1e3:.2f}"
                  f" ms, max {fz['per_step']['max']:.3f} s; per 0.25 ms of step max "
                  f"{fz['per_quarter_ms']['max'] * 1e3:.3f} ms "
                  f"({fz['max_quarter_ms_over_ordinary']:.1f}x the ordinary step's)",
                  flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
