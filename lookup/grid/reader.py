"""Friction grids in memory and their fast multilinear interpolation (numpy only).

A :class:`FrictionGrid` holds the steady-sliding friction of one compound on one surface
tabulated on three axes,

================  =====================  =====================================================
axis              unit                   meaning
================  =====================  =====================================================
``log10_v``       log10(m/s)             decimal logarithm of the slip speed v
``T``             K                      background (tread) temperature T0
``log10_p``       log10(Pa)              decimal logarithm of the nominal contact pressure p
================  =====================  =====================================================

and the variables of :data:`VARIABLES` on every node (arrays of shape ``(nv, nT, np)``):
cold and hot friction coefficient with their viscoelastic and contact (adhesive) parts, the
relative real contact area A/A0 of both branches, the flash temperature rise and the residual
of the hot self-consistent solve. ``meta`` carries provenance (compound, surface, engine
settings), the macroasperity contact diameter ``D_m`` and the blending length ``s0_m`` of eq.
(28) in ``docs/review-notes.md``, and the content hash.

Interpolation is multilinear in (log10 v, T, log10 p); optionally monotone cubic along log10 v
(``v_interp="pchip"``) and along log10 p (``p_interp="pchip"``) and, across T, linear at fixed
reduced speed log10(v a_T(T)) (``T_interp="reduced_speed"``, :meth:`FrictionGrid.interpolate`).
Both log axes use base 10 (the pressure axis is stored as ``log10_p``; :attr:`FrictionGrid.log_p`
is an alias).

Out-of-range policy (explicit, never NaN)
-----------------------------------------
* The slip speed enters as ``|v|``; speeds below the first axis node ``v_min`` (including
  v = 0, a tread element sticking or at standstill) are read at ``v_min``, the grid's
  low-speed limit. This is normal operation and is not counted.
* Every other query coordinate outside its axis (v above ``v_max``, T or p outside their
  axes) is clamped to the nearest axis end and the grid's value there is returned (constant
  extrapolation).
* Clamped coordinates are counted per axis and side in :attr:`FrictionGrid.out_of_range_detail`
  (``"below"`` / ``"above"``; ``log10_v`` ``"below"`` stays 0 by the rule above);
  :attr:`FrictionGrid.out_of_range_count` gives the total per axis. A non-zero count means the
  grid does not cover the use.
* A NaN query coordinate is an error (:class:`~tirefric.errors.GridError`), not a NaN result.

This module runs inside an FMU: it imports only numpy and the standard library (and the
stdlib-only :mod:`tirefric.errors`).
"""

from __future__ import annotations

import hashlib
import json
import math
import zipfile
import zlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import GridError

#: Axis names in storage order, with units.
AXES: tuple[str, str, str] = ("log10_v", "T", "log10_p")
AXIS_UNITS: dict[str, str] = {"log10_v": "log10(m/s)", "T": "K", "log10_p": "log10(Pa)"}
AXIS_LONG_NAMES: dict[str, str] = {
    "log10_v": "decimal logarithm of the slip speed v [m/s]",
    "T": "background temperature T0",
    "log10_p": "decimal logarithm of the nominal contact pressure p [Pa]",
}

#: Variables of a complete grid, with units and descriptions.
VARIABLES: tuple[str, ...] = (
    "mu_cold", "mu_hot", "mu_visc_cold", "mu_cont_cold", "mu_visc_hot", "mu_cont_hot",
    "area_cold", "area_hot", "dT_flash", "residual_hot",
)
#: Variables a grid has only where they apply: the share of each node's friction integrand
#: taken from outside a tabulated master curve's measured band (lookup.friction module
#: docstring); a compound with an analytic master curve has none, and its grid leaves them out.
DIAGNOSTIC_VARIABLES: tuple[str, ...] = ("outside_cold", "outside_hot")
#: Every variable a grid may hold, in storage (and hash) order.
ALL_VARIABLES: tuple[str, ...] = VARIABLES + DIAGNOSTIC_VARIABLES
VARIABLE_UNITS: dict[str, str] = {
    "mu_cold": "1", "mu_hot": "1", "mu_visc_cold": "1", "mu_cont_cold": "1",
    "mu_visc_hot": "1", "mu_cont_hot": "1", "area_cold": "1", "area_hot": "1",
    "dT_flash": "K", "residual_hot": "K", "outside_cold": "1", "outside_hot": "1",
}
VARIABLE_LONG_NAMES: dict[str, str] = {
    "mu_cold": "friction coefficient, cold branch (no flash heating)",
    "mu_hot": "friction coefficient, hot branch (flash temperature fully developed)",
    "mu_visc_cold": "viscoelastic part of mu_cold",
    "mu_cont_cold": "contact (adhesive) part of mu_cold",
    "mu_visc_hot": "viscoelastic part of mu_hot",
    "mu_cont_hot": "contact (adhesive) part of mu_hot",
    "area_cold": "relative real contact area A/A0, cold branch",
    "area_hot": "relative real contact area A/A0, hot branch",
    "dT_flash": "flash temperature rise of the hot branch",
    "residual_hot": "convergence residual of the self-consistent hot solve",
    "outside_cold": "share of mu_cold's integrand from outside the measured master curve",
    "outside_hot": "share of mu_hot's integrand from outside the measured master curve",
}
#: Variables every grid must have (a reduced grid, e.g. for tests, may leave out the others).
REQUIRED_VARIABLES: tuple[str, ...] = ("mu_cold", "mu_hot", "dT_flash")
#: Metadata every grid must have.
REQUIRED_META: tuple[str, ...] = ("s0_m", "D_m")
#: Version of the file layout written by :meth:`FrictionGrid.save_npz` and ``store.save_grid``.
FORMAT_VERSION = 1
NPZ_FORMAT = "tirefric-friction-grid"

DEFAULT_NAMES: tuple[str, ...] = ("mu_cold", "mu_hot", "dT_flash")
#: Interpolations along log10 v offered by :meth:`FrictionGrid.interpolate`.
V_INTERPOLATIONS: tuple[str, ...] = ("linear", "pchip")
#: Interpolations across T offered by :meth:`FrictionGrid.interpolate`: ``"linear"`` at fixed
#: log10 v (multilinear), or ``"reduced_speed"``: linear in T at fixed reduced speed
#: log10(v a_T(T)) (:func:`shift_from_meta`).
T_INTERPOLATIONS: tuple[str, ...] = ("linear", "reduced_speed")
#: Interpolations along log10 p offered by :meth:`FrictionGrid.interpolate`.
P_INTERPOLATIONS: tuple[str, ...] = ("linear", "pchip")


