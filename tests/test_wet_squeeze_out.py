"""Squeeze-out on the right time scales (lookup.wet.squeeze, tire_brush.wet_friction).

* the asperity contacts' squeeze-out (Stefan's law over their lifetime, Roberts & Tabor's
  collapse thickness, Persson's pressure distribution) against an independent evaluation:
  the film thickness integrated in time from the squeeze-film ODE and the pressure
  distribution integrated by quadrature;
* the grid's dry share changes with the drainage time where the macro contact's law runs
  its course, and the tire reads it at the water film's time under the footprint at the
  entrainment speed (the core and the steady brush alike);
* friction never rises with the water depth (grid and transient tire, as in the FMU).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from brush_cases import passenger
from scipy.integrate import quad, solve_ivp

from lookup.grid import load_grid
from lookup.grid.store import resolve_grid_path
from lookup.grid.wet import load_wet
from lookup.wet.squeeze import H_COLLAPSE, asperity_dry_share, asperity_pressure_threshold
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire
from tire_brush.wet_friction import (
    WetRoad,
    WetTireFriction,
    drainage_time,
    entrainment_speed,
    wet_branch_table,
)

ETA = 1.0016e-3  # water at 20 C [Pa s]


@pytest.fixture(scope="module")
def grids():
    return load_grid("r117_wet"), load_wet(resolve_grid_path("r117_wet"))


def _film_after(t: float, sigma: float, r: float, eta: float, h0: float = 1e-3) -> float:
    """Film thickness after time t: dh/dt = -2 h^3 sigma / (3 eta r^2) (Reynolds' squeeze
    flow between a disc of radius r and a plane under the mean pressure sigma), integrated
    numerically from h0 (independent of the closed form in lookup.wet.squeeze)."""
    sol = solve_ivp(lambda _, h: -2.0 * h**3 * sigma / (3.0 * eta * r * r), (0.0, t), [h0],
                    method="LSODA", rtol=1e-10, atol=1e-14)
    return float(sol.y[0, -1])


def _pressure_density(s: float, sigma0: float, G: float) -> float:
    """Persson's distribution of the contact pressure at magnification q1 (J. Chem. Phys. 115
    (2001) 3840), written out independently."""
    c = 4.0 * G * sigma0**2
    return (math.exp(-(s - sigma0) ** 2 / c) - math.exp(-(s + sigma0) ** 2 / c)) / math.sqrt(
        math.pi * c)


@pytest.mark.parametrize("v,G", [(0.5, 40.0), (5.0, 40.0), (5.0, 400.0), (28.0, 4.0),
                                 (28.0, 4000.0), (2.0, 0.05)])
def test_asperity_share_against_the_squeeze_film_ode(v, G):
    """w_asp = share of the real contact (pressure density over sigma > 0) whose film, from a
    thick start, is below 40 nm after the contact time pi / (q1 v). The threshold pressure is
    found by bisection on the integrated film thickness, the share by quadrature; both
    independent of the closed forms. Tolerance 1e-6: the ODE and the quadrature are solved
    to 1e-10 (1e-5 for the share, see below)."""
    q1, sigma0 = 1.6e5, 2e5
    r = 0.5 * math.pi / q1
    t_c = 2.0 * r / v
    lo, hi = 1e3, 1e11  # bisection in log sigma on h(t_c; sigma) = h_c (h falls with sigma)
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        if _film_after(t_c, mid, r, ETA) > H_COLLAPSE:
            lo = mid
        else:
            hi = mid
    s_star = math.sqrt(lo * hi)
    # the closed form's threshold (h0 -> infinity) agrees with the ODE's from h0 = 1 mm
    assert float(asperity_pressure_threshold(v, ETA, q1)) == pytest.approx(s_star, rel=1e-6)
    width = 2.0 * sigma0 * math.sqrt(G)
    top = sigma0 + 40.0 * width
    total = quad(_pressure_density, 0.0, top, args=(sigma0, G), limit=400, epsabs=0,
                 epsrel=1e-12)[0]
    dry = quad(_pressure_density, min(s_star, top), top, args=(sigma0, G), limit=400,
               epsabs=0, epsrel=1e-12)[0]
    w = float(asperity_dry_share(v, ETA, q1, sigma0, G))
    # 1e-5: the quadrature of a distribution up to ~130 sigma0 wide (G = 4000) loses digits
    assert w == pytest.approx(dry / total, rel=1e-5, abs=1e-9)


def test_asperity_share_limits():
    q1, sigma0, G = 1.6e5, 2e5, 30.0
    # at rest every contact region has time: dry
    assert float(asperity_dry_share(0.0, ETA, q1, sigma0, G)) == pytest.approx(1.0, abs=1e-15)
    # falls with the sliding speed at a fixed contact state, and with the viscosity
    v = np.geomspace(1e-2, 1e2, 41)
    w = asperity_dry_share(v, ETA, q1, sigma0, G)
    assert np.all(np.diff(w) <= 0) and w[-1] < 1e-6 < w[0] - 0.99
    assert float(asperity_dry_share(5.0, 2 * ETA, q1, sigma0, G)) < float(
        asperity_dry_share(5.0, ETA, q1, sigma0, G))
    # full contact at the nominal pressure (G -> 0): all or nothing at sigma* = sigma0
    s_star = float(asperity_pressure_threshold(1.0, ETA, q1))
    assert float(asperity_dry_share(1.0, ETA, q1, 1.01 * s_star, 1e-8)) == 1.0
    assert float(asperity_dry_share(1.0, ETA, q1, 0.99 * s_star, 1e-8)) == 0.0


def test_grid_dry_share_moves_where_the_macro_law_runs(grids):
    """The grid's drainage-time axis spans the macro contact's squeeze-out (Stefan's law over
    D/2, lookup.wet.squeeze): on the wet reference road at 20 C, 0.2-0.5 MPa and a rolling
    tire's small slip speeds, w_dry rises by more than half between 0.1 us and 0.1 ms and
    is flat (within 1e-3) from 1 ms on, where a tire's footprint times lie (3-80 ms)."""
    _, wet = grids
    lv, T, lp = (wet.axes[n] for n in ("log10_v", "T", "log10_p"))
    iv = (lv >= -3.0) & (lv <= -1.0)
    iT = int(np.argmin(abs(T - 293.15)))
    ip = (10.0**lp >= 1.9e5) & (10.0**lp <= 5.1e5)
    lt = wet.axes["log10_t_drain"]
    w = wet.variables["w_dry"][1][:, iv][:, :, iT][:, :, ip]
    early, late = w[np.argmin(abs(lt + 7.0))], w[np.argmin(abs(lt + 4.0))]
    assert np.all(late - early > 0.5), (early, late)
    slow = lt >= -3.0
    assert np.all(np.ptp(w[slow], axis=0) < 1e-3)


