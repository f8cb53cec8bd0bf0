"""Steady-state brush tire: forces at a given slip, speed, load and temperature.

In steady state every element repeats the history of the one before it, so the patch is
computed by following one element from the leading edge to the trailing edge (Pacejka 2012,
ch. 3): ``n`` equal cells, the element at the cell midpoints, the first step half a cell long
(an element enters undeflected at the edge; physics-notes: accumulating from cell edges while
evaluating at midpoints doubles the first deflection). Each step is the implicit element step of
:mod:`tire_brush.element` with ``dt = dx / |V_r|``, so the steady model and the transient model
share one element law (stick, slide with eq. (28) friction, tip mass and damping). The belt is
at rest relative to the rim in steady state: carcass compliance does not enter.

Many operating points are solved at once (numpy over points); points with different
temperatures are grouped. A single operating point takes a line-for-line pure-Python copy of
the element step (:func:`~tire_brush.element.march_point`): for one point numpy's per-call
overhead dominates (0.9 ms instead of 6 ms at 64 cells); tests pin the two paths together.

Rolling backwards (``V_r < 0``) mirrors the patch (elements enter at
``x = -a``). A wheel that does not roll (``|V_r|`` below :data:`V_ROLL_MIN`) is computed at
``V_r = V_ROLL_MIN``: the elements stay in the patch so long that they reach the fully
developed hot branch (a locked wheel); no speed is divided by zero.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lookup.errors import InputError

from .element import CREEP_SPEED, ElementProps, StepCoefficients, element_step, march_point
from .friction import BranchTable, FrictionModel, FrictionQuery, as_table
from .params import TireParams
from .patch import midpoint_weights, patch_size
from .slip import BrushOutputs, velocities_from_slip

#: Default number of cells along the patch of the steady model (convergence: tests).
N_STEADY = 64
#: Default friction evaluations per element step of the steady model.
N_NEWTON_STEADY = 2
#: Smallest rolling speed of the steady model [m/s] (module docstring).
V_ROLL_MIN = 1e-6


def _finite(name: str, x: np.ndarray) -> None:
    if not np.isfinite(x).all():
        raise InputError("must be finite", field=name, value=np.asarray(x).tolist())


class SteadyBrush:
    """Steady-state brush tire on a friction provider.

    Parameters
    ----------
    params
        Tire parameters.
    friction
        A :class:`~tire_brush.friction.FrictionModel`, a
        :class:`~tire_brush.friction.BranchTable` or a :class:`lookup.grid.FrictionGrid`.
    n_elements
        Cells along the patch.
    massless
        Drop the tip mass and damping (Pacejka's massless brush, for the closed forms).
    n_newton
        Friction evaluations per element step (:func:`~tire_brush.element.element_step`).
    """

    def __init__(self, params: TireParams, friction: FrictionModel | BranchTable | Any, *,
                 n_elements: int = N_STEADY, massless: bool = False,
                 n_newton: int = N_NEWTON_STEADY) -> None:
        if not (isinstance(n_elements, int) and n_elements >= 2):
            raise InputError("must be an integer >= 2", field="n_elements", value=n_elements)
        self.params = params
        self.table = as_table(friction)
        self.props = ElementProps.from_tread(params.tread, massless=massless)
        if not (isinstance(n_newton, int) and n_newton >= 1):
            raise InputError("must be an integer >= 1", field="n_newton", value=n_newton)
        self.n_elements = n_elements
        self.n_newton = n_newton
        self._xi, self._share = midpoint_weights(n_elements)
        uniform, lv0, inv = self.table._ax[0]
        #: single points take the pure-Python march (needs index arithmetic on the speed axis)
        self._scalar_ok = uniform
        self._v_axis = (lv0, inv, float(self.table.log10_v.size - 1),
                        self.table._inv_dlnv.tolist())

    def solve(self, kappa: Any, alpha: Any, vx: Any, Fz: Any, T: Any,
              mu_scale: float = 1.0) -> BrushOutputs:
        """Steady state at slip ``kappa`` [1], slip angle ``alpha`` [rad], forward speed ``vx``
        [m/s] (> 0), load ``Fz`` [N] and background temperature ``T`` [K] (numpy
        broadcasting); returns :class:`~tire_brush.slip.BrushOutputs` of the broadcast shape.
        """
        kappa, alpha, vx = (np.asarray(x, float) for x in (kappa, alpha, vx))
        for name, x in (("kappa", kappa), ("alpha", alpha), ("vx", vx)):
            _finite(name, x)
        if (vx <= 0).any():
            raise InputError("the steady model is given slips at a forward speed vx > 0 m/s "
                             "(use solve_velocities for other motions)", field="vx",
                             value=vx.tolist())
        if (np.abs(alpha) >= np.pi / 2).any():
            raise InputError("slip angle must lie in (-pi/2, pi/2) rad", field="alpha",
                             value=alpha.tolist())
        Vsx, Vsy, Vr = velocities_from_slip(kappa, alpha, vx)
        out = self.solve_velocities(Vsx, Vsy, Vr, Fz, T, mu_scale)
        shape = np.shape(out.Fx)
        out.kappa = np.broadcast_to(kappa, shape).copy()
        out.alpha = np.broadcast_to(alpha, shape).copy()
        return out

    def fx_over_fz(self, kappa: Any, vx: Any, Fz: Any, T_K: Any) -> np.ndarray:
        """``Fx / Fz`` in pure longitudinal slip (the braking studies' friction source)."""
        out = self.solve(kappa, 0.0, vx, Fz, T_K)
        Fz_b = np.broadcast_to(np.asarray(Fz, float), np.shape(out.Fx))
        return np.where(Fz_b > 0, out.Fx / np.where(Fz_b > 0, Fz_b, 1.0), 0.0)

    def solve_velocities(self, V_sx: Any, V_sy: Any, V_r: Any, Fz: Any, T: Any,
                         mu_scale: float = 1.0) -> BrushOutputs:
        """Steady state for slip velocities ``V_sx``, ``V_sy`` [m/s] of the contact point and
        rolling speed ``V_r`` [m/s] (any signs), load ``Fz`` [N], temperature ``T`` [K].

        The result's ``kappa`` and ``alpha`` are left at 0 (slips need a reference speed;
        :meth:`solve` fills them in).
        """
        arrs = np.broadcast_arrays(*(np.asarray(x, float) for x in (V_sx, V_sy, V_r, Fz, T)))
        for name, x in zip(("V_sx", "V_sy", "V_r", "Fz", "T"), arrs, strict=True):
            _finite(name, x)
        shape = arrs[0].shape
        Vsx, Vsy, Vr, Fz_, T_ = (x.ravel() for x in arrs)
        if (T_ <= 0).any():
            raise InputError("temperature must be > 0 K", field="T", value=T_.tolist())
        if not (np.isfinite(mu_scale) and mu_scale >= 0):
            raise InputError("must be a finite number >= 0", field="mu_scale", value=mu_scale)
        res = np.zeros((7, Vsx.size))
        if Vsx.size == 1 and self._scalar_ok:
            res[:, 0] = self._march_point(float(Vsx[0]), float(Vsy[0]), float(Vr[0]),
                                          float(Fz_[0]), float(T_[0]), float(mu_scale))
        else:
            for Tu in np.unique(T_):
                sel = np.flatnonzero(T_ == Tu)
                res[:, sel] = self._march(Vsx[sel], Vsy[sel], Vr[sel], Fz_[sel], float(Tu),
                                          float(mu_scale))
        Fx, Fy, Mz, mu_eff, mu_slide, frac, dT = (r.reshape(shape) for r in res)
        zero = np.zeros(shape)
        return BrushOutputs(Fx, Fy, Mz, zero, zero.copy(), mu_eff, mu_slide, frac, dT,
                            np.broadcast_to(arrs[4], shape).copy())

    def _march_point(self, Vsx: float, Vsy: float, Vr: float, Fz: float, T: float,
                     mu_scale: float) -> np.ndarray:
        """:meth:`_march` for one point in Python floats (:func:`~.element.march_point`)."""
        n = self.n_elements
        a, b = self.params.patch.size(Fz)
        area = b * 2.0 * a / n
        if not area > 0:
            return np.zeros(7)
        sgn = -1.0 if Vr < 0 else 1.0
        dt = 2.0 * a / n / max(abs(Vr), V_ROLL_MIN)
        p = self._share * (Fz / area)
        q = self.table.prepare(T, p / (1.0 - self.params.tread.void_ratio))
        nodes = np.broadcast_to(10.0 ** self.table.log10_v, (n, self.table.log10_v.size))
        rows = self.table.at(nodes, FrictionQuery(q.base[:, None], q.fp[:, None], q.fT,
                                                   q.mu0))
        rows = np.concatenate([rows, rows[:, :, -1:]], axis=2).transpose(1, 0, 2).tolist()
        Fx, Fy, Mz, n_sl, f_sl, p_sl, dT = march_point(
            self.props, rows, q.mu0.T.tolist(), p.tolist(), (p * mu_scale).tolist(),
            self._xi.tolist(), (0.5 * dt, dt), (Vsx, Vsy), self._v_axis, self.table.inv_s0,
            self.n_newton)
        Fx, Fy, Mz = Fx * area, Fy * area, Mz * area * a * sgn
        mu_eff = math.hypot(Fx, Fy) / Fz
        return np.array([Fx, Fy, Mz, mu_eff, f_sl / p_sl if p_sl > 0 else 0.0, n_sl / n, dT])

    def _march(self, Vsx: np.ndarray, Vsy: np.ndarray, Vr: np.ndarray, Fz: np.ndarray,
               T: float, mu_scale: float) -> np.ndarray:
        """Follow one element through the patch for every point (module docstring)."""
        n, P = self.n_elements, Vsx.size
        tread = self.params.tread
        a, b = patch_size(self.params.patch, Fz)
        dx = 2.0 * a / n
        area = b * dx
        loaded = area > 0
        safe_area = np.where(loaded, area, 1.0)
        sgn = np.where(Vr < 0, -1.0, 1.0)
        dt = np.where(loaded, dx, 1.0) / np.maximum(np.abs(Vr), V_ROLL_MIN)   # 1: unloaded
        Vb = np.stack([Vsx, Vsy])
        # pressures of every cell and point, and their table indices
        p = self._share[:, None] * np.where(loaded, np.maximum(Fz, 0.0) / safe_area, 0.0)
        query = self.table.prepare(T, p / (1.0 - tread.void_ratio))   # all cells at once
        pf = p * mu_scale
        state = np.zeros((5, P))
        F = np.zeros((2, P))
        Mz = np.zeros(P)
        n_slide = np.zeros(P)
        f_slide = np.zeros(P)
        p_slide = np.zeros(P)
        dT_max = np.zeros(P)
        co_first = StepCoefficients.build(self.props, 0.5 * dt)
        co = StepCoefficients.build(self.props, dt)
        for j in range(n):
            r = element_step(state, pf[j], Vb, self.props, co_first if j == 0 else co,
                             self.table, query[j], n_newton=self.n_newton)
            F += r.tau
            Mz += self._xi[j] * r.tau[1]
            sliding = r.speed > CREEP_SPEED
            n_slide += sliding
            f_slide += r.friction * sliding
            p_slide += p[j] * sliding
            np.maximum(dT_max, r.dT_flash * (1.0 - r.cold) * sliding, out=dT_max)
        F *= area
        Mz *= area * a * sgn
        Fabs = np.hypot(F[0], F[1])
        mu_eff = np.where(Fz > 0, Fabs / np.where(Fz > 0, Fz, 1.0), 0.0)
        mu_slide = np.where(p_slide > 0, f_slide / np.where(p_slide > 0, p_slide, 1.0), 0.0)
        return np.stack([F[0], F[1], Mz, mu_eff, mu_slide, n_slide / n, dT_max]) * loaded
