"""Minimum-stopping-distance braking of a quarter car: direct collocation with CasADi + IPOPT.

Problem (states and equations in :mod:`.quarter_car`)::

    minimise    x(t_f)                         (distance travelled until v = v_stop)
    subject to  quarter-car dynamics, Fx/Fz from the force map (CasADi B-spline)
                x(0) = 0, v(0) = v0, omega(0) = v0 / R (free rolling), T_b(0) = T_b0,
                T_tread(0) = T_ambient
                v(t_f) = v_stop, v >= v_stop
                kappa_min <= kappa <= 0   (kappa_min: the map's slip range, -1 at most)
                0 <= T_b <= T_b,max,  |T_b'| <= T_b',max
                t_f free

Transcription: direct collocation with Lagrange polynomials on Legendre points (Biegler,
*Nonlinear Programming*, SIAM 2010, sec. 10.2), piecewise-constant torque rate per interval,
time scaled to ``tau = t / t_f`` in [0, 1]. Implicit collocation is A-stable, which the stiff
wheel dynamics need (explicit shooting fails there). Decision variables are scaled to
order one by reference values (v0, v0 / R, T_b,max, the point-mass distance).

The singular arc (braking at the peak of mu(kappa)) makes the torque rate a singular control;
a small quadratic penalty on it, ``rate_penalty * mean((u / u_max)^2)`` added to the scaled
distance, regularises the problem. Measured with 200 intervals (Burckhardt dry asphalt and
snow): the default 1e-4 changes the distance by less than 1e-7 relative to no penalty, and
IPOPT needs fewer iterations (47 instead of 68 on dry asphalt).

Initial guess: constant deceleration ``g mu*`` at the map's optimal slip ``kappa*`` at v0 (the
slip map), brake torque ramped at the rate limit to the torque that holds ``kappa*``; or a
simulated stop (``initial_guess``, e.g. the locked wheel), which satisfies the dynamics and the
bounds. With the tread temperature as a state the problem can have several local optima
(braking at the peak of a cold tire, or sliding to warm a tread whose friction rises with
temperature); :func:`tire_brush.braking.study.solve_ocp_from_starts` starts from both.
"""

from __future__ import annotations

import hashlib
import math
import os
import shutil
import subprocess
import tempfile
import time
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import ConvergenceError, InputError

from .force_map import ForceMap
from .quarter_car import QuarterCar, rhs, slip
from .reference import point_mass_stopping_distance
from .results import Trajectory
from .slip_map import optimal_slip


@dataclass(frozen=True)
class OCPSettings:
    """Transcription and solver settings.

    Attributes
    ----------
    intervals : int
        Number of collocation intervals N.
    degree : int
        Collocation polynomial degree (Legendre points per interval).
    rate_penalty : float
        Weight of the torque-rate regularisation [1] (see module doc).
    tol : float
        IPOPT tolerance.
    max_iter : int
        IPOPT iteration limit.
    kappa_min : float or None
        Lower bound of the slip [1]. None: ``2 kappa* - 0.05`` with ``kappa*`` the most
        negative optimal slip over the braking speeds (clipped to the map, >= -1). Without such
        a bound, iterates that lock a wheel (omega = 0 pinned by its bound, the brake torque
        then has no effect) are stationary points where IPOPT stalls; a bound active at the
        solution is reported (``OCPResult.kappa_bound_active``).
    coarse_intervals : int
        Mesh continuation: the problem is first solved on this many intervals from the
        initial guess, and its solution starts the solve on ``intervals`` (0, or more than
        half of ``intervals``: off). Measured on the brush-map study ``abs_default`` (200
        intervals, one core): 2.7 s instead of 7-13 s at 0 C and 4.5 s instead of 11 s at
        20 C, the same stopping distance to 1e-5 relative. Most of the cost of an IPOPT
        iteration here is the repeated factorisation of the inertia correction, which the
        coarse mesh makes 4x cheaper. When the coarse solve fails, the fine one starts from
        the initial guess.
    guess_smoothing : float
        Window [s] over which a simulated initial guess is averaged (the ABS's cycles).
    max_wall_time : float
        IPOPT's wall-time limit per solve [s] (a start that wanders fails instead of holding
        up the study; the coarse solve of the continuation gets a quarter of it).
    jit : bool
        Solve with the NLP's functions compiled to C (:func:`_compiled_solver`; cached on
        disk, built once per car, map and mesh) when a C compiler is at hand; otherwise, or
        when the build fails, CasADi's interpreted functions (the same expressions: the
        result does not depend on it; ``OCPResult.extra["compiled"]`` says which ran).
    """

    intervals: int = 200
    degree: int = 3
    rate_penalty: float = 1e-4
    tol: float = 1e-8
    max_iter: int = 500
    kappa_min: float | None = None
    coarse_intervals: int = 50
    guess_smoothing: float = 0.1
    max_wall_time: float = 120.0
    jit: bool = True

    def __post_init__(self) -> None:
        if self.intervals < 5:
            raise InputError("need at least 5 intervals", field="ocp.intervals",
                             value=self.intervals)
        if not 1 <= self.degree <= 9:
            raise InputError("collocation degree must be 1 to 9", field="ocp.degree",
                             value=self.degree)
        if self.kappa_min is not None and not -1.0 <= self.kappa_min < 0.0:
            raise InputError("must be in [-1, 0)", field="ocp.kappa_min", value=self.kappa_min)
        if not (self.guess_smoothing >= 0 and self.max_wall_time > 0):
            raise InputError("need guess_smoothing >= 0 s and max_wall_time > 0 s",
                             field="ocp", value=(self.guess_smoothing, self.max_wall_time))
        if self.coarse_intervals < 0:
            raise InputError("must be >= 0", field="ocp.coarse_intervals",
                             value=self.coarse_intervals)
        if not (math.isfinite(self.rate_penalty) and self.rate_penalty >= 0):
            raise InputError("must be >= 0", field="ocp.rate_penalty", value=self.rate_penalty)


