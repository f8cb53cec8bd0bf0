"""Steady-state brush tire: forces at a given slip, speed, load and temperature.

In steady state every element repeats the history of the one before it, so the patch is
computed by following one element from the leading edge to the trailing edge (Pacejka 2012,
ch. 3): it enters with its tip moving with the belt (slip velocity ``V_s``, undeflected), is
integrated in time with the error-controlled element integration of the transient model
(:mod:`tire_brush.element`, docs/tire-core.md), and its stress is sampled at ``n`` equal cell
midpoints; the force is the midpoint sum. The steady and the transient model therefore share
one element law (stick, slide with eq. (28) friction, tip mass and damping) and one
integrator. The belt's translation is at rest relative to the rim in steady state and does
not enter; its yaw (twist) does: the aligning moment turns the belt by ``psi = Mz / k_psi``
and the tread sees the lateral slip speed ``V_sy - V_r psi`` (Pacejka 2012, sec. 3.3), solved
per point by a bracketed root search on ``psi`` (``tf_steady``). A rigid carcass
(``carcass.rigid``) has no yaw.

The march runs in the compiled core (``tf_steady``, :mod:`tire_brush.ccore`), many operating
points per call; ``backend = "reference"`` runs the Python reference
(:func:`tire_brush.element.steady_point`, bit for bit the same).

Rolling backwards (``V_r < 0``) mirrors the patch (elements enter at ``x = -a``). A wheel
that does not roll (``|V_r|`` below :data:`V_ROLL_MIN`) is computed at ``V_r = V_ROLL_MIN``:
the elements stay in the patch so long that they reach the fully developed hot branch (a
locked wheel); no speed is divided by zero.
"""

from __future__ import annotations

import ctypes
from typing import Any

import numpy as np

from tirefric.errors import InputError

from . import ccore
from .element import V_ROLL_MIN, RefTable, steady_point
from .friction import BranchTable, FrictionModel, as_table
from .params import TireParams
from .slip import V_FLOOR, BrushOutputs, velocities_from_slip

#: Default number of cells along the patch of the steady model (convergence: tests).
N_STEADY = 64
#: Default local error tolerance of the element integration [1].
TOL = 2e-3

