"""Transient brush tire: a state that advances in time, as a vehicle simulator steps it.

Inputs are what a simulator gives (:meth:`TransientBrushTire.step`): wheel-centre velocities
``vx`` (in the wheel plane), ``vy`` (lateral), spin ``omega``, load ``Fz`` and the background
temperature ``T_surface``, plus a road-friction scale. They are held over the step; the model
then advances with equal outer steps no longer than ``dt_internal`` ("synchronize, then
advance", as Project Chrono's tires do). The state:

* **Brush elements carried through the patch.** Elements sit on a lattice of spacing
  ``dx = 2 a(Fz_nom) / n_elements`` that moves with the rolling speed ``omega R_e``
  (Lagrangian: no interpolation, no numerical diffusion). An element enters the patch with
  its tip moving with the belt (undeflected, slip velocity ``V_b``: its kinematic velocity)
  at the moment it crosses the leading edge; it is integrated only for the time it has been in
  contact. Within an outer step each element is integrated with its own error-controlled
  sub-steps (:mod:`tire_brush.element`, docs/tire-core.md): stick, or slide with eq. (28)
  friction, tip mass and damping, with the pressure following the element along the patch.
  The result converges as ``dt_internal``, ``n_elements`` and ``tol`` shrink, and the
  defaults are within 1 % of the converged forces (tests).
* **Carcass compliance.** A massless belt on springs and dampers against the rim
  (:class:`~tire_brush.params.CarcassParams`); the belt velocity adds to the slip velocity of
  the element bases. It is coupled linearly implicitly, every element (sticking or sliding)
  stiffening it (docs/tire-core.md). Forces then build up over a relaxation length ~ ``a +
  C_F / k_carcass`` (Pacejka 2012, sec. 7.2); with a rigid carcass, ~ ``a``.
* **Tread temperature (optional).** ``C dT/dt = eta P_fric - G (T - T_surface)``, implicit
  Euler with the friction work of the step integrated element by element; it is the
  background temperature ``T0`` of the friction tables. Off: ``T0 = T_surface``.

Low speed: at standstill (``omega = 0``, ``vx = vy = 0``) the elements keep their deflections,
so a parked tire holds its force (or creeps, where Persson's mu(v) has no static friction:
docs/physics.md); a wheel that does not roll while the vehicle moves keeps its elements in the
patch, they slide and reach the hot branch (a locked wheel). Lift-off (``Fz <= 0``) empties
the patch: forces are exactly zero and the belt relaxes. Only the reported ``kappa`` and
``alpha`` use a speed floor (:mod:`tire_brush.slip`). Non-finite inputs are refused
(:class:`~tirefric.errors.InputError`) and leave the state unchanged.

The stepping runs in the compiled core (:mod:`tire_brush.ccore`, C99); ``backend =
"reference"`` runs the same algorithm in Python floats (:class:`tire_brush.element.RefTire`),
bit for bit equal and ~300x slower. The full state is available for co-simulation rollback:
:meth:`TransientBrushTire.get_state` returns copies, :meth:`TransientBrushTire.set_state`
restores them bit for bit; stepping is deterministic.

This module imports only numpy and the standard library (and the stdlib-only
:mod:`tirefric.errors`): it runs inside an FMU.
"""

from __future__ import annotations

import ctypes
import math
from typing import Any

import numpy as np

from tirefric.errors import InputError

from . import ccore
from .element import N_ELEM, STATE_HEAD, STATE_VERSION, RefTable, RefTire, RefWet
from .friction import BranchTable, FrictionModel, as_table
from .hydroplaning import D_FULL
from .params import TireParams
from .realtime import PatchEval, PatchTable
from .signals import INPUT_NAMES
from .slip import V_FLOOR, BrushOutputs

