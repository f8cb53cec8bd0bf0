"""The transient brush tire before the fused element step, as a reference for the tests.

Provenance: ``TransientBrushTire`` of ``tire_brush/transient.py`` at commit 6786fb0, copied
unchanged apart from the class name and absolute imports. It advances the elements through
the unfused :func:`tire_brush.element.element_step` (the law the steady model uses too) with
:class:`~tire_brush.element.StepCoefficients` and
:func:`~tire_brush.patch.parabolic_pressure`; ``tests/test_brush_transient_fused.py`` pins the
fused :class:`~tire_brush.element.LatticeStepper` path of the shipped model to it bit for bit.
The element law itself is not copied: both paths share :func:`element_step`'s arithmetic
(including eq. (28)'s step-averaged cold weight), which ``LatticeStepper`` repeats operation
for operation.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lookup.errors import InputError
from tire_brush.element import CREEP_SPEED, ElementProps, StepCoefficients, element_step
from tire_brush.friction import BranchTable, FrictionModel, as_table
from tire_brush.params import TireParams
from tire_brush.patch import parabolic_pressure
from tire_brush.slip import V_FLOOR, BrushOutputs, slip_from_kinematics
from tire_brush.transient import DT_INTERNAL, N_NEWTON_TRANSIENT, N_TRANSIENT, STATE_VERSION


class UnfusedTransientTire:
    """:class:`tire_brush.transient.TransientBrushTire` as of commit 6786fb0, stepping
    through :func:`tire_brush.element.element_step` (module docstring).

    Parameters
    ----------
    params
        Tire parameters.
    friction
        A :class:`~tire_brush.friction.FrictionModel`, a
        :class:`~tire_brush.friction.BranchTable` or a :class:`lookup.grid.FrictionGrid`.
    n_elements
        Elements on the patch at the nominal load ``params.Fz_nom``.
    dt_internal
        Longest internal step [s].
    thermal
        Carry the tread temperature; default ``params.thermal.enabled``.
    rigid_carcass
        Ignore the belt compliance; default ``params.carcass.rigid``.
    massless
        Drop the tread tip mass and damping (Pacejka's brush).
    n_newton
        Friction evaluations per element step (:func:`~tire_brush.element.element_step`).
    v_floor
        Speed floor of the reported slips [m/s].
    """

    def __init__(self, params: TireParams, friction: FrictionModel | BranchTable | Any, *,
                 n_elements: int = N_TRANSIENT, dt_internal: float = DT_INTERNAL,
                 thermal: bool | None = None, rigid_carcass: bool | None = None,
                 massless: bool = False, n_newton: int = N_NEWTON_TRANSIENT,
                 v_floor: float = V_FLOOR) -> None:
        if not (isinstance(n_elements, int) and n_elements >= 2):
            raise InputError("must be an integer >= 2", field="n_elements", value=n_elements)
        if not (math.isfinite(dt_internal) and dt_internal > 0):
            raise InputError("must be a finite time > 0 s", field="dt_internal",
                             value=dt_internal)
        if not (math.isfinite(v_floor) and v_floor > 0):
            raise InputError("must be a finite speed > 0 m/s", field="v_floor", value=v_floor)
        self.params = params
        self.table = as_table(friction)
        self.props = ElementProps.from_tread(params.tread, massless=massless)
        if not (isinstance(n_newton, int) and n_newton >= 1):
            raise InputError("must be an integer >= 1", field="n_newton", value=n_newton)
        self.n_elements = n_elements
        self.n_newton = n_newton
        self.dt_internal = float(dt_internal)
        self.thermal = params.thermal.enabled if thermal is None else bool(thermal)
        self.rigid_carcass = params.carcass.rigid if rigid_carcass is None else bool(
            rigid_carcass)
        self.v_floor = float(v_floor)
        a_nom, _ = params.patch.size(params.Fz_nom)
        self.a_max, _ = params.patch.size(params.patch.Fz_max)
        self.dx = 2.0 * a_nom / n_elements
        #: lattice size: covers the largest patch plus one cell on either side
        self.n_lattice = math.ceil(2.0 * self.a_max / self.dx) + 2
        self._offsets = np.arange(self.n_lattice) * self.dx
        self._void = 1.0 - params.tread.void_ratio
        c = params.carcass
        self._kd = (float(self.props.k[0, 0]), float(self.props.k[1, 0]),
                    float(self.props.d[0, 0]), float(self.props.d[1, 0]))
        self._kc = (c.k_x, c.k_y)
        self._dc = (c.d_x, c.d_y)
        th = params.thermal
        self._th = (th.heat_capacity, th.conductance, th.heat_fraction)
        self.reset()

    # -- state ------------------------------------------------------------------------------
    def reset(self, T_tread: float | None = None) -> None:
        """Undeflected tire at rest; the tread temperature starts at ``T_tread`` [K] (default:
        the first step's ``T_surface``)."""
        self._S = np.zeros((5, self.n_lattice))
        self._x_top = self.a_max
        self._delta = (0.0, 0.0)
        self._Vb = (0.0, 0.0)
        self._F = (0.0, 0.0)
        self._T_tread = math.nan if T_tread is None else float(T_tread)
        self._time = 0.0
        self._out = np.zeros(len(BrushOutputs.__dataclass_fields__))

    def get_state(self) -> dict[str, np.ndarray | float | int]:
        """The full internal state (copies): element states, lattice phase, belt deflection
        and velocity, last tread force, tread temperature, time and the last outputs."""
        return {"version": STATE_VERSION, "elements": self._S.copy(), "x_top": self._x_top,
                "delta": np.array(self._delta), "Vb": np.array(self._Vb),
                "F": np.array(self._F),
                "T_tread": self._T_tread, "time": self._time, "outputs": self._out.copy()}

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (bit for bit)."""
        try:
            version = int(state["version"])
            S = np.array(state["elements"], dtype=float)
            delta = np.array(state["delta"], dtype=float)
            Vb = np.array(state["Vb"], dtype=float)
            F = np.array(state["F"], dtype=float)
            out = np.array(state["outputs"], dtype=float)
            x_top, T_tread, time = (float(state[k]) for k in ("x_top", "T_tread", "time"))
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"not a state of this model ({exc!r})", field="state") from None
        if version != STATE_VERSION or S.shape != self._S.shape or delta.shape != (2,) or \
                Vb.shape != (2,) or F.shape != (2,) or out.shape != self._out.shape:
            raise InputError("state does not match this model (version or discretisation)",
                             field="state", value={"version": version, "elements": S.shape})
        self._S, self._out = S, out
        self._delta = (float(delta[0]), float(delta[1]))
        self._Vb = (float(Vb[0]), float(Vb[1]))
        self._F = (float(F[0]), float(F[1]))
        self._x_top, self._T_tread, self._time = x_top, T_tread, time

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._time

    @property
    def outputs(self) -> BrushOutputs:
        """Outputs at the end of the last step."""
        return BrushOutputs.from_array(self._out)

    def element_positions(self) -> np.ndarray:
        """Current positions of the lattice elements along the patch [m]."""
        return self._x_top - self._offsets

    # -- stepping ---------------------------------------------------------------------------
    def step(self, dt: float, vx: float, vy: float, omega: float, Fz: float, T_surface: float,
             mu_scale: float = 1.0) -> BrushOutputs:
        """Advance by ``dt`` [s] with inputs held over the step.

        Parameters
        ----------
        dt
            Step [s], >= 0 (0 returns the current outputs).
        vx, vy
            Wheel-centre velocity in the wheel plane and lateral [m/s].
        omega
            Wheel spin [rad/s].
        Fz
            Vertical load [N]; ``Fz <= 0`` is lift-off.
        T_surface
            Background tread/road temperature [K] (> 0).
        mu_scale
            Road friction scale [1] (>= 0) multiplying both branches.

        Returns
        -------
        BrushOutputs
            Forces and diagnostics at the end of the step.
        """
        vals = (dt, vx, vy, omega, Fz, T_surface, mu_scale)
        names = ("dt", "vx", "vy", "omega", "Fz", "T_surface", "mu_scale")
        for name, x in zip(names, vals, strict=True):
            if not (isinstance(x, int | float | np.floating | np.integer) and math.isfinite(x)):
                raise InputError("must be a finite number", field=name, value=x)
        if dt < 0 or T_surface <= 0 or mu_scale < 0:
            raise InputError("need dt >= 0 s, T_surface > 0 K and mu_scale >= 0",
                             field="step", value={"dt": dt, "T_surface": T_surface,
                                                  "mu_scale": mu_scale})
        if math.isnan(self._T_tread):
            self._T_tread = float(T_surface)
        if dt == 0:
            return self.outputs
        n_sub = max(1, math.ceil(dt / self.dt_internal - 1e-9))
        h = dt / n_sub
        Fz = max(float(Fz), 0.0)
        V_r = float(omega) * self.params.R_e
        Vs = np.array([float(vx) - V_r, float(vy)])
        a, b = self.params.patch.size(Fz)
        last = None
        for _ in range(n_sub):
            last = self._advance(h, Vs, V_r, Fz, a, b, float(T_surface), float(mu_scale))
        self._time += dt
        kappa, alpha = slip_from_kinematics(float(vx), float(vy), float(omega),
                                            self.params.R_e, self.v_floor)
        T0 = self._T_tread if self.thermal else float(T_surface)
        self._out = self._outputs(last, Fz, kappa, alpha, T0)
        return self.outputs

    def _advance(self, h: float, Vs: np.ndarray, V_r: float, Fz: float, a: float, b: float,
                 T_surface: float, mu_scale: float) -> tuple | None:
        """One internal step of length ``h`` [s] (module docstring)."""
        S = self._S
        dx = self.dx
        # carry the lattice with the rolling speed; fresh (zero) elements fill in
        x_top = self._x_top - V_r * h
        shift = math.floor((x_top - self.a_max) / dx)
        if shift:
            n = abs(shift)
            if n >= self.n_lattice:
                S[...] = 0.0
            elif shift < 0:
                S[:, n:] = S[:, :-n]
                S[:, :n] = 0.0
            else:
                S[:, :-n] = S[:, n:]
                S[:, -n:] = 0.0
            x_top -= shift * dx
        self._x_top = x_top
        T0 = self._T_tread if self.thermal else T_surface
        area = b * dx
        # elements in contact, |x| < a, form the contiguous lattice slice i0:i1
        i0 = max(math.floor((x_top - a) / dx) + 1, 0)
        i1 = min(math.ceil((x_top + a) / dx), self.n_lattice)
        if i0 < i1 and x_top - i0 * dx >= a:
            i0 += 1
        if i0 < i1 and x_top - (i1 - 1) * dx <= -a:
            i1 -= 1
        S[:, :i0] = 0.0
        S[:, i1:] = 0.0
        if not (a > 0.0 and area > 0.0 and i0 < i1):
            S[...] = 0.0
            self._relax_belt(h)
            self._Vb = (float(Vs[0]), float(Vs[1]))
            self._F = (0.0, 0.0)
            self._heat(h, 0.0, T_surface)
            return None
        E = S[:, i0:i1]                                    # view: updated in place
        x = x_top - self._offsets[i0:i1]
        # contact time within this step of elements that entered during it
        if V_r != 0.0:
            dt_e = (a - math.copysign(1.0, V_r) * x) * (1.0 / abs(V_r))
            np.minimum(dt_e, h, out=dt_e)
            np.maximum(dt_e, 1e-12, out=dt_e)
            co = StepCoefficients.build(self.props, dt_e)
        else:
            co = StepCoefficients.build(self.props, h)
        p = parabolic_pressure(x, a, Fz, area)
        query = self.table.prepare(T0, p * (1.0 / self._void))
        V0 = np.hypot(E[2], E[3])
        if self.rigid_carcass:
            Vb = Vs[:, None]
        else:
            Vb = self._belt_velocity(h, Vs, co, V0, area)[:, None]
        r = element_step(E, p * mu_scale, Vb, self.props, co, self.table, query,
                         n_newton=self.n_newton, V0=V0)
        self._Vb = (float(Vb[0, 0]), float(Vb[1, 0]))
        F = r.tau.sum(axis=1)
        self._F = (float(F[0]) * area, float(F[1]) * area)
        if self.thermal:
            self._heat(h, float(np.dot(r.friction, r.speed)) * area, T_surface)
        return r, x, p, r.dT_flash, area

    def _belt_velocity(self, h: float, Vs: np.ndarray, co: StepCoefficients, V0: np.ndarray,
                       area: float) -> np.ndarray:
        """Belt velocity over the step from its implicit equilibrium (module docstring).

        The tread force over the step is linearised about the last one, ``F_n``: a sticking
        element changes its stress by ``-k dt V_b - d (V_b - V_b,n)``, a sliding one keeps it,
        so ``F(V_b) = F_n + D V_b,n - J V_b`` with ``J = sum (k dt + d) dA`` and
        ``D = sum d dA`` over the sticking elements.
        """
        n_stuck = float(np.count_nonzero(V0 == 0.0))
        # elements that entered during the step (dt_e < h) are fresh, hence sticking
        dt_stuck = h * n_stuck
        if np.ndim(co.dt):
            dt_stuck -= h * V0.size - float(co.dt.sum())
        kx, ky, dx, dy = self._kd
        Dx, Dy = dx * n_stuck * area, dy * n_stuck * area
        Jx, Jy = kx * dt_stuck * area + Dx, ky * dt_stuck * area + Dy
        (Fx, Fy), (Vbx, Vby), (ex, ey) = self._F, self._Vb, self._delta
        kcx, kcy = self._kc
        dcx, dcy = self._dc
        Vsx, Vsy = float(Vs[0]), float(Vs[1])
        ux = (Fx + Dx * Vbx - Jx * Vsx - kcx * ex) / (kcx * h + dcx + Jx)
        uy = (Fy + Dy * Vby - Jy * Vsy - kcy * ey) / (kcy * h + dcy + Jy)
        self._delta = (ex + h * ux, ey + h * uy)
        return np.array([Vsx + ux, Vsy + uy])

    def _relax_belt(self, h: float) -> None:
        """Belt without tread force: implicit relaxation towards zero deflection."""
        if self.rigid_carcass:
            return
        self._delta = tuple(e * dc / (kc * h + dc) for e, kc, dc in
                            zip(self._delta, self._kc, self._dc, strict=True))

    def _heat(self, h: float, power: float, T_surface: float) -> None:
        """Implicit Euler step of the lumped tread temperature."""
        if not self.thermal:
            return
        C, G, eta = self._th
        self._T_tread = (self._T_tread + h / C * (eta * power + G * T_surface)) / (
            1.0 + h * G / C)

    def _outputs(self, last: tuple | None, Fz: float, kappa: float, alpha: float,
                 T0: float) -> np.ndarray:
        """Output array (:data:`~tire_brush.slip.OUTPUT_UNITS` order) of the last sub-step."""
        if last is None:
            return np.array([0.0, 0.0, 0.0, kappa, alpha, 0.0, 0.0, 0.0, 0.0, T0])
        r, x, p, dT, area = last
        F = self._F
        Mz = float(np.dot(x, r.tau[1])) * area
        sliding = r.speed > CREEP_SPEED
        frac = float(sliding.sum()) / x.size
        p_sl = float(np.dot(p, sliding))
        mu_slide = float(np.dot(r.friction, sliding)) / p_sl if p_sl > 0 else 0.0
        dT_max = float((dT * (1.0 - r.cold) * sliding).max())
        mu_eff = math.hypot(F[0], F[1]) / Fz if Fz > 0 else 0.0
        return np.array([F[0], F[1], Mz, kappa, alpha, mu_eff, mu_slide, frac, dT_max, T0])
