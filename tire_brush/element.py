r"""Tread elements, belt and tread temperature: the readable reference of the compiled core.

This module is the tire core written out in plain Python floats, operation for operation the
same as ``tire_brush/csrc/tirecore.c`` (the tests pin the two to each other). It is slow (one
element sub-step costs ~30 us here and ~0.1 us in C) and is not used for simulation; it is the
text to read, and docs/tire-core.md explains it.

The element (per unit footprint area): a tip of mass ``m`` on a Kelvin-Voigt shear spring
(``k``, ``d``, anisotropic in x and y) to the belt. With the deflection ``u = tip - base``,
the tip's slip velocity over the road ``w`` and the base (belt) slip velocity ``V_b``:

.. math::  \dot u = w - V_b, \qquad m \dot w = f - k u - d (w - V_b), \qquad \dot s = |w|,

``f`` the friction stress: while the tip sticks (``w = 0``) whatever holds it, up to
``mu(0+, s) p``; while it slides ``f = -p mu(|w|, s) w/|w|`` with eq. (28) of the review,
``mu = mu_cold(|w|) e^{-s/s0} + mu_hot(|w|) (1 - e^{-s/s0})``, both branches read from the
grid's table (piecewise linear in log10 v, constant below the first and above the last node).
The stress on the belt is ``tau = k u + d (w - V_b)``.

Time integration (per element, inside each outer step): the two-stage, stiffly accurate,
L-stable SDIRK method of order 2 with ``gamma = 1 - 1/sqrt(2)`` (R. Alexander, SIAM J. Numer.
Anal. 14, 1006 (1977); Hairer and Wanner, *Solving ODEs II*, sec. IV.6), with the embedded
first-order solution ``y_n + h k_1`` for the local error and the usual step-size control
(Hairer and Wanner, sec. IV.8). Each stage is an implicit Euler solve of step ``gamma h``,

.. math::  A w - f(w) = g, \quad A = m/H + k H + d, \quad
           g = (m/H) Z_w - k Z_u + (k H + d) V_b ,

which sticks if ``|g| <= p mu(0+, s)`` and otherwise slides with the speed ``V`` that solves
``R(V) = 1 / |(A V + p mu(V, s_0 + H V))^{-1} g| - 1 = 0`` (``= (A V + p mu)/|g| - 1`` for an
isotropic element). The root is *bracketed*: from the speed the element had, the table's
cells are walked in the direction that the sign of ``R`` gives (``R < 0``: the tip
accelerates, the first root above; ``R > 0``: the first root below), and the root in the
bracketing cell is found by Newton's method safeguarded by bisection. No fixed iteration
count, no slope limiter: a falling friction branch, however steep, costs only cell walks,
and the error control resolves the stick-slip transitions (a step that crosses one has a
large error and is retried shorter). Elements enter the patch with the tip moving with the
belt (``u = 0``, ``w = V_b``, ``s = 0``), the pressure under an element follows it along the
patch during the step (``p(x(t))``, parabolic).

The belt (massless, springs ``k_c`` and dampers ``d_c`` to the rim) is coupled linearly
implicitly: over an outer step ``h`` the tread force is ``F_n - J (V_b - V_{b,n})`` with ``J``
the tread's stiffness against belt motion over the step, ``(k h + d)`` for a sticking element
and the exact response of the linearised element for a sliding one
(:func:`element_stiffness`, with ``c = p mu/|w|`` the secant friction stiffness); a steady
state (``F_n = k_c delta``, ``V_b = V_s``) is reproduced exactly whatever ``J``. The outer step
is ``dt_internal``, shortened where the coupling needs it (:func:`outer_step`;
docs/tire-core.md, "belt coupling at high rolling speed").

This module imports only the standard library (and :mod:`tire_brush.realtime`, the real-time
fidelity's sub-step, which imports numpy): it runs inside an FMU.
"""

from __future__ import annotations

import copy
import math

from .realtime import PatchEval, rt_advance

#: SDIRK2 coefficient ``gamma = 1 - 1/sqrt(2)``.
GAMMA = 0.2928932188134524
#: Elements slipping slower than this [m/s] count as adhering in the sliding fraction.
CREEP_SPEED = 1e-3
#: Shortest step [s] that advances the tire (``TF_DT_FLOOR``): a shorter one only advances the
#: clock, so outputs are continuous as the step -> 0 (nothing moves in 1 ns).
DT_FLOOR = 1e-9
#: Smallest element sub-step [s]: accepted whatever its error.
H_MIN = 1e-8
#: Largest slipped distance carried [m].
S_MAX = 1e6
#: Smallest rolling speed of the steady march [m/s] (a locked wheel).
V_ROLL_MIN = 1e-6
#: Columns of one element: u_x, u_y, w_x, w_y, s, proposed sub-step, in contact, contact age.
N_ELEM = 8
#: Head of the state vector (version, lattice size, x_top, belt deflection and velocity,
#: tread force, tread temperature, time, 12 outputs, belt yaw angle, yaw rate, tread moment,
#: spin of the base from camber).
STATE_HEAD = 27
#: State layout version.
STATE_VERSION = 5
#: Contact-age length per renewal length of eq. (28): s0 = 0.2 D, so D = 5 s0
#: (``AGE_D_PER_S0`` of the core; docs/tire-core.md, "contact age").
AGE_D_PER_S0 = 5.0
#: Number of outputs of a step (``TF_NOUT``): Fx, Fy, Mz, kappa, alpha, mu_eff, mu_slide,
#: sliding_fraction, dT_flash_max, T_tread, Mx, My.
N_OUT = 12
#: pi / 2: the inclination angle is refused at or beyond it.
HALF_PI = 1.5707963267948966
LN10 = 2.302585092994046
#: Longest outer step in units of ``1 / sqrt(k / m)``, the tread tip's period over 2 pi
#: (``TIP_STEP`` of the core): the belt coupling holds the belt's velocity over the step while
#: the tips ring against it (docs/tire-core.md, "belt coupling at high rolling speed").
TIP_STEP = 1.4
#: Largest loop gain of the belt's lateral-yaw coupling through the rolling speed over an outer
#: step (:func:`belt_gain`; ``BELT_GAIN_MAX`` of the core).
BELT_GAIN_MAX = 0.5
#: Work budget of an outer step: element sub-step attempts per element of the nominal patch
#: (``TF_BUDGET``; docs/tire-core.md, "work budget").
BUDGET = 24
#: Flags of a step (``TF_FLAG_*``): an outer step's work budget was spent; the friction was
#: read at a temperature outside the table's temperature axis.
FLAG_BUDGET = 1
FLAG_T_RANGE = 2
#: Relative margin of the bounds of the node walk (tirecore.c, WALK_MARGIN): a node skipped as
#: "R < 0" (or "R >= 0") has |R| > 1e-7, far above the rounding of its evaluation.
WALK_MARGIN = 1e-6


def _cold_weight(a: float) -> float:
    """``exp(-a)``, the cold weight of eq. (28) at ``a = s/s0``, taken as 0 beyond
    ``a = 700`` (below 1e-304: fully developed elements skip the exponential), as the core."""
    return 0.0 if a > 700.0 else math.exp(-a)


def _norm2(x: float, y: float) -> float:
    """``sqrt(x^2 + y^2)``, as the core computes it (``math.hypot`` rounds differently)."""
    return math.sqrt(x * x + y * y)


