"""The tread's series loading, the structure's energy share and the thermal equilibrium of the
rolling-resistance model (tire_brush.rolling_resistance; docs/rolling.md): each law against its
closed form and limits, checked independently of the code's formula where one exists."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from lookup.compound import load_compound
from tire_brush import rolling_resistance as rrm
from tire_brush.params import load_tire
from tirefric.errors import InputError

MODELS = Path(__file__).resolve().parents[1] / "models"


@pytest.fixture(scope="module")
def tire():
    return load_tire(MODELS / "tires" / "passenger.toml")


@pytest.fixture(scope="module")
def t210(tire):
    return replace(tire, patch=replace(tire.patch, p_inflation=210e3))


@pytest.fixture(scope="module")
def compound():
    return load_compound(MODELS / "compounds" / "summer.toml")


@pytest.fixture(scope="module")
def rr(tire):
    return rrm.load_rolling_params(tire)


def test_deformation_index_is_the_log_slope_of_the_series_loss():
    """Futamura's index: the loss of a tread (c_t = s/E) in series with an elastic belt c_b
    under an imposed deflection, omega Im(c_t)/|c_t + c_b|^2, scales as E''/|E|^n at small
    tan delta. The index is checked against the numerical log-derivative of that loss in |E|
    at fixed tan delta (central difference, step 1e-4: error ~1e-8; tan delta 1e-3: the
    closed form's neglected terms are ~tan^2 delta), and its limits: 0 on a rigid belt
    (imposed compression, loss ~ E''), 2 on a belt much softer than the tread (imposed
    pressure, loss ~ E''/|E|^2)."""
    s, tan_d = 8e-3, 1e-3

    def loss(E_abs, c_b):
        E = E_abs * (1 + 1j * tan_d) / math.hypot(1, tan_d)
        c_t = s / np.conj(E)  # Im c_t > 0 (review eq. 4 convention)
        return c_t.imag / abs(c_t + c_b) ** 2

    E_abs, h = 4e6, 1e-4
    for c_b in (0.0, 1e-10, 1e-9, 2e-9, 1e-8, 1e-6):
        slope = (math.log(loss(E_abs * math.exp(h), c_b))
                 - math.log(loss(E_abs * math.exp(-h), c_b))) / (2 * h)
        n = rrm.deformation_index(s / E_abs, c_b)
        assert slope == pytest.approx(1.0 - n, abs=1e-5), c_b
    assert rrm.deformation_index(2e-9, 0.0) == 0.0
    assert rrm.deformation_index(2e-9, 1e3) == pytest.approx(2.0, abs=1e-11)
    assert rrm.deformation_index(2e-9, 2e-9) == pytest.approx(1.0)


def test_series_factor_limits():
    """|c_ref + c_b|^2/|c_t + c_b|^2: 1 in the reference state and on a belt much softer than
    the tread (pressure imposed); |c_ref/c_t|^2 on a rigid belt (compression imposed)."""
    c_t = np.array([2e-9 + 4e-10j, 5e-9 + 1e-9j])
    c_ref = 3e-9 + 5e-10j
    np.testing.assert_allclose(rrm.series_factor(c_t, c_ref, 1e6), 1.0, rtol=1e-12)
    np.testing.assert_allclose(rrm.series_factor(c_t, c_t, 1e-9), 1.0, rtol=1e-15)
    np.testing.assert_allclose(rrm.series_factor(c_t, c_ref, 0.0), abs(c_ref) ** 2
                               / np.abs(c_t) ** 2, rtol=1e-15)


def test_belt_compliance_is_the_tensioned_beam_on_its_foundation(t210, rr):
    """c_b(q) against a finite-difference solution of the beam equation
    EI w'''' - T w'' + k w = b p0 cos(q x) on one period (second-order differences, 400
    cells per wavelength: 1e-4), with T = p R0 b_belt and k = T/lambda^2 of the ring; and the
    limits: the string's b/(T (q^2 + lambda^-2)) without bending stiffness, b lambda^2/T for a
    uniform pressure."""
    Fz = 4825.0
    a, b = t210.patch.size(Fz)
    rho = rrm.deflection(t210, rr, Fz)  # the MF law (tests/test_rolling_vertical.py)
    _, lam = rrm.ring_pulse(a, rho, t210.patch.R0)
    T = t210.patch.p_inflation * t210.patch.R0 * rr.belt_width
    k = T / lam**2
    EI = rr.belt_bending_stiffness
    for q in (5.0, 40.0, 120.0):
        n = 400
        dx = 2 * math.pi / q / n
        x = np.arange(n) * dx
        eye = np.eye(n)
        d2 = (np.roll(eye, 1, axis=1) - 2 * eye + np.roll(eye, -1, axis=1)) / dx**2
        A = EI * d2 @ d2 - T * d2 + k * eye
        w = np.linalg.solve(A, b * np.cos(q * x))
        amp = 2 * abs(np.fft.rfft(w)[1]) / n
        assert float(rrm.belt_compliance(t210, rr, Fz, q)) == pytest.approx(amp, rel=1e-4)
    string = replace(rr, belt_bending_stiffness=0.0)
    q = np.array([1e-6, 10.0, 100.0])
    np.testing.assert_allclose(rrm.belt_compliance(t210, string, Fz, q),
                               b / (T * (q**2 + lam**-2)), rtol=1e-12)
    assert float(rrm.belt_compliance(t210, rr, Fz, 1e-9)) == pytest.approx(b * lam**2 / T)


def test_tread_loading_between_imposed_pressure_and_imposed_compression(t210, compound, rr):
    """The tread's footprint loss under the series loading tends to the pressure-imposed one
    (eq. 29 as it stands) on a belt much softer than the tread (no bending stiffness, a belt
    too narrow to carry tension: c_b -> infinity), and its change with temperature at the ISO
    point lies between the imposed pressure's (n = 2, a compliance loss that rises on the
    summer compound's glass-transition flank) and the imposed compression's (a belt too wide
    to yield, c_b -> 0: n = 0, loss ~ E'', which falls)."""
    V, Fz, T = rrm.ISO_SPEED, 4825.0, np.array([293.15, 303.15])
    pressure = replace(rr, tread_loading="pressure", belt_bending_stiffness=0.0)
    soft = replace(rr, belt_bending_stiffness=0.0, belt_width=1e-30)

    def footprint(r, temps):
        res = rrm.rolling_resistance(t210, compound, V, Fz, temps, rr=r)
        return res.f_tread - res.f_band

    np.testing.assert_allclose(footprint(soft, T), footprint(pressure, T), rtol=1e-6)
    rigid = replace(rr, belt_width=1e9)

    def per_K(r):
        f = footprint(r, T)
        return (f[1] - f[0]) / (10 * f.mean())

    s_p, s_series, s_rigid = per_K(pressure), per_K(rr), per_K(rigid)
    assert s_rigid < s_series < s_p
    assert s_rigid < 0 < s_p


def test_structure_share_is_the_parallel_springs_energy(tire, rr):
    """The structure (chi C_z, pressure-independent) and the gas (the rest of C_z', ~ p) take
    the same deflection rho = Fz/C_z': the structure stores chi C_z rho^2/2, i.e. the share
    chi C_z/C_z' of Fz^2/(2 C_z'); at the nominal pressure it is chi itself."""
    assert tire.patch.p_inflation == tire.patch.p_nom
    assert rrm.structure_share(tire, rr) == pytest.approx(rr.deflection_energy_share, rel=1e-15)
    Fz = 4825.0
    for p in (210e3, 230e3, 250e3):
        t = replace(tire, patch=replace(tire.patch, p_inflation=p))
        Cz = t.patch.vertical_stiffness
        rho = Fz / Cz
        U_s = 0.5 * rr.deflection_energy_share * t.patch.C_z * rho**2
        assert rrm.structure_share(t, rr) * Fz**2 / (2 * Cz) == pytest.approx(U_s, rel=1e-12)


def _tread_heat(t, compound, rr, V, Fz):
    def Q(T):
        res = rrm.rolling_resistance(t, compound, V, Fz, T, rr=rr)
        return float(res.tread_share * res.heat_rate)
    return Q


def test_steady_temperature_balances_the_tread_heat(t210, compound, rr):
    """At the equilibrium the conductance's cooling equals the tread's share of the rolling
    loss (to G x 1e-5 K: the root's xtol 1e-6 K); where the heat falls with temperature the
    tread warms by less than the ambient rises (dT/dT_a = G/(G - dQ/dT) < 1)."""
    V, Fz, Ta = rrm.ISO_SPEED, 4825.0, 298.15
    G = t210.thermal.conductance
    Q = _tread_heat(t210, compound, rr, V, Fz)
    T = rrm.steady_temperature(t210, compound, V, Fz, np.array([Ta - 5.0, Ta, Ta + 5.0]),
                               rr=rr)
    for t, ta in zip(T, (Ta - 5.0, Ta, Ta + 5.0), strict=True):
        assert abs(G * (t - ta) - Q(t)) < G * 1e-5
    assert Q(T[2]) < Q(T[0]) and 0 < (T[2] - T[0]) / 10.0 < 1.0
    with pytest.raises(InputError):
        rrm.steady_temperature(t210, compound, V, Fz, Ta, rr=rr, conductance=0.0)


def test_bracketed_roots_closed_form():
    """The vectorised Illinois solve finds each component's root of x^3 - c (closed form
    c^(1/3)) to its xtol, from brackets of different widths, one being the root's own end
    (f = 0 there) and one a function whose secant overshoots (x^9: regula falsi without the
    Illinois step stalls on one end)."""
    c = np.array([0.5, 2.0, 27.0, 8.0])
    lo = np.array([0.0, 1.0, 0.0, 1.0])
    hi = np.array([1.0, 2.0, 10.0, 2.0])
    x = rrm._bracketed_roots(lambda t: t**3 - c, lo, hi, xtol=1e-9)
    assert np.allclose(x, np.cbrt(c), rtol=0, atol=1e-9)
    y = rrm._bracketed_roots(lambda t: t**9 - 0.5, np.array([0.0]), np.array([3.0]), xtol=1e-9)
    assert y[0] == pytest.approx(0.5 ** (1 / 9), abs=1e-9)


@pytest.mark.slow
def test_steady_temperature_independent_of_the_bracket(t210, compound, rr):
    """The root equals a plain bracketed solve on [T_a, T_a + 150 K] (independent of the
    lattice), and tends to the ambient as the conductance grows, as T_a + Q(T_a)/G to first
    order (G = 1e5 W/K: the second-order term Q' Q/G^2 is below 1e-3 of it)."""
    V, Fz, Ta = rrm.ISO_SPEED, 4825.0, 298.15
    G = t210.thermal.conductance
    Q = _tread_heat(t210, compound, rr, V, Fz)
    T = rrm.steady_temperature(t210, compound, V, Fz, Ta, rr=rr)
    plain = brentq(lambda t: G * (t - Ta) - Q(t), Ta, Ta + 150.0, xtol=1e-8)
    assert T == pytest.approx(plain, abs=1e-5)
    big = 1e5
    Tb = rrm.steady_temperature(t210, compound, V, Fz, Ta, rr=rr, conductance=big)
    assert Tb - Ta == pytest.approx(Q(Ta) / big, rel=1e-3)


def test_iso28580_at_thermal_equilibrium(tire, compound, rr):
    """The ISO RRC with the warm-up is the whole tire's at its equilibrium tread temperature at
    25 C ambient (the balance holds there); the isothermal change per K at 25 C is the same
    with and without the warm-up."""
    iso = rrm.iso28580(tire, compound)
    t210 = replace(tire, patch=replace(tire.patch, p_inflation=rr.iso_inflation))
    res = rrm.rolling_resistance(t210, compound, rrm.ISO_SPEED, iso.load_N, iso.T_tire_K,
                                 rr=rr)
    G = tire.thermal.conductance
    assert abs(G * (iso.T_tire_K - iso.T_K) - float(res.tread_share * res.heat_rate)) < G * 1e-5
    assert iso.T_tire_K > iso.T_K + 10.0
    assert iso.rrc_N_per_kN == pytest.approx(1000 * float(res.f_r), rel=1e-12)
    assert iso.label_class == rrm.eu_label_class(iso.rrc_N_per_kN)
    # the ambient's change per K: the tire follows the ambient by less than one to one
    cold = rrm.iso28580(tire, compound, warm_up=False)
    assert cold.per_K == cold.per_K_isothermal == iso.per_K_isothermal


def test_series_loading_needs_the_belt_width():
    with pytest.raises(InputError, match="belt width"):
        rrm.RollingResistanceParams(
            tread_depth=0.008, tread_support="winkler", deflection_energy_share=0.3,
            carcass_loss_tangent=0.1, carcass_reference_frequency=1.0,
            carcass_reference_temperature=300.0, carcass_loss_slope=0.1, carcass_T_g=213.0,
            tread_loading="series")
    with pytest.raises(InputError, match="series"):
        rrm.RollingResistanceParams(
            tread_depth=0.008, tread_support="winkler", deflection_energy_share=0.3,
            carcass_loss_tangent=0.1, carcass_reference_frequency=1.0,
            carcass_reference_temperature=300.0, carcass_loss_slope=0.1, carcass_T_g=213.0,
            tread_loading="strain")
