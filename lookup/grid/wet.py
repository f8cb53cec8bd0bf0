"""The wet branch of a friction grid: tables over water depth and drainage time (numpy reader).

A grid file may carry, beside the dry tables of :mod:`lookup.grid.reader` (which it leaves
untouched: a dry reader reads a file with a wet branch exactly as before), a wet branch
computed by :class:`lookup.wet.friction.WetPerssonFriction`:

=================  ==========  ============================================================
axis               unit        meaning
=================  ==========  ============================================================
``water_depth``    m           water film depth (volume per nominal area); node 0 is 0 = dry
``log10_t_drain``  log10(s)    drainage time at the macro-contact radius D/2 (see below)
=================  ==========  ============================================================

Variables, dimensions ``(water_depth, log10_v, T, log10_p)``:

* ``mu_wet_cold_w0``, ``mu_wet_cold_w1``: cold branch with the adhesive term off (dry share
  w = 0) and fully on (w = 1), on the sealed spectrum;
* ``mu_wet_hot_w0``, ``mu_wet_hot_w1``: the same on the hot branch (each a self-consistent
  flash-temperature solve);

and ``w_dry`` with dimensions ``(water_depth, log10_t_drain, log10_v, T, log10_p)``: the dry
share of the real contact after the drainage time (:mod:`lookup.wet.squeeze`, cold state).

At depth node 0 (the dry road) all four are the grid's own ``mu_cold`` / ``mu_hot`` (copied
from the file's dry tables when the branch is appended, :class:`PendingWetGrid`) and
``w_dry`` = 1, so a read at zero depth is the dry read.

Reading (:meth:`WetGrid.interpolate`): mu_wet = (1 - w) mu_w0 + w mu_w1. On the cold branch
this is exact (the cold friction is linear in w). On the hot branch it is a documented
reduction: the flash temperature depends on w through the adhesive heat, and the hot value
at intermediate w is interpolated linearly between the two self-consistent end points
(exact at w = 0 and 1), instead of a hot solve per drainage time.

The drainage time. The squeeze-out depends on the available time t and the drainage radius
R only through t / R^2 (Stefan's law, :mod:`lookup.wet.friction`), so the table is over
t_drain = t (D / 2R)^2. A sliding block (R = D/2, t = D/v) reads t_drain = D / v; a tire's
tread element that must drain over its half-length R_b during its time in the footprint
t_fp = (patch length) / (rolling speed) reads t_drain = t_fp (D / 2 R_b)^2. The tire core's
future wet lookup therefore needs mu(v, T, p, water depth, t_drain): these five axes.

Stored in the NetCDF file as extra dimensions and variables with ``units`` and ``long_name``
and the global attributes ``wet_meta_json`` (provenance of every mechanism's parameters) and
``wet_hash`` (SHA-256 of the wet axes and variables, defined like the dry hash). numpy only.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

import numpy as np

from tirefric.errors import GridError, InputError

WET_AXES: tuple[str, str] = ("water_depth", "log10_t_drain")
WET_AXIS_UNITS = {"water_depth": "m", "log10_t_drain": "log10(s)"}
WET_AXIS_LONG_NAMES = {
    "water_depth": "water film depth (volume of water per nominal road area), 0 = dry",
    "log10_t_drain": "decimal logarithm of the drainage time t (D/2R)^2 [s]",
}
WET_VARIABLES: tuple[str, ...] = ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0",
                                  "mu_wet_hot_w1", "w_dry")
WET_DIMS = {n: ("water_depth", "log10_v", "T", "log10_p") for n in WET_VARIABLES[:4]}
WET_DIMS["w_dry"] = ("water_depth", "log10_t_drain", "log10_v", "T", "log10_p")
WET_LONG_NAMES = {
    "mu_wet_cold_w0": "wet friction, cold branch, adhesive term off (dry share 0)",
    "mu_wet_cold_w1": "wet friction, cold branch, adhesive term fully on (dry share 1)",
    "mu_wet_hot_w0": "wet friction, hot branch, adhesive term off (dry share 0)",
    "mu_wet_hot_w1": "wet friction, hot branch, adhesive term fully on (dry share 1)",
    "w_dry": "dry share of the real contact after the drainage time (squeeze-out)",
}


def wet_hash(axes: Mapping[str, np.ndarray], variables: Mapping[str, np.ndarray]) -> str:
    """SHA-256 over the wet axes and variables (name, shape, little-endian float64 values)."""
    h = hashlib.sha256()
    for name, arr in [(a, axes[a]) for a in WET_AXES] + [(v, variables[v])
                                                          for v in WET_VARIABLES]:
        a = np.ascontiguousarray(arr, dtype="<f8")
        h.update(name.encode())
        h.update(repr(tuple(a.shape)).encode())
        h.update(a.tobytes())
    return "sha256:" + h.hexdigest()


def _axis_pos(axis: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cell index and fraction of ``x`` on ``axis`` (clamped to the ends)."""
    x = np.clip(x, axis[0], axis[-1])
    i = np.clip(np.searchsorted(axis, x, side="right") - 1, 0, axis.size - 2)
    return i, (x - axis[i]) / (axis[i + 1] - axis[i])


