"""Steady-state force map ``Fx/Fz(kappa, vx, Fz, T)`` as a smooth, differentiable CasADi function.

Any friction source with the signature ``fx_over_fz(kappa, vx, Fz, T_K) -> ndarray`` (numpy
broadcasting; the brush tire's steady state, or a curve of :mod:`.reference`) is tabulated on
a tensor grid and interpolated by a tensor-product B-spline:

* per axis, scipy's ``make_interp_spline`` (not-a-knot end conditions, degree 3 unless the axis
  is too short) gives the knot vector and the collocation solve; applying it along each axis
  in turn gives the tensor coefficient array ``c[i, j, k, l]`` such that
  ``sum c B_i(kappa) B_j(log10 vx) B_k(Fz) B_l(T) = Fx/Fz`` at every node (de Boor,
  *A Practical Guide to Splines*, 2001, ch. XVII, tensor-product interpolation);
* the knots and the coefficients (flattened in Fortran order, the first axis fastest, as
  CasADi's ``BSpline`` node expects) go to ``casadi.Function.bspline``. This is exact and
  fast; ``casadi.interpolant(..., 'bspline')`` fits its own coefficients and becomes slow and
  memory-hungry beyond ~1e4 nodes (measured).

The speed axis is stored and interpolated as ``log10(vx)`` (``docs/design.md``, "Units").
An axis with a single node is a constant: the map does not depend on that input.

Out of range: every input is clamped to its axis range (CasADi and numpy evaluation alike), so
the map extends as a constant beyond its edges and its derivative there is zero. Studies keep
their operating points inside the axes (the OCP bounds ``kappa`` to the map's range).
"""

from __future__ import annotations

import bisect
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tirefric.errors import InputError

#: A friction source: ``fx_over_fz(kappa, vx, Fz, T_K) -> Fx/Fz`` with numpy broadcasting.
FxOverFz = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: Input names in call order, and the units of the axes (speed axis stored as log10).
INPUTS = ("kappa", "vx", "Fz", "T_K")
UNITS = {"kappa": "1", "vx": "m/s", "Fz": "N", "T_K": "K"}


def _validate_axis(name: str, values, *, positive: bool = False) -> np.ndarray:
    a = np.asarray(values, dtype=float).ravel()
    if a.size == 0:
        raise InputError("axis is empty", field=name)
    bad = ~np.isfinite(a)
    if bad.any():
        raise InputError(f"entry {int(np.flatnonzero(bad)[0])} is not finite", field=name,
                         value=a.tolist())
    if positive and (a <= 0).any():
        raise InputError("entries must be > 0", field=name, value=a.tolist())
    if a.size > 1 and not (np.diff(a) > 0).all():
        i = int(np.flatnonzero(np.diff(a) <= 0)[0]) + 1
        raise InputError(f"the points in axis '{name}' must be strictly ascending "
                         f"(entry {i} = {a[i]!r} follows {a[i - 1]!r})", field=name)
    return a


def tensor_bspline_coefficients(
    axes: list[np.ndarray], values: np.ndarray, degrees: list[int]
) -> tuple[list[np.ndarray], np.ndarray]:
    """Knots and coefficients of the tensor-product B-spline interpolating ``values``.

    Parameters
    ----------
    axes
        Strictly ascending node coordinates per dimension, each of length >= 2.
    values
        Node values, shape ``tuple(len(a) for a in axes)`` (``indexing='ij'``).
    degrees
        Spline degree per dimension, ``1 <= k < len(axis)``.

    Returns
    -------
    knots, coefficients
        One knot vector per dimension and the coefficient array (same shape as ``values``,
        C order). Flatten with ``order='F'`` for CasADi.

    Notes
    -----
    Interpolation along one axis is a linear solve with that axis' collocation matrix, and the
    tensor-product system is the Kronecker product of those, so solving axis by axis gives the
    exact tensor coefficients (de Boor 2001, ch. XVII).
    """
    from scipy.interpolate import make_interp_spline

    coeffs = np.asarray(values, dtype=float)
    knots = []
    for i, (x, k) in enumerate(zip(axes, degrees, strict=True)):
        spl = make_interp_spline(x, coeffs, k=k, axis=i)
        # scipy returns the coefficients with the interpolation axis first
        coeffs = np.moveaxis(spl.c, 0, i)
        knots.append(np.asarray(spl.t, dtype=float))
    return knots, np.ascontiguousarray(coeffs)


