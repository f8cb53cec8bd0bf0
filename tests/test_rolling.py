"""Rolling friction (lookup.rolling, review sec. 6-7) against independent solutions.

The main check: eq. (30) for a hard cylinder on the single-relaxation solid of review eq. (4)
(E1/E0 = 10) against the exact steady rolling contact of a rigid cylinder on a standard linear
solid (the problem S. C. Hunter solved, J. Appl. Mech. 28, 611 (1961)), solved here from
scratch: the surface slope of the viscoelastic half space in the frame of the cylinder is

    u'(x) = J1 U'(x) + (J0 - J1) int_0^inf ds (1/tau) e^{-s/tau} U'(x + v s),
    U'(x) = -(2/pi) PV int p(s) / (x - s) ds,

(creep compliance J(t) = J1 + (J0 - J1)(1 - e^{-t/tau}) of eq. (4), material entering at the
leading edge x > 0), equal to -x/R on the contact [e - A, e + A]. The pressure is expanded as
p = sqrt(1 - t^2) sum c_n U_{n-1}(t) (bounded at both edges, no adhesion), for which the
Hilbert transform is sum c_n T_n(t) inside and (t - sqrt(t^2 - 1))^n outside; collocation at
Chebyshev points gives a linear system for (c_n, e) at fixed A and lambda = v tau / A. Nothing
of lookup.rolling is used.
"""

from __future__ import annotations

import json
import tomllib
from importlib.metadata import EntryPoint
from pathlib import Path

import numpy as np
import pytest
from conftest import T20, make_compound

from lookup import reference
from lookup.compound import load_compound
from lookup.modulus import SingleRelaxation
from lookup.rolling import (
    EffectiveModulus,
    bonded_layer_factor,
    cylinder_half_width,
    mu_cylinder,
    mu_profile,
    mu_sphere,
    mu_stress_field,
    mu_wedge,
    sphere_contact_radius,
    tread_rolling_resistance,
    wedge_half_width,
    wedge_strain,
)
from lookup.softening import TabulatedSoftening
from tirefric.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
E0, TAU = 1e6, 1.0


# -- the exact steady rolling solution (standard linear solid), independent of lookup ---------
def _gl_panels(edges: np.ndarray, m: int = 16) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(m)
    a, b = edges[:-1, None], edges[1:, None]
    return ((a + b) / 2 + (b - a) / 2 * x).ravel(), ((b - a) / 2 * w).ravel()


def steady_rolling_sls(lam: float, E0: float, E1: float, N: int = 32
                       ) -> tuple[float, float, np.ndarray]:
    """Half-width A = 1, R = 1: (f_N, offset e, coefficients c_1..c_N) at lambda = v tau/A."""
    J1, D = 1.0 / E1, 1.0 / E0 - 1.0 / E1
    n = np.arange(1, N + 1)
    tj = np.cos((2 * np.arange(N + 1) + 1) * np.pi / (2 * (N + 1)))
    # beyond the leading edge: int_1^inf (1/lam) e^{-(t'-1)/lam} (t' - sqrt(t'^2-1))^n dt'
    # with t' = 1 + lam s^2
    s, ws = _gl_panels(np.concatenate([[0.0], np.geomspace(1e-7, 7.0, 80)]))
    rho = 1 + lam * s * s - s * np.sqrt(lam * (2 + lam * s * s))
    outer = (2 * s * np.exp(-s * s) * ws) @ (rho[:, None] ** n[None, :])
    M = np.empty((N + 1, N))
    for j, t in enumerate(tj):
        top = min(1 - t, 50 * lam)
        e1 = np.concatenate([[0.0], lam * np.geomspace(1e-6, 50, 40)])
        edges = np.unique(np.concatenate([e1[e1 < top], np.arange(0, top, min(lam / 2, 0.05)),
                                          [top]]))
        u, wu = _gl_panels(edges)
        Tn = np.cos(n[None, :] * np.arccos(np.clip(t + u, -1, 1))[:, None])
        M[j] = (np.exp(-u / lam) / lam * wu) @ Tn + np.exp(-(1 - t) / lam) * outer
    A = np.empty((N + 1, N + 1))
    A[:, :N] = -2 * (J1 * np.cos(n[None, :] * np.arccos(tj)[:, None]) + D * M)
    A[:, N] = 1.0
    sol = np.linalg.solve(A, -tj)
    c, e = sol[:N], sol[N]
    return np.pi / 2 * c[0], e, c


