"""The relaxation spectrum of several log-normal components (lookup.modulus.LogNormalSpectrum):
its limits, positivity, Kramers-Kronig consistency, the loss-area sum rule, the closed forms
it reduces to, and its TOML layout.

References: Ferry, *Viscoelastic Properties of Polymers*, 3rd ed., ch. 3-4 (spectra, the
moduli they give); Tschoegl, *The Phenomenological Theory of Linear Viscoelastic Behavior*
(1989), ch. 4 (causality, Kramers-Kronig relations). The review's sign convention: E = E_R -
i E_I with E_I >= 0 for omega > 0 (docs/review-notes.md, Trap 1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lookup.compound import load_compound
from lookup.modulus import LogNormalSpectrum, Prony, SingleRelaxation, TabulatedMasterCurve
from tirefric.errors import InputError

#: A two-component spectrum of tread-compound size: a glass transition of 2 GPa and a broad
#: rubbery-side component of 33 MPa (the shape of the shipped summer compound, written out).
TWO = LogNormalSpectrum(3.9e6, [1.96e9, 33.1e6], [6.84e-10, 3.38e-6], [1.49, 3.5], 4)


def kramers_kronig_storage(m, omega: float, per_decade: int = 200,
                           decades: tuple[float, float] = (-30.0, 30.0)) -> float:
    r"""E_R(omega) from the loss modulus alone, by the Kramers-Kronig relation.

    For a causal response with time dependence e^{-i w t} (the review's eq. 3),
    :math:`E_R(\omega) = E_R(\infty) - \frac{2}{\pi} P\!\int_0^\infty
    \frac{u E_I(u)}{u^2 - \omega^2} du` (Tschoegl 1989, ch. 4). The principal value is removed
    by subtracting omega E_I(omega) (whose principal-value integral against 1/(u^2 - w^2)
    vanishes); the rest is integrated with the trapezoidal rule in ln u, which converges
    geometrically for this smooth integrand. E_R(infinity) is the glassy modulus."""
    s = np.linspace(decades[0], decades[1], int((decades[1] - decades[0]) * per_decade) + 1)
    s = (s + 0.37 / per_decade) * np.log(10.0)  # no node on u = omega
    u = np.exp(s)
    fu = m.storage_loss(u)[1]
    fw = m.storage_loss(np.array([omega]))[1][0]
    g = u * (u * fu - omega * fw) / (u * u - omega * omega)
    return float(m.storage_loss(np.array([1e40]))[0][0] - 2.0 / np.pi * np.trapezoid(g, s))


def test_one_component_is_prony_lognormal_bit_for_bit() -> None:
    """One component gives exactly the arms (and so the moduli) of Prony.lognormal."""
    w = np.logspace(-40, 40, 3201)
    for E_inf, E_g, tau, width, apd in [(10e6, 2e9, 1e-10, 1.8, 2), (8e6, 1.5e9, 1e-12, 1.8, 2),
                                        (10e6, 3e9, 1e-7, 2.0, 2), (5e6, 1e9, 3.3e-5, 1.37, 3)]:
        ref = Prony.lognormal(E_inf, E_g, tau, width, apd)
        got = LogNormalSpectrum(E_inf, [E_g - E_inf], [tau], [width], apd)
        assert np.array_equal(got.prony.E_k, ref.E_k) and np.array_equal(got.prony.tau_k,
                                                                            ref.tau_k)
        for a, b in zip(got.storage_loss(w), ref.storage_loss(w), strict=True):
            assert np.array_equal(a, b), "single log-normal unchanged bit for bit"


def test_components_add_their_arms() -> None:
    """Several components: the Prony series is the union of each component's arms, so the
    moduli add (to round-off)."""
    a = LogNormalSpectrum(1.0, [1.96e9], [6.84e-10], [1.49], 4)
    b = LogNormalSpectrum(1.0, [33.1e6], [3.38e-6], [3.5], 4)
    w = np.logspace(-8, 14, 221)
    ER, EI = TWO.storage_loss(w)
    ERa, EIa = a.storage_loss(w)
    ERb, EIb = b.storage_loss(w)
    np.testing.assert_allclose(ER, 3.9e6 + (ERa - 1.0) + (ERb - 1.0), rtol=1e-12)
    np.testing.assert_allclose(EI, EIa + EIb, rtol=1e-12)
    assert TWO.prony.E_k.sum() == pytest.approx(1.96e9 + 33.1e6, rel=1e-14)


def test_limits_rubbery_and_glassy() -> None:
    """E_R -> E_inf (rubbery) and E_inf + sum Delta E (glassy); E_I -> 0 at both ends, as
    omega and 1/omega (the terminal and glassy asymptotes of any Prony series, Ferry ch. 3).
    Tolerances: the arms span 1e-20 ... 1e9 s (+-4 widths of each component), so 1e-18 and
    1e30 rad/s lie decades outside the spectrum (relative remainders < 1e-9)."""
    ER, EI = TWO.storage_loss(np.array([1e-18, 1e-17, 1e30, 1e31]))
    assert ER[0] == pytest.approx(3.9e6, rel=1e-9)
    assert ER[2] == pytest.approx(TWO.E_glassy, rel=1e-9)
    assert TWO.E_glassy == pytest.approx(3.9e6 + 1.96e9 + 33.1e6, rel=1e-15)
    assert EI[1] / EI[0] == pytest.approx(10.0, rel=1e-6), "E_I ~ omega below the spectrum"
    assert EI[2] / EI[3] == pytest.approx(10.0, rel=1e-6), "E_I ~ 1/omega above it"


def test_absurd_reduced_frequencies_stay_finite() -> None:
    """A shift factor continued far below its range (WLF's linear continuation near T_ref -
    C2) can ask for omega ~ 1e200 rad/s: the moduli are the glassy limit, without overflow."""
    with np.errstate(all="raise"):
        ER, EI = TWO.storage_loss(np.array([1e200, -1e200, 1e300]))
    np.testing.assert_allclose(ER, TWO.E_glassy, rtol=1e-12)
    assert (np.abs(EI) < 1e-80).all() and EI[0] > 0 > EI[1]


def test_loss_positive_and_storage_rising() -> None:
    """Positive arms: E_I > 0 for omega > 0 (odd in omega, docs/review-notes.md Trap 1) and
    E_R rises monotonically with frequency."""
    w = np.logspace(-12, 18, 3001)
    ER, EI = TWO.storage_loss(w)
    assert (EI > 0).all()
    assert (np.diff(ER) > 0).all()
    ERm, EIm = TWO.storage_loss(-w)
    np.testing.assert_array_equal(EIm, -EI)
    np.testing.assert_array_equal(ERm, ER)


def test_kramers_kronig_consistent() -> None:
    """E_R computed from E_I alone by the Kramers-Kronig relation equals the model's E_R.

    Measured agreement 1e-13; asserted 1e-9 (the quadrature's error, not the model's). The
    same check fails for a curve that is not causal: doubling E'' of a tabulated copy of the
    spectrum moves the reconstructed E' by tens of percent."""
    for w in (1e-6, 1e-2, 1.0, 1e3, 1e6, 1e9, 1e12):
        ER = TWO.storage_loss(np.array([w]))[0][0]
        assert kramers_kronig_storage(TWO, w) == pytest.approx(ER, rel=1e-9), f"w = {w:g}"
    grid = np.logspace(-40, 40, 3201)
    ER, EI = TWO.storage_loss(grid)
    broken = TabulatedMasterCurve(grid, ER, 2.0 * EI)
    w = 1e6
    assert abs(kramers_kronig_storage(broken, w) / ER[np.searchsorted(grid, w)] - 1) > 0.1


def test_loss_area_sum_rule() -> None:
    r"""Closed form: :math:`\int_{-\infty}^{\infty} E_I\, d\ln\omega = (\pi/2)\sum_i \Delta E_i`
    (each Maxwell arm contributes E_k pi/2; Ferry ch. 3, the relaxation strength as the area of
    the loss peak). Trapezoid in ln omega over 60 decades: measured 1e-15, asserted 1e-10."""
    s = np.linspace(-30.0, 30.0, 60 * 200 + 1) * np.log(10.0)
    EI = TWO.storage_loss(np.exp(s))[1]
    assert np.trapezoid(EI, s) == pytest.approx(np.pi / 2 * (1.96e9 + 33.1e6), rel=1e-10)


def test_narrow_component_is_the_single_relaxation_solid() -> None:
    """Closed form of eq. (4): a component much narrower than the arm spacing, centred on an
    arm, is one Maxwell arm, i.e. the standard linear solid E0 = E_inf, E1 = E_inf + Delta E,
    with eq. (4)'s tau = tau_arm E1/E0 (docs/review-notes.md: tau' = tau E0/E1)."""
    E0, dE, tau_arm = 5e6, 1e9, 1e-4
    m = LogNormalSpectrum(E0, [dE], [tau_arm], [1e-3], 4)
    ref = SingleRelaxation(E0, E0 + dE, tau_arm * (E0 + dE) / E0)
    w = np.logspace(-2, 10, 121)
    for a, b in zip(m.storage_loss(w), ref.storage_loss(w), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12)


def test_arm_density_converges() -> None:
    """4 arms per decade sample the continuous spectrum: the moduli agree with 32 arms per
    decade to 1 % in E_I and 0.1 % in E_R (a log-normal of 1.5 decades is smooth on a quarter
    decade; measured 0.03 % and 0.005 %)."""
    fine = LogNormalSpectrum(3.9e6, [1.96e9, 33.1e6], [6.84e-10, 3.38e-6], [1.49, 3.5], 32)
    w = np.logspace(-6, 14, 401)
    np.testing.assert_allclose(TWO.storage_loss(w)[0], fine.storage_loss(w)[0], rtol=1e-3)
    np.testing.assert_allclose(TWO.storage_loss(w)[1], fine.storage_loss(w)[1], rtol=1e-2)


@pytest.mark.parametrize("kwargs,field", [
    ({"E_inf": -1.0}, "E_inf"),
    ({"strengths": [1e9, -1e6]}, "strength"),
    ({"tau_centers": [1e-9, 0.0]}, "tau_center"),
    ({"widths": [1.5, np.nan]}, "width_decades"),
    ({"strengths": [1e9]}, "modulus"),
])
def test_bad_spectrum_refused(kwargs, field) -> None:
    args = {"E_inf": 3.9e6, "strengths": [1.96e9, 33.1e6], "tau_centers": [6.84e-10, 3.38e-6],
            "widths": [1.49, 3.5]}
    args.update(kwargs)
    with pytest.raises(InputError, match=field):
        LogNormalSpectrum(**args)


# -- the TOML layout (lookup/compound.py) ---
COMPOUND = """name = "two_components"
[modulus]
T_ref = "20 degC"
model = "prony"
spectrum = "lognormal"
E_inf = "3.9 MPa"
arms_per_decade = 4
[[modulus.component]]
name = "alpha"
strength = "1.96 GPa"
tau_center = 6.84e-10
width_decades = 1.49
[[modulus.component]]
name = "rubbery"
strength = "33.1 MPa"
tau_center = 3.38e-6
width_decades = 3.5
[shift]
model = "wlf"
C1 = 9.316
C2 = 96.6
T_ref = "20 degC"
"""


def test_toml_components_load(tmp_path: Path) -> None:
    p = tmp_path / "c.toml"
    p.write_text(COMPOUND)
    c = load_compound(p)
    assert isinstance(c.modulus, LogNormalSpectrum)
    assert c.modulus.names == ("alpha", "rubbery")
    w = np.logspace(-6, 14, 41)
    for a, b in zip(c.modulus.storage_loss(w), TWO.storage_loss(w), strict=True):
        assert np.array_equal(a, b), "the file gives the spectrum written out above"
    d = c.modulus.describe()
    assert d["model"] == "lognormal_spectrum" and len(d["components"]) == 2
    assert d["E_glassy_Pa"] == pytest.approx(TWO.E_glassy, rel=1e-15)


@pytest.mark.parametrize("old,new,field,msg", [
    ('strength = "33.1 MPa"', 'strength = "-33.1 MPa"', "modulus.component[1].strength",
     "must be > 0"),
    ("width_decades = 3.5", "width_decades = 3.5\nwidth = 2", "modulus.component[1].width",
     "unknown field"),
    ('E_inf = "3.9 MPa"', 'E_inf = "3.9 MPa"\nE_glassy = "2 GPa"', "modulus.E_glassy",
     "single-component form"),
    ("tau_center = 6.84e-10", 'tau_center = "6.84e-10 m"', "modulus.component[0].tau_center",
     "unit"),
    ("arms_per_decade = 4", "arms_per_decade = 0", "modulus.arms_per_decade", ">= 1"),
])
def test_toml_component_errors_name_the_field(tmp_path: Path, old, new, field, msg) -> None:
    assert old in COMPOUND
    p = tmp_path / "c.toml"
    p.write_text(COMPOUND.replace(old, new, 1))
    with pytest.raises(InputError, match=msg) as err:
        load_compound(p)
    assert str(p) in str(err.value) and field in str(err.value), str(err.value)
