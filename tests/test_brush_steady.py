"""Steady-state brush tire against Pacejka's closed forms (constant and static/kinetic
friction), eq. (28) limits, and convergence with element count on velocity-weakening friction.

Tolerances: the issue asks for 1% of the peak force against the analytic brush; the numerical
march is far better than that (midpoint cells: second order, ~1e-4 at the default 64 cells),
so the tests also pin a tighter discretisation bound where it holds, with the reason given.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from brush_cases import T20, isotropic, pacejka_like, passenger, peaked_grid, without_thermal

from lookup.grid import FrictionGrid
from tire_brush import reference as ref
from tire_brush.friction import ConstantFriction, GridFriction
from tire_brush.steady import N_STEADY, SteadyBrush
from tirefric.errors import InputError

FZ = 4000.0
VX = 20.0


@pytest.fixture(scope="module")
def tire():
    """The passenger tire with Pacejka's parabolic pressure and no belt yaw, the brush the
    closed forms describe (the shipped tire's flat-topped pressure and carcass twist are
    tested in test_tire_realism.py)."""
    return pacejka_like(without_thermal(passenger()))


def _geometry(tire, Fz=FZ):
    a, b = tire.patch.size(Fz)
    return a, tire.tread.k_x * b, tire.tread.k_y * b


def test_pure_slip_matches_pacejka(tire) -> None:
    """Constant friction, massless brush: Fx(kappa), Fy(alpha), Mz(alpha) within 1% of the peak
    force of Pacejka's closed forms; discretisation error at 64 cells < 0.1%."""
    mu = 0.9
    a, cpx, cpy = _geometry(tire)
    model = SteadyBrush(tire, ConstantFriction(mu), massless=True)
    kappa = np.linspace(-0.4, 0.4, 81)
    out = model.solve(kappa, 0.0, VX, FZ, T20)
    sx, _ = ref.theoretical_slip(kappa, 0.0)
    err = np.abs(out.Fx - ref.brush_force(sx, mu, FZ, a, cpx)).max() / (mu * FZ)
    assert err < 1e-3, f"Fx(kappa) deviates from the closed form by {err:.2%} of mu Fz"
    assert np.all(out.Fy == 0) and np.all(out.Mz == 0), "pure longitudinal slip: no Fy, Mz"
    alpha = np.radians(np.linspace(-15, 15, 61))
    out = model.solve(0.0, alpha, VX, FZ, T20)
    _, sy = ref.theoretical_slip(0.0, alpha)
    err = np.abs(out.Fy - ref.brush_force(sy, mu, FZ, a, cpy)).max() / (mu * FZ)
    assert err < 1e-3, f"Fy(alpha) deviates from the closed form by {err:.2%} of mu Fz"
    Mz_ref = ref.brush_moment(sy, mu, FZ, a, cpy)
    err = np.abs(out.Mz - Mz_ref).max() / np.abs(Mz_ref).max()
    assert err < 1e-2, f"Mz(alpha) deviates by {err:.2%} of its peak"


def test_combined_slip_matches_pacejka(tire) -> None:
    """Isotropic tread (the closed form's assumption), combined slip grid: Fx, Fy within 1% of
    mu Fz and Mz within 1% of its peak."""
    tire = isotropic(tire)
    mu = 1.0
    a, cp, _ = _geometry(tire)
    K, A = np.meshgrid(np.linspace(-0.25, 0.15, 17), np.radians(np.linspace(-10, 10, 11)))
    out = SteadyBrush(tire, ConstantFriction(mu), massless=True).solve(K, A, VX, FZ, T20)
    Fx, Fy, Mz = ref.brush_combined(*ref.theoretical_slip(K, A), mu, FZ, a, cp)
    assert np.abs(out.Fx - Fx).max() < 1e-2 * mu * FZ, "combined Fx off the closed form"
    assert np.abs(out.Fy - Fy).max() < 1e-2 * mu * FZ, "combined Fy off the closed form"
    assert np.abs(out.Mz - Mz).max() < 1e-2 * np.abs(Mz).max(), "combined Mz off the closed form"


