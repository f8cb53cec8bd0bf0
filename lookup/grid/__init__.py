"""Friction grids: build Persson-friction tables, store them as NetCDF-4, read them fast.

* :mod:`lookup.grid.reader` -- :class:`FrictionGrid` and its interpolation (numpy only, runs
  inside an FMU), ``.npz`` persistence;
* :mod:`lookup.grid.store` -- NetCDF-4 files (h5netcdf) with units, provenance and hash,
  :func:`load_grid` (``"default"`` names the shipped grid);
* :mod:`lookup.grid.spec` -- grid specifications (TOML under ``models/grids/``);
* :mod:`lookup.grid.build` -- parallel, resumable grid builds (local processes or Dask);
* :mod:`lookup.grid.cli` -- ``tirefric grid build|info|query|plot``;
* :mod:`lookup.grid.plots` -- matplotlib figures of a grid.

Importing this package imports only the numpy reader; the others load on first use.
"""

from __future__ import annotations

from typing import Any

from .reader import AXES, VARIABLES, FrictionGrid, content_hash

__all__ = ["AXES", "VARIABLES", "FrictionGrid", "content_hash", "load_grid", "save_grid"]


def __getattr__(name: str) -> Any:
    # load_grid / save_grid need h5netcdf: import it only when asked for (FMU stays numpy-only)
    if name in ("load_grid", "save_grid"):
        from . import store

        return getattr(store, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
