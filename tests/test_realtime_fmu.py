"""The real-time fidelity through both FMU flavours (docs/realtime.md, docs/fmu.md).

Built with ``fidelity="realtime"`` (coarse table axes: the packaging, the selection and the
FMI behaviour are under test here, not the table's resolution), the FMU computes what the
Python model at that fidelity computes, bit for bit; the parameter ``fidelity`` selects either
fidelity in one build; a build without the table and parameters the table was not built for
are refused; rollback, four instances and the fuzz hold as for the full fidelity.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from fmu_support import FmuDriver, braking_inputs, synthetic_grid
from test_fmu_fuzz import _check, fuzz_one
from test_realtime import SMALL_AXES

from fmu_src.make.build import BuildOptions, build_fmu
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.realtime_build import cached_patch_table
from tire_brush.transient import TransientBrushTire

HAS_CC = shutil.which("cc") is not None or shutil.which("gcc") is not None
OPTS = {"fidelity": "realtime", "realtime_axes": SMALL_AXES}


@pytest.fixture(scope="module", params=["pythonfmu", "native"])
def flavour(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(f"rt_{request.param}")
    if request.param == "pythonfmu":
        return request.param, build_fmu("passenger", synthetic_grid(), d / "rt.fmu",
                                        BuildOptions(**OPTS)).path
    if not HAS_CC:
        pytest.skip("the native FMU needs a C compiler")
    from fmu_src.make.native_build import build_native_fmu

    return request.param, build_native_fmu("passenger", synthetic_grid(), d / "rtn.fmu",
                                           BuildOptions(**OPTS), platforms=("linux64",)).path


def _model(fidelity: int = 1) -> TransientBrushTire:
    tp = load_tire("passenger")
    g = synthetic_grid()
    table = None
    if fidelity:
        table, _ = cached_patch_table(tp, GridFriction(g), axes=SMALL_AXES)
    return TransientBrushTire(tp, GridFriction(g), patch=table)


@pytest.mark.parametrize("fidelity", [1, 0])
def test_fmu_equals_the_python_model_at_either_fidelity(flavour, fidelity):
    """400 braking steps (load, temperature, friction and camber changes): the FMU at
    ``fidelity`` is the Python model at that fidelity, bit for bit (the same core)."""
    _, fmu = flavour
    U = braking_inputs(400)
    drv = FmuDriver(fmu, None, start_values={"fidelity": fidelity})
    model = _model(fidelity)
    for k in range(U.shape[1]):
        u = [float(x) for x in U[:, k]]
        assert np.array_equal(drv.step(u), np.array(model.step_array(1e-3, *u))), k
    drv.close()


def test_realtime_build_starts_at_fidelity_1_and_full_build_refuses_it(flavour, tmp_path):
    from fmpy import read_model_description
    from fmpy.fmi1 import FMICallException

    name, fmu = flavour
    md = read_model_description(str(fmu))
    assert next(v.start for v in md.modelVariables if v.name == "fidelity") == "1"
    if name == "native":
        from fmu_src.make.native_build import build_native_fmu
        full = build_native_fmu("passenger", synthetic_grid(), tmp_path / "f.fmu",
                                platforms=("linux64",)).path
        with pytest.raises(FMICallException):
            FmuDriver(full, None, start_values={"fidelity": 1})
        for bad in ({"fidelity": 2}, {"tire.tread.k_x": 8e7}, {"s0": 1e-3}):
            with pytest.raises(FMICallException):
                FmuDriver(fmu, None, start_values=bad)
        # the belt and the thermal state run in the fidelity's own dynamics: free to change
        FmuDriver(fmu, None, start_values={"tire.carcass.k_y": 2e5}).close()


def test_pythonfmu_refusals_are_logged():
    """The pythonfmu slave logs the same refusals (it cannot return fmi2Error) and discards
    the steps."""
    import tempfile
    from pathlib import Path

    from fmu_src.make.stage import stage_resources
    from fmu_src.runtime.slave import BrushTireSlave

    with tempfile.TemporaryDirectory() as d:
        stage_resources(load_tire("passenger"), synthetic_grid(), Path(d), BuildOptions(**OPTS))
        for bad, msg in (({"fidelity": 3}, "must be 0"), ({"tire.tread.k_x": 8e7}, "k_x")):
            s = BrushTireSlave(instance_name="s", resources=d)
            logs: list[str] = []

            def log(m, *a, _logs=logs, **k):
                _logs.append(m)
            s.log = log
            vr = {v.name: v.value_reference for v in s.vars.values()}
            s.enter_initialization_mode()
            for key, val in bad.items():
                (s.set_integer if key == "fidelity" else s.set_real)([vr[key]], [val])
            s.exit_initialization_mode()
            assert any(msg in m for m in logs), logs
            assert s.do_step(0.0, 1e-3) is False


def test_rollback_and_four_instances(flavour):
    name, fmu = flavour
    U = braking_inputs(120)
    drv = FmuDriver(fmu, None)
    for k in range(60):
        drv.step(list(U[:, k]))
    s = drv.fmu.getFMUstate()
    t0 = drv.time
    first = [drv.step(list(U[:, k])) for k in range(60, 120)]
    drv.fmu.setFMUstate(s)
    drv.time = t0
    again = [drv.step(list(U[:, k])) for k in range(60, 120)]
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    if name == "native":
        blob = drv.fmu.serializeFMUstate(s)
        drv.fmu.setFMUstate(drv.fmu.deSerializeFMUstate(blob))
        drv.time = t0
        third = [drv.step(list(U[:, k])) for k in range(60, 120)]
        assert all(np.array_equal(a, b) for a, b in zip(first, third, strict=True))
    drv.fmu.freeFMUstate(s)
    drv.close()
    drvs = [FmuDriver(fmu, None, name=f"t{i}") for i in range(4)]
    models = [_model() for _ in range(4)]
    for k in range(100):
        for i, (d, m) in enumerate(zip(drvs, models, strict=True)):
            u = [float(x) for x in U[:, k] * (1.0 + 0.05 * i)]
            assert np.array_equal(d.step(u), np.array(m.step_array(1e-3, *u)))
    for d in drvs:
        d.close()


def test_nan_and_negative_load_are_guarded(flavour):
    """NaN inputs and a negative load: reported through input_status (bits 1 and 2) with
    finite outputs; a negative load is lift-off (no forces)."""
    _, fmu = flavour
    drv = FmuDriver(fmu, None)
    for _ in range(20):
        drv.step([20.0, 0.3, 61.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    out = drv.step([float("nan"), 0.3, 61.0, -500.0, 293.15, 1.0, 0.0, 0.0])
    assert np.isfinite(out).all()
    assert drv.status() & 1 and drv.status() & 2
    assert out[0] == 0.0 and out[1] == 0.0
    drv.close()


def test_fuzz_smoke(flavour):
    """A short run of the FMU fuzz (test_fmu_fuzz.py) at the real-time fidelity."""
    name, fmu = flavour
    _check({99: fuzz_one(fmu, None, seed=99, n=400)}, f"{name} real-time")
    _check({1000: fuzz_one(fmu, None, seed=1000, n=400, thermal=True)}, f"{name} real-time",
           recovery=False)


@pytest.mark.slow
def test_fuzz_ten_seeds(flavour):
    """Seeds 1000-1009 x 1e4 steps at the real-time fidelity, and three with the thermal
    state on: no crash, non-finite output, hang, unrecovered state or heat above the work."""
    import fmpy

    name, fmu = flavour
    unz = fmpy.extract(str(fmu))
    _check({s: fuzz_one(fmu, unz, s, 10_000) for s in range(1000, 1010)}, f"{name} rt")
    _check({s: fuzz_one(fmu, unz, s, 10_000, thermal=True) for s in range(1000, 1003)},
           f"{name} rt thermal", recovery=False)