def exact_cylinder_curve(lams: np.ndarray, E0: float = 1.0, E1: float = 10.0, N: int = 32
                         ) -> np.ndarray:
    """Rows (v tau / a0, mu R / a0, A / a0, min p / max p on the contact)."""
    rows = []
    t = np.linspace(-1, 1, 801)[1:-1]
    for lam in lams:
        fN, e, c = steady_rolling_sls(lam, E0, E1, N)
        a0 = np.sqrt(4 * fN / (np.pi * E0))
        mu = (e * fN + np.pi * c[1] / 4) / fN  # int p x dx / (R f_N)
        U = np.array([np.sin((k + 1) * np.arccos(t)) / np.sqrt(1 - t * t)
                      for k in range(len(c))])
        p = np.sqrt(1 - t * t) * (c @ U)
        rows.append((lam / a0, mu / a0, 1 / a0, p.min() / p.max()))
    return np.array(rows)


@pytest.fixture(scope="module")
def exact() -> np.ndarray:
    return exact_cylinder_curve(np.logspace(-2, 3, 31))


def sls_modulus(E1_over_E0: float = 10.0, eta_I: float = 1.0, nu: float = 0.0
                ) -> EffectiveModulus:
    """Review eq. (4) at its reference temperature; eta_I scales the loss modulus."""
    soft = TabulatedSoftening(np.array([1e-3, 1.0]), np.ones(2), np.full(2, eta_I))
    c = make_compound(modulus=SingleRelaxation(E0, E1_over_E0 * E0, TAU), nu=nu)
    c = type(c)(c.name, c.modulus, c.T_ref, c.shift, soft, 0.1, c.adhesion, c.nu, c.thermal)
    return EffectiveModulus(c, T20)


def cylinder_curve(x: np.ndarray, modulus: EffectiveModulus) -> np.ndarray:
    """mu R / a0 at v tau / a0 = x (R = 1 m, a0 = 1 mm at E0)."""
    R, a0 = 1.0, 1e-3
    f_N = np.pi * E0 * a0**2 / (4 * R)
    return mu_cylinder(f_N, R, x * a0 / TAU, modulus) * R / a0


# -- the exact solver itself ------------------------------------------------------------------
def test_exact_solver_limits_and_convergence(exact: np.ndarray) -> None:
    # Hertz with E0 at low speed and with E1 at high speed (A/a0 -> sqrt(E0/E1))
    assert exact[0, 2] == pytest.approx(1.0, rel=1e-2), "slow rolling: Hertz width with E0"
    assert exact[-1, 2] == pytest.approx(np.sqrt(0.1), rel=1e-3), "fast: Hertz width with E1"
    assert (exact[:, 3] > -1e-6).all(), "contact pressure must stay >= 0"
    fN, e, c = steady_rolling_sls(1.0, 1.0, 1.0 + 1e-12)
    assert abs(e) < 1e-9 and np.allclose(c[1:], 0, atol=1e-9), "elastic: symmetric Hertz"
    assert fN == pytest.approx(np.pi / 4, rel=1e-9), "elastic: f_N = pi E A^2 / (4 R)"
    # truncation: N = 32 against N = 48 (mu R/a0 to 1e-4 relative at lambda >= 0.05)
    lam = np.array([0.05, 1.0, 30.0])
    a, b = exact_cylinder_curve(lam, N=32), exact_cylinder_curve(lam, N=48)
    np.testing.assert_allclose(a[:, 1], b[:, 1], rtol=1e-4, err_msg="Chebyshev truncation")


