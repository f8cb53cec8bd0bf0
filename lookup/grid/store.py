"""Grid files: NetCDF-4 (HDF5) with units, provenance and a content hash.

File layout (readable without tirefric: ``xarray.open_dataset(path)``, MATLAB
``ncread(path, 'mu_hot')``, ``h5read``):

* dimensions and coordinate variables ``log10_v`` [log10(m/s)], ``T`` [K], ``log10_p``
  [log10(Pa)] (see :mod:`lookup.grid.reader`);
* data variables of :data:`~lookup.grid.reader.VARIABLES`, dimensions
  ``(log10_v, T, log10_p)``, each with ``units`` and ``long_name`` attributes, stored as
  float32 when the values are float32-exact (built grids are rounded so; see
  :func:`~lookup.grid.reader.storage_array`) and float64 otherwise, with the shuffle, deflate
  and Fletcher-32 checksum filters (a flipped byte in the data fails its checksum);
* global attributes: ``tirefric_format``, ``format_version``, ``hash`` (SHA-256 of axes and
  variables, :func:`~lookup.grid.reader.content_hash`, defined in ``hash_definition``), and
  every metadata item: numbers and strings as plain attributes (``s0_m``, ``D_m``,
  ``q1_per_m``, ``compound_name``, ``surface_name``, ``package_version``, ``created`` (UTC,
  ISO 8601), ``history``, ...), structured items as JSON strings ``<key>_json`` (the full
  compound and surface parameter sets ``compound_json``, ``surface_json``, the engine
  settings ``engine_settings_json``, ``q1_rule_json``, the grid spec ``spec_json``, ...); and
  all metadata together as ``meta_json`` (what :func:`load_grid` restores).

:func:`load_grid` validates everything (format, dimensions, units, shapes, finite values,
strictly ascending axes, hash) and raises :class:`~tirefric.errors.GridError` naming the file
and the problem. ``"default"`` and other names of files in ``models/grids/`` resolve to the
shipped grids.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import GridError, InputError
from tirefric.paths import models_dir

from .reader import (
    ALL_VARIABLES,
    AXES,
    AXIS_LONG_NAMES,
    AXIS_UNITS,
    DIAGNOSTIC_VARIABLES,
    FORMAT_VERSION,
    NPZ_FORMAT,
    VARIABLE_LONG_NAMES,
    VARIABLE_UNITS,
    VARIABLES,
    FrictionGrid,
    _json_default,
    storage_array,
)

#: Value of the global attribute ``tirefric_format`` (shared with the npz archives).
FILE_FORMAT = NPZ_FORMAT

def package_version() -> str:
    """Installed version of tirefric (``"unknown"`` when not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("tirefric")
    except PackageNotFoundError:
        return "unknown"


def utc_now() -> str:
    """Current UTC time, ISO 8601 to the second."""
    return datetime.now(UTC).replace(microsecond=0).isoformat()


def resolve_grid_path(name_or_path: str | Path) -> Path:
    """A grid file path, or the name of a grid shipped in ``models/grids/`` (e.g. ``default``).

    Raises
    ------
    InputError
        Neither an existing file nor a shipped grid name.
    """
    p = Path(name_or_path)
    if p.is_file():
        return p
    folder = models_dir() / "grids"
    for suffix in (".nc", ".npz"):
        shipped = folder / f"{name_or_path}{suffix}"
        if shipped.is_file():
            return shipped
    available = sorted({f.stem for f in folder.glob("*.nc")} | {f.stem for f in
                                                                 folder.glob("*.npz")})
    raise InputError(f"no such grid file, and not a shipped grid name (shipped: "
                     f"{', '.join(available) or 'none'})", source=str(name_or_path))


def save_grid(grid: FrictionGrid, path: str | Path, *, compression_level: int = 4) -> Path:
    """Write ``grid`` as a NetCDF-4 file (atomically: a temporary file, then a rename).

    Parameters
    ----------
    grid
        The grid; its ``meta`` goes into the global attributes.
    path
        Target file (``.nc``).
    compression_level
        Deflate level 0-9 of the data variables.

    Returns
    -------
    Path
        ``path``.
    """
    import h5netcdf

    path = Path(path)
    missing = [n for n in VARIABLES if n not in grid.variables]
    if missing:
        raise GridError(f"{path}: a grid file needs every variable; missing {missing}")
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    meta = dict(grid.meta)
    try:
        with h5netcdf.File(tmp, "w") as f:
            f.dimensions = {n: grid.axes[n].size for n in AXES}
            for n in AXES:
                var = f.create_variable(n, (n,), "f8", data=np.asarray(grid.axes[n]))
                var.attrs["units"] = AXIS_UNITS[n]
                var.attrs["long_name"] = AXIS_LONG_NAMES[n]
            for n in (n for n in ALL_VARIABLES if n in grid.variables):
                data = storage_array(grid.variables[n])
                var = f.create_variable(n, AXES, data.dtype, data=data, compression="gzip",
                                        compression_opts=compression_level, shuffle=True,
                                        fletcher32=True)
                var.attrs["units"] = VARIABLE_UNITS[n]
                var.attrs["long_name"] = VARIABLE_LONG_NAMES[n]
            f.attrs["title"] = "tirefric friction grid (Persson rubber friction, cold and hot)"
            f.attrs["tirefric_format"] = FILE_FORMAT
            f.attrs["format_version"] = FORMAT_VERSION
            f.attrs["hash"] = grid.hash
            f.attrs["hash_definition"] = (
                "sha256 over, in order, the axes log10_v, T, log10_p and then the variables "
                + ", ".join(n for n in ALL_VARIABLES if n in grid.variables)
                + ": for each its name (UTF-8), its shape as a Python tuple repr, and its "
                  "values as little-endian float64 in C order")
            # every metadata item as its own attribute too, for readers without JSON:
            # numbers and strings as they are, everything else as "<key>_json"
            for key, value in meta.items():
                if key == "hash":
                    continue
                if isinstance(value, str | int | float) and not isinstance(value, bool):
                    f.attrs[key] = value
                elif value is not None:
                    f.attrs[f"{key}_json"] = json.dumps(value, default=_json_default,
                                                        sort_keys=True)
            f.attrs["meta_json"] = json.dumps(meta, default=_json_default, sort_keys=True)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def _read_nc(path: Path) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], dict]:
    """Read and check a grid file's structure; returns axes, variables and metadata."""
    import h5netcdf
    import h5py

    src = str(path)
    problems: list[str] = []
    try:
        # walk the HDF5 metadata with h5py first: a damaged file then fails here, before
        # h5netcdf builds (and, on failure, half-destroys) its File object
        with h5py.File(path, "r") as h5:
            list(h5.attrs)
            h5.visititems(lambda _name, obj: list(obj.attrs))
        with h5netcdf.File(path, "r") as f:
            fmt = f.attrs.get("tirefric_format")
            if fmt != FILE_FORMAT:
                raise GridError(f"{src}: not a tirefric grid file (attribute tirefric_format "
                                f"is {fmt!r}, expected {FILE_FORMAT!r})")
            version = f.attrs.get("format_version")
            if version is None or int(version) != FORMAT_VERSION:
                raise GridError(f"{src}: unsupported grid format version {version!r} "
                                f"(this reader: {FORMAT_VERSION})")
            def read(kind: str, n: str, dims: tuple[str, ...], unit: str) -> np.ndarray | None:
                """One axis or variable, its problems appended to ``problems``."""
                if n not in f.variables:
                    problems.append(f"{kind} '{n}' is missing")
                    return None
                var = f.variables[n]
                if tuple(var.dimensions) != dims:
                    problems.append(f"{kind} '{n}' has dimensions {var.dimensions}, "
                                    f"expected {dims}")
                units = var.attrs.get("units")
                if units != unit:
                    problems.append(f"{kind} '{n}' has units {units!r}, expected {unit!r}")
                return np.asarray(var[...], dtype=float)

            axes = {n: a for n in AXES
                    if (a := read("axis", n, (n,), AXIS_UNITS[n])) is not None}
            # diagnostic variables only where the grid has them (reader.DIAGNOSTIC_VARIABLES)
            present = [n for n in ALL_VARIABLES
                       if n not in DIAGNOSTIC_VARIABLES or n in f.variables]
            variables = {n: a for n in present
                         if (a := read("variable", n, AXES, VARIABLE_UNITS[n])) is not None}
            text = f.attrs.get("meta_json")
            stored_hash = f.attrs.get("hash")
    except GridError:
        raise
    except (OSError, KeyError, ValueError, TypeError, RuntimeError) as exc:
        raise GridError(f"{src}: corrupt or truncated grid file, cannot be read as NetCDF-4/"
                        f"HDF5 ({type(exc).__name__}: {exc})") from None
    if text is None:
        problems.append("global attribute 'meta_json' is missing")
        meta: dict = {}
    else:
        try:
            meta = json.loads(text)
        except json.JSONDecodeError as exc:
            raise GridError(f"{src}: attribute 'meta_json' is not valid JSON ({exc})") from None
        if not isinstance(meta, dict):
            problems.append("attribute 'meta_json' is not a JSON object")
            meta = {}
    if stored_hash is None:
        problems.append("global attribute 'hash' is missing")
    elif meta.get("hash") != stored_hash:
        problems.append(f"attribute 'hash' ({stored_hash}) differs from the hash in "
                        f"meta_json ({meta.get('hash')})")
    if problems:
        raise GridError(f"{src}: invalid grid file:\n" + "\n".join(f"  - {p}" for p in problems))
    return axes, variables, meta


