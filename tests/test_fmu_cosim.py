"""The built FMU driven step by step through fmpy, as a co-simulation master drives it:
state rollback, four instances in one process, module isolation, bad inputs, standstill and
reversing."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmu_support import (
    INPUTS,
    OUTPUTS,
    FmuDriver,
    braking_inputs,
    build_test_fmu,
    synthetic_grid,
)

from fmu_src.runtime.interface import STATUS_BITS
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.transient import N_TRANSIENT, TransientBrushTire

FMI_OK, FMI_WARNING, FMI_DISCARD, FMI_ERROR = 0, 1, 2, 3
R_E = 0.31


@pytest.fixture(scope="module")
def fmu(tmp_path_factory):
    return build_test_fmu(tmp_path_factory.mktemp("cosim"))


@pytest.fixture(scope="module")
def unzipdir(fmu):
    import fmpy

    return fmpy.extract(str(fmu))


def python_model(**kw) -> TransientBrushTire:
    return TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()), **kw)


# -- rollback ----------------------------------------------------------------------------------
def test_rollback_through_fmpy_is_bit_exact(fmu, unzipdir):
    d = FmuDriver(fmu, unzipdir, "rollback")
    U = braking_inputs(300)
    for k in range(150):
        d.step(U[:, k])
    state = d.fmu.getFMUstate()
    blob = d.fmu.serializeFMUstate(state)
    first = np.array([d.step(U[:, k]) for k in range(150, 300)])
    d.fmu.setFMUstate(state)
    second = np.array([d.step(U[:, k]) for k in range(150, 300)])
    assert second.tobytes() == first.tobytes(), "get/set FMU state must roll back exactly"
    d.fmu.setFMUstate(state)  # the same state restores twice
    assert np.array(d.step(U[:, 150])).tobytes() == first[0].tobytes()
    d.fmu.freeFMUstate(state)

    e = FmuDriver(fmu, unzipdir, "restored")
    restored = e.fmu.deSerializeFMUstate(blob)
    e.fmu.setFMUstate(restored)
    third = np.array([e.step(U[:, k]) for k in range(150, 300)])
    assert third.tobytes() == first.tobytes(), \
        "a serialized state must restore exactly in another instance"
    assert len(blob) > 5 * 8 * 100, "the state carries the element deflections"
    e.fmu.freeFMUstate(restored)
    d.close()
    e.close()


# -- misuse a master survives -------------------------------------------------------------------
def _misuse_calls(d: FmuDriver) -> dict:
    f, n_vars = d.fmu, len(d.md.modelVariables)
    return {"fixed parameter after init": lambda: f.setReal([d.vr["tire.R_e"]], [0.4]),
            "set an output": lambda: f.setReal([d.vr["Fx"]], [1.0]),
            "set an unknown reference": lambda: f.setReal([n_vars + 5], [1.0]),
            "get an unknown reference": lambda: f.getReal([n_vars + 5]),
            "set with the wrong type": lambda: f.setInteger([d.vr["vx"]], [1]),
            "get with the wrong type": lambda: f.getReal([d.vr["n_elements"]]),
            "set a constant": lambda: f.setString([d.vr["info.tire"]], ["x"]),
            "set the status output": lambda: f.setInteger([d.vr["input_status"]], [0]),
            "atomic multi-set": lambda: f.setReal([d.vr["vx"], d.vr["Fy"]], [99.0, 1.0])}


def test_pythonfmu_misuse_is_logged_and_changes_nothing(fmu, unzipdir):
    """Every misuse FMI 2.0 lets an FMU recover from: never fmi2Fatal (pythonfmu would free
    the Python instance and the host would crash on its next call), an fmi2Error message in
    the log, and nothing changed: the instance then steps exactly like a twin that saw no
    misuse (fmu_src/runtime/slave.py, module docstring)."""
    from fmpy.fmi1 import FMICallException

    # the twin first: fmpy's logger proxy delivers every instance's messages to the logger
    # registered last
    twin = FmuDriver(fmu, unzipdir, "twin")
    d = FmuDriver(fmu, unzipdir, "misused")
    U = braking_inputs(40)
    for k in range(20):
        d.step(U[:, k])
        twin.step(U[:, k])
    for name, call in _misuse_calls(d).items():
        n_log = len(d.messages)
        try:
            call()
        except FMICallException as exc:
            assert exc.status == FMI_ERROR, f"{name}: status {exc.status}"
        assert any(s == FMI_ERROR for s, _, _ in d.messages[n_log:]), f"{name}: not logged"
    assert d.fmu.getReal([d.vr["tire.R_e"]])[0] == twin.fmu.getReal([twin.vr["tire.R_e"]])[0]
    for k in range(20, 40):
        assert d.step(U[:, k]).tobytes() == twin.step(U[:, k]).tobytes(), f"step {k}"
    d.close()
    twin.close()


def test_corrupt_or_foreign_state_blob_is_refused_and_changes_nothing(fmu, unzipdir, tmp_path):
    """A state blob with a flipped byte, a truncated one, random bytes and a state of another
    build are refused (logged as errors, never Fatal) and the instance goes on exactly as a
    twin that was not asked to restore them."""
    from fmpy.fmi1 import FMICallException

    U = braking_inputs(60)
    other = build_test_fmu(tmp_path, "Other.fmu", n_elements=12)  # another build id
    o = FmuDriver(other, None, "other", logging=False)
    o.step(U[:, 0])
    foreign = bytes(o.fmu.serializeFMUstate(o.fmu.getFMUstate()))
    o.close()
    twin = FmuDriver(fmu, unzipdir, "twin2")               # before d: see the test above
    d = FmuDriver(fmu, unzipdir, "target")
    for k in range(30):
        d.step(U[:, k])
        twin.step(U[:, k])
    blob = bytes(d.fmu.serializeFMUstate(d.fmu.getFMUstate()))
    flipped = bytearray(blob)
    flipped[len(blob) // 2] ^= 0x40
    for name, bad in (("flipped byte", bytes(flipped)), ("truncated", blob[:-17]),
                      ("random", np.random.default_rng(1).bytes(len(blob))),
                      ("other build", foreign)):
        n_log = len(d.messages)
        try:
            st = d.fmu.deSerializeFMUstate(bad)
            d.fmu.setFMUstate(st)
            d.fmu.freeFMUstate(st)
        except FMICallException as exc:
            assert exc.status == FMI_ERROR, f"{name}: status {exc.status}"
        assert any(s == FMI_ERROR for s, _, _ in d.messages[n_log:]), f"{name}: not logged"
    for k in range(30, 60):
        assert d.step(U[:, k]).tobytes() == twin.step(U[:, k]).tobytes(), f"step {k}"
    d.close()
    twin.close()


# -- several instances -------------------------------------------------------------------------
def test_four_instances_in_one_process_stay_independent(fmu, unzipdir):
    """Four wheels of one car: different loads, slips and one with another discretisation,
    stepped interleaved; each must equal its own Python model exactly."""
    n = 200
    wheels = []
    for w in range(4):
        start = {"n_elements": 60} if w == 3 else {}
        U = braking_inputs(n, seed=w)
        U[3] *= 0.8 + 0.15 * w           # load
        U[2] *= 1.0 - 0.02 * w           # more slip on the rear
        wheels.append((FmuDriver(fmu, unzipdir, f"wheel{w}", start_values=start), U,
                       python_model(n_elements=60 if w == 3 else N_TRANSIENT)))
    for k in range(n):
        for w, (drv, U, model) in enumerate(wheels):
            got = drv.step(U[:, k])
            ref = model.step(1e-3, *U[:, k]).as_array()
            assert np.array_equal(got, ref), f"wheel {w} step {k}: {got} != {ref}"
    fx = [drv.outputs()[0] for drv, _, _ in wheels]
    assert len(set(fx)) == 4, "the wheels must not share state"
    for drv, _, _ in wheels:
        drv.close()


def test_fmu_ignores_other_modules_of_the_same_names(fmu, tmp_path):
    """Another FMU (or the host) has loaded modules named lookup, tire_brush and fmu_src: the
    FMU must use its private copy. Run in a child process (it poisons sys.modules), which
    frees its instance before it exits as a host must: a pythonfmu (cppfmu) FMU whose
    instance is still alive when the host process exits can crash in the exit's teardown
    (seen once here as glibc's "corrupted double-linked list" after every output had been
    printed; viproma/cppfmu on GitHub, "Segmentation fault when freeing the instance in pyfmi
    before exiting")."""
    U = braking_inputs(100)
    model = python_model()
    ref = [model.step(1e-3, *U[:, k]).as_array().tolist() for k in range(100)]
    script = textwrap.dedent(f"""
        import json, sys, types
        for name in ("tirefric", "tirefric.errors", "lookup", "lookup.grid", "lookup.grid.reader",
                     "tire_brush", "tire_brush.transient", "tire_brush.params", "fmu_src",
                     "fmu_src.runtime.slave", "fmu_src.runtime.guard"):
            sys.modules[name] = types.ModuleType(name)   # empty impostors
        sys.path.insert(0, {str(tmp_path)!r})
        sys.path.insert(0, {str(__file__.rsplit("/", 1)[0])!r})
        from fmu_support import FmuDriver
        d = FmuDriver({str(fmu)!r}, name="isolated")
        U = json.loads(sys.stdin.read())
        out = [d.step(u).tolist() for u in U]
        d.close()
        print(json.dumps(out))
    """)
    proc = subprocess.run([sys.executable, "-c", script], input=json.dumps(U.T.tolist()),
                          capture_output=True, text=True, timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert np.array_equal(np.array(got), np.array(ref)), "the FMU used foreign modules"


# -- bad inputs --------------------------------------------------------------------------------
def _step_status(d: FmuDriver, u, dt=1e-3) -> int:
    """FMI status of one doStep (fmpy raises for statuses above warning)."""
    try:
        d.step(u, dt)
        return FMI_OK
    except FMICallException as exc:
        d.time += dt
        return int(exc.status)


def test_bad_inputs_are_repaired_logged_and_flagged(fmu, unzipdir):
    d = FmuDriver(fmu, unzipdir, "bad")
    good = [20.0, 0.0, 20.0 / R_E * 0.95, 4000.0, 293.15, 1.0, 0.0, 0.0]
    for _ in range(20):
        d.step(good)
    cases = [
        ("vx", math.nan, "nonfinite", "not finite"),
        ("omega", math.inf, "nonfinite", "not finite"),
        ("Fz", -500.0, "negative_load", "lift-off"),
        ("vx", 1e6, "speed_clamped", "beyond the envelope"),
        ("omega", -1e12, "speed_clamped", "beyond the envelope"),
        ("Fz", 1e9, "load_clamped", "beyond the envelope"),
        ("T_surface", -5.0, "temperature_clamped", "outside"),
        ("mu_scale", -1.0, "mu_scale_clamped", "outside"),
    ]
    for name, value, bit, text in cases:
        u = list(good)
        u[INPUTS.index(name)] = value
        n_before = len(d.messages)
        y = d.step(u)
        assert np.isfinite(y).all(), f"{name} = {value}: outputs must stay finite"
        assert d.status() & STATUS_BITS[bit], f"{name} = {value}: input_status bit {bit}"
        new = d.messages[n_before:]
        assert any(s == FMI_WARNING and name in m and text in m for s, _, m in new), \
            f"{name} = {value}: a warning naming the input, got {new}"
        d.step(good)
        assert d.status() == 0, "the flag clears with good inputs"
    lift = d.step([20.0, 0.0, 60.0, -1.0, 293.15, 1.0, 0.0, 0.0])
    assert lift[0] == lift[1] == lift[2] == 0.0, "negative load is lift-off: no forces"
    d.close()


def _adversarial(rng: np.random.Generator, n: int) -> np.ndarray:
    """Random drive with bursts of garbage: NaN, inf, extreme values, sign flips."""
    t = np.arange(n) * 1e-3
    U = np.stack([20 * np.sin(0.7 * t) + rng.normal(0, 0.5, n),
                  rng.normal(0, 1, n),
                  (20 * np.sin(0.7 * t)) / R_E * (1 + rng.normal(0, 0.1, n)),
                  4000 + rng.normal(0, 1500, n),
                  rng.uniform(250, 330, n),
                  rng.uniform(0.3, 1.2, n)])
    garbage = np.array([math.nan, math.inf, -math.inf, 1e308, -1e308, 0.0, -0.0, 5e-324,
                        1e9, -1e9, -4000.0])
    hit = rng.random(U.shape) < 0.03
    U[hit] = rng.choice(garbage, size=int(hit.sum()))
    return U


def test_random_and_adversarial_sequences_through_fmpy(fmu, unzipdir):
    """Every step returns a defined status (fmi2OK, or fmi2Discard with an error message), the
    outputs are always finite, every repaired input is flagged, and the FMI logger gets a
    message for every condition."""
    rng = np.random.default_rng(20261122)
    d = FmuDriver(fmu, unzipdir, "fuzz")
    U = _adversarial(rng, 3000)
    steps = np.full(U.shape[1], 1e-3)
    odd = rng.random(steps.size) < 0.01
    steps[odd] = rng.choice([0.0, 1e-9, 0.02, -1e-3, math.nan], size=int(odd.sum()))
    statuses = []
    for k in range(U.shape[1]):
        n_before = len(d.messages)
        st = _step_status(d, U[:, k], float(steps[k]))
        statuses.append(st)
        y = d.outputs()
        assert np.isfinite(y).all(), f"step {k}: non-finite outputs {y} for {U[:, k]}"
        bad_input = not np.isfinite(U[:, k]).all() or U[3, k] < 0 or \
            np.abs(U[:2, k]).max() > 150 or abs(U[2, k]) > 1000 or U[3, k] > 5e4
        if st == FMI_OK and bad_input:
            assert d.status() != 0, f"step {k}: repaired input not flagged: {U[:, k]}"
        if st == FMI_DISCARD:
            assert any(s == FMI_ERROR for s, _, _ in d.messages[n_before:]), \
                f"step {k}: a discarded step must log an error"
    counts = {s: statuses.count(s) for s in set(statuses)}
    assert set(counts) <= {FMI_OK, FMI_DISCARD}, f"statuses {counts}"
    assert counts[FMI_OK] > 0.9 * len(statuses)
    assert sum(s == FMI_WARNING for s, _, _ in d.messages) > 10
    d.close()


# -- standstill, creeping, reversing, lift-off -------------------------------------------------
def test_standstill_reversing_and_lift_off(fmu, unzipdir):
    d = FmuDriver(fmu, unzipdir, "slow")
    for _ in range(500):   # parked
        y = d.step([0.0, 0.0, 0.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    assert np.isfinite(y).all() and abs(y[0]) < 1.0 and y[3] == 0.0, "parked: no force"
    for k in range(1, 1001):   # roll away, then back through zero to reversing
        v = 2.0 * math.sin(2 * math.pi * k / 1000)
        y = d.step([v, 0.0, v / R_E, 4000.0, 293.15, 1.0, 0.0, 0.0])
        assert np.isfinite(y).all() and abs(y[0]) < 0.5 * 4000.0, f"creeping v = {v}"
    for _ in range(300):   # braking while reversing at 5 m/s
        y = d.step([-5.0, 0.0, -5.0 / R_E * 0.9, 4000.0, 293.15, 1.0, 0.0, 0.0])
    fx, kappa = y[OUTPUTS.index("Fx")], y[OUTPUTS.index("kappa")]
    assert fx > 500.0, f"braking in reverse pushes forwards (+x), Fx = {fx}"
    assert kappa == pytest.approx(-0.1, rel=1e-9), "braking slip keeps its sign in reverse"
    locked = np.array([d.step([-5.0, 0.0, 0.0, 4000.0, 293.15, 1.0, 0.0, 0.0]) for _ in range(200)])
    tail = locked[-100:]   # locked wheel in reverse: slides (stick-slipping), pushes forwards
    assert tail[:, OUTPUTS.index("sliding_fraction")].mean() > 0.3 and tail[:, 0].min() > 0.0
    y = d.step([-5.0, 0.0, 0.0, 0.0, 293.15, 1.0, 0.0, 0.0])
    assert y[0] == y[1] == y[2] == 0.0, "lift-off: exactly zero forces"
    assert d.status() == 0, "standstill, reversing and lift-off are normal inputs"
    d.close()


def test_reset_returns_to_a_fresh_instance(fmu, unzipdir):
    d = FmuDriver(fmu, unzipdir, "reset")
    U = braking_inputs(100)
    fresh = np.array([d.step(U[:, k]) for k in range(100)])
    d.fmu.reset()
    d.fmu.setupExperiment(startTime=0.0)
    d.fmu.enterInitializationMode()
    d.fmu.exitInitializationMode()
    d.time = 0.0
    again = np.array([d.step(U[:, k]) for k in range(100)])
    assert again.tobytes() == fresh.tobytes(), "fmi2Reset must give a fresh tire"
    d.close()


@pytest.mark.slow
def test_quarter_car_example_on_the_shipped_grid(tmp_path):
    """The example's vehicle loop on the default grid: the locked wheel brakes the car."""
    import runpy
    from pathlib import Path

    from fmu_src.make.build import build_fmu

    ex = runpy.run_path(str(Path(__file__).parents[1] / "examples" / "quarter_car_braking.py"))
    fmu = build_fmu("passenger", "default", tmp_path / "BrushTire.fmu").path
    data = ex["simulate"](fmu, mass=400.0, inertia=1.0, v0=20.0, torque=2500.0,
                          ramp=(0.05, 0.2), T_road=293.15, t_max=1.0)
    assert data["kappa"][-1] == pytest.approx(-1.0), "the wheel locks"
    assert data["v"][-1] < 20.0 - 5.0, "the car slows down"
    assert data["dT_flash_max"].max() > 5.0, "sliding heats the contacts"
    ex["plot"](data, tmp_path / "braking.png", "test")
    assert (tmp_path / "braking.png").stat().st_size > 10_000


@pytest.mark.slow
def test_long_adversarial_soak(fmu, unzipdir):
    """Ten times the default fuzz, several seeds (slow)."""
    for seed in range(3):
        rng = np.random.default_rng(seed)
        d = FmuDriver(fmu, unzipdir, f"soak{seed}", logging=False)
        U = _adversarial(rng, 10000)
        for k in range(U.shape[1]):
            _step_status(d, U[:, k])
            assert np.isfinite(d.outputs()).all(), f"seed {seed} step {k}"
        d.close()


def test_extreme_inputs_after_lift_off_leave_no_hidden_state(fmu, unzipdir):
    """From a lift-off state, one step of extreme inputs (clamped by the guard, input_status
    29) used to leave the old tire core in a lateral limit cycle (Fy flipping sign every step
    at 3-5 kN). Now the forces settle, within 0.5 s of steady braking inputs, on those of a
    fresh instance given the same inputs (thermal state off, so that the one 500 K step of
    T_surface does not linger in the tread temperature): step-to-step change below 1 % Fz and
    the same forces within 1 % Fz. Braking at 5 % slip: at 10 % this test grid's falling
    mu(v) makes the tread stick-slip (docs/tire-core.md), fresh instance included."""
    start = {"tire.thermal.enabled": False}
    vx, FZ = 20.0, 4000.0
    braking = [vx, 0.0, vx * 0.95 / R_E, FZ, 293.15, 1.0, 0.0, 0.0]
    hit = FmuDriver(fmu, unzipdir, "hit", start_values=start)
    fresh = FmuDriver(fmu, unzipdir, "fresh", start_values=start)
    for _ in range(50):
        hit.step(braking)
    for _ in range(20):
        hit.step([vx, 0.0, vx * 0.9 / R_E, 0.0, 293.15, 1.0, 0.0, 0.0])          # lift-off
    hit.step([-1e30, 1e6, vx * 0.9 / R_E, 1e308, 3e38, -math.inf])  # clamped
    # the guard reports what it clamped; the model that it read the friction at 500 K, above
    # the grid's 393 K
    assert hit.status() == 29 | STATUS_BITS["temperature_range"]
    a = np.array([hit.step(braking) for _ in range(500)])
    b = np.array([fresh.step(braking) for _ in range(500)])
    tail = slice(400, 500)
    assert np.abs(np.diff(a[tail, :2], axis=0)).max() < 1e-2 * FZ, "settled"
    assert np.abs(a[tail, :2] - b[tail, :2]).max() < 1e-2 * FZ, "as a fresh instance"
    assert np.abs(a[tail, 1]).max() < 1e-3 * FZ, "no lateral force without lateral slip"
    assert hit.status() == 0
    hit.close()
    fresh.close()


def _run_exit_paths(fmu, n: int) -> list[int]:
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).parent / "fmu_exit_paths.py"
    codes = []
    for _ in range(n):
        r = subprocess.run([sys.executable, str(script), str(fmu)], capture_output=True,
                           text=True, timeout=300,
                           env={**__import__("os").environ, "MALLOC_CHECK_": "3"})
        codes.append(r.returncode)
        assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stderr[-2000:]
    return codes


def test_in_process_fmu_paths_exit_cleanly(fmu):
    """The quarter car (locked and ABS), four instances, misuse and a corrupt state blob in
    one process, instances left to the interpreter's shutdown: exit status 0 (with glibc's
    heap checks on: MALLOC_CHECK_=3)."""
    assert _run_exit_paths(fmu, 1) == [0]


@pytest.mark.slow
def test_in_process_fmu_paths_exit_cleanly_twenty_times(fmu):
    """The same, 20 times: a heap corruption that strikes one run in three is caught."""
    assert _run_exit_paths(fmu, 20) == [0] * 20


def test_c_host_without_numpy_gets_a_message_not_a_crash(fmu, tmp_path):
    """A C host with libpython in the process whose Python cannot import numpy (stood in for
    by a ``numpy`` that raises ImportError first on PYTHONPATH): fmi2Instantiate returns NULL
    and the FMI logger says what is missing and which flavour to take; no crash."""
    import os
    import shutil
    import subprocess
    import sysconfig
    import zipfile

    import fmpy

    from fmu_src.make.native_build import NATIVE_DIR

    libpython = Path(sysconfig.get_config_var("LIBDIR") or "") / str(
        sysconfig.get_config_var("INSTSONAME") or "")
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None or not libpython.is_file():
        pytest.skip("needs a C compiler and a shared libpython")
    exe = tmp_path / "host"
    subprocess.run([cc, "-std=c99", "-O2", "-DHOST_LOGGING=fmi2True", "-I",
                    str(NATIVE_DIR / "fmi2"), str(NATIVE_DIR / "host_example.c"), "-o",
                    str(exe), "-ldl", "-lm"], check=True)
    unz = tmp_path / "fmu"
    zipfile.ZipFile(fmu).extractall(unz)
    md = fmpy.read_model_description(str(fmu))
    so = unz / "binaries" / "linux64" / f"{md.coSimulation.modelIdentifier}.so"
    fake = tmp_path / "fake" / "numpy"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('no numpy here (test stand-in)')\n")
    env = {**os.environ, "PYTHONPATH": str(fake.parent), "LD_PRELOAD": str(libpython)}
    r = subprocess.run([str(exe), str(so), (unz / "resources").as_uri(), md.guid, "5", "1"],
                       capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 3, (r.returncode, r.stderr[-2000:])   # instantiate refused
    assert "needs numpy" in r.stderr and "--native" in r.stderr, r.stderr[-2000:]