# -- eq. (30) against the exact solution ------------------------------------------------------
def test_cylinder_eq30_against_exact_rolling(exact: np.ndarray) -> None:
    """Measured (2026, this branch): ratio eq.(30)/exact is 1.0014 at v tau/a0 = 0.01,
    < 1.006 for v tau/a0 <= 0.04, 0.9953 at 10, 0.9997 at 42 and 1.0000 above 100; largest
    deviations +6.8 % (v tau/a0 ~ 0.57, rising flank) and -3.4 % (~2.2, falling flank); the
    peak 0.4789 against 0.4819 (-0.6 %) at the same v tau/a0 ~ 1.26. The review: 'some
    distance away from the maximum the agreement is nearly perfect' (small tan delta, where
    eq. 13 is essentially exact) and 'a small difference near the maximum'."""
    x, mu_ex = exact[:, 0], exact[:, 1]
    mu30 = cylinder_curve(x, sls_modulus())
    ratio = mu30 / mu_ex
    away = (x <= 0.04) | (x >= 10.0)
    # tier 1 (away from the maximum, small tan delta): 1 %, margin over the measured 0.6 %
    assert np.abs(ratio[away] - 1).max() < 0.01, f"away from max: {ratio[away]}"
    # tier 2 (near the maximum, eq. 30 is an approximation there): peak value 2 %, its
    # position within one grid step, whole curve within 10 %
    i, j = np.argmax(mu_ex), np.argmax(mu30)
    assert mu30[j] == pytest.approx(mu_ex[i], rel=0.02), "peak value of mu R/a0"
    assert abs(np.log10(x[j] / x[i])) <= 1.01 * np.log10(x[1] / x[0]), "peak position"
    assert 0.5 < x[i] < 2.5, "maximum near v tau / a0 of order 1"
    assert np.abs(ratio - 1).max() < 0.10, f"whole curve: {ratio}"


def test_exact_comparison_detects_half_the_loss(exact: np.ndarray) -> None:
    """The comparison above fails if the loss modulus is halved (a wrong factor 2 or
    Im E taken at half strength)."""
    x, mu_ex = exact[:, 0], exact[:, 1]
    ratio = cylinder_curve(x, sls_modulus(eta_I=0.5)) / mu_ex
    away = (x <= 0.04) | (x >= 10.0)
    assert np.abs(ratio[away] - 1).max() > 0.3


def test_fixed_contact_size_is_worse_than_the_reviews_choice(exact: np.ndarray) -> None:
    """The contact size at |E_eff(q v)| (review after eq. 31) matters: with the static E0
    the fast branch is off by > 15 %."""
    x, mu_ex = exact[:, 0], exact[:, 1]
    R, a0 = 1.0, 1e-3
    f_N = np.pi * E0 * a0**2 / (4 * R)
    fixed = mu_cylinder(f_N, R, x * a0 / TAU, sls_modulus(), E_contact=E0) * R / a0
    assert np.abs(fixed / mu_ex - 1)[x > 1].max() > 0.15


def test_mu_vanishes_at_both_ends() -> None:
    m = sls_modulus()
    mu = cylinder_curve(np.array([1e-5, 1.26, 1e5]), m)
    assert mu[0] < 1e-3 * mu[1] and mu[2] < 1e-3 * mu[1], f"mu(v -> 0, inf) -> 0: {mu}"
    # the shipped summer compound: its relaxation spectrum reaches 1e9 s (the broad rubbery
    # component, 4 widths out), so "v -> 0" for a 1-mm contact lies below ~1e-13 m/s
    real = EffectiveModulus(load_compound("summer"), T20)
    mu_r = mu_cylinder(1000.0, 5e-3, [1e-16, 1e4, 1e12], real)
    assert mu_r[0] < 1e-6 and mu_r[2] < 1e-2 * mu_r[1], f"summer: {mu_r}"


