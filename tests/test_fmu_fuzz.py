"""Fuzz of both FMU flavours followed by a recovery check (slow, except a short smoke run).

Each seed drives one instance for ``n`` steps of adversarial use -- NaN, +-inf, 1e30, negative
load, zero speed and spin, communication steps that are tiny, subnormal, zero, negative, NaN
or long; API misuse (sets of outputs, constants and fixed parameters, unknown references,
wrong types); random rollbacks to states saved earlier; corrupt state blobs -- and then holds
steady braking inputs for 1 s. It counts crashes (the test process would die), non-finite
outputs, fmi2Fatal returns and *unrecovered* states: after the steady second the forces must
have settled (step-to-step change below 1 % of Fz over the last 0.5 s) on those of a fresh
instance given the same steady second (within 1 % of Fz). The thermal state is off (a hot
tread would legitimately remember the history). The steady inputs brake at 5 % slip at 20 m/s
and 4 kN: outside the stick-slip and two-branch regimes of the brush (docs/tire-core.md,
"Limits"), where a fresh instance is not unique either.

Run in fmpy (one instance per seed) for the pythonfmu and the native flavour, and in libcosim
(libcosimpy: C++ host) with four instances side by side for both flavours (inputs only:
libcosimpy's API has no FMU-state calls or misuse paths).
"""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
from fmu_support import INPUTS, FmuDriver, build_test_fmu, synthetic_grid

FZ, VX, R_E = 4000.0, 20.0, 0.31
STEADY = [VX, 0.0, VX * 0.95 / R_E, FZ, 293.15, 1.0, 0.0, 0.0]
START = {"tire.thermal.enabled": False}
FATAL = 4
GARBAGE = (math.nan, math.inf, -math.inf, 1e30, -1e30, 1e308, 0.0, -0.0, 5e-324, -4000.0)
STEPS = (1e-3,) * 12 + (1e-12, 5e-324, 0.0, 2e-4, 3e-3, 1e-7, -1e-3, math.nan, math.inf)