__all__ = ["N_STEADY", "TOL", "V_ROLL_MIN", "SteadyBrush"]


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
    rigid_carcass
        No belt yaw (default: the tire's ``carcass.rigid``).
    tol
        Local error tolerance of the element integration [1] (docs/tire-core.md).
    backend
        ``"c"`` (the compiled core) or ``"reference"`` (the same algorithm in Python).
    """

    def __init__(self, params: TireParams, friction: FrictionModel | BranchTable | Any, *,
                 n_elements: int = N_STEADY, massless: bool = False, tol: float = TOL,
                 backend: str = "c", rigid_carcass: bool | None = None) -> None:
        if isinstance(n_elements, bool) or not (isinstance(n_elements, int) and n_elements >= 2):
            raise InputError("must be an integer >= 2", field="n_elements", value=n_elements)
        if not (isinstance(tol, int | float) and np.isfinite(tol) and tol > 0):
            raise InputError("must be a finite number > 0", field="tol", value=tol)
        if backend not in ("c", "reference"):
            raise InputError("must be 'c' or 'reference'", field="backend", value=backend)
        self.params = params
        self.table = as_table(friction)
        self.n_elements = n_elements
        self.tol = float(tol)
        self.massless = bool(massless)
        self.backend = backend
        self.rigid_carcass = (params.carcass.rigid if rigid_carcass is None
                              else bool(rigid_carcass))
        self._P = ccore.core_params(params, n_elements=n_elements, dt_internal=1.0, tol=tol,
                                    v_floor=V_FLOOR, thermal=False, rigid=self.rigid_carcass,
                                    massless=massless)
        if backend == "c":
            self._lib = ccore.load()
            self._ctab = ccore.core_table(self.table)
        else:
            t = self.table
            self._rtab = RefTable(t.log10_v, t.T, t.log10_p, t.values, t.inv_s0)

    def solve(self, kappa: Any, alpha: Any, vx: Any, Fz: Any, T: Any,
              mu_scale: float = 1.0, *, gamma: Any = 0.0) -> BrushOutputs:
        """Steady state at slip ``kappa`` [1], slip angle ``alpha`` [rad], forward speed ``vx``
        [m/s] (> 0), load ``Fz`` [N], background temperature ``T`` [K] and inclination
        ``gamma`` [rad] (numpy broadcasting); returns :class:`~tire_brush.slip.BrushOutputs`
        of the broadcast shape.
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
        out = self.solve_velocities(Vsx, Vsy, Vr, Fz, T, mu_scale, gamma=gamma)
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
                         mu_scale: float = 1.0, *, gamma: Any = 0.0) -> BrushOutputs:
        """Steady state for slip velocities ``V_sx``, ``V_sy`` [m/s] of the contact point and
        rolling speed ``V_r`` [m/s] (any signs), load ``Fz`` [N], temperature ``T`` [K] and
        inclination ``gamma`` [rad] (the base of the tread spins at ``-(1 - eps) (V_r / R_e)
        sin(gamma)``, :class:`~tire_brush.params.CarcassParams`).

        The result's ``kappa`` and ``alpha`` are left at 0 (slips need a reference speed;
        :meth:`solve` fills them in). ``Mx = -delta_y Fz`` with the belt's steady lateral
        deflection ``delta_y = Fy / k_y`` (the tread's stress on the belt is Fy less the
        lateral momentum the tread carries out of the patch, a few per mille here); ``My``
        is 0 (no rolling-resistance model in the steady brush).
        """
        arrs = np.broadcast_arrays(*(np.asarray(x, float)
                                     for x in (V_sx, V_sy, V_r, Fz, T, gamma)))
        for name, x in zip(("V_sx", "V_sy", "V_r", "Fz", "T", "gamma"), arrs, strict=True):
            _finite(name, x)
        if (np.abs(arrs[5]) >= np.pi / 2).any():
            raise InputError("inclination angle must lie in (-pi/2, pi/2) rad", field="gamma",
                             value=arrs[5].tolist())
        shape = arrs[0].shape
        Vsx, Vsy, Vr, Fz_, T_, G_ = (x.ravel() for x in arrs)
        if (T_ <= 0).any():
            raise InputError("temperature must be > 0 K", field="T", value=T_.tolist())
        if not (np.isfinite(mu_scale) and mu_scale >= 0):
            raise InputError("must be a finite number >= 0", field="mu_scale", value=mu_scale)
        res = np.zeros((7, Vsx.size))
        for Tu in np.unique(T_):
            sel = np.flatnonzero(T_ == Tu)
            res[:, sel] = self._march(Vsx[sel], Vsy[sel], Vr[sel], Fz_[sel], float(Tu),
                                      float(mu_scale), G_[sel])
        Fx, Fy, Mz, mu_eff, mu_slide, frac, dT = (r.reshape(shape) for r in res)
        zero = np.zeros(shape)
        Mx = zero.copy() if self.rigid_carcass else -(Fy / self.params.carcass.k_y) * arrs[3]
        return BrushOutputs(Fx, Fy, Mz, zero, zero.copy(), mu_eff, mu_slide, frac, dT,
                            np.broadcast_to(arrs[4], shape).copy(), Mx, zero.copy())

    def _march(self, Vsx: np.ndarray, Vsy: np.ndarray, Vr: np.ndarray, Fz: np.ndarray,
               T: float, mu_scale: float, gamma: np.ndarray) -> np.ndarray:
        """Follow one element through the patch for every point (module docstring); rows
        ``Fx, Fy, Mz, mu_eff, mu_slide, sliding_fraction, dT_flash_max``."""
        pts = np.ascontiguousarray(np.stack([Vsx, Vsy, Vr, Fz, gamma], axis=1), dtype=float)
        n = pts.shape[0]
        if self.backend == "reference":
            out = np.array([steady_point(self._P, self._rtab, self.n_elements, *row[:4], T,
                                         mu_scale, row[4])
                            for row in pts.tolist()]).reshape(n, ccore.STEADY_OUT)
        else:
            out = np.zeros((n, ccore.STEADY_OUT))
            rc = self._lib.tf_steady(ctypes.byref(self._P), self._ctab.handle,
                                     self.n_elements, n, ccore._ptr(pts), float(T),
                                     float(mu_scale), ccore._ptr(out))
            if rc != 0:                               # inputs are checked above
                raise InputError("the tire core refused the operating points", field="points")
        return out[:, :7].T.copy()

    def patch_response(self, V_sx: Any, V_sy: Any, V_r: Any, Fz: Any, T: float,
                       gamma: Any = 0.0, mu_scale: float = 1.0) -> np.ndarray:
        """The march's results for points at one background temperature ``T`` [K]: rows
        ``Fx, Fy, Mz, mu_eff, mu_slide, sliding_fraction, dT_flash_max, sub-steps, friction
        power, M_belt`` (``tf_steady``'s outputs: the friction work on the road per unit time
        [W], the moment of the tread's stress on the belt [N m]), one column per point of the
        broadcast 1-d inputs. The real-time fidelity
        (:mod:`tire_brush.realtime`) tabulates these."""
        arrs = np.broadcast_arrays(*(np.atleast_1d(np.asarray(x, float))
                                     for x in (V_sx, V_sy, V_r, Fz, gamma)))
        for name, x in zip(("V_sx", "V_sy", "V_r", "Fz", "gamma"), arrs, strict=True):
            _finite(name, x)
        if not (np.isfinite(T) and T > 0):
            raise InputError("temperature must be > 0 K", field="T", value=T)
        if (np.abs(arrs[4]) >= np.pi / 2).any():
            raise InputError("inclination angle must lie in (-pi/2, pi/2) rad", field="gamma",
                             value=arrs[4].tolist())
        pts = np.ascontiguousarray(np.stack([x.ravel() for x in arrs], axis=1), dtype=float)
        n = pts.shape[0]
        if self.backend == "reference":
            return np.array([steady_point(self._P, self._rtab, self.n_elements, *row[:4], T,
                                          mu_scale, row[4])
                             for row in pts.tolist()]).reshape(n, ccore.STEADY_OUT).T.copy()
        out = np.zeros((n, ccore.STEADY_OUT))
        rc = self._lib.tf_steady(ctypes.byref(self._P), self._ctab.handle, self.n_elements, n,
                                 ccore._ptr(pts), float(T), float(mu_scale), ccore._ptr(out))
        if rc != 0:
            raise InputError("the tire core refused the operating points", field="points")
        return out.T.copy()