def test_drainage_time_at_the_entrainment_speed(grids):
    """t_drain = 2a / U, U = (|vx| + |V_r|)/2: a locked wheel's film stays twice as long
    under the patch as a free-rolling one's (closed form), and the steady wet brush reads
    the branch at exactly that time."""
    dry, wet = grids
    p = passenger()
    src = WetTireFriction(p, dry, wet, WetRoad(1e-3, 7e-4, 8e-3, drainage_radius=0.02))
    a, _ = p.patch.size(4000.0)
    scale = (float(dry.meta["D_m"]) / 0.04) ** 2
    for kappa in (0.0, -0.1, -1.0):
        want = 2.0 * a / (0.5 * 20.0 * (2.0 + kappa)) * scale
        assert src.t_drain(20.0, 4000.0, kappa) == pytest.approx(want, rel=1e-12)
    assert src.t_drain(20.0, 4000.0, -1.0) == pytest.approx(2 * src.t_drain(20.0, 4000.0),
                                                            rel=1e-12)
    assert entrainment_speed(-3.0, 1.0) == 2.0
    # the blended table equals the branch table built at that drainage time
    t = src.t_drain(20.0, 4000.0, -0.3)
    direct = wet_branch_table(dry, wet, 1e-3, t)
    np.testing.assert_allclose(src.table(t).values, direct.values, rtol=1e-12, atol=1e-14)
    assert drainage_time(1e-2, 1e-3, 0.02) == pytest.approx(1e-2 / 1600.0, rel=1e-12)


