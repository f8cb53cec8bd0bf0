"""What both FMU flavours share at build time: options, inputs, resources, archive, GUID.

The pythonfmu flavour (:mod:`fmu_src.make.build`) and the native one
(:mod:`fmu_src.make.native_build`) stage the same data resources (:func:`stage_resources`:
the grid, ``build.json`` with the tire parameters, the model options, the input envelope,
the grid's hash and provenance, the rolling-resistance table and the wet branch), write the
archive the same way (:func:`write_fmu`: sorted entries, fixed timestamps, validated with
fmpy) and derive the GUID from the build id the same way (:func:`guid_of`).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import sys
import tempfile
import time
import uuid
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

from fmu_src.runtime.interface import (
    MODEL_NAME,
    check_tire_fields,
    default_limits,
    tire_to_dict,
)
from fmu_src.runtime.slave import (
    BUILD_FILE,
    CORE_DIR,
    DATA_DIR,
    PATCH_FILE,
    ROLLING_FILE,
    WET_FILE,
)
from fmu_src.runtime.table_file import table_bytes, wet_bytes
from tire_brush.params import TireParams, load_tire
from tire_brush.slip import V_FLOOR
from tire_brush.transient import DT_INTERNAL, N_TRANSIENT
from tirefric import __version__
from tirefric.errors import InputError, TirefricError

from .package import RuntimePackage

#: Name of the grid archive inside the FMU's data folder.
GRID_FILE = "grid.npz"
#: What the host's Python must provide at simulation time (pythonfmu itself is inside the FMU).
REQUIREMENTS = ("numpy>=1.26",)
#: Format tag of build.json.
BUILD_FORMAT = "tirefric-fmu-build"
#: Fixed timestamp of every archive entry (the earliest a zip can hold).
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)


class BuildError(TirefricError):
    """The FMU could not be built, or the built FMU failed validation."""


#: The fidelities of the tire (the FMU parameter ``fidelity`` is the index).
FIDELITIES: tuple[str, ...] = ("full", "realtime")


@dataclass(frozen=True)
class BuildOptions:
    """Start values of the model options (FMU parameters; a master may change them).

    Attributes
    ----------
    n_elements : int
        Tread elements on the patch at the nominal load.
    dt_internal : float
        Longest internal step [s].
    s0 : float or None
        Blending length of eq. (28) [m]; None: the grid's ``s0_m``.
    v_floor : float
        Speed floor of the reported slips [m/s].
    axes : int
        Axis system of vy, Fy, Mz and alpha (:data:`fmu_src.runtime.interface.OPTIONS`):
        0 adapted SAE (the brush's own), 1 ISO-W, 2 SAE.
    texture_depth : float
        The road's mean texture depth [m] (hydroplaning; 0: the texture holds no water, the
        early bound).
    fidelity : str
        ``"full"``, or ``"realtime"``: the FMU also carries the real-time fidelity's patch
        table (:mod:`tire_brush.realtime`; built from the steady march of this tire on this
        grid, cached) and its parameter ``fidelity`` starts at 1 (docs/realtime.md).
    realtime_axes : dict or None
        Axes of the patch table by :data:`tire_brush.realtime.AXIS_NAMES` where they differ
        from the defaults (coarser ones build faster and interpolate worse: docs/realtime.md),
        and ``"water_depth"``: the water depths [m] of its layers on a grid with a wet branch
        (default the branch's depth nodes; layers between them read the branch as the full
        model does).
    """

    n_elements: int = N_TRANSIENT
    dt_internal: float = DT_INTERNAL
    s0: float | None = None
    v_floor: float = V_FLOOR
    axes: int = 0
    texture_depth: float = 0.0
    fidelity: str = "full"
    realtime_axes: dict | None = None

    def __post_init__(self) -> None:
        if self.fidelity not in FIDELITIES:
            raise InputError(f"must be one of {FIDELITIES}", field="fidelity",
                             value=self.fidelity)
        if not (isinstance(self.texture_depth, int | float) and
                0 <= self.texture_depth < float("inf")):
            raise InputError("must be a finite length >= 0 m", field="texture_depth",
                             value=self.texture_depth)
        if isinstance(self.axes, bool) or self.axes not in (0, 1, 2):
            raise InputError("must be 0 (adapted SAE), 1 (ISO-W) or 2 (SAE)", field="axes",
                             value=self.axes)
        if isinstance(self.n_elements, bool) or not isinstance(self.n_elements, int) or \
                self.n_elements < 2:
            raise InputError("must be an integer >= 2", field="n_elements",
                             value=self.n_elements)
        for name in ("dt_internal", "v_floor"):
            x = getattr(self, name)
            if not (isinstance(x, int | float) and 0 < x < float("inf")):
                raise InputError("must be a finite number > 0", field=name, value=x)
        if self.s0 is not None and not (0 <= self.s0 < float("inf")):
            raise InputError("must be a finite length >= 0 m", field="s0", value=self.s0)


@dataclass
class BuildReport:
    """What :func:`build_fmu` made.

    Attributes
    ----------
    path : Path
        The FMU file.
    guid, build_id : str
        GUID of the model description and the hash of the build inputs.
    sha256 : str
        Hash of the FMU file's bytes.
    size_bytes : int
        File size.
    tire : str
        Tire name.
    grid_hash, grid_source : str
        Content hash and origin of the grid.
    runtime_package : str
        Private package name inside the FMU.
    n_variables : int
        Variables in the model description.
    deferred_imports : list of str
        Imports inside functions that point outside the FMU's copy (not run by the slave).
    seconds : float
        Build time.
    """

    path: Path
    guid: str
    build_id: str
    sha256: str
    size_bytes: int
    tire: str
    grid_hash: str
    grid_source: str
    runtime_package: str
    n_variables: int
    deferred_imports: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        """JSON-able dict (``tirefric fmu build --json``)."""
        d = dict(self.__dict__)
        d["path"] = str(self.path)
        return d


def _package_version(name: str) -> str:
    try:
        return version(name)
    except PackageNotFoundError:
        return "unknown"


def load_inputs(tire: str | Path | TireParams, grid: str | Path | Any) -> tuple[TireParams,
                                                                                  Any, str]:
    """The tire, the grid and a short name of the grid's origin."""
    tire_p = tire if isinstance(tire, TireParams) else load_tire(tire)
    if hasattr(grid, "save_npz") and hasattr(grid, "hash"):
        return tire_p, grid, Path(str(grid.source)).name
    from lookup.grid import load_grid

    g = load_grid(grid)
    return tire_p, g, Path(str(g.source)).name


