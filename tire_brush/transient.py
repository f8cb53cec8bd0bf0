"""Transient brush tire: a state that advances in time, as a vehicle simulator steps it.

Inputs are what a simulator gives (:meth:`TransientBrushTire.step`): wheel-centre velocities
``vx`` (in the wheel plane), ``vy`` (lateral), spin ``omega``, load ``Fz`` and the background
temperature ``T_surface``, plus a road-friction scale. They are held over the step; the model
then advances with equal internal sub-steps no longer than ``dt_internal`` ("synchronize, then
advance", as Project Chrono's tires do). The state:

* **Brush elements carried through the patch.** Elements sit on a lattice of spacing
  ``dx = 2 a(Fz_nom) / n_elements`` that moves with the rolling speed ``omega R_e``
  (Lagrangian: no interpolation, no numerical diffusion). An element enters the patch
  undeflected (at ``x = a`` rolling forwards, at ``x = -a`` rolling backwards); within the step
  it is integrated only for the time it has been in contact; outside the patch its state is
  zero. Each element follows the implicit step of :mod:`tire_brush.element` (stick, or slide
  with eq. (28) friction, tip mass and damping), run by
  :class:`~tire_brush.element.LatticeStepper`, the fused form of
  :func:`~tire_brush.element.element_step` (bit-identical, fewer numpy calls). The patch size
  follows the load (:class:`~tire_brush.params.PatchLaw`): more or fewer lattice elements are
  in contact. Only the contact slice is stored; :meth:`TransientBrushTire.get_state` returns
  the whole lattice.
* **Carcass compliance.** A massless belt on springs and dampers against the rim
  (:class:`~tire_brush.params.CarcassParams`); the belt velocity adds to the slip velocity of the
  element bases. The belt equilibrium is solved implicitly with the tread's response linearised
  over the step (sticking elements: ``dtau/dV_b = -(k dt + d)``; sliding elements: unchanged
  stress). Forces then build up over a relaxation length ~ ``a + C_F / k_carcass`` (Pacejka
  2012, sec. 7.2); with a rigid carcass, ~ ``a``.
* **Tread temperature (optional).** ``C dT/dt = eta P_fric - G (T - T_surface)``, implicit
  Euler; it is the background temperature ``T0`` of the friction tables. Off: ``T0 =
  T_surface``.

Low-speed treatment (documented, no division by a speed anywhere in the dynamics): at
standstill (``omega = 0``, ``vx = vy = 0``) the elements keep their deflections, so a parked
tire holds its force; creeping and reversing move the lattice slowly or backwards; a wheel
that does not roll while the vehicle moves keeps its elements in the patch, they slide and
reach the hot branch (a locked wheel). Lift-off (``Fz <= 0``) empties the patch: forces are
exactly zero and the belt relaxes. Only the reported ``kappa`` and ``alpha`` use a speed floor
(:mod:`tire_brush.slip`). Non-finite inputs are refused (:class:`~lookup.errors.InputError`)
and leave the state unchanged.

The full state is available for co-simulation rollback: :meth:`TransientBrushTire.get_state`
returns copies of every array and number, :meth:`TransientBrushTire.set_state` restores it bit
for bit; stepping is deterministic.

This module imports only numpy and the standard library (and the stdlib-only
:mod:`lookup.errors`): it runs inside an FMU.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lookup.errors import InputError

from .element import CREEP_SPEED, ElementProps, LatticeStepper
from .friction import BranchTable, FrictionModel, as_table
from .params import TireParams
from .slip import V_FLOOR, BrushOutputs, slip_from_kinematics

#: Default number of elements on the patch at the nominal load.
N_TRANSIENT = 100
#: Default longest internal step [s].
DT_INTERNAL = 1e-3
#: Default friction evaluations per element step of the transient model.
N_NEWTON_TRANSIENT = 1
#: State format version (in :meth:`TransientBrushTire.get_state`).
STATE_VERSION = 1
#: Inputs of :meth:`TransientBrushTire.step`, in order, and the number types they accept.
_INPUT_NAMES = ("dt", "vx", "vy", "omega", "Fz", "T_surface", "mu_scale")
_NUMBER_TYPES = (int, float, np.floating, np.integer)


class TransientBrushTire:
    """Brush tire with elements carried through the patch, belt compliance and tread
    temperature (module docstring).

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
        self._inv_void = 1.0 / self._void
        c = params.carcass
        self._kd = (float(self.props.k[0, 0]), float(self.props.k[1, 0]),
                    float(self.props.d[0, 0]), float(self.props.d[1, 0]))
        self._kc = (c.k_x, c.k_y)
        self._dc = (c.d_x, c.d_y)
        th = params.thermal
        self._th = (th.heat_capacity, th.conductance, th.heat_fraction)
        self._kernel = LatticeStepper(self.props, self.table, n_newton)
        #: (Fz, a, b) of the last load seen: the patch size is a function of Fz only
        self._size = (math.nan, 0.0, 0.0)
        self.reset()

    # -- state ------------------------------------------------------------------------------
    def reset(self, T_tread: float | None = None) -> None:
        """Undeflected tire at rest; the tread temperature starts at ``T_tread`` [K] (default:
        the first step's ``T_surface``)."""
        self._E = np.zeros((5, 0))
        self._e0 = 0
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
        S = np.zeros((5, self.n_lattice))
        E, e0 = self._E, self._e0
        S[:, e0:e0 + E.shape[1]] = E
        return {"version": STATE_VERSION, "elements": S, "x_top": self._x_top,
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
        if version != STATE_VERSION or S.shape != (5, self.n_lattice) or delta.shape != (2,) or \
                Vb.shape != (2,) or F.shape != (2,) or out.shape != self._out.shape:
            raise InputError("state does not match this model (version or discretisation)",
                             field="state", value={"version": version, "elements": S.shape})
        self._E, self._e0, self._out = S, 0, out
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
        # fast path: seven Python floats with a finite sum are seven finite floats (a sum
        # that overflows takes the per-input check, which then passes)
        if not (type(dt) is float and type(vx) is float and type(vy) is float and
                type(omega) is float and type(Fz) is float and type(T_surface) is float and
                type(mu_scale) is float and math.isfinite(dt + vx + vy + omega + Fz + T_surface
                                                          + mu_scale)):
            for name, x in zip(_INPUT_NAMES, vals, strict=True):
                if not (isinstance(x, _NUMBER_TYPES) and math.isfinite(x)):
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
        vx, vy, omega = float(vx), float(vy), float(omega)
        T_surface, mu_scale = float(T_surface), float(mu_scale)
        R_e = self.params.R_e
        V_r = omega * R_e
        Vs = (vx - V_r, vy)
        if Fz != self._size[0]:
            self._size = (Fz, *self.params.patch.size(Fz))
        _, a, b = self._size
        last = None
        for _ in range(n_sub):
            last = self._advance(h, Vs, V_r, Fz, a, b, T_surface, mu_scale)
        self._time += dt
        kappa, alpha = slip_from_kinematics(vx, vy, omega, R_e, self.v_floor)
        T0 = self._T_tread if self.thermal else T_surface
        out = self._outputs(last, Fz, kappa, alpha, T0)
        self._out = np.array(out)
        return BrushOutputs(*out)

    def _advance(self, h: float, Vs: tuple[float, float], V_r: float, Fz: float, a: float,
                 b: float, T_surface: float, mu_scale: float) -> tuple | None:
        """One internal step of length ``h`` [s] (module docstring)."""
        dx = self.dx
        L = self.n_lattice
        # carry the lattice with the rolling speed; fresh (zero) elements fill in
        x_top = self._x_top - V_r * h
        shift = math.floor((x_top - self.a_max) / dx)
        x_top -= shift * dx
        self._x_top = x_top
        T0 = self._T_tread if self.thermal else T_surface
        area = b * dx
        # elements in contact, |x| < a, form the contiguous lattice slice i0:i1
        i0 = max(math.floor((x_top - a) / dx) + 1, 0)
        i1 = min(math.ceil((x_top + a) / dx), L)
        if i0 < i1 and x_top - i0 * dx >= a:
            i0 += 1
        if i0 < i1 and x_top - (i1 - 1) * dx <= -a:
            i1 -= 1
        # the new contact slice: its elements moved by ``shift`` cells; every other lattice
        # element is zero (fresh elements enter, elements that left the patch are cleared).
        # Only the slice is stored: lattice columns e0:e0+n hold E, the rest are zero.
        E_old, e0 = self._E, self._e0
        if not (a > 0.0 and area > 0.0 and i0 < i1):
            self._E, self._e0 = np.zeros((5, 0)), 0
            self._relax_belt(h)
            self._Vb = Vs
            self._F = (0.0, 0.0)
            self._heat(h, 0.0, T_surface)
            return None
        n = i1 - i0
        E = np.zeros((5, n))
        j0, j1 = max(i0, e0 - shift), min(i1, e0 + E_old.shape[1] - shift)
        if j0 < j1:                                   # lattice columns with an element to carry
            E[:, j0 - i0:j1 - i0] = E_old[:, j0 + shift - e0:j1 + shift - e0]
        self._E, self._e0 = E, i0
        x = x_top - self._offsets[i0:i1]
        # contact time within this step of elements that entered during it, as two equal
        # rows (the x and y coefficients of the element step)
        if V_r != 0.0:
            inv_vr = 1.0 / abs(V_r)
            dt2 = np.empty((2, n))
            dt_e = dt2[0]
            if V_r > 0.0:
                np.subtract(a, x, out=dt_e)
                dt_min = (a - float(x[0])) * inv_vr      # the element nearest the edge
            else:
                np.add(a, x, out=dt_e)
                dt_min = (a + float(x[-1])) * inv_vr
            dt_e *= inv_vr
            np.minimum(dt_e, h, out=dt_e)
            if not (dt_min >= 1e-12 and h >= 1e-12):   # else the floor changes nothing
                np.maximum(dt_e, 1e-12, out=dt_e)
            dt2[1] = dt_e
        else:
            dt_e = dt2 = h
        # parabolic pressure (:func:`~tire_brush.patch.parabolic_pressure`); |x| < a on the
        # slice, so |x (1/a)| <= 1 after rounding too and 1 - x^2/a^2 >= 0 needs no clamp
        p = x * (1.0 / a)
        p *= p
        np.subtract(1.0, p, out=p)
        total = float(np.add.reduce(p))
        if total > 0.0:
            p *= Fz / (area * total)
        query = self.table.prepare(T0, p * self._inv_void)
        V0 = np.hypot(E[2], E[3])
        Vb = Vs if self.rigid_carcass else self._belt_velocity(h, Vs, dt_e, V0, area)
        Vb2 = np.empty((2, n))
        Vb2[0].fill(Vb[0])
        Vb2[1].fill(Vb[1])
        pf = p if mu_scale == 1.0 else p * mu_scale    # p * 1.0 is p
        tau, friction, speed, cold, dT = self._kernel.step(E, pf, Vb2, dt2, dt_e, query, V0)
        self._Vb = (float(Vb[0]), float(Vb[1]))
        F = np.add.reduce(tau, 1).tolist()
        self._F = (F[0] * area, F[1] * area)
        if self.thermal:
            self._heat(h, float(np.dot(friction, speed)) * area, T_surface)
        return tau, friction, speed, cold, x, p, dT, area

    def _belt_velocity(self, h: float, Vs: tuple[float, float], dt: float | np.ndarray,
                       V0: np.ndarray, area: float) -> tuple[float, float]:
        """Belt velocity over the step from its implicit equilibrium (module docstring).

        The tread force over the step is linearised about the last one, ``F_n``: a sticking
        element changes its stress by ``-k dt V_b - d (V_b - V_b,n)``, a sliding one keeps it,
        so ``F(V_b) = F_n + D V_b,n - J V_b`` with ``J = sum (k dt + d) dA`` and
        ``D = sum d dA`` over the sticking elements. ``dt`` is the step of every element (a
        float, or one per element for elements that entered during the step).
        """
        n_stuck = float(V0.size - np.count_nonzero(V0))  # V0 == 0 (NaN counts as moving)
        # elements that entered during the step (dt_e < h) are fresh, hence sticking
        dt_stuck = h * n_stuck
        if isinstance(dt, np.ndarray):
            dt_stuck -= h * V0.size - float(np.add.reduce(dt))
        kx, ky, dx, dy = self._kd
        Dx, Dy = dx * n_stuck * area, dy * n_stuck * area
        Jx, Jy = kx * dt_stuck * area + Dx, ky * dt_stuck * area + Dy
        (Fx, Fy), (Vbx, Vby), (ex, ey) = self._F, self._Vb, self._delta
        kcx, kcy = self._kc
        dcx, dcy = self._dc
        Vsx, Vsy = Vs
        ux = (Fx + Dx * Vbx - Jx * Vsx - kcx * ex) / (kcx * h + dcx + Jx)
        uy = (Fy + Dy * Vby - Jy * Vsy - kcy * ey) / (kcy * h + dcy + Jy)
        self._delta = (ex + h * ux, ey + h * uy)
        return Vsx + ux, Vsy + uy

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
                 T0: float) -> list[float]:
        """Outputs (:data:`~tire_brush.slip.OUTPUT_UNITS` order) of the last sub-step."""
        if last is None:
            return [0.0, 0.0, 0.0, kappa, alpha, 0.0, 0.0, 0.0, 0.0, T0]
        tau, friction, speed, cold, x, p, dT, area = last
        F = self._F
        Mz = float(np.dot(x, tau[1])) * area
        sliding = speed > CREEP_SPEED
        frac = float(np.count_nonzero(sliding)) / x.size
        p_sl = float(np.dot(p, sliding))
        mu_slide = float(np.dot(friction, sliding)) / p_sl if p_sl > 0 else 0.0
        np.subtract(1.0, cold, out=cold)
        cold *= dT
        cold *= sliding
        dT_max = float(np.maximum.reduce(cold))
        mu_eff = math.hypot(F[0], F[1]) / Fz if Fz > 0 else 0.0
        return [F[0], F[1], Mz, kappa, alpha, mu_eff, mu_slide, frac, dT_max, T0]