@pytest.fixture(scope="module", params=["pythonfmu", "native"])
def flavour(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(f"fuzz_{request.param}")
    if request.param == "pythonfmu":
        return request.param, build_test_fmu(d)
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("the native FMU needs a C compiler")
    from fmu_src.make.native_build import build_native_fmu

    return request.param, build_native_fmu("passenger", synthetic_grid(),
                                           d / "BrushTireNative.fmu",
                                           platforms=("linux64",)).path


def _inputs(rng: np.random.Generator) -> list[float]:
    u = [rng.normal(VX, 15.0), rng.normal(0.0, 3.0), rng.normal(VX / R_E, 40.0),
         rng.normal(FZ, 3000.0), rng.uniform(240.0, 360.0), rng.uniform(0.0, 1.5)]
    for i in range(6):
        r = rng.random()
        if r < 0.04:
            u[i] = float(rng.choice(GARBAGE))
        elif r < 0.06:
            u[i] = 0.0                                  # zero speed, spin, load
    return [float(x) for x in u]


def _misuse(d: FmuDriver, rng: np.random.Generator) -> None:
    from fmpy.fmi1 import FMICallException

    f, n = d.fmu, len(d.md.modelVariables)
    calls = (lambda: f.setReal([d.vr["Fx"]], [1.0]), lambda: f.getReal([n + 7]),
             lambda: f.setReal([n + 7], [0.0]), lambda: f.setInteger([d.vr["vx"]], [3]),
             lambda: f.getInteger([d.vr["Fz"]]), lambda: f.setReal([d.vr["tire.R_e"]], [0.2]),
             lambda: f.setString([d.vr["info.tire"]], ["x"]),
             lambda: f.setInteger([d.vr["input_status"]], [5]))
    try:
        calls[int(rng.integers(len(calls)))]()
    except FMICallException as exc:
        assert exc.status != FATAL, "fmi2Fatal on misuse"


def _status(d: FmuDriver, dt: float) -> int:
    from fmpy.fmi1 import FMICallException

    try:
        st = int(d.fmu.fmi2DoStep(d.fmu.component, d.time, dt, 1))
    except FMICallException as exc:                # fmpy raises above fmi2Warning
        st = int(exc.status)
    assert st != FATAL, f"fmi2Fatal from doStep({dt!r})"
    if st in (0, 1) and math.isfinite(dt) and dt > 0:
        d.time += dt
    return st


def _steady(d: FmuDriver, seconds: float = 1.0) -> np.ndarray:
    d.fmu.setReal(d._vin, STEADY)
    out = []
    for _ in range(round(seconds / 1e-3)):
        _status(d, 1e-3)
        out.append(d.outputs()[:2])
    return np.array(out)


def fuzz_one(fmu, unzipdir, seed: int, n: int) -> dict[str, int]:
    """One seed (module docstring); returns the counts of the table."""
    from fmpy.fmi1 import FMICallException

    rng = np.random.default_rng(seed)
    d = FmuDriver(fmu, unzipdir, f"fuzz{seed}", logging=False, start_values=START)
    saved: list = []
    counts = {"non_finite": 0, "discarded_or_error": 0, "rollbacks": 0, "corrupt_blobs": 0}
    for _ in range(n):
        r = rng.random()
        if r < 0.03:
            _misuse(d, rng)
        elif r < 0.05:
            saved.append(d.fmu.getFMUstate())
            if len(saved) > 3:
                d.fmu.freeFMUstate(saved.pop(0))
        elif r < 0.07 and saved:
            d.fmu.setFMUstate(saved[int(rng.integers(len(saved)))])
            counts["rollbacks"] += 1
        elif r < 0.08:
            blob = bytearray(d.fmu.serializeFMUstate(d.fmu.getFMUstate()))
            blob[int(rng.integers(len(blob)))] ^= 1 << int(rng.integers(8))
            try:
                st = d.fmu.deSerializeFMUstate(bytes(blob))
                d.fmu.setFMUstate(st)
                d.fmu.freeFMUstate(st)
            except FMICallException as exc:
                assert exc.status != FATAL, "fmi2Fatal on a corrupt blob"
            counts["corrupt_blobs"] += 1
        else:
            d.fmu.setReal(d._vin, _inputs(rng))
            if _status(d, float(rng.choice(STEPS))) > 1:
                counts["discarded_or_error"] += 1
        counts["non_finite"] += int(not np.isfinite(d.outputs()).all())
    hit = _steady(d)
    fresh = FmuDriver(fmu, unzipdir, f"fresh{seed}", logging=False, start_values=START)
    ref = _steady(fresh)
    late = hit[len(hit) // 2:]
    settled = np.abs(np.diff(late, axis=0)).max() < 0.01 * FZ
    same = np.abs(hit[-50:].mean(axis=0) - ref[-50:].mean(axis=0)).max() < 0.01 * FZ
    counts["unrecovered"] = int(not (settled and same))
    for s in saved:
        d.fmu.freeFMUstate(s)
    d.close()
    fresh.close()
    return counts


def test_fuzz_smoke_both_flavours(flavour):
    """A short run of the fuzz (fast)."""
    name, fmu = flavour
    c = fuzz_one(fmu, None, seed=99, n=400)
    assert c["non_finite"] == 0 and c["unrecovered"] == 0, (name, c)


@pytest.mark.slow
def test_fuzz_ten_seeds_recover_in_fmpy(flavour):
    """10 seeds x 1e4 steps per flavour: 0 crashes, 0 non-finite outputs, 0 Fatal, 0
    unrecovered states (module docstring)."""
    import fmpy

    name, fmu = flavour
    unz = fmpy.extract(str(fmu))
    table = {seed: fuzz_one(fmu, unz, seed, 10_000) for seed in range(10)}
    print(f"\n{name}: " + "; ".join(f"seed {s}: {c}" for s, c in table.items()))
    assert all(c["non_finite"] == 0 for c in table.values()), table
    assert all(c["unrecovered"] == 0 for c in table.values()), table


@pytest.mark.slow
def test_fuzz_four_instances_recover_in_libcosim(flavour):
    """libcosim (C++ host, libcosimpy) steps four instances of the flavour side by side through
    2000 steps of adversarial inputs (different seeds), then the steady second; each settles on
    the forces of a fresh instance, every output finite."""
    pytest.importorskip("libcosimpy")
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    name, fmu = flavour
    ex = CosimExecution.from_step_size(step_size=1_000_000)       # 1 ms in ns
    idx = [ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=f"t{i}"))
           for i in range(5)]                                    # the last one stays fresh
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    man = CosimManipulator.create_override()
    ex.add_manipulator(man)
    import fmpy

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    vin = [vr[n] for n in INPUTS]
    for i in idx:
        ex.boolean_initial_value(i, vr["tire.thermal.enabled"], False)
        for v, x in zip(vin, STEADY, strict=True):
            ex.real_initial_value(i, v, x)
    rngs = [np.random.default_rng(100 + i) for i in idx[:4]]
    for _ in range(2000):
        for i, rng in zip(idx[:4], rngs, strict=True):
            man.slave_real_values(i, vin, _inputs(rng))
        assert ex.step(1)
        for i in idx:
            assert np.isfinite(obs.last_real_values(i, [vr["Fx"], vr["Fy"]])).all(), name
    for i in idx[:4]:
        man.slave_real_values(i, vin, STEADY)
    fx = {i: [] for i in idx}
    for _ in range(1000):
        assert ex.step(1)
        for i in idx:
            fx[i].append(obs.last_real_values(i, [vr["Fx"], vr["Fy"]]))
    ref = np.array(fx[idx[4]])[-50:].mean(axis=0)
    for i in idx[:4]:
        a = np.array(fx[i])
        assert np.abs(np.diff(a[500:], axis=0)).max() < 0.01 * FZ, (name, i, "not settled")
        assert np.abs(a[-50:].mean(axis=0) - ref).max() < 0.01 * FZ, (name, i, "hidden state")
