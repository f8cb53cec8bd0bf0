"""The native (Python-free) FMU: build, validation, same model description as the pythonfmu
flavour, equality with the Python model, input guard, FMU state, misuse, several instances,
and a C host that loads the binary with dlopen."""

from __future__ import annotations

import ctypes
import math
import shutil
import subprocess
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmu_support import INPUTS, OUTPUTS, FmuDriver, braking_inputs, synthetic_grid

from fmu_src.make.build import BuildOptions
from fmu_src.make.native_build import (
    C_SOURCES,
    MODEL_IDENTIFIER,
    TABLE_FILE,
    build_native_fmu,
)
from fmu_src.runtime.guard import InputGuard
from fmu_src.runtime.interface import LIMITS, default_limits
from fmu_src.runtime.table_file import read_table_bytes
from tire_brush.friction import GridFriction, as_table
from tire_brush.params import load_tire
from tire_brush.transient import TransientBrushTire

pytestmark = pytest.mark.skipif(shutil.which("cc") is None and shutil.which("gcc") is None,
                                reason="needs a C compiler")


@pytest.fixture(scope="module")
def fmu(tmp_path_factory):
    d = tmp_path_factory.mktemp("native")
    return build_native_fmu("passenger", synthetic_grid(), d / "BrushTireNative.fmu",
                            platforms=("linux64",)).path


@pytest.fixture(scope="module")
def unzipdir(fmu):
    import fmpy

    return fmpy.extract(str(fmu))


def _model(**kw):
    return TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid(), **kw))


def test_native_fmu_passes_fmpy_validation(fmu):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
    assert f"binaries/linux64/{MODEL_IDENTIFIER}.so" in names
    assert f"resources/{TABLE_FILE}" in names and "sources/fmu_wrapper.c" in names
    assert not any(n.endswith(".py") for n in names), "nothing of Python in the native FMU"


def test_native_model_description_equals_pythonfmu_variables(fmu, tmp_path):
    """Same variables, units, starts, structure as the pythonfmu flavour (one generator)."""
    from fmu_support import build_test_fmu

    py = build_test_fmu(tmp_path)

    def parts(path):
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
        mv = ET.tostring(root.find("ModelVariables"))
        units = ET.tostring(root.find("UnitDefinitions"))
        ms = ET.tostring(root.find("ModelStructure"))
        cs = root.find("CoSimulation")
        return mv, units, ms, cs, root

    a, b = parts(py), parts(fmu)
    # info.build_id differs (another build); everything else is equal
    mv_a = a[0].replace(a[4].find(".//ScalarVariable[@name='info.build_id']/String")
                        .get("start").encode(), b"X")
    mv_b = b[0].replace(b[4].find(".//ScalarVariable[@name='info.build_id']/String")
                        .get("start").encode(), b"X")
    assert mv_a == mv_b and a[1] == b[1] and a[2] == b[2]
    assert b[3].get("modelIdentifier") == MODEL_IDENTIFIER
    assert b[3].get("needsExecutionTool") == "false"
    assert b[3].get("canGetAndSetFMUstate") == "true"
    assert [f.get("name") for f in b[3].findall("SourceFiles/File")] == list(C_SOURCES)


def test_table_resource_is_the_models_table(fmu):
    with zipfile.ZipFile(fmu) as z:
        t = read_table_bytes(z.read(f"resources/{TABLE_FILE}"))
    ref = as_table(GridFriction(synthetic_grid()))
    for k in ("log10_v", "T", "log10_p", "values"):
        assert np.array_equal(t[k], getattr(ref, k))


def _compare(drv, model, U, dt=1e-3):
    worst = 0.0
    for k in range(U.shape[1]):
        got = drv.step(list(U[:, k]), dt)
        ref = np.array(model.step(dt, *(float(x) for x in U[:, k])).as_array())
        scale = np.maximum(np.abs(ref), 1e-300)
        err = np.where(ref == got, 0.0, np.abs(got - ref) / scale)
        worst = max(worst, float(err.max()))
        assert np.allclose(got, ref, rtol=1e-9, atol=1e-12), f"step {k}: {got} != {ref}"
    return worst


def test_native_equals_python_model_braking(fmu, unzipdir):
    """Equal to TransientBrushTire (backend c) within 1e-9 relative over 400 braking steps
    (in fact bit for bit: the same core compiled with the same flags)."""
    U = braking_inputs(400)
    drv = FmuDriver(fmu, unzipdir)
    worst = _compare(drv, _model(), U)
    drv.close()
    assert worst <= 1e-9
    assert U.shape[1] == 400