def test_loss_sign_trap1() -> None:
    """Im(1/E) > 0 for omega > 0 with review eq. (4), and odd in omega (Trap 1)."""
    m = sls_modulus()
    w = np.logspace(-3, 3, 13)
    g = m.im_compliance(w)
    assert (g > 0).all()
    np.testing.assert_allclose(m.im_compliance(-w), -g, rtol=1e-12)
    E = SingleRelaxation(E0, 10 * E0, TAU).complex_modulus(w)
    np.testing.assert_allclose(g, (1 / E).imag, rtol=2e-3, err_msg="table vs eq. (4)")


def test_time_temperature_superposition() -> None:
    """No heating: mu(v, T) = mu(v a_T(T), T_ref) (review sec. 6: the rolling master curve)."""
    c = load_compound("summer")
    T = 273.15 + 50
    aT = 10.0 ** float(c.log10_aT(np.array(T)))
    v = np.logspace(-4, 1, 6)
    a = mu_cylinder(800.0, 5e-3, v, EffectiveModulus(c, T))
    b = mu_cylinder(800.0, 5e-3, v * aT, EffectiveModulus(c, c.T_ref))
    np.testing.assert_allclose(a, b, rtol=1e-9)
    assert aT < 1


# -- eq. (29) paths agree ---------------------------------------------------------------------
def test_eq29_line_load_paths_agree() -> None:
    """Hertz line load with a fixed width: eq. (30), the sampled profile (exact transform of
    its interpolant) and the 2D FFT of eq. (29) on a strip. Tolerances: 1e-3 for the
    profile (piecewise-linear square root at 401 nodes); 1e-2 for the FFT (finite box)."""
    m = sls_modulus()
    R, a0 = 1.0, 1e-3
    f_N = np.pi * E0 * a0**2 / (4 * R)
    v = np.array([0.1, 1.0]) * a0 / TAU
    ref = mu_cylinder(f_N, R, v, m, E_contact=E0)
    x = np.linspace(-a0, a0, 401)
    p = 2 * f_N / (np.pi * a0) * np.sqrt(1 - (x / a0) ** 2)
    np.testing.assert_allclose(mu_profile(x, p, v, m), ref, rtol=1e-3)
    xx = np.linspace(-32 * a0, 32 * a0, 8192, endpoint=False)
    prof = 2 * f_N / (np.pi * a0) * np.sqrt(np.clip(1 - (xx / a0) ** 2, 0, None))
    fft = [mu_stress_field(np.tile(prof, (4, 1)), xx[1] - xx[0], 1e-3, vi, m) for vi in v]
    np.testing.assert_allclose(fft, ref, rtol=1e-2)
    # eq. (30)'s closed form: small-loss limit mu = (8 f_N/pi) int Im(1/E) J1^2/(qa)^2 dq
    assert ref[1] > 2 * ref[0] > 0


def test_sphere_eq32_against_eq29_field() -> None:
    """Eq. (32) with a fixed contact radius against the 2D FFT of eq. (29) for the Hertz
    field (1 %: finite box and grid; larger v tau/r0 need a larger box)."""
    m = sls_modulus()
    R, r0 = 1.0, 1e-3
    F_N = 4 * E0 * r0**3 / (3 * R)
    v = np.array([0.1, 1.0]) * r0 / TAU
    ref = mu_sphere(F_N, R, v, m, E_contact=E0)
    n, L = 512, 16 * r0
    x = (np.arange(n) - n / 2) * (L / n)
    X, Y = np.meshgrid(x, x)
    s = 3 * F_N / (2 * np.pi * r0**2) * np.sqrt(np.clip(1 - (X**2 + Y**2) / r0**2, 0, None))
    fft = [mu_stress_field(s, L / n, L / n, vi, m) for vi in v]
    np.testing.assert_allclose(fft, ref, rtol=1e-2)


