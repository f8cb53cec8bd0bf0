"""Build-time side of the real-time fidelity: the steady patch response tabulated
(:class:`tire_brush.realtime.PatchTable`) from the steady march of the full model
(:meth:`tire_brush.steady.SteadyBrush.patch_response`, ``tf_steady``), so that the table follows
the full model's physics whatever it becomes (docs/realtime.md)."""

from __future__ import annotations

import ctypes
import hashlib
import itertools
import math
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import InputError

from . import ccore
from .friction import as_table
from .realtime import (
    AXIS_NAMES,
    GAMMA_NODES,
    LOAD_NODES,
    N_VALUES,
    RHO_NODES,
    SPEED_NODES,
    T_STEP,
    THETA_NODES,
    PatchTable,
)
from .slip import V_FLOOR
from .steady import N_STEADY, TOL, SteadyBrush


def default_axes(friction_T: np.ndarray) -> dict[str, np.ndarray]:
    """Default axes for a friction table whose temperature axis is ``friction_T`` [K]: the
    nodes above, and temperatures every :data:`T_STEP` over the friction's range (its ends
    included)."""
    lo, hi = float(friction_T[0]), float(friction_T[-1])
    n = max(2, math.ceil((hi - lo) / T_STEP - 1e-9) + 1)
    return {"gamma": np.array(GAMMA_NODES), "T": np.linspace(lo, hi, n),
            "Fz": np.array(LOAD_NODES), "log10_v": np.log10(SPEED_NODES),
            "theta": np.array(THETA_NODES), "rho": np.array(RHO_NODES)}


def table_key(params: Any, table: Any, axes: dict[str, np.ndarray], n_cells: int,
              tol: float, wet: Any | None = None, drain_scale: float = 1.0,
              depths: Any = None) -> str:
    """Hash of what a patch table depends on: the tire parameters, the friction table's axes,
    values and blend length, the axes and the march's settings, and the wet branch (its
    hash, water depths and drainage times, the drainage scale and the layers' depths
    ``depths``, default the branch's) when the table has one."""
    h = hashlib.sha256()
    h.update(repr(params).encode())
    for a in (table.log10_v, table.T, table.log10_p, table.values):
        h.update(np.ascontiguousarray(a, float).tobytes())
    h.update(repr(float(table.inv_s0)).encode())
    for name in AXIS_NAMES:
        h.update(np.ascontiguousarray(axes[name], float).tobytes())
    h.update(repr((n_cells, tol, "rho_n = rho / (rho + q (1 - rho))", "f0",
                   "values float32")).encode())
    if wet is not None:
        h.update(repr(("wet", str(wet.meta.get("hash", "")), float(drain_scale),
                       "U = V_r + V_sx / 2", DEPTH_LAW)).encode())
        for name in ("water_depth", "log10_t_drain"):
            h.update(np.ascontiguousarray(wet.axes[name], float).tobytes())
        for name in sorted(wet.variables):
            h.update(np.ascontiguousarray(wet.variables[name], float).tobytes())
        if depths is not None:
            h.update(np.ascontiguousarray(depths, float).tobytes())
    return h.hexdigest()


#: What the depth law between two layers is measured on (:func:`depth_law`; part of the key).
DEPTH_LAW = ("s = f - kappa f (1 - f); friction (cold + hot) / 2 at the slip speed, "
             "Fz / (2 a b), the node's drainage time, mid-depth")


