"""Closed-form friction curves of tire_brush.braking.reference against brute force."""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush.braking.reference import (
    BURCKHARDT_ROADS,
    MAGIC_FORMULA_ROADS,
    Burckhardt,
    MagicFormula,
    burckhardt_road,
    magic_formula_road,
    point_mass_stopping_distance,
)
from tirefric.errors import InputError

K = -np.linspace(0.0, 1.0, 200_001)   # brute-force slip grid, step 5e-6


@pytest.mark.parametrize("road", sorted(BURCKHARDT_ROADS))
def test_burckhardt_peak_closed_form(road):
    curve = burckhardt_road(road)
    i = np.argmin(curve(K))
    if curve.c3 > 0:   # with c3 = 0 (ice) the curve saturates: no unique peak slip
        # 1e-5: twice the brute-force grid step
        assert abs(-K[i] - curve.peak_slip()) < 1e-5, f"{road}: peak slip closed form vs argmax"
    assert abs(-curve(K[i]) - curve.peak_mu()) < 1e-8, f"{road}: peak mu closed form"


@pytest.mark.parametrize("road", sorted(MAGIC_FORMULA_ROADS))
def test_magic_formula_peak(road):
    curve = magic_formula_road(road)
    i = np.argmin(curve(K))
    assert abs(-K[i] - curve.peak_slip()) < 1e-5, f"{road}: MF peak slip vs argmax"
    assert abs(curve.peak_mu() - curve.D) < 1e-9, "the MF peak equals D"


def test_curves_are_odd_and_broadcast():
    k = np.linspace(-1, 1, 11)
    for curve in (burckhardt_road("asphalt_dry", c4=0.03), magic_formula_road("asphalt_wet")):
        np.testing.assert_allclose(curve(k, 10.0), -curve(-k, 10.0), atol=1e-15,
                                   err_msg=f"{curve.name}: mu(-kappa) = -mu(kappa)")
        out = curve(k[:, None], np.array([1.0, 20.0])[None, :], 4000.0, 293.15)
        assert out.shape == (11, 2), "numpy broadcasting of the fx_over_fz signature"


def test_burckhardt_velocity_term_lowers_friction():
    c = burckhardt_road("asphalt_dry", c4=0.03)
    assert c(-0.5, 30.0) > c(-0.5, 1.0), "Fx/Fz < 0: less braking friction at higher speed"


def test_point_mass_bound():
    assert point_mass_stopping_distance(20.0, 1.0, 0.0, g=10.0) == pytest.approx(20.0)
    assert point_mass_stopping_distance(20.0, 0.5, 10.0, g=10.0) == pytest.approx(30.0)


@pytest.mark.parametrize("make", [
    lambda: Burckhardt(-1.0, 20.0, 0.5),
    lambda: Burckhardt(1.0, float("nan"), 0.5),
    lambda: MagicFormula(10.0, 1.9, 1.0, 1.5),
    lambda: burckhardt_road("moon"),
    lambda: point_mass_stopping_distance(5.0, 1.0, 6.0),
])
def test_invalid_parameters_raise(make):
    with pytest.raises(InputError):
        make()