def test_static_kinetic_closed_form(tire) -> None:
    """Static/kinetic friction (eq. 28 with s0 -> 0): Pacejka's closed form within 1% of
    mu_s Fz. The adhesion/sliding boundary falls inside a cell, so the error is first order in
    the cell size (0.34% at 64 cells, halving with the cell count)."""
    a, cpx, _ = _geometry(tire)
    kappa = np.linspace(-0.3, 0.3, 61)
    sx, _ = ref.theoretical_slip(kappa, 0.0)
    F_ref = ref.brush_static_kinetic(sx, 1.2, 0.8, FZ, a, cpx)
    errs = []
    for n in (N_STEADY, 2 * N_STEADY):
        model = SteadyBrush(tire, ConstantFriction.static_kinetic(1.2, 0.8), massless=True,
                            n_elements=n)
        errs.append(np.abs(model.solve(kappa, 0.0, VX, FZ, T20).Fx - F_ref).max() / (1.2 * FZ))
    assert errs[0] < 1e-2, f"static/kinetic brush off the closed form by {errs[0]:.2%}"
    assert errs[1] < 0.7 * errs[0], f"no convergence with cell count: {errs}"


def test_flat_two_branch_grid_s0_limits(tire) -> None:
    """A flat grid with mu_cold != mu_hot: s0 -> inf gives the constant-mu_cold brush, s0 -> 0
    the static/kinetic brush with (mu_s, mu_k) = (mu_cold, mu_hot) (eq. 28 at s = 0 and s > 0),
    and an intermediate s0 lies in between."""
    a, cpx, _ = _geometry(tire)
    kappa = np.linspace(-0.3, -0.005, 30)
    sx, _ = ref.theoretical_slip(kappa, 0.0)

    def Fx(s0):
        grid = FrictionGrid.constant(1.1, 0.7, s0_m=1e-3)
        model = SteadyBrush(tire, GridFriction(grid, s0=s0), massless=True)
        return model.solve(kappa, 0.0, VX, FZ, T20).Fx

    cold = ref.brush_force(sx, 1.1, FZ, a, cpx)
    sk = ref.brush_static_kinetic(sx, 1.1, 0.7, FZ, a, cpx)
    assert np.abs(Fx(np.inf) - cold).max() < 1e-2 * 1.1 * FZ, "s0 = inf is not cold-only"
    assert np.abs(Fx(0.0) - sk).max() < 1e-2 * 1.1 * FZ, "s0 = 0 is not static/kinetic"
    mid = Fx(2e-4)
    tol = 5e-3 * FZ   # first-order cell error at an adhesion/sliding jump (0.3% at 64 cells)
    between = (mid >= np.minimum(cold, sk) - tol) & (mid <= np.maximum(cold, sk) + tol)
    assert between.all(), "a finite s0 must give forces between the two limits"


