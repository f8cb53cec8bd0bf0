"""The native FMU in C/C++ hosts other than fmpy: libcosim (C++, through libcosimpy) with four
instances, and the win64 cross-build (exports checked; not run: no Windows here)."""

from __future__ import annotations

import shutil
import subprocess
import zipfile

import numpy as np
import pytest
from fmu_support import synthetic_grid

from fmu_src.make.native_build import MODEL_IDENTIFIER, build_native_fmu, compilers
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.transient import TransientBrushTire

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
U = [20.0, 0.3, 20.0 * 0.95 / 0.31, 4000.0, 293.15, 1.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def fmu(tmp_path_factory):
    return build_native_fmu("passenger", synthetic_grid(),
                            tmp_path_factory.mktemp("hosts") / "BrushTireNative.fmu",
                            platforms=("linux64",)).path


def test_libcosim_runs_four_native_tires(fmu):
    """libcosim (C++) loads the FMU four times and steps it; each tire equals the Python
    model to 1e-9 (libcosim's time is integer nanoseconds: its step is 1e-3 s to ~1 ulp, so
    the inputs are kept out of the stick-slip regime, where such a difference grows)."""
    pytest.importorskip("libcosimpy")
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    ex = CosimExecution.from_step_size(step_size=1_000_000)       # 1 ms in ns
    idx = [ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=f"tire{i}"))
           for i in range(4)]
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    man = CosimManipulator.create_override()
    ex.add_manipulator(man)
    for i in idx:
        for vr, x in enumerate(U):
            ex.real_initial_value(i, vr, x * (1.0 + 0.1 * i) if vr == 3 else x)
    assert ex.step(150)
    model = [TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()))
             for _ in idx]
    for i, m in zip(idx, model, strict=True):
        u = [*U[:3], U[3] * (1.0 + 0.1 * i), *U[4:]]
        for _ in range(150):
            ref = m.step(1e-3, *u).as_array()
        got = np.array(obs.last_real_values(i, list(range(8, 20))))
        np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-12)
    assert len({tuple(obs.last_real_values(i, [8])) for i in idx}) == 4, "independent tires"


@pytest.mark.skipif("win64" not in compilers(), reason="no win64 cross-compiler (mingw-w64 "
                    "or the ziglang wheel)")
def test_win64_cross_build_exports_fmi(tmp_path):
    """The win64 DLL is built and exports the FMI functions (not run: no Windows here)."""
    r = build_native_fmu("passenger", synthetic_grid(), tmp_path / "w.fmu",
                         platforms=("linux64", "win64"))
    with zipfile.ZipFile(r.path) as z:
        dll = z.read(f"binaries/win64/{MODEL_IDENTIFIER}.dll")
    assert dll[:2] == b"MZ"
    for name in (b"fmi2Instantiate", b"fmi2DoStep", b"fmi2SerializeFMUstate"):
        assert name in dll
    objdump = shutil.which("objdump")
    if objdump:
        (tmp_path / "x.dll").write_bytes(dll)
        out = subprocess.run([objdump, "-p", str(tmp_path / "x.dll")], capture_output=True,
                             text=True, check=False).stdout
        if "Export" in out:
            assert "fmi2DoStep" in out and "pei-x86-64" in out


def test_reference_fmus_import_layer_host(fmu, tmp_path):
    """The FMI import layer of the Modelica Reference FMUs (``src/FMI.c``, ``src/FMI2.c``,
    what their ``fmusim`` is built on) loads and steps the FMU, with a rollback through
    serialize/deserialize; equal to the Python model. Needs ``$REFERENCE_FMUS`` = a checkout
    of github.com/modelica/Reference-FMUs (not shipped)."""
    import os
    from pathlib import Path

    import fmpy

    root = os.environ.get("REFERENCE_FMUS")
    if not root or not (Path(root) / "src" / "FMI2.c").is_file():
        pytest.skip("set REFERENCE_FMUS to a checkout of modelica/Reference-FMUs")
    root = Path(root)
    exe = tmp_path / "rhost"
    src = [str(root / "src" / f) for f in ("FMI.c", "FMI2.c", "FMI3.c")
           if (root / "src" / f).is_file()]
    subprocess.run(["cc", "-std=c99", "-D_GNU_SOURCE", "-O2", "-I", str(root / "include"),
                    "-o", str(exe), str(Path(__file__).with_name("reffmus_host.c")), *src,
                    "-ldl", "-lm"], check=True, capture_output=True)
    unz = Path(fmpy.extract(str(fmu)))
    guid = fmpy.read_model_description(str(fmu)).guid
    res = subprocess.run([str(exe), str(unz / "binaries" / "linux64" /
                                        f"{MODEL_IDENTIFIER}.so"),
                          (unz / "resources").as_uri(), guid, "100"], capture_output=True,
                         text=True, check=False)
    assert res.returncode == 0, res.stderr
    first, replay = ([float(x) for x in line.split()] for line in res.stdout.splitlines())
    assert first == replay, "rollback through serialize/deserialize replays bit for bit"
    m = TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()))
    for _ in range(100):
        out = m.step(1e-3, *U)
    assert first == [out.Fx, out.Fy, out.Mz]
