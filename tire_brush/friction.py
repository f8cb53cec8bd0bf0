r"""Friction seen by a brush element: cold and hot branch, blended by eq. (28) of the review.

A tread element that slips with speed ``v`` at background temperature ``T0`` and nominal
pressure ``p`` after having slipped a distance ``s`` since it entered the footprint feels

.. math::  \mu = \mu_{cold}(v, T_0, p)\, e^{-s/s_0} + \mu_{hot}(v, T_0, p)\,(1 - e^{-s/s_0})

(review eq. 28; docs/review-notes.md), with ``s0 ~ 0.2 D``, D the macroasperity contact diameter.

Friction providers follow the small protocol :class:`FrictionModel` (``branches``, ``s0``,
``describe``). Adapters:

* :class:`ConstantFriction` -- constant branches (``mu_cold = mu_hot`` for Pacejka's constant-
  friction brush; ``mu_cold != mu_hot`` for flat two-branch checks);
  :meth:`ConstantFriction.static_kinetic` is the static/kinetic law: eq. (28) with
  ``s0 -> 0``, ``mu_cold = mu_s``, ``mu_hot = mu_k`` gives ``mu_s`` until an element has
  slipped at all and ``mu_k`` afterwards;
* :class:`GridFriction` -- a :class:`lookup.grid.FrictionGrid` (Persson cold and hot tables).

The brush model evaluates friction through :class:`BranchTable`, a multilinear table on
(log10 v, T, log10 p) built once from the provider (for a grid: its own nodes, so the table
reproduces the grid's interpolation exactly). The compiled tire core takes its node values
(:mod:`tire_brush.ccore`) and interpolates them itself, with the same clamping
(docs/tire-core.md); :meth:`BranchTable.evaluate` is the general evaluation in numpy.

Out of range (explicit, never NaN): speeds below the first node (including v = 0, a sticking
element) are read at the first node, the table's low-speed limit; speeds above the last node,
temperatures and pressures outside their axes are clamped to the axis ends. Pressures near the
footprint edges fall below any grid's pressure axis; there the friction is read at the lowest
tabulated pressure (the stress it produces vanishes with p).

This module imports only numpy and the standard library: it runs inside an FMU.
"""

from __future__ import annotations

import math
import weakref
from typing import Any, Protocol, runtime_checkable

import numpy as np

from tirefric.errors import InputError

#: Default blending length s0 [m] of :class:`ConstantFriction`: 0.2 D with D = 1 mm
#: (review sec. 5.1: macroasperity contacts of ~1 mm on road surfaces).
S0_DEFAULT = 2e-4
#: Largest inverse blending length used for s0 -> 0 [1/m]: any slip above 1e-100 m counts as
#: fully developed; keeps ``s / s0`` finite for s0 = 0.
_INV_S0_MAX = 1e100

#: Nodes used to tabulate a provider that does not name its own (log10 v [m/s], T [K],
#: log10 p [Pa]): 20 per decade from 1e-8 to 1e2 m/s, 5 K from -40 to 150 C, 10 per decade
#: from 10 kPa to 10 MPa.
DEFAULT_NODES = (np.linspace(-8.0, 2.0, 201), np.linspace(233.15, 423.15, 39),
                 np.linspace(4.0, 7.0, 31))
#: Tables built from a grid object, by s0 (:meth:`BranchTable.from_model`).
_SHARED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def inverse_blend_length(s0: float) -> float:
    """``1 / s0`` [1/m] for eq. (28), with the limits s0 = 0 (hot as soon as an element slips)
    and s0 = inf (always cold)."""
    if not s0 >= 0:
        raise InputError("the blending length s0 must be >= 0 m (inf allowed)", field="s0",
                         value=s0)
    if s0 == math.inf:
        return 0.0
    return min(1.0 / s0, _INV_S0_MAX) if s0 > 0 else _INV_S0_MAX


