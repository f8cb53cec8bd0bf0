"""The contact age of a tread element (docs/tire-core.md, "contact age"): the ageing law of
rate-and-state friction (J.H. Dieterich, J. Geophys. Res. 84 (1979) 2161; A. Ruina, J.
Geophys. Res. 88 (1983) 10359), ``d theta/dt = 1 - |w| theta / D``, with the grid's friction
read at ``v_eff = D / theta`` (our closure, ``D = s0 / 0.2``).

Closed forms on a table that is linear in log10 v (the table's own interpolation is then exact):

* steady sliding at V: ``theta -> D / V`` and the friction -> ``mu(V)``, the table's;
* at rest for a time t from entry: ``theta = t`` (linear: the SDIRK stages integrate it
  exactly) and the stick limit is ``p mu(D / t)``;
* after a step of the sliding speed to V2: ``theta = D/V2 + (theta0 - D/V2) exp(-s/D)`` over
  the slipped distance s.

And the core equals its Python mirror with the law on; the state carries the age.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from brush_cases import T20, passenger, with_contact_age

from lookup.grid.store import load_grid
from tire_brush import element as ref_core
from tire_brush.friction import ConstantFriction
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire
from tirefric.errors import InputError

S0 = 2e-4                  # blending length of eq. (28) [m]
D = S0 / 0.2               # contact-age length [m]
P_GROSS = 3e5              # pressure [Pa]
LV = [-6.0 + k for k in range(9)]   # log10 v nodes, 1 um/s .. 100 m/s


def _mu_cold(v: float) -> float:
    return 1.0 - 0.05 * math.log10(v)


def _mu_hot(v: float) -> float:
    return 0.8 - 0.08 * math.log10(v)


def _table() -> ref_core.RefTable:
    vals = np.zeros((len(LV), 2, 2, 3))
    for i, lv in enumerate(LV):
        vals[i, :, :, 0] = _mu_cold(10.0 ** lv)
        vals[i, :, :, 1] = _mu_hot(10.0 ** lv)
    return ref_core.RefTable(LV, [200.0, 500.0], [3.0, 8.0], vals, 1.0 / S0)


class _P:
    """One element on an almost rigid spring: the tip moves with its base when sliding."""
    k_x = k_y = 1e14
    d_x = d_y = 0.0
    mass = 0.0
    void_ratio = 0.0
    tol = 1e-4
    contact_ageing = 1


def _ctx(V: float, ageing: int = 1) -> ref_core.Ctx:
    P = type("P", (_P,), {"contact_ageing": ageing})
    # Fz = 2 p on a unit patch: tol_abs = tol p, the tolerance relative to the pressure
    c = ref_core.Ctx(P, _table(), 300.0, 2.0 * P_GROSS, 1.0, 1.0, 0.0, P_GROSS, 1.0, V, 0.0, 0.0)
    c.c_flat = math.inf                   # uniform pressure
    return c


def test_steady_sliding_reads_the_tables_friction() -> None:
    """Sliding at a constant V from a fresh contact for 40 D: theta = D / V (the residual
    exp(-40) is far below the 1e-6 tolerance, which is the integrator's) and the friction is
    the table's hot branch at V (the cold weight exp(-s/s0) is exp(-200))."""
    for V in (3e-3, 0.5, 20.0):
        c = _ctx(V)
        e = [0.0, 0.0, V, 0.0, 0.0, 0.0, 1.0, 0.0]
        r = ref_core.integrate(c, e, 0.0, 40.0 * D / V)
        assert c.D == pytest.approx(D, rel=1e-15)
        assert e[7] == pytest.approx(D / V, rel=1e-6), "steady age D / V"
        assert r[2] == pytest.approx(P_GROSS * _mu_hot(V), rel=1e-6), "steady friction mu(V)"


def test_stick_limit_after_rest_is_mu_at_D_over_t() -> None:
    """An element at rest from entry for a time t: its age is t (to rounding: theta' = 1 is
    integrated exactly), and a stage of 1e-15 s holds a spring force just below
    p mu_cold(D / t) and slides just above it (margins 1e-6, beyond the 1e-12 shift of
    v_eff by the stage's own length). Without the law the limit is mu at the first node."""
    k = _P.k_x
    for t_rest in (1e-4, 1e-2, 1.0):
        c = _ctx(0.0)
        e = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        ref_core.integrate(c, e, 0.0, t_rest)
        assert e[7] == pytest.approx(t_rest, rel=1e-12), "age at rest = time"
        limit = P_GROSS * _mu_cold(D / t_rest)
        held = ref_core.stage(c, 1e-15, P_GROSS, 0.0, -(1.0 - 1e-6) * limit / k, 0.0, 0.0, 0.0,
                              0.0, e[7], 0.0)
        slips = ref_core.stage(c, 1e-15, P_GROSS, 0.0, -(1.0 + 1e-6) * limit / k, 0.0, 0.0,
                               0.0, 0.0, e[7], 0.0)
        assert held[5] == 0.0 and slips[5] > 0.0, f"stick limit at rest {t_rest} s"
        assert held[11] == pytest.approx(t_rest, rel=1e-12), "stuck stage ages"
    # law off: the limit is mu_cold at the first speed node (1.3), which holds the force
    # that slips an element aged 1 s (1.15)
    c = _ctx(0.0, ageing=0)
    limit0 = P_GROSS * _mu_cold(10.0 ** LV[0])
    held = ref_core.stage(c, 1e-15, P_GROSS, 0.0, -(1.0 - 1e-6) * limit0 / k, 0.0, 0.0, 0.0,
                          0.0, 1.0, 0.0)
    aged = ref_core.stage(c, 1e-15, P_GROSS, 0.0, -(1.0 + 1e-6) * limit / k, 0.0, 0.0, 0.0,
                          0.0, 1.0, 0.0)
    assert held[5] == 0.0 and aged[5] == 0.0


def test_age_relaxes_over_the_slipped_distance() -> None:
    """After a step of the sliding speed V1 -> V2 the age relaxes as
    theta = D/V2 + (theta0 - D/V2) exp(-s/D) (exact for constant V2; the tip's speed differs
    from the base's only while the 1e14 N/m^3 spring reloads, by ~1e-9 of theta). Tolerance
    1e-4 of the larger age: the local error is held to 1e-4 of the age per step (tol = 1e-4);
    over the 35-110 steps the global error measured 2e-6 to 1e-5."""
    for V1, V2 in ((0.05, 0.5), (0.5, 0.05), (1e-4, 2.0)):
        th0 = D / V1
        for n_D in (0.5, 2.0):
            c = _ctx(V2)
            e = [0.0, 0.0, V2, 0.0, 0.0, 0.0, 1.0, th0]
            ref_core.integrate(c, e, 0.0, n_D * D / V2)
            s = e[4]
            exact = D / V2 + (th0 - D / V2) * math.exp(-s / D)
            assert e[7] == pytest.approx(exact, abs=1e-4 * max(th0, D / V2)), (V1, V2, n_D)


# -- the tire with the law on --------------------------------------------------------------
@pytest.fixture(scope="module")
def grid():
    return load_grid()


def test_steady_core_equals_referencewith_contact_age(grid) -> None:
    """The steady march with the contact age on: the C core and the mirror agree (1e-10, the
    same IEEE operations)."""
    tire = with_contact_age(passenger(), True)
    kappa = np.array([-0.6, -0.06, -0.01, 0.08])
    alpha = np.array([0.0, 0.05, -0.1, 0.2])
    c = SteadyBrush(tire, grid, n_elements=16).solve(kappa, alpha, 20.0, 4000.0, 280.0)
    r = SteadyBrush(tire, grid, n_elements=16, backend="reference").solve(
        kappa, alpha, 20.0, 4000.0, 280.0)
    np.testing.assert_allclose(np.stack([c.Fx, c.Fy, c.Mz, c.mu_slide]),
                               np.stack([r.Fx, r.Fy, r.Mz, r.mu_slide]), rtol=1e-10, atol=1e-9)


def test_no_renewal_length_reads_the_slip_speed() -> None:
    """s0 = inf (a table with inv_s0 = 0: always cold, here a constant friction): there is
    no D and the law reads the friction at |w|, bit for bit the law switched off."""
    tire = passenger()
    f = ConstantFriction(1.2, 0.8, s0=math.inf)
    on = TransientBrushTire(with_contact_age(tire, True), f, n_elements=12)
    off = TransientBrushTire(with_contact_age(tire, False), f, n_elements=12)
    for k in range(30):
        u = (1e-3, 15.0, 0.3, 15.0 * (1.0 - 0.05 * (k % 4)) / tire.R_e, 4000.0, T20, 1.0)
        np.testing.assert_array_equal(on.step_array(*u), off.step_array(*u))


def test_ageing_changes_a_braking_tire(grid) -> None:
    """The switch reaches the core: at 0 C, kappa = -0.05, the force differs with the law
    (steady sliding is unchanged, the re-sticking elements are not)."""
    tire = passenger()
    out = {}
    for on in (False, True):
        tr = TransientBrushTire(with_contact_age(tire, on), grid)
        om = 10.0 * 0.95 / tire.R_e
        out[on] = np.array([tr.step_array(1e-3, 10.0, 0.0, om, 4000.0, 273.15)[0]
                            for _ in range(60)])
    assert np.abs(out[True] - out[False]).max() > 1e-3 * 4000.0


def test_state_round_trip_carries_the_age(grid) -> None:
    """get_state / set_state restore the age column bit for bit (the continued runs agree to
    the bit); a state of the previous layout, or with a negative age, is refused."""
    tire = with_contact_age(passenger(), True)
    a = TransientBrushTire(tire, grid, n_elements=20)
    om = 12.0 * 0.97 / tire.R_e
    for _ in range(40):
        a.step_array(1e-3, 12.0, 0.2, om, 4000.0, 278.15)
    st = a.get_state()
    assert st["elements"].shape[1] == 8 and st["elements"][:, 7].max() > 0.0
    b = TransientBrushTire(tire, grid, n_elements=20)
    b.set_state(st)
    for _ in range(10):
        np.testing.assert_array_equal(a.step_array(1e-3, 12.0, 0.2, om, 4000.0, 278.15),
                                      b.step_array(1e-3, 12.0, 0.2, om, 4000.0, 278.15))
    old = dict(st, version=st["version"] - 1)
    with pytest.raises(InputError):
        b.set_state(old)
    bad = dict(st, elements=st["elements"].copy())
    bad["elements"][0, 7] = -1.0
    with pytest.raises(InputError):
        b.set_state(bad)