def test_s0_limits_recover_hot_only_and_cold_only(tire) -> None:
    """With branches that agree at the lowest speed (no flash heating at v -> 0, as in a real
    grid), s0 -> 0 is exactly the hot-only tire and s0 -> inf the cold-only tire (eq. 28).
    The identities are eq. (28)'s, with the friction read at the slip speed: the contact age
    is off here (its length D = s0 / 0.2 moves with s0; its own limit is checked below)."""
    aged = dataclasses.replace(tire, tread=dataclasses.replace(tire.tread,
                                                               contact_ageing=True))
    tire = dataclasses.replace(tire, tread=dataclasses.replace(tire.tread,
                                                               contact_ageing=False))
    grid = peaked_grid()
    mu_c, mu_h = grid["mu_cold"], grid["mu_hot"]
    base = {n: grid[n] for n in ("mu_cold", "mu_hot", "dT_flash")}

    def only(branch):
        variables = dict(base, mu_cold=branch, mu_hot=branch)
        return FrictionGrid(grid.log10_v, grid.T, grid.log10_p, variables,
                            {"s0_m": 2e-4, "D_m": 1e-3})

    kappa = np.array([-0.01, -0.03, -0.06, -0.1, -0.3])

    def Fx(friction):
        return SteadyBrush(tire, friction).solve(kappa, 0.0, VX, FZ, T20).Fx

    hot, cold = Fx(GridFriction(only(mu_h))), Fx(GridFriction(only(mu_c)))
    np.testing.assert_allclose(Fx(GridFriction(grid, s0=0.0)), hot, rtol=0, atol=1e-6 * FZ,
                               err_msg="s0 -> 0 must reproduce the hot-only curve")
    np.testing.assert_allclose(Fx(GridFriction(grid, s0=np.inf)), cold, rtol=0, atol=1e-6 * FZ,
                               err_msg="s0 -> inf must reproduce the cold-only curve")
    assert np.abs(hot - cold).max() > 0.05 * FZ, "test grid must separate the branches"
    # with the contact age: s0 = inf has no D (the friction at |w|: the same bits); s0 -> 0
    # sends D -> 0, the age relaxes at once in sliding and a stuck element reads the first
    # node either way, so the law-off hot-only curve again, up to the stick-slip events'
    # first 10 ns stage, which reads the stuck age (measured 4.5e-5 Fz; bound 2e-4 Fz)
    assert aged.tread.contact_ageing
    np.testing.assert_array_equal(
        SteadyBrush(aged, GridFriction(grid, s0=np.inf)).solve(kappa, 0.0, VX, FZ, T20).Fx,
        Fx(GridFriction(grid, s0=np.inf)))
    np.testing.assert_allclose(
        SteadyBrush(aged, GridFriction(grid, s0=0.0)).solve(kappa, 0.0, VX, FZ, T20).Fx, hot,
        rtol=0, atol=2e-4 * FZ)


def test_mass_and_damping_change_constant_friction_little(tire) -> None:
    """The tread tip mass and damping (regularisation for velocity weakening) move the
    constant-friction curve by less than 3% of mu Fz at 20 m/s: the sliding tips carry the
    momentum flux m b V_r |V_s| out of the patch (1.5% of Fz at kappa = 0.3) and the damper
    adds d |V_s| over the adhesion zone."""
    kappa = np.linspace(-0.3, 0.3, 31)
    massive = SteadyBrush(tire, ConstantFriction(1.0)).solve(kappa, 0.0, VX, FZ, T20)
    massless = SteadyBrush(tire, ConstantFriction(1.0), massless=True).solve(kappa, 0.0, VX, FZ,
                                                                            T20)
    diff = np.abs(massive.Fx - massless.Fx).max() / FZ
    assert diff < 0.03, f"mass/damping changes Fx by {diff:.2%} of Fz"


def test_convergence_with_element_count_velocity_weakening(tire) -> None:
    """Peaked (velocity-weakening) friction with tread mass: the curve does not depend on
    the number of cells."""
    friction = GridFriction(peaked_grid())
    kappa = np.array([-0.01, -0.03, -0.06, -0.1, -0.3])
    F = {n: SteadyBrush(tire, friction, n_elements=n).solve(kappa, 0.0, VX, FZ, T20).Fx / FZ
         for n in (32, 64, 128, 256)}
    # the force is the patch integral of the element's friction impulse (no sampling), so
    # the cell count only places the diagnostics: every count gives the same force
    for n in (32, 64, 128):
        d = np.abs(F[n] - F[256]).max()
        assert d < 2e-3, f"{n} cells differ from 256 by {d:.4f} Fz"


def test_full_sliding_reaches_hot_branch(tire) -> None:
    """A nearly locked wheel slides over the whole patch: |Fx|/Fz tends to mu_hot(V_s) of the
    grid (the elements have slipped far beyond s0), and the flash temperature is reported."""
    grid = peaked_grid()
    out = SteadyBrush(tire, GridFriction(grid)).solve(-0.95, 0.0, VX, FZ, T20)
    mu_hot = grid.interpolate(0.95 * VX, T20, 2e5)["mu_hot"]
    assert abs(-out.Fx / FZ - mu_hot) < 0.03, "locked wheel must read the hot branch"
    assert out.sliding_fraction == pytest.approx(1.0)
    assert out.dT_flash_max > 50.0, "hot branch flash temperature must be reported"