def _multilinear(table: np.ndarray, pos: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    out = 0.0
    k = len(pos)
    for corner in range(2**k):
        idx, wt = [], 1.0
        for j, (i, f) in enumerate(pos):
            bit = (corner >> j) & 1
            idx.append(i + bit)
            wt = wt * (f if bit else 1.0 - f)
        out = out + wt * table[tuple(idx)]
    return out


class WetGrid:
    """The wet branch of a grid file (module docstring); numpy only.

    Parameters
    ----------
    dry_axes : mapping
        ``log10_v``, ``T``, ``log10_p`` of the dry grid.
    wet_axes : mapping
        ``water_depth`` [m] (first node 0) and ``log10_t_drain``.
    variables : mapping
        :data:`WET_VARIABLES` with the shapes of :data:`WET_DIMS`.
    meta : mapping
        Provenance; ``hash`` is checked against :func:`wet_hash` when present.
    """

    def __init__(self, dry_axes: Mapping[str, Any], wet_axes: Mapping[str, Any],
                 variables: Mapping[str, Any], meta: Mapping[str, Any] | None = None,
                 *, source: str = "grid") -> None:
        self.source = source
        self.axes = {n: np.asarray(dry_axes[n], float) for n in ("log10_v", "T", "log10_p")}
        for n in WET_AXES:
            a = np.asarray(wet_axes[n], float)
            if a.ndim != 1 or a.size < 2 or not np.all(np.diff(a) > 0) or not np.isfinite(
                    a).all():
                raise GridError(f"{source}: wet axis '{n}' must be finite, strictly ascending, "
                                f"with >= 2 points")
            self.axes[n] = a
        if self.axes["water_depth"][0] != 0.0:
            raise GridError(f"{source}: the first water_depth node must be 0 (dry)")
        self.variables = {}
        for n in WET_VARIABLES:
            if n not in variables:
                raise GridError(f"{source}: wet variable '{n}' is missing")
            a = np.asarray(variables[n], float)
            shape = tuple(self.axes[d].size for d in WET_DIMS[n])
            if a.shape != shape:
                raise GridError(f"{source}: wet variable '{n}' has shape {a.shape}, expected "
                                f"{shape} = {WET_DIMS[n]}")
            if not np.isfinite(a).all():
                raise GridError(f"{source}: wet variable '{n}' has non-finite values")
            self.variables[n] = a
        self.meta = dict(meta or {})
        digest = wet_hash(self.axes, self.variables)
        if self.meta.get("hash") not in (None, digest):
            raise GridError(f"{source}: wet content hash mismatch (stored "
                            f"{self.meta.get('hash')}, computed {digest})")
        self.meta["hash"] = digest

    def interpolate(self, v: Any, T: Any, p: Any, water_depth: Any, t_drain: Any
                    ) -> dict[str, np.ndarray]:
        """mu_wet_cold, mu_wet_hot and w_dry at slip speed v [m/s], T [K], p [Pa], water
        depth [m] and drainage time [s] (arrays broadcast). Multilinear in (water depth,
        log10 t_drain, log10 v, T, log10 p); coordinates outside an axis are clamped to it.

        Raises
        ------
        InputError
            A negative or non-finite water depth, a non-positive drainage time.
        """
        v, T, p, d, t = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                             (v, T, p, water_depth, t_drain)))
        bad = ~(np.isfinite(d) & (d >= 0))
        if bad.any():
            raise InputError("water film depth must be finite and >= 0 [m]",
                             field="water_depth", value=float(d[bad].flat[0]))
        bad = ~(np.isfinite(t) & (t > 0))
        if bad.any():
            raise InputError("drainage time must be finite and > 0 [s]", field="t_drain",
                             value=float(t[bad].flat[0]))
        lv = np.log10(np.maximum(np.abs(v), 10.0 ** self.axes["log10_v"][0]))
        pd = _axis_pos(self.axes["water_depth"], d)
        pt = _axis_pos(self.axes["log10_t_drain"], np.log10(t))
        pv = _axis_pos(self.axes["log10_v"], lv)
        pT = _axis_pos(self.axes["T"], T)
        pp = _axis_pos(self.axes["log10_p"], np.log10(p))
        w = np.clip(_multilinear(self.variables["w_dry"], [pd, pt, pv, pT, pp]), 0.0, 1.0)
        out = {"w_dry": w}
        for b in ("cold", "hot"):
            m0 = _multilinear(self.variables[f"mu_wet_{b}_w0"], [pd, pv, pT, pp])
            m1 = _multilinear(self.variables[f"mu_wet_{b}_w1"], [pd, pv, pT, pp])
            out[f"mu_wet_{b}"] = (1.0 - w) * m0 + w * m1
        return out