def depth_law(params: Any, wet: Any, depths: Any, ax: dict[str, np.ndarray],
              drain_scale: float = 1.0) -> np.ndarray:
    """The full model's depth law between neighbouring layers of a patch table, at each node
    (:attr:`tire_brush.realtime.PatchTable.depth_law`).

    The full model reads the wet branch at a depth between its nodes as the product of two
    interpolations linear in the depth (:mod:`lookup.grid.wet`: the dry share ``w`` and the
    frictions ``mu_w0``, ``mu_w1`` at either share), so its friction
    ``(1 - w) mu_w0 + w mu_w1`` is quadratic in the fraction ``f`` of the way between two
    depths, ``mu(f) = (1 - s) mu(0) + s mu(1)`` with ``s = f - kappa f (1 - f)``; on water
    it stays above the chord (``kappa > 0``: the adhesive part ``w (mu_w1 - mu_w0)`` is the
    product of the dry share, falling from 1, and the difference, rising from 0 at depth 0
    where both are the dry friction). The patch's force is a nonlinear function of the
    friction, but between two layers of one node it follows the friction far more closely
    than the depth (the sliding zone's force is the friction's; the adhering zone's does
    not depend on it): the table reads the layers with the weights ``1 - s`` and ``s``.

    ``kappa`` is measured on the friction where the node's patch slides: at its slip speed
    ``|V|`` (clamped to the branch's first node), its tread temperature, the mean pressure
    ``Fz / (2 a b)`` and its drainage time (that of the march, :func:`_wet_march`), the
    mean of the cold and hot branches (eq. (28) blends between them), at the two layers'
    depths and midway; ``s`` there gives ``kappa = 2 - 4 s``, clamped to [-1, 1] (``s``
    monotonic in ``f``). Exact for the friction between layers within one cell of the
    branch's depths; a fit through the midpoint across a node of the branch.

    Returns shape ``(len(depths) - 1, n_gamma, n_T, n_Fz, n_v, n_theta, n_rho)``.
    """
    Fz_ax = np.asarray(ax["Fz"], float)
    TT, F, LV, TH, RN = np.meshgrid(ax["T"], Fz_ax, ax["log10_v"], ax["theta"], ax["rho"],
                                    indexing="ij")
    q = np.interp(F, Fz_ax, full_sliding_share(params, Fz_ax))
    RHO = RN * q / (1.0 - RN * (1.0 - q))          # as _layer
    vref = 10.0 ** LV
    s = RHO * vref
    Vr = vref - s
    U = 0.5 * (np.abs(Vr + s * np.cos(TH)) + np.abs(Vr))
    size = np.array([params.patch.size(float(f)) for f in Fz_ax])
    ia = np.searchsorted(Fz_ax, F)
    a, b = size[ia, 0], size[ia, 1]
    t = drain_scale * (2.0 * a / U)
    p = F / (2.0 * a * b)
    v = np.maximum(s, 10.0 ** float(wet.axes["log10_v"][0]))

    def mu(d: float) -> np.ndarray:
        r = wet.interpolate(v, TT, p, d, t)
        return 0.5 * (r["mu_wet_cold"] + r["mu_wet_hot"])

    out = []
    for d0, d1 in itertools.pairwise(depths):
        m0, m1, mm = mu(float(d0)), mu(float(d1)), mu(0.5 * (float(d0) + float(d1)))
        den = m1 - m0
        ok = np.abs(den) > 1e-9
        sm = np.where(ok, (mm - m0) / np.where(ok, den, 1.0), 0.5)
        out.append(np.clip(2.0 - 4.0 * sm, -1.0, 1.0))
    k = np.stack(out)
    return np.ascontiguousarray(np.broadcast_to(k[:, None], (k.shape[0], len(ax["gamma"]),
                                                              *k.shape[1:])))


def _wet_layer_arrays(table: Any, wet: Any, d: float) -> tuple[np.ndarray, ...]:
    """The wet branch at the water depth ``d`` [m] on the friction table's nodes: the cold and
    hot friction at dry share 0 and 1, shape (nv, nT, np) each, and the dry share at every
    drainage-time node, (nt, nv, nT, np) (:mod:`lookup.grid.wet`); between the branch's depth
    nodes each linear in the depth, as the core's ``step_table`` reads them (clamped to the
    nodes)."""
    for name, a, b in (("log10_v", table.log10_v, wet.axes["log10_v"]),
                       ("T", table.T, wet.axes["T"]), ("log10_p", table.log10_p,
                                                         wet.axes["log10_p"])):
        if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-9):
            raise InputError("the wet branch has other nodes than the friction table",
                             field=name)
    ax = np.asarray(wet.axes["water_depth"], float)
    k, f = _cell(ax, d)
    v = wet.variables
    return tuple((1.0 - f) * np.asarray(v[name][k], float) + f * np.asarray(v[name][k + 1],
                                                                             float)
                 for name in ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0",
                              "mu_wet_hot_w1", "w_dry"))


def _cell(ax: np.ndarray, x: float) -> tuple[int, float]:
    """The cell ``k`` of the ascending axis ``ax`` holding ``x`` and the fraction ``f`` in it,
    clamped to the axis (``f`` 0 below it, 1 above; NaN reads the first node): the core's
    ``locate_arr``."""
    n = ax.size
    if not (x > ax[0]):
        return 0, 0.0
    if not (x < ax[n - 1]):
        return n - 2, 1.0
    k = int(np.searchsorted(ax, x, side="right")) - 1
    return k, float((x - ax[k]) / (ax[k + 1] - ax[k]))