class RefTable:
    """Friction table on (log10 v, T, log10 p), as the core holds it.

    Parameters
    ----------
    log10_v, T, log10_p
        Strictly ascending axes (sequences of floats).
    values
        Node values ``values[iv][iT][ip] = (mu_cold, mu_hot, dT_flash)`` (nested sequences or
        an array of shape ``(nv, nT, np, 3)``).
    inv_s0
        ``1/s0`` of eq. (28) [1/m].
    """

    def __init__(self, log10_v, T, log10_p, values, inv_s0: float) -> None:
        self.ax = [list(map(float, a)) for a in (log10_v, T, log10_p)]
        self.n = [len(a) for a in self.ax]
        self.uni, self.lo, self.inv = [], [], []
        for a in self.ax:
            n = len(a)
            d = (a[n - 1] - a[0]) / (n - 1)
            self.uni.append(all(abs((a[i] - a[i - 1]) - d) <= 1e-9 * abs(d)
                                for i in range(1, n)))
            self.lo.append(a[0])
            self.inv.append((n - 1) / (a[n - 1] - a[0]))
        flat = [float(x) for row in _flatten(values) for x in row]
        self.val = flat
        nv = self.n[0]
        self.vnode = [math.pow(10.0, x) for x in self.ax[0]]
        self.ispan = [1.0 / (self.ax[0][j + 1] - self.ax[0][j]) if j < nv - 1 else 0.0
                      for j in range(nv)]
        self.inv_s0 = float(inv_s0)
        # bounds for the node walk of the stage solve (tirecore.c, struct tf_table): the
        # largest branch value at nodes >= j and the smallest at nodes <= j; None when the
        # table has a negative value (nothing is skipped then)
        ntp = self.n[1] * self.n[2]
        self.smax: list[float] | None = None
        self.pmin: list[float] | None = None
        if all(flat[i] >= 0.0 for i in range(len(flat)) if i % 3 != 2):
            self.smax = [0.0] * (nv * ntp)
            self.pmin = [0.0] * (nv * ntp)
            self.bounds(0, ntp)

    def bounds(self, k0: int, k1: int) -> None:
        """Node-walk bounds ``smax``, ``pmin`` of the (T, p) columns ``k0 <= k < k1`` from the
        values (``table_bounds`` of the core)."""
        nv = self.n[0]
        ntp = self.n[1] * self.n[2]
        flat, smax, pmin = self.val, self.smax, self.pmin
        for k in range(k0, k1):
            for j in range(nv - 1, -1, -1):
                b = (j * ntp + k) * 3
                hi = flat[b] if flat[b] > flat[b + 1] else flat[b + 1]
                if j < nv - 1 and smax[(j + 1) * ntp + k] > hi:
                    hi = smax[(j + 1) * ntp + k]
                smax[j * ntp + k] = hi
            for j in range(nv):
                b = (j * ntp + k) * 3
                lo = flat[b] if flat[b] < flat[b + 1] else flat[b + 1]
                if j > 0 and pmin[(j - 1) * ntp + k] < lo:
                    lo = pmin[(j - 1) * ntp + k]
                pmin[j * ntp + k] = lo

    def bound(self, arr: list[float], q: tuple, j: int) -> float:
        """Bilinear (T, p) interpolation of a bound array (``smax`` or ``pmin``) at speed
        node ``j``: it bounds both branches (and their blends) at the nodes >= j or <= j."""
        b, w00, w01, w10, w11 = q
        base = j * self.n[1] * self.n[2] + b // 3
        o2 = self.n[2]
        return w00 * arr[base] + w01 * arr[base + 1] + w10 * arr[base + o2] + w11 * arr[
            base + o2 + 1]

    def locate(self, k: int, x: float) -> tuple[int, float]:
        """Cell index and fraction of ``x`` on axis ``k``, clamped."""
        n = self.n[k]
        a = self.ax[k]
        if not x > a[0]:
            return 0, 0.0
        if not x < a[n - 1]:
            return n - 2, 1.0
        if self.uni[k]:
            tt = (x - self.lo[k]) * self.inv[k]
            j = int(tt)
            if j > n - 2:
                j = n - 2
            return j, tt - j
        return _locate_arr(a, x)

    def prep(self, iT: int, fT: float, p_rubber: float) -> tuple:
        """Offset and bilinear weights in (T, p) for pressure ``p_rubber`` [Pa]."""
        lp = math.log10(p_rubber) if p_rubber > 0.0 else -math.inf
        ip, fp = self.locate(2, lp)
        return ((iT * self.n[2] + ip) * 3, (1.0 - fT) * (1.0 - fp), (1.0 - fT) * fp,
                fT * (1.0 - fp), fT * fp)

    def node(self, q: tuple, j: int) -> list[float]:
        """``(mu_cold, mu_hot, dT_flash)`` at speed node ``j`` for a prepared query."""
        b, w00, w01, w10, w11 = q
        base = j * self.n[1] * self.n[2] * 3 + b
        o2 = self.n[2] * 3
        v = self.val
        return [w00 * v[base + k] + w01 * v[base + 3 + k] + w10 * v[base + o2 + k]
                + w11 * v[base + o2 + 3 + k] for k in range(3)]


