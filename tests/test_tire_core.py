"""The compiled tire core: equal to its Python reference, converged at its defaults, smooth at
standstill, and against independent references (Pacejka's closed forms; a brute-force march
of a massive element written here; the creep speed of a parked car from the grid itself).

Tolerances:

* core vs reference: 1e-10 relative (the two perform the same IEEE operations; they are
  equal to the bit on this machine, the tolerance leaves room for another libm);
* convergence: the defaults within 1 % of Fz of the converged value (the accuracy the
  defaults promise, docs/tire-core.md), the converged value taken at 4x the element count,
  1/10 of the outer step and 1/100 of the tolerance;
* closed forms: 1e-3 of mu Fz for the massless brush and for full sliding (only the
  discretisation of the pressure parabola remains: O(1/n^2));
* brute-force element: 2e-3 of mu Fz (its fixed step of 0.2 us leaves ~1e-3).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest
from brush_cases import T20, pacejka_like, passenger, peaked_grid, with_contact_age, without_thermal

from lookup.grid import FrictionGrid
from lookup.grid.store import load_grid
from tire_brush import element as ref_core
from tire_brush import reference as ref
from tire_brush.friction import BranchTable, ConstantFriction, GridFriction
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire

FZ = 4000.0


@pytest.fixture(scope="module")
def grid() -> FrictionGrid:
    return load_grid()


@pytest.fixture(scope="module")
def tire():
    return passenger()


@pytest.fixture(scope="module")
def pac():
    """The passenger tire with Pacejka's parabolic pressure and a rigid carcass: the brush of
    the closed forms and of the independent marches below."""
    return pacejka_like(passenger())


#: The transient tread stick-slips without end at 0 C on the realistic summer compound's
#: default grid, and the steady march at its defaults misses one 0 C case by 1.02 % of Fz:
#: open, written down in docs/tire-core.md ("Convergence"). With the tread's contact age on
#: (off in the shipped tire, docs/tire-core.md "contact age") the same cases pass.
#: Strict: when the cases converge these tests pass and the mark must go.
OPEN_0C = pytest.mark.xfail(strict=True, reason="0 C stick-slip on the realistic compound "
                            "(docs/tire-core.md, Convergence: open)")


def _omega(tire, kappa: float, vx: float) -> float:
    return vx * (1.0 + kappa) / tire.R_e


# -- convergence at the defaults -------------------------------------------------------------
def _transient_fx(tire, grid, T_C: float, kappa: float, vx: float, Fz: float, alpha: float = 0.0,
                  t_end: float = 0.25, **kw) -> np.ndarray:
    """Mean (Fx, Fy) / Fz over the last 50 ms of a held operating point."""
    tr = TransientBrushTire(without_thermal(tire), grid, **kw)
    om, vy = _omega(tire, kappa, vx), -vx * math.tan(alpha)
    out = np.array([tr.step_array(1e-3, vx, vy, om, Fz, 273.15 + T_C)
                    for _ in range(round(t_end / 1e-3))])
    return out[-50:, :2].mean(axis=0) / Fz


@pytest.mark.parametrize("T_C,ageing", [pytest.param(0.0, False, marks=OPEN_0C), (0.0, True),
                                        (20.0, False)])
def test_result_does_not_depend_on_the_outer_step(tire, grid, T_C, ageing) -> None:
    """kappa -0.06, 27.8 m/s, 4 kN: the outer (lattice and belt) step of 1 ms, 0.25 ms (the
    default) and 0.1 ms give the same force within 0.3 % of Fz. Elements leaving the patch
    during a step are integrated up to the trailing edge and the pressure is normalised by
    its time mean over the step; dropping the leavers' last part-step, as the core once did,
    lost 3.4 % (0 C) and 8 % (20 C) of Fz at 1 ms."""
    tire = with_contact_age(tire, ageing)
    f = [_transient_fx(tire, grid, T_C, -0.06, 27.8, FZ, dt_internal=h)[0]
         for h in (1e-3, 2.5e-4, 1e-4)]
    assert max(f) - min(f) < 3e-3, f"{T_C} C: Fx/Fz at outer steps 1, 0.25, 0.1 ms: {f}"


@pytest.mark.parametrize("T_C,ageing", [pytest.param(0.0, False, marks=OPEN_0C), (0.0, True),
                                        (20.0, False), (50.0, False)])
def test_defaults_are_converged_braking(tire, grid, T_C, ageing) -> None:
    """kappa -0.06, 27.8 m/s, 4 kN (the case whose old answer depended on the solver): the
    transient model at its defaults, the same at 8x the elements, 1/10 the outer step and
    1/100 the tolerance, and the steady model converged, agree within 1 % of Fz. Both
    transient runs hold the inputs 0.25 s: at 0 C the fine run rings (stick-slip of the
    tread, 3 % of Fz) for ~0.15 s after the start before it settles."""
    tire = with_contact_age(tire, ageing)
    default = _transient_fx(tire, grid, T_C, -0.06, 27.8, FZ)[0]
    fine = _transient_fx(tire, grid, T_C, -0.06, 27.8, FZ, n_elements=256, dt_internal=2.5e-5,
                         tol=1e-4)[0]
    steady = float(SteadyBrush(tire, grid, n_elements=256, tol=1e-4).solve(
        -0.06, 0.0, 27.8, FZ, 273.15 + T_C).Fx) / FZ
    assert abs(default - fine) < 1e-2, f"{T_C} C: defaults {default:.4f} vs fine {fine:.4f}"
    assert abs(default - steady) < 1e-2, f"{T_C} C: defaults {default:.4f} vs steady {steady:.4f}"


@pytest.mark.parametrize("T_C,vx,Fz,ageing", [
    pytest.param(T, v, F, False, marks=OPEN_0C) if (T, v, F) == (0.0, 10.0, 2000.0)
    else (T, v, F, False)
    for T, v, F in itertools.product((0.0, 20.0, 50.0), (10.0, 30.0), (2000.0, 6000.0))]
    + [(0.0, 10.0, 2000.0, True)])
def test_steady_defaults_converged_over_shipped_cases(tire, grid, T_C, vx, Fz, ageing) -> None:
    """The steady model at its defaults within 1 % of Fz of a converged run (4x the cells,
    1/100 the tolerance) over 0-50 C, kappa -0.02..-1, alpha 0..15 deg, 10-30 m/s, 2-6 kN.
    At 0 C, 10 m/s, 2 kN the realistic compound's stick-slipping tread puts kappa -0.06 at
    1.02 % (docs/tire-core.md): expected to fail until the tread model settles it; with the
    tread's contact age on it passes."""
    tire = with_contact_age(tire, ageing)
    k = np.array([-0.02, -0.06, -0.15, -0.4, -1.0, 0.0, 0.0, 0.0, -0.05])
    a = np.radians([0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 6.0, 15.0, 4.0])
    d = SteadyBrush(tire, grid).solve(k, a, vx, Fz, 273.15 + T_C)
    c = SteadyBrush(tire, grid, n_elements=256, tol=1e-4).solve(k, a, vx, Fz, 273.15 + T_C)
    err = np.hypot(d.Fx - c.Fx, d.Fy - c.Fy).max() / Fz
    assert err < 1e-2, f"{T_C} C, {vx} m/s, {Fz} N: defaults off by {err:.2%}"