def cold_weight(s: Any, s0: float) -> np.ndarray:
    """Weight ``exp(-s/s0)`` of the cold branch in eq. (28) for slipped distance ``s`` [m].

    ``s0 = 0`` gives 1 at ``s = 0`` and 0 for any ``s > 0``; ``s0 = inf`` gives 1.
    """
    return np.exp(-np.asarray(s, dtype=float) * inverse_blend_length(s0))


def blend(mu_cold: Any, mu_hot: Any, s: Any, s0: float) -> np.ndarray:
    """Review eq. (28): ``mu_cold exp(-s/s0) + mu_hot (1 - exp(-s/s0))``."""
    w = cold_weight(s, s0)
    return np.asarray(mu_hot, float) + (np.asarray(mu_cold, float) - mu_hot) * w


@runtime_checkable
class FrictionModel(Protocol):
    """What the brush model needs from a friction provider."""

    @property
    def s0(self) -> float:
        """Blending slip length of eq. (28) [m]."""
        ...

    def branches(self, v: Any, T: Any, p: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(mu_cold, mu_hot, dT_flash)`` at slip speed ``v`` [m/s], background temperature
        ``T`` [K] and nominal pressure ``p`` [Pa] (numpy broadcasting); ``dT_flash`` [K] is the
        flash-temperature rise of the hot branch."""
        ...

    def describe(self) -> dict:
        """JSON-able description (for provenance of results)."""
        ...


class ConstantFriction:
    """Constant cold and hot branches (no dependence on v, T, p).

    Parameters
    ----------
    mu_cold
        Friction coefficient of the cold branch [1].
    mu_hot
        Friction coefficient of the hot branch [1]; default ``mu_cold`` (Pacejka's constant
        friction).
    s0
        Blending length of eq. (28) [m], ``0 <= s0 <= inf``.
    dT_flash
        Flash temperature rise reported for the hot branch [K].
    """

    def __init__(self, mu_cold: float, mu_hot: float | None = None, *, s0: float = S0_DEFAULT,
                 dT_flash: float = 0.0) -> None:
        mu_hot = mu_cold if mu_hot is None else mu_hot
        for name, val in (("mu_cold", mu_cold), ("mu_hot", mu_hot), ("dT_flash", dT_flash)):
            if not (math.isfinite(val) and val >= 0):
                raise InputError("must be a finite number >= 0", field=name, value=val)
        inverse_blend_length(s0)
        self.mu_cold = float(mu_cold)
        self.mu_hot = float(mu_hot)
        self.dT_flash = float(dT_flash)
        self._s0 = float(s0)

    @classmethod
    def static_kinetic(cls, mu_s: float, mu_k: float) -> ConstantFriction:
        """Static ``mu_s`` until an element slips, kinetic ``mu_k`` after: eq. (28) with
        ``s0 -> 0`` (the law behind the static/kinetic brush of Pacejka 2012, sec. 3.2)."""
        return cls(mu_s, mu_k, s0=0.0)

    @property
    def s0(self) -> float:
        """Blending length of eq. (28) [m]."""
        return self._s0

    def branches(self, v: Any, T: Any, p: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Constant ``(mu_cold, mu_hot, dT_flash)`` of the broadcast shape of the inputs."""
        shape = np.broadcast_shapes(np.shape(v), np.shape(T), np.shape(p))
        return (np.full(shape, self.mu_cold), np.full(shape, self.mu_hot),
                np.full(shape, self.dT_flash))

    def table_nodes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Two nodes per axis suffice for constant branches."""
        return np.array([-8.0, 2.0]), np.array([200.0, 500.0]), np.array([3.0, 8.0])

    def describe(self) -> dict:
        """Kind, branch values and s0."""
        return {"kind": "constant", "mu_cold": self.mu_cold, "mu_hot": self.mu_hot,
                "dT_flash_K": self.dT_flash, "s0_m": self._s0}


class GridFriction:
    """Cold and hot branches from a friction grid (:class:`lookup.grid.FrictionGrid`).

    Parameters
    ----------
    grid
        The grid (duck-typed: ``interpolate``, ``axes``, ``__getitem__``, ``meta``).
    s0
        Blending length of eq. (28) [m]; default the grid's ``meta["s0_m"]`` (0.2 D of its
        surface).
    """

    def __init__(self, grid: Any, *, s0: float | None = None) -> None:
        self.grid = grid
        self._s0 = float(grid.meta["s0_m"]) if s0 is None else float(s0)
        inverse_blend_length(self._s0)

    @property
    def s0(self) -> float:
        """Blending length of eq. (28) [m]."""
        return self._s0

    def branches(self, v: Any, T: Any, p: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Grid interpolation of ``mu_cold``, ``mu_hot``, ``dT_flash`` (grid's clamping)."""
        out = self.grid.interpolate(v, T, p, ("mu_cold", "mu_hot", "dT_flash"))
        return out["mu_cold"], out["mu_hot"], out["dT_flash"]

    def table_nodes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The grid's own axes (log10 v, T, log10 p)."""
        ax = self.grid.axes
        return ax["log10_v"], ax["T"], ax["log10_p"]

    def node_values(self) -> np.ndarray:
        """Node values, shape ``(nv, nT, np, 3)`` for (mu_cold, mu_hot, dT_flash)."""
        return np.stack([self.grid[n] for n in ("mu_cold", "mu_hot", "dT_flash")], axis=-1)

    def describe(self) -> dict:
        """Kind, the grid's hash and provenance keys, and s0."""
        meta = {k: v for k, v in self.grid.meta.items() if isinstance(v, str | int | float)}
        return {"kind": "grid", "s0_m": self._s0, "grid": meta}