@dataclass(frozen=True)
class ForceMap:
    """Tabulated ``Fx/Fz`` on (kappa, log10 vx, Fz, T) with its tensor B-spline.

    Build with :meth:`build`. Calling the map evaluates the spline with numpy/scipy
    (broadcasting, same signature as the source); :meth:`casadi_function` gives the CasADi
    function.

    Attributes
    ----------
    axes : dict
        Node coordinates per input: ``kappa`` [1], ``vx`` [m/s], ``Fz`` [N], ``T_K`` [K].
    values : numpy.ndarray
        Tabulated ``Fx/Fz`` [1], shape of the axes (``indexing='ij'``).
    degree : int
        Requested spline degree (an axis with n nodes uses ``min(degree, n - 1)``).
    build_time_s : float
        Wall time of the tabulation and the fit [s].
    label : str
        Provenance of the source (e.g. the friction curve or tire/grid names).
    """

    axes: dict[str, np.ndarray]
    values: np.ndarray
    degree: int
    knots: tuple[np.ndarray, ...] = field(repr=False)
    coefficients: np.ndarray = field(repr=False)
    active: tuple[str, ...] = ()
    build_time_s: float = 0.0
    label: str = ""

    @classmethod
    def build(cls, fx_over_fz: FxOverFz, *, kappa, vx, Fz, T_K, degree: int = 3,
              label: str = "") -> ForceMap:
        """Tabulate ``fx_over_fz`` on the tensor grid of the axes and fit the B-spline.

        Parameters
        ----------
        fx_over_fz
            Friction source, ``fx_over_fz(kappa, vx, Fz, T_K) -> Fx/Fz`` broadcasting.
        kappa, vx, Fz, T_K
            Strictly ascending axes: slip [1] (at least 2 nodes), speed [m/s] (> 0; stored as
            log10), load [N], temperature [K]. An axis with one node is a constant.
        degree
            Spline degree, 1 to 5 (3: cubic, C2-smooth, what the NLP solver wants).
        label
            Provenance text carried along.
        """
        t0 = time.perf_counter()
        if not 1 <= degree <= 5:
            raise InputError("spline degree must be 1 to 5", field="degree", value=degree)
        axes = {
            "kappa": _validate_axis("kappa", kappa),
            "vx": _validate_axis("vx", vx, positive=True),
            "Fz": _validate_axis("Fz", Fz),
            "T_K": _validate_axis("T_K", T_K, positive=True),
        }
        if axes["kappa"].size < 2:
            raise InputError("the slip axis needs at least 2 nodes", field="kappa",
                             value=axes["kappa"].tolist())
        grids = np.meshgrid(*axes.values(), indexing="ij")
        shape = grids[0].shape
        values = np.asarray(fx_over_fz(*grids), dtype=float)
        if values.shape != shape:
            raise InputError(f"friction source returned shape {values.shape}, expected "
                             f"{shape} (it must broadcast like numpy)", field="fx_over_fz")
        bad = ~np.isfinite(values)
        if bad.any():
            idx = np.unravel_index(int(np.flatnonzero(bad)[0]), shape)
            point = {n: float(a[i]) for (n, a), i in zip(axes.items(), idx, strict=True)}
            raise InputError(f"friction source gave {int(bad.sum())} non-finite value(s), "
                             f"first at {point}", field="fx_over_fz")
        active = tuple(n for n, a in axes.items() if a.size > 1)
        active_idx = [INPUTS.index(n) for n in active]
        squeezed = values.reshape([shape[i] for i in active_idx])
        coords = [cls._coord(n, axes[n]) for n in active]
        degrees = [min(degree, axes[n].size - 1) for n in active]
        knots, coeffs = tensor_bspline_coefficients(coords, squeezed, degrees)
        return cls(axes=axes, values=values, degree=degree, knots=tuple(knots),
                   coefficients=coeffs, active=active,
                   build_time_s=time.perf_counter() - t0, label=label)

    # -- coordinates ----------------------------------------------------------------------------
    @staticmethod
    def _coord(name: str, x):
        """Spline coordinate of input ``name``: log10 for the speed, identity otherwise."""
        return np.log10(x) if name == "vx" else x

    @property
    def degrees(self) -> tuple[int, ...]:
        """Spline degree per active axis."""
        return tuple(min(self.degree, self.axes[n].size - 1) for n in self.active)

    @property
    def n_nodes(self) -> int:
        """Number of tabulated points."""
        return int(self.values.size)

    def bounds(self, name: str) -> tuple[float, float]:
        """Range ``(lo, hi)`` of an input's axis in its SI unit."""
        a = self.axes[name]
        return float(a[0]), float(a[-1])

    def fixed(self, **values: float) -> ForceMap:
        """The map with inputs held at fixed values (e.g. ``fixed(Fz=4413.0)``): exact.

        A tensor B-spline at a fixed coordinate ``x`` of one axis is the spline of the other
        axes whose coefficients are contracted with that axis' basis functions at ``x``
        (``c'_{..} = sum_j c_{..j..} B_j(x)``), so the result equals the full map wherever
        the fixed input takes its value (to rounding). The value is clamped to the axis as
        the map's evaluation does. An OCP at a fixed load evaluates a cubic spline of
        ``4^3`` instead of ``4^4`` coefficients per point (``4^2`` when the temperature is
        fixed too). ``values`` of the result are the spline at the remaining nodes.
        """
        from scipy.interpolate import BSpline

        unknown = set(values) - set(INPUTS)
        if unknown:
            raise InputError(f"no input(s) {sorted(unknown)}; inputs are {INPUTS}",
                             field="fixed", value=sorted(unknown))
        coeffs = self.coefficients
        knots, active, degrees = list(self.knots), list(self.active), list(self.degrees)
        axes = dict(self.axes)
        for name, val in values.items():
            lo, hi = self.bounds(name)
            x = min(max(float(val), lo), hi)
            axes[name] = np.array([x])
            if name not in active:
                continue
            i = active.index(name)
            xc = float(self._coord(name, x))
            basis = BSpline.design_matrix(np.array([xc]), knots[i], degrees[i]).toarray()[0]
            coeffs = np.tensordot(coeffs, basis, axes=([i], [0]))
            del knots[i], active[i], degrees[i]
        if "kappa" not in active:
            raise InputError("the slip cannot be fixed", field="fixed", value="kappa")
        out = ForceMap(axes=axes, values=np.empty(0), degree=self.degree, knots=tuple(knots),
                       coefficients=np.ascontiguousarray(coeffs), active=tuple(active),
                       build_time_s=self.build_time_s, label=self.label)
        grids = np.meshgrid(*axes.values(), indexing="ij")
        object.__setattr__(out, "values", out(*grids))
        return out

    # -- numpy evaluation -----------------------------------------------------------------------
    def __call__(self, kappa, vx, Fz, T_K) -> np.ndarray:
        """``Fx/Fz`` [1] from the spline (inputs clamped to the axes), numpy broadcasting."""
        args = (kappa, vx, Fz, T_K)
        shape = np.broadcast_shapes(*(np.shape(a) for a in args))
        xi = np.empty((*shape, len(self.active)))
        # the spline coordinates, clamped to the axes (a lean loop: simulations call this
        # with a handful of points per step)
        for j, (i, lo, hi, log) in enumerate(self._clamps()):
            x = np.minimum(np.maximum(np.asarray(args[i], dtype=float), lo), hi)
            xi[..., j] = np.log10(x) if log else x
        return self._ndbspline()(xi.reshape(-1, len(self.active))).reshape(shape)

    def _clamps(self) -> tuple[tuple[int, float, float, bool], ...]:
        """Per active axis: input position, range and whether its coordinate is log10."""
        cache = self.__dict__.get("_clamp_cache")
        if cache is None:
            cache = tuple((INPUTS.index(n), *self.bounds(n), n == "vx") for n in self.active)
            object.__setattr__(self, "_clamp_cache", cache)
        return cache

    def on_grid(self, kappa, vx, Fz, T_K) -> np.ndarray:
        """``Fx/Fz`` [1] on the tensor grid of four 1-D coordinate arrays (inputs clamped to the
        axes), shape ``(len(kappa), len(vx), len(Fz), len(T_K))``.

        The same spline as :meth:`__call__`, evaluated through one basis (design) matrix per
        axis: the coefficient array is contracted with each axis' matrix in turn (de Boor
        2001, ch. XVII), which costs a few matrix products instead of ``4^k`` coefficients per
        grid point. An input whose axis is a single node (inactive) only sets the length of
        its dimension.
        """
        from scipy.interpolate import BSpline

        pts = {n: np.atleast_1d(np.asarray(a, dtype=float)).ravel()
               for n, a in zip(INPUTS, (kappa, vx, Fz, T_K), strict=True)}
        out = self.coefficients
        for i, name in enumerate(self.active):
            lo, hi = self.bounds(name)
            x = self._coord(name, np.clip(pts[name], lo, hi))
            basis = BSpline.design_matrix(x, self.knots[i], self.degrees[i]).toarray()
            out = np.moveaxis(np.tensordot(out, basis, axes=([i], [1])), -1, i)
        shape = tuple(pts[n].size for n in INPUTS)
        expanded = [slice(None) if n in self.active else np.newaxis for n in INPUTS]
        return np.broadcast_to(out[tuple(expanded)], shape).copy()

    def point_evaluator(self, backend: str = "c") -> PointEvaluator | CompiledPointEvaluator:
        """The map as a function of one point (Python floats in and out): the same spline as
        :meth:`__call__`, equal to it to rounding, for callers that evaluate one point at a
        time. ``backend``: ``"c"`` the compiled tire core's reader
        (:class:`CompiledPointEvaluator`, ~1 us per point), ``"python"`` its readable
        reference (:class:`PointEvaluator`, ~10 us per point)."""
        if backend == "c":
            return CompiledPointEvaluator(self)
        if backend == "python":
            return PointEvaluator(self)
        raise InputError("must be 'c' or 'python'", field="backend", value=backend)

    def _ndbspline(self):
        cache = self.__dict__.get("_nd_cache")
        if cache is None:
            from scipy.interpolate import NdBSpline

            cache = NdBSpline(self.knots, self.coefficients, self.degrees, extrapolate=False)
            object.__setattr__(self, "_nd_cache", cache)
        return cache

    # -- CasADi ---------------------------------------------------------------------------------
    def casadi_bspline(self):
        """The bare ``casadi.Function.bspline`` over the active spline coordinates.

        Input: one column vector of the active coordinates (``log10 vx`` for the speed),
        output ``Fx/Fz``. No clamping (used by the tests against scipy).
        """
        import casadi as ca

        return ca.Function.bspline(
            "fx_over_fz_bspline", [k.tolist() for k in self.knots],
            self.coefficients.ravel(order="F").tolist(), list(self.degrees), 1, {})

    def casadi_function(self, name: str = "fx_over_fz"):
        """CasADi function ``(kappa, vx, Fz, T_K) -> Fx/Fz`` (scalars), inputs clamped to the axes.

        Smooth (C^(degree-1)) inside the axes, with first and second derivatives for the NLP
        solver. Evaluate it on many points at once with ``.map(n)``.
        """
        import casadi as ca

        bs = self.casadi_bspline()
        syms = [ca.MX.sym(n) for n in INPUTS]
        coords = []
        for n in self.active:
            lo, hi = self.bounds(n)
            x = ca.fmin(ca.fmax(syms[INPUTS.index(n)], lo), hi)
            coords.append(ca.log10(x) if n == "vx" else x)
        return ca.Function(name, syms, [bs(ca.vertcat(*coords))], list(INPUTS), ["fx_over_fz"])