# -- closed forms and an independent element march ------------------------------------------
def test_massless_brush_matches_pacejka_at_defaults(pac) -> None:
    a, b = pac.patch.size(FZ)
    cpx = pac.tread.k_x * b
    kappa = np.linspace(-0.5, 0.3, 33)
    sx, _ = ref.theoretical_slip(kappa, 0.0)
    F = SteadyBrush(pac, ConstantFriction(1.0), massless=True).solve(kappa, 0.0, 20.0, FZ,
                                                                      T20).Fx
    err = np.abs(F - ref.brush_force(sx, 1.0, FZ, a, cpx)).max() / FZ
    assert err < 1e-3, f"massless brush off Pacejka's closed form by {err:.2e} mu Fz"


@pytest.mark.parametrize("vx", [10.0, 30.0])
def test_full_sliding_with_tread_mass_is_mu_fz(pac, vx) -> None:
    """Elements enter with the belt's velocity, and the force is the road's friction on
    them: full sliding gives mu Fz with the default tip mass (it was 1-2.5 % above). On the
    parabolic pressure: with the shipped flat-topped one the steeper pressure rise at the
    leading edge lets an entering tip catch for a moment in strong driving slip (kappa 0.5,
    10 m/s: 0.29 % below mu Fz, converged in cells and tolerance; docs/tire-core.md)."""
    tire = pac
    kappa = np.array([-1.0, -0.5, 0.5, 1.0])
    for model in (SteadyBrush(tire, ConstantFriction(0.9)),):
        F = model.solve(kappa, 0.0, vx, FZ, T20).Fx
        np.testing.assert_allclose(np.abs(F), 0.9 * FZ, rtol=1e-3)
    tr = TransientBrushTire(without_thermal(tire), ConstantFriction(0.9))
    for _ in range(150):
        o = tr.step(1e-3, vx, 0.0, _omega(tire, -0.5, vx), FZ, T20)
    assert abs(o.Fx) == pytest.approx(0.9 * FZ, rel=1e-3), "transient full sliding: mu Fz"


