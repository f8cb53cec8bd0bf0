"""Build the brush-tire FMU: tire + grid -> ``BrushTire.fmu`` (FMI 2.0 co-simulation).

Steps of :func:`build_fmu`:

1. **Inputs.** The tire (:func:`tire_brush.params.load_tire`: a TOML file or a shipped name)
   and the friction grid (:func:`lookup.grid.load_grid`: NetCDF or npz, or a shipped name).
2. **Runtime.** :func:`fmu_src.make.package.build_runtime` collects the modules the slave
   needs under a private package name and checks that they import only numpy and the
   standard library.
3. **Resources** (:func:`stage_resources`): the grid as a numpy ``.npz`` archive (the format
   the numpy-only reader loads; same content hash as the source grid), ``build.json`` (tire
   parameters, model options, input envelope, grid hash and provenance, build id) and
   ``requirements.txt`` (what the host's Python needs: numpy; ``pythonfmu deploy`` reads it).
4. **pythonfmu** builds the FMU in a child process (it imports the slave to write the model
   description; the child keeps those imports out of this interpreter).
5. **Post-processing** (:mod:`fmu_src.make.model_description`): units, InitialUnknowns, GUID, model
   metadata. The archive is rewritten with sorted entries and fixed timestamps, so the same
   inputs give the same bytes (and the same GUID).
6. **Validation** with ``fmpy.validation.validate_fmu``: any problem stops the build.

The build id is the SHA-256 of everything that goes into the FMU: the copied sources, the
grid archive, the tire parameters, options, limits, the tirefric and pythonfmu versions. The
GUID is derived from it.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path
from typing import Any

from fmu_src.runtime.interface import MODEL_NAME, variables
from fmu_src.runtime.slave import DATA_DIR
from tire_brush.params import TireParams
from tirefric.errors import InputError

from .model_description import postprocess
from .native_build import build_native_fmu
from .package import RuntimePackage, build_runtime
from .stage import (
    BuildError,
    BuildOptions,
    BuildReport,
    guid_of,
    load_inputs,
    read_fmu_info,
    stage_resources,
    write_fmu,
)

__all__ = ["BuildError", "BuildOptions", "BuildReport", "build_fmu", "read_fmu_info",
           "stage_resources"]


def _run_pythonfmu(stage: Path, runtime: RuntimePackage, out_dir: Path) -> Path:
    """pythonfmu's builder in a child process; returns the raw FMU."""
    cmd = [sys.executable, "-m", "pythonfmu", "build", "-f",
           str(stage / f"{runtime.slave_module}.py"), "-d", str(out_dir),
           str(stage / runtime.package), str(stage / DATA_DIR), str(stage / "requirements.txt")]
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    proc = subprocess.run(cmd, cwd=stage, env=env, capture_output=True, text=True,
                          check=False)
    raw = out_dir / f"{MODEL_NAME}.fmu"
    if proc.returncode != 0 or not raw.is_file():
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-15:]
        raise BuildError("pythonfmu could not build the FMU:\n" + "\n".join(tail))
    return raw


def build_fmu(tire: str | Path | TireParams, grid: str | Path | Any, output: str | Path,
              options: BuildOptions | None = None, *, validate: bool = True,
              native: bool = False) -> BuildReport:
    """Build the brush-tire FMU (module docstring).

    Parameters
    ----------
    tire
        Tire TOML file, shipped name (``"passenger"``) or :class:`TireParams`.
    grid
        Grid file (``.nc``/``.npz``), shipped name (``"default"``) or a
        :class:`lookup.grid.FrictionGrid`.
    output
        The ``.fmu`` file to write (replaced atomically).
    options
        Start values of the model options.
    validate
        Run fmpy's validation and refuse an FMU with problems.
    native
        Build the Python-free flavour instead (:func:`fmu_src.make.native_build.build_native_fmu`:
        the C core with an FMI wrapper, for every platform a compiler is found for).

    Returns
    -------
    BuildReport

    Raises
    ------
    InputError, GridError
        Bad tire or grid (from their readers).
    BuildError
        Packaging, pythonfmu or validation failed (the message lists the problems).
    """
    if native:
        return build_native_fmu(tire, grid, output, options, validate=validate)
    t0 = time.perf_counter()
    output = Path(output)
    if output.suffix != ".fmu":
        raise InputError("the FMU file name must end in .fmu", source="-o", value=str(output))
    tire_p, grid_o, grid_source = load_inputs(tire, grid)
    runtime = build_runtime()
    with tempfile.TemporaryDirectory(prefix="tirefric_fmu_") as tmp:
        stage = Path(tmp) / "stage"
        build = stage_resources(tire_p, grid_o, stage, options, grid_source=grid_source,
                                runtime=runtime)
        raw = _run_pythonfmu(stage, runtime, Path(tmp) / "out")
        with zipfile.ZipFile(raw) as z:
            entries = {n: z.read(n) for n in z.namelist()
                       if not n.endswith("/") and "__pycache__" not in n
                       and not n.endswith(".pyc")}
        guid = guid_of(build["build_id"])
        info = {"info.tire": tire_p.name, "info.grid_hash": grid_o.hash,
                "info.build_id": build["build_id"]}
        variables_ = variables(build["tire"], build["options"], build["limits"], info)
        vendor = {"build_id": build["build_id"], "grid_hash": grid_o.hash,
                  "grid_source": grid_source, "tire": tire_p.name,
                  "tire_file": build["tire"]["file"], "runtime_package": runtime.package,
                  "tirefric_version": build["versions"]["tirefric"]}
        entries["modelDescription.xml"] = postprocess(
            entries["modelDescription.xml"], variables_, guid=guid, model=build["model"],
            vendor=vendor, step_size=1e-3)
        data = write_fmu(entries, output, validate=validate, what="the FMU")
    return BuildReport(path=output, guid=guid, build_id=build["build_id"],
                       sha256="sha256:" + hashlib.sha256(data).hexdigest(),
                       size_bytes=len(data), tire=tire_p.name, grid_hash=grid_o.hash,
                       grid_source=grid_source, runtime_package=runtime.package,
                       n_variables=len(variables_), deferred_imports=runtime.deferred_imports,
                       seconds=time.perf_counter() - t0)