@pytest.mark.parametrize("ageing", [True, False])
def test_native_honours_parameters(fmu, unzipdir, ageing):
    """n_elements, dt_internal, s0, v_floor and tire parameters (a number and the contact
    age's switch) set before initialisation."""
    tire = load_tire("passenger")
    start = {"n_elements": 20, "dt_internal": 5e-4, "s0": 1e-3, "v_floor": 0.5,
             "tire.tread.k_x": 1.5 * tire.tread.k_x, "tire.thermal.enabled": False,
             "tire.tread.contact_ageing": ageing}
    drv = FmuDriver(fmu, unzipdir, start_values=start)
    from dataclasses import replace

    t2 = replace(tire, tread=replace(tire.tread, k_x=1.5 * tire.tread.k_x,
                                     contact_ageing=ageing),
                 thermal=replace(tire.thermal, enabled=False))
    model = TransientBrushTire(t2, GridFriction(synthetic_grid(), s0=1e-3), n_elements=20,
                               dt_internal=5e-4, v_floor=0.5)
    _compare(drv, model, braking_inputs(150))
    drv.close()


def _guard_reference(U, tire):
    g = InputGuard(default_limits(tire), [0.0, 0.0, 0.0, tire.Fz_nom, 293.15, 1.0, 0.0, 0.0])
    return [g.apply(list(u))[:2] for u in U]


def test_native_input_guard_matches_python_guard(fmu, unzipdir):
    tire = load_tire("passenger")
    nan, inf = math.nan, math.inf
    U = [[20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0],
         [nan, 0.1, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0],
         [20.0, 0.0, 60.0, -500.0, 293.15, 1.0, 0.0, 0.0],
         [1e9, -1e9, 1e12, 1e12, 1e5, 1e3, 0.0, 0.0],
         [-inf, inf, nan, nan, nan, nan, 0.0, 0.0],
         [20.0, 0.0, 60.0, 4000.0, 10.0, -1.0, 0.0, 0.0],
         [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0],
         [-3.0, 0.5, -10.0, 3000.0, 300.0, 0.5, 0.0, 0.0],
         [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.03, 0.0],
         [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, nan, 0.0],
         [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, -2.0, 0.0]]
    ref = _guard_reference(U, tire)
    drv = FmuDriver(fmu, unzipdir)
    py = _model()
    for u, (x, status) in zip(U, ref, strict=True):
        got = drv.step(u)
        assert drv.status() == status, f"input_status for {u}"
        want = py.step(1e-3, *x).as_array()
        assert np.array_equal(got, want), f"guarded inputs {x}"
        assert np.isfinite(got).all()
    drv.close()
    warnings = [m for s, _, m in drv.messages if s == 1]
    assert any("not finite" in m for m in warnings) and any("negative" in m for m in warnings)
    assert any("cleared" in m for _, _, m in drv.messages)