class PointEvaluator:
    """A :class:`ForceMap` evaluated at one point at a time, ``f(kappa, vx, Fz, T_K) ->
    float``.

    The tensor B-spline of the map at a point is ``sum c[i, j, ..] B_i(x_1) B_j(x_2) ..``
    over the ``k + 1`` basis functions per axis that do not vanish there (de Boor, *A
    Practical Guide to Splines*, 2001, ch. X: the knot span by bisection, the values by the
    recurrence of de Boor's routine BSPLVB, ch. X); the coefficient block of those is
    contracted with the basis vectors axis by axis. Inputs are clamped to the axes as in
    :meth:`ForceMap.__call__`. It computes what ``ForceMap.__call__`` computes, with the
    floating-point operations in another order, so the two agree to rounding
    (tests/test_braking_force_map.py), and costs about a third to a half of it per point (no array
    set-up: a simulation step evaluates one point three times).
    """

    def __init__(self, fmap: ForceMap) -> None:
        self._axes = []
        for i, name in enumerate(fmap.active):
            t = [float(x) for x in fmap.knots[i]]
            k = fmap.degrees[i]
            lo, hi = fmap.bounds(name)
            self._axes.append((INPUTS.index(name), lo, hi, name == "vx", t, k, len(t) - k - 1))
        self._c = fmap.coefficients
        self._last: list[tuple] = [(math.nan, 0, [])] * len(self._axes)
        self.axes = fmap.axes

    @staticmethod
    def _basis(t: list[float], k: int, n: int, x: float) -> tuple[int, list[float]]:
        """First index and values of the ``k + 1`` B-splines of degree ``k`` nonzero at ``x``
        (knots ``t``, ``n`` coefficients; ``t[k] <= x <= t[n]``): de Boor's recurrence,
        written out for the cubic."""
        m = min(max(bisect.bisect_right(t, x) - 1, k), n - 1)
        if k == 3:
            tr1, tr2, tr3 = t[m + 1] - x, t[m + 2] - x, t[m + 3] - x
            tl1, tl2, tl3 = x - t[m], x - t[m - 1], x - t[m - 2]
            temp = 1.0 / (tr1 + tl1)
            a0, a1 = tr1 * temp, tl1 * temp
            temp = a0 / (tr1 + tl2)
            b0, saved = tr1 * temp, tl2 * temp
            temp = a1 / (tr2 + tl1)
            b1, b2 = saved + tr2 * temp, tl1 * temp
            temp = b0 / (tr1 + tl3)
            c0, saved = tr1 * temp, tl3 * temp
            temp = b1 / (tr2 + tl2)
            c1, saved = saved + tr2 * temp, tl2 * temp
            temp = b2 / (tr3 + tl1)
            return m - 3, [c0, c1, saved + tr3 * temp, tl1 * temp]
        b = [1.0]
        for j in range(1, k + 1):
            saved = 0.0
            nxt = []
            for r in range(j):
                right = t[m + r + 1] - x
                left = x - t[m + r + 1 - j]
                temp = b[r] / (right + left)
                nxt.append(saved + right * temp)
                saved = left * temp
            nxt.append(saved)
            b = nxt
        return m - k, b

    def __call__(self, kappa: float, vx: float, Fz: float, T_K: float) -> float:
        """``Fx/Fz`` [1] at one point (scalars; inputs clamped to the axes)."""
        args = (kappa, vx, Fz, T_K)
        block = []
        bases = []
        last = self._last
        for j, (i, lo, hi, log, t, k, n) in enumerate(self._axes):
            x = min(max(float(args[i]), lo), hi)
            if log:
                x = math.log10(x)
            if last[j][0] != x:          # a simulation step asks twice at one speed
                last[j] = (x, *self._basis(t, k, n, x))
            _, first, b = last[j]
            block.append(slice(first, first + k + 1))
            bases.append(b)
        out = self._c[tuple(block)]
        for b in reversed(bases):
            out = out @ b
        return float(out)