@dataclass(frozen=True, kw_only=True)
class OCPResult(Trajectory):
    """Optimal braking trajectory at the interval boundaries (N + 1 points): the time
    histories of :class:`.results.Trajectory` (``stop_time`` is the free final time
    ``t_f``) and the solver's report.

    Attributes
    ----------
    T_tread : numpy.ndarray
        Tread temperature [K].
    torque_rate : numpy.ndarray
        Brake torque rate per interval [N m/s] (N values).
    solve_time_s : float
        Wall time of IPOPT [s] (the problem set-up excluded, see ``setup_time_s``).
    setup_time_s : float
        Wall time of building the NLP [s]: the initial guess and bounds, and on first use
        of a car, map and mesh its transcription (on the very first, compiling it:
        ``OCPSettings.jit``); later solves of the same transcription reuse it.
    iterations : int
        IPOPT iterations.
    status : str
        IPOPT return status.
    kappa_bound : float
        Lower slip bound used [1].
    kappa_bound_active : bool
        Whether the solution touches it (then the optimum may lie beyond: widen the bound).
    """

    T_tread: np.ndarray
    torque_rate: np.ndarray
    solve_time_s: float
    setup_time_s: float
    iterations: int
    status: str
    kappa_bound: float = -1.0
    kappa_bound_active: bool = False
    extra: dict = field(default_factory=dict)