def _wet_march(params: Any, table: Any, n_cells: int, tol: float, wet: tuple, Vsx: np.ndarray,
               Vsy: np.ndarray, Vr: np.ndarray, Fz: np.ndarray, T: float,
               g: float) -> np.ndarray:
    """The steady march at each point on the wet friction the full model reads there
    (``step_table`` of tirecore.c, :meth:`tire_brush.transient.TransientBrushTire.set_wet`):
    at the layer's water depth and the drainage time ``drain_scale 2a / U`` of the point,
    ``U = (|v_x| + |V_r|) / 2`` the entrainment speed with ``v_x = V_r + V_sx`` (the table
    holds the braking side, ``V_sx >= 0``: docs/realtime.md), the dry share linear in
    log10 t_drain between the branch's nodes (clamped to them) and the friction
    ``(1 - w) mu_w0 + w mu_w1`` (:mod:`tire_brush.wet_friction`). Rows as
    :meth:`~tire_brush.steady.SteadyBrush.patch_response`'s."""
    c0, c1, h0, h1, wd, lt_ax, drain_scale = wet
    # the march at T reads the two temperature rows about it (clamped to the axis): the
    # friction is made for those only (as the core's step_table)
    Tax = np.asarray(table.T, float)
    iT = 0 if not T > Tax[0] else min(int(np.searchsorted(Tax, T, side="right")) - 1,
                                      Tax.size - 2)
    r = slice(iT, iT + 2)
    c0, c1, h0, h1, wd = c0[:, r], c1[:, r], h0[:, r], h1[:, r], wd[:, :, r]
    T_rows = np.ascontiguousarray(Tax[r])
    P = ccore.core_params(params, n_elements=n_cells, dt_internal=1.0, tol=tol,
                          v_floor=V_FLOOR, thermal=False, rigid=True, massless=False)
    lib = ccore.load()
    n = Vsx.size
    # the drainage-time cell of every point, then the points grouped by it: points of one
    # cell and fraction read the same friction (e.g. theta and -theta at an inclination,
    # every direction at zero slip), so one friction table and one call of the march serve
    # them all; the march of a point does not depend on the others in its call (tf_steady)
    half = {F: params.patch.size(F)[0] for F in set(Fz.tolist())}
    cells: dict[tuple[int, float], list[int]] = {}
    for j in range(n):
        a = half[float(Fz[j])]
        U = 0.5 * (abs(float(Vr[j] + Vsx[j])) + abs(float(Vr[j])))
        lt = math.log10(drain_scale * (2.0 * a / U)) if U > 0.0 and a > 0.0 else math.inf
        cells.setdefault(_cell(lt_ax, lt), []).append(j)
    pts = np.ascontiguousarray(np.stack([Vsx, Vsy, Vr, Fz, np.full(n, float(g))], axis=1),
                               dtype=float)
    out = np.zeros((n, ccore.STEADY_OUT))
    vals = np.array(table.values[:, r], float)     # C-contiguous: refilled for each cell
    axes = [np.ascontiguousarray(a, float) for a in (table.log10_v, T_rows, table.log10_p)]
    nv, nT, npp = (a.size for a in axes)
    ax_ptrs = [ccore._ptr(a) for a in axes]
    v_ptr = ccore._ptr(vals)
    for (i, f), idx in cells.items():
        ws = (1.0 - f) * wd[i] + f * wd[i + 1]
        ws = np.where(ws > 0.0, ws, 0.0)
        ws = np.where(ws > 1.0, 1.0, ws)
        vals[..., 0] = (1.0 - ws) * c0 + ws * c1
        vals[..., 1] = (1.0 - ws) * h0 + ws * h1
        handle = lib.tf_table_new(nv, nT, npp, *ax_ptrs, v_ptr, float(table.inv_s0))
        if not handle:
            raise InputError("the tire core refused the wet friction table", field="wet")
        q = np.ascontiguousarray(pts[idx])
        o = np.zeros((len(idx), ccore.STEADY_OUT))
        try:
            rc = lib.tf_steady(ctypes.byref(P), handle, n_cells, len(idx), ccore._ptr(q),
                               float(T), 1.0, ccore._ptr(o))
        finally:
            lib.tf_table_free(handle)
        if rc != 0:
            raise InputError("the tire core refused the operating point", field="points",
                             value=q.tolist())
        out[idx] = o
    return out.T.copy()