class CompiledPointEvaluator:
    """A :class:`ForceMap` evaluated at one point at a time by the compiled tire core
    (``tf_bspline_eval`` of ``tire_brush/csrc/bspline.c``), ``f(kappa, vx, Fz, T_K) ->
    float``.

    The same operations as :class:`PointEvaluator` (its readable reference: the knot span by
    bisection, de Boor's recurrence, the coefficient block contracted the last axis first),
    in C: about a tenth of its cost per point, which is most of what the quarter car of a
    stop spends per step (docs/screening.md). The two agree to rounding (the reference's
    contraction is numpy's matrix product, whose order of summation is its own;
    tests/test_braking_force_map.py).
    """

    def __init__(self, fmap: ForceMap) -> None:
        import ctypes

        from tire_brush import ccore

        lib = ccore.load()
        n = len(fmap.active)
        ints = ctypes.c_int * n
        dbls = ctypes.c_double * n
        bounds = [fmap.bounds(name) for name in fmap.active]
        knots = np.ascontiguousarray(np.concatenate(fmap.knots), dtype=float)
        coef = np.ascontiguousarray(fmap.coefficients, dtype=float)
        handle = lib.tf_bspline_new(
            n, ints(*(INPUTS.index(name) for name in fmap.active)), ints(*fmap.degrees),
            ints(*(k.size for k in fmap.knots)), ints(*(name == "vx" for name in fmap.active)),
            dbls(*(b[0] for b in bounds)), dbls(*(b[1] for b in bounds)),
            ccore._ptr(knots), ccore._ptr(coef))
        if not handle:
            raise InputError("the tire core refused the force map's spline", field="fmap",
                             value=fmap.label)
        self._lib, self._handle = lib, handle
        self._eval = lib.tf_bspline_eval
        self.axes = fmap.axes

    def __call__(self, kappa: float, vx: float, Fz: float, T_K: float) -> float:
        """``Fx/Fz`` [1] at one point (scalars; inputs clamped to the axes)."""
        return self._eval(self._handle, kappa, vx, Fz, T_K)

    def __del__(self) -> None:
        handle = self.__dict__.get("_handle")
        if handle:
            self._lib.tf_bspline_free(handle)
            self._handle = None

    def __reduce__(self):
        raise TypeError("a CompiledPointEvaluator holds a handle of this process: pickle its "
                        "ForceMap instead")


def default_axes(v0: float, v_stop: float, Fz: float, T_K: float, *,
                 n_kappa: int = 61, n_v: int = 9) -> dict[str, np.ndarray]:
    """Axes for a braking study at one load and temperature.

    Slip from -1 (lock) to 0 (free rolling) with nodes graded towards small slip, where the
    curves bend (``kappa = -u^2``, u uniform on [0, 1]), mirrored to ``kappa <= 0.05`` so that
    free rolling is an interior point of the map (the clamp at an axis end has no slope);
    speed log-spaced from ``v_stop / 2`` to ``1.2 v0`` [m/s]; load ``Fz`` [N] and
    temperature ``T_K`` [K] single nodes (constants).
    """
    u = np.linspace(0.0, 1.0, n_kappa)
    neg = -(u[::-1] ** 2)
    neg[-1] = 0.0
    pos = -neg[(neg < 0.0) & (neg >= -0.05)][::-1]
    kappa = np.concatenate([neg, pos])
    v = np.geomspace(0.5 * v_stop, 1.2 * v0, n_v)
    return {"kappa": kappa, "vx": v, "Fz": np.array([Fz]), "T_K": np.array([T_K])}