def test_transient_tire_drains_at_the_entrainment_speed(grids):
    """The core's drainage time is the steady brush's 2a / U: a wheel locked at 2 m/s on 1 mm
    of water (V_r = 0, so U = vx / 2; the drainage scale puts t_drain at 1 us, where the
    macro squeeze-out acts) settles within 1 % of Fz (the transient defaults'
    convergence bound, docs/tire-core.md) on the steady brush at 2a / U; the steady brush at
    half or twice that time is more than 2 % of Fz away, and a rolling-speed time 2a / |V_r|
    (infinite here) reads the fully drained table, further still."""
    dry, wet = grids
    tire, Fz, vx, kappa = passenger(), 4000.0, 2.0, -1.0
    a, _ = tire.patch.size(Fz)
    scale = 1e-6 / (2.0 * a / (0.5 * vx))
    tr = TransientBrushTire(tire, dry)
    tr.set_wet(wet, texture_depth=7e-4, drain_scale=scale)
    fx = []
    for i in range(400):
        out = tr.step(1e-3, vx, 0.0, 0.0, Fz, 293.15, 1.0, 0.0, 1e-3)
        if i >= 300:
            fx.append(out.Fx)

    def steady(t_drain):
        b = SteadyBrush(tire, wet_branch_table(dry, wet, 1e-3, t_drain))
        return float(b.solve(kappa, 0.0, vx, Fz, float(out.T_tread)).Fx) / Fz

    t = 2.0 * a / (0.5 * vx) * scale
    got, want = float(np.mean(fx)) / Fz, steady(t)
    assert got == pytest.approx(want, abs=1e-2)
    for other in (0.5 * t, 2.0 * t, 10.0):
        assert abs(steady(other) - want) > 2e-2, other


def test_friction_never_rises_with_water_depth_on_the_grid(grids):
    """At every node (v, T, p) and drainage time, the cold wet friction at each depth is at
    most the friction at the next shallower depth (dry at 0). The hot branch is each depth's
    own flash-temperature solve: where warm rubber is past its adhesive peak (40 C, ~0.1 m/s)
    the sealed road's smaller viscoelastic heat leaves the interface cooler and the adhesive
    stress higher, by up to 1.7 % of the dry value on the previous synthetic compound's grid;
    2.5 % allows for that (on the realistic summer compound's grid it does not happen: at
    most 0.9997 of dry; docs/physics.md sec. 7a); the tire (below) never gains force from
    water."""
    _, wet = grids
    lv, T, lp = (wet.axes[n] for n in ("log10_v", "T", "log10_p"))
    V, TT, P = np.meshgrid(10.0**lv, T, 10.0**lp, indexing="ij")
    depths = np.concatenate([wet.axes["water_depth"], [2e-3, 4e-3]])
    for t in 10.0 ** wet.axes["log10_t_drain"][::3]:
        prev = None
        for d in depths:
            m = wet.interpolate(V, TT, P, d, t)
            if prev is not None:
                assert np.all(m["mu_wet_cold"] <= prev["cold"] + 1e-12), (t, d)
                assert np.all(m["mu_wet_hot"] <= 1.025 * prev["hot"]), (t, d)
            prev = {b: m[f"mu_wet_{b}"] for b in ("cold", "hot")}


def test_transient_force_never_rises_with_water_depth(grids):
    """The FMU's case of the wet-road report (braking at 27.8 m/s, kappa -0.06, 20 C, 4 kN,
    no road texture): the mean |Fx| over 0.9-1 s never rises with the water depth, from the
    dry road through the sealing (0-1 mm) to Horne's lift (above the 2.4 mm the grooves
    hold). The transient core is the FMU's (both flavours step it bit for bit,
    tests/test_wet_tire.py). Tolerance 1 % of Fz: the transient defaults' convergence bound
    (docs/tire-core.md)."""
    dry, wet = grids
    tire, Fz, vx, kappa = passenger(), 4000.0, 27.8, -0.06
    prev = math.inf
    for d in (0.0, 0.25e-3, 0.5e-3, 1e-3, 2e-3, 3e-3, 4e-3, 5e-3):
        tr = TransientBrushTire(tire, dry)
        tr.set_wet(wet, texture_depth=0.0)
        fx = []
        for i in range(1000):
            out = tr.step(1e-3, vx, 0.0, vx * (1.0 + kappa) / tire.R_e, Fz, 293.15, 1.0, 0.0,
                          d)
            if i >= 900:
                fx.append(out.Fx)
        f = -float(np.mean(fx))
        assert f <= prev + 1e-2 * Fz, (d, f, prev)
        prev = f
    assert prev == 0.0, "5 mm at 27.8 m/s hydroplanes fully (Horne: 26.8 m/s at 230 kPa)"