def _layer(args: tuple) -> tuple[np.ndarray, np.ndarray]:
    """One (gamma, T) layer of the table (a worker's job): the march at every (Fz, v, theta,
    rho) node with theta >= 0, or every theta when gamma > 0; and the force at zero slip (of
    the camber alone) at every (Fz, v), which the slip's-frame values leave out."""
    params, friction, n_cells, tol, g, T, Fz_ax, lv_ax, th_ax, rho_ax = args[:10]
    wet = args[10] if len(args) > 10 else None
    sb = SteadyBrush(params, friction, n_elements=n_cells, tol=tol, rigid_carcass=True)
    F, LV, TH, RN = np.meshgrid(Fz_ax, lv_ax, th_ax, rho_ax, indexing="ij")
    q = np.interp(F, Fz_ax, full_sliding_share(params, Fz_ax))
    RHO = RN * q / (1.0 - RN * (1.0 - q))          # the inverse of rho_n (realtime.py)
    vref = 10.0 ** LV
    s = RHO * vref
    Vr = vref - s
    Vsx = s * np.cos(TH)
    Vsy = s * np.sin(TH)
    out = np.zeros((*F.shape, N_VALUES))
    marched = (RHO > 0.0) | (g > 0.0)
    if g == 0.0:
        marched &= TH >= 0.0
    sel = np.flatnonzero(marched.ravel())
    if wet is None:
        r = sb.patch_response(Vsx.ravel()[sel], Vsy.ravel()[sel], Vr.ravel()[sel],
                              F.ravel()[sel], float(T), gamma=float(g))
    else:
        r = _wet_march(params, sb.table, n_cells, tol, wet, Vsx.ravel()[sel],
                       Vsy.ravel()[sel], Vr.ravel()[sel], F.ravel()[sel], float(T), float(g))
    Fx, Fy, Mz, _, mu_sl, frac, dT, _, P, Mb = r
    f0 = np.zeros((Fz_ax.size, lv_ax.size, 2))
    if g > 0.0:
        # zero slip: the camber's force, the same at every theta (rho = 0 rows)
        full = np.zeros((*F.shape, 2))
        full.reshape(-1, 2)[sel] = np.stack([Fx, Fy], axis=1)
        f0 = full[:, :, 0, 0, :] / Fz_ax[:, None, None]
        iF, iv = np.unravel_index(sel, F.shape)[:2]
        Fx = Fx - f0[iF, iv, 0] * Fz_ax[iF]
        Fy = Fy - f0[iF, iv, 1] * Fz_ax[iF]
    th = TH.ravel()[sel]
    c, sn = np.cos(th), np.sin(th)
    Fzs = F.ravel()[sel]
    vals = np.stack([-(Fx * c + Fy * sn) / Fzs, (-Fx * sn + Fy * c) / Fzs, Mz / Fzs, Mb / Fzs,
                     mu_sl, frac, dT, P / (Fzs * vref.ravel()[sel])], axis=1)
    flat = out.reshape(-1, N_VALUES)
    flat[sel] = vals
    if g == 0.0:
        # (V_y, gamma) -> (-V_y, -gamma) mirrors the patch: Fx, mu_slide, sliding fraction,
        # flash temperature and power are even, Fy and Mz odd; in the slip's frame the force
        # along is even and the force across odd in theta, as is Mz
        nth = th_ax.size
        for j in range(nth):
            if th_ax[j] < 0.0:
                jm = int(np.argmin(np.abs(th_ax + th_ax[j])))
                if abs(th_ax[jm] + th_ax[j]) > 1e-12:
                    raise InputError("theta nodes must be symmetric about 0",
                                     field="patch_table.theta", value=th_ax.tolist())
                out[:, :, j] = out[:, :, jm]
                out[:, :, j, :, 1:4] *= -1.0
    return out, f0


def full_sliding_share(params: Any, Fz: Any) -> np.ndarray:
    """The slip share ``q = 3 Fz / C`` at which a brush of friction 1 slides over the whole
    patch (Pacejka 2012, ch. 3: the massless brush's full-sliding slip ``3 mu Fz / C``), with
    its slip stiffness ``C = 2 k_x b a^2`` at the load (``a``, ``b`` of the patch law); at
    most 0.9. The real-time table reads the slip share on this scale
    (:mod:`tire_brush.realtime`)."""
    out = []
    for F in np.atleast_1d(np.asarray(Fz, float)).tolist():
        a, b = params.patch.size(F)
        C = 2.0 * params.tread.k_x * b * a * a
        out.append(min(3.0 * F / C, 0.9) if C > 0 else 0.9)
    return np.array(out)


