"""The vertical spring of the carcass term (tire_brush.rolling_resistance.deflection,
structure_energy): the MF 6.1/6.2 load-deflection law, checked against the law written out
here, its stiffness at the nominal load, its work by quadrature, the linear limit, and what
it does to the carcass term (docs/rolling.md)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tire_brush import rolling_resistance as rrm
from tire_brush.params import load_tire
from tirefric.errors import InputError

MODELS = Path(__file__).resolve().parents[1] / "models"


@pytest.fixture(scope="module")
def tire():
    return load_tire(MODELS / "tires" / "passenger.toml")


@pytest.fixture(scope="module")
def rr(tire):
    return rrm.load_rolling_params(tire)


def _mf_Fz(t, q2, rho):
    """Pacejka 2012 eq. (A3.3) (flat road, free rolling, no camber, speed or horizontal
    forces) with the pressure factor of MF 6.2, q_Fz1 from C_z (MFeval, FITTYP 61/62)."""
    p = t.patch
    q1 = math.sqrt((p.C_z * p.R0 / t.Fz_nom) ** 2 - 4 * q2)
    xi = rho / p.R0
    return (1 + p.p_fz1 * (p.p_inflation - p.p_nom) / p.p_nom) * t.Fz_nom * (q1 * xi + q2 * xi**2)


def test_shipped_tire_uses_the_mf_example_q_fz2(rr):
    """The passenger file carries the MF 6.2 example tire's Q_FZ2 (its provenance)."""
    assert rr.q_fz2 == 15.416


@pytest.mark.parametrize("p", [210e3, 230e3, 250e3])
def test_deflection_solves_the_mf_law(tire, rr, p):
    """rho(Fz) put back into the MF law gives Fz (1e-12: the root's rounding only)."""
    t = replace(tire, patch=replace(tire.patch, p_inflation=p))
    for Fz in (100.0, 2000.0, 4825.0, 9000.0):
        rho = rrm.deflection(t, rr, Fz)
        assert rho > 0
        assert _mf_Fz(t, rr.q_fz2, rho) == pytest.approx(Fz, rel=1e-12)
    assert rrm.deflection(t, rr, 0.0) == 0.0


def test_stiffness_is_C_z_at_the_nominal_load_and_progressive(tire, rr):
    """C_z is the slope dFz/drho at Fz_nom and p_nom (central difference, 1e-7: its
    truncation at a step of 1 N is ~(1/4000)^2); below it the spring is softer, above it
    stiffer (q_fz2 > 0); without q_fz2 the spring is linear, rho = Fz/C_z' exactly."""
    assert tire.patch.p_inflation == tire.patch.p_nom
    F0, h = tire.Fz_nom, 1.0
    slope = 2 * h / (rrm.deflection(tire, rr, F0 + h) - rrm.deflection(tire, rr, F0 - h))
    assert slope == pytest.approx(tire.patch.C_z, rel=1e-7)
    for Fz in (1000.0, 8000.0):
        d = 1.0
        k = 2 * d / (rrm.deflection(tire, rr, Fz + d) - rrm.deflection(tire, rr, Fz - d))
        assert (k < tire.patch.C_z) if Fz < F0 else (k > tire.patch.C_z)
    lin = replace(rr, q_fz2=0.0)
    for p in (210e3, 250e3):
        t = replace(tire, patch=replace(tire.patch, p_inflation=p))
        assert rrm.deflection(t, lin, 4825.0) == pytest.approx(
            4825.0 / t.patch.vertical_stiffness, rel=1e-14)


@pytest.mark.parametrize("p", [210e3, 250e3])
def test_structure_energy_is_the_structural_springs_work(tire, rr, p):
    """U_s = chi x the work of the law at p_nom up to rho (the structural spring does not
    change with the pressure), by Simpson's rule on 2001 points (1e-9: a cubic is exact up to
    rounding); on the linear spring it is structure_share x Fz^2/(2 C_z') (1e-12)."""
    t = replace(tire, patch=replace(tire.patch, p_inflation=p))
    t_nom = replace(tire, patch=replace(tire.patch, p_inflation=tire.patch.p_nom))
    for Fz in (2000.0, 4825.0, 8000.0):
        rho = rrm.deflection(t, rr, Fz)
        r = np.linspace(0.0, rho, 2001)
        f = _mf_Fz(t_nom, rr.q_fz2, r)
        work = (r[1] - r[0]) / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())
        assert rrm.structure_energy(t, rr, Fz) == pytest.approx(
            rr.deflection_energy_share * work, rel=1e-9)
        lin = replace(rr, q_fz2=0.0)
        Cz = t.patch.vertical_stiffness
        assert rrm.structure_energy(t, lin, Fz) == pytest.approx(
            rrm.structure_share(t, lin) * Fz**2 / (2 * Cz), rel=1e-12)


def test_progressive_spring_stores_work_more_slowly_than_Fz_squared(tire, rr):
    """Over 0.5-1.2 x the load-index load the work of the linear spring grows as Fz^2 and the
    MF spring's more slowly (its local exponent d ln Fz/d ln rho is above 1 there)."""
    lo, hi = 0.5 * rr.load_index_load, 1.2 * rr.load_index_load
    lin = replace(rr, q_fz2=0.0)
    k_lin = math.log(rrm.structure_energy(tire, lin, hi) / rrm.structure_energy(tire, lin, lo))
    k_mf = math.log(rrm.structure_energy(tire, rr, hi) / rrm.structure_energy(tire, rr, lo))
    assert k_lin / math.log(hi / lo) == pytest.approx(2.0, rel=1e-12)
    assert k_mf / math.log(hi / lo) < 1.95


def test_carcass_term_follows_the_structure_energy(tire, rr):
    """On the footprint pulse (its shape does not depend on rho) and without the belt, the
    carcass part is 2 U_s/(R_e Fz) x sum n w_n eta: the MF spring changes it by the ratio of
    the works (1e-12)."""
    law = replace(rr, carcass_pulse="footprint", belt_bending_stiffness=0.0)
    lin = replace(law, q_fz2=0.0)
    for Fz in (2000.0, 4825.0, 8000.0):
        f_mf = float(rrm.carcass_coefficient(tire, law, Fz, np.array(20.0), np.array(300.0)))
        f_lin = float(rrm.carcass_coefficient(tire, lin, Fz, np.array(20.0), np.array(300.0)))
        ratio = rrm.structure_energy(tire, law, Fz) / rrm.structure_energy(tire, lin, Fz)
        assert f_mf / f_lin == pytest.approx(ratio, rel=1e-12)


def test_bad_q_fz2_is_refused(tire, rr):
    """Negative, or so large that q_Fz1 would be imaginary: an InputError naming the field."""
    with pytest.raises(InputError, match="q_fz2"):
        replace(rr, q_fz2=-1.0)
    c = tire.patch.C_z * tire.patch.R0 / tire.Fz_nom
    with pytest.raises(InputError, match="q_fz2"):
        rrm.deflection(tire, replace(rr, q_fz2=c * c / 4 + 1.0), 4000.0)