def _deterministic_zip(entries: dict[str, bytes]) -> bytes:
    """A zip archive of ``entries`` with sorted names and fixed metadata."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name in sorted(entries):
            info = zipfile.ZipInfo(name, date_time=_ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            info.create_system = 3
            z.writestr(info, entries[name], compresslevel=9)
    return buf.getvalue()


def _grid_npz(grid: Any) -> bytes:
    """The grid as an npz archive with deterministic bytes (the reader's own format)."""
    with tempfile.TemporaryDirectory(prefix="tirefric_grid_") as tmp:
        path = grid.save_npz(Path(tmp) / GRID_FILE)
        with zipfile.ZipFile(path) as z:
            members = {n: z.read(n) for n in z.namelist()}
    return _deterministic_zip(members)


def write_fmu(entries: dict[str, bytes], output: Path, *, validate: bool, what: str) -> bytes:
    """Zip ``entries`` deterministically into ``output`` (written as ``output.part`` first,
    validated with fmpy if asked, then moved into place; a failed validation leaves nothing)
    and return the archive's bytes. Shared by both FMU flavours."""
    data = _deterministic_zip(entries)
    output.parent.mkdir(parents=True, exist_ok=True)
    part = output.with_name(output.name + ".part")
    part.write_bytes(data)
    if validate:
        from fmpy.validation import validate_fmu

        problems = validate_fmu(str(part))
        if problems:
            part.unlink()
            raise BuildError(f"{what} failed validation:\n" +
                             "\n".join(f"  - {p}" for p in problems))
    os.replace(part, output)
    return data


def json_bytes(obj: Any) -> bytes:
    return (json.dumps(obj, indent=1, sort_keys=True, allow_nan=False) + "\n").encode()


def _grid_provenance(grid: Any) -> dict[str, Any]:
    """Scalar metadata of the grid (compound, surface, s0, D, engine version, ...)."""
    return {k: v for k, v in sorted(grid.meta.items())
            if isinstance(v, str | int | float) and not isinstance(v, bool)}


def _stage_core(data: Path) -> dict[str, Any]:
    """Copy the compiled tire core (this platform's build) and its C sources into the FMU's
    data folder; returns their description for ``build.json``."""
    from tire_brush import ccore

    lib = ccore.library_path()
    rel = f"{CORE_DIR}/{ccore.platform_dir()}/{ccore.library_file_name()}"
    target = data / rel
    target.parent.mkdir(parents=True, exist_ok=True)
    blob = lib.read_bytes()
    target.write_bytes(blob)
    sources = {}
    for name in (*ccore.SOURCES, *ccore.HEADERS):
        text = (ccore.SOURCE_DIR / name).read_bytes()
        (data / CORE_DIR / "csrc").mkdir(parents=True, exist_ok=True)
        (data / CORE_DIR / "csrc" / name).write_bytes(text)
        sources[name] = "sha256:" + hashlib.sha256(text).hexdigest()
    return {"library": rel, "platform": ccore.platform_dir(),
            "library_sha256": "sha256:" + hashlib.sha256(blob).hexdigest(),
            "sources": sources}


def stage_resources(tire: TireParams, grid: Any, directory: str | Path,
                    options: BuildOptions | None = None, *, grid_source: str = "",
                    runtime: RuntimePackage | None = None) -> dict[str, Any]:
    """Write the FMU's data resources into ``directory`` and return the build description.

    ``directory/tirefric-data/`` receives ``build.json`` and the grid archive; with
    ``runtime`` given, its sources and ``requirements.txt`` are written as well (the full
    resources folder). Without it, the folder is enough for
    :class:`fmu_src.runtime.slave.BrushTireSlave` to run in a source checkout (tests).

    Raises
    ------
    BuildError
        The tire has parameters the FMU interface does not cover.
    """
    problems = check_tire_fields()
    if problems:
        raise BuildError("; ".join(problems))
    options = options or BuildOptions()
    directory = Path(directory)
    data = directory / DATA_DIR
    data.mkdir(parents=True, exist_ok=True)
    npz = _grid_npz(grid)
    (data / GRID_FILE).write_bytes(npz)
    rolling_bytes, rolling = _rolling_resource(tire, grid)
    if rolling_bytes:
        (data / ROLLING_FILE).write_bytes(rolling_bytes)
    wet_data, wet = _wet_resource(grid)
    if wet_data:
        (data / WET_FILE).write_bytes(wet_data)
    s0 = float(grid.meta["s0_m"]) if options.s0 is None else float(options.s0)
    patch_data, realtime = _patch_resource(tire, grid, s0, options.fidelity,
                                           options.realtime_axes, wet=bool(wet_data))
    if patch_data:
        (data / PATCH_FILE).write_bytes(patch_data)
    tire_d = tire_to_dict(tire)
    tire_d["file"] = Path(tire.source).name if tire.source else ""
    tirefric_version = __version__  # the one definition, also read by the packaging
    build: dict[str, Any] = {
        "format": BUILD_FORMAT, "format_version": 1,
        "model": {
            "name": MODEL_NAME,
            "description": (f"Transient brush tire '{tire.name}' on a Persson friction grid "
                            f"({grid.hash}) with eq. (28) cold/hot blending (tirefric)"),
            "author": "tirefric developers", "version": tirefric_version, "license": "MIT",
            "generationTool": (f"tirefric {tirefric_version} (pythonfmu "
                               f"{_package_version('pythonfmu')})"),
        },
        "versions": {"tirefric": tirefric_version, "pythonfmu": _package_version("pythonfmu"),
                     "python_built_with": ".".join(map(str, sys.version_info[:2]))},
        "tire": tire_d,
        "grid": {"file": GRID_FILE, "hash": grid.hash, "source": grid_source,
                 "npz_sha256": "sha256:" + hashlib.sha256(npz).hexdigest(),
                 "meta": _grid_provenance(grid)},
        "options": {"n_elements": options.n_elements, "dt_internal": options.dt_internal,
                    "s0": s0, "v_floor": options.v_floor, "axes": options.axes,
                    "texture_depth": options.texture_depth,
                    "fidelity": FIDELITIES.index(options.fidelity)},
        "limits": default_limits(tire),
        "rolling": rolling,
        "wet": wet,
        "realtime": realtime,
        "requirements": list(REQUIREMENTS),
    }
    h = hashlib.sha256(json_bytes(build) + npz + rolling_bytes + wet_data + patch_data)
    if runtime is not None:
        build["runtime"] = {"package": runtime.package, "slave_module": runtime.slave_module,
                            "code_hash": runtime.code_hash, "modules": runtime.modules}
        for rel in sorted(runtime.files):
            h.update(rel.encode() + b"\0" + runtime.files[rel].encode() + b"\0")
            path = directory / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(runtime.files[rel], encoding="utf-8")
        (directory / "requirements.txt").write_text("\n".join(REQUIREMENTS) + "\n")
        core = _stage_core(data)
        build["core"] = core
        h.update(json_bytes(core))
    build["build_id"] = "sha256:" + h.hexdigest()
    (data / BUILD_FILE).write_bytes(json_bytes(build))
    return build


def _rolling_resource(tire: TireParams, grid: Any) -> tuple[bytes, dict[str, Any]]:
    """The rolling-resistance table file of the FMU (:mod:`tire_brush.rolling_resistance`;
    empty bytes when the tire or the grid cannot give one) and its entry in build.json (the
    file, its hash and the compound, or why there is none: the FMU's ``My`` is then 0)."""
    from tire_brush.rolling_resistance import rolling_table

    table, why = rolling_table(tire, grid)
    if table is None:
        return b"", {"file": None, "why": why}
    data = table_bytes(table)
    return data, {"file": ROLLING_FILE, "sha256": "sha256:" + hashlib.sha256(data).hexdigest(),
                  "compound": table.compound,
                  "model": "tire_brush.rolling_resistance (docs/rolling.md)"}


def _patch_resource(tire: TireParams, grid: Any, s0: float, fidelity: str,
                    axes: dict | None = None, *, wet: bool = False
                    ) -> tuple[bytes, dict[str, Any]]:
    """The real-time fidelity's patch table file (empty bytes for a full-fidelity build) and
    its entry in build.json: built from the steady march of this tire on the grid's friction
    with the blend length ``s0`` (:func:`tire_brush.realtime_build.cached_patch_table`), with
    a layer at each water depth of the grid's wet branch when the FMU carries one (``wet``;
    drainage scale 1, as the FMU's)."""
    if fidelity != "realtime":
        return b"", {"file": None}
    from lookup.grid.wet import load_wet
    from tire_brush.friction import GridFriction, as_table
    from tire_brush.realtime_build import cached_patch_table

    t0 = time.perf_counter()
    branch = load_wet(Path(str(grid.source))) if wet else None
    axes = dict(axes or {})
    depths = axes.pop("water_depth", None)
    table, path = cached_patch_table(tire, as_table(GridFriction(grid, s0=s0)), axes=axes,
                                     wet=branch, depths=depths if wet else None)
    data = path.read_bytes()
    return data, {"file": PATCH_FILE, "sha256": "sha256:" + hashlib.sha256(data).hexdigest(),
                  "key": table.key, "shape": list(table.values.shape),
                  "water_depth_m": table.depth.tolist(),
                  "seconds": round(time.perf_counter() - t0, 1),
                  "model": "tire_brush.realtime (docs/realtime.md)"}


def _wet_resource(grid: Any) -> tuple[bytes, dict[str, Any]]:
    """The wet branch of the grid's file for the FMU (empty bytes when it has none: every
    water depth is then a dry road, input_status bit 512) and its entry in build.json."""
    import numpy as np

    from lookup.grid.wet import load_wet
    from tire_brush.hydroplaning import D_FULL
    from tirefric.errors import GridError

    src = Path(str(getattr(grid, "source", "")))
    if src.suffix != ".nc" or not src.is_file():
        return b"", {"file": None, "why": "the grid was not read from a grid file (no wet "
                                          "branch)"}
    try:
        w = load_wet(src)
    except GridError as exc:
        return b"", {"file": None, "why": str(exc)}
    if any(w.axes[n].shape != np.shape(grid.axes[n]) or
           not np.allclose(w.axes[n], grid.axes[n], rtol=0, atol=1e-9)
           for n in ("log10_v", "T", "log10_p")):
        return b"", {"file": None, "why": "the wet branch has other nodes than the grid"}
    data = wet_bytes(w, D_FULL)
    return data, {"file": WET_FILE, "sha256": "sha256:" + hashlib.sha256(data).hexdigest(),
                  "wet_hash": w.meta.get("hash"), "water_depth_m": w.axes["water_depth"].tolist(),
                  "d_full_m": D_FULL, "drain_scale": 1.0,
                  "model": "lookup.grid.wet, tire_brush.hydroplaning (docs/tire-core.md)"}


def guid_of(build_id: str) -> str:
    """The FMU's GUID: a UUID (version 5 layout) from the first 16 bytes of the build id."""
    digest = bytes.fromhex(build_id.partition(":")[2])
    return "{" + str(uuid.UUID(bytes=digest[:16], version=5)) + "}"


def read_fmu_info(path: str | Path) -> dict[str, Any]:
    """Build description and model attributes of a built FMU (``tirefric fmu info``)."""
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as z:
            build = json.loads(z.read(f"resources/{DATA_DIR}/{BUILD_FILE}"))
            md = z.read("modelDescription.xml")
    except (OSError, KeyError, zipfile.BadZipFile, ValueError) as exc:
        raise InputError(f"not a tirefric FMU ({exc})", source=str(path)) from None
    root = ET.fromstring(md)
    return {"file": str(path), "guid": root.get("guid"), "modelName": root.get("modelName"),
            "description": root.get("description"), "version": root.get("version"),
            "build_id": build["build_id"], "tire": build["tire"]["name"],
            "tire_file": build["tire"].get("file", ""), "grid": build["grid"],
            "options": build["options"], "limits": build["limits"],
            "requirements": build["requirements"], "versions": build["versions"],
            "runtime": build.get("runtime", {}), "flavour": build.get("flavour", "pythonfmu"),
            "native": build.get("native", {}),
            "rolling": build.get("rolling", {"file": None, "why": "built before My existed"}),
            "wet": build.get("wet", {"file": None, "why": "built before water_depth existed"})}