def load_grid(name_or_path: str | Path = "default") -> FrictionGrid:
    """Load and validate a grid file (NetCDF-4 ``.nc`` or numpy ``.npz``).

    Parameters
    ----------
    name_or_path
        A file path, or the name of a grid shipped in ``models/grids/`` (``"default"``).

    Returns
    -------
    FrictionGrid

    Raises
    ------
    InputError
        No such file and no shipped grid of that name.
    GridError
        The file is corrupt, truncated, incomplete (a variable, axis, units attribute or
        metadata missing), has non-monotonic axes, wrong shapes or non-finite values, or its
        content does not match its hash. All structural problems are listed together.
    """
    path = resolve_grid_path(name_or_path)
    if path.suffix == ".npz":
        return FrictionGrid.load_npz(path)
    axes, variables, meta = _read_nc(path)
    return FrictionGrid(axes["log10_v"], axes["T"], axes["log10_p"], variables, meta,
                        source=str(path))


def grid_summary(grid: FrictionGrid) -> dict[str, Any]:
    """A JSON-able description of a grid: axes (ranges, counts, units), variables, metadata."""
    axes: dict[str, Any] = {}
    for n in AXES:
        a = grid.axes[n]
        axes[n] = {"n": int(a.size), "min": float(a[0]), "max": float(a[-1]),
                   "units": AXIS_UNITS[n]}
    axes["log10_v"].update(v_min_m_s=float(10 ** grid.log10_v[0]),
                           v_max_m_s=float(10 ** grid.log10_v[-1]))
    axes["T"].update(T_min_C=float(grid.T[0] - 273.15), T_max_C=float(grid.T[-1] - 273.15))
    axes["log10_p"].update(p_min_Pa=float(10 ** grid.log10_p[0]),
                           p_max_Pa=float(10 ** grid.log10_p[-1]))
    variables = {}
    for n, arr in grid.variables.items():
        variables[n] = {"units": VARIABLE_UNITS[n], "min": float(arr.min()),
                        "max": float(arr.max())}
    return {"source": grid.source, "shape": list(grid.shape), "hash": grid.hash, "axes": axes,
            "variables": variables, "meta": _jsonable(grid.meta)}


def _jsonable(meta: Mapping[str, Any]) -> Any:
    return json.loads(json.dumps(meta, default=_json_default))
