"""The engine against references that share no code with it.

Each check recomputes a physics number from the review's equations written out again here (or
in :mod:`persson_reference`, which imports nothing from the package) and compares it with the
engine, with a tolerance whose reason is stated. These are the tests a wrong prefactor,
argument, sign or unit must fail (``python tests/mutations.py`` checks that they do).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import T20, make_compound, make_surface
from persson_reference import mu_visc_bruteforce
from scipy.special import erf

from lookup.adhesion import GaussianShearLaw, NoAdhesion
from lookup.contact import Phi
from lookup.friction import EngineSettings, PerssonFriction
from lookup.modulus import Prony, SingleRelaxation
from lookup.roughness import CutoffRule
from lookup.shift import WLF, Arrhenius, TabulatedShift
from lookup.softening import KrausSoftening, TabulatedSoftening

E0, E1, TAU = 5e6, 5e9, 1e-2
Q0, Q1, H, H_RMS = 1e3, 1e5, 0.8, 1e-4
FINE = EngineSettings(q_per_decade=100, n_phi=32, modulus_per_decade=200)


def _single_relaxation_engine(settings: EngineSettings, softening=None, strain: float = 0.0):
    comp = make_compound(SingleRelaxation(E0, E1, TAU), NoAdhesion(), nu=0.5)
    if softening is not None:
        from dataclasses import replace

        comp = replace(comp, softening=softening, strain=strain)
    surf = make_surface(H=H, q0=Q0, q_r=Q0, h_rms=H_RMS, cutoff=CutoffRule("fixed", q1=Q1))
    return PerssonFriction(comp, surf, settings)


# -- eq. (17): mu_visc by brute force ------------------------------------------------------------
@pytest.mark.parametrize("v", [1e-3, 0.1, 1.0])
def test_mu_visc_against_bruteforce_quadrature(v: float) -> None:
    """Single-relaxation solid (eq. 4) on a self-affine surface, sigma0 = 1 MPa, where P(q)
    falls smoothly (A/A0 ~ 1e-3..0.5) so that 400 q per decade and 2000 angles converge the
    brute force to ~1e-5. The engine at fine settings agrees to 5e-4 (its modulus table is
    log-log interpolated, error ~1e-4); a factor 2 anywhere in eq. (17) or a wrong P or S is
    off by tens of percent."""
    mu_ref, area_ref = mu_visc_bruteforce(v, 1e6, 0.5, E0, E1, TAU, Q0, Q1, H, H_RMS)
    r = _single_relaxation_engine(FINE).cold(v, T20, 1e6)
    assert float(r.mu_visc) == pytest.approx(mu_ref, rel=5e-4), "mu_visc vs eq. (17) quadrature"
    assert float(r.area) == pytest.approx(area_ref, rel=3e-4), "A/A0 = P(q1) vs eqs. (18)-(19)"


def test_mu_visc_default_settings_against_bruteforce() -> None:
    """The shipped settings (24 q per decade, 16 angles, 40 modulus points per decade) are
    within 3e-3 of the converged quadrature (table interpolation limits them, ~2e-3)."""
    m = _single_relaxation_engine(EngineSettings())
    for v in (1e-3, 0.1):
        mu_ref, _ = mu_visc_bruteforce(v, 1e6, 0.5, E0, E1, TAU, Q0, Q1, H, H_RMS)
        assert float(m.cold(v, T20, 1e6).mu_visc) == pytest.approx(mu_ref, rel=3e-3), v


def test_strain_softening_enters_friction_eq6() -> None:
    """Review eq. (6): Re E x eta_R, Im E x eta_I. Kraus law at eps = eps_c: x = 1, so
    eta_R = r_inf + (1 - r_inf)/2 = 0.75 and eta_I = 1 + 2 (h - 1)/2 = 1.5 (by hand)."""
    kraus = KrausSoftening(eps_c=0.1, m=0.5, r_inf=0.5, h=1.5)
    assert kraus.factors(0.1) == pytest.approx((0.75, 1.5), rel=1e-12)
    # eps = 0.4: x = 2, eta_R = 0.5 + 0.5/5 = 0.6, eta_I = 1 + 1 * 2/5 = 1.4
    assert kraus.factors(0.4) == pytest.approx((0.6, 1.4), rel=1e-12)
    m = _single_relaxation_engine(FINE, kraus, 0.1)
    mu_ref, area_ref = mu_visc_bruteforce(0.1, 1e6, 0.5, E0, E1, TAU, Q0, Q1, H, H_RMS,
                                          eta_R=0.75, eta_I=1.5)
    r = m.cold(0.1, T20, 1e6)
    assert float(r.mu_visc) == pytest.approx(mu_ref, rel=5e-4), "softened mu_visc"
    assert float(r.area) == pytest.approx(area_ref, rel=3e-4), "softened contact area"


def test_tabulated_softening_hand_values() -> None:
    """Linear in log10(strain) between rows, clamped outside: at the geometric mean of two
    rows the factors are the arithmetic means."""
    tab = TabulatedSoftening(np.array([0.01, 0.1, 1.0]), np.array([1.0, 0.8, 0.4]),
                             np.array([1.0, 1.6, 1.2]))
    assert tab.factors(math.sqrt(0.1)) == pytest.approx((0.6, 1.4), rel=1e-12)
    assert tab.factors(0.1) == pytest.approx((0.8, 1.6), rel=1e-12)
    assert tab.factors(1e-4) == pytest.approx((1.0, 1.0), rel=1e-12), "clamped below"
    assert tab.factors(10.0) == pytest.approx((0.4, 1.2), rel=1e-12), "clamped above"


# -- shift factors --------------------------------------------------------------------------------
def test_wlf_hand_values_and_continuation() -> None:
    """Eq. (5): log10 a_T = -C1 (T - T_r)/(C2 + T - T_r); a_T < 1 above T_r (faster
    relaxation when hot). Below T_r - 0.9 C2 the law is continued linearly with the slope
    -C1 C2/(0.1 C2)^2 it has there (values by hand for C1 = 10, C2 = 100 K)."""
    w = WLF(10.0, 100.0, 300.0)
    assert float(w.log10_aT(350.0)) == pytest.approx(-10.0 * 50 / 150, rel=1e-12)
    assert float(w.log10_aT(250.0)) == pytest.approx(10.0, rel=1e-12)  # -10 (-50)/50
    at = float(w.log10_aT(210.0))  # dT = -90 = -0.9 C2: -10 (-90)/10 = 90
    assert at == pytest.approx(90.0, rel=1e-12)
    # 5 K further down: 90 + slope (-5), slope = -10 * 100 / 10^2 = -10 per K
    assert float(w.log10_aT(205.0)) == pytest.approx(140.0, rel=1e-12)
    assert float(w.log10_aT(150.0)) == pytest.approx(90.0 + 600.0, rel=1e-12)


def test_tabulated_shift_hand_values() -> None:
    """Linear in T between rows, end segments continued linearly."""
    tab = TabulatedShift(np.array([250.0, 300.0, 350.0]), np.array([4.0, 0.0, -2.0]), 300.0)
    np.testing.assert_allclose(tab.log10_aT(np.array([275.0, 325.0, 200.0, 400.0])),
                               [2.0, -1.0, 8.0, -4.0], rtol=1e-12, err_msg="table a_T")


def test_shift_direction_in_the_friction() -> None:
    """Heating moves the friction to higher speed: with a_T from WLF, mu(v, T) at T above
    T_ref equals mu at the lower speed v a_T(T) (a_T < 1) at T_ref. Hand value of a_T (WLF
    C1 = 15, C2 = 150 K at 20 C, T = 60 C): log10 a_T = -15 * 40 / 190 = -3.158."""
    comp = make_compound(SingleRelaxation(E0, E1, TAU), NoAdhesion(), shift=WLF(15, 150, T20))
    m = PerssonFriction(comp, make_surface())
    la = -15.0 * 40.0 / 190.0
    a = m.cold(1.0, T20 + 40.0, 3e5).mu
    b = m.cold(10.0**la, T20, 3e5).mu
    assert float(a) == pytest.approx(float(b), rel=1e-9), "mu(v, T) = mu(v a_T, T_ref)"
    assert float(comp.log10_aT(np.array(T20 + 40.0))) == pytest.approx(la, rel=1e-12)


# -- contact mechanics pieces ---------------------------------------------------------------------
def test_phi_table_against_direct_quadrature() -> None:
    """Phi(G) = int_0^G S(P(g)) P(g) dg with P = erf(1/(2 sqrt g)), S = 1/2 + P^2/2, by a
    fine midpoint rule in ln g (1e5 points per unit of ln g; error < 1e-8). The table is
    cubic Hermite in ln-ln and documented to ~1e-10; 1e-7 leaves room for this quadrature."""
    for G in (1e-3, 0.3, 2.0, 50.0, 1e4):
        lg = np.linspace(np.log(1e-14), np.log(G), 400001)
        mid = 0.5 * (lg[1:] + lg[:-1])
        g = np.exp(mid)
        P = erf(1.0 / (2.0 * np.sqrt(g)))
        ref = 1e-14 + np.sum((0.5 + 0.5 * P * P) * P * g) * (lg[1] - lg[0])
        assert float(Phi(np.array(G), 0.5)) == pytest.approx(ref, rel=1e-7), f"Phi({G})"


# -- flash temperature and the hot branch --------------------------------------------------------
#: q1 of the flash case: the heat kernel starts its time quadrature at tau_lo ~ 1e-3/(4 q1^2
#: D_th) and drops the surface-flux part below it, a relative error 1.5 sqrt(tau_lo/t_c) at
#: the surface (3e-2 at q1 = 1e5, 3e-4 at q1 = 1e7).
Q1_FLASH = 1e7


def _adhesive_only(activation_J: float):
    """Elastic (lossless) rubber with a Gaussian shear law: all heat is the adhesive surface
    flux, so the flash temperature has a closed form."""
    E = 8e6
    comp = make_compound(Prony(E, np.array([0.0]), np.array([1.0])),
                         GaussianShearLaw(5e6, 0.17, 1e-2, T20, Arrhenius(activation_J, T20)))
    surf = make_surface(H=H, q0=Q0, q_r=Q0, h_rms=1e-5, thermal=False,
                        cutoff=CutoffRule("fixed", q1=Q1_FLASH))
    return PerssonFriction(comp, surf, EngineSettings(q_per_decade=40)), surf, E / 0.75


def _xi2(q: float) -> float:
    """Cumulative mean-square slope of the self-affine test surface (h_rms = 1e-5 m), by hand:
    2 pi C0 q0^(2H+2) (q^(2-2H) - q0^(2-2H))/(2-2H), C0 = 2 H h_rms^2/(2 pi q0^2)."""
    C0 = 2 * H * 1e-10 / (2 * np.pi * Q0**2)
    return 2 * np.pi * C0 * Q0 ** (2 * H + 2) * (q ** (2 - 2 * H) - Q0 ** (2 - 2 * H)) / (2 - 2 * H)


@pytest.mark.parametrize("activation_eV", [0.0, 1.0])
def test_flash_temperature_closed_form_and_self_consistency(activation_eV: float) -> None:
    """A surface flux W switched on for the contact time t_c = D/v heats a half-space by
    T(0, t) = 2 W sqrt(D_th t/pi)/kappa; its contact-time average is
    (4/(3 sqrt pi)) W sqrt(D_th D/v)/kappa (Carslaw & Jaeger sec. 2.9). Lateral losses:
    J_d = v D/D_th = 7.5e4, factor (1 + 16/(9 pi)/J_d)^(-1/2) = 1 - 4e-6 (review eq. 26).
    W = mu_cont sigma0 v / P(q_m) is the heat per macro-contact area, q_m = pi/D, with P from
    eq. (10) at q_m. The temperature is re-evaluated from the *returned* friction, and the
    returned friction from the returned temperature (eq. 21-22 by hand): both hold at the fixed
    point. Tolerance 3e-3: the engine's heat-kernel time quadrature (~1e-3, see Q1_FLASH);
    a doubled contact time is off by 40 %."""
    eps = activation_eV * 1.602176634e-19
    m, surf, E_star = _adhesive_only(max(eps, 1e-30))
    v, sigma0 = 10.0, 1e6
    h = m.hot(v, T20, sigma0)
    kappa, D_th = 0.3, 0.3 / (1500.0 * 1500.0)
    q_m = np.pi / surf.D
    P_m = erf(np.sqrt(2) * sigma0 / (np.sqrt(_xi2(q_m)) * E_star))
    area = erf(np.sqrt(2) * sigma0 / (np.sqrt(_xi2(Q1_FLASH)) * E_star))
    assert float(h.area) == pytest.approx(area, rel=1e-3), "A/A0 vs eq. (10)"
    W = float(h.mu_cont) * sigma0 * v / P_m
    J_d = v * surf.D / D_th
    dT = 4 / (3 * np.sqrt(np.pi)) * W * np.sqrt(D_th * surf.D / v) / kappa \
        / np.sqrt(1 + 16 / (9 * np.pi) / J_d)
    assert float(h.dT_flash) == pytest.approx(dT, rel=3e-3), "flash temperature, closed form"
    assert float(h.dT_flash) > 20.0, "the case heats (tens of K)"
    T = T20 + float(h.dT_flash)
    log10_aT = eps / 1.380649e-23 * (1 / T - 1 / T20) / np.log(10)
    sigma_f = 5e6 * np.exp(-0.17 * (np.log10(v / 1e-2) + log10_aT) ** 2)
    assert float(h.mu_cont) == pytest.approx(sigma_f * area / sigma0, rel=3e-3), \
        "friction at the returned temperature (eqs. 21-22)"
    assert float(h.residual) <= m.settings.hot_tol, "reported residual within tolerance"


def test_hot_residual_reported_by_cli_and_grid(tmp_path, compound, surface) -> None:
    """The residual [K] that the hot solve reports is the max-norm |F(dT) - dT| of the
    returned state: a starved iteration budget must report a large residual, a converged
    solve one below hot_tol; the grid slice carries the same numbers as ``residual_hot``."""
    v, T, p = 3.0, np.array([T20]), np.array([3e5])
    starved = PerssonFriction(compound, surface, EngineSettings(hot_max_iter=1, aitken_iter=1))
    full = PerssonFriction(compound, surface)
    r_starved = float(starved.hot(v, T20, 3e5).residual)
    r_full = float(full.hot(v, T20, 3e5).residual)
    assert r_starved > 10 * full.settings.hot_tol, "one iteration is not converged"
    assert starved.last_hot_residual == pytest.approx(r_starved, rel=1e-12)
    assert r_full <= full.settings.hot_tol
    sl = full.grid_slice(v, T, p)
    assert float(sl["residual_hot"][0, 0]) == pytest.approx(r_full, rel=1e-12, abs=1e-15)
    sl2 = starved.grid_slice(v, T, p)
    assert float(sl2["residual_hot"][0, 0]) == pytest.approx(r_starved, rel=1e-12)


def test_cli_reports_the_hot_residual(capsys) -> None:
    """``tirefric mu --json`` reports as ``hot_residual_K`` the largest residual of the hot
    solves it printed: 0 < r <= hot_tol when the speeds heat the rubber (10 m/s: tens of K)."""
    import json

    from lookup.compound import load_compound
    from lookup.surface import load_surface
    from tirefric.cli import main

    assert main(["mu", "--compound", "summer", "--surface", "asphalt", "--v", "0.01,10",
                 "--T", "20", "--p", "3e5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    m = PerssonFriction(load_compound("summer"), load_surface("asphalt"))
    h = m.hot(np.array([0.01, 10.0]), T20, 3e5)
    assert out["hot_residual_K"] == pytest.approx(float(h.residual.max()), rel=1e-12)
    assert 0.0 < out["hot_residual_K"] <= m.settings.hot_tol
    assert out["points"][1]["dT_flash"] == pytest.approx(float(h.dT_flash[1]), rel=1e-12)