def test_sphere_scaling() -> None:
    """Review Fig. (cylinder and sphere): mu R/r0 depends on v tau/r0 only; the maximum lies
    at v tau/r0 of order 1; at equal radius and equal static mean pressure the sphere rolls
    with less friction than the cylinder (lower curve)."""
    m = sls_modulus()
    x = np.array([0.1, 0.3, 1.0, 3.0, 10.0])
    curves = []
    for R, F_N in ((1.0, 1e-2), (0.2, 3e-3)):
        r0 = float(sphere_contact_radius(F_N, R, E0))
        curves.append(mu_sphere(F_N, R, x * r0 / TAU, m) * R / r0)
    np.testing.assert_allclose(curves[0], curves[1], rtol=1e-3, err_msg="collapse")
    assert 0.3 < x[np.argmax(curves[0])] < 3.0
    # equal mean pressure: f_N/(2 a0) = F_N/(pi r0^2) with R equal -> r0 = (3 pi^2/32) a0
    R, a0 = 1.0, 1e-3
    r0 = 3 * np.pi**2 / 32 * a0
    f_N = np.pi * E0 * a0**2 / (4 * R)
    F_N = 4 * E0 * r0**3 / (3 * R)
    assert f_N / (2 * a0) == pytest.approx(F_N / (np.pi * r0**2), rel=1e-12)
    v = np.logspace(-2, 2, 17) * a0 / TAU
    mu_c = mu_cylinder(f_N, R, v, m)
    mu_s = mu_sphere(F_N, R, v, m)
    assert (mu_s < mu_c).all()
    assert 0.3 < mu_s.max() / mu_c.max() < 0.95


# -- the wedge (sec. 7) -----------------------------------------------------------------------
def test_wedge_width_and_strain_against_the_review() -> None:
    alpha = np.radians(65.0)
    assert wedge_strain(alpha) == pytest.approx(0.233, abs=1e-3), "review: ~0.25"
    # review Fig. of p(x): E_eff = 25 MPa x 0.2 = 5 MPa, f_N = 3000 N/m -> w = 2 a ~ 2.5 mm
    assert 2 * wedge_half_width(3000.0, alpha, 5e6) == pytest.approx(2.5e-3, rel=0.05)
    # plausibility with a shipped tread compound at the wedge strain: footprints of 2 mm
    # (6 s) and 2.5 mm (600 s) in the review (its SBR, E_eff = 5 MPa); the shipped summer
    # compound is softer there (|E_eff| = 1.6 and 1.3 MPa at 1/6 and 1/600 rad/s: a
    # small-strain modulus of 5.2 and 4.2 MPa, eta_R = 0.23 at the wedge strain, over
    # 1 - nu^2) and gives 8 and 10 mm, so within a factor 5 (w ~ 1/E_eff), widening with time
    m = EffectiveModulus(load_compound("summer"), T20, wedge_strain(alpha))
    w6, w600 = (2 * wedge_half_width(3000.0, alpha, m.magnitude(1.0 / t)) for t in (6, 600))
    assert 2e-3 < w6 < w600 < 12.5e-3, (w6, w600)


def test_wedge_transform_against_sampled_profile() -> None:
    """mu_wedge's closed-form transform k^-1 int_0^k J0 against the sampled arccosh profile
    (2 %: the log singularity at the tip is sampled)."""
    m = sls_modulus()
    alpha, f_N = np.radians(65.0), 3000.0
    a = float(wedge_half_width(f_N, alpha, E0))
    x = np.concatenate([-np.geomspace(a, 1e-7 * a, 600), np.geomspace(1e-7 * a, a, 600)])
    p = f_N / (np.pi * a) * np.arccosh(a / np.abs(x))
    v = np.array([0.3, 3.0]) * a / TAU
    np.testing.assert_allclose(mu_profile(x, p, v, m), mu_wedge(f_N, alpha, v, m,
                                                                 E_contact=E0), rtol=2e-2)


# -- tread layer ------------------------------------------------------------------------------
def _footprint(a: float = 0.06, p0: float = 3e5) -> tuple[np.ndarray, np.ndarray]:
    x = np.linspace(-a, a, 121)
    return x, p0 * (1 - (x / a) ** 2)