def _locate_arr(a: list[float], x: float) -> tuple[int, float]:
    """Cell index and fraction of ``x`` on the ascending axis ``a``, clamped (``locate_arr``
    of the core)."""
    n = len(a)
    if not x > a[0]:
        return 0, 0.0
    if not x < a[n - 1]:
        return n - 2, 1.0
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if a[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo, (x - a[lo]) / (a[lo + 1] - a[lo])


class RefWet:
    """Wet branch of a friction table (``tf_wet`` of the core; ``tirecore.h`` documents the
    layout) on ``n = (nv, nT, np)`` nodes: axes ``depth`` [m] (first 0) and ``log10_t``, flat
    lists ``mu`` (nd, nv, nT, np, 4: cold_w0, cold_w1, hot_w0, hot_w1) and ``w`` (nd, nt, nv,
    nT, np), the excess depth of full hydroplaning ``d_full`` [m] and ``drain_scale``."""

    def __init__(self, n, depth, log10_t, mu, w, d_full: float, drain_scale: float) -> None:
        self.n = [int(x) for x in n]
        self.depth = [float(x) for x in depth]
        self.log10_t = [float(x) for x in log10_t]
        self.mu = [float(x) for x in mu]
        self.w = [float(x) for x in w]
        self.d_full = float(d_full)
        self.drain_scale = float(drain_scale)


def _flatten(values):
    """Rows of three values in (v, T, p) order."""
    try:
        import numpy as np
        return np.asarray(values, dtype=float).reshape(-1, 3).tolist()
    except ImportError:                           # pragma: no cover - numpy is a dependency
        return [c for a in values for b in a for c in b]


class _Stage:
    """The friction root problem of one stage (module docstring)."""

    __slots__ = ("Amax", "Amin", "Ax", "Ay", "D", "E", "G", "Hs", "P", "Zs", "c0", "c1", "cell",
                 "dT", "gx", "gy", "inv_s0", "iso", "ispan", "jlo", "lvj", "pf", "q", "t", "th")

    def vn(self, j: int) -> float:
        """Speed node ``j`` as the stage's slip speed: ``v_j``, or with the contact age the
        ``V`` at which ``v_eff(V) = (D + Hs V) / th`` reaches it, ``(th v_j - D) / Hs``."""
        v = self.t.vnode[j]
        return (self.th * v - self.D) / self.Hs if self.D > 0.0 else v

    def cell_of(self, lo: int, V: float) -> int:
        """The largest node ``j`` in ``[lo, nv - 1]`` with ``vn(j) <= V``."""
        hi = self.t.n[0]
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if self.vn(mid) <= V:
                lo = mid
            else:
                hi = mid
        return lo

    def set_cell(self, j: int) -> None:
        t = self.t
        nv = t.n[0]
        self.cell = j
        if j < 0 or j >= nv - 1:
            self.c0 = t.node(self.q, 0 if j < 0 else nv - 1)
            self.c1 = [0.0, 0.0, 0.0]
            self.lvj = 0.0
            self.ispan = 0.0
        else:
            self.c0 = t.node(self.q, j)
            n1 = t.node(self.q, j + 1)
            self.c1 = [n1[k] - self.c0[k] for k in range(3)]
            self.lvj = t.ax[0][j]
            self.ispan = t.ispan[j]

    def resid(self, V: float) -> tuple[float, float]:
        """``(R, dR/dV)`` at speed ``V`` (module docstring); keeps the friction stress
        ``P``, the cold weight ``E`` and the flash temperature ``dT`` of this evaluation."""
        c0, c1 = self.c0, self.c1
        if self.ispan > 0.0:
            # with the contact age the table is read at v_eff = (D + Hs V) / th, whose slope
            # Hs / th enters the derivative
            ve = (self.D + self.Hs * V) / self.th if self.D > 0.0 else V
            tt = (math.log10(ve) - self.lvj) * self.ispan
            dl = self.ispan / (ve * LN10)
            if self.D > 0.0:
                dl *= self.Hs / self.th
            mc = c0[0] + c1[0] * tt
            mh = c0[1] + c1[1] * tt
            dT = c0[2] + c1[2] * tt
            dmc = c1[0] * dl
            dmh = c1[1] * dl
        else:
            mc, mh, dT, dmc, dmh = c0[0], c0[1], c0[2], 0.0, 0.0
        E = _cold_weight((self.Zs + self.Hs * V) * self.inv_s0) if self.inv_s0 > 0.0 else 1.0
        dm = mc - mh
        P = self.pf * (mh + dm * E)
        dP = self.pf * ((dmh + (dmc - dmh) * E) - dm * E * (self.Hs * self.inv_s0))
        if self.iso:
            R = (self.Ax * V + P) / self.G - 1.0
            d = (self.Ax + dP) / self.G
        else:
            Dx = self.Ax * V + P
            Dy = self.Ay * V + P
            rx = self.gx / Dx
            ry = self.gy / Dy
            Q = rx * rx + ry * ry
            sq = math.sqrt(Q)
            R = 1.0 / sq - 1.0
            d = (rx * rx * (self.Ax + dP) / Dx + ry * ry * (self.Ay + dP) / Dy) / (Q * sq)
        self.P, self.E, self.dT = P, E, dT
        return R, d

    def node_resid(self, j: int) -> float:
        """R at speed node ``j`` from the node's values alone (no interpolation)."""
        n = self.t.node(self.q, j)
        V = self.vn(j)
        E = _cold_weight((self.Zs + self.Hs * V) * self.inv_s0) if self.inv_s0 > 0.0 else 1.0
        P = self.pf * (n[1] + (n[0] - n[1]) * E)
        if self.iso:
            return (self.Ax * V + P) / self.G - 1.0
        rx = self.gx / (self.Ax * V + P)
        ry = self.gy / (self.Ay * V + P)
        return 1.0 / math.sqrt(rx * rx + ry * ry) - 1.0

    def solve_cell(self, lo: float, hi: float, x: float, r: float, d: float) -> float:
        """Root in ``[lo, hi]`` (``R(lo) < 0 <= R(hi)``) by Newton's method from ``x``
        (``R(x) = r``, ``R'(x) = d``) safeguarded by bisection; returns the last point
        evaluated."""
        for _ in range(200):
            if r == 0.0:
                return x
            if r < 0.0:
                lo = x
            else:
                hi = x
            xn = x - r / d if d != 0.0 else math.nan
            if not d > 0.0 or not (lo < xn < hi):
                xn = 0.5 * (lo + hi)
            if abs(xn - x) <= 1e-14 * xn or hi - lo <= 1e-15 * hi:
                return x
            x = xn
            r, d = self.resid(x)
        return x


class Ctx:
    """Constants of one outer step (``tf_ctx`` of the core)."""

    __slots__ = (
        "D",
        "Vbx",
        "Vby",
        "Vr",
        "c_flat",
        "dx",
        "dy",
        "fT",
        "iT",
        "inv_ac",
        "inv_void",
        "kx",
        "ky",
        "m",
        "mu_scale",
        "p_amp",
        "t",
        "tol_abs",
        "w",
        "wpsi",
        "zx",
        "zy",
    )

    def __init__(self, p, t: RefTable, T: float, Fz: float, a: float, b: float, c_flat: float,
                 p_amp: float, mu_scale: float, Vbx: float, Vby: float, Vr: float) -> None:
        self.t = t
        self.iT, self.fT = t.locate(1, T)
        self.kx, self.ky, self.dx, self.dy, self.m = p.k_x, p.k_y, p.d_x, p.d_y, p.mass
        self.Vbx, self.Vby, self.Vr = Vbx, Vby, Vr
        self.wpsi = 0.0
        self.inv_void = 1.0 / (1.0 - p.void_ratio)
        self.mu_scale = mu_scale
        self.p_amp = p_amp
        self.c_flat = c_flat
        self.inv_ac = 1.0 / (a - c_flat)
        self.tol_abs = p.tol * (0.5 * Fz / (a * b))
        self.zx = math.sqrt(p.k_x * p.mass) + p.d_x
        self.zy = math.sqrt(p.k_y * p.mass) + p.d_y
        #: contact-age length [m] (0: the friction read at |w|)
        self.D = AGE_D_PER_S0 / t.inv_s0 if getattr(p, "contact_ageing", 0) and t.inv_s0 > 0.0 \
            else 0.0
        #: the outer step's work ``[attempts left, stage solves, fallbacks]`` (``tf_work`` of
        #: the core; docs/tire-core.md, "work budget"), or None: no budget
        self.w: list[float] | None = None

    def pressure(self, x: float) -> float:
        """Gross pressure [Pa] at position ``x`` [m]: flat centre, parabolic ends."""
        return self.p_amp * shape(self.c_flat, self.inv_ac, x)


def shape(c_flat: float, inv_ac: float, x: float) -> float:
    """Pressure shape [1] at ``x`` [m]: 1 on ``|x| <= c_flat``, then ``1 - t^2`` with
    ``t = (|x| - c_flat) inv_ac`` (``inv_ac = 1/(a - c_flat)``), 0 beyond the patch."""
    ax = abs(x)
    if ax <= c_flat:
        return 1.0
    t = (ax - c_flat) * inv_ac
    w = 1.0 - t * t
    return w if w > 0.0 else 0.0


def stage(c: Ctx, Hs: float, p: float, Vby: float, Zux: float, Zuy: float, Zwx: float,
          Zwy: float, Zs: float, Zth: float, V_start: float) -> tuple[float, ...]:
    """One implicit stage ``Y = Z + Hs F(Y)`` at pressure ``p`` [Pa] with the base's lateral
    slip speed ``Vby`` [m/s] (module docstring).

    Returns
    -------
    tuple
        ``(u_x, u_y, w_x, w_y, s, V, P, E, dT_flash, f_x, f_y, theta)``: the stage state,
        its slip speed, the friction stress ``P = mu_scale p mu`` [Pa] (0 when sticking), the cold
        weight of eq. (28), the hot branch's flash temperature rise [K] and the friction
        stress vector on the tip ``f = A w - g`` [Pa] (what holds a sticking tip), and the
        contact age [s] (``Zth`` unchanged without the law).

    With the contact age (docs/tire-core.md, "contact age") the stage's age is implicit,
    ``theta = (Z_theta + Hs) / (1 + Hs V / D)``, and the friction is read at
    ``v_eff = D / theta = (D + Hs V) / th``, ``th = Z_theta + Hs``; a second-stage
    extrapolation ``Z_theta < 0`` (a stiff relaxation step) counts as a fresh contact.
    """
    t = c.t
    S = _Stage()
    mdt = c.m / Hs
    kdx = c.kx * Hs + c.dx
    kdy = c.ky * Hs + c.dy
    S.t = t
    S.Ax = mdt + kdx
    S.Ay = mdt + kdy
    S.gx = mdt * Zwx - c.kx * Zux + kdx * c.Vbx
    S.gy = mdt * Zwy - c.ky * Zuy + kdy * Vby
    S.G = _norm2(S.gx, S.gy)
    S.pf = c.mu_scale * p
    S.Zs = Zs
    S.Hs = Hs
    S.inv_s0 = t.inv_s0
    S.iso = S.Ax == S.Ay
    S.Amin = S.Ax if S.Ax < S.Ay else S.Ay
    S.Amax = S.Ay if S.Ax < S.Ay else S.Ax
    S.q = t.prep(c.iT, c.fT, p * c.inv_void)
    S.D = c.D
    S.th = Zth + Hs if Zth > 0.0 else Hs
    S.jlo = S.cell_of(-1, 0.0) if S.D > 0.0 else -1
    S.set_cell(S.jlo)
    # the friction at rest: at v_eff(0) = D / th with the contact age, else at the first node
    # (without the age the cell is below the table, ispan = 0: its first node)
    E0 = _cold_weight(Zs * S.inv_s0) if S.inv_s0 > 0.0 else 1.0
    mc, mh, dT0 = S.c0[0], S.c0[1], S.c0[2]
    if S.D > 0.0 and S.ispan > 0.0:
        tt = (math.log10(S.D / S.th) - S.lvj) * S.ispan
        mc = S.c0[0] + S.c1[0] * tt
        mh = S.c0[1] + S.c1[1] * tt
        dT0 = S.c0[2] + S.c1[2] * tt
    mu0 = mh + (mc - mh) * E0
    S.dT = dT0
    if S.G <= mu0 * S.pf:                       # the tip sticks
        return (Zux - Hs * c.Vbx, Zuy - Hs * Vby, 0.0, 0.0, Zs, 0.0, 0.0, E0, S.dT,
                -S.gx, -S.gy, S.th if S.D > 0.0 else Zth)
    V_hi = S.G / (S.Ax if S.Ax < S.Ay else S.Ay)
    Vs = V_start if V_start < V_hi else V_hi
    nv = t.n[0]
    if S.D > 0.0:                               # the cells in V of the mapped nodes
        if not Vs > 0.0:
            v1 = S.vn(S.jlo + 1) if S.jlo + 1 <= nv - 1 else V_hi
            Vs = 0.5 * v1 if 0.5 * v1 < V_hi else 0.5 * V_hi
        j = S.cell_of(S.jlo, Vs)
        if j != S.cell:
            S.set_cell(j)
    elif not Vs > t.vnode[0]:
        if not Vs > 0.0:
            Vs = 0.5 * t.vnode[0] if 0.5 * t.vnode[0] < V_hi else 0.5 * V_hi
    elif Vs >= t.vnode[nv - 1]:
        S.set_cell(nv - 1)
    else:
        j, _ = t.locate(0, math.log10(Vs))
        if Vs < t.vnode[j]:                     # rounding of log10
            j -= 1
        elif Vs >= t.vnode[j + 1]:
            j += 1
        S.set_cell(j)
    r, d = S.resid(Vs)
    if r < 0.0:                                 # accelerating: the first root above
        lo = Vs
        while True:
            last = False
            ub = S.vn(S.cell + 1) if S.cell < nv - 1 else V_hi
            if ub >= V_hi:
                ub, last = V_hi, True
            V = None
            for _ in range(50):                 # Newton from below
                if not d > 0.0:
                    break
                x = lo - r / d
                if not x < ub:
                    break
                rx, dx = S.resid(x)
                if rx >= 0.0:
                    V = S.solve_cell(lo, x, x, rx, dx)
                    break
                tiny = x - lo <= 1e-14 * x
                lo, r, d = x, rx, dx
                if tiny:
                    V = x
                    break
            if V is not None:
                break
            if last:
                r_ub, d_ub = S.resid(ub)
                V = S.solve_cell(lo, ub, ub, r_ub, d_ub) if r_ub >= 0.0 else V_hi
                break
            # walk the nodes above from their values alone (R is continuous across a node)
            # up to the first where R >= 0, or to the cell that holds V_hi
            j = S.cell + 1
            while True:
                # nodes below (G - P_max) / A_max have R < 0 whatever the friction there:
                # skipped without evaluating them (the walk stops where it would anyway)
                if t.smax is not None:
                    Pm = S.pf * t.bound(t.smax, S.q, j)
                    Vb = (S.G * (1.0 - WALK_MARGIN) - Pm) / S.Amax
                    if S.vn(j) < Vb:         # the bound holds at every node above j too
                        stop = False
                        while True:
                            if not (j + 1 <= nv - 1 and S.vn(j + 1) < V_hi):
                                stop = True
                                break
                            j += 1
                            if not S.vn(j) < Vb:
                                break
                        rj = -1.0
                        if stop:
                            break
                        continue
                rj = S.node_resid(j)
                if not (rj < 0.0 and j + 1 <= nv - 1 and S.vn(j + 1) < V_hi):
                    break
                j += 1
            if rj >= 0.0:                       # the root is in [vnode[j-1], vnode[j]]
                if j - 1 != S.cell:
                    S.set_cell(j - 1)
                    lo = S.vn(j - 1)
                r_, d_ = S.resid(S.vn(j))
                V = S.solve_cell(lo, S.vn(j), S.vn(j), r_, d_)
                break
            S.set_cell(j)                       # R < 0 up to node j: go on in cell j
            lo = S.vn(j)
            r, d = S.resid(lo)
    elif r > 0.0:                               # decelerating: the first root below
        hi = Vs
        while True:
            lb = 0.0 if S.cell <= S.jlo else S.vn(S.cell)
            V = None
            for _ in range(50):                 # Newton from above
                if not d > 0.0:
                    break
                x = hi - r / d
                if not x > lb:
                    break
                rx, dx = S.resid(x)
                if rx < 0.0:
                    V = S.solve_cell(x, hi, x, rx, dx)
                    break
                tiny = hi - x <= 1e-14 * hi
                hi, r, d = x, rx, dx
                if tiny:
                    V = x
                    break
            if V is not None:
                break
            if S.cell <= S.jlo:                 # R(0) < 0: the stick test failed
                V = S.solve_cell(0.0, hi, hi, r, d)
                break
            # walk the nodes below from their values alone down to the first where R < 0
            j = S.cell
            while True:
                # nodes above (G - P_min) / A_min have R >= 0 whatever the friction there
                if t.pmin is not None:
                    Pn = S.pf * t.bound(t.pmin, S.q, j)
                    Vd = (S.G * (1.0 + WALK_MARGIN) - Pn) / S.Amin
                    if S.vn(j) >= Vd:        # the bound holds at every node below j too
                        stop = False
                        while True:
                            if not j > S.jlo + 1:
                                stop = True
                                break
                            j -= 1
                            if not S.vn(j) >= Vd:
                                break
                        rj = 1.0
                        if stop:
                            break
                        continue
                rj = S.node_resid(j)
                if not (rj >= 0.0 and j > S.jlo + 1):
                    break
                j -= 1
            if rj < 0.0:                        # the root is in [vnode[j], vnode[j+1]]
                if j != S.cell:
                    S.set_cell(j)
                    hi = S.vn(j + 1)
                r_, d_ = S.resid(S.vn(j))
                V = S.solve_cell(S.vn(j), hi, S.vn(j), r_, d_)
                break
            S.set_cell(S.jlo)                   # R >= 0 down to the first node in reach
            hi = S.vn(S.jlo + 1)
            r, d = S.resid(hi)
    else:
        V = Vs
    P = S.P
    Dx = S.Ax * V + P
    Dy = S.Ay * V + P
    wx = S.gx * V / Dx
    wy = S.gy * V / Dy
    s = Zs + Hs * V
    if s > S_MAX:
        s = S_MAX
    th = S.th / (1.0 + Hs * V / S.D) if S.D > 0.0 else Zth
    return (Zux + Hs * (wx - c.Vbx), Zuy + Hs * (wy - Vby), wx, wy, s, V, P, S.E, S.dT,
            S.Ax * wx - S.gx, S.Ay * wy - S.gy, th)


def integrate(c: Ctx, e: list[float], x_end: float, h_e: float) -> tuple[float, ...]:
    """Integrate element ``e`` (list of :data:`N_ELEM` floats, updated in place) over its
    contact time ``h_e`` [s] ending at position ``x_end`` [m] (module docstring).

    Returns
    -------
    tuple
        ``(energy, V, P, E, dT_flash, p, steps, J_x, J_y, J_m, J_t)``: friction work per
        unit area over the step [J/m^2], the end-of-step slip speed, friction stress, cold
        weight, flash temperature rise, pressure, the sub-steps taken, the impulse of the
        friction (the road's force on the element) per unit area [N s/m^2] with its moment
        about the patch centre [N s/m], and the moment of the impulse of the tread's lateral
        stress on the belt ``k_y u_y + d_y (w_y - V_by)`` [N s/m], by the method's own
        quadrature (weights ``1 - gamma, gamma``).
    """
    ux, uy, wx, wy, s, th = e[0], e[1], e[2], e[3], e[4], e[7]
    Hn = e[5]
    if not Hn > 0.0 or Hn > h_e:
        Hn = h_e
    t = 0.0
    energy = steps = Jx = Jy = Jm = Jt = 0.0
    g1 = (1.0 - GAMMA) / GAMMA
    ig = 1.0 / GAMMA
    o2 = (0.0, 0.0, 0.0, 0.0, 0.0, _norm2(wx, wy), 0.0,
          _cold_weight(s * c.t.inv_s0) if c.t.inv_s0 > 0.0 else 1.0, 0.0, 0.0, 0.0, th)
    p2 = c.pressure(x_end)
    w = c.w
    while h_e - t > 1e-12 * h_e:
        rest = h_e - t
        cut = Hn >= rest
        H = rest if cut else Hn
        if w is not None and not w[0] > 0.0:
            # the outer step's budget is spent: the rest of the element's time in one implicit
            # Euler stage (L-stable: it lands on the stuck or sliding equilibrium of the end of
            # the step, whatever its length)
            pe = c.pressure(x_end)
            vbe = c.Vby + x_end * c.wpsi
            o2 = stage(c, rest, pe, vbe, ux, uy, wx, wy, s, th, _norm2(wx, wy))
            ux, uy, wx, wy, s, th = o2[0], o2[1], o2[2], o2[3], o2[4], o2[11]
            energy += rest * (o2[6] * o2[5])
            Jx += rest * o2[9]
            Jy += rest * o2[10]
            Jm += rest * (x_end * o2[10])
            Jt += rest * (x_end * (c.ky * o2[1] + c.dy * (o2[3] - vbe)))
            steps += 1.0
            w[1] += 1.0
            w[2] += 1.0
            p2 = pe
            break
        if w is not None:
            w[0] -= 1.0
        if H <= H_MIN:
            # event step: at the smallest step a stick-slip event (a snap, instantaneous for a
            # massless tip) is taken with one implicit Euler stage, which lands on the new
            # equilibrium; the SDIRK extrapolation would overshoot it
            xe = x_end + c.Vr * (rest - H)
            pe = c.pressure(xe)
            vbe = c.Vby + xe * c.wpsi
            o2 = stage(c, H, pe, vbe, ux, uy, wx, wy, s, th, _norm2(wx, wy))
            if w is not None:
                w[1] += 1.0
            ux, uy, wx, wy, s, th = o2[0], o2[1], o2[2], o2[3], o2[4], o2[11]
            energy += H * (o2[6] * o2[5])
            Jx += H * o2[9]
            Jy += H * o2[10]
            Jm += H * (xe * o2[10])
            Jt += H * (xe * (c.ky * o2[1] + c.dy * (o2[3] - vbe)))
            steps += 1.0
            p2 = pe
            t += H
            Hn = Hn if cut else 4.0 * H
            continue
        Hs = GAMMA * H
        x1 = x_end + c.Vr * (rest - Hs)
        p1 = c.pressure(x1)
        vb1 = c.Vby + x1 * c.wpsi
        o1 = stage(c, Hs, p1, vb1, ux, uy, wx, wy, s, th, _norm2(wx, wy))
        Zux = ux + g1 * (o1[0] - ux)
        Zuy = uy + g1 * (o1[1] - uy)
        Zwx = wx + g1 * (o1[2] - wx)
        Zwy = wy + g1 * (o1[3] - wy)
        Zs = s + g1 * (o1[4] - s)
        Zth = th + g1 * (o1[11] - th)
        xe = x_end + c.Vr * (rest - H)
        pe = c.pressure(xe)
        vbe = c.Vby + xe * c.wpsi
        o2 = stage(c, Hs, pe, vbe, Zux, Zuy, Zwx, Zwy, Zs, Zth, o1[5])
        if w is not None:
            w[1] += 2.0
        err = abs(o2[0] - (ux + (o1[0] - ux) * ig)) * c.kx
        ey = abs(o2[1] - (uy + (o1[1] - uy) * ig)) * c.ky
        evx = abs(o2[2] - (wx + (o1[2] - wx) * ig)) * c.zx
        evy = abs(o2[3] - (wy + (o1[3] - wy) * ig)) * c.zy
        if ey > err:
            err = ey
        if evx > err:
            err = evx
        if evy > err:
            err = evy
        if c.D > 0.0:
            # the age's error as a friction stress: a relative error e of theta moves the
            # friction by mu_scale p e |dmu / dln v|, taken with |dmu / dln v| <= 1; e is
            # relative to the step's end age and filtered by the age's implicit factor
            # 1 / (1 + Hs V / D) (Hairer and Wanner, sec. IV.8; tirecore.c)
            the = th + (o1[11] - th) * ig
            eth = abs(o2[11] - the) / (1.0 + Hs * o2[5] / c.D) / o2[11] * (c.mu_scale * pe)
            # the friction is constant beyond the table's speed axis: between two ages that
            # both read there (an embedded age <= 0 reads v_eff = inf) it moves nothing
            vlo, vhi = c.t.vnode[0], c.t.vnode[c.t.n[0] - 1]
            if (c.D >= vhi * o2[11] and c.D >= vhi * the) or \
                    (c.D <= vlo * o2[11] and c.D <= vlo * the):
                eth = 0.0
            if eth > err:
                err = eth
        err /= c.tol_abs
        fac = 0.9 / math.sqrt(err) if err > 0.0 else 4.0
        if fac > 4.0:
            fac = 4.0
        if fac < 0.2:
            fac = 0.2
        if err <= 1.0:
            ux, uy, wx, wy, s, th = o2[0], o2[1], o2[2], o2[3], o2[4], o2[11]
            energy += H * ((1.0 - GAMMA) * o1[6] * o1[5] + GAMMA * o2[6] * o2[5])
            Jx += H * ((1.0 - GAMMA) * o1[9] + GAMMA * o2[9])
            Jy += H * ((1.0 - GAMMA) * o1[10] + GAMMA * o2[10])
            Jm += H * ((1.0 - GAMMA) * (x1 * o1[10]) + GAMMA * (xe * o2[10]))
            Jt += H * ((1.0 - GAMMA) * (x1 * (c.ky * o1[1] + c.dy * (o1[3] - vb1)))
                       + GAMMA * (xe * (c.ky * o2[1] + c.dy * (o2[3] - vbe))))
            steps += 1.0
            p2 = pe
            t += H
            Hf = H * fac
            Hn = (Hf if Hf > Hn else Hn) if cut else Hf
        else:
            Hn = H * fac
            if Hn < H_MIN:
                Hn = H_MIN
    e[0], e[1], e[2], e[3], e[4], e[5], e[7] = ux, uy, wx, wy, s, Hn, th
    return energy, o2[5], o2[6], o2[7], o2[8], p2, steps, Jx, Jy, Jm, Jt


def element_stiffness(k: float, d: float, m: float, c: float, h: float) -> float:
    r"""Stiffness [N s/m^3] of one tread element against its base over an outer step ``h``
    (``element_stiffness`` of the core; docs/tire-core.md, "belt").

    The stress the element puts on the belt at the end of the step, per unit step of the base
    velocity at its start, for the element linearised with the secant friction stiffness
    ``c = p mu / |w|``: tip mass ``m``, spring ``k``, damper ``d``. With ``y`` the change of
    the deflection plus ``c / k`` and ``y'`` the relative velocity of tip and base,

    .. math::  y'' + 2 q y' + \omega^2 y = 0, \quad q = (c + d)/2m, \quad \omega^2 = k/m,
               \quad y(0) = c/k, \quad y'(0) = -1,

    and the stiffness is ``J = c - k y(h) - d y'(h)``, in closed form: trigonometric
    (underdamped), hyperbolic (near critical damping), the two exponential modes when the
    friction dominates (the slow rate ``-omega^2 / (q + s)`` taken without cancellation) and
    one exponential for a massless tip or one whose mass the damping and friction dwarf
    (``q`` beyond 1e300). ``c -> infinity`` (a stuck tip) gives ``k h + d``.
    One implicit Euler step of the element, ``(k h + d)(m/h + c)/(m/h + k h + d + c)``,
    underestimates it for an inertia-dominated tip by ``sin(omega h) (1 + omega^2 h^2) /
    (omega h)`` (2.1x at the default 0.25 ms): the cause of the belt's period-2 chatter at
    high rolling speed (docs/tire-core.md).
    """
    if not c < 1e300:                             # held like a stuck tip (c -> infinity)
        return k * h + d
    q = (c + d) / (2.0 * m) if m > 0.0 else math.inf
    if not q < 1e300:                             # massless, or the mass negligible
        cd = c + d
        if not cd > 0.0:                          # a free massless tip carries nothing
            return 0.0
        return c * (d - c * math.expm1(-k * h / cd)) / cd
    w2 = k / m
    w = math.sqrt(w2)
    if q < w:                                     # underdamped
        Om = math.sqrt((w - q) * (w + q))
        C = math.cos(Om * h)
        S = math.sin(Om * h) / Om
    else:
        r = w / q
        s = q * math.sqrt((1.0 - r) * (1.0 + r))
        if s > 0.5 * q:                           # friction-dominated: two real modes
            l1 = -w2 / (q + s)
            l2 = -(q + s)
            e1 = math.exp(l1 * h)
            e2 = math.exp(l2 * h)
            dA = -(k + l1 * c) / (2.0 * s)        # k y = (c + dA) e1 - dA e2
            A = (c + dA) / k
            B = -dA / k
            return -c * math.expm1(l1 * h) - dA * (e1 - e2) - d * (l1 * A * e1 + l2 * B * e2)
        C = math.cosh(s * h)                      # near critical damping
        S = math.sinh(s * h) / s if s > 0.0 else h
    e = math.exp(-q * h)
    return c - e * ((c - d) * C + ((c * c + d * d) / (2.0 * m) - k) * S)


def vertical_stiffness(p) -> float:
    """Vertical stiffness at the inflation pressure [N/m] (MF 6.2; Pacejka 2012, sec. 4.3.2)."""
    return p.C_z * (1.0 + p.p_fz1 * ((p.p_inflation - p.p_nom) / p.p_nom))


def patch_size(p, Fz: float) -> tuple[float, float]:
    """Half-length ``a`` and width ``b`` [m] (Pacejka 2012, eqs. (A3.7)-(A3.8)) with the
    vertical stiffness at the inflation pressure."""
    if not Fz > 0.0:
        return 0.0, 0.0
    r = (Fz if Fz < p.Fz_max else p.Fz_max) / (vertical_stiffness(p) * p.R0)
    return (p.R0 * (p.q_ra2 * r + p.q_ra1 * math.sqrt(r)),
            2.0 * p.width * (p.q_rb2 * r + p.q_rb1 * _cbrt(r)))


def flat_half_length(p, Fz: float, a: float, b: float) -> float:
    """Half-length [m] of the flat centre of the pressure
    (:class:`tire_brush.params.PatchLaw`): ``c/a = 3 Fz / (2 a b p_inflation) - 2`` clipped
    to ``[0, 1 - end_zone]``."""
    f = 3.0 * (Fz / (2.0 * a * b * p.p_inflation)) - 2.0
    if not f > 0.0:
        f = 0.0
    if f > 1.0 - p.end_zone:
        f = 1.0 - p.end_zone
    return f * a


def _cbrt(x: float) -> float:
    """Cube root as C's ``cbrt`` (correctly rounded where ``x ** (1/3)`` is not)."""
    try:
        return math.cbrt(x)                       # Python >= 3.11
    except AttributeError:                        # pragma: no cover
        return x ** (1.0 / 3.0)


def _steady_march(p, t: RefTable, n_cells: int, Vsx: float, Vsy: float, Vr: float, Fz: float,
                  a: float, b: float, T: float, mu_scale: float,
                  wc: float) -> tuple[list[float], float]:
    """One steady march with the belt unyawed and its base spinning at ``wc`` (camber, for
    the march's direction of travel; ``steady_march`` of the core): the outputs of
    :func:`steady_point` and the moment of the tread's stress on the belt [N m] (the friction
    moment less that of the momentum the tread carries through the patch)."""
    out = [0.0] * 10
    sgn = -1.0 if Vr < 0.0 else 1.0
    vr = abs(Vr) if abs(Vr) > V_ROLL_MIN else V_ROLL_MIN
    cf = flat_half_length(p, Fz, a, b)
    mean = (cf + (2.0 / 3.0) * (a - cf)) / a
    c = Ctx(p, t, T, Fz, a, b, cf, Fz / (2.0 * a * b * mean), mu_scale, Vsx, Vsy, vr)
    c.wpsi = wc
    e = [0.0, 0.0, Vsx, Vsy + a * wc, 0.0, 0.0, 1.0, 0.0]
    Jx = Jy = Jm = Jt = nsl = fsl = psl = dTm = steps = work = 0.0
    x_prev = a
    # followed to the trailing edge; the forces are the friction impulse over the transit
    # times b V_r (the patch integral); the diagnostics are read at the cell midpoints
    for j in range(n_cells + 1):
        x = a * (1.0 - (2.0 * j + 1.0) / n_cells) if j < n_cells else -a
        en, V, P, E, dT, pj, st, jx, jy, jm, jt = integrate(c, e, x, (x_prev - x) / vr)
        x_prev = x
        steps += st
        work += en
        Jx += jx
        Jy += jy
        Jm += jm
        Jt += jt
        if j < n_cells and V > CREEP_SPEED:
            nsl += 1.0
            fsl += P
            psl += pj
            d = dT * (1.0 - E)
            if d > dTm:
                dTm = d
    Fx = Jx * b * vr
    Fy = Jy * b * vr
    out[0], out[1], out[2] = Fx, Fy, Jm * b * vr * sgn
    out[3] = _norm2(Fx, Fy) / Fz if Fz > 0.0 else 0.0
    out[4] = fsl / psl if psl > 0.0 else 0.0
    out[5] = nsl / n_cells
    out[6] = dTm
    out[7] = steps
    out[8] = work * b * vr
    out[9] = Jt * b * vr * sgn
    return out, out[9]


#: Largest number of marches of the belt-yaw iteration of one steady point.
YAW_MAX_IT = 60


def steady_point(p, t: RefTable, n_cells: int, Vsx: float, Vsy: float, Vr: float, Fz: float,
                 T: float, mu_scale: float, gamma: float = 0.0) -> list[float]:
    """Steady state of one operating point: one element marched through the patch, the
    stress sampled at ``n_cells`` cell midpoints (``tf_steady`` of the core). Unless the
    carcass is rigid, the belt yaws by ``psi = M_belt / kc_psi`` (``M_belt`` the moment of the
    tread's stress on it) and the tread sees the lateral slip speed ``Vsy - V_r psi``
    (Pacejka 2012, sec. 3.3): ``g(psi) = M_belt(psi)/kc_psi - psi`` is bracketed from 0 and
    its root found by the Illinois variant of regula falsi. Camber ``gamma`` [rad] spins the
    base at ``-(1 - eps) (|V_r| / R_e) sin(gamma)`` (``p.camber_reduction = eps``; the march
    runs forward, and for ``V_r < 0`` it is the mirror image).

    Returns
    -------
    list
        ``[Fx, Fy, Mz, mu_eff, mu_slide, sliding_fraction, dT_flash_max, sub-steps,
        friction power, M_belt]``: the friction work on the road per unit time [W] and the
        moment of the tread's stress on the belt [N m].
    """
    wc = -(1.0 - p.camber_reduction) * (abs(Vr) / p.R_e) * math.sin(gamma)
    a, b = patch_size(p, Fz)
    if not (a > 0.0 and b > 0.0):
        return [0.0] * 10
    o, Mb = _steady_march(p, t, n_cells, Vsx, Vsy, Vr, Fz, a, b, T, mu_scale, wc)
    if p.rigid or Mb == 0.0:
        return o
    steps = o[7]
    lo, glo = 0.0, Mb / p.kc_psi
    hi = glo
    it = 0
    while True:
        oh, Mh = _steady_march(p, t, n_cells, Vsx, Vsy - Vr * hi, Vr, Fz, a, b, T, mu_scale,
                               wc)
        steps += oh[7]
        it += 1
        ghi = Mh / p.kc_psi - hi
        if ghi == 0.0 or (ghi > 0.0) != (glo > 0.0) or it >= YAW_MAX_IT:
            break
        lo, glo = hi, ghi
        hi = 2.0 * hi
    o = oh
    while ghi != 0.0 and it < YAW_MAX_IT and abs(hi - lo) > 1e-12 + 1e-9 * abs(hi):
        x = hi - ghi * (hi - lo) / (ghi - glo)
        o, Mx = _steady_march(p, t, n_cells, Vsx, Vsy - Vr * x, Vr, Fz, a, b, T, mu_scale, wc)
        steps += o[7]
        it += 1
        gx = Mx / p.kc_psi - x
        if gx == 0.0:
            break
        if (gx > 0.0) != (ghi > 0.0):             # the root lies between x and hi
            lo, glo = hi, ghi
        else:                                     # Illinois: halve the kept end's value
            glo *= 0.5
        hi, ghi = x, gx
    o[7] = steps
    return o


def belt_gain(p, V_r: float, a: float, b: float, h: float) -> float:
    """Upper bound of the loop gain of the belt's lateral translation and yaw through the
    rolling speed over an outer step ``h`` (``belt_gain`` of the core; docs/tire-core.md,
    "belt coupling at high rolling speed"): ``(V_r h)^2 J^2 / ((k_cy h + d_cy + J)(k_psi h +
    d_psi + S2))`` with ``J = (k_y h + d_y) 2 a b`` and ``S2 = (k_y h + d_y) 2 a^3 b / 3``,
    the stiffness of a stuck patch against the belt and its second moment."""
    kd = p.k_y * h + p.d_y
    J = kd * (2.0 * a * b)
    S2 = kd * ((2.0 * a * a * a * b) / 3.0)
    vh = V_r * h
    return (vh * vh) * (J * J) / ((p.kc_y * h + p.dc_y + J) * (p.kc_psi * h + p.dc_psi + S2))


def outer_step(p, V_r: float, a: float, b: float) -> float:
    """Longest outer step [s] at rolling speed ``V_r`` [m/s] and patch ``a``, ``b`` [m]
    (``outer_step`` of the core): ``dt_internal``, shortened to resolve the tread tip's period
    (:data:`TIP_STEP`) and to keep :func:`belt_gain` at most :data:`BELT_GAIN_MAX` (the
    largest such step, by bisection)."""
    h = p.dt_internal
    if p.mass > 0.0:
        kmax = p.k_x if p.k_x > p.k_y else p.k_y
        ht = TIP_STEP / math.sqrt(kmax / p.mass)
        if ht < h:
            h = ht
    if p.rigid or not (a > 0.0 and b > 0.0) or not belt_gain(p, V_r, a, b, h) > BELT_GAIN_MAX:
        return h
    lo, hi = 0.0, h
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if belt_gain(p, V_r, a, b, mid) > BELT_GAIN_MAX:
            hi = mid
        else:
            lo = mid
    return lo


class RefTire:
    """The transient tire of the core (``tf_tire``) in Python floats.

    Parameters
    ----------
    p
        Core parameters (:class:`tire_brush.ccore.Params` or any object with its fields).
    t
        Friction table.
    """

    def __init__(self, p, t: RefTable) -> None:
        self.p = p
        self.t = t
        a_nom, _ = patch_size(p, p.Fz_nom)
        self.a_max, _ = patch_size(p, p.Fz_max)
        self.dx = 2.0 * a_nom / p.n_elements
        self.L = math.ceil(2.0 * self.a_max / self.dx) + 2
        self.work = 0.0
        self.stages = 0.0
        self.fallbacks = 0.0
        self.flags = 0
        self.rr: RefTable | None = None
        self.wet: RefWet | None = None
        self.texture_depth = 0.0
        self.scratch: RefTable | None = None
        self.wkey: tuple | None = None
        #: the real-time fidelity's patch table (:mod:`tire_brush.realtime`), or None: full
        self.patch: PatchEval | None = None
        self.reset(math.nan)

    def set_wet(self, w: RefWet | None, texture_depth: float = 0.0) -> None:
        """Wet branch on this tire's table nodes and the road's texture depth [m]
        (``tf_tire_set_wet``)."""
        self.texture_depth = float(texture_depth)
        if w is not None and w.n != self.t.n:
            raise ValueError("the wet branch has other nodes than the friction table")
        self.wet = w
        self.wkey = None
        if w is not None and self.scratch is None:
            s = copy.copy(self.t)
            s.val = list(self.t.val)
            nn = self.t.n[0] * self.t.n[1] * self.t.n[2]
            s.smax = [0.0] * nn
            s.pmin = [0.0] * nn
            self.scratch = s

    def _step_table(self, T0: float, d: float, lt: float) -> RefTable:
        """``step_table`` of the core: the dry table, or the wet branch at water depth ``d``
        and log10 drainage time ``lt`` for the temperature rows of ``T0``."""
        w, t = self.wet, self.t
        if w is None or not d > 0.0:
            return t
        iT, _ = t.locate(1, T0)
        if self.wkey == (d, lt, iT):
            return self.scratch
        i_d, fd = _locate_arr(w.depth, d)
        it, ft = _locate_arr(w.log10_t, lt)
        nv, nT, n_p = t.n
        nn = nv * nT * n_p
        b00 = (i_d * len(w.log10_t) + it) * nn
        b01 = b00 + nn
        b10 = b00 + len(w.log10_t) * nn
        b11 = b10 + nn
        m0 = i_d * nn * 4
        m1 = m0 + nn * 4
        W, M, val = w.w, w.mu, self.scratch.val
        for j in range(nv):
            for r in range(iT, iT + 2):
                for q in range(n_p):
                    node = (j * nT + r) * n_p + q
                    ws = ((1.0 - fd) * ((1.0 - ft) * W[b00 + node] + ft * W[b01 + node])
                          + fd * ((1.0 - ft) * W[b10 + node] + ft * W[b11 + node]))
                    if not ws > 0.0:
                        ws = 0.0
                    if ws > 1.0:
                        ws = 1.0
                    a0 = m0 + node * 4
                    a1 = m1 + node * 4
                    c0 = (1.0 - fd) * M[a0] + fd * M[a1]
                    c1 = (1.0 - fd) * M[a0 + 1] + fd * M[a1 + 1]
                    h0 = (1.0 - fd) * M[a0 + 2] + fd * M[a1 + 2]
                    h1 = (1.0 - fd) * M[a0 + 3] + fd * M[a1 + 3]
                    val[node * 3] = (1.0 - ws) * c0 + ws * c1
                    val[node * 3 + 1] = (1.0 - ws) * h0 + ws * h1
        self.scratch.bounds(iT * n_p, (iT + 2) * n_p)
        self.wkey = (d, lt, iT)
        return self.scratch

    def set_rolling(self, rr: RefTable | None) -> None:
        """Rolling resistance table (``tf_tire_set_rolling``): axes (log10 |V_r|, T_tread,
        log10 Fz), node values (f_r, tread share, unused)."""
        self.rr = rr

    def _rolling(self, vr: float, T: float, Fz: float) -> tuple[float, float]:
        """``rolling`` of the core: trilinear, clamped, proportional to |V_r| below the
        first speed node."""
        rr = self.rr
        v0 = rr.vnode[0]
        scale = 1.0
        if vr < v0:
            scale = vr / v0
            vr = v0
        iv, fv = rr.locate(0, math.log10(vr))
        iT, fT = rr.locate(1, T)
        ip, fp = rr.locate(2, math.log10(Fz))
        nT, n_p = rr.n[1], rr.n[2]
        acc0 = acc1 = 0.0
        for c in range(8):
            dv, dT, dp = c >> 2, (c >> 1) & 1, c & 1
            w = ((fv if dv else 1.0 - fv) * (fT if dT else 1.0 - fT)
                 * (fp if dp else 1.0 - fp))
            if w == 0.0:
                continue
            q = (((iv + dv) * nT + iT + dT) * n_p + ip + dp) * 3
            acc0 += w * rr.val[q]
            acc1 += w * rr.val[q + 1]
        return scale * acc0, acc1

    def reset(self, T_tread: float) -> None:
        """Undeflected tire at rest."""
        self.el = [[0.0] * N_ELEM for _ in range(self.L)]
        self.x_top = self.a_max
        self.delta = [0.0, 0.0]
        self.Vb = [0.0, 0.0]
        self.F = [0.0, 0.0]
        self.psi = self.wpsi = self.M = self.wc = 0.0
        self.T_tread = T_tread
        self.time = 0.0
        self.out = [0.0] * N_OUT
        self.flags = 0

    def get_state(self) -> list[float]:
        """State vector in the core's layout."""
        return ([float(STATE_VERSION), float(self.L), self.x_top, *self.delta, *self.Vb,
                 *self.F, self.T_tread, self.time, *self.out, self.psi, self.wpsi, self.M,
                 self.wc]
                + [x for e in self.el for x in e])

    def set_state(self, buf) -> None:
        """Restore :meth:`get_state`."""
        buf = [float(x) for x in buf]
        self.x_top = buf[2]
        self.delta = buf[3:5]
        self.Vb = buf[5:7]
        self.F = buf[7:9]
        self.T_tread, self.time = buf[9], buf[10]
        self.out = buf[11:11 + N_OUT]
        self.psi, self.wpsi, self.M, self.wc = buf[23], buf[24], buf[25], buf[26]
        self.el = [buf[STATE_HEAD + i * N_ELEM:STATE_HEAD + (i + 1) * N_ELEM]
                   for i in range(self.L)]

    def _tread_stiffness(self, c: Ctx, h: float) -> tuple[float, float, float, float]:
        """Stiffness of the tread against the belt over the outer step ``h`` and its first and
        second moments about the patch centre (``tread_stiffness`` of the core):
        :func:`element_stiffness` per element, ``k h + d`` for a stuck one."""
        p = self.p
        jx = jy = s1 = s2 = 0.0
        kdx = p.k_x * h + p.d_x
        kdy = p.k_y * h + p.d_y
        t = c.t
        for i, e in enumerate(self.el):
            if e[6] == 0.0:
                continue
            V = _norm2(e[2], e[3])
            x = self.x_top - i * self.dx
            if V == 0.0:
                jx += kdx
                jy += kdy
                s1 += x * kdy
                s2 += x * (x * kdy)
                continue
            pr = c.pressure(x)
            S = _Stage()
            S.t = t
            S.q = t.prep(c.iT, c.fT, pr * c.inv_void)
            j = -1
            if V > t.vnode[0]:
                if V >= t.vnode[t.n[0] - 1]:
                    j = t.n[0] - 1
                else:
                    j, _ = t.locate(0, math.log10(V))
            S.set_cell(j)
            S.Ax = S.Ay = 1.0
            S.gx = S.gy = 0.0
            S.G = 1.0
            S.pf = c.mu_scale * pr
            S.Zs = e[4]
            S.Hs = 0.0
            S.inv_s0 = t.inv_s0
            S.D = 0.0                             # the secant at |w| (a linearisation)
            S.th = 1.0
            S.iso = True
            S.resid(V)
            cs = S.P / V
            if not cs > 0.0:                      # no friction (or a negative table value)
                cs = 0.0
            ex = element_stiffness(p.k_x, p.d_x, p.mass, cs, h)
            ey = element_stiffness(p.k_y, p.d_y, p.mass, cs, h)
            jx += ex
            jy += ey
            s1 += x * ey
            s2 += x * (x * ey)
        return jx, jy, s1, s2

    def _advance(self, h, Vsx, Vsy, V_r, Fz, a, b, Ts, mus, wc, q_roll, d_water,
                 lt_drain) -> list[float]:
        p = self.p
        dx, L = self.dx, self.L
        x_top = self.x_top - V_r * h
        shift = math.floor((x_top - self.a_max) / dx)
        x_top -= shift * dx
        self.x_top = x_top
        sh = int(shift)
        if sh != 0:
            zero = [[0.0] * N_ELEM for _ in range(min(abs(sh), L))]
            if abs(sh) >= L:
                self.el = [[0.0] * N_ELEM for _ in range(L)]
            elif sh > 0:
                self.el = self.el[sh:] + zero
            else:
                self.el = zero + self.el[:L + sh]
        T0 = self.T_tread if p.thermal else Ts
        area = b * dx
        any_in = False
        wsum = 0.0
        cf = flat_half_length(p, Fz, a, b) if a > 0.0 and b > 0.0 else 0.0
        iac = 1.0 / (a - cf) if a > 0.0 else 0.0
        for i in range(L):
            x = x_top - i * dx
            e = self.el[i]
            inside = a > 0.0 and area > 0.0 and -a < x < a
            exiting = (not inside and a > 0.0 and area > 0.0 and e[6] != 0.0
                       and ((V_r > 0.0 and x <= -a and x + V_r * h > -a)
                            or (V_r < 0.0 and x >= a and x + V_r * h < a)))
            if not inside and not exiting:
                self.el[i] = [0.0] * N_ELEM
                continue
            # time mean over the step of the element's pressure shape (Simpson over its
            # contact within the step)
            x0 = x + V_r * h
            x1 = x
            x0 = a if x0 > a else (-a if x0 < -a else x0)
            x1 = a if x1 > a else (-a if x1 < -a else x1)
            frac = (x0 - x1) / (V_r * h) if V_r != 0.0 else 1.0
            wm = (shape(cf, iac, x0) + 4.0 * shape(cf, iac, 0.5 * (x0 + x1))
                  + shape(cf, iac, x1)) / 6.0
            if V_r == 0.0:
                wm = shape(cf, iac, x1)
            if inside:
                any_in = True
            wsum += frac * wm
        if not wsum > 0.0:
            any_in = False
        if not any_in:
            if not p.rigid:
                self.delta = [self.delta[0] * (p.dc_x / (p.kc_x * h + p.dc_x)),
                              self.delta[1] * (p.dc_y / (p.kc_y * h + p.dc_y))]
                self.psi *= p.dc_psi / (p.kc_psi * h + p.dc_psi)
            self.Vb = [Vsx, Vsy - V_r * self.psi]
            self.wpsi = 0.0
            self.wc = wc
            self.F = [0.0, 0.0]
            self.M = 0.0
            if p.thermal:
                self.T_tread = (self.T_tread + h / p.heat_capacity * (p.conductance * Ts)) / (
                    1.0 + h * p.conductance / p.heat_capacity)
            return [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        c = Ctx(p, self._step_table(T0, d_water, lt_drain), T0, Fz, a, b, cf,
                Fz / (area * wsum), mus, Vsx, Vsy, V_r)
        # the friction is read at T0: outside the table's temperature axis it is its edge's
        Tax = self.t.ax[1]
        if not (Tax[0] <= T0 <= Tax[-1]):
            self.flags |= FLAG_T_RANGE
        w = [float(BUDGET) * p.n_elements, 0.0, 0.0]
        c.w = w
        Vbx, Vby, wpsi = Vsx, Vsy, 0.0
        if not p.rigid:
            # belt translation and yaw, linearly implicit (docs/tire-core.md, "belt"): the
            # base of element i moves at Vby + x_i (wpsi + wc) laterally, Vby = Vsy + uy -
            # V_r psi, wc the spin from camber; the tread force is linearised in the change
            # of the total spin, hence wpsi_n + wc_n - wc below
            Jx, Jy, S1, S2 = self._tread_stiffness(c, h)
            Jx *= area
            Jy *= area
            S1 *= area
            S2 *= area
            ux = (self.F[0] - Jx * (Vsx - self.Vb[0]) - p.kc_x * self.delta[0]) / (
                p.kc_x * h + p.dc_x + Jx)
            D0 = (Vsy - V_r * self.psi) - self.Vb[1]
            a11 = p.kc_y * h + p.dc_y + Jy
            a12 = S1 - V_r * h * Jy
            a21 = S1
            a22 = p.kc_psi * h + p.dc_psi + S2 - V_r * h * S1
            wn = self.wpsi + (self.wc - wc)
            b1 = self.F[1] - p.kc_y * self.delta[1] - Jy * D0 + S1 * wn
            b2 = self.M - p.kc_psi * self.psi - S1 * D0 + S2 * wn
            det = a11 * a22 - a12 * a21
            uy = (b1 * a22 - a12 * b2) / det
            wpsi = (a11 * b2 - a21 * b1) / det
            self.delta = [self.delta[0] + h * ux, self.delta[1] + h * uy]
            self.psi += h * wpsi
            Vbx, Vby = Vsx + ux, (Vsy + uy) - V_r * self.psi
        c.Vbx, c.Vby, c.wpsi = Vbx, Vby, wpsi + wc
        Jx = Jy = Jm = heat = nsl = fsl = psl = dTm = n_in = Tx = Ty = Tm = 0.0
        for i in range(L):
            x = x_top - i * dx
            e = self.el[i]
            if not (-a < x < a):
                if e[6] == 0.0:
                    continue
                # left the patch during the step: integrated up to the trailing edge
                xe = -a if V_r > 0.0 else a
                h_x = (x + V_r * h - xe) / V_r
                if not h_x > 0.0:
                    self.el[i] = [0.0] * N_ELEM
                    continue
                energy, _, _, _, _, _, st, jx, jy, jm, _ = integrate(c, e, xe, h_x)
                self.work += st
                Jx += jx
                Jy += jy
                Jm += jm
                heat += energy
                self.el[i] = [0.0] * N_ELEM
                continue
            h_e = h
            if e[6] == 0.0:                       # enters: tip moving with the belt
                if V_r > 0.0:
                    h_e = (a - x) / V_r
                elif V_r < 0.0:
                    h_e = (a + x) / -V_r
                if h_e > h:
                    h_e = h
                x_in = x + V_r * h_e              # where it entered
                e[:] = [0.0, 0.0, Vbx, Vby + x_in * c.wpsi, 0.0, h_e, 1.0, 0.0]  # fresh contact
            energy, V, P, E, dT, pe, st, jx, jy, jm, _ = integrate(c, e, x, h_e)
            self.work += st
            Tx += c.kx * e[0] + c.dx * (e[2] - Vbx)
            ty = c.ky * e[1] + c.dy * (e[3] - (Vby + x * c.wpsi))
            Ty += ty
            Tm += x * ty
            Jx += jx
            Jy += jy
            Jm += jm
            heat += energy
            n_in += 1.0
            if V > CREEP_SPEED:
                nsl += 1.0
                fsl += P
                psl += pe
                d = dT * (1.0 - E)
                if d > dTm:
                    dTm = d
        self.stages += w[1]
        self.fallbacks += w[2]
        if w[2] > 0.0:
            self.flags |= FLAG_BUDGET
        self.Vb = [Vbx, Vby]
        self.wpsi = wpsi
        self.wc = wc
        self.F = [Tx * area, Ty * area]
        self.M = Tm * area
        if p.thermal:
            # friction heat (its share heat_fraction enters the rubber) and the tread's share
            # of the rolling loss q_roll [W], generated inside the tread
            Q = heat * area
            self.T_tread = (self.T_tread + (p.heat_fraction * Q + h * q_roll
                                            + h * p.conductance * Ts)
                            / p.heat_capacity) / (1.0 + h * p.conductance / p.heat_capacity)
        return [1.0, 0.0, nsl / n_in, fsl / psl if psl > 0.0 else 0.0, dTm, Jx * area,
                Jy * area, Jm * area]

    def step(self, dt: float, vx: float, vy: float, omega: float, Fz: float, Ts: float,
             mus: float, gamma: float = 0.0, d_water: float = 0.0) -> list[float]:
        """Advance by ``dt`` [s] (``tf_tire_step``); inputs must be valid."""
        p = self.p
        if math.isnan(self.T_tread):
            self.T_tread = Ts
        self.flags = 0
        if 0.0 < dt < DT_FLOOR:
            self.time += dt
        elif dt > 0.0:
            if Fz < 0.0:
                Fz = 0.0
            V_r = omega * p.R_e
            # water: dynamic hydroplaning lifts the share L of the load off the road; the
            # tread carries Fz_road = (1 - L) Fz
            Fz_road, lt_drain = Fz, 0.0
            wet = self.wet if d_water > 0.0 else None
            if wet is not None:
                Vp = 6.35 * math.sqrt(p.p_inflation / 1e3) / 3.6
                de = d_water - (p.void_ratio * p.tread_depth + self.texture_depth)
                sd = de / wet.d_full if de > 0.0 else 0.0
                if sd > 1.0:
                    sd = 1.0
                rv = (vx / Vp) * (vx / Vp)
                if rv > 1.0:
                    rv = 1.0
                Fz_road = (1.0 - sd * rv) * Fz
            a, b = patch_size(p, Fz_road)
            # equal outer steps no longer than dt_internal and the coupling's limits (the
            # real-time fidelity: no longer than dt_internal)
            h_max = p.dt_internal if self.patch is not None else outer_step(p, V_r, a, b)
            ns = math.ceil(dt / h_max - 1e-9)
            n_sub = int(ns) if ns > 1.0 else 1
            h = dt / n_sub
            if wet is not None and a > 0.0:   # drainage time: drain_scale t_footprint at
                U = 0.5 * (abs(vx) + abs(V_r))    # the entrainment speed (wet_friction)
                lt_drain = math.log10(wet.drain_scale * (2.0 * a / U)) if U > 0.0 else math.inf
            # camber: the base spins at -(1 - eps) omega sin(gamma)
            wc = -(1.0 - p.camber_reduction) * omega * math.sin(gamma)
            # rolling resistance at the start of the step, held over it
            f_r = share = 0.0
            if self.rr is not None and Fz > 0.0:
                f_r, share = self._rolling(abs(V_r), self.T_tread if p.thermal else Ts, Fz)
            q_roll = share * f_r * Fz * abs(V_r)
            fin = [0.0]
            Ix = Iy = Im = 0.0
            for _ in range(n_sub):
                if self.patch is not None:
                    fin = rt_advance(p, self.patch, self, h, vx - V_r, vy, V_r, Fz_road, a,
                                     Ts, mus, gamma, q_roll,
                                     d_water if wet is not None else 0.0)
                    self.wc = wc
                else:
                    fin = self._advance(h, vx - V_r, vy, V_r, Fz_road, a, b, Ts, mus, wc,
                                        q_roll, d_water, lt_drain)
                Ix += fin[5]
                Iy += fin[6]
                Im += fin[7]
            self.time += dt
            ref = abs(vx) if abs(vx) > p.v_floor else p.v_floor
            kappa = (omega * p.R_e - vx) / ref
            if vx < 0.0:
                kappa = -kappa
            alpha = math.atan2(-vy, ref)
            T0 = self.T_tread if p.thermal else Ts
            o = self.out
            # the road force: the friction impulse of the step over its length; a step
            # shorter than the output window W = dt_internal moves the outputs towards its
            # mean by dt/W only (a first-order relaxation): O(dt) changes as dt -> 0
            W = p.dt_internal
            if dt >= W:
                o[0], o[1], o[2] = Ix / dt, Iy / dt, Im / dt
                o[5] = _norm2(o[0], o[1]) / Fz if Fz > 0.0 else 0.0
            else:
                o[0] += (Ix - dt * o[0]) / W
                o[1] += (Iy - dt * o[1]) / W
                o[2] += (Im - dt * o[2]) / W
                # the utilised friction relaxes the same way, towards the step's own
                # |I| / (dt Fz) (at most mu_scale max(mu)): the relaxed force over the step's
                # load would be unbounded as the load drops to 0
                o[5] = o[5] + (_norm2(Ix, Iy) / Fz - dt * o[5]) / W if Fz > 0.0 else 0.0
            if fin[0] == 0.0:
                o[6] = o[7] = o[8] = 0.0
            else:
                o[6], o[7], o[8] = fin[3], fin[2], fin[4]
            o[3], o[4], o[9] = kappa, alpha, T0
            # overturning moment of the load, shifted sideways by the belt's deflection,
            # about the contact centre; rolling resistance moment against the spin
            o[10] = 0.0 if p.rigid else -self.delta[1] * Fz
            sgn = 1.0 if V_r > 0.0 else (-1.0 if V_r < 0.0 else 0.0)
            o[11] = sgn * (f_r * Fz * p.R_e)
        return list(self.out)
