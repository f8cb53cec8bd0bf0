"""Fuzz of the native FMU from a C host (tests/native_fuzz.c): adversarial inputs, odd and long
(0.05-0.3 s) steps, random rollbacks (get/set and serialize/deserialize, across two
instances), corrupt state blobs and misuse. No crash, every output finite, every status as
documented; without sanitizers, no doStep above the CPU bound of tests/test_fmu_fuzz.py."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from fmu_support import synthetic_grid

from fmu_src.make.native_build import C_SOURCES, MODEL_IDENTIFIER, build_native_fmu

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
FUZZ = Path(__file__).with_name("native_fuzz.c")


@pytest.fixture(scope="module")
def fmu_dir(tmp_path_factory):
    import fmpy

    d = tmp_path_factory.mktemp("native_fuzz")
    fmu = build_native_fmu("passenger", synthetic_grid(), d / "BrushTireNative.fmu",
                           platforms=("linux64",)).path
    unz = Path(fmpy.extract(str(fmu)))
    return unz, fmpy.read_model_description(str(fmu)).guid


def _run(unz, guid, lib, steps, seed, flags=(), cpu=True):
    exe = lib.with_name(lib.stem + "_fuzz")
    subprocess.run(["cc", "-std=c99", "-O1", "-g", *flags, "-I", str(unz / "sources"), "-o",
                    str(exe), str(FUZZ), "-ldl", "-lm"], check=True)
    res = subprocess.run([str(exe), str(lib), (unz / "resources").as_uri(), guid, str(steps),
                          str(seed), str(int(cpu))], capture_output=True, text=True, check=False,
                         timeout=1800)
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-4000:]
    counts = dict(zip(*[iter(res.stdout.split())] * 2, strict=True))
    assert int(counts["steps"]) == steps
    assert int(counts["corrupt_refused"]) > 0 and int(counts["rollbacks"]) > 0
    return counts


def test_fuzz_short(fmu_dir):
    unz, guid = fmu_dir
    _run(unz, guid, unz / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so", 5000, 1)


@pytest.mark.slow
def test_fuzz_1e5_steps(fmu_dir):
    unz, guid = fmu_dir
    counts = _run(unz, guid, unz / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so",
                  100_000, 7)
    print(counts)


SANITIZERS = ("-fsanitize=address,undefined", "-fno-sanitize-recover=undefined")


def _sanitized(unz: Path, lib: Path) -> Path:
    """The FMU's wrapper and core compiled from its sources/ with ASan and UBSan."""
    src = unz / "sources"
    subprocess.run(["cc", "-std=c99", "-O1", "-g", *SANITIZERS, "-fPIC", "-shared", "-I",
                    str(src), "-o", str(lib), *(str(src / f) for f in C_SOURCES), "-lm"],
                   check=True)
    return lib


@pytest.mark.slow
def test_fuzz_under_address_and_undefined_sanitizers(fmu_dir, tmp_path):
    unz, guid = fmu_dir
    _run(unz, guid, _sanitized(unz, tmp_path / "asan.so"), 10_000, 3, SANITIZERS, cpu=False)


@pytest.fixture(scope="module")
def wet_fmu_dir(tmp_path_factory):
    """The native FMU on the wet reference road's grid: wet branch and rolling-resistance
    table as resources, so the fuzz reaches the water and My paths."""
    import fmpy

    d = tmp_path_factory.mktemp("native_fuzz_wet")
    fmu = build_native_fmu("passenger", "r117_wet", d / "BrushTireWet.fmu",
                           platforms=("linux64",)).path
    unz = Path(fmpy.extract(str(fmu)))
    assert (unz / "resources" / "tirefric-wet.bin").is_file()
    assert (unz / "resources" / "tirefric-rolling.bin").is_file()
    return unz, fmpy.read_model_description(str(fmu)).guid


@pytest.mark.slow
def test_fuzz_wet_build_under_sanitizers(wet_fmu_dir, tmp_path):
    """Water (a third of the steps, -2 ... 10 mm), camber and My with adversarial inputs,
    rollbacks and corrupt blobs, under ASan and UBSan."""
    unz, guid = wet_fmu_dir
    _run(unz, guid, _sanitized(unz, tmp_path / "asan_wet.so"), 10_000, 11, SANITIZERS,
         cpu=False)


@pytest.fixture(scope="module")
def rt_fmu_dir(tmp_path_factory):
    """The native FMU built with the real-time fidelity's table (coarse axes) on the wet
    reference road's grid: its parameter fidelity starts at 1, so the fuzz steps the real-time
    fidelity through water, camber and My."""
    import fmpy
    from test_realtime import SMALL_AXES

    from fmu_src.make.stage import BuildOptions

    d = tmp_path_factory.mktemp("native_fuzz_rt")
    axes = dict(SMALL_AXES, T=[253.15, 293.15, 333.15])
    fmu = build_native_fmu("passenger", "r117_wet", d / "BrushTireRT.fmu",
                           BuildOptions(fidelity="realtime", realtime_axes=axes),
                           platforms=("linux64",)).path
    unz = Path(fmpy.extract(str(fmu)))
    assert (unz / "resources" / "tirefric-patch.bin").is_file()
    return unz, fmpy.read_model_description(str(fmu)).guid


def test_fuzz_short_realtime(rt_fmu_dir):
    unz, guid = rt_fmu_dir
    _run(unz, guid, unz / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so", 5000, 2)


@pytest.mark.slow
def test_fuzz_realtime_under_sanitizers(rt_fmu_dir, tmp_path):
    """The real-time fidelity with adversarial inputs, rollbacks and corrupt blobs, 1e5 steps
    plain and 1e4 under ASan and UBSan."""
    unz, guid = rt_fmu_dir
    _run(unz, guid, unz / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so", 100_000, 13)
    _run(unz, guid, _sanitized(unz, tmp_path / "asan_rt.so"), 10_000, 17, SANITIZERS,
         cpu=False)