def shift_from_meta(meta: Mapping[str, Any], source: str = "grid"):
    """log10 a_T(T) [T in K] of the grid's compound, from its provenance (numpy only).

    Grids written by ``lookup.grid.build`` store the compound's parameters under
    ``meta["compound"]["shift"]``; this evaluates the two bulk shift laws found there, with
    the same formulas as :mod:`lookup.shift` (kept here so that the reader stays numpy-only):

    * ``"wlf"``: review eq. (5), log10 a_T = -C1 (T - T_r)/(C2 + T - T_r), continued linearly
      below T_r - 0.9 C2 (as :class:`lookup.shift.WLF`);
    * ``"tabulated"``: log10 a_T linear in T between the points, end segments continued.

    Only differences log10 a_T(T) - log10 a_T(T') are used, so the reference temperature
    drops out.

    Raises
    ------
    GridError
        The grid carries no shift law or one this reader does not know.
    """
    shift = (meta.get("compound") or {}).get("shift") if isinstance(meta, Mapping) else None
    model = shift.get("model") if isinstance(shift, Mapping) else None
    try:
        if model == "wlf":
            C1, C2, Tr = float(shift["C1"]), float(shift["C2_K"]), float(shift["T_ref_K"])

            def wlf(T: np.ndarray) -> np.ndarray:
                dT = np.asarray(T, dtype=float) - Tr
                d_min = -0.9 * C2
                dTc = np.maximum(dT, d_min)
                val = -C1 * dTc / (C2 + dTc)
                slope = -C1 * C2 / (C2 + d_min) ** 2
                return np.where(dT < d_min, val + slope * (dT - d_min), val)

            return wlf
        if model == "tabulated":
            x = np.asarray(shift["T_K"], dtype=float)
            y = np.asarray(shift["log10_aT"], dtype=float)
            s0 = (y[1] - y[0]) / (x[1] - x[0])
            s1 = (y[-1] - y[-2]) / (x[-1] - x[-2])

            def table(T: np.ndarray) -> np.ndarray:
                T = np.asarray(T, dtype=float)
                out = np.interp(T, x, y)
                out = np.where(T < x[0], y[0] + s0 * (T - x[0]), out)
                return np.where(T > x[-1], y[-1] + s1 * (T - x[-1]), out)

            return table
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise GridError(f"{source}: the compound's shift law in the metadata is incomplete "
                        f"({type(exc).__name__}: {exc})") from None
    raise GridError(f"{source}: T interpolation 'reduced_speed' needs the compound's shift "
                    f"factor in the metadata (meta['compound']['shift'] with model 'wlf' or "
                    f"'tabulated'); found {model!r}")


def pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Node slopes dy/dx of the monotone piecewise cubic Hermite interpolant along axis 0.

    Fritsch and Carlson's method in the form of Fritsch and Butland (SIAM J. Sci. Stat.
    Comput. 5, 300, 1984), as in scipy's ``PchipInterpolator``: at an interior node the
    slope is 0 where the secant slopes change sign (a local extremum) and otherwise their
    weighted harmonic mean with weights ``w1 = 2 h_k + h_{k-1}``, ``w2 = h_k + 2 h_{k-1}``;
    at the ends a one-sided three-point estimate, set to 0 if its sign differs from the end
    secant's and limited to three times that secant where the secants change sign. The
    resulting cubic is monotone on every interval whose end values are monotone with their
    neighbours', and reproduces linear data exactly.

    Parameters
    ----------
    x
        Strictly ascending nodes, shape ``(n,)``, n >= 2.
    y
        Values, shape ``(n, ...)``.

    Returns
    -------
    ndarray
        Slopes, shape of ``y``.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    delta = np.diff(y, axis=0) / h
    d = np.zeros_like(y)
    if x.size == 2:
        d[:] = delta[0]
        return d
    h0, h1 = h[:-1], h[1:]
    d0, d1 = delta[:-1], delta[1:]
    w1, w2 = 2.0 * h1 + h0, h1 + 2.0 * h0
    same = (d0 * d1) > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        harmonic = (w1 + w2) / (w1 / d0 + w2 / d1)
    d[1:-1] = np.where(same, harmonic, 0.0)

    def end(hA: np.ndarray, hB: np.ndarray, dA: np.ndarray, dB: np.ndarray) -> np.ndarray:
        e = ((2.0 * hA + hB) * dA - hA * dB) / (hA + hB)
        e = np.where(np.sign(e) != np.sign(dA), 0.0, e)
        return np.where((np.sign(dA) != np.sign(dB)) & (np.abs(e) > 3.0 * np.abs(dA)),
                        3.0 * dA, e)

    d[0] = end(h[0], h[1], delta[0], delta[1])
    d[-1] = end(h[-1], h[-2], delta[-1], delta[-2])
    return d


def _cell_diff(A: np.ndarray, axis: int) -> np.ndarray:
    """Forward difference of ``A`` along ``axis``, 0 on the last node (whose cell is only used
    with fraction 0)."""
    d = np.zeros_like(A)
    sl = [slice(None)] * A.ndim
    lo, hi = list(sl), list(sl)
    lo[axis], hi[axis] = slice(None, -1), slice(1, None)
    d[tuple(lo)] = A[tuple(hi)] - A[tuple(lo)]
    return d


def _cell_powers(y: np.ndarray, d: np.ndarray | None, x: np.ndarray,
                 axis: int) -> list[np.ndarray]:
    """Monomial coefficients, per cell along ``axis``, of the interpolant in the fraction f.

    ``d is None``: linear, ``[y, dy]``. Otherwise the cubic Hermite polynomial with node
    slopes ``d`` (dy/dx): ``[y, h d0, 3 dy - 2 h d0 - h d1, h d0 + h d1 - 2 dy]`` with the
    cell width h. Cells of the last node are 0 beyond the constant term.
    """
    dy = _cell_diff(y, axis)
    if d is None:
        return [y, dy]
    shape = [1] * y.ndim
    shape[axis] = -1
    h = np.append(np.diff(x), 0.0).reshape(shape)
    hd0 = h * d
    hd1 = h * np.roll(d, -1, axis=axis)  # the last cell's entry is multiplied by h = 0
    return [y, hd0, 3.0 * dy - 2.0 * hd0 - hd1, hd0 + hd1 - 2.0 * dy]


def content_hash(axes: Mapping[str, np.ndarray], variables: Mapping[str, np.ndarray]) -> str:
    """SHA-256 of the numeric content of a grid (axes and variables, not metadata).

    The digest covers, in this order, each axis of :data:`AXES` and then each present variable
    in the order of :data:`ALL_VARIABLES`: its name (UTF-8), its shape and its values as
    little-endian float64 in C order. It is therefore independent of the file format (NetCDF
    or npz) the grid was stored in.

    Returns
    -------
    str
        ``"sha256:<64 hex digits>"``.
    """
    h = hashlib.sha256()
    items = [(a, axes[a]) for a in AXES] + [(v, variables[v]) for v in ALL_VARIABLES
                                             if v in variables]
    for name, arr in items:
        a = np.ascontiguousarray(arr, dtype="<f8")
        h.update(name.encode())
        h.update(repr(tuple(a.shape)).encode())
        h.update(a.tobytes())
    return "sha256:" + h.hexdigest()