def test_bonded_layer_factor() -> None:
    qh = np.array([0.1, 0.5, 1.0, 3.0])
    for nu in (0.3, 0.45):
        ref = reference.layered_K(qh, 1.0, nu, 1e9, 0.3)  # film on a nearly rigid base
        np.testing.assert_allclose(bonded_layer_factor(qh, nu), ref, rtol=1e-6)
    small = np.array([1e-5, 1e-3])
    np.testing.assert_allclose(bonded_layer_factor(small, 0.5), 2 / 3 * small**3, rtol=1e-2)
    assert bonded_layer_factor(np.array([50.0, 1e4]), 0.5) == pytest.approx(1.0)


def test_tread_positive_and_rises_with_loss() -> None:
    x, p = _footprint()
    c = load_compound("summer")
    for support in ("bonded", "winkler"):
        vals = [tread_rolling_resistance(x, p, 8e-3, V, c, 313.15, support=support)
                for V in (1.0, 30.0)]
        assert min(vals) > 0, (support, vals)
    # loss scaled by eta_I at the rolling frequency V/a: the coefficient rises with it
    # (proportional in the small-tan-delta limit)
    for support in ("bonded", "winkler"):
        r = []
        for eta in (0.25, 0.5, 1.0):
            comp = sls_modulus(1.2, eta).compound
            r.append(tread_rolling_resistance(x, p, 8e-3, 0.06 / TAU, comp, T20,
                                              support=support))
        assert r[0] < r[1] < r[2], (support, r)
        assert r[2] / r[0] == pytest.approx(4.0, rel=0.1), (support, r)


def test_thick_bonded_layer_is_the_half_space() -> None:
    x, p = _footprint()
    m = sls_modulus(nu=0.3)
    V = np.array([0.05, 0.5])
    half = mu_profile(x, p, V, m)
    thick = [tread_rolling_resistance(x, p, 100.0, Vi, m.compound, T20) for Vi in V]
    np.testing.assert_allclose(thick, half, rtol=1e-3)


def test_winkler_against_time_domain_columns() -> None:
    """Winkler tread: independent columns of height h, each a standard linear solid
    (review eq. 4) loaded by p(-V t); the work sum of sigma d(eps) per column, times h,
    divided by the load, against the frequency-domain formula (0.5 %: time step)."""
    x, p = _footprint()
    m = sls_modulus(E1_over_E0=3.0)
    h, V = 8e-3, 0.6 / TAU
    got = tread_rolling_resistance(x, p, h, V, m.compound, T20, support="winkler")
    dt = 1e-4 * TAU
    t = np.arange(0, (x[-1] - x[0]) / V + 20 * TAU, dt)
    sig = np.interp(x[-1] - V * t, x, p, left=0.0, right=0.0)
    # tau z' = sigma - z (z = creep part), exact for piecewise-linear sigma
    E = np.exp(-dt / TAU)
    beta = TAU / dt * (1 - E)
    z = np.zeros_like(sig)
    for k in range(sig.size - 1):
        z[k + 1] = E * z[k] + sig[k + 1] * (1 - beta) + sig[k] * (beta - E)
    D = 1 / E0 - 1 / (3 * E0)
    W = D * np.sum(0.5 * (sig[1:] + sig[:-1]) * np.diff(z))  # J/m^3 per passage
    f_N = float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(x)))
    assert got == pytest.approx(h * W / f_N, rel=5e-3)