def _collocation(d: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Collocation matrix C, continuity weights D and quadrature weights B on Legendre points.

    As in CasADi's ``direct_collocation.py`` example (Biegler 2010, sec. 10.2).
    """
    tau = np.append(0.0, np.polynomial.legendre.leggauss(d)[0] * 0.5 + 0.5)
    C = np.zeros((d + 1, d + 1))
    D = np.zeros(d + 1)
    B = np.zeros(d + 1)
    for j in range(d + 1):
        p = np.poly1d([1.0])
        for r in range(d + 1):
            if r != j:
                p *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
        D[j] = p(1.0)
        dp = np.polyder(p)
        for r in range(d + 1):
            C[j, r] = dp(tau[r])
        B[j] = np.polyint(p)(1.0)
    return C, D, B


class _Transcription:
    """The collocation NLP of the module doc at N intervals, built once and solved many times.

    The decision vector is ``[vec(Z), vec(Zc), W, t_f]`` (scaled states at the interval
    boundaries and at the collocation points, scaled torque rate per interval, final time);
    the parameters are the state scales, the ambient temperature and the slip bound
    (``kappa_lo``). Everything that changes from one solve to the next (initial state,
    ``v0``, ``v_stop``, the slip bound, the range of ``t_f``, the initial guess) enters as a
    parameter, a variable bound or the starting point, so one IPOPT instance serves every
    start of a case (:func:`_transcription` keeps them). Simple bounds (speed above
    ``v_stop``, torque in ``[0, T_b,max]``, torque rate, the fixed initial state) are
    variable bounds, which IPOPT handles without slack variables; only the slip bound
    ``kappa_lo v <= omega R - v <= 0`` (two linear inequalities per point) remains a
    constraint beside the collocation equations.
    """

    def __init__(self, car: QuarterCar, fmap: ForceMap, N: int, d: int, rate_penalty: float,
                 solver_options: dict, jit: bool = False) -> None:
        import casadi as ca

        thermal = car.thermal is not None
        nx = 5 if thermal else 4
        R, u_max = car.radius, car.brake_torque_rate_max
        self.N, self.d, self.nx, self.thermal = N, d, nx, thermal
        t0 = time.perf_counter()
        S = ca.MX.sym("S", nx)                      # scales of the states
        T_amb = ca.MX.sym("T_amb")
        k_lo = ca.MX.sym("kappa_lo")
        Z = ca.MX.sym("Z", nx, N + 1)
        Zc = ca.MX.sym("Zc", nx, N * d)
        W = ca.MX.sym("W", 1, N)
        tf = ca.MX.sym("tf")

        # friction at all collocation points in one mapped call
        vc, wc = Zc[1, :] * S[1], Zc[2, :] * S[2]
        kc = slip(vc, wc, R)
        Tc = Zc[4, :] * S[4] if thermal else ca.repmat(T_amb, 1, N * d)
        muc = fmap.casadi_function().map(N * d)(kc, vc, ca.DM.ones(1, N * d) * car.Fz, Tc)

        # one interval's collocation and continuity residuals, in scaled variables, as an SX
        # function mapped over the N intervals (a small expression graph: fast derivatives)
        C, Dc, _ = _collocation(d)
        zk, zk1, Ss = ca.SX.sym("zk", nx), ca.SX.sym("zk1", nx), ca.SX.sym("S", nx)
        zc = ca.SX.sym("zc", nx, d)
        w_k, tf_s, mu_s, Ta = ca.SX.sym("w"), ca.SX.sym("tf"), ca.SX.sym("mu", 1, d), \
            ca.SX.sym("Ta")
        pts = [zk * Ss] + [zc[:, j] * Ss for j in range(d)]
        res = []
        for j in range(1, d + 1):
            xp = sum(C[r, j] * pts[r] for r in range(d + 1))
            xj = pts[j]
            f = rhs(car, mu_s[j - 1], xj[1], xj[2], xj[3], w_k * u_max,
                    xj[4] if thermal else 0.0, Ta)
            fvec = ca.vertcat(*f[:4], *([f[4]] if thermal else []))
            res.append((xp - tf_s / N * fvec) / Ss)
        xend = sum(Dc[r] * pts[r] for r in range(d + 1))
        res.append((zk1 * Ss - xend) / Ss)
        interval = ca.Function("interval", [zk, zc, zk1, w_k, tf_s, mu_s, Ss, Ta],
                               [ca.vertcat(*res)])
        residuals = interval.map(N)(Z[:, :N], Zc, Z[:, 1:], W, tf, muc, S, T_amb)

        # slip bound kappa_lo v <= omega R - v <= 0 at boundaries and collocation points,
        # scaled by v0 (linear in the scaled states)
        Za = ca.horzcat(Z, Zc)
        creep = (Za[2, :] * S[2] * R - Za[1, :] * S[1]) / S[1]
        g = ca.vertcat(ca.vec(residuals), ca.vec(creep - k_lo * Za[1, :]), ca.vec(creep))
        self.n_res = nx * (d + 1) * N
        self.n_pts = (N + 1) + N * d
        x = ca.vertcat(ca.vec(Z), ca.vec(Zc), ca.vec(W), tf)
        self.n_x = x.numel()
        f_obj = Z[0, N] + rate_penalty * ca.sumsqr(W) / N
        nlp = {"x": x, "p": ca.vertcat(S, T_amb, k_lo), "f": f_obj, "g": g}
        self.solver = ca.nlpsol("braking_ocp", "ipopt", nlp, solver_options)
        self.compiled = ""
        if jit:
            # the library is named by the NLP itself (CasADi's serialisation of its
            # expression graph, the map's coefficients included) and CasADi's version: a
            # changed formulation or map never loads a stale library
            key = hashlib.sha1((self.solver.oracle().serialize() + ca.__version__).encode())
            self.solver, self.compiled = _compiled_solver(self.solver, key.hexdigest()[:24],
                                                          solver_options)
        inf = np.inf
        self.lbg = np.concatenate([np.zeros(self.n_res), np.zeros(self.n_pts),
                                   np.full(self.n_pts, -inf)])
        self.ubg = np.concatenate([np.zeros(self.n_res), np.full(self.n_pts, inf),
                                   np.zeros(self.n_pts)])
        self.build_time_s = time.perf_counter() - t0

    def pack(self, Z, Zc, W, tf) -> np.ndarray:
        """Decision vector from its parts (CasADi's column-major ``vec``)."""
        return np.concatenate([np.asarray(Z).ravel(order="F"), np.asarray(Zc).ravel(order="F"),
                               np.asarray(W).ravel(), [float(tf)]])

    def unpack(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """``(Z, Zc, W, tf)`` from a decision vector."""
        x = np.asarray(x, dtype=float).ravel()
        nx, N, d = self.nx, self.N, self.d
        a, b = nx * (N + 1), nx * (N + 1) + nx * N * d
        return (x[:a].reshape((nx, N + 1), order="F"), x[a:b].reshape((nx, N * d), order="F"),
                x[b:b + N], float(x[-1]))


#: Transcriptions built in this process (:func:`_transcription`), least recently used first.
_TRANSCRIPTIONS: OrderedDict[tuple, _Transcription] = OrderedDict()
#: How many are kept (each holds one IPOPT instance: a few MB).
_TRANSCRIPTIONS_KEPT = 8


def _map_fingerprint(fmap: ForceMap) -> str:
    """Hash of what a force map's CasADi function is made of (knots, coefficients, degrees,
    clamping ranges): equal maps give the same transcription."""
    h = hashlib.sha1()
    for k in fmap.knots:
        h.update(np.ascontiguousarray(k, dtype=float).tobytes())
    h.update(np.ascontiguousarray(fmap.coefficients, dtype=float).tobytes())
    h.update(repr((fmap.active, fmap.degrees,
                   [fmap.bounds(n) for n in fmap.axes])).encode())
    return h.hexdigest()


def _transcription(car: QuarterCar, fmap: ForceMap, N: int, d: int, rate_penalty: float,
                   solver_options: dict, jit: bool = False) -> tuple[_Transcription, bool]:
    """The transcription for these inputs, built on first use; and whether it was reused.

    With ``jit`` its NLP functions are compiled C code (:func:`_compiled_solver`)."""
    key = (car, _map_fingerprint(fmap), N, d, rate_penalty,
           repr(sorted(solver_options.items())), jit)
    tr = _TRANSCRIPTIONS.get(key)
    if tr is not None:
        _TRANSCRIPTIONS.move_to_end(key)
        return tr, True
    tr = _Transcription(car, fmap, N, d, rate_penalty, solver_options, jit)
    _TRANSCRIPTIONS[key] = tr
    while len(_TRANSCRIPTIONS) > _TRANSCRIPTIONS_KEPT:
        _TRANSCRIPTIONS.popitem(last=False)
    return tr, False


def _cache_dir() -> Path:
    """Folder of the compiled OCPs: ``$TIREFRIC_CACHE/braking_ocp`` (the tire core's cache
    root, default ``~/.cache/tirefric``)."""
    root = Path(os.environ.get("TIREFRIC_CACHE", Path.home() / ".cache" / "tirefric"))
    return root / "braking_ocp"


def _compiled_solver(solver: Any, key: str, solver_options: dict) -> tuple[Any, str]:
    """``solver`` with its NLP functions (the NLP, objective gradient, constraint Jacobian,
    Lagrangian Hessian) as compiled C code, and the library's path; or ``solver`` itself and
    why not (no C compiler, a failed build).

    The C code is CasADi's code generation of the same expressions (the results are those
    of the interpreted functions to rounding); the library is built once per ``key`` with
    the system's C compiler (``cc -O1``) into :func:`_cache_dir` and loaded by every later
    transcription with the same key, in this and in other processes (the study's case
    workers, later runs). Measured on the brush-map study: derivatives 3-4x faster than
    CasADi's virtual machine.
    """
    import casadi as ca

    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    if cc is None:
        return solver, "not compiled: no C compiler (cc, gcc) on the PATH"
    folder = _cache_dir()
    name = f"braking_ocp_{key}"
    lib = folder / f"{name}.so"
    try:
        if not lib.is_file():
            folder.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryDirectory(dir=folder) as tmp:
                cg = ca.CodeGenerator(f"{name}.c", {"with_header": False})
                cg.add(solver.oracle())
                for fn in ("nlp_f", "nlp_g", "nlp_grad_f", "nlp_jac_g", "nlp_hess_l",
                           "nlp_grad"):
                    cg.add(solver.get_function(fn))
                cg.generate(tmp + os.sep)
                out = Path(tmp) / f"{name}.so"
                subprocess.run([cc, "-O1", "-shared", "-fPIC", str(Path(tmp) / f"{name}.c"),
                                "-o", str(out)], check=True, capture_output=True)
                os.replace(out, lib)        # atomic: a parallel worker sees all or nothing
        return ca.nlpsol("braking_ocp", "ipopt", str(lib), solver_options), str(lib)
    except (OSError, RuntimeError, subprocess.CalledProcessError) as exc:
        detail = getattr(exc, "stderr", b"") or b""
        return solver, f"not compiled: {exc} {detail.decode(errors='replace')[:200]}".strip()


def solve_braking_ocp(
    car: QuarterCar,
    force_map: ForceMap,
    v0: float,
    v_stop: float,
    T_ambient: float,
    *,
    settings: OCPSettings | None = None,
    brake_torque_initial: float = 0.0,
    verbose: bool = False,
    ipopt_options: dict | None = None,
    initial_guess: Any = None,
) -> OCPResult:
    """Solve the minimum-stopping-distance problem (module doc) with IPOPT.

    Parameters
    ----------
    car
        Quarter car (its ``thermal`` decides whether the tread temperature is a state).
    force_map
        Friction ``Fx/Fz(kappa, vx, Fz, T)`` as a B-spline force map.
    v0, v_stop
        Initial and final speed [m/s], ``v0 > v_stop > 0`` (slip is singular at v = 0).
    T_ambient
        Ambient/initial tread temperature [K].
    settings
        Transcription and solver settings.
    brake_torque_initial
        Brake torque at t = 0 [N m].
    verbose
        Print IPOPT's iteration log.
    ipopt_options
        Extra IPOPT options (``{"ipopt.mu_strategy": "adaptive"}``, ...).
    initial_guess
        A simulated stop of the same car on the same map (a :class:`.simulation.SimResult`:
        ``t``, ``x``, ``v``, ``omega``, ``brake_torque``, ``T_tread``, ``stop_time``) or an
        :class:`OCPResult` to start from instead of the constant-deceleration guess (module
        doc). It satisfies the dynamics and the bounds, which a rough friction map (a glassy
        compound's stick-slip branches) needs: from the constant-deceleration guess IPOPT can
        end in restoration failures there.

    Raises
    ------
    ConvergenceError
        IPOPT did not find an optimal point.
    """
    settings = settings or OCPSettings()
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    if not 0 <= brake_torque_initial <= car.brake_torque_max:
        raise InputError("initial brake torque outside [0, brake_torque_max]",
                         field="brake_torque_initial", value=brake_torque_initial)
    nc = settings.coarse_intervals
    if 5 <= nc <= settings.intervals // 2:
        return _solve_coarse_to_fine(car, force_map, v0, v_stop, T_ambient, settings,
                                     brake_torque_initial, verbose, ipopt_options,
                                     initial_guess)
    t_setup = time.perf_counter()
    N, d = settings.intervals, settings.degree
    R, Fz = car.radius, car.Fz
    thermal = car.thermal is not None
    map_lo = max(force_map.bounds("kappa")[0], -1.0)

    # initial guess and slip bound from the optimal slip over the speed range
    v_axis = np.geomspace(v_stop, v0, 7)
    sm = optimal_slip(force_map, v_axis, np.array([Fz]), np.array([T_ambient]),
                      kappa_min=map_lo)
    k_star, mu_star = float(sm.kappa_opt[-1, 0, 0]), float(sm.mu_max[-1, 0, 0])
    if settings.kappa_min is None:
        kappa_lo = max(map_lo, 2.0 * float(sm.kappa_opt.min()) - 0.05)
    else:
        kappa_lo = max(map_lo, settings.kappa_min)
    a_guess = car.g * mu_star
    tf_guess = (v0 - v_stop) / a_guess
    d_ref = point_mass_stopping_distance(v0, mu_star, v_stop, car.g)

    # scales of the decision variables
    sx = np.array([d_ref, v0, v0 / R, car.brake_torque_max] + ([T_ambient] if thermal else []))
    u_max = car.brake_torque_rate_max

    # the load is fixed (and the temperature without the thermal state): an exact slice of
    # the map has fewer spline axes, so fewer coefficients per evaluation (ForceMap.fixed)
    fixed = {"Fz": Fz} if thermal else {"Fz": Fz, "T_K": T_ambient}
    opts = {"ipopt.print_level": 5 if verbose else 0, "print_time": False,
            "ipopt.sb": "yes", "ipopt.tol": settings.tol, "ipopt.max_iter": settings.max_iter,
            "ipopt.max_wall_time": settings.max_wall_time,
            **(ipopt_options or {})}
    tr, reused = _transcription(car, force_map.fixed(**fixed), N, d, settings.rate_penalty,
                                opts, settings.jit)

    # bounds: initial state fixed, v >= v_stop (v = v_stop at the end), 0 <= T_b <= T_b,max
    inf = np.inf
    x0 = np.array([0.0, v0, v0 / R, brake_torque_initial]
                  + ([T_ambient] if thermal else [])) / sx
    lb_pt = np.array([-inf, v_stop / v0, -inf, 0.0] + ([-inf] if thermal else []))
    ub_pt = np.array([inf, inf, inf, 1.0] + ([inf] if thermal else []))
    lbZ, ubZ = np.repeat(lb_pt[:, None], N + 1, 1), np.repeat(ub_pt[:, None], N + 1, 1)
    lbZ[:, 0] = ubZ[:, 0] = x0
    lbZ[1, N] = ubZ[1, N] = v_stop / v0
    lbZc, ubZc = np.repeat(lb_pt[:, None], N * d, 1), np.repeat(ub_pt[:, None], N * d, 1)
    lbx = tr.pack(lbZ, lbZc, -np.ones(N), 0.2 * tf_guess)
    ubx = tr.pack(ubZ, ubZc, np.ones(N), 5.0 * tf_guess)

    # initial guess
    tg = np.linspace(0.0, tf_guess, N + 1)
    tcg = (np.arange(N)[:, None] + np.polynomial.legendre.leggauss(d)[0][None, :] * 0.5 + 0.5
           ).ravel() * tf_guess / N
    Tb_ss = R * Fz * mu_star + car.wheel_inertia * a_guess * (1 + k_star) / R

    def guess(t):
        v = v0 - a_guess * t
        x = v0 * t - 0.5 * a_guess * t**2
        w = v * (1 + k_star) / R
        Tb = np.minimum(Tb_ss, brake_torque_initial + u_max * t)
        rows = [x, v, w, Tb] + ([np.full_like(t, T_ambient)] if thermal else [])
        return np.vstack(rows) / sx[:, None]

    if initial_guess is None:
        ramp = np.clip((Tb_ss - brake_torque_initial) / u_max - tg[:-1], 0,
                       tf_guess / N) * N / tf_guess
        start = tr.pack(guess(tg), guess(tcg), ramp, tf_guess)
    else:
        g = initial_guess
        tf_sim = float(g.stop_time)
        if not 0.2 * tf_guess < tf_sim < 5.0 * tf_guess:
            raise InputError("the initial guess' stop time is outside the OCP's bounds on t_f",
                             field="initial_guess", value=tf_sim)
        cols = [g.x, g.v, g.omega, g.brake_torque] + ([g.T_tread] if thermal else [])

        # a simulated ABS cycles at ~10 Hz: point samples on a coarse mesh catch random
        # phases of the cycle (a wheel nearly locked at one node, rolling at the next), from
        # which IPOPT needs huge Hessian corrections (measured: ~1 s per iteration at 50
        # intervals, 0 C brush map). The guess is the trajectory averaged over a window of
        # settings.guess_smoothing s. Other guesses (a locked wheel, an OCP solution such as
        # the coarse one) are sampled at the nodes.
        # a stop with release phases (code 2, abs_control.RELEASE): an ABS that cycled
        cycling = np.any(np.asarray(getattr(g, "phase", [])) == 2)
        win = max(settings.guess_smoothing, tf_sim / N) if cycling else 0.0

        def sampled(t):
            rows = []
            for c in cols:
                cum = np.concatenate(([0.0], np.cumsum(0.5 * (c[1:] + c[:-1]) * np.diff(g.t))))
                lo = np.clip(t - 0.5 * win, g.t[0], g.t[-1])
                hi = np.clip(t + 0.5 * win, g.t[0], g.t[-1])
                wide = hi - lo > 1e-12
                avg = np.interp(t, g.t, c)
                avg[wide] = (np.interp(hi[wide], g.t, cum) - np.interp(lo[wide], g.t, cum)) \
                    / (hi[wide] - lo[wide])
                rows.append(avg)
            return np.vstack(rows) / sx[:, None]

        tg = np.linspace(0.0, tf_sim, N + 1)
        tcg = (np.arange(N)[:, None] + np.polynomial.legendre.leggauss(d)[0][None, :] * 0.5
               + 0.5).ravel() * tf_sim / N
        Tb = np.interp(tg, g.t, g.brake_torque)
        start = tr.pack(sampled(tg), sampled(tcg),
                        np.clip(np.diff(Tb) / (tf_sim / N) / u_max, -1, 1), tf_sim)
    nlp_guess = getattr(initial_guess, "extra", {}).get("nlp") if initial_guess is not None \
        else None
    if (nlp_guess is not None and nlp_guess["d"] == d and nlp_guess["nx"] == tr.nx
            and np.allclose(nlp_guess["sx"], sx)):
        # a solution of the same problem on another mesh (the coarse solve): its collocation
        # polynomials at this mesh's points
        start = _refined_start(tr, nlp_guess)
    # the guess inside the variable bounds (IPOPT would push it in by its own rule)
    start = np.clip(start, lbx, ubx)
    p = np.concatenate([sx, [T_ambient, kappa_lo]])
    setup = time.perf_counter() - t_setup
    t0 = time.perf_counter()
    try:
        sol = tr.solver(x0=start, p=p, lbx=lbx, ubx=ubx, lbg=tr.lbg, ubg=tr.ubg)
        stats = tr.solver.stats()
    except RuntimeError as exc:
        try:                                     # the stats can be missing after a failure
            stats = tr.solver.stats()
        except Exception:  # never hide the solver's own error behind this one
            stats = {}
        raise ConvergenceError(f"braking OCP did not converge: "
                               f"{stats.get('return_status', 'no status')} after "
                               f"{stats.get('iter_count', '?')} iterations ({exc})") from exc
    solve_time = time.perf_counter() - t0
    if not stats.get("success", False):
        raise ConvergenceError(f"braking OCP did not converge: "
                               f"{stats.get('return_status', 'no status')} after "
                               f"{stats.get('iter_count', '?')} iterations")
    Zs, Zcs, Ws, tf_v = tr.unpack(sol["x"])
    Xv = Zs * sx[:, None]
    t = np.linspace(0.0, tf_v, N + 1)
    kappa = slip(Xv[1], Xv[2], R)
    T_tread = Xv[4] if thermal else np.full(N + 1, T_ambient)
    mu = force_map(kappa, Xv[1], Fz, T_tread)
    return OCPResult(
        t=t, x=Xv[0], v=Xv[1], omega=Xv[2], brake_torque=Xv[3], kappa=kappa, mu=mu,
        T_tread=T_tread, torque_rate=Ws * u_max,
        stopping_distance=float(Xv[0, -1]), stop_time=tf_v, solve_time_s=solve_time,
        setup_time_s=setup, iterations=int(stats.get("iter_count", -1)),
        status=str(stats.get("return_status", "")),
        kappa_bound=kappa_lo, kappa_bound_active=bool(kappa.min() < kappa_lo + 1e-4),
        extra={"kappa_guess": k_star, "mu_guess": mu_star, "solver_reused": reused,
               "solver_build_s": 0.0 if reused else tr.build_time_s,
               "compiled": tr.compiled,
               "nlp": {"N": N, "d": d, "nx": tr.nx, "sx": sx, "kappa_lo": kappa_lo,
                       "Z": Zs, "Zc": Zcs, "W": Ws, "tf": tf_v,
},
               "t_wall": {k[7:]: float(v) for k, v in stats.items()
                          if k.startswith("t_wall_") and isinstance(v, float)}},
    )


def _solve_coarse_to_fine(car, force_map, v0, v_stop, T_ambient, settings,
                          brake_torque_initial, verbose, ipopt_options, initial_guess
                          ) -> OCPResult:
    """``settings.coarse_intervals`` first, its solution as the fine solve's guess
    (:class:`OCPSettings`); times (set-up and solve apart) and iterations of both are summed
    in the result."""
    from dataclasses import replace

    nc = settings.coarse_intervals
    t0 = time.perf_counter()
    try:
        coarse = solve_braking_ocp(
            car, force_map, v0, v_stop, T_ambient,
            settings=replace(settings, intervals=nc, coarse_intervals=0,
                             max_wall_time=0.25 * settings.max_wall_time),
            brake_torque_initial=brake_torque_initial, ipopt_options=ipopt_options,
            initial_guess=initial_guess)
    except ConvergenceError as exc:
        coarse, info = None, {"failed": str(exc)}
    else:
        info = {"iterations": coarse.iterations, "stopping_distance": coarse.stopping_distance}
    info.update(intervals=nc, time_s=time.perf_counter() - t0)
    fine = solve_braking_ocp(
        car, force_map, v0, v_stop, T_ambient, settings=replace(settings, coarse_intervals=0),
        brake_torque_initial=brake_torque_initial, verbose=verbose,
        ipopt_options=ipopt_options, initial_guess=initial_guess if coarse is None else coarse)
    # the coarse set-up (building, on first use compiling, its transcription) counts as
    # set-up, the rest of its wall time (a failed one's all of it) as solve time
    coarse_setup = 0.0 if coarse is None else coarse.setup_time_s
    return replace(fine, solve_time_s=fine.solve_time_s + info["time_s"] - coarse_setup,
                   setup_time_s=fine.setup_time_s + coarse_setup,
                   iterations=fine.iterations + (0 if coarse is None else coarse.iterations),
                   extra=dict(fine.extra, coarse=info))


def _legendre_tau(d: int) -> np.ndarray:
    """Collocation points of one interval on [0, 1] (Legendre)."""
    return np.polynomial.legendre.leggauss(d)[0] * 0.5 + 0.5


def _on_mesh(Xb: np.ndarray, Xc: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A collocation solution (rows: quantities; ``Xb`` at the N + 1 interval boundaries,
    ``Xc`` at the N d collocation points) at normalised times ``t`` in [0, 1]: its Lagrange
    polynomial on each interval (the solution the transcription represents, Biegler 2010,
    sec. 10.2), not a linear interpolation of its nodes."""
    N = Xb.shape[1] - 1
    d = Xc.shape[1] // N
    tau = np.append(0.0, _legendre_tau(d))
    k = np.clip(np.floor(t * N).astype(int), 0, N - 1)
    s = t * N - k
    basis = np.ones((t.size, d + 1))
    for r in range(d + 1):
        for q in range(d + 1):
            if q != r:
                basis[:, r] *= (s - tau[q]) / (tau[r] - tau[q])
    pts = np.stack([Xb[:, :-1]] + [Xc[:, j::d] for j in range(d)], axis=-1)   # rows, N, d+1
    return np.einsum("ikr,kr->ik", pts[:, k, :], basis)


def _refined_start(tr: _Transcription, coarse: dict) -> np.ndarray:
    """Starting point on ``tr``'s mesh from a solution of the same problem on another mesh:
    the states are its collocation polynomials at this mesh's points (:func:`_on_mesh`), the
    torque rate that of the interval containing each new one, the final time its own."""
    N, d, Nc = tr.N, tr.d, coarse["N"]
    tau = _legendre_tau(d)
    tb = np.arange(N + 1) / N
    tcol = ((np.arange(N)[:, None] + tau[None, :]) / N).ravel()
    Zb, Zc = coarse["Z"], coarse["Zc"]
    W = coarse["W"][np.minimum((np.arange(N) + 0.5) / N * Nc, Nc - 1).astype(int)]
    return tr.pack(_on_mesh(Zb, Zc, tb), _on_mesh(Zb, Zc, tcol), W, coarse["tf"])
