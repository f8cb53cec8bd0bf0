r"""One time step of many brush (tread) elements: stick, or slide with eq. (28) friction.

The element (per unit footprint area) is a tip of mass ``m`` joined to the belt by a shear
spring ``k`` and a damper ``d`` (Kelvin-Voigt), anisotropic in x and y. With the deflection
``u = tip - base`` [m], the tip's slip velocity over the road ``w`` [m/s] and the belt (base)
slip velocity ``V_b`` [m/s]:

.. math::  \dot u = w - V_b, \qquad m \dot w = f - k u - d (w - V_b),

where ``f`` is the friction stress from the road: while the tip sticks (``w = 0``),
``|f| <= mu(0, s) p``; while it slides, ``f = -mu(|w|, s) p w/|w|`` with ``mu`` from eq. (28)
of the review (:mod:`tire_brush.friction`), ``s`` the slipped distance since the element entered
the footprint. The stress on the belt (the tire) is ``tau = k u + d (w - V_b)``.

Time discretisation: implicit (backward) Euler for the linear part, so one step reads

.. math::  A w^+ = g + f^+, \quad A = m/\Delta t + d + k \Delta t,
           \quad g = (m/\Delta t) w - k u + (k \Delta t + d) V_b ;

``-g`` is the friction needed to hold the tip (stick test ``|g| <= mu(0, s) p``); a sliding tip
moves along ``(A + mu p/|w^+|)^{-1} g`` with ``|w^+|`` the root of
``A_e V + p mu(V) = |g|`` (``A_e``: ``A`` weighted by the direction of ``g``; exact for
isotropic elements and pure slip, one Newton step on the 2-D magnitude corrects combined slip).
The root is sought from the previous speed (continuation: the tip's velocity is continuous):
``n_newton - 1`` Newton steps in ``ln V`` on the table (piecewise linear in log10 v, with exact
slopes), then the implicit solve with mu linearised at the last iterate.

Eq. (28)'s cold weight is the mean of ``exp(-s(t)/s0)`` over the step at a predicted slip
speed ``V_p`` (``ds = V_p dt``, ``s`` the slipped distance at the start of the step):

.. math::  E = \frac{s_0}{ds}\left(e^{-s/s_0} - e^{-(s + ds)/s_0}\right)
             = e^{-s/s_0}\,\frac{-\mathrm{expm1}(-ds/s_0)}{ds/s_0}
             \;\to\; e^{-s/s_0} \quad (ds \to 0),

evaluated in the second form (``ds/s0`` floored at :data:`W_FLOOR`, where the factor is 1 to
rounding). Why the mean: with s0 ~ 0.2 mm a sliding element moves ``V dt`` >> s0 in one
step (1 m/s x 1 ms = 1 mm), so the weight at either end of the step misstates the
cold -> hot transition (at the end: the element is on the hot branch after one step). The
mean makes the friction impulse over a step exact for constant slip
speed: what is left is first order in the speed change over the step. Limits: s0 -> inf gives
1 (cold only); s0 -> 0 gives ``s0/ds -> 0`` in an element's first sliding step, so the
static/kinetic law switches to the kinetic value within it, as before; sticking elements
(``V_p = 0``) get ``exp(-s/s0)``.

Velocity weakening. A massless element (``m = d = 0``) gives ``A = k dt`` and a step that is
ill posed on a falling mu(v) branch as dt -> 0 (physics-notes: several roots). The tip mass
makes ``A >= m/dt`` grow as dt -> 0: the continuous model is well posed and the steps converge
(tests: element count and step size). Where a step is too coarse for that
(``A + p dmu/dV <= 0``), the Newton steps are damped and the falling slope in the final solve is
limited to ``-0.9 A / p``: over that step the weakening is treated explicitly and the root
nearest the previous speed is followed. On steep falling branches the elements stick-slip
along the patch (physical for a massive slider with velocity weakening); forces then converge
roughly first order in the cell size and the transient force carries a fluctuation of a few
percent of Fz.

This module imports only numpy: it runs inside an FMU.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .friction import BranchTable, FrictionQuery
from .params import TreadParams

#: Elements slipping slower than this [m/s] count as adhering in the sliding fraction and the
#: flash temperature (creep on the rising, low-speed branch of Persson's mu(v)); it does not
#: change any force.
CREEP_SPEED = 1e-3
#: Largest slipped distance carried [m] (eq. 28 is fully hot long before; keeps s finite).
S_MAX = 1e6
#: Fraction of A up to which a falling friction chord is treated implicitly (module docstring).
SLOPE_LIMIT = 0.9
#: Floor of ``Vp dt / s0`` in the step-averaged cold weight (module docstring): below it the
#: weight's factor ``-expm1(-x)/x`` is 1 to rounding, and ``x = 0`` needs no branch.
W_FLOOR = 1e-300


@dataclass(frozen=True)
class ElementProps:
    """Tread element properties as arrays shaped for broadcasting over ``(2, n)`` arrays.

    Attributes
    ----------
    k, d : ndarray
        Stiffness [N/m^3] and damping [N s/m^3] per unit area, shape ``(2, 1)`` (x, y).
    m : float
        Tip mass per unit area [kg/m^2].
    isotropic : bool
        Whether ``k`` and ``d`` are equal in x and y (then the slide solve is closed form).
    """

    k: np.ndarray
    d: np.ndarray
    m: float
    isotropic: bool

    @classmethod
    def from_tread(cls, tread: TreadParams, *, massless: bool = False) -> ElementProps:
        """Properties of :class:`~tire_brush.params.TreadParams`; ``massless`` drops the tip
        mass and the damping (Pacejka's brush of ch. 3)."""
        k = np.array([[tread.k_x], [tread.k_y]])
        d = np.zeros((2, 1)) if massless else np.array([[tread.d_x], [tread.d_y]])
        return cls(k, d, 0.0 if massless else float(tread.mass),
                   bool(tread.k_x == tread.k_y and (massless or tread.d_x == tread.d_y)))


@dataclass
class StepResult:
    """What one element step returns besides the updated state.

    Attributes
    ----------
    tau : ndarray
        Stress on the belt ``k u + d (w - V_b)`` at the end of the step [Pa], shape ``(2, n)``.
    slide : ndarray
        Bool, shape ``(n,)``: the element was friction-limited (not sticking) in this step.
    friction : ndarray
        Friction stress ``mu_scale mu p`` [Pa] of eq. (28) on sliding elements (undefined
        where sticking).
    speed : ndarray
        Slip speed ``|w|`` at the end of the step [m/s] (0 where sticking).
    cold : ndarray
        Cold weight of eq. (28) averaged over the step at the predicted speed (module
        docstring).
    dT_flash : ndarray
        Hot-branch flash temperature rise at the final linearisation speed [K].
    """

    tau: np.ndarray
    slide: np.ndarray
    friction: np.ndarray
    speed: np.ndarray
    cold: np.ndarray
    dT_flash: np.ndarray


@dataclass
class StepCoefficients:
    """Per-step constants of the implicit element step for one step size (module docstring).

    Attributes
    ----------
    kd : ndarray
        ``k dt + d`` [N s/m^3], shape ``(2, 1)`` or ``(2, n)``.
    A : ndarray
        ``m/dt + k dt + d`` [N s/m^3], same shape.
    mdt : ndarray or float
        ``m / dt`` [N s/m^3] (0 for a massless tip).
    floor : ndarray
        Lower limit ``-SLOPE_LIMIT min(A_x, A_y)`` of ``p dmu/dV`` [N s/m^3].
    dt : float or ndarray
        The step [s].
    """

    kd: np.ndarray
    A: np.ndarray
    mdt: np.ndarray | float
    floor: np.ndarray
    dt: float | np.ndarray

    @classmethod
    def build(cls, props: ElementProps, dt: float | np.ndarray) -> StepCoefficients:
        """Coefficients for step ``dt`` [s] (scalar, or one per element)."""
        kd = props.k * dt
        kd += props.d
        mdt = props.m / dt if props.m > 0.0 else 0.0
        A = kd + mdt
        A_min = A[0] if props.isotropic else np.minimum(A[0], A[1])
        return cls(kd, A, mdt, -SLOPE_LIMIT * A_min, dt)


def element_step(state: np.ndarray, pf: np.ndarray, Vb: np.ndarray, props: ElementProps,
                 co: StepCoefficients, table: BranchTable, q: FrictionQuery, *,
                 n_newton: int = 2, V0: np.ndarray | None = None) -> StepResult:
    """Advance elements by one implicit step (module docstring), updating ``state`` in place.

    Parameters
    ----------
    state
        Shape ``(5, n)``: rows ``u_x, u_y`` [m], ``w_x, w_y`` [m/s], ``s`` [m].
    pf
        Pressure times road-friction scale, ``mu_scale * p`` [Pa], shape ``(n,)``.
    Vb
        Belt slip velocity [m/s], shape ``(2, 1)`` or ``(2, n)``.
    props
        Element properties.
    co
        Step coefficients (:meth:`StepCoefficients.build`).
    table
        Friction branches (:class:`~tire_brush.friction.BranchTable`).
    q
        ``table.prepare(T0, p_rubber)``: the step's temperature and pressures on the rubber,
        with the branches at v -> 0.
    n_newton
        Friction evaluations per step (>= 1): ``n_newton - 1`` Newton steps in ``ln |w|`` from
        the predicted speed (the start speed if sliding, the hot-branch estimate if not), then
        the implicit solve with the friction linearised at the last one.
    V0
        ``|w|`` at the start [m/s] if the caller has it.

    Notes
    -----
    Eq. (28)'s cold weight is the mean of ``exp(-s/s0)`` over the step (module docstring) at
    a predicted speed: the start speed for an element that was sliding, the hot-branch
    estimate ``(|g| - mu_hot(0) p) / A`` for one that starts to slide (so that the
    static/kinetic limit s0 -> 0 uses the kinetic value from its first sliding step).
    """
    u = state[0:2]
    w = state[2:4]
    s = state[4]
    k, A, dt = props.k, co.A, co.dt
    inv_s0 = table.inv_s0
    g = k * u
    np.subtract(co.kd * Vb, g, out=g)                 # g = (k dt + d) Vb - k u (+ m w / dt)
    if props.m > 0.0:
        g += co.mdt * w
    G = np.hypot(g[0], g[1])
    if V0 is None:
        V0 = np.hypot(w[0], w[1])
    mu0 = q.mu0
    dmu0 = mu0[0] - mu0[1]
    # stick test against eq. (28) at v -> 0 with the slip distance so far
    E0 = np.exp(-s * inv_s0)
    stick = G <= (mu0[1] + dmu0 * E0) * pf
    if props.isotropic:
        Ae = A[0] * np.ones_like(G) if A.shape[1] != G.size else A[0]
    else:
        g2 = g * g
        Ae = A[1] + (A[0] - A[1]) * (g2[0] / np.maximum(g2[0] + g2[1], 1e-300))
    V_hi = G / Ae                                     # the root lies below: mu >= 0
    # cold weight averaged over the step at a predicted speed: with y = -Vp dt / s0,
    # E = exp(-s/s0) (exp(y) - 1) / y (y floored at -1e-300: the limit y -> 0 gives exactly 1)
    Vp = np.where(V0 > 0.0, V0, np.maximum(G - mu0[1] * pf, 0.0) / Ae)
    y = Vp * dt * -inv_s0
    np.minimum(y, -W_FLOOR, out=y)
    E = np.expm1(y) / y * E0
    # Newton steps in ln V on  Ae V + p mu(V) = |g|  from the predicted speed
    V = np.maximum(np.minimum(Vp, V_hi), table.v_floor)
    for _ in range(n_newton - 1):
        br, dl = table.at(V, q, slope=True)
        AV = Ae * V
        f = br[1] + (br[0] - br[1]) * E
        f *= pf
        f += AV
        f -= G
        fp = (dl[1] + (dl[0] - dl[1]) * E) * pf
        fp += AV
        np.maximum(fp, 0.1 * AV, out=fp)             # falling branch: damped step
        step = np.clip(f / fp, -10.0, 10.0)
        V = np.maximum(np.minimum(V * np.exp(-step), V_hi), table.v_floor)
    # implicit solve with mu linearised at V: mu(V') ~ (pa + pb V') / p
    br, dl = table.at(V, q, slope=True)
    pb = np.maximum((dl[1] + (dl[0] - dl[1]) * E) * (pf / V), co.floor)
    pa = (br[1] + (br[0] - br[1]) * E) * pf - pb * V
    B = A + pb
    if props.isotropic:
        V = (G - pa) / B[0]
    else:
        V = (G - pa) * (G * G) / np.maximum(g2[0] * B[0] + g2[1] * B[1], 1e-300)
        np.maximum(V, 0.0, out=V)
        # one Newton step on |(B V + p a)^-1 g| = 1 (exact for pure slip along an axis)
        D = B * V + pa
        np.maximum(D, 1e-9, out=D)
        r = g2 / (D * D)
        qq = r[0] + r[1]
        dq = (r * B / D).sum(axis=0)
        V = V - (qq - qq * np.sqrt(qq)) / np.maximum(dq, 1e-300)
    np.maximum(V, 0.0, out=V)
    slide = ~stick
    V *= slide
    D = B * V
    D += pa
    D += 1e-300
    w_new = g * (V / D)
    # state update: u+ = u + dt (w+ - Vb); s+ = s + |w+| dt
    rel = w_new - Vb
    u += dt * rel
    w[...] = w_new
    s += V * dt
    np.minimum(s, S_MAX, out=s)
    tau = k * u
    tau += props.d * rel
    return StepResult(tau, slide, pa + pb * V, V, E, br[2])


def march_point(props: ElementProps, rows: list, mu0: list, p: list, pf: list, xi: list,
                dts: tuple[float, float], Vb: tuple[float, float], v_axis: tuple,
                inv_s0: float, n_newton: int) -> tuple[float, ...]:
    """One element through the patch for a single operating point, in Python floats.

    The same implicit step as :func:`element_step` (line for line, scalars instead of arrays):
    for one point numpy's per-call overhead dominates, and this path is ~5x faster. Tests pin
    the two to each other.

    Parameters
    ----------
    props
        Element properties.
    rows
        Per cell, the branches at the table's speed nodes at this cell's (T, p):
        ``rows[j] = (mu_cold, mu_hot, dT_flash)`` lists of length ``nv + 1`` (last node
        repeated).
    mu0
        Per cell ``(mu_cold, mu_hot)`` at v -> 0.
    p, pf
        Per cell gross pressure and ``mu_scale * p`` [Pa].
    xi
        Per cell position ``x / a``.
    dts
        First (half-cell) and regular step [s].
    Vb
        Slip velocity of the element bases [m/s].
    v_axis
        ``(log10 v_floor, 1/spacing in log10 v, n nodes - 1, list of 1/(ln 10 spacing))``:
        the table's speed axis (uniform).
    inv_s0
        ``1/s0`` of eq. (28) [1/m].
    n_newton
        Friction evaluations per step.

    Returns
    -------
    tuple
        Sums over the cells: ``Fx, Fy`` (stress), ``sum xi tau_y``, number of sliding cells,
        friction stress and pressure of sliding cells, largest flash temperature.
    """
    (kx,), (ky,) = props.k.tolist()
    (dx,), (dy,) = props.d.tolist()
    m = props.m
    iso = props.isotropic
    lv0, inv_lv, n_max, inv_dlnv = v_axis
    v_floor = 10.0 ** lv0
    Vbx, Vby = Vb
    exp, expm1, hypot, log10, sqrt = math.exp, math.expm1, math.hypot, math.log10, math.sqrt
    coef = []
    for h in dts:
        kdx, kdy = kx * h + dx, ky * h + dy
        mdt = m / h if m > 0.0 else 0.0
        Ax, Ay = kdx + mdt, kdy + mdt
        coef.append((h, kdx, kdy, mdt, Ax, Ay, -SLOPE_LIMIT * (Ax if iso else min(Ax, Ay))))

    def look(row: tuple, V: float) -> tuple[float, ...]:
        t = (log10(max(V, v_floor)) - lv0) * inv_lv
        t = min(max(t, 0.0), n_max)
        i = int(t)
        f = t - i
        c, hh, dT = row
        dc, dh = c[i + 1] - c[i], hh[i + 1] - hh[i]
        s_ = inv_dlnv[i] if V >= v_floor else 0.0
        return c[i] + f * dc, hh[i] + f * dh, dT[i] + f * (dT[i + 1] - dT[i]), dc * s_, dh * s_

    ux = uy = wx = wy = s = 0.0
    Fx = Fy = Mz = n_slide = f_slide = p_slide = dT_max = 0.0
    for j in range(len(p)):
        h, kdx, kdy, mdt, Ax, Ay, floor = coef[0] if j == 0 else coef[1]
        pj, pfj = p[j], pf[j]
        gx = kdx * Vbx - kx * ux + mdt * wx
        gy = kdy * Vby - ky * uy + mdt * wy
        G = hypot(gx, gy)
        V0 = hypot(wx, wy)
        m0c, m0h = mu0[j]
        E0 = exp(-s * inv_s0)
        stick = G <= (m0h + (m0c - m0h) * E0) * pfj
        if iso:
            Ae = Ax
        else:
            g2x, g2y = gx * gx, gy * gy
            Ae = Ay + (Ax - Ay) * (g2x / max(g2x + g2y, 1e-300))
        V_hi = G / Ae
        Vp = V0 if V0 > 0.0 else max(G - m0h * pfj, 0.0) / Ae
        y = min(Vp * h * -inv_s0, -W_FLOOR)
        E = expm1(y) / y * E0
        V = max(min(Vp, V_hi), v_floor)
        row = rows[j]
        for _ in range(n_newton - 1):
            mc, mh, _dT, dc, dh = look(row, V)
            AV = Ae * V
            f = (mh + (mc - mh) * E) * pfj + AV - G
            fp = max((dh + (dc - dh) * E) * pfj + AV, 0.1 * AV)
            step = min(max(f / fp, -10.0), 10.0)
            V = max(min(V * exp(-step), V_hi), v_floor)
        mc, mh, dT, dc, dh = look(row, V)
        pb = max((dh + (dc - dh) * E) * (pfj / V), floor)
        pa = (mh + (mc - mh) * E) * pfj - pb * V
        Bx, By = Ax + pb, Ay + pb
        if iso:
            V = (G - pa) / Bx
        else:
            V = max((G - pa) * (G * G) / max(g2x * Bx + g2y * By, 1e-300), 0.0)
            Dx, Dy = max(Bx * V + pa, 1e-9), max(By * V + pa, 1e-9)
            rx, ry = g2x / (Dx * Dx), g2y / (Dy * Dy)
            qq = rx + ry
            V = V - (qq - qq * sqrt(qq)) / max(rx * Bx / Dx + ry * By / Dy, 1e-300)
        V = 0.0 if stick else max(V, 0.0)
        wx = gx * (V / (Bx * V + pa + 1e-300))
        wy = gy * (V / (By * V + pa + 1e-300))
        relx, rely = wx - Vbx, wy - Vby
        ux += h * relx
        uy += h * rely
        s = min(s + V * h, S_MAX)
        tauy = ky * uy + dy * rely
        Fx += kx * ux + dx * relx
        Fy += tauy
        Mz += xi[j] * tauy
        if V > CREEP_SPEED:
            n_slide += 1.0
            f_slide += pa + pb * V
            p_slide += pj
            dT_max = max(dT_max, dT * (1.0 - E))
    return Fx, Fy, Mz, n_slide, f_slide, p_slide, dT_max


class _Workspace:
    """Preallocated arrays (and their row views) of :class:`LatticeStepper` for ``n``
    elements: the step writes every intermediate into them."""

    __slots__ = ("A", "A0", "A1", "Ae", "B", "B0", "B1", "D", "D0", "D1", "E", "E0", "G", "V",
                 "V_hi", "Vn", "Vp", "d", "den", "dq", "floor", "g", "g0", "g1", "g2", "g2_0",
                 "g2_1", "k", "kd", "mdt", "pa", "pb", "pos", "qq", "r", "r0", "r1", "rel",
                 "slide", "t1", "t2", "t2_0", "t2_1", "tau", "thr")

    def __init__(self, props: ElementProps, n: int) -> None:
        self.k = np.repeat(props.k, n, axis=1)        # (2, n) rows of k and d
        self.d = np.repeat(props.d, n, axis=1)
        self.kd, self.mdt, self.rel, self.tau = (np.empty((2, n)) for _ in range(4))
        self.A, self.g, self.g2, self.B, self.D, self.r, self.t2 = (
            np.empty((2, n)) for _ in range(7))
        self.A0, self.A1 = self.A
        self.g0, self.g1 = self.g
        self.g2_0, self.g2_1 = self.g2
        self.B0, self.B1 = self.B
        self.D0, self.D1 = self.D
        self.r0, self.r1 = self.r
        self.t2_0, self.t2_1 = self.t2
        (self.floor, self.G, self.thr, self.Ae, self.V_hi, self.Vp, self.E, self.E0, self.V,
         self.Vn, self.pb, self.pa, self.den, self.qq, self.dq, self.t1) = np.empty((16, n))
        self.slide = np.empty(n, dtype=bool)
        self.pos = np.empty(n, dtype=bool)


class LatticeStepper:
    """:func:`element_step` fused for the transient model's lattice (one call per sub-step).

    The same implicit step, operation for operation, so the results are identical to the
    bit (pinned by the tests against :func:`element_step` through the transient model). At
    ~100 elements numpy's per-call overhead, not arithmetic, sets the cost, so the step
    removes calls and their overhead: constants are bound once (0-d arrays, cheaper ufunc
    operands than Python floats), x and y run as ``(2, n)`` rows with same-shape operands
    (numpy's broadcasting machinery costs more than a second call at this size),
    intermediates are written into preallocated arrays (:class:`_Workspace`, one per
    element count), and the table is read through
    :meth:`~tire_brush.friction.BranchTable.at_sliding` (the linearisation speed never drops
    below the table's ``v_floor``).

    Parameters
    ----------
    props
        Element properties.
    table
        Friction branches.
    n_newton
        Friction evaluations per step (as :func:`element_step`).
    """

    def __init__(self, props: ElementProps, table: BranchTable, n_newton: int) -> None:
        self.props = props
        self.table = table
        self.n_newton = n_newton
        (kx,), (ky,) = props.k.tolist()
        (dx,), (dy,) = props.d.tolist()
        # row of A that is the smaller one for every step size (A_x - A_y keeps the sign of
        # k_x - k_y and d_x - d_y when those agree); None: take the element-wise minimum
        if props.isotropic or (kx <= ky and dx <= dy):
            self._a_min_row: int | None = 0
        elif kx >= ky and dx >= dy:
            self._a_min_row = 1
        else:
            self._a_min_row = None
        self._c = tuple(np.array(x) for x in (-table.inv_s0, table.v_floor, 0.0, 1e-300,
                                              1e-9, S_MAX, -SLOPE_LIMIT, props.m, -W_FLOOR))
        self._work: dict[int, _Workspace] = {}

    def step(self, state: np.ndarray, pf: np.ndarray, Vb: np.ndarray, dt: float | np.ndarray,
             dt1: float | np.ndarray, q: FrictionQuery, V0: np.ndarray) -> tuple:
        """Advance elements by one implicit step of :func:`element_step`, updating ``state``
        in place.

        Parameters
        ----------
        state
            Shape ``(5, n)``, C-contiguous: rows ``u_x, u_y`` [m], ``w_x, w_y`` [m/s],
            ``s`` [m].
        pf
            ``mu_scale * p`` [Pa], shape ``(n,)``.
        Vb
            Belt slip velocity [m/s], shape ``(2, n)`` (equal columns).
        dt
            The step [s]: a float, or shape ``(2, n)`` with two equal rows (one step per
            element, :meth:`StepCoefficients.build`).
        dt1
            ``dt`` as a float or one row, shape ``(n,)``.
        q
            ``table.prepare(T0, p_rubber)``.
        V0
            ``|w|`` at the start [m/s].

        Returns
        -------
        tuple
            ``(tau, friction, speed, cold, dT_flash)`` as the fields of :class:`StepResult`.
            The arrays belong to the stepper and are overwritten by its next step.
        """
        mul, add, sub, div = np.multiply, np.add, np.subtract, np.divide
        maximum, minimum = np.maximum, np.minimum
        neg_inv_s0, v_floor, zero, tiny, d_floor, s_max, neg_slope, m0, neg_w_floor = self._c
        props = self.props
        n = state.shape[1]
        W = self._work.get(n)
        if W is None:
            W = self._work[n] = _Workspace(props, n)
        # step coefficients (StepCoefficients.build)
        kd, A = W.kd, W.A
        mul(W.k, dt, kd)
        add(kd, W.d, kd)
        massive = props.m > 0.0
        if not massive:
            mdt = zero
        elif isinstance(dt, np.ndarray):
            mdt = div(m0, dt, W.mdt)
        else:
            mdt = props.m / dt                        # a scalar step keeps its own type
        add(kd, mdt, A)
        row = self._a_min_row
        floor = mul(W.A1 if row == 1 else W.A0 if row == 0 else minimum(W.A0, W.A1),
                    neg_slope, W.floor)
        u = state[0:2]
        w = state[2:4]
        s = state[4]
        # g = (k dt + d) Vb - k u (+ m w / dt)
        g, t2, t1 = W.g, W.t2, W.t1
        mul(kd, Vb, g)
        sub(g, mul(W.k, u, t2), g)
        if massive:
            add(g, mul(mdt, w, t2), g)
        G = np.hypot(W.g0, W.g1, W.G)
        mu0 = q.mu0
        mu0h = mu0[1]
        # stick test against eq. (28) at v -> 0 with the slip distance so far
        E0 = np.exp(mul(s, neg_inv_s0, W.E0), W.E0)
        thr = mul(E0, sub(mu0[0], mu0h, t1), W.thr)
        add(thr, mu0h, thr)
        mul(thr, pf, thr)
        slide = np.logical_not(np.less_equal(G, thr, W.slide), W.slide)   # as ~(G <= thr)
        iso = props.isotropic
        if iso:
            Ae = W.A0
        else:
            g2 = mul(g, g, W.g2)
            Ae = add(W.g2_0, W.g2_1, W.Ae)
            maximum(Ae, tiny, out=Ae)
            div(W.g2_0, Ae, Ae)
            mul(Ae, sub(W.A0, W.A1, t1), Ae)
            add(Ae, W.A1, Ae)
        V_hi = div(G, Ae, W.V_hi)                     # the root lies below: mu >= 0
        # cold weight averaged over the step at a predicted speed (element_step)
        Vp = mul(mu0h, pf, W.Vp)
        sub(G, Vp, Vp)
        maximum(Vp, zero, out=Vp)
        div(Vp, Ae, Vp)
        np.copyto(Vp, V0, where=np.greater(V0, zero, W.pos))   # V0 where V0 > 0
        E = mul(Vp, dt1, W.E)                         # y = -Vp dt / s0, floored at -W_FLOOR
        mul(E, neg_inv_s0, E)
        minimum(E, neg_w_floor, out=E)
        div(np.expm1(E, t1), E, E)
        mul(E, E0, E)
        V = minimum(Vp, V_hi, out=W.V)
        maximum(V, v_floor, out=V)
        table = self.table
        for _ in range(self.n_newton - 1):
            mu_c, mu_h, _, dmu_c, dmu_h = table.at_sliding(V, q)
            AV = Ae * V
            f = mu_c - mu_h
            f *= E
            f += mu_h
            f *= pf
            f += AV
            f -= G
            fp = dmu_c - dmu_h
            fp *= E
            fp += dmu_h
            fp *= pf
            fp += AV
            maximum(fp, 0.1 * AV, out=fp)            # falling branch: damped step
            step = np.clip(f / fp, -10.0, 10.0)
            np.negative(step, out=step)
            np.exp(step, out=step)
            V *= step
            minimum(V, V_hi, out=V)
            maximum(V, v_floor, out=V)
        # implicit solve with mu linearised at V: mu(V') ~ (pa + pb V') / p, eq. (28) blends
        # of the table's slope (pb) and value (pa)
        mu_c, mu_h, dT, dmu_c, dmu_h = table.at_sliding(V, q)
        pb = sub(dmu_c, dmu_h, W.pb)
        mul(pb, E, pb)
        add(pb, dmu_h, pb)
        mul(pb, div(pf, V, t1), pb)
        maximum(pb, floor, out=pb)
        pa = sub(mu_c, mu_h, W.pa)
        mul(pa, E, pa)
        add(pa, mu_h, pa)
        mul(pa, pf, pa)
        sub(pa, mul(pb, V, t1), pa)
        B, B0, B1, D, D0, D1 = W.B, W.B0, W.B1, W.D, W.D0, W.D1
        add(W.A0, pb, B0)
        add(W.A1, pb, B1)
        V = sub(G, pa, W.Vn)
        if iso:
            div(V, B0, V)
        else:
            mul(V, mul(G, G, t1), V)
            mul(g2, B, t2)
            den = add(W.t2_0, W.t2_1, W.den)
            maximum(den, tiny, out=den)
            div(V, den, V)
            maximum(V, zero, out=V)
            # one Newton step on |(B V + p a)^-1 g| = 1 (exact for pure slip along an axis)
            add(mul(B0, V, D0), pa, D0)
            add(mul(B1, V, D1), pa, D1)
            maximum(D, d_floor, out=D)
            r = mul(D, D, W.r)
            div(g2, r, r)
            qq = add(W.r0, W.r1, W.qq)
            mul(r, B, r)
            div(r, D, r)
            dq = add(W.r0, W.r1, W.dq)
            maximum(dq, tiny, out=dq)
            corr = np.sqrt(qq, t1)
            mul(corr, qq, corr)
            sub(qq, corr, corr)
            div(corr, dq, corr)
            sub(V, corr, V)
        maximum(V, zero, out=V)
        mul(V, slide, V)
        add(mul(B0, V, D0), pa, D0)
        add(mul(B1, V, D1), pa, D1)
        add(D, tiny, D)
        div(V, D0, D0)
        div(V, D1, D1)
        mul(g, D, w)
        # state update: u+ = u + dt (w+ - Vb); s+ = s + |w+| dt
        rel = sub(w, Vb, W.rel)
        add(u, mul(rel, dt, t2), u)
        add(s, mul(V, dt1, t1), s)
        minimum(s, s_max, out=s)
        tau = mul(W.k, u, W.tau)
        add(tau, mul(W.d, rel, t2), tau)
        mul(pb, V, pb)
        add(pb, pa, pb)
        return tau, pb, V, E, dT