def _brute_force_element_march(tire, mu: float, kappa: float, vx: float, n_cells: int,
                               h: float = 2e-7) -> float:
    """Fx of the steady massive brush by an independent march: one element, fixed step ``h``,
    semi-implicit Euler with Coulomb friction (stick when the force that holds the tip is
    below mu p, else slide with friction mu p against the tip's velocity), the force sampled
    at the cell midpoints. Shares no code with the core."""
    tr = tire.tread
    a, b = tire.patch.size(FZ)
    Vs, Vr = -kappa * vx, vx * (1.0 + kappa)
    xi = 1.0 - (2.0 * np.arange(n_cells) + 1.0) / n_cells
    p_amp = FZ / (b * 2.0 * a / n_cells * float(np.sum(1.0 - xi * xi)))
    u, w, x = 0.0, Vs, a
    F, j = 0.0, 0
    while j < n_cells:
        x_next = x - Vr * h
        p = p_amp * max(1.0 - x_next * x_next / (a * a), 0.0)
        # implicit in w and u: m (w+ - w)/h = f - k u+ - d (w+ - Vs), u+ = u + h (w+ - Vs)
        A = tr.mass / h + tr.k_x * h + tr.d_x
        g = tr.mass / h * w - tr.k_x * u + (tr.k_x * h + tr.d_x) * Vs
        if abs(g) <= mu * p:
            w_new, f = 0.0, -g
        else:
            f = -math.copysign(mu * p, g)
            w_new = (g + f) / A
        u += h * (w_new - Vs)
        w = w_new
        if x_next <= a * xi[j]:
            F += f
            j += 1
        x = x_next
    return F * b * 2.0 * a / n_cells


@pytest.mark.parametrize("kappa", [-0.1, -0.03, 0.05])
def test_massive_brush_against_brute_force_march(pac, kappa) -> None:
    """With the default tip mass and damping, partial sliding departs from the massless closed
    form (the entering tip must be stopped first: up to ~2.5 % of mu Fz at 30 m/s,
    docs/tire-core.md); the core reproduces an independent fine-step march of the same
    massive element."""
    vx, n = 20.0, 32
    core = float(SteadyBrush(pac, ConstantFriction(1.0), n_elements=n).solve(
        kappa, 0.0, vx, FZ, T20).Fx)
    brute = _brute_force_element_march(pac, 1.0, kappa, vx, n)
    assert abs(core - brute) < 2e-3 * FZ, f"core {core:.1f} N vs brute force {brute:.1f} N"


def test_tip_mass_departure_from_pacejka_grows_as_sqrt_mass(pac) -> None:
    """Partial sliding with constant friction: the massive brush carries less force than
    Pacejka's massless closed form because an element entering at the slip speed must first be
    stopped by the small friction at the leading edge (docs/tire-core.md, "Tip mass and the
    closed forms"). Without damping, the departure halves (factor 0.5 +- 0.05: sqrt) when the
    mass is divided by 4, and at 1/4096 of the mass (1/64 of the departure) the brush is within
    1e-3 of mu Fz of the closed form."""
    a, b = pac.patch.size(FZ)
    vx, kappa = 30.0, -0.06
    sx, _ = ref.theoretical_slip(np.array([kappa]), 0.0)
    closed = float(ref.brush_force(sx, 1.0, FZ, a, pac.tread.k_x * b)[0])

    def departure(scale: float) -> float:
        tread = dataclasses.replace(pac.tread, d_x=0.0, d_y=0.0, mass=pac.tread.mass * scale)
        t = dataclasses.replace(pac, tread=tread)
        F = float(SteadyBrush(t, ConstantFriction(1.0), n_elements=128, tol=1e-4).solve(
            kappa, 0.0, vx, FZ, T20).Fx)
        return (F - closed) / FZ

    d1, d4, d_light = departure(1.0), departure(0.25), departure(1.0 / 4096.0)
    assert d1 > 0.02, f"the massive brush departs (less braking force): {d1:+.4f}"
    assert d4 / d1 == pytest.approx(0.5, abs=0.05), f"not sqrt(m): {d1:+.4f}, {d4:+.4f}"
    assert abs(d_light) < 1e-3, f"light tip off the closed form by {d_light:+.2e} mu Fz"