def build_patch_table(params: Any, friction: Any, *, axes: dict[str, Any] | None = None,
                      n_cells: int | None = None, tol: float | None = None,
                      processes: int = 1, wet: Any | None = None,
                      drain_scale: float = 1.0, depths: Any = None) -> PatchTable:
    """Tabulate the steady patch response for the real-time fidelity (module docstring).

    Parameters
    ----------
    params
        :class:`~tire_brush.params.TireParams`.
    friction
        What :class:`~tire_brush.steady.SteadyBrush` takes (a grid, a branch table).
    axes
        Axes by :data:`AXIS_NAMES` (default :func:`default_axes`).
    n_cells, tol
        The march's settings (default those of :mod:`tire_brush.steady`).
    processes
        Worker processes (layers of (gamma, T) run in parallel).
    wet
        The grid's wet branch (:class:`lookup.grid.wet.WetGrid`, on the friction table's
        nodes) or None. With it the table has a layer at each of the branch's water depths:
        depth 0 the dry road's, the others the march on the wet friction the full model reads
        at each node (its drainage time from the node's speed and load, :func:`_wet_march`).
    drain_scale
        ``(D / 2R)^2`` of the drainage time, as :meth:`~tire_brush.transient.
        TransientBrushTire.set_wet` takes it (the FMUs: 1).
    depths
        Water depths [m] of the layers, strictly ascending from 0 (default: the branch's
        nodes); a layer between the branch's nodes is marched on the branch read at that
        depth, as the full model reads it (fewer interpolation errors between them at the
        cost of a layer each: docs/realtime.md).
    """
    table = as_table(friction)
    n_cells = N_STEADY if n_cells is None else n_cells
    tol = TOL if tol is None else tol
    ax = default_axes(np.asarray(table.T, float))
    if axes:
        for k, v in axes.items():
            if k not in AXIS_NAMES:
                raise InputError(f"unknown axis (one of {AXIS_NAMES})", field="axes", value=k)
            ax[k] = np.asarray(v, float)
    if wet is None:
        depths = [0.0]
    elif depths is None:
        depths = [float(d) for d in wet.axes["water_depth"]]
    else:
        depths = [float(d) for d in depths]
        if not depths or depths[0] != 0.0 or not all(math.isfinite(d) for d in depths) or \
                not bool(np.all(np.diff(depths) > 0)):
            raise InputError("must be strictly ascending water depths from 0 m",
                             field="depths", value=depths)
    if not (math.isfinite(drain_scale) and drain_scale > 0):
        raise InputError("must be a finite number > 0", field="drain_scale", value=drain_scale)
    jobs = []
    for d in depths:
        extra: tuple = ()
        if d > 0.0:
            extra = ((*_wet_layer_arrays(table, wet, d),
                      np.asarray(wet.axes["log10_t_drain"], float), float(drain_scale)),)
        jobs += [(params, table, n_cells, tol, float(g), float(T), ax["Fz"], ax["log10_v"],
                  ax["theta"], ax["rho"], *extra) for g in ax["gamma"] for T in ax["T"]]
    if processes > 1:
        import multiprocessing as mp
        # the costliest layers first (a wet one marches point by point, an inclined one every
        # direction), so that the workers finish together instead of one waiting on the last
        order = sorted(range(len(jobs)), key=lambda i: (-len(jobs[i]), -jobs[i][4]))
        with mp.get_context("fork").Pool(processes) as pool:
            done = pool.map(_layer, [jobs[i] for i in order], chunksize=1)
        layers = [None] * len(jobs)
        for i, lay in zip(order, done, strict=True):
            layers[i] = lay
    else:
        layers = [_layer(j) for j in jobs]
    lead = (len(depths), ax["gamma"].size, ax["T"].size)
    if len(depths) == 1:
        lead = lead[1:]
    vals = np.stack([v for v, _ in layers]).reshape((*lead, *layers[0][0].shape))
    f0 = np.stack([f for _, f in layers]).reshape((*lead, *layers[0][1].shape))
    return PatchTable(ax["gamma"], ax["T"], ax["Fz"], ax["log10_v"], ax["theta"], ax["rho"],
                      full_sliding_share(params, ax["Fz"]), f0, vals,
                      key=table_key(params, table, ax, n_cells, tol, wet, drain_scale,
                                    None if wet is None else depths),
                      depth=np.array(depths),
                      depth_law=None if len(depths) < 2 else depth_law(params, wet, depths,
                                                                        ax, drain_scale))