# -- inputs and CLI ---------------------------------------------------------------------------
@pytest.mark.parametrize("call", [
    lambda m: mu_cylinder(1000.0, 0.0, 1.0, m),
    lambda m: mu_cylinder(1000.0, float("nan"), 1.0, m),
    lambda m: mu_cylinder(-1.0, 0.01, 1.0, m),
    lambda m: mu_sphere(10.0, 0.01, [1.0, float("nan")], m),
    lambda m: mu_wedge(3000.0, np.pi / 2, 1.0, m),
    lambda m: mu_wedge(3000.0, 0.0, 1.0, m),
    lambda m: mu_cylinder(1000.0, 0.01, 0.0, m),
    lambda m: mu_profile([0.0, 1.0], [1.0, float("nan")], 1.0, m),
    lambda m: tread_rolling_resistance([0, 1], [1, 0], 0.0, 1.0, m.compound, T20),
])
def test_bad_inputs_raise(call) -> None:
    with pytest.raises(InputError):
        call(sls_modulus())


def _pyproject_rolling_entry() -> str:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    return data["project"]["entry-points"]["tirefric.commands"]["rolling"]


@pytest.fixture
def main(monkeypatch):
    """tirefric.cli.main with the entry point declared in pyproject.toml (an installed copy
    made before this command existed does not list it yet)."""
    import tirefric.cli as cli

    real = cli.entry_points

    def eps(group: str):
        found = list(real(group=group))
        if not any(e.name == "rolling" for e in found):
            found.append(EntryPoint("rolling", _pyproject_rolling_entry(), group))
        return found

    monkeypatch.setattr(cli, "entry_points", eps)
    return cli.main


def test_cli_table_json_plot(main, capsys, tmp_path) -> None:
    assert _pyproject_rolling_entry() == "lookup.rolling_cli:register"
    rc = main(["rolling", "cylinder", "--compound", "summer", "--radius", "0.005",
               "--load", "1000", "--v", "1e-3,1", "--T", "20,50", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    pts = out["points"]
    assert len(pts) == 4 and {p["T_C"] for p in pts} == {20.0, 50.0}
    m = EffectiveModulus(load_compound("summer"), T20)
    assert pts[1]["mu"] == pytest.approx(float(mu_cylinder(1000.0, 0.005, 1.0, m)[0]),
                                         rel=1e-12)
    # the a_m column: the half-width a that solves a = a(|E_eff(v / a)|) (eq. 31 at the
    # frequency of the contact size), here by fixed-point iteration
    a0 = 1e-3
    for _ in range(60):
        a0 = float(cylinder_half_width(1000.0, 0.005, m.magnitude(np.array(1e-3 / a0))))
    assert pts[0]["a_m"] == pytest.approx(a0, rel=1e-3)
    png = tmp_path / "wedge.png"
    rc = main(["rolling", "wedge", "--compound", "summer", "--angle-deg", "65", "--load",
               "3000", "--v", "1e-6,1", "--T", "0,20", "--plot", str(png)])
    assert rc == 0 and png.stat().st_size > 10_000
    text = capsys.readouterr().out
    assert "strain = 0.233" in text and "a_m" in text
    rc = main(["rolling", "sphere", "--compound", "summer", "--radius", "0.01", "--load", "5",
               "--v", "0.1", "--T", "20"])
    assert rc == 0 and "r_c_m" in capsys.readouterr().out


@pytest.mark.parametrize("args,option,value", [
    (["cylinder", "--radius", "0"], "--radius", "'0'"),
    (["cylinder", "--radius", "nan"], "--radius", "'nan'"),
    (["sphere", "--radius", "-2"], "--radius", "'-2'"),
    (["wedge", "--angle-deg", "90"], "--angle-deg", "'90'"),
    (["wedge", "--angle-deg", "0"], "--angle-deg", "'0'"),
    (["cylinder", "--radius", "0.01", "--load", "0"], "--load", "'0'"),
    (["cylinder", "--radius", "0.01", "--load", "nan"], "--load", "'nan'"),
])
def test_cli_bad_inputs_exit_2(main, capsys, args, option, value) -> None:
    base = ["rolling", args[0], "--compound", "summer", "--v", "1", "--T", "20"]
    rest = args[1:]
    if "--load" not in rest:
        rest += ["--load", "1000"]
    assert main(base + rest) == 2
    err = capsys.readouterr().err
    assert option in err and value in err, err