def test_native_dostep_status_codes(fmu, unzipdir):
    from fmpy.fmi1 import FMICallException

    drv = FmuDriver(fmu, unzipdir)
    drv.step([20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    # repaired inputs: fmi2Warning (fmpy returns it, it does not raise)
    drv.fmu.setReal([drv.vr["Fz"]], [-1.0])
    assert drv.fmu.fmi2DoStep(drv.fmu.component, drv.time, 1e-3, 1) == 1
    drv.time += 1e-3
    for bad in (-1e-3, math.nan, math.inf, 1e6):
        with pytest.raises(FMICallException) as e:
            drv.fmu.doStep(drv.time, bad)
        assert e.value.status == 3, "fmi2Error (not Fatal) for a bad communication step"
    drv.fmu.setReal([drv.vr["Fz"]], [4000.0])
    assert np.isfinite(drv.step([20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])).all()
    drv.close()


def test_native_misuse_is_fmi2error_and_changes_nothing(fmu, unzipdir):
    from fmpy.fmi1 import FMICallException

    drv = FmuDriver(fmu, unzipdir)
    drv.step([20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    before = drv.outputs()
    f = drv.fmu
    n_vars = len(drv.md.modelVariables)
    calls = [lambda: f.setReal([drv.vr["tire.R_e"]], [0.4]),       # fixed after init
             lambda: f.setReal([drv.vr["Fx"]], [1.0]),             # output
             lambda: f.setReal([n_vars + 5], [1.0]),               # unknown vr
             lambda: f.getReal([n_vars]),                          # unknown vr
             lambda: f.setInteger([drv.vr["vx"]], [1]),            # wrong type
             lambda: f.getReal([drv.vr["n_elements"]]),            # wrong type
             lambda: f.setInteger([drv.vr["n_elements"]], [10]),   # fixed after init
             lambda: f.setString([drv.vr["info.tire"]], ["x"]),    # constant
             lambda: f.setReal([drv.vr["vx"], drv.vr["Fy"]], [99.0, 1.0])]  # atomic
    for call in calls:
        with pytest.raises(FMICallException) as e:
            call()
        assert e.value.status == 3
    assert f.getReal([drv.vr["vx"]])[0] == 20.0, "a refused multi-set sets nothing"
    assert f.getReal([drv.vr["tire.R_e"]])[0] == load_tire("passenger").R_e
    assert np.array_equal(drv.outputs(), before)
    assert f.getString([drv.vr["info.tire"]])[0] == b"passenger"
    assert any("fixed" in m for s, _, m in drv.messages if s == 3)
    drv.close()


def test_native_bad_parameters_refused_at_initialisation(fmu, unzipdir):
    from fmpy.fmi1 import FMICallException

    for bad in ({"tire.R_e": -1.0}, {"n_elements": 1}, {"dt_internal": math.nan},
                {"limit.T_min": 600.0}, {"s0": -1.0}):
        with pytest.raises(FMICallException) as e:
            FmuDriver(fmu, unzipdir, start_values=bad)
        assert e.value.status == 3, bad


def test_native_state_get_set_serialize_exact(fmu, unzipdir):
    from fmpy.fmi1 import FMICallException

    U = braking_inputs(120)
    drv = FmuDriver(fmu, unzipdir)
    f = drv.fmu
    for k in range(60):
        drv.step(list(U[:, k]))
    s = f.getFMUstate()
    blob = f.serializeFMUstate(s)
    t0 = drv.time
    first = [drv.step(list(U[:, k])) for k in range(60, 120)]
    f.setFMUstate(s)
    drv.time = t0
    again = [drv.step(list(U[:, k])) for k in range(60, 120)]
    assert all(np.array_equal(a, b) for a, b in zip(first, again, strict=True))
    s2 = f.deSerializeFMUstate(blob)
    f.setFMUstate(s2)
    drv.time = t0
    third = [drv.step(list(U[:, k])) for k in range(60, 120)]
    assert all(np.array_equal(a, b) for a, b in zip(first, third, strict=True))
    assert bytes(f.serializeFMUstate(f.getFMUstate())) != bytes(blob)
    # corrupt blobs are refused with fmi2Error; the state stays as it was
    now = drv.outputs()
    for bad in (blob[:-1], blob[:10], bytes([blob[0] ^ 1]) + bytes(blob[1:]),
                bytes(blob[:100]) + bytes([blob[100] ^ 0x40]) + bytes(blob[101:])):
        with pytest.raises(FMICallException) as e:
            f.deSerializeFMUstate(bad)
        assert e.value.status == 3
    assert np.array_equal(drv.outputs(), now)
    f.freeFMUstate(s)
    f.freeFMUstate(s2)
    drv.close()


def test_native_state_with_other_parameters_rebuilds(fmu, unzipdir):
    """A state taken with other parameters (another instance's blob) restores them too."""
    U = braking_inputs(80)
    a = FmuDriver(fmu, unzipdir, name="a", start_values={"n_elements": 20})
    b = FmuDriver(fmu, unzipdir, name="b")
    for k in range(40):
        a.step(list(U[:, k]))
    blob = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
    b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(blob))
    b.time = a.time
    assert b.fmu.getInteger([b.vr["n_elements"]])[0] == 20
    for k in range(40, 80):
        assert np.array_equal(a.step(list(U[:, k])), b.step(list(U[:, k])))
    a.close()
    b.close()


def test_native_instances_are_independent(fmu, unzipdir):
    U = braking_inputs(100)
    drvs = [FmuDriver(fmu, unzipdir, name=f"t{i}") for i in range(4)]
    models = [_model() for _ in range(4)]
    for k in range(100):
        for i, (d, m) in enumerate(zip(drvs, models, strict=True)):
            u = U[:, k] * (1.0 + 0.05 * i)
            assert np.array_equal(d.step(list(u)), m.step(1e-3, *map(float, u)).as_array())
    for d in drvs:
        d.close()


def test_native_limits_are_parameters(fmu, unzipdir):
    drv = FmuDriver(fmu, unzipdir, start_values={"limit.Fz": 3000.0})
    drv.step([20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    assert drv.status() == 8
    assert set(LIMITS) <= set(drv.vr)
    drv.close()


# -- a C host ----------------------------------------------------------------------------------
def compile_host(source, unzipdir, exe):
    """Compile a C host against the FMI headers in the FMU's sources/."""
    from pathlib import Path

    subprocess.run(["cc", "-std=c99", "-O2", "-I", str(Path(unzipdir) / "sources"), "-o",
                    str(exe), str(source), "-ldl", "-lm"], check=True)
    return exe


def test_c_host_dlopens_and_steps(fmu, unzipdir, tmp_path):
    """fmu_src/runtime/native/host_example.c (the README's example) loads the binary with dlopen and
    steps 4 tires; tire 0 equals the Python model bit for bit."""
    from pathlib import Path

    import fmpy

    from fmu_src.make.native_build import NATIVE_DIR

    exe = compile_host(NATIVE_DIR / "host_example.c", unzipdir, tmp_path / "host")
    md = fmpy.read_model_description(str(fmu))
    lib = Path(unzipdir) / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so"
    uri = (Path(unzipdir) / "resources").as_uri()
    res = subprocess.run([str(exe), str(lib), uri, md.guid, "100", "4"], capture_output=True,
                         text=True, check=False)
    assert res.returncode == 0, res.stdout + res.stderr
    got = [float(x) for x in res.stdout.splitlines()[0].split()]
    assert res.stdout.splitlines()[1].startswith("median_us ")
    model = _model()
    for k in range(100):
        out = model.step(1e-3, 20.0, 0.3, 20.0 * (1.0 - 0.05 * (k > 20)) / 0.31, 4000.0,
                         293.15, 1.0)
    assert got == [out.Fx, out.Fy, out.Mz]
    # a wrong GUID is refused at instantiation
    res = subprocess.run([str(exe), str(lib), uri, "{wrong}", "1"], capture_output=True,
                         text=True, check=False)
    assert res.returncode == 3 and "GUID" in res.stderr


def test_ctypes_symbols_are_only_fmi(fmu, unzipdir):
    from pathlib import Path

    lib = ctypes.CDLL(str(Path(unzipdir) / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so"))
    assert hasattr(lib, "fmi2DoStep")
    assert not hasattr(lib, "tf_tire_step"), "the core's symbols stay inside the FMU"


def test_build_options_are_start_values(tmp_path):
    r = build_native_fmu("passenger", synthetic_grid(), tmp_path / "o.fmu",
                         BuildOptions(n_elements=24, dt_internal=5e-4), platforms=("linux64",))
    import fmpy

    md = fmpy.read_model_description(str(r.path))
    by = {v.name: v for v in md.modelVariables}
    assert by["n_elements"].start == "24" and float(by["dt_internal"].start) == 5e-4
    drv = FmuDriver(r.path)
    model = TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()),
                               n_elements=24, dt_internal=5e-4)
    _compare(drv, model, braking_inputs(50))
    drv.close()
    assert set(INPUTS) | set(OUTPUTS) <= set(by)


def test_cli_build_native_and_info(tmp_path, capsys):
    import json

    from tirefric.cli import main

    grid = tmp_path / "g.npz"
    synthetic_grid().save_npz(grid)
    out = tmp_path / "cli.fmu"
    assert main(["fmu", "build", "--native", "--grid", str(grid), "-o", str(out),
                 "--n-elements", "40", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["path"] == str(out)
    assert main(["fmu", "info", str(out), "--json", "--validate"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["flavour"] == "native" and info["validation_problems"] == []
    assert info["options"]["n_elements"] == 40 and "linux64" in info["native"]["platforms"]
    assert main(["fmu", "info", str(out)]) == 0
    assert "needs     nothing" in capsys.readouterr().out


def test_native_initial_outputs_and_reset(fmu, unzipdir):
    """Before the first step: zero forces, the reported slips of the start inputs and
    T_tread = T_surface (as the pythonfmu slave); fmi2Reset gives a fresh instance."""
    from tire_brush.slip import slip_from_kinematics

    tire = load_tire("passenger")
    start = {"vx": 10.0, "vy": -1.0, "omega": 30.0, "T_surface": 300.0}
    drv = FmuDriver(fmu, unzipdir, start_values=start)
    kappa, alpha = slip_from_kinematics(10.0, -1.0, 30.0, tire.R_e, 0.1)
    assert drv.outputs().tolist() == [0.0, 0.0, 0.0, kappa, alpha, 0.0, 0.0, 0.0, 0.0, 300.0,
                                      0.0, 0.0]
    for _ in range(20):
        drv.step([20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    f = drv.fmu
    f.reset()
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.setInteger([drv.vr["n_elements"]], [20])
    f.exitInitializationMode()
    drv.time = 0.0
    model = TransientBrushTire(tire, GridFriction(synthetic_grid()), n_elements=20)
    _compare(drv, model, braking_inputs(30))
    drv.close()