#: Default number of elements on the patch at the nominal load.
N_TRANSIENT = 32
#: Default longest outer step [s]: the belt coupling settles an abrupt input change without
#: overshoot at 0.25 ms (docs/tire-core.md); the elements sub-step inside it anyway.
DT_INTERNAL = 2.5e-4
#: Default local error tolerance of the element integration [1] (a fraction of the mean
#: footprint pressure per sub-step; docs/tire-core.md).
TOL = 1e-2
#: Inputs of :meth:`TransientBrushTire.step`, in order, and the number types they accept.
_INPUT_NAMES = ("dt", *INPUT_NAMES)
#: Slice of the outputs in the state vector (docs/tire-core.md, "state").
_OUT = slice(11, 11 + ccore.N_OUT)
_NUMBER_TYPES = (int, float, np.floating, np.integer)
#: Backends of the stepping.
BACKENDS = ("c", "reference")


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
        Longest outer step [s] (belt coupling and lattice transport); the core takes shorter
        ones where the belt coupling needs them (:func:`tire_brush.element.outer_step`).
    thermal
        Carry the tread temperature; default ``params.thermal.enabled``.
    rigid_carcass
        Ignore the belt compliance; default ``params.carcass.rigid``.
    massless
        Drop the tread tip mass and damping (Pacejka's brush).
    tol
        Local error tolerance of the element integration [1] (docs/tire-core.md).
    v_floor
        Speed floor of the reported slips [m/s].
    backend
        ``"c"`` (the compiled core) or ``"reference"`` (the same algorithm in Python).
    patch
        A :class:`~tire_brush.realtime.PatchTable` (built for these parameters and this
        friction by :func:`tire_brush.realtime_build.build_patch_table`) selects the real-time
        fidelity: the quasi-steady patch on the belt's dynamics (docs/realtime.md); None (the
        default) the full one.
    """

    def __init__(self, params: TireParams, friction: FrictionModel | BranchTable | Any, *,
                 n_elements: int = N_TRANSIENT, dt_internal: float = DT_INTERNAL,
                 thermal: bool | None = None, rigid_carcass: bool | None = None,
                 massless: bool = False, tol: float = TOL, v_floor: float = V_FLOOR,
                 backend: str = "c", patch: PatchTable | None = None) -> None:
        if isinstance(n_elements, bool) or not (isinstance(n_elements, int) and n_elements >= 2):
            raise InputError("must be an integer >= 2", field="n_elements", value=n_elements)
        for name, x in (("dt_internal", dt_internal), ("tol", tol), ("v_floor", v_floor)):
            if not (isinstance(x, _NUMBER_TYPES) and math.isfinite(x) and x > 0):
                raise InputError("must be a finite number > 0", field=name, value=x)
        if backend not in BACKENDS:
            raise InputError(f"must be one of {BACKENDS}", field="backend", value=backend)
        self.params = params
        self.table = as_table(friction)
        self.n_elements = n_elements
        self.dt_internal = float(dt_internal)
        self.tol = float(tol)
        self.thermal = params.thermal.enabled if thermal is None else bool(thermal)
        self.rigid_carcass = params.carcass.rigid if rigid_carcass is None else bool(
            rigid_carcass)
        self.massless = bool(massless)
        self.v_floor = float(v_floor)
        self.backend = backend
        self._P = ccore.core_params(params, n_elements=n_elements, dt_internal=dt_internal,
                                    tol=tol, v_floor=v_floor, thermal=self.thermal,
                                    rigid=self.rigid_carcass, massless=massless)
        t = self.table
        if backend == "c":
            self._lib = ccore.load()
            self._ctab = ccore.core_table(t)
            handle = self._lib.tf_tire_new(ctypes.byref(self._P), self._ctab.handle)
            if not handle:
                raise InputError("the tire core refused these parameters", field="params",
                                 value=params.name)
            self._h = handle
            self.n_lattice = int(self._lib.tf_tire_lattice(handle))
            self._in = np.zeros(ccore.N_IN)
            self._out = np.zeros(ccore.N_OUT)
            self._pin = ccore._ptr(self._in)
            self._pout = ccore._ptr(self._out)
            self._step = self._lib.tf_tire_step
        else:
            self._ref = RefTire(self._P, RefTable(t.log10_v, t.T, t.log10_p, t.values,
                                                  t.inv_s0))
            self.n_lattice = self._ref.L
        self.patch = patch
        self.fidelity = "full" if patch is None else "realtime"
        if patch is not None:
            if not isinstance(patch, PatchTable):
                raise InputError("must be a tire_brush.realtime.PatchTable", field="patch",
                                 value=type(patch).__name__)
            if backend == "c":
                self._cpatch = ccore.core_patch(patch)
                self._lib.tf_tire_set_patch(self._h, self._cpatch.handle)
            else:
                self._ref.patch = PatchEval(patch)
        a_nom, _ = params.patch.size(params.Fz_nom)
        self.dx = 2.0 * a_nom / n_elements
        self.a_max, _ = params.patch.size(params.patch.Fz_max)
        self._state_size = STATE_HEAD + N_ELEM * self.n_lattice
        self.rolling = None
        self.wet = None

    def set_wet(self, wet: Any | None, *, texture_depth: float = 0.0,
                d_full: float = D_FULL, drain_scale: float = 1.0) -> None:
        """Give the tire the wet branch of its grid (or ``None``: every water depth is dry).

        Parameters
        ----------
        wet
            A :class:`lookup.grid.wet.WetGrid` on the nodes of this tire's friction table.
        texture_depth
            The road's mean texture depth [m]: water the texture holds below the tire
            (hydroplaning starts above ``void_ratio * tread.depth + texture_depth``).
        d_full
            Excess depth [m] of full hydroplaning (:mod:`tire_brush.hydroplaning`).
        drain_scale
            ``(D / 2R)^2`` of the drainage time (:func:`tire_brush.wet_friction.drainage_time`;
            1: the water leaves each macro-asperity contact over D / 2).

        With water of depth ``d > 0`` (the step's ``water_depth``), the elements read
        ``mu = (1 - w) mu_w0 + w mu_w1`` of the wet branch at ``d`` and at the drainage time
        ``drain_scale * 2a / U`` (the water film's time under the footprint at the
        entrainment speed ``U = (|vx| + |V_r|) / 2``, :mod:`tire_brush.wet_friction`), exact
        at the grid's (v, T, p) nodes (:func:`tire_brush.wet_friction.wet_branch_table`), and the
        water carries Horne's share of the load (:mod:`tire_brush.hydroplaning`).
        """
        if wet is None:
            self.wet = None
            if self.backend == "c":
                self._lib.tf_tire_set_wet(self._h, None, 0.0)
                self._cwet = None
            else:
                self._ref.set_wet(None)
            return
        t = self.table
        for name, a, b in (("log10_v", t.log10_v, wet.axes["log10_v"]), ("T", t.T, wet.axes["T"]),
                           ("log10_p", t.log10_p, wet.axes["log10_p"])):
            if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-9):
                raise InputError("the wet branch has other nodes than the friction table",
                                 field=name)
        v = wet.variables
        mu = np.stack([v["mu_wet_cold_w0"], v["mu_wet_cold_w1"], v["mu_wet_hot_w0"],
                       v["mu_wet_hot_w1"]], axis=-1)
        self.set_wet_arrays(wet.axes["water_depth"], wet.axes["log10_t_drain"], mu,
                            v["w_dry"], texture_depth=texture_depth, d_full=d_full,
                            drain_scale=drain_scale)
        self.wet = wet

    def set_wet_arrays(self, depth: Any, log10_t: Any, mu: Any, w_dry: Any, *,
                       texture_depth: float, d_full: float, drain_scale: float) -> None:
        """:meth:`set_wet` from the arrays of the wet branch on this tire's table nodes:
        ``depth`` [m] (first 0), ``log10_t`` [log10 s], ``mu`` of shape (nd, nv, nT, np, 4)
        (cold_w0, cold_w1, hot_w0, hot_w1) and ``w_dry`` (nd, nt, nv, nT, np)."""
        t = self.table
        depth = np.ascontiguousarray(depth, float)
        lt = np.ascontiguousarray(log10_t, float)
        mu = np.ascontiguousarray(mu, float)
        w_dry = np.ascontiguousarray(w_dry, float)
        nodes = (t.log10_v.size, t.T.size, t.log10_p.size)
        if mu.shape != (depth.size, *nodes, 4) or w_dry.shape != (depth.size, lt.size, *nodes):
            raise InputError("wet branch arrays do not match the friction table's nodes",
                             field="wet", value={"mu": mu.shape, "w_dry": w_dry.shape})
        for name, x, ok in (("texture_depth", texture_depth, texture_depth >= 0),
                            ("d_full", d_full, d_full > 0),
                            ("drain_scale", drain_scale, drain_scale > 0)):
            if not (math.isfinite(x) and ok):
                raise InputError("out of range", field=name, value=x)
        if self.backend == "c":
            mu = np.ascontiguousarray(mu, float)
            handle = self._lib.tf_wet_new(t.log10_v.size, t.T.size, t.log10_p.size,
                                          depth.size, lt.size,
                                          ccore._ptr(depth), ccore._ptr(lt), ccore._ptr(mu),
                                          ccore._ptr(w_dry), float(d_full),
                                          float(drain_scale))
            if not handle:
                raise InputError("the tire core refused the wet branch (mu >= 0 and finite, "
                                 "depth axis from 0)", field="wet")
            cw = ccore.CoreWet(handle, self._lib)
            if self._lib.tf_tire_set_wet(self._h, cw.handle,
                                         float(texture_depth)) != 0:  # pragma: no cover
                raise InputError("the tire core refused the wet branch", field="wet")
            self._cwet = cw                     # the core holds a pointer: keep it alive
        else:
            self._ref.set_wet(RefWet(self._ref.t.n, depth.tolist(), lt.tolist(),
                                     mu.reshape(-1).tolist(), w_dry.reshape(-1).tolist(),
                                     d_full, drain_scale), float(texture_depth))
        self.wet = True

    def set_rolling(self, table: Any | None) -> None:
        """Give the tire a rolling-resistance table (or ``None`` to remove it).

        Parameters
        ----------
        table
            An object with attributes ``log10_v`` (rolling speed |V_r| [m/s], log10), ``T``
            (tread temperature [K]), ``log10_Fz`` (load [N], log10), strictly ascending with
            >= 2 nodes each, and ``f_r``, ``tread_share`` of shape ``(nV, nT, nFz)``: the
            coefficient ``F_r / Fz`` [1] and the share of the loss dissipated in the tread
            [1]. The core interpolates trilinearly (clamped; proportional to |V_r| below the
            first speed node) and outputs ``My = f_r Fz R_e`` against the spin; the tread's
            share of ``F_r |V_r|`` heats the tread temperature.
        """
        if table is None:
            self.rolling = None
            if self.backend == "c":
                self._lib.tf_tire_set_rolling(self._h, None)
                self._rtab = None
            else:
                self._ref.set_rolling(None)
            return
        f_r = np.asarray(table.f_r, float)
        share = np.asarray(table.tread_share, float)
        axes = [np.asarray(a, float) for a in (table.log10_v, table.T, table.log10_Fz)]
        shape = tuple(a.size for a in axes)
        if f_r.shape != shape or share.shape != shape or not (
                np.isfinite(f_r).all() and (f_r >= 0).all() and np.isfinite(share).all()
                and ((share >= 0) & (share <= 1)).all()):
            raise InputError("rolling-resistance table: f_r >= 0 and tread_share in [0, 1], "
                             f"finite, of shape {shape}", field="rolling",
                             value={"f_r": f_r.shape, "tread_share": share.shape})
        values = np.stack([f_r, share, np.zeros_like(f_r)], axis=-1)
        if self.backend == "c":
            ct = ccore.CoreTable(axes[0], axes[1], axes[2], values, 0.0)
            self._lib.tf_tire_set_rolling(self._h, ct.handle)
            self._rtab = ct                     # the core holds a pointer: keep it alive
        else:
            self._ref.set_rolling(RefTable(axes[0], axes[1], axes[2], values, 0.0))
        self.rolling = table

    def __del__(self) -> None:
        h = getattr(self, "_h", None)
        if h:
            self._lib.tf_tire_free(h)
            self._h = None

    # -- state ------------------------------------------------------------------------------
    def reset(self, T_tread: float | None = None) -> None:
        """Undeflected tire at rest; the tread temperature starts at ``T_tread`` [K] (default:
        the first step's ``T_surface``)."""
        T = math.nan if T_tread is None else float(T_tread)
        if self.backend == "c":
            self._lib.tf_tire_reset(self._h, T)
        else:
            self._ref.reset(T)

    def state_vector(self) -> np.ndarray:
        """The full state as the core's flat vector (docs/tire-core.md, "state")."""
        if self.backend == "c":
            buf = np.zeros(self._state_size)
            self._lib.tf_tire_get_state(self._h, ccore._ptr(buf))
            return buf
        return np.array(self._ref.get_state())

    def get_state(self) -> dict[str, np.ndarray | float | int]:
        """The full internal state (copies): element states, lattice phase, belt deflection
        and velocity, last tread force, tread temperature, time, the last outputs, the
        belt's yaw (angle ``psi``, rate ``wpsi``, tread moment on it ``M``) and the spin of
        the base from camber in the last step (``wc``)."""
        b = self.state_vector()
        k = _OUT.stop
        return {"version": STATE_VERSION, "elements": b[STATE_HEAD:].reshape(-1, N_ELEM).copy(),
                "x_top": float(b[2]), "delta": b[3:5].copy(), "Vb": b[5:7].copy(),
                "F": b[7:9].copy(), "T_tread": float(b[9]), "time": float(b[10]),
                "outputs": b[_OUT].copy(), "psi": float(b[k]), "wpsi": float(b[k + 1]),
                "M": float(b[k + 2]), "wc": float(b[k + 3])}

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (bit for bit)."""
        try:
            version = int(state["version"])
            S = np.array(state["elements"], dtype=float)
            parts = [np.array(state[k], dtype=float).reshape(-1)
                     for k in ("delta", "Vb", "F", "outputs")]
            x_top, T_tread, time, psi, wpsi, M, wc = (float(state[k]) for k in (
                "x_top", "T_tread", "time", "psi", "wpsi", "M", "wc"))
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"not a state of this model ({exc!r})", field="state") from None
        if version != STATE_VERSION or S.shape != (self.n_lattice, N_ELEM) or \
                [p.size for p in parts] != [2, 2, 2, ccore.N_OUT]:
            raise InputError("state does not match this model (version or discretisation)",
                             field="state", value={"version": version, "elements": S.shape})
        buf = np.concatenate([[float(STATE_VERSION), float(self.n_lattice), x_top],
                              parts[0], parts[1], parts[2], [T_tread, time], parts[3],
                              [psi, wpsi, M, wc], S.reshape(-1)])
        if not np.isfinite(np.delete(buf, 9)).all():
            raise InputError("state holds non-finite numbers", field="state")
        if self.backend == "c":
            if self._lib.tf_tire_set_state(self._h, ccore._ptr(buf)) != 0:
                raise InputError("the tire core refused the state", field="state")
        else:
            self._ref.set_state(buf.tolist())

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.state_vector()[10])

    @property
    def outputs(self) -> BrushOutputs:
        """Outputs at the end of the last step."""
        return BrushOutputs.from_array(self.state_vector()[_OUT])

    def element_positions(self) -> np.ndarray:
        """Current positions of the lattice elements along the patch [m]."""
        return float(self.state_vector()[2]) - np.arange(self.n_lattice) * self.dx

    def work(self) -> float:
        """Element sub-steps taken so far (a measure of the integration's work)."""
        if self.backend == "c":
            return float(self._lib.tf_tire_work(self._h))
        return self._ref.work

    def counters(self) -> dict[str, float]:
        """Work since creation (docs/tire-core.md, "work budget"): element ``substeps``
        taken, ``stages`` solved (two per SDIRK attempt, accepted or not, one per event step
        or budget fallback) and ``fallbacks`` (elements that finished an outer step with one
        implicit Euler stage because its budget was spent)."""
        if self.backend == "c":
            buf = np.zeros(ccore.N_COUNT)
            self._lib.tf_tire_counters(self._h, ccore._ptr(buf))
            n, st, fb = buf.tolist()
        else:
            n, st, fb = self._ref.work, self._ref.stages, self._ref.fallbacks
        return {"substeps": n, "stages": st, "fallbacks": fb}

    @property
    def flags(self) -> int:
        """Flags of the last step (:data:`tire_brush.element.FLAG_BUDGET`: an outer step's
        work budget was spent and its remaining elements finished with one implicit Euler
        stage; :data:`tire_brush.element.FLAG_T_RANGE`: the friction was read at a
        temperature outside the table's temperature axis, i.e. at its edge's values)."""
        if self.backend == "c":
            return int(self._lib.tf_tire_flags(self._h))
        return self._ref.flags

    # -- stepping ---------------------------------------------------------------------------
    def step(self, dt: float, vx: float, vy: float, omega: float, Fz: float, T_surface: float,
             mu_scale: float = 1.0, gamma: float = 0.0,
             water_depth: float = 0.0) -> BrushOutputs:
        """Advance by ``dt`` [s] with inputs held over the step.

        Parameters
        ----------
        dt
            Step [s], >= 0; a step shorter than :data:`~tire_brush.element.DT_FLOOR`
            (1 ns, subnormal included) only advances the clock and returns the current
            outputs (nothing in the model moves in 1 ns: outputs are continuous as dt -> 0).
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
        gamma
            Inclination (camber) angle [rad], ``|gamma| < pi/2`` (docs/axes.md: the same sign
            in every axis system): the base of the tread spins at ``-(1 - eps) omega
            sin(gamma)`` (:class:`~tire_brush.params.CarcassParams`).
        water_depth
            Water film depth on the road [m] (>= 0; 0: dry), read through the wet branch
            (:meth:`set_wet`; without one the road is dry whatever the depth).

        Returns
        -------
        BrushOutputs
            Forces and diagnostics at the end of the step.
        """
        return BrushOutputs(*self.step_array(dt, vx, vy, omega, Fz, T_surface, mu_scale,
                                             gamma, water_depth))

    def step_array(self, dt: float, vx: float, vy: float, omega: float, Fz: float,
                   T_surface: float, mu_scale: float = 1.0, gamma: float = 0.0,
                   water_depth: float = 0.0) -> list[float]:
        """:meth:`step` returning the outputs as a list in
        :data:`~tire_brush.slip.OUTPUT_UNITS` order (no dataclass: the FMU's fast path)."""
        vals = (dt, vx, vy, omega, Fz, T_surface, mu_scale, gamma, water_depth)
        if not (type(dt) is float and type(vx) is float and type(vy) is float and
                type(omega) is float and type(Fz) is float and type(T_surface) is float and
                type(mu_scale) is float and type(gamma) is float and
                type(water_depth) is float and
                math.isfinite(dt + vx + vy + omega + Fz + T_surface + mu_scale + gamma
                              + water_depth)):
            for name, x in zip(_INPUT_NAMES, vals, strict=True):
                if isinstance(x, bool) or not (isinstance(x, _NUMBER_TYPES) and
                                               math.isfinite(x)):
                    raise InputError("must be a finite number", field=name, value=x)
        if dt < 0 or T_surface <= 0 or mu_scale < 0 or not abs(gamma) < 0.5 * math.pi or \
                water_depth < 0:
            raise InputError("need dt >= 0 s, T_surface > 0 K, mu_scale >= 0, |gamma| < "
                             "pi/2 rad and water_depth >= 0 m", field="step",
                             value={"dt": dt, "T_surface": T_surface, "mu_scale": mu_scale,
                                    "gamma": gamma, "water_depth": water_depth})
        if self.backend == "reference":
            return self._ref.step(float(dt), float(vx), float(vy), float(omega), float(Fz),
                                  float(T_surface), float(mu_scale), float(gamma),
                                  float(water_depth))
        i = self._in
        i[0], i[1], i[2], i[3], i[4], i[5], i[6], i[7] = (vx, vy, omega, Fz, T_surface,
                                                          mu_scale, gamma, water_depth)
        if self._step(self._h, float(dt), self._pin, self._pout) != 0:   # pragma: no cover
            raise InputError("the tire core refused the inputs", field="step",
                             value=dict(zip(_INPUT_NAMES, vals, strict=True)))
        return self._out.tolist()
