"""Physics checks of the Persson engine (docs/review-notes.md, "Closed forms and checks"; the
traps cited as "trap N" are those of docs/review-notes.md). Tolerances are tiered: ~1e-9 where only
floating point separates two evaluations of the same formula, ~1e-6 against closed forms with
converged quadrature, looser where the default resolution or a physical approximation limits
accuracy (reason given at each)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import T20, make_compound, make_surface

from lookup.adhesion import GaussianShearLaw, NoAdhesion
from lookup.flash_temperature import heat_kernel, lateral_factor
from lookup.friction import EngineSettings, PerssonFriction
from lookup.modulus import Prony, SingleRelaxation, TabulatedMasterCurve
from lookup.reference import (
    contact_area_elastic,
    gaussian_law_fwhm,
    single_relaxation_angular_abs2,
    single_relaxation_angular_loss,
)
from lookup.roughness import CutoffRule
from lookup.shift import WLF, Arrhenius


# -- docs/review-notes.md, Trap 1: the sign of Im E ---
def test_loss_modulus_sign_and_parity(single_relaxation: SingleRelaxation) -> None:
    w = np.logspace(-3, 8, 50)
    E = single_relaxation.complex_modulus(w)
    assert (E.imag < 0).all(), "eq. (4) with e^{-i w t}: Im E < 0 for w > 0 (Trap 1)"
    assert ((1.0 / E).imag > 0).all(), "Im(1/E) > 0 for w > 0 (Trap 1)"
    ER, EI = single_relaxation.storage_loss(w)
    assert (EI > 0).all(), "the loss modulus E_I = -Im E is positive"
    ERm, EIm = single_relaxation.storage_loss(-w)
    np.testing.assert_allclose(EIm, -EI, rtol=1e-12, err_msg="E_I is odd in w")
    np.testing.assert_allclose(ERm, ER, rtol=1e-12, err_msg="E_R is even in w")
    prony = Prony.lognormal(5e6, 1e9, 1e-6, 2.0)
    assert (prony.storage_loss(w)[1] > 0).all(), "Prony loss modulus positive for w > 0"


def test_viscoelastic_friction_is_positive(compound, surface) -> None:
    m = PerssonFriction(compound, surface)
    r = m.cold(np.logspace(-8, 1.5, 20), T20, 3e5)
    assert (r.mu_visc > 0).all(), "mu_visc > 0 at every speed (loss sign pinned, Trap 1)"


# -- docs/review-notes.md, Trap 2, and eq. (10): elastic limit ---
def test_contact_area_elastic_limit_eq10() -> None:
    """With E real and constant, P(q1) = erf(sqrt(2) sigma0/(xi E*)) exactly (Trap 2).

    The rms slope xi is evaluated by the engine's own q quadrature, so the identity holds to
    round-off; against the closed-form xi the trapezoidal rule at 400 nodes per decade is good
    to ~1e-6 (h^2 error, h = ln 10 / 400)."""
    E = 8e6
    elastic = Prony(E, np.array([0.0]), np.array([1.0]))
    comp = make_compound(elastic, NoAdhesion(), nu=0.5)
    surf = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-5,
                        cutoff=CutoffRule("fixed", q1=1e6))
    m = PerssonFriction(comp, surf, EngineSettings(q_per_decade=400))
    E_star = E / (1 - 0.5**2)
    xi_quad = np.sqrt(2 * np.pi * np.sum(m.w_lnq * m.F))
    xi_exact = np.sqrt(surf.psd.xi_squared(1e6))
    for sigma0 in (1e4, 1e5, 1e6, 5e6):
        area = m.cold(1.0, T20, sigma0).area
        np.testing.assert_allclose(area, contact_area_elastic(sigma0, xi_quad, E_star),
                                   rtol=1e-9, err_msg="P(q1) vs eq. (10), same xi quadrature")
        np.testing.assert_allclose(area, contact_area_elastic(sigma0, xi_exact, E_star),
                                   rtol=1e-6, err_msg="P(q1) vs eq. (10), closed-form xi")
    assert m.cold(1.0, T20, 1e5).mu_visc == pytest.approx(0.0, abs=1e-200), \
        "no loss, no viscoelastic friction"


def test_area_decreases_with_magnification(compound, surface) -> None:
    """P(q) = erf(1/(2 sqrt G)) decreases with G, i.e. with magnification (Trap 2: the printed
    middle expression of eq. 18 would grow)."""
    m = PerssonFriction(compound, surface)
    parts = m._evaluate(np.array([0.1]), np.array([T20]), np.array([3e5]), None)
    assert parts["area"][0] < 1.0
    areas = [m.cold(0.1, T20, 3e5).area, m.cold(0.1, T20, 6e5).area]
    assert areas[1] > areas[0], "more pressure, more contact"


# -- single-relaxation closed forms -------------------------------------------------------------
@pytest.mark.parametrize("n_phi,per_decade,rtol", [(64, 400, 2e-6), (16, 40, 2e-3)])
def test_single_relaxation_angular_integrals(n_phi, per_decade, rtol) -> None:
    """Angular integrals of eq. (17) and (19) vs the closed forms of docs/review-notes.md.

    Converged settings (64 nodes, modulus table at 400/decade) must agree to ~1e-6; the
    default settings are limited by the log-log table (error ~ (dx)^2/8 curvature, 2e-3)."""
    E0, E1, tau = 5e6, 5e9, 1e-4
    mod = SingleRelaxation(E0, E1, tau)
    comp = make_compound(mod, NoAdhesion(), nu=0.0)
    m = PerssonFriction(comp, make_surface(), EngineSettings(n_phi=n_phi,
                                                             modulus_per_decade=per_decade))
    tau_p = tau * E0 / E1
    v = 1.0
    A_I, A_2 = m._angular(np.array([v]), np.zeros((1, m.q.size)))
    x = m.q * v * tau_p
    np.testing.assert_allclose(A_I[0], single_relaxation_angular_loss(x, E0, E1), rtol=rtol,
                               err_msg="int cos(phi) E_I dphi vs closed form")
    np.testing.assert_allclose(A_2[0], single_relaxation_angular_abs2(x, E0, E1), rtol=rtol,
                               err_msg="int |E|^2 dphi vs closed form")


# -- time-temperature superposition ----------------------------------------------------------
def test_time_temperature_superposition() -> None:
    """Without heating mu(v, T) = mu(v a_T(T), T_ref) exactly (adhesion shifted with the bulk
    a_T so that both parts obey it). Agreement to 1e-9: the two evaluations add the same
    logarithms in a different order."""
    shift = WLF(15.0, 150.0, T20)
    comp = make_compound(adhesion=GaussianShearLaw(4e6, 0.17, 1e-2, T20, shift), shift=shift)
    m = PerssonFriction(comp, make_surface())
    v = np.logspace(-6, 1, 15)
    for T in (253.15, 313.15, 373.15):
        aT = 10.0 ** comp.log10_aT(np.array(T))
        a = m.cold(v, T, 3e5)
        b = m.cold(v * aT, T20, 3e5)
        np.testing.assert_allclose(a.mu, b.mu, rtol=1e-9, err_msg=f"TTS at T = {T} K")
        np.testing.assert_allclose(a.area, b.area, rtol=1e-9)


# -- eq. (21) ---
def test_gaussian_shear_law_fwhm() -> None:
    law = GaussianShearLaw(5e6, 0.17, 1e-2, T20, Arrhenius(1.602176634e-19, T20))
    lv = np.linspace(-8, 4, 200001)
    s = law.sigma_f(10.0**lv, T20)
    above = lv[s >= 0.5 * s.max()]
    fwhm = above[-1] - above[0]
    assert fwhm == pytest.approx(gaussian_law_fwhm(0.17), abs=1e-4), "FWHM of eq. (21)"
    assert gaussian_law_fwhm(0.17) == pytest.approx(4.04, abs=0.01), "review: about 4 decades"
    assert lv[np.argmax(s)] == pytest.approx(-2.0, abs=1e-4), "maximum at v* = 1 cm/s"


def test_arrhenius_shift_eq22() -> None:
    a = Arrhenius(1.602176634e-19, T20)
    # ln a = (eps/k_B)(1/T - 1/T_ref): 1 eV / k_B = 11604.5 K
    expected = 11604.518 * (1 / 313.15 - 1 / T20) / np.log(10)
    assert a.log10_aT(313.15) == pytest.approx(expected, rel=1e-6)


# -- hot branch ---
def test_hot_equals_cold_at_low_speed(compound, surface) -> None:
    """Below ~1e-4 m/s frictional heating is negligible (review sec. 5.1). At 1e-4 m/s the
    flash temperature is a fraction of a kelvin, which moves mu by well under 1 %."""
    m = PerssonFriction(compound, surface)
    v = np.array([1e-7, 1e-6, 1e-5, 1e-4])
    c, h = m.cold(v, T20, 3e5), m.hot(v, T20, 3e5)
    np.testing.assert_allclose(h.mu[:3], c.mu[:3], rtol=1e-3, err_msg="hot = cold, v <= 1e-5")
    np.testing.assert_allclose(h.mu[3], c.mu[3], rtol=1e-2, err_msg="hot ~ cold at 1e-4 m/s")
    assert (h.dT_flash < 1.0).all(), "flash temperature below 1 K up to 1e-4 m/s"


def test_hot_branch_stays_physical(compound, surface) -> None:
    """Bounds of the converged hot branch over the operating range (the residual and the
    fixed point itself are checked against a closed form in test_physics_reference.py)."""
    m = PerssonFriction(compound, surface)
    v = np.array([0.01, 0.1, 1.0, 10.0, 30.0])
    for T in (253.15, 293.15, 353.15):
        for p in (5e4, 3e5, 2e6):
            h = m.hot(v, T, p)
            assert np.isfinite(h.mu).all() and (h.mu > 0).all() and (h.mu < 5).all()
            assert ((h.area > 0) & (h.area <= 1)).all()
            assert ((h.dT_flash >= 0) & (h.dT_flash < 500)).all(), \
                f"flash temperature physical at 30 m/s: {h.dT_flash}"


def test_heat_sources_add_up_to_friction_power(compound, surface) -> None:
    """Energy balance: heat produced in the macro contacts (times their area fraction) equals
    the friction power mu sigma0 v per nominal area."""
    m = PerssonFriction(compound, surface)
    v, T0, p = np.array([0.3, 5.0]), np.array([T20, 330.0]), np.array([3e5, 1e6])
    parts = m._evaluate(v, T0, p, None)
    W = m.heat_sources(v, p, parts)
    power = (parts["mu_visc"] + parts["mu_cont"]) * p * v
    np.testing.assert_allclose(W.sum(axis=1) * parts["P_m"], power, rtol=1e-12)


# -- the heat kernel ---
@pytest.mark.parametrize("R", [1.0, 0.3, -0.28])
def test_heat_kernel_energy_balance(R) -> None:
    """Heat stored in the rubber: int rho c <dT> dz = (t_c/2) x (fraction kept) per unit power.

    A volumetric source loses to the road only what reaches the surface; a surface flux keeps
    the fraction (1 + R)/2 = e_rubber/(e_rubber + e_road). Depth quadrature on 4000 log-spaced
    points limits agreement to ~2e-3."""
    D_th, rho_c, t_c = 1e-7, 1500.0 * 1500.0, 1e-3
    z = np.concatenate([[0.0], np.geomspace(1e-10, 0.05, 4000)])
    a = np.array([np.inf, 2e4, 2e6])
    K = heat_kernel(z, a, t_c, D_th, rho_c, R)
    stored = rho_c * np.trapezoid(K, z, axis=0) / (t_c / 2)
    assert stored[0] == pytest.approx((1 + R) / 2, rel=2e-3), "surface flux partition"
    if R == 1.0:
        np.testing.assert_allclose(stored, 1.0, rtol=2e-3, err_msg="insulated: all heat kept")
    else:
        assert ((stored > (1 + R) / 2 - 2e-3) & (stored <= 1 + 2e-3)).all()


def test_heat_kernel_surface_source_limits() -> None:
    """Surface flux: 1D contact-time average (4/(3 sqrt pi)) q sqrt(D t_c)/kappa for J_d >> 1
    (the eq. 27 scaling, prefactor of the 1D average), and q D/kappa (eq. 25) for J_d -> 0
    once the lateral factor is applied."""
    D_th, rho_c, D = 1e-7, 2.25e6, 1e-3
    kappa = D_th * rho_c
    for v in (100.0, 1e-7):
        t_c = D / v
        K = heat_kernel(np.array([0.0]), np.array([np.inf]), t_c, D_th, rho_c, 1.0)[0, 0]
        one_d = 4.0 / (3.0 * np.sqrt(np.pi)) * np.sqrt(D_th * t_c) / kappa
        assert K == pytest.approx(one_d, rel=1e-3), f"1D average at v = {v}"
        J_d = v * D / D_th
        with_lat = K * lateral_factor(J_d)
        if J_d > 1e3:
            assert with_lat == pytest.approx(one_d, rel=1e-3)
        else:
            assert with_lat == pytest.approx(D / kappa, rel=1e-3), "eq. (25) limit"


# -- tabulated master curve policy ---
def test_tabulated_master_curve_outside_policy() -> None:
    ref = Prony.lognormal(5e6, 1e9, 1e-4, 1.5)
    w = np.logspace(-2, 6, 81)
    ER, EI = ref.storage_loss(w)
    tab = TabulatedMasterCurve(w, ER, EI)
    inside = np.logspace(-1.5, 5.5, 30)
    np.testing.assert_allclose(tab.storage_loss(inside)[0], ref.storage_loss(inside)[0],
                               rtol=5e-3, err_msg="log-log interpolation at 10 pts/decade")
    lo = tab.storage_loss(np.array([1e-4, 1e-3]))
    np.testing.assert_allclose(lo[0], ER[0], rtol=1e-12, err_msg="E' held below the data")
    assert lo[1][1] / lo[1][0] == pytest.approx(10.0, rel=1e-9), "E'' ~ w below the data"
    hi = tab.storage_loss(np.array([1e7, 1e8]))
    assert hi[1][0] / hi[1][1] == pytest.approx(10.0, rel=1e-9), "E'' ~ 1/w above the data"
    strict = TabulatedMasterCurve(w, ER, EI, outside="error")
    with pytest.raises(ValueError, match="outside"):
        strict.storage_loss(np.array([1e9]))


def test_cold_and_hot_equal_separate_branches(compound, surface) -> None:
    """The shared-start solve gives exactly the numbers of cold() and hot() (bit for bit:
    the hot iteration starts from the same dT = 0 evaluation)."""
    from dataclasses import asdict

    m = PerssonFriction(compound, surface)
    T = np.array([[253.15], [293.15], [353.15]])
    p = np.array([[5e4, 3e5, 2e6]])
    for v in (1e-5, 0.03, 3.0, 30.0):
        c, h = m.cold_and_hot(v, T, p)
        for a, b in ((c, m.cold(v, T, p)), (h, m.hot(v, T, p))):
            for key, val in asdict(a).items():
                np.testing.assert_array_equal(val, getattr(b, key), err_msg=f"{key} at v={v}")