def test_low_speed_and_edge_inputs_finite(tire) -> None:
    """Zero load, reversing/rolling backwards, no rolling, tiny speed: finite, NaN-free."""
    model = SteadyBrush(tire, GridFriction(peaked_grid()))
    out = model.solve_velocities([0.0, 1.0, -1.0, 20.0, 1e-9, 0.0], [0.0, 0.5, 0.0, 0.0, 0.0, 3.0],
                                 [0.0, 0.0, -2.0, 0.0, 1e-9, 10.0],
                                 [4000.0, 4000.0, 4000.0, 4000.0, 4000.0, 0.0], T20)
    for name in ("Fx", "Fy", "Mz", "mu_eff", "sliding_fraction", "dT_flash_max"):
        assert np.isfinite(getattr(out, name)).all(), f"{name} not finite"
    assert out.Fx[0] == 0 and out.Fy[0] == 0, "no motion, no force"
    assert out.Fx[5] == 0 and out.Fy[5] == 0, "no load, no force"
    assert out.Fx[3] < -0.3 * FZ, "wheel not rolling while moving forward: braking force"


def test_reversing_mirrors_forward(tire) -> None:
    """Rolling backwards with mirrored slip velocities gives the mirrored forces."""
    model = SteadyBrush(tire, ConstantFriction(1.0))
    fwd = model.solve_velocities(1.0, 0.5, 19.0, FZ, T20)
    rev = model.solve_velocities(-1.0, 0.5, -19.0, FZ, T20)
    assert rev.Fx == pytest.approx(-fwd.Fx, rel=1e-12)
    assert rev.Fy == pytest.approx(fwd.Fy, rel=1e-12)
    assert rev.Mz == pytest.approx(-fwd.Mz, rel=1e-12)


def test_input_errors(tire) -> None:
    model = SteadyBrush(tire, ConstantFriction(1.0))
    with pytest.raises(InputError, match="vx"):
        model.solve(0.1, 0.0, -1.0, FZ, T20)
    with pytest.raises(InputError, match="kappa"):
        model.solve(np.nan, 0.0, VX, FZ, T20)
    with pytest.raises(InputError, match="alpha"):
        model.solve(0.0, 2.0, VX, FZ, T20)
    with pytest.raises(InputError, match="n_elements"):
        SteadyBrush(tire, ConstantFriction(1.0), n_elements=1)


def test_fx_over_fz_for_braking_studies(tire) -> None:
    """The braking studies' friction source: broadcasting over (kappa, vx, Fz, T)."""
    model = SteadyBrush(tire, ConstantFriction(1.0))
    k = np.linspace(-0.3, 0.0, 4)[:, None, None, None]
    v = np.array([5.0, 20.0])[None, :, None, None]
    Fz = np.array([2000.0, 4000.0])[None, None, :, None]
    T = np.array([273.15, T20])[None, None, None, :]
    r = model.fx_over_fz(k, v, Fz, T)
    assert r.shape == (4, 2, 2, 2)
    assert np.all(r[-1] == 0) and np.all(r[0] < -0.9), "zero slip no force; -0.3 near -mu"


@pytest.mark.parametrize("massless", [False, True])
def test_single_point_path_equals_batch(tire, massless) -> None:
    """A single operating point takes the pure-Python march (speed); it must agree with the
    numpy march of a batch to rounding (1e-9 of Fz), for flat, static/kinetic and
    velocity-weakening friction, pure and combined slip."""
    cases = [(-0.05, 0.0), (-0.02, 0.03), (0.1, -0.05), (-0.5, 0.1), (0.0, 0.0), (-0.97, 0.0)]
    for friction in (ConstantFriction(1.0), ConstantFriction.static_kinetic(1.2, 0.8),
                     GridFriction(peaked_grid())):
        model = SteadyBrush(tire, friction, massless=massless)
        for kappa, alpha in cases:
            one = model.solve(kappa, alpha, VX, FZ, T20)
            two = model.solve([kappa, kappa], alpha, VX, FZ, T20)
            for name in ("Fx", "Fy", "Mz", "mu_eff", "mu_slide", "sliding_fraction",
                         "dT_flash_max"):
                a, b = float(getattr(one, name)), float(getattr(two, name)[0])
                assert abs(a - b) <= 1e-9 * max(FZ, abs(b)), (name, kappa, alpha, a, b)