class PendingWetGrid:
    """A wet branch whose depth-0 (dry road) tables are still to be taken from its grid file.

    The wet engine at water depth 0 is the dry engine, so the depth-0 tables of the wet
    variables are the grid's own ``mu_cold`` and ``mu_hot`` (and w_dry = 1).
    :func:`lookup.grid.wet_build.build_wet` leaves them out (NaN) when the dry tables are
    already in the file the branch is appended to, and :func:`save_wet` fills them from it
    (:meth:`complete`). Same arguments as :class:`WetGrid`.
    """

    def __init__(self, dry_axes: Mapping[str, Any], wet_axes: Mapping[str, Any],
                 variables: Mapping[str, Any], meta: Mapping[str, Any] | None = None,
                 *, source: str = "grid") -> None:
        self.dry_axes = {n: np.asarray(dry_axes[n], float) for n in ("log10_v", "T",
                                                                      "log10_p")}
        self.wet_axes = {n: np.asarray(wet_axes[n], float) for n in WET_AXES}
        self.variables = {n: np.array(variables[n], float) for n in WET_VARIABLES}
        self.meta = dict(meta or {})
        self.source = source

    def complete(self, dry_axes: Mapping[str, Any], mu_cold: Any, mu_hot: Any) -> WetGrid:
        """The :class:`WetGrid` with depth 0 set to the dry tables ``mu_cold``, ``mu_hot``
        (nv, nT, np) of a grid with the axes ``dry_axes`` (checked against this branch's)."""
        for n, a in self.dry_axes.items():
            b = np.asarray(dry_axes[n], float)
            if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-9):
                raise GridError(f"{self.source}: the grid file's '{n}' nodes differ from the "
                                f"wet branch's")
        var = {n: a.copy() for n, a in self.variables.items()}
        for n in WET_VARIABLES[:4]:
            var[n][0] = np.asarray(mu_cold if "cold" in n else mu_hot, float)
        var["w_dry"][0] = 1.0
        meta = {k: v for k, v in self.meta.items() if k != "hash"}
        return WetGrid(self.dry_axes, self.wet_axes, var, meta, source=self.source)


def save_wet(path: Any, wet: WetGrid | PendingWetGrid) -> None:
    """Append the wet branch to an existing NetCDF grid file (its dry content unchanged).

    A :class:`PendingWetGrid` is completed first with the file's dry ``mu_cold`` and
    ``mu_hot`` (as stored, i.e. as the dry reader returns them).
    """
    import h5netcdf

    if isinstance(wet, PendingWetGrid):
        with h5netcdf.File(path, "r") as f:
            ax = {n: np.asarray(f.variables[n][...], float) for n in ("log10_v", "T",
                                                                      "log10_p")}
            mc = np.asarray(f.variables["mu_cold"][...], float)
            mh = np.asarray(f.variables["mu_hot"][...], float)
        wet = wet.complete(ax, mc, mh)
    with h5netcdf.File(path, "a") as f:
        for n in WET_AXES:
            f.dimensions[n] = wet.axes[n].size
            var = f.create_variable(n, (n,), "f8", data=wet.axes[n])
            var.attrs["units"] = WET_AXIS_UNITS[n]
            var.attrs["long_name"] = WET_AXIS_LONG_NAMES[n]
        for n in WET_VARIABLES:
            var = f.create_variable(n, WET_DIMS[n], "f8", data=wet.variables[n],
                                    compression="gzip", shuffle=True, fletcher32=True)
            var.attrs["units"] = "1"
            var.attrs["long_name"] = WET_LONG_NAMES[n]
        f.attrs["wet_hash"] = wet.meta["hash"]
        f.attrs["wet_meta_json"] = json.dumps(wet.meta, sort_keys=True, default=str)


def load_wet(path: Any) -> WetGrid:
    """Read the wet branch of a grid file; a :class:`GridError` if it has none."""
    import h5netcdf

    from .store import resolve_grid_path

    path = resolve_grid_path(path)
    with h5netcdf.File(path, "r") as f:
        if "wet_meta_json" not in f.attrs:
            raise GridError(f"{path}: the grid has no wet branch (build it with a [wet] table "
                            f"in the grid spec)")
        dry = {n: np.asarray(f.variables[n][...], float) for n in ("log10_v", "T", "log10_p")}
        wax = {n: np.asarray(f.variables[n][...], float) for n in WET_AXES}
        var = {n: np.asarray(f.variables[n][...], float) for n in WET_VARIABLES}
        meta = json.loads(f.attrs["wet_meta_json"])
        if f.attrs.get("wet_hash") != meta.get("hash"):
            raise GridError(f"{path}: attribute wet_hash differs from the wet metadata")
    return WetGrid(dry, wax, var, meta, source=str(path))