def _axis_index(axis: np.ndarray) -> tuple[bool, float, float]:
    """(uniform?, first node, inverse spacing) of an ascending axis."""
    d = np.diff(axis)
    uniform = bool(np.all(np.abs(d - d.mean()) <= 1e-9 * abs(d.mean())))
    return uniform, float(axis[0]), float((axis.size - 1) / (axis[-1] - axis[0]))


class BranchTable:
    """Multilinear table of ``(mu_cold, mu_hot, dT_flash)`` on (log10 v, T, log10 p).

    Build it with :meth:`from_model`. Evaluation is trilinear in the nested monomial form of
    the grid reader (:meth:`lookup.grid.reader.FrictionGrid.interpolate`), with the clamping
    described in the module docstring.

    Parameters
    ----------
    log10_v, T, log10_p
        Ascending axes (at least two nodes each).
    values
        Node values, shape ``(nv, nT, np, 3)``: mu_cold, mu_hot [1], dT_flash [K].
    s0
        Blending length of eq. (28) [m].
    description
        Provenance of the table (the provider's ``describe()``).
    """

    def __init__(self, log10_v: np.ndarray, T: np.ndarray, log10_p: np.ndarray,
                 values: np.ndarray, s0: float, description: dict | None = None) -> None:
        axes = [np.asarray(a, dtype=float) for a in (log10_v, T, log10_p)]
        for name, a in zip(("log10_v", "T", "log10_p"), axes, strict=True):
            if a.ndim != 1 or a.size < 2 or not np.isfinite(a).all() or not (
                    np.diff(a) > 0).all():
                raise InputError("friction table axis must hold >= 2 finite, strictly "
                                 "ascending nodes", field=name, value=a.tolist())
        values = np.asarray(values, dtype=float)
        shape = (axes[0].size, axes[1].size, axes[2].size, 3)
        if values.shape != shape:
            raise InputError(f"friction table values must have shape {shape}",
                             field="values", value=values.shape)
        if not np.isfinite(values).all():
            raise InputError("friction table values must be finite", field="values")
        self.log10_v, self.T, self.log10_p = axes
        self.values = values
        self.s0 = float(s0)
        self.inv_s0 = inverse_blend_length(self.s0)
        self.description = dict(description or {})
        self.v_floor = float(10.0 ** self.log10_v[0])
        self.p_floor = float(10.0 ** self.log10_p[0])
        nv, nT, np_ = shape[:3]
        self._n = (nv - 1.0, nT - 1.0, np_ - 1.0)
        self._ax = [_axis_index(a) for a in axes]
        self._stride_v = nT * np_
        self._stride_T = np_
        self._QT_cache: np.ndarray | None = None  # _monomials(), on the first evaluation

    def _monomials(self) -> np.ndarray:
        """The cells' monomial coefficients, shape ``(n_cells, 24)``, computed on the first
        evaluation in Python (a table that only feeds the compiled core, e.g. one of the
        wet friction's per-point blends, never needs them)."""
        if self._QT_cache is not None:
            return self._QT_cache
        # monomial coefficients of every cell (one per node; the last node's cells reach into
        # an edge-padded layer and are used with fraction 0 only), read as (8, 3, n_cells)
        nv, nT, np_ = self.values.shape[:3]
        V = np.pad(self.values, ((0, 1), (0, 1), (0, 1), (0, 0)), mode="edge")

        def c(a: int, b: int, d: int) -> np.ndarray:
            return V[a:a + nv, b:b + nT, d:d + np_, :]

        coef = (c(0, 0, 0), c(1, 0, 0) - c(0, 0, 0), c(0, 1, 0) - c(0, 0, 0),
                c(1, 1, 0) - c(1, 0, 0) - c(0, 1, 0) + c(0, 0, 0),
                c(0, 0, 1) - c(0, 0, 0), c(1, 0, 1) - c(1, 0, 0) - c(0, 0, 1) + c(0, 0, 0),
                c(0, 1, 1) - c(0, 1, 0) - c(0, 0, 1) + c(0, 0, 0),
                c(1, 1, 1) - c(1, 1, 0) - c(1, 0, 1) - c(0, 1, 1) + c(1, 0, 0) + c(0, 1, 0)
                + c(0, 0, 1) - c(0, 0, 0))
        Q = np.empty((8, 3, nv * nT * np_))
        for k, ck in enumerate(coef):
            Q[k] = ck.reshape(-1, 3).T
        # stored cell by cell, shape (n_cells, 24): a look-up gathers one contiguous row of
        # 24 coefficients per element (the (24, n_cells) layout touches 24 rows spread over
        # the whole table: 100 cells of the default grid took ~2.2 us to gather against
        # ~0.7 us, plus ~0.9 us to transpose the gathered rows)
        self._QT_cache = np.ascontiguousarray(Q.reshape(24, -1).T)
        return self._QT_cache

    @classmethod
    def from_model(cls, model: FrictionModel) -> BranchTable:
        """Tabulate a friction provider.

        Uses the provider's ``table_nodes()`` if it has one (a grid's own axes: exact), else
        :data:`DEFAULT_NODES`; node values come from ``node_values()`` if the provider has it,
        else from one call of ``branches`` on the node mesh. Tables of one grid object and one
        s0 are built once and shared (several tires on one grid, e.g. four FMU instances):
        a table is immutable apart from a cache that is a pure function of its inputs.
        """
        if isinstance(model, BranchTable):
            return model
        grid = getattr(model, "grid", None)
        if grid is not None:
            try:
                shared = _SHARED.setdefault(grid, {})
            except TypeError:                         # not weak-referenceable: no sharing
                shared = {}
            table = shared.get(model.s0)
            if table is None:
                table = shared[model.s0] = cls._tabulate(model)
            return table
        return cls._tabulate(model)

    @classmethod
    def _tabulate(cls, model: FrictionModel) -> BranchTable:
        """Build the table of :meth:`from_model` (no sharing)."""
        nodes = model.table_nodes() if hasattr(model, "table_nodes") else DEFAULT_NODES
        lv, T, lp = (np.asarray(a, dtype=float) for a in nodes)
        if hasattr(model, "node_values"):
            values = model.node_values()
        else:
            V, TT, P = np.meshgrid(10.0 ** lv, T, 10.0 ** lp, indexing="ij")
            values = np.stack(model.branches(V, TT, P), axis=-1)
        return cls(lv, T, lp, values, model.s0, model.describe())

    def describe(self) -> dict:
        """The provider's description."""
        return dict(self.description)

    # -- evaluation -----------------------------------------------------------------------------
    def _t(self, k: int, x: np.ndarray | float) -> np.ndarray | float:
        """Fractional node index of ``x`` on axis ``k``, clamped to the axis."""
        uniform, lo, inv = self._ax[k]
        if isinstance(x, float):
            if uniform:
                t = (x - lo) * inv
            else:
                axis = (self.log10_v, self.T, self.log10_p)[k]
                t = float(np.interp(x, axis, np.arange(axis.size, dtype=float)))
            return min(max(t, 0.0), self._n[k])
        if uniform:
            t = x - lo
            t *= inv
        else:
            axis = (self.log10_v, self.T, self.log10_p)[k]
            t = np.interp(x, axis, np.arange(axis.size, dtype=float))
        np.maximum(t, 0.0, out=t)
        np.minimum(t, self._n[k], out=t)
        return t

    def _cells(self, cell: np.ndarray) -> np.ndarray:
        """Monomial coefficients of the cells ``cell`` (flat indices, any shape), shape
        ``(8, 3, *cell.shape)``."""
        return self._monomials().take(cell.ravel(), axis=0).T.copy().reshape(8, 3, *cell.shape)

    def evaluate(self, v: Any, T: Any, p: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """General evaluation with numpy broadcasting: ``(mu_cold, mu_hot, dT_flash)``."""
        v, T, p = np.broadcast_arrays(np.asarray(v, float), np.asarray(T, float),
                                      np.asarray(p, float))
        shape = v.shape
        v, T, p = v.ravel(), T.ravel(), p.ravel()
        if np.isnan(v).any() or np.isnan(T).any() or np.isnan(p).any():
            raise InputError("friction queried at NaN (v, T and p must be numbers)")
        tv = self._t(0, np.log10(np.maximum(np.abs(v), self.v_floor)))
        tT = self._t(1, T.copy())
        tp = self._t(2, np.log10(np.maximum(p, self.p_floor)))
        iv, iT, ip = tv.astype(np.intp), tT.astype(np.intp), tp.astype(np.intp)
        fv, fT, fp = tv - iv, tT - iT, tp - ip
        cell = iv * self._stride_v + iT * self._stride_T + ip
        c = self._cells(cell)
        a = c[4:8] * fp + c[0:4]
        b = a[2:4] * fT + a[0:2]
        out = b[1] * fv + b[0]
        return out[0].reshape(shape), out[1].reshape(shape), out[2].reshape(shape)

    def branches(self, v: Any, T: Any, p: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Alias of :meth:`evaluate` (a table is itself a :class:`FrictionModel`)."""
        return self.evaluate(v, T, p)


def as_table(friction: FrictionModel | BranchTable | Any) -> BranchTable:
    """A :class:`BranchTable` for ``friction``: a table, a provider, or a
    :class:`lookup.grid.FrictionGrid` (wrapped in :class:`GridFriction`)."""
    if isinstance(friction, BranchTable):
        return friction
    if hasattr(friction, "interpolate") and hasattr(friction, "axes"):
        friction = GridFriction(friction)
    if not isinstance(friction, FrictionModel):
        raise InputError("not a friction provider (needs branches(v, T, p), s0 and "
                         "describe())", field="friction", value=type(friction).__name__)
    return BranchTable.from_model(friction)