def test_eq28_along_the_slip_path_of_a_sliding_patch(pac) -> None:
    """Eq. (28) at a realistic s0 through the compiled core: a massless brush in full
    sliding on a flat two-branch friction. Each element obeys k u = -mu(s) p and
    s' = V_s - (mu(s) p)'/k, so s + mu(s) p(t)/k = V_s t along its path; solved here for s by
    bisection and integrated over the patch, F = b V_r int mu(s(t)) p(t) dt."""
    mu_c, mu_h, s0 = 1.1, 0.7, 2e-3           # s0 = 0.2 D with D = 10 mm
    grid = FrictionGrid.constant(mu_c, mu_h, s0_m=s0)
    kappa, vx = -0.15, 20.0                  # just past full sliding (lambda ~ 1.15)
    Vs, Vr = -kappa * vx, vx * (1.0 + kappa)
    a, b = pac.patch.size(FZ)
    k = pac.tread.k_x
    p_amp = 0.75 * FZ / (a * b)
    t = np.linspace(0.0, 2.0 * a / Vr, 4001)
    p = p_amp * (1.0 - ((a - Vr * t) / a) ** 2)

    def mu(s):
        return mu_h + (mu_c - mu_h) * np.exp(-s / s0)

    lo, hi = np.zeros_like(t), Vs * t + 1e-12
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        f = mid + mu(mid) * p / k - Vs * t
        lo, hi = np.where(f < 0, mid, lo), np.where(f < 0, hi, mid)
    F_ref = -b * Vr * np.trapezoid(mu(lo) * p, t)
    F = float(SteadyBrush(pac, GridFriction(grid), massless=True).solve(
        kappa, 0.0, vx, FZ, T20).Fx)
    assert F == pytest.approx(F_ref, rel=1e-3), f"eq. (28) along the path: {F:.1f} vs {F_ref:.1f}"
    # s0 matters at this scale: halving it changes the force far beyond the tolerance
    assert abs(F_ref - (-b * Vr * np.trapezoid(mu(2.0 * lo) * p, t))) > 5e-3 * FZ


def test_tread_heat_is_the_friction_work(tire) -> None:
    """Energy balance of the tread temperature: a massless brush with constant friction
    sliding over the whole patch (rigid carcass; elements enter and leave undeflected) turns
    all the work of the road force, -Fx V_sx, into friction heat; the tread warms as
    C dT/dt = eta P - G (T - T_surface), integrated here from that power. (A massless tip on
    a falling mu(v) is ill posed, docs/review-notes.md: not used here.)"""
    th = tire.thermal
    tr = TransientBrushTire(tire, ConstantFriction(1.0), thermal=True, rigid_carcass=True,
                            massless=True)
    vx, kappa, T0 = 20.0, -0.5, 293.15
    out = np.array([tr.step_array(1e-3, vx, 0.0, _omega(tire, kappa, vx), FZ, T0)
                    for _ in range(400)])
    Fx, T = out[:, 0], out[:, 9]
    P = -Fx * (-kappa * vx)                   # friction power [W]
    # implicit Euler of the lumped balance with the model's own power history
    Tm = T0
    for Pk in P:
        Tm = (Tm + 1e-3 / th.heat_capacity * (th.heat_fraction * Pk + th.conductance * T0)) / (
            1.0 + 1e-3 * th.conductance / th.heat_capacity)
    assert T[-1] - T0 > 1.0, "sliding warms the tread"
    assert T[-1] - T0 == pytest.approx(Tm - T0, rel=2e-2), "tread heat = eta x friction work"


# -- standstill and a parked car -------------------------------------------------------------
@pytest.mark.parametrize("T_C", [0.0, 20.0, 50.0])
def test_locked_wheel_to_standstill_is_smooth(tire, grid, T_C) -> None:
    """Locked wheel, vx ramped 2 -> 0 m/s over 1 s, then held: once the inputs are steady no
    step-to-step change above 1 % Fz (the old belt coupling chattered here by 0.2-0.76 Fz)."""
    tr = TransientBrushTire(tire, grid)
    F = np.array([tr.step_array(1e-3, max(2.0 * (1.0 - k / 1000.0), 0.0), 0.0, 0.0, FZ,
                                273.15 + T_C)[0] for k in range(1300)])
    jump = np.abs(np.diff(F[1000:])).max() / FZ
    assert jump < 1e-2, f"{T_C} C: jump of {jump:.2%} Fz at standstill"
    assert np.isfinite(F).all() and F[-1] < 0.0, "the stopped tire holds a braking force"


