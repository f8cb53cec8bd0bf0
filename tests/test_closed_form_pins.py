"""Closed forms that pin two formulas no other test held: the q1 rule and the road's share of
the heat.

Each test computes its reference from first principles here, sharing no code with the
engine, and fails when the formula it pins is changed (``tests/mutations.py`` plants those
changes: "q1 rule: ..." and "road heat partition: ...").
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import make_compound

from lookup.compound import RubberThermal
from lookup.flash_temperature import heat_kernel, lateral_factor
from lookup.friction import EngineSettings, PerssonFriction
from lookup.roughness import CutoffRule, SelfAffinePSD, TabulatedPSD
from lookup.surface import RoadThermal, Surface


# -- the q1 rule: xi(q1) = xi1 ---------------------------------------------------------------
def q1_closed_form(q0: float, q_r: float, H: float, C0: float, xi1: float) -> float:
    r"""The wavenumber where the rms slope of a self-affine spectrum with roll-off reaches xi1.

    The spectrum is C = C0 for q0 <= q < q_r and C = C0 (q/q_r)^{-2(1+H)} above (review
    sec. 4). The cumulative mean-square slope is xi^2(q) = 2 pi int_{q0}^{q} q'^3 C(q') dq'
    (review sec. 4; docs/review-notes.md, Trap 4). On the plateau

        xi^2(q) = 2 pi C0 (q^4 - q0^4) / 4 = (pi C0 / 2) (q^4 - q0^4),

    so xi^2(q_r) = (pi C0 / 2)(q_r^4 - q0^4) =: xi_r^2. Above the roll-off
    q'^3 C = C0 q_r^{2+2H} q'^{1-2H}, whose integral from q_r to q is
    C0 q_r^{2+2H} (q^{2-2H} - q_r^{2-2H}) / (2 - 2H):

        xi^2(q) = xi_r^2 + (pi C0 / (1 - H)) q_r^{2+2H} (q^{2-2H} - q_r^{2-2H}).

    Solving xi(q1) = xi1: if xi1^2 <= xi_r^2, q1 = (q0^4 + 2 xi1^2 / (pi C0))^{1/4}; else

        q1 = [q_r^{2-2H} + (1 - H)(xi1^2 - xi_r^2) / (pi C0 q_r^{2+2H})]^{1/(2-2H)}.
    """
    xi_r2 = 0.5 * math.pi * C0 * (q_r**4 - q0**4)
    if xi1**2 <= xi_r2:
        return (q0**4 + 2.0 * xi1**2 / (math.pi * C0)) ** 0.25
    e = 2.0 - 2.0 * H
    return (q_r**e + (1.0 - H) * (xi1**2 - xi_r2) / (math.pi * C0 * q_r ** (2 + 2 * H))) ** (1 / e)


CASES = [  # (q0, q_r, H, h_rms, xi1): without roll-off, and with q1 on the plateau or beyond it
    (1e3, 1e3, 0.8, 1e-4, 1.0),
    (1e3, 1e3, 0.6, 3e-4, 0.5),
    (2e2, 3e3, 0.85, 5e-4, 1.0),  # xi_r = 0.36: q1 on the self-affine tail
    (2e2, 3e3, 0.85, 5e-4, 0.2),  # q1 on the plateau
]


@pytest.mark.parametrize("q0,q_r,H,h_rms,xi1", CASES)
def test_q1_rule_closed_form_self_affine(q0, q_r, H, h_rms, xi1) -> None:
    """The rule on the analytic spectrum: the bisection in log q reaches machine precision
    (60 halvings of a bracket one grid step wide), so 1e-9 relative."""
    psd = SelfAffinePSD.from_h_rms(q0, q_r, H, h_rms)
    want = q1_closed_form(q0, q_r, H, psd.C0, xi1)
    assert (want <= q_r) == (xi1**2 <= 0.5 * math.pi * psd.C0 * (q_r**4 - q0**4))
    assert CutoffRule("rms_slope", xi1).resolve(psd) == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize("q0,q_r,H,h_rms,xi1", CASES)
def test_q1_rule_closed_form_tabulated(q0, q_r, H, h_rms, xi1) -> None:
    """The same spectrum as a measured table (log-log interpolation reproduces its power-law
    pieces exactly, q_r is a table point): the rule integrates xi^2 numerically (trapezoid in
    ln q, 200 points per decade). Its relative error in xi^2 is h^2 n^2 / 12 for an integrand
    ~ q^n in ln q (n <= 4 on the plateau, h = ln 10 / 200): <= 2e-4, i.e. <= 5e-5 in q1
    (d ln xi^2 / d ln q >= 2 - 2H = 0.3 here: <= 7e-4), plus the linear interpolation of
    xi^2 between the nodes (same order); 1e-3 relative."""
    psd = SelfAffinePSD.from_h_rms(q0, q_r, H, h_rms)
    q = np.unique(np.concatenate([np.geomspace(q0, q_r, 41), np.geomspace(q_r, 1e9, 201)]))
    tab = TabulatedPSD(q, psd.C(q))
    want = q1_closed_form(q0, q_r, H, psd.C0, xi1)
    assert CutoffRule("rms_slope", xi1).resolve(tab) == pytest.approx(want, rel=1e-3)


# -- heat partition between rubber and road -------------------------------------------------
RUBBER = (1500.0, 1500.0, 0.3)  # rho [kg/m^3], c_v [J/(kg K)], kappa [W/(m K)]
ROADS = [(1.0, 2300.0, 900.0), (2.5, 2600.0, 800.0), (0.1, 1000.0, 1000.0)]  # kappa, rho, c


def engine(road: tuple[float, float, float] | None, road_heat: bool = True
           ) -> PerssonFriction:
    comp = make_compound()
    comp = type(comp)(comp.name, comp.modulus, comp.T_ref, comp.shift, comp.softening,
                      comp.strain, comp.adhesion, comp.nu, RubberThermal(*RUBBER))
    psd = SelfAffinePSD.from_h_rms(1e3, 1e3, 0.8, 1e-4)
    surf = Surface("test", psd, CutoffRule("fixed", q1=1e6), 1e-3,
                   None if road is None else RoadThermal(*road))
    return PerssonFriction(comp, surf, EngineSettings(road_heat=road_heat))


def effusivity(kappa: float, rho: float, c: float) -> float:
    """e = sqrt(kappa rho c) [W s^0.5 / (m^2 K)]."""
    return math.sqrt(kappa * rho * c)


@pytest.mark.parametrize("road", ROADS)
def test_road_takes_its_effusivity_share_of_a_surface_flux(road) -> None:
    r"""Two half-spaces in perfect contact (rubber and road, effusivities e_r, e_s) heated by a
    flux W at their interface: both see the same surface temperature, which for a half-space
    heated by a flux q_i is 2 q_i sqrt(t / pi) / e_i (Carslaw & Jaeger, *Conduction of Heat
    in Solids*, 2nd ed., ch. II: semi-infinite solid, constant surface flux); equal
    temperatures split W as q_i ~ e_i, so the road takes

        q_s / W = e_s / (e_r + e_s)

    and the surface temperature is T(t) = 2 W sqrt(t / pi) / (e_r + e_s); averaged over the
    contact time t_c it is (4 / (3 sqrt pi)) W sqrt(t_c) / (e_r + e_s).

    Checked on the engine's own kernel (its effusivities, image strength and thermal data):
    the surface temperature per unit surface flux, against the closed form (the kernel's
    time quadrature: 1e-3, as in tests/test_persson_engine.py); the rubber's share of the
    heat, against the same kernel without the road (the surface term scales with the rubber's
    share exactly: 1e-12); and the heat stored in the rubber, by depth quadrature (4000
    log-spaced depths: 2e-3)."""
    e_r, e_s = effusivity(RUBBER[2], RUBBER[0], RUBBER[1]), effusivity(*road)
    road_share = e_s / (e_r + e_s)
    m = engine(road)
    v = 0.3
    t_c = m.D / v
    K = m._kernel(v)[0, 0] / lateral_factor(v * m.D / m.D_th)  # surface flux, at the surface
    assert K == pytest.approx(4.0 / (3.0 * math.sqrt(math.pi)) * math.sqrt(t_c) / (e_r + e_s),
                              rel=1e-3)
    insulated = engine(road, road_heat=False)._kernel(v)[0, 0] / lateral_factor(
        v * m.D / m.D_th)
    assert 1.0 - K / insulated == pytest.approx(road_share, rel=1e-12)
    z = np.concatenate([[0.0], np.geomspace(1e-10, 0.05, 4000)])
    Kz = heat_kernel(z, np.array([np.inf]), t_c, m.D_th, m.rho_c, m.R_image)[:, 0]
    stored = m.rho_c * np.trapezoid(Kz, z) / (t_c / 2)  # per unit power over t_c
    assert 1.0 - stored == pytest.approx(road_share, rel=2e-3)


def test_without_road_data_the_rubber_keeps_all_heat() -> None:
    """No road thermal data: an insulated interface (image strength 1), the rubber keeps all
    of a surface flux; the same when the road's share is switched off."""
    for m in (engine(None), engine(ROADS[0], road_heat=False)):
        assert m.R_image == 1.0


def test_heat_kernel_is_shared_by_what_it_is_computed_from():
    """Engines of one process share a heat kernel (lookup.friction._SHARED_KERNELS) only when
    everything it is computed from agrees: a second engine of the same road and rubber
    thermal data gets the first one's array, equal bit for bit to the kernel computed afresh
    (heat_kernel and the lateral factor); another image strength (no road heat), or another
    rubber diffusivity, gets its own."""
    import lookup.friction as fr

    road = (1.0, 2000.0, 900.0)
    v = 0.7
    a, b = engine(road), engine(road)
    Ka = a._kernel(v)
    assert b._kernel(v) is Ka
    fresh = heat_kernel(a.z_eval, a.a_src, a.D / v, a.D_th, a.rho_c, a.R_image,
                        fr.HeatKernelSettings(a.settings.tau_per_decade)) * lateral_factor(
        v * a.D / a.D_th)
    assert np.array_equal(Ka, fresh)
    other = engine(road, road_heat=False)
    assert not np.array_equal(other._kernel(v), Ka)
    hotter = engine(road)
    hotter.D_th = 2.0 * a.D_th          # before its first kernel: part of the key
    assert not np.array_equal(hotter._kernel(v), Ka)