def _validate_axis(name: str, values: Any, source: str) -> np.ndarray:
    try:
        a = np.array(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise GridError(f"{source}: axis '{name}' is not numeric ({exc})") from None
    if a.ndim != 1:
        raise GridError(f"{source}: axis '{name}' must be one-dimensional (shape {a.shape})")
    if a.size < 2:
        raise GridError(f"{source}: axis '{name}' needs at least 2 points (has {a.size})")
    if not np.isfinite(a).all():
        i = int(np.flatnonzero(~np.isfinite(a))[0])
        raise GridError(f"{source}: axis '{name}' entry {i} is not finite ({a[i]!r})")
    d = np.diff(a)
    if not (d > 0).all():
        i = int(np.flatnonzero(d <= 0)[0])
        raise GridError(f"{source}: the points of axis '{name}' must be strictly ascending "
                        f"(entry {i + 1} = {a[i + 1]!r} follows {a[i]!r})")
    return a


def _is_uniform(a: np.ndarray) -> bool:
    """Whether the axis nodes are equally spaced to rounding (then index arithmetic is exact)."""
    d = np.diff(a)
    return bool(np.all(np.abs(d - d.mean()) <= 1e-9 * abs(d.mean())))


class FrictionGrid:
    """Friction tables on (log10 v, T, log10 p) with fast multilinear interpolation.

    Parameters
    ----------
    log10_v
        Slip-speed axis, log10 of v in m/s, strictly ascending.
    T
        Background-temperature axis [K], strictly ascending.
    log10_p
        Nominal-pressure axis, log10 of p in Pa, strictly ascending.
    variables
        Name -> array of shape ``(len(log10_v), len(T), len(log10_p))``; names from
        :data:`ALL_VARIABLES`, at least :data:`REQUIRED_VARIABLES`; all values finite.
    meta
        Provenance and constants; must contain ``"s0_m"`` and ``"D_m"`` [m] (positive
        floats). The key ``"hash"`` is set to :func:`content_hash`; if ``meta`` already carries
        a hash that differs, the content was altered and :class:`GridError` is raised.
    source
        Where the grid came from (a file name), used in error messages.

    Raises
    ------
    GridError
        Non-monotonic or non-finite axes, wrong shapes, NaN/inf values, unknown or missing
        variables, missing metadata or a hash mismatch; the message names the item.
    """

    def __init__(
        self,
        log10_v: Any,
        T: Any,
        log10_p: Any,
        variables: Mapping[str, Any],
        meta: Mapping[str, Any] | None = None,
        *,
        source: str = "grid",
    ) -> None:
        self.source = str(source)
        axes = {"log10_v": log10_v, "T": T, "log10_p": log10_p}
        self.axes: dict[str, np.ndarray] = {
            n: _validate_axis(n, axes[n], self.source) for n in AXES}
        shape = tuple(self.axes[n].size for n in AXES)
        unknown = sorted(set(variables) - set(ALL_VARIABLES))
        if unknown:
            raise GridError(f"{self.source}: unknown variable(s) {unknown} "
                            f"(known: {', '.join(ALL_VARIABLES)})")
        missing = [n for n in REQUIRED_VARIABLES if n not in variables]
        if missing:
            raise GridError(f"{self.source}: required variable(s) missing: {missing}")
        self.variables: dict[str, np.ndarray] = {}
        for name in ALL_VARIABLES:
            if name not in variables:
                continue
            try:
                arr = np.array(variables[name], dtype=float)
            except (TypeError, ValueError) as exc:
                raise GridError(f"{self.source}: variable '{name}' is not numeric "
                                f"({exc})") from None
            if arr.shape != shape:
                raise GridError(f"{self.source}: variable '{name}' has shape {arr.shape}, "
                                f"expected {shape} = (log10_v, T, log10_p)")
            bad = ~np.isfinite(arr)
            if bad.any():
                idx = tuple(int(i) for i in np.argwhere(bad)[0])
                raise GridError(f"{self.source}: variable '{name}' has {int(bad.sum())} "
                                f"non-finite value(s), first at index {idx} "
                                f"({arr[idx]!r})")
            arr.flags.writeable = False
            self.variables[name] = arr
        for a in self.axes.values():
            a.flags.writeable = False
        self.meta: dict[str, Any] = dict(meta or {})
        for key in REQUIRED_META:
            if key not in self.meta:
                raise GridError(f"{self.source}: metadata '{key}' is missing")
            try:
                val = float(self.meta[key])
            except (TypeError, ValueError):
                raise GridError(f"{self.source}: metadata '{key}' is not a number "
                                f"({self.meta[key]!r})") from None
            if not (math.isfinite(val) and val > 0):
                raise GridError(f"{self.source}: metadata '{key}' must be a positive "
                                f"length in m (is {val!r})")
            self.meta[key] = val
        digest = content_hash(self.axes, self.variables)
        stored = self.meta.get("hash")
        if stored is not None and stored != digest:
            raise GridError(f"{self.source}: content hash mismatch (stored {stored}, "
                            f"computed {digest}): the file is corrupt or was altered")
        self.meta["hash"] = digest
        self._setup_interpolation()
        self.reset_out_of_range_count()

    # -- construction helpers -----------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        v: Any,
        T: Any,
        p: Any,
        variables: Mapping[str, Any],
        *,
        s0_m: float,
        D_m: float,
        meta: Mapping[str, Any] | None = None,
    ) -> FrictionGrid:
        """Build a grid from axes in plain units.

        Parameters
        ----------
        v
            Slip speeds [m/s], positive, ascending (stored as log10).
        T
            Background temperatures [K], ascending.
        p
            Nominal pressures [Pa], positive, ascending (stored as log10).
        variables
            Name -> array of shape ``(len(v), len(T), len(p))``.
        s0_m, D_m
            Blending slip length s0 and macroasperity contact diameter D [m].
        meta
            Further metadata (provenance).
        """
        v = np.asarray(v, dtype=float)
        p = np.asarray(p, dtype=float)
        if (v <= 0).any() or (p <= 0).any():
            raise GridError("from_arrays: slip speeds and pressures must be > 0 "
                            "(their axes are stored as log10)")
        m = dict(meta or {})
        m.update(s0_m=s0_m, D_m=D_m)
        return cls(np.log10(v), T, np.log10(p), variables, m, source="from_arrays")

    @classmethod
    def constant(
        cls,
        mu_cold: float,
        mu_hot: float,
        *,
        s0_m: float | None = None,
        D_m: float = 1e-3,
        dT_flash: float = 0.0,
        area: float = 0.0,
        v_range: tuple[float, float] = (1e-6, 40.0),
        T_range: tuple[float, float] = (253.15, 393.15),
        p_range: tuple[float, float] = (5e4, 2e6),
    ) -> FrictionGrid:
        """A flat grid (every node equal), e.g. for the constant-friction brush limit.

        Parameters
        ----------
        mu_cold, mu_hot
            Friction coefficients of the cold and hot branch on every node.
        s0_m
            Blending slip length s0 of eq. (28) [m]; default ``0.2 * D_m``
            (docs/review-notes.md: s0 ~ 0.2 D).
        D_m
            Macroasperity contact diameter D [m].
        dT_flash
            Flash temperature rise on every node [K].
        area
            Relative contact area A/A0 of both branches on every node.
        v_range, T_range, p_range
            Axis ends [m/s], [K], [Pa]; each axis has two nodes.

        Notes
        -----
        The friction is attributed entirely to the viscoelastic part
        (``mu_visc_* = mu_*``, ``mu_cont_* = 0``); ``residual_hot`` is 0.
        """
        shape = (2, 2, 2)

        def full(x: float) -> np.ndarray:
            return np.full(shape, float(x))

        variables = {
            "mu_cold": full(mu_cold), "mu_hot": full(mu_hot),
            "mu_visc_cold": full(mu_cold), "mu_cont_cold": full(0.0),
            "mu_visc_hot": full(mu_hot), "mu_cont_hot": full(0.0),
            "area_cold": full(area), "area_hot": full(area),
            "dT_flash": full(dT_flash), "residual_hot": full(0.0),
        }
        return cls.from_arrays(
            v_range, T_range, p_range, variables,
            s0_m=0.2 * D_m if s0_m is None else s0_m, D_m=D_m,
            meta={"kind": "constant", "mu_cold": float(mu_cold), "mu_hot": float(mu_hot)})

    # -- properties ---------------------------------------------------------------------------
    @property
    def log10_v(self) -> np.ndarray:
        """Slip-speed axis, log10(v / (m/s))."""
        return self.axes["log10_v"]

    @property
    def T(self) -> np.ndarray:
        """Background-temperature axis [K]."""
        return self.axes["T"]

    @property
    def log10_p(self) -> np.ndarray:
        """Nominal-pressure axis, log10(p / Pa)."""
        return self.axes["log10_p"]

    @property
    def log_p(self) -> np.ndarray:
        """Alias of :attr:`log10_p` (the pressure axis is stored in base 10)."""
        return self.axes["log10_p"]

    @property
    def v(self) -> np.ndarray:
        """Slip-speed nodes [m/s]."""
        return 10.0 ** self.axes["log10_v"]

    @property
    def p(self) -> np.ndarray:
        """Pressure nodes [Pa]."""
        return 10.0 ** self.axes["log10_p"]

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(nv, nT, np)``."""
        return tuple(self.axes[n].size for n in AXES)  # type: ignore[return-value]

    @property
    def names(self) -> tuple[str, ...]:
        """Variables present in this grid."""
        return tuple(self.variables)

    @property
    def s0_m(self) -> float:
        """Blending slip length s0 of eq. (28) [m]."""
        return self.meta["s0_m"]

    @property
    def D_m(self) -> float:
        """Macroasperity contact diameter D [m]."""
        return self.meta["D_m"]

    @property
    def hash(self) -> str:
        """Content hash, ``"sha256:..."`` (see :func:`content_hash`)."""
        return self.meta["hash"]

    def __getitem__(self, name: str) -> np.ndarray:
        """The node values of variable ``name``, shape ``(nv, nT, np)`` (read-only)."""
        try:
            return self.variables[name]
        except KeyError:
            raise GridError(f"{self.source}: no variable '{name}' "
                            f"(present: {', '.join(self.variables)})") from None

    def __repr__(self) -> str:
        v0, v1 = 10 ** self.log10_v[[0, -1]]
        p0, p1 = 10 ** self.log10_p[[0, -1]]
        return (f"FrictionGrid(shape={self.shape}, v={v0:.3g}..{v1:.3g} m/s, "
                f"T={self.T[0]:.2f}..{self.T[-1]:.2f} K, p={p0:.3g}..{p1:.3g} Pa, "
                f"hash={self.hash[:19]}...)")

    # -- out-of-range bookkeeping -------------------------------------------------------------
    def reset_out_of_range_count(self) -> None:
        """Set the clamp counters to zero."""
        self._below = np.zeros(3, dtype=np.int64)
        self._above = np.zeros(3, dtype=np.int64)

    @property
    def out_of_range_count(self) -> dict[str, int]:
        """Number of clamped query coordinates per axis (both sides) since the last reset."""
        return {n: int(self._below[i] + self._above[i]) for i, n in enumerate(AXES)}

    @property
    def out_of_range_detail(self) -> dict[str, dict[str, int]]:
        """Clamped query coordinates per axis and side, ``{axis: {"below": n, "above": n}}``."""
        return {n: {"below": int(self._below[i]), "above": int(self._above[i])}
                for i, n in enumerate(AXES)}

    # -- interpolation ------------------------------------------------------------------------
    #: Queries of up to this many points use contiguous per-point copies of the axis offset,
    #: scale and length (no broadcasting, ~0.5 us less per operation); larger ones broadcast.
    _SMALL = 512
    #: At most this many query sizes keep such copies (a brush asks for varying sizes).
    _SMALL_SIZES = 64
    #: Larger queries are evaluated in chunks of this many points (cache-sized temporaries).
    _CHUNK = 2048

    def _setup_interpolation(self) -> None:
        """Precompute what the interpolation needs (index maps, strides, cell coefficients).

        Each coordinate maps to a fractional node index ``t = (x - x_0) * scale`` (``x`` is
        log10 v, T or log10 p, ``x_0`` the first node) on an equally spaced axis: 0 at the
        first node and, after rounding, not above ``n - 1`` at the last (so a query on an
        axis end is never counted as out of range); an unequally spaced axis keeps ``x``
        (``x_0`` = 0, scale 1) and maps it with ``np.interp`` on its nodes.
        """
        ax = [self.axes[n] for n in AXES]
        n = np.array([a.size for a in ax])
        lo = np.array([a[0] for a in ax])
        hi = np.array([a[-1] for a in ax])
        # axes with equal spacing map to fractional indices by arithmetic, others by np.interp
        self._nonuniform = [k for k, a in enumerate(ax) if not _is_uniform(a)]
        scale = (n - 1) / (hi - lo)
        for k in range(3):
            while (hi[k] - lo[k]) * scale[k] > n[k] - 1:
                scale[k] = math.nextafter(scale[k], 0.0)
        offset = lo.copy()
        scale[self._nonuniform] = 1.0
        offset[self._nonuniform] = 0.0
        nmax = (n - 1).astype(float)
        self._nmax = nmax[:, None]
        self._index_axes = [np.arange(k, dtype=float) for k in n]
        # (offset, scale, nmax), each (3, 1) for broadcasting over large queries; small
        # queries use (3, n) copies made by _affine_for
        self._affine = (offset[:, None], scale[:, None], self._nmax)
        self._affine_small: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        vfloor = float(10.0 ** ax[0][0])
        while np.log10(vfloor) < ax[0][0]:  # rounding must not push v_min below the axis
            vfloor = math.nextafter(vfloor, math.inf)
        self._vfloor = vfloor
        # one interpolation cell per node: cell (i, j, k) spans nodes i..i+1, j..j+1, k..k+1;
        # the cells of the last node of an axis reach into an edge-padded layer and are only
        # used with fraction 0 there (a query exactly on the last node)
        self._strides_f = np.array([n[1] * n[2], n[2], 1], dtype=float)
        self._coef_cache: dict[tuple[str, ...], np.ndarray] = {}

    def _affine_for(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(offset, scale, nmax) as contiguous ``(3, n)`` arrays, cached per query size."""
        if len(self._affine_small) >= self._SMALL_SIZES:
            self._affine_small.clear()
        arrays = tuple(np.repeat(a, n, axis=1) for a in self._affine)
        for a in arrays:
            a.flags.writeable = False
        self._affine_small[n] = arrays  # type: ignore[assignment]
        return arrays  # type: ignore[return-value]

    def _coefficients(self, names: tuple[str, ...], v_interp: str = "linear",
                      p_interp: str = "linear") -> np.ndarray:
        """Monomial coefficients of the interpolant of every cell.

        The interpolant is ``sum c_abc fx^a fy^b fz^c`` in the fractional coordinates
        ``(fx, fy, fz)`` of the cell along (log10 v, T, log10 p), with ``b`` in {0, 1} (linear
        in T), ``a = 0 .. K`` and ``c = 0 .. L``: K = 1 for ``v_interp="linear"`` and K = 3
        for ``"pchip"`` (the cubic Hermite polynomial of :func:`pchip_slopes` along log10 v);
        likewise L = 1 or 3 for ``p_interp`` (see :meth:`_patches`).

        Returns an array ``Q`` of shape ``(n_cells, 2 (K + 1) (L + 1) len(names))``; row
        ``r``, read as ``(2 (K + 1) (L + 1), len(names))``, holds cell ``r``'s coefficients in
        the order ``index = c 2 (K + 1) + b (K + 1) + a``, so that the value is evaluated in
        nested form (Horner in fz, then y, then a Horner step per power of fx): six array
        operations for the trilinear case, fewer than forming the eight corner weights. One
        cell is one contiguous row, so that gathering the cells of a query reads a few cache
        lines per point. The cache key is ``(names, v_interp)`` for a linear p axis and
        ``(names, v_interp, p_interp)`` otherwise.
        """
        key = (names, v_interp) if p_interp == "linear" else (names, v_interp, p_interp)
        table = self._coef_cache.get(key)
        if table is None:
            plane = self._coef_cache.get((names, v_interp, p_interp, "plane"))
            A = self._patches(names, v_interp, p_interp) if plane is None else plane
            nv, nT, np_ = self.shape
            m = len(names)
            A = A.reshape(nv, nT, np_, -1)
            P = np.pad(A, ((0, 0), (0, 1), (0, 0), (0, 0)), mode="edge")  # b = 1: T step
            table = np.stack([A, P[:, 1:] - A], axis=-1)  # (..., kp k m, 2)
            kp_k = A.shape[-1] // m
            k = 2 if v_interp == "linear" else 4
            table = table.reshape(nv * nT * np_, kp_k // k, k, m, 2)
            table = np.ascontiguousarray(table.transpose(0, 1, 4, 2, 3)).reshape(
                nv * nT * np_, 2 * kp_k * m)
            table.flags.writeable = False
            self._coef_cache[key] = table
        return table

    def _plane_coefficients(self, names: tuple[str, ...], v_interp: str,
                            p_interp: str) -> np.ndarray:
        """Each cell's patch on its own T node (the ``b = 0`` part of :meth:`_coefficients`),
        shape ``(n_cells, (K + 1) (L + 1) len(names))``, index ``c (K + 1) + a``; cached."""
        key = (names, v_interp, p_interp, "plane")
        table = self._coef_cache.get(key)
        if table is None:
            table = self._patches(names, v_interp, p_interp)
            table.flags.writeable = False
            self._coef_cache[key] = table
        return table

    def _patches(self, names: tuple[str, ...], v_interp: str, p_interp: str) -> np.ndarray:
        """Monomial coefficients ``c_ac`` of ``fx^a fz^c`` of every cell on its own T node,
        shape ``(n_cells, (K + 1) (L + 1) len(names))`` (not cached).

        Along log10 v and log10 p linear or cubic Hermite with :func:`pchip_slopes`; with both
        cubic, the bicubic Hermite patch of the node values, their pchip slopes along v and
        along p, and as cross derivative the pchip slope along p of the v slopes: it reduces to
        the 1-D pchip along v on the p nodes and along p on the v nodes.
        """
        if v_interp not in V_INTERPOLATIONS:
            raise GridError(f"{self.source}: unknown interpolation along log10 v "
                            f"{v_interp!r} (known: {', '.join(V_INTERPOLATIONS)})")
        if p_interp not in P_INTERPOLATIONS:
            raise GridError(f"{self.source}: unknown interpolation along log10 p "
                            f"{p_interp!r} (known: {', '.join(P_INTERPOLATIONS)})")
        for nm in names:
            if nm not in self.variables:
                raise GridError(f"{self.source}: no variable '{nm}' "
                                f"(present: {', '.join(self.variables)})")
        m = len(names)
        y = np.stack([self.variables[nm] for nm in names], axis=-1)  # (nv, nT, np, m)
        dv = pchip_slopes(self.log10_v, y) if v_interp == "pchip" else None
        along_v = _cell_powers(y, dv, self.log10_v, 0)  # fx^a, a = 0 .. K
        if p_interp == "linear":
            powers = [[A, _cell_diff(A, 2)] for A in along_v]
        else:
            # the p slopes of each v power are the same combination of the p slopes of the
            # values and (cross derivative) of the v slopes
            yp = np.moveaxis(pchip_slopes(self.log10_p, np.moveaxis(y, 2, 0)), 0, 2)
            dvp = (None if dv is None else
                   np.moveaxis(pchip_slopes(self.log10_p, np.moveaxis(dv, 2, 0)), 0, 2))
            along_v_p = _cell_powers(yp, dvp, self.log10_v, 0)
            powers = [_cell_powers(A, Ap, self.log10_p, 2)
                      for A, Ap in zip(along_v, along_v_p, strict=True)]
        k, kp = len(powers), len(powers[0])
        n = y.shape[0] * y.shape[1] * y.shape[2]
        table = np.empty((n, kp, k, m))
        for a_, row in enumerate(powers):
            for c_, A in enumerate(row):
                table[:, c_, a_, :] = A.reshape(-1, m)
        return table.reshape(n, kp * k * m)

    def _out_of_range(self, t: np.ndarray, p: np.ndarray) -> None:
        """Refuse NaN coordinates, count and clamp out-of-range ones (in place on ``t``).

        ``t`` holds the fractional node indices, shape ``(3, n)``; ``p`` the query pressures
        (to name a non-positive pressure as the cause of a NaN).
        """
        nan = np.isnan(t)
        if nan.any():
            k = int(np.flatnonzero(nan.any(axis=1))[0])
            if AXES[k] == "log10_p" and (np.asarray(p) < 0).any():
                raise GridError(f"{self.source}: query pressure p must be > 0 Pa "
                                f"(got {float(np.min(p))!r})")
            raise GridError(f"{self.source}: query coordinate '{AXES[k]}' is NaN "
                            f"(v, T and p must be numbers)")
        below = t < 0.0
        above = t > self._nmax
        self._below += below.sum(axis=1)
        self._above += above.sum(axis=1)
        np.maximum(t, 0.0, out=t)
        np.minimum(t, self._nmax, out=t)

    def interpolate(
        self,
        v: Any,
        T: Any,
        p: Any,
        names: Sequence[str] = DEFAULT_NAMES,
        v_interp: str = "linear",
        T_interp: str = "linear",
        p_interp: str = "linear",
    ) -> dict[str, np.ndarray]:
        """Interpolation in (log10 |v|, T, log10 p): multilinear by default; optionally monotone
        cubic along v and p and across T at fixed reduced speed.

        The most accurate combination is ``v_interp="pchip", T_interp="reduced_speed",
        p_interp="pchip"`` (shipped default grid, cold branch, all axes off-node: max 0.31 %
        against the engine instead of 1.7 %, ``docs/engine-inputs.md``); the default stays the
        multilinear one (about ten times faster, what the tire model reads).

        Parameters
        ----------
        v
            Slip speed(s) [m/s]; the sign is ignored (``|v|``), speeds below the first node
            are read at the first node.
        T
            Background temperature(s) [K].
        p
            Nominal pressure(s) [Pa], > 0 (p = 0 reads the lowest pressure and is counted).
        names
            Variables to return.
        v_interp
            Along log10 v: ``"linear"`` (default; trilinear interpolation) or ``"pchip"``
            (piecewise cubic Hermite with Fritsch-Carlson slopes, :func:`pchip_slopes`: it
            keeps monotone runs of the nodes monotone and does not overshoot). Both reproduce
            the node values.
        T_interp
            Across T: ``"linear"`` (default; at fixed log10 v) or ``"reduced_speed"``: linear
            in T at fixed reduced speed log10(v a_T(T)). With the two T nodes T_j <= T <=
            T_j+1 around the query, each node is read (along v as ``v_interp`` says, linearly
            in log10 p or as ``p_interp`` says) at the speed with the query's reduced speed,
            log10 v + log10 a_T(T) -
            log10 a_T(T_j), and the two values are blended linearly in T. By
            time-temperature superposition (review sec. 2: E(omega, T) = E(omega a_T, T_ref))
            the cold branch without frictional heating depends on v and T only through
            v a_T(T) when the adhesive law shifts with the bulk a_T, so this removes the T part
            of the interpolation error there; elsewhere (hot branch, an Arrhenius adhesive
            shift) it follows the dominant viscoelastic shift. a_T comes from the grid's
            provenance (:func:`shift_from_meta`). Queries within one T step's shift of the v
            axis ends: where the lower node's shifted speed falls below v_min, the upper node
            alone is read at the query's reduced speed (exact for the cold branch under
            time-temperature superposition; on the default grid this band had errors up to
            1.1 % with fixed-v interpolation, 0.11 % so); where the upper node's shifted speed
            exceeds v_max, the point is interpolated across T at fixed log10 v (there the hot
            branch, 50-110 K of flash heating, is far from superposition: a one-sided read
            errs by up to 5.5 %, fixed v by 0.5 %; the cold branch by 0.1 % either way).
            Out-of-range counting and clamping of the query are the same as with
            ``"linear"``.
        p_interp
            Along log10 p: ``"linear"`` (default) or ``"pchip"``: the cubic Hermite polynomial
            with the slopes of :func:`pchip_slopes` along log10 p; with ``v_interp="pchip"``
            the bicubic Hermite patch of :meth:`_coefficients`. It removes the pressure part
            of the error (up to 0.6 % between the highest pressure nodes of the default
            grid, where mu(log10 p) bends).

        Returns
        -------
        dict
            Name -> array of the broadcast shape of ``v``, ``T`` and ``p``.

        Raises
        ------
        GridError
            NaN in a query coordinate, a negative pressure, or an unknown variable name,
            ``v_interp``, ``T_interp`` or ``p_interp``.

        Notes
        -----
        Out-of-range coordinates are clamped to the axis ends and counted (module docstring).
        The query is mapped to a fractional node index per axis (index arithmetic on
        equally spaced axes, ``np.interp`` on the node positions otherwise); the cells'
        monomial coefficients (:meth:`_coefficients`) are gathered as one row per point and
        the trilinear polynomial is evaluated in nested form. A call costs about 20 numpy
        operations, about 15 us, plus 0.03-0.07 us per point (``benchmarks/bench_grid.py``);
        queries longer than :attr:`_CHUNK` points are evaluated chunk by chunk. The options
        cost more (``benchmarks/bench_grid.py`` prints them).

        A pressure p = 0 gives ``log10 p = -inf`` (numpy warns), is read at the lowest
        pressure and counted; a negative pressure is refused.
        """
        names = names if type(names) is tuple else tuple(names)
        if T_interp != "linear" or p_interp != "linear":
            return self._interpolate_general(v, T, p, names, v_interp, T_interp, p_interp)
        Q = self._coef_cache.get((names, v_interp))
        if Q is None:
            Q = self._coefficients(names, v_interp)
        degree = 1 if v_interp == "linear" else 3
        v = np.asarray(v, dtype=float)
        T = np.asarray(T, dtype=float)
        p = np.asarray(p, dtype=float)
        shape = v.shape
        if len(shape) != 1 or not (shape == T.shape == p.shape):
            if not (shape == T.shape == p.shape):
                shape = np.broadcast_shapes(shape, T.shape, p.shape)
                v, T, p = np.broadcast_arrays(v, T, p)
            v, T, p = v.reshape(-1), T.reshape(-1), p.reshape(-1)
        n = v.size
        if n <= self._CHUNK:
            if n == 0:
                return {nm: np.empty(shape) for nm in names}
            out = self._interpolate_chunk(Q, len(names), degree, v, T, p)
        else:  # chunks keep the working set in cache (and memory bounded)
            out = np.empty((len(names), n))
            for s in range(0, n, self._CHUNK):
                e = s + self._CHUNK
                out[:, s:e] = self._interpolate_chunk(Q, len(names), degree, v[s:e], T[s:e],
                                                      p[s:e])
        if len(shape) == 1:
            return dict(zip(names, out, strict=False))  # (strict=True costs 0.5 us)
        return {nm: out[j].reshape(shape) for j, nm in enumerate(names)}

    def _interpolate_chunk(
        self, Q: np.ndarray, n_names: int, degree: int, v: np.ndarray, T: np.ndarray,
        p: np.ndarray, p_degree: int = 1,
    ) -> np.ndarray:
        """The interpolation of :meth:`interpolate` on 1-D inputs of one length ``n`` > 0.

        Returns the values, shape ``(n_names, n)``, rows in the order of the columns of ``Q``
        (:meth:`_coefficients`).
        """
        n = v.shape[0]
        if n <= self._SMALL:
            affine = self._affine_small.get(n)
            if affine is None:
                affine = self._affine_for(n)
            offset, scale, nmax = affine
        else:
            offset, scale, nmax = self._affine
        # rows 0-2: the coordinates, then their fractional node indices t, then the fractions
        # within the cells; rows 3-5: nmax - t, then the cells' node indices (floor t)
        buf = np.empty((6, n))
        t = buf[:3]
        t0 = t[0]
        np.abs(v, out=t0)
        np.maximum(t0, self._vfloor, out=t0)
        t[1] = T
        t[2] = p
        logs = t[::2]
        np.log10(logs, out=logs)  # both log axes in one call
        t -= offset
        t *= scale
        for k in self._nonuniform:
            t[k] = np.interp(t[k], self.axes[AXES[k]], self._index_axes[k], left=-1.0,
                             right=np.inf)
        # 0 <= t <= nmax on every axis iff min(t, nmax - t) >= 0 (False for NaN as well)
        node = buf[3:]
        np.subtract(nmax, t, out=node)
        if not buf.min() >= 0.0:
            self._out_of_range(t, p)
        np.trunc(t, out=node)  # = floor, t >= 0
        t -= node
        # flat cell index, exact in float64 (< 2**53); float ops avoid int-float mixing
        cell = (self._strides_f @ node).astype(np.intp)
        if p_degree != 1:
            return self._evaluate_cells(Q, n_names, degree, cell, t[0], t[1], t[2], p_degree)
        k = degree + 1
        c = Q.take(cell, axis=0).T.copy().reshape(4 * k, n_names, n)
        a = c[2 * k:]  # c is a fresh copy: safe to update in place
        a *= t[2]
        a += c[:2 * k]
        b = a[k:]
        b *= t[1]
        b += a[:k]
        out = b[degree]  # Horner in fx
        for j in range(degree - 1, -1, -1):
            out *= t[0]
            out += b[j]
        return out

    def interpolate_one(
        self, name: str, v: Any, T: Any, p: Any, v_interp: str = "linear",
        T_interp: str = "linear", p_interp: str = "linear",
    ) -> np.ndarray:
        """One variable; shorthand for ``interpolate(v, T, p, (name,), v_interp,
        T_interp, p_interp)[name]``."""
        return self.interpolate(v, T, p, (name,), v_interp, T_interp, p_interp)[name]

    def log10_aT(self, T: Any) -> np.ndarray:
        """log10 a_T(T) of the grid's compound (T in K), from its metadata; the law is
        read once (:func:`shift_from_meta`)."""
        f = self.__dict__.get("_shift_fn")
        if f is None:
            f = self._shift_fn = shift_from_meta(self.meta, self.source)
        return f(T)

    def _indices(self, k: int, x: np.ndarray) -> np.ndarray:
        """Fractional node index of coordinates ``x`` on axis ``k`` (unclamped)."""
        offset, scale = self._affine[0][k, 0], self._affine[1][k, 0]
        t = (x - offset) * scale
        if k in self._nonuniform:
            t = np.interp(t, self.axes[AXES[k]], self._index_axes[k], left=-1.0,
                          right=np.inf)
        return t

    def _interpolate_general(
        self, v: Any, T: Any, p: Any, names: tuple[str, ...], v_interp: str, T_interp: str,
        p_interp: str,
    ) -> dict[str, np.ndarray]:
        """:meth:`interpolate` with ``T_interp="reduced_speed"`` or ``p_interp="pchip"``."""
        if T_interp not in T_INTERPOLATIONS:
            raise GridError(f"{self.source}: unknown interpolation across T {T_interp!r} "
                            f"(known: {', '.join(T_INTERPOLATIONS)})")
        reduced = T_interp == "reduced_speed"
        # the reduced speed reads the T nodes' own patches only
        Q = (self._plane_coefficients if reduced else self._coefficients)(names, v_interp,
                                                                          p_interp)
        degree = 1 if v_interp == "linear" else 3
        p_degree = 1 if p_interp == "linear" else 3
        v, T, p = np.broadcast_arrays(np.asarray(v, dtype=float), np.asarray(T, dtype=float),
                                      np.asarray(p, dtype=float))
        shape = v.shape
        v, T, p = v.reshape(-1), T.reshape(-1), p.reshape(-1)
        if v.size == 0:
            return {nm: np.empty(shape) for nm in names}
        out = np.empty((len(names), v.size))
        for s in range(0, v.size, self._CHUNK):  # cache-sized pieces, as interpolate
            e = s + self._CHUNK
            if reduced:
                out[:, s:e] = self._reduced_chunk(Q, len(names), degree, p_degree, v[s:e],
                                                  T[s:e], p[s:e])
            else:
                out[:, s:e] = self._interpolate_chunk(Q, len(names), degree, v[s:e], T[s:e],
                                                      p[s:e], p_degree)
        if len(shape) == 1:
            return dict(zip(names, out, strict=False))
        return {nm: out[k].reshape(shape) for k, nm in enumerate(names)}

    def _reduced_chunk(self, Qp: np.ndarray, n_names: int, degree: int, p_degree: int,
                       v: np.ndarray, T: np.ndarray, p: np.ndarray) -> np.ndarray:
        """``T_interp="reduced_speed"`` on 1-D inputs; values, shape ``(n_names, n)``.

        ``Qp`` are the cells' patches on their own T nodes (:meth:`_plane_coefficients`).
        """
        lv = np.log10(np.maximum(np.abs(v), self._vfloor))
        with np.errstate(divide="ignore", invalid="ignore"):
            lp = np.log10(p)
        t = np.stack([self._indices(0, lv), self._indices(1, T), self._indices(2, lp)])
        if not (np.minimum(t, self._nmax - t).min() >= 0.0):
            self._out_of_range(t, p)  # counts, refuses NaN, clamps t in place
        nT = self.axes["T"].size
        jT = np.minimum(np.trunc(t[1]), nT - 2)
        fT = t[1] - jT
        j = jT.astype(np.intp)
        Tn = self.axes["T"]
        Tq = Tn[j] + fT * (Tn[j + 1] - Tn[j])  # the (clamped) query temperature
        la_nodes = self.__dict__.get("_la_nodes")
        if la_nodes is None:
            la_nodes = self._la_nodes = self.log10_aT(Tn)
        la_q = self.log10_aT(Tq)
        ip = np.trunc(t[2])
        fp = t[2] - ip
        nmax_v = self._nmax[0, 0]
        vals = []
        inside = []
        for upper in (0, 1):
            # node jT + upper, read on its own patch (cell (iv, jT + upper, ip), fy = 0)
            tv = self._indices(0, lv + (la_q - la_nodes[j + upper]))
            inside.append((tv >= 0.0) & (tv <= nmax_v))
            np.clip(tv, 0.0, nmax_v, out=tv)
            iv = np.trunc(tv)
            cell = (iv * self._strides_f[0] + (jT + upper) * self._strides_f[1]
                    + ip * self._strides_f[2]).astype(np.intp)
            vals.append(self._evaluate_cells(Qp, n_names, degree, cell, tv - iv, None, fp,
                                             p_degree))
        # next to v_min the lower node's shifted speed falls below the v axis: the upper node
        # alone is read at the query's reduced speed (exact for the cold branch by TTS)
        w = np.where(inside[0], fT, 1.0)
        out = vals[0]
        out += w * (vals[1] - vals[0])
        fixed = ~inside[1]
        if fixed.any():
            # next to v_max (the upper node's shifted speed above the axis): across T at
            # fixed log10 v (a one-sided read there errs by up to 5 % on the hot branch)
            k = np.flatnonzero(fixed)
            iv = np.trunc(t[0, k])
            cell = (iv * self._strides_f[0] + jT[k] * self._strides_f[1]
                    + ip[k] * self._strides_f[2]).astype(np.intp)
            lo, hi = (self._evaluate_cells(Qp, n_names, degree, cell + int(u * self._strides_f[1]),
                                           t[0, k] - iv, None, fp[k], p_degree) for u in (0, 1))
            hi -= lo
            hi *= fT[k]
            hi += lo
            out[:, k] = hi
        return out

    @staticmethod
    def _evaluate_cells(Q: np.ndarray, n_names: int, degree: int, cell: np.ndarray,
                        fx: np.ndarray, fy: np.ndarray | None, fz: np.ndarray,
                        p_degree: int = 1) -> np.ndarray:
        """The cell polynomials of :meth:`_coefficients` at fractions (fx, fy, fz); with
        ``fy=None`` those of :meth:`_plane_coefficients` (no T term)."""
        k = degree + 1
        nb = 1 if fy is None else 2
        blk = nb * k
        c = Q.take(cell, axis=0).T.copy().reshape((p_degree + 1) * blk, n_names, cell.size)
        a = c[p_degree * blk:]  # c is a fresh copy: safe to update in place; Horner in fz
        for jj in range(p_degree - 1, -1, -1):
            a *= fz
            a += c[jj * blk:(jj + 1) * blk]
        if fy is not None:
            b = a[k:]
            b *= fy
            b += a[:k]
            a = b
        out = a[degree]  # Horner in fx
        for jj in range(degree - 1, -1, -1):
            out *= fx
            out += a[jj]
        return out

    # -- numpy-only persistence ---------------------------------------------------------------
    def save_npz(self, path: str | Path) -> Path:
        """Write the grid as a numpy ``.npz`` archive (what an FMU carries).

        The (deflate-compressed) archive holds the axes as float64 arrays, the variables as
        float32 where that is lossless (see :func:`storage_array`) and float64 otherwise, the
        units, and the metadata as a JSON string; :meth:`load_npz` validates all of it,
        including the hash (computed on the float64 values, so it does not depend on the
        storage type).
        """
        path = Path(path)
        units = {**AXIS_UNITS, **{n: VARIABLE_UNITS[n] for n in self.variables}}
        header = {"format": NPZ_FORMAT, "format_version": FORMAT_VERSION, "units": units,
                  "variables": list(self.variables), "meta": self.meta}
        arrays = {f"axis_{n}": self.axes[n] for n in AXES}
        arrays.update({f"var_{n}": storage_array(a) for n, a in self.variables.items()})
        header_arr = np.frombuffer(json.dumps(header, default=_json_default).encode(),
                                   dtype=np.uint8)
        with open(path, "wb") as fh:
            np.savez_compressed(fh, header_json=header_arr, **arrays)
        return path

    @classmethod
    def load_npz(cls, path: str | Path) -> FrictionGrid:
        """Read and validate a grid written by :meth:`save_npz`.

        Raises
        ------
        GridError
            Not a grid archive, truncated or corrupt, a missing array, missing units, or
            content that does not match the stored hash.
        """
        path = Path(path)
        src = str(path)
        if not path.is_file():
            raise GridError(f"{src}: no such grid file")
        try:
            with np.load(path, allow_pickle=False) as z:
                files = set(z.files)
                if "header_json" not in files:
                    raise GridError(f"{src}: not a tirefric grid archive (no header)")
                header = json.loads(z["header_json"].tobytes().decode())
                fmt = header.get("format") if isinstance(header, dict) else None
                if fmt != NPZ_FORMAT:
                    raise GridError(f"{src}: not a tirefric grid archive (format {fmt!r})")
                if header.get("format_version") != FORMAT_VERSION:
                    raise GridError(f"{src}: unsupported grid format version "
                                    f"{header.get('format_version')!r} (this reader: "
                                    f"{FORMAT_VERSION})")
                units = header.get("units", {})
                axes = {}
                for n in AXES:
                    if f"axis_{n}" not in files:
                        raise GridError(f"{src}: axis '{n}' is missing")
                    axes[n] = z[f"axis_{n}"]
                    if units.get(n) != AXIS_UNITS[n]:
                        raise GridError(f"{src}: axis '{n}' has units {units.get(n)!r}, "
                                        f"expected {AXIS_UNITS[n]!r}")
                variables = {}
                for n in header.get("variables", []):
                    if f"var_{n}" not in files:
                        raise GridError(f"{src}: variable '{n}' is missing")
                    if n in VARIABLE_UNITS and units.get(n) != VARIABLE_UNITS[n]:
                        raise GridError(f"{src}: variable '{n}' has units {units.get(n)!r}, "
                                        f"expected {VARIABLE_UNITS[n]!r}")
                    variables[n] = z[f"var_{n}"]
                meta = header.get("meta", {})
        except GridError:
            raise
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile,
                UnicodeDecodeError, zlib.error) as exc:
            raise GridError(f"{src}: corrupt or truncated grid archive "
                            f"({type(exc).__name__}: {exc})") from None
        if "hash" not in meta:
            raise GridError(f"{src}: metadata 'hash' is missing")
        return cls(axes["log10_v"], axes["T"], axes["log10_p"], variables, meta, source=src)


def storage_array(a: np.ndarray) -> np.ndarray:
    """``a`` as float32 if that loses nothing (values already rounded to float32), else as is.

    Grid builds round their results to float32 precision (relative 6e-8, far below the
    interpolation error), which halves the file size; reading converts back to float64 exactly.
    """
    a32 = a.astype(np.float32)
    return a32 if np.array_equal(a32.astype(np.float64), a) else a


def round_to_float32(a: np.ndarray) -> np.ndarray:
    """``a`` rounded to the nearest float32 values, returned as float64."""
    return np.asarray(a, dtype=np.float64).astype(np.float32).astype(np.float64)


def _json_default(obj: Any) -> Any:
    """JSON encoder for numpy scalars and arrays in metadata."""
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"metadata value of type {type(obj).__name__} is not JSON-able")