def _parked_car(tire, grid, T_C: float, grade: float, t_end: float, ageing: bool = False,
                **kw) -> tuple:
    """Mean speed [m/s] over the second half of ``t_end`` and final position [m] of a quarter
    car (load FZ) parked with a locked wheel on a grade (rise/run), gravity along the slope
    FZ * grade; ``ageing``: the tread's contact age."""
    m = FZ / 9.81
    tire = with_contact_age(tire, ageing)
    tr = TransientBrushTire(without_thermal(tire), grid, **kw)
    v, x, h, n = 0.0, 0.0, 1e-3, round(t_end / 1e-3)
    xs = []
    for k in range(n):
        Fx = tr.step_array(h, v, 0.0, 0.0, FZ, 273.15 + T_C)[0]
        # the grade is applied smoothly over 0.6 s (the car on its tire is a ~4 Hz, lightly
        # damped oscillator: a sudden release would set it rocking)
        ramp = 0.5 * (1.0 - math.cos(math.pi * min(k * h / 0.6, 1.0)))
        v += h * (FZ * grade * ramp + Fx) / m
        x += h * v
        xs.append(x)
    return (xs[-1] - xs[n // 2]) / (h * (n - 1 - n // 2)), x


def test_parked_car_same_answer_at_every_setting(tire, grid) -> None:
    """A parked car (wheel locked): where the grade needs less than the friction at the
    table's lowest speed it holds, else it creeps at the speed where mu(v) Fz balances the
    grade (docs/physics.md); every solver setting gives the same answer. Without the contact
    age: with it the creep is the same in the end (steady sliding reads the grid unchanged),
    but an element's age reaches the creep's D / v = 1 mm / 7e-5 m/s = 14 s only after 14 s
    of contact, so within the 6 s here the car still holds (checked at the end)."""
    settings = ({}, {"dt_internal": 1e-4}, {"n_elements": 96, "tol": 1e-3})
    # 20 C: the grid's mu at 1 um/s is ~0.16 (pressure-weighted over the patch) and a 5 %
    # grade holds (the car rocks by a millimetre on the tire); 50 C: mu(1 um/s) is ~0.011, a
    # 10 % grade creeps
    held = [_parked_car(tire, grid, 20.0, 0.05, 2.0, **s) for s in settings]
    # holding: the car settles ~0.65 mm downhill and rocks about it by ~0.02 mm (a lightly
    # damped 4 Hz oscillation on the tire), so its mean speed over a second stays below
    # 5e-5 m/s; creeping at 50 C is 7e-5 m/s. The creep settles slowly (the rocking decays
    # while the car creeps; mean over 1-2 s: +50 %, over 2-4 s: -18 %), so it is averaged over
    # the second half of 6 s (measured -4 % against the balance below)
    for v, x in held:
        assert abs(v) < 5e-5 and 0.0 < x < 2e-3, f"20 C, 5 %: holds (v {v:.2e}, x {x:.2e})"
    v50 = [_parked_car(tire, grid, 50.0, 0.1, 6.0, **s)[0] for s in settings]
    assert min(v50) > 0.0 and max(v50) / min(v50) < 1.05, f"50 C, 10 %: creep {v50}"
    # the creep speed is where the grid's friction balances the grade (all elements slide
    # at v; mu(v) = 0.1 on the rising branch, read from the grid at the patch's pressures)
    bt = BranchTable.from_model(GridFriction(grid))
    a, b = tire.patch.size(FZ)
    xi = np.linspace(-0.98, 0.98, 50)
    p = 0.75 * FZ / (a * b) * (1.0 - xi * xi) / (1.0 - tire.tread.void_ratio)

    def mean_mu(v: float) -> float:
        mu = bt.evaluate(np.full_like(p, v), 323.15, p)[0]
        return float(np.sum(mu * (1.0 - xi * xi)) / np.sum(1.0 - xi * xi))

    lo, hi = 1e-7, 1.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if mean_mu(mid) < 0.1 else (lo, mid)
    assert v50[0] == pytest.approx(lo, rel=0.15), f"creep {v50[0]:.3g} vs mu(v) = 0.1 at {lo:.3g}"
    # with the contact age an element parked for t <= 6 s reads the friction at
    # v_eff >= D / 6 s = 1.7e-4 m/s, above the creep speed on the rising branch, where the
    # friction exceeds the grade's 0.1: the car holds (speed as the 20 C case)
    D = GridFriction(grid).s0 / 0.2
    assert mean_mu(D / 6.0) > 0.1
    v_aged, _ = _parked_car(tire, grid, 50.0, 0.1, 6.0, ageing=True)
    assert abs(v_aged) < 5e-5, f"50 C, 10 %, contact age: holds for 6 s (v {v_aged:.2e})"


def test_cold_weight_follows_the_slip_path_of_eq28() -> None:
    """Eq. (28) for one element at a realistic s0, hand-integrated: a tip dragged at a
    constant slip speed V over a flat two-branch friction slides with
    mu(s) = mu_hot + (mu_cold - mu_hot) exp(-s/s0), s = V t; its friction work over the step
    is the integral of p mu(s) V dt. The core's energy for one element equals it."""
    s0, V, p, h = 2e-4, 0.5, 3e5, 2e-3
    mu_c, mu_h = 1.2, 0.7
    t = ref_core.RefTable([-8.0, 2.0], [200.0, 500.0], [3.0, 8.0],
                          np.broadcast_to(np.array([mu_c, mu_h, 0.0]), (2, 2, 2, 3)),
                          1.0 / s0)

    class P:
        k_x = k_y = 1e12                      # a stiff spring: the tip moves with the base
        d_x = d_y = 0.0
        mass = 0.0
        void_ratio = 0.0
        tol = 1e-6

    c = ref_core.Ctx(P, t, 300.0, 1.0, 1.0, 1.0, 0.0, p, 1.0, V, 0.0, 0.0)
    c.c_flat = math.inf                       # uniform pressure p
    e = [0.0, 0.0, V, 0.0, 0.0, 0.0, 1.0, 0.0]
    r = ref_core.integrate(c, e, 0.0, h)
    s_end = V * h
    # the tip lags the base by the change of the spring's deflection, (mu_c - mu_h) p / k
    assert e[4] == pytest.approx(s_end, rel=1e-3), "slipped distance"
    mu_end = mu_h + (mu_c - mu_h) * math.exp(-e[4] / s0)
    assert r[2] == pytest.approx(p * mu_end, rel=1e-9), "eq. (28) at the slipped distance"
    # the work is the method's second-order quadrature of the power on its sub-steps
    exact = p * (mu_h * s_end + (mu_c - mu_h) * s0 * (1.0 - math.exp(-s_end / s0)))
    assert r[0] == pytest.approx(exact, rel=1e-3), "friction work along the slip path"
    # halving s0 changes it by far more than the tolerance (a test that sees s0)
    exact_half = p * (mu_h * s_end + (mu_c - mu_h) * 0.5 * s0 * (1 - math.exp(-2 * s_end / s0)))
    assert abs(exact_half - exact) > 100 * 1e-4 * exact


def test_massive_model_shares_tire_core_with_steady(tire, grid) -> None:
    """Held inputs: the transient model settles on the steady model's forces (one element law
    and one integrator, sampled on a moving lattice or at fixed cells)."""
    for T_C, kappa, alpha in ((20.0, -0.1, 0.0), (50.0, 0.0, 0.05), (0.0, -0.03, 0.03)):
        tr = _transient_fx(tire, grid, T_C, kappa, 20.0, FZ, alpha=alpha, rigid_carcass=True)
        st = SteadyBrush(tire, grid, rigid_carcass=True).solve(kappa, alpha, 20.0, FZ,
                                                               273.15 + T_C)
        assert abs(tr[0] - float(st.Fx) / FZ) < 1e-2 and abs(tr[1] - float(st.Fy) / FZ) < 1e-2


def test_anisotropic_tread_is_used(pac) -> None:
    """k_y != k_x: the lateral slip stiffness follows k_y (Pacejka: C_Falpha = 2 k_y b a^2;
    at 0.05 deg the closed form's sliding, 1 - lambda + lambda^2/3, is 0.8 % below linear)."""
    a, b = pac.patch.size(FZ)
    alpha = np.radians(0.05)
    Fy = float(SteadyBrush(pac, ConstantFriction(1.0), massless=True).solve(
        0.0, alpha, 20.0, FZ, T20).Fy)
    assert Fy / math.tan(alpha) == pytest.approx(2.0 * pac.tread.k_y * b * a * a, rel=2e-2)
    iso = dataclasses.replace(pac, tread=dataclasses.replace(pac.tread, k_y=pac.tread.k_x))
    Fy_iso = float(SteadyBrush(iso, ConstantFriction(1.0), massless=True).solve(
        0.0, alpha, 20.0, FZ, T20).Fy)
    assert Fy_iso / Fy == pytest.approx(pac.tread.k_x / pac.tread.k_y, rel=2e-2)


# -- the core equals its reference ---------------------------------------------------------
@pytest.mark.parametrize("ageing", [False, True])
@pytest.mark.parametrize("case", ["grid", "peaked_aniso_thermal", "massless_static_kinetic"])
def test_core_equals_python_reference(tire, grid, case, ageing) -> None:
    """Random inputs (slips, loads, speeds through zero and reversing, lift-off, step sizes):
    the C core and the Python reference give the same outputs and states, with the tread's
    contact age off (the shipped tire) and on (docs/tire-core.md, "contact age"; its column
    carried only when on)."""
    tire = with_contact_age(tire, ageing)
    kw: dict = {"n_elements": 12, "dt_internal": 5e-4}
    if case == "grid":
        friction, t = grid, tire
    elif case == "peaked_aniso_thermal":
        friction, t = peaked_grid(), tire
        kw["thermal"] = True
    else:
        friction, t = ConstantFriction.static_kinetic(1.2, 0.8), tire
        kw["massless"] = True
    c = TransientBrushTire(t, friction, **kw)
    r = TransientBrushTire(t, friction, backend="reference", **kw)
    rng = np.random.default_rng(5)
    for k in range(60):
        vx = 25.0 * math.cos(k / 9.0)
        kappa = rng.uniform(-0.3, 0.2)
        u = (float(rng.choice([1e-3, 2.3e-3, 1e-7])), vx, float(rng.normal(0.0, 1.0)),
             vx * (1.0 + kappa) / t.R_e, float(rng.choice([4000.0, 2500.0, 0.0, 6000.0])),
             T20 - 20.0 + 40.0 * rng.random(), 1.0)
        a, b = c.step_array(*u), r.step_array(*u)
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * FZ,
                                   err_msg=f"outputs differ at step {k}")
    sc = c.state_vector()
    np.testing.assert_allclose(sc, r.state_vector(), rtol=1e-10, atol=1e-14)
    ages = sc[ref_core.STATE_HEAD:].reshape(-1, ref_core.N_ELEM)[:, 7]
    if ageing:
        assert (ages >= 0.0).all() and ages.max() > 0.0, "the age column is carried"
    else:
        assert (ages == 0.0).all(), "no age without the law"


def test_node_walk_bounds_change_no_result(tire, grid) -> None:
    """The stage solve skips the speed nodes whose residual sign the friction bounds decide
    (tirecore.c, ``node_bound``); the walk must stop at the same node. The C core (bounds on)
    and the reference with the bounds switched off give identical bits over snaps, creep,
    reversals and lift-off at 0 C, where the walks are longest."""
    kw: dict = {"n_elements": 12, "dt_internal": 5e-4}
    c = TransientBrushTire(tire, grid, **kw)
    r = TransientBrushTire(tire, grid, backend="reference", **kw)
    assert r._ref.t.smax is not None
    r._ref.t.smax = r._ref.t.pmin = None
    rng = np.random.default_rng(11)
    for k in range(40):
        vx = 25.0 * math.cos(k / 7.0)
        kappa = float(rng.choice([-1.0, -0.3, -0.06, 0.1]))
        u = (1e-3, vx, float(rng.normal(0.0, 2.0)), vx * (1.0 + kappa) / tire.R_e,
             float(rng.choice([4000.0, 0.0, 6000.0])), 273.15, 1.0)
        np.testing.assert_array_equal(c.step_array(*u), r.step_array(*u),
                                      err_msg=f"outputs differ at step {k}")
    np.testing.assert_array_equal(c.state_vector(), r.state_vector())


def test_steady_core_equals_reference(tire, grid) -> None:
    kappa = np.array([-0.6, -0.06, -0.01, 0.08])
    alpha = np.array([0.0, 0.05, -0.1, 0.2])
    c = SteadyBrush(tire, grid, n_elements=16).solve(kappa, alpha, 20.0, FZ, 280.0)
    r = SteadyBrush(tire, grid, n_elements=16, backend="reference").solve(kappa, alpha, 20.0,
                                                                          FZ, 280.0)
    np.testing.assert_allclose(np.stack([c.Fx, c.Fy, c.Mz, c.mu_slide]),
                               np.stack([r.Fx, r.Fy, r.Mz, r.mu_slide]), rtol=1e-10, atol=1e-9)


def test_diagnostics_mu_slide_and_flash_temperature(tire) -> None:
    """The diagnostic outputs against hand values on a flat two-branch grid with a constant
    flash temperature rise of 37 K: a locked wheel (every element slides, s >> s0: the hot
    branch) reports mu_slide = mu_scale mu_hot, dT_flash_max = 37 K, sliding fraction 1, in
    the steady and the transient model; a free-rolling wheel reports no sliding and no flash
    temperature."""
    grid = FrictionGrid.constant(1.2, 0.8, s0_m=2e-4, dT_flash=37.0)
    st = SteadyBrush(tire, GridFriction(grid)).solve_velocities(10.0, 0.0, 0.0, FZ, T20, 0.5)
    assert float(st.mu_slide) == pytest.approx(0.5 * 0.8, rel=1e-9)
    assert float(st.dT_flash_max) == pytest.approx(37.0, rel=1e-9)
    assert float(st.sliding_fraction) == 1.0
    tr = TransientBrushTire(without_thermal(tire), GridFriction(grid))
    for _ in range(200):
        o = tr.step(1e-3, 10.0, 0.0, 0.0, FZ, T20, 0.5)
    assert o.mu_slide == pytest.approx(0.4, rel=1e-9) and o.sliding_fraction == 1.0
    assert o.dT_flash_max == pytest.approx(37.0, rel=1e-9)
    assert o.mu_eff == pytest.approx(0.4, rel=1e-3), "locked wheel: |F| = mu_scale mu_hot Fz"
    free = SteadyBrush(tire, GridFriction(grid)).solve(0.0, 0.0, 20.0, FZ, T20)
    assert float(free.sliding_fraction) == 0.0 and float(free.dT_flash_max) == 0.0


def test_tiny_and_subnormal_steps_are_defined(tire, grid) -> None:
    """A step below 1 ns (the floor; element sub-steps stop at 10 ns) changes nothing but
    the clock: the forces after doStep(1e-12) equal those before (the old core moved Fx by
    10 % of Fz), subnormal steps too, and a normal step afterwards continues as if the tiny
    one had not been there."""
    u = (27.8, 0.0, 27.8 * 0.9 / tire.R_e, FZ, 273.15, 1.0)
    a = TransientBrushTire(tire, grid)
    b = TransientBrushTire(tire, grid)
    for _ in range(100):
        a.step_array(1e-3, *u)
        b.step_array(1e-3, *u)
    before = a.step_array(0.0, *u)
    for h in (1e-12, 5e-324, 2.2e-308, 9.9e-10):
        out = a.step_array(h, *u)
        assert out == before, f"doStep({h:g}) changed the outputs"
    assert a.time == pytest.approx(b.time + 1e-12 + 9.9e-10 + 2.2e-308, abs=1e-15)
    np.testing.assert_array_equal(a.step_array(1e-3, *u), b.step_array(1e-3, *u))
    python = TransientBrushTire(tire, grid, backend="reference", n_elements=8)
    python.step_array(1e-3, *u)
    x = python.step_array(0.0, *u)
    assert python.step_array(1e-12, *u) == x, "the Python reference has the same floor"


def test_outputs_change_by_order_h_as_the_step_shrinks(tire, grid) -> None:
    """Continuity in the step size: from a braking state at 0 C (stick-slip at the trailing
    edge, so the instantaneous patch force differs from the 1 ms mean), steps of 1e-6, 1e-7
    and 1e-8 s move Fx by at most (h / W) times the largest possible jump (2 mu_max Fz with
    mu_max < 2, W = dt_internal: the output relaxation), i.e. O(h); and the change shrinks in
    proportion to h (a ratio within [5, 20] for a 10x smaller step: linear, not constant)."""
    u = (27.8, 0.0, 27.8 * 0.94 / tire.R_e, FZ, 273.15, 1.0)
    m = TransientBrushTire(tire, grid)
    for _ in range(150):
        before = m.step_array(1e-3, *u)
    state = m.get_state()
    moves = []
    for h in (1e-6, 1e-7, 1e-8):
        m.set_state(state)
        after = m.step_array(h, *u)
        d = abs(after[0] - before[0])
        assert d <= h / m.dt_internal * 4.0 * FZ, f"doStep({h:g}) moved Fx by {d:.3g} N"
        moves.append(d)
    assert moves[0] > 0.0
    for big, small in itertools.pairwise(moves):
        assert 5.0 <= big / small <= 20.0, f"not O(h): {moves}"