def cache_dir() -> Path:
    """Folder of cached patch tables (``$TIREFRIC_CACHE``, default ``~/.cache/tirefric``)."""
    return Path(os.environ.get("TIREFRIC_CACHE", Path.home() / ".cache" / "tirefric"))


def cached_patch_table(params: Any, friction: Any, *, axes: dict[str, Any] | None = None,
                       processes: int = 2, directory: str | Path | None = None,
                       wet: Any | None = None, drain_scale: float = 1.0,
                       depths: Any = None) -> tuple[PatchTable, Path]:
    """:func:`build_patch_table` at the default march settings (and the default axes, or those
    of ``axes`` given; with the layers of the wet branch ``wet`` when given), cached on disk
    by :func:`table_key` (the tire parameters, the friction table, the axes and settings, the
    wet branch): a table is built once per tire, grid and axes. Returns the table and its
    file (:meth:`~tire_brush.realtime.PatchTable.to_bytes`' format)."""
    table = as_table(friction)
    ax = default_axes(np.asarray(table.T, float))
    for k, v in (axes or {}).items():
        if k not in AXIS_NAMES:
            raise InputError(f"unknown axis (one of {AXIS_NAMES})", field="axes", value=k)
        ax[k] = np.asarray(v, float)
    if wet is not None and depths is None:
        depths = [float(d) for d in wet.axes["water_depth"]]
    key = table_key(params, table, ax, N_STEADY, TOL, wet, drain_scale,
                    None if wet is None else depths)
    d = Path(directory) if directory is not None else cache_dir()
    path = d / f"patch-{key[:24]}.bin"
    if path.is_file():
        try:
            return PatchTable.from_bytes(path.read_bytes(), key=key, verify=False), path
        except InputError:
            pass                                    # a damaged cache file: build again
    pt = build_patch_table(params, table, axes=ax, processes=processes, wet=wet,
                           drain_scale=drain_scale, depths=depths)
    d.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=d, delete=False, suffix=".tmp") as f:
        f.write(pt.to_bytes())
    os.replace(f.name, path)
    return pt, path


def settled(tire: Any, kappa: float, alpha: float, vx: float, Fz: float, T: float, *,
            gamma: float = 0.0, dt: float = 1e-3, distance: float = 6.0,
            tail: int = 50, water_depth: float = 0.0) -> list[float]:
    """The outputs of a transient tire (either fidelity) held at slip ``kappa``, slip angle
    ``alpha`` [rad], speed ``vx`` [m/s], load ``Fz`` [N], temperature ``T`` [K],
    inclination ``gamma`` [rad] and water depth ``water_depth`` [m] from rest until it has
    rolled ``distance`` [m] (at least 0.3 s): the mean of the last ``tail`` steps' outputs
    (:data:`tire_brush.signals.OUTPUTS`)."""
    tire.reset()
    R = tire.params.R_e
    omega = vx * (1.0 + kappa) / R
    vy = -vx * math.tan(alpha)
    n = max(int(0.3 / dt), int(distance / (vx * dt)), tail)
    acc = []
    for k in range(n):
        o = tire.step_array(dt, vx, vy, omega, Fz, T, 1.0, gamma, water_depth)
        if k >= n - tail:
            acc.append(o)
    return np.mean(acc, axis=0).tolist()


def realtime_curve(params: Any, friction: Any, kappa: Any, alpha: Any, vx: float, Fz: float,
                   T: float) -> dict[str, np.ndarray]:
    """The steady state of the real-time fidelity (thermal state off, as the steady model)
    at each (kappa, alpha) [1, rad]: the tire held until settled (:func:`settled`) on the
    cached patch table of this tire and friction; outputs by name."""
    from .signals import OUTPUT_NAMES
    from .transient import TransientBrushTire

    table, _ = cached_patch_table(params, friction)
    tire = TransientBrushTire(params, friction, patch=table, thermal=False)
    k, a = np.broadcast_arrays(np.asarray(kappa, float), np.asarray(alpha, float))
    rows = [settled(tire, float(x), float(y), vx, Fz, T) for x, y in zip(k.ravel(), a.ravel(),
                                                                        strict=True)]
    arr = np.array(rows).reshape((*k.shape, len(OUTPUT_NAMES)))
    return {n: arr[..., i] for i, n in enumerate(OUTPUT_NAMES)}
