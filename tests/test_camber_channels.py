"""Camber, the overturning moment and the channel set of the brush tire.

The brush with camber (Pacejka 2012, ch. 3): a thin disk tilted by gamma and pressed on the
road has a base line curved with sin(gamma) / R_e, so a sticking tread element is deflected by
``(1 - eps) sin(gamma) (a^2 - x^2) / (2 R_e)`` at x, and the camber thrust is

    Fy = (2/3) c_py a^3 (1 - eps) sin(gamma) / R_e,   c_py = k_y b,

positive (adapted SAE, y right) when the top of the wheel leans to the right: the thrust acts
towards the side the wheel leans to, as MF-Tyre's camber stiffness PKY6 < 0 in ISO-W says.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from brush_cases import T20, pacejka_like, passenger

from lookup.grid import load_grid
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire
from tirefric.errors import InputError

FZ, VX = 4000.0, 20.0


@pytest.fixture(scope="module")
def grid():
    return load_grid("default")


def _with_eps(tire, eps):
    return dataclasses.replace(tire, carcass=dataclasses.replace(tire.carcass,
                                                                 camber_reduction=eps))


@pytest.mark.parametrize("eps", [0.0, 0.5])
@pytest.mark.parametrize("gamma", [0.005, -0.02])
def test_camber_thrust_is_the_brush_closed_form(grid, eps, gamma):
    """Massless, parabolic, rigid brush at small camber and no slip: the closed form above.
    No element slides (the deflection and the parabolic pressure both vanish at the edges),
    so the only error is the march's cell sampling: 1.2e-4 measured, 1e-3 allowed."""
    tire = _with_eps(pacejka_like(passenger()), eps)
    out = SteadyBrush(tire, grid, massless=True).solve(0.0, 0.0, VX, FZ, T20, gamma=gamma)
    a, b = tire.patch.size(FZ)
    closed = (2.0 / 3.0) * tire.tread.k_y * b * a ** 3 * (1.0 - eps) * math.sin(gamma) / tire.R_e
    assert out.Fy == pytest.approx(closed, rel=1e-3)
    assert np.sign(out.Fy) == np.sign(gamma), "thrust towards the side the wheel leans to"
    assert float(out.sliding_fraction) == 0.0


def test_camber_is_mirror_symmetric_and_adds_to_slip(grid):
    """gamma -> -gamma mirrors Fy, Mz and Mx exactly; small camber and slip angle add (the
    brush is linear while nothing slides): Fy(alpha, gamma) = Fy(alpha) + Fy(gamma) to 1 %
    (the carcass twist couples them through the moment, a few per mille here)."""
    tire = passenger()
    st = SteadyBrush(tire, grid)
    p, m = (st.solve(0.0, 0.0, VX, FZ, T20, gamma=g) for g in (0.02, -0.02))
    for q in ("Fy", "Mz", "Mx"):
        assert float(getattr(m, q)) == -float(getattr(p, q)), q
    a = st.solve(0.0, 0.002, VX, FZ, T20)
    both = st.solve(0.0, 0.002, VX, FZ, T20, gamma=0.02)
    assert float(both.Fy) == pytest.approx(float(a.Fy) + float(p.Fy), rel=1e-2)


def test_camber_stiffness_of_the_shipped_tire_near_the_mf_example(grid):
    """At the nominal load the shipped tire's camber stiffness (camber_reduction from the MF
    example tire's PECP1) is that tire's |C_Fgamma| = Fz |PKY6| = 3.59 kN/rad within 10 %
    (measured 3.83: the brush grows with a^3, models/tires/passenger.toml)."""
    st = SteadyBrush(passenger(), grid)
    out = st.solve(0.0, 0.0, VX, FZ, T20, gamma=0.01)
    assert float(out.Fy) / 0.01 == pytest.approx(FZ * 0.8987, rel=0.10)


def test_transient_camber_settles_on_the_steady_state(grid):
    """Rolling at constant camber, the transient tire (belt on springs, yaw, tread mass)
    settles on the steady model's thrust and overturning moment within 1 % (the defaults'
    convergence bound, docs/tire-core.md)."""
    tire = passenger()
    tr = TransientBrushTire(tire, grid)
    for _ in range(300):
        out = tr.step(1e-3, VX, 0.0, VX / tire.R_e, FZ, T20, 1.0, 0.03)
    ss = SteadyBrush(tire, grid).solve(0.0, 0.0, VX, FZ, float(out.T_tread), gamma=0.03)
    assert out.Fy == pytest.approx(float(ss.Fy), rel=1e-2)
    assert out.Mx == pytest.approx(float(ss.Mx), rel=1e-2)


def test_overturning_moment_is_the_shifted_load(grid):
    """Mx = -delta_y Fz: in the transient model with the belt's deflection of its state, in
    the steady one with delta_y = Fy / k_y; Fy > 0 (adapted SAE) shifts the load to the right
    and gives Mx < 0, as MF-Tyre's QSX3 Fy term in ISO-W (where both signs flip for Fy only)."""
    tire = passenger()
    tr = TransientBrushTire(tire, grid)
    for _ in range(200):
        out = tr.step(1e-3, VX, -0.3, VX / tire.R_e, FZ, T20)
    assert out.Fy > 0 and out.Mx < 0
    assert out.Mx == -tr.get_state()["delta"][1] * FZ
    ss = SteadyBrush(tire, grid).solve(0.0, 0.02, VX, FZ, T20)
    assert float(ss.Mx) == pytest.approx(-float(ss.Fy) / tire.carcass.k_y * FZ, rel=1e-12)
    rigid = SteadyBrush(tire, grid, rigid_carcass=True).solve(0.0, 0.02, VX, FZ, T20)
    assert float(rigid.Mx) == 0.0


def test_moments_vanish_without_load(grid):
    """Lift-off: Fx, Fy, Mx, My and Mz are exactly zero, camber or not."""
    tire = passenger()
    tr = TransientBrushTire(tire, grid)
    for _ in range(50):
        tr.step(1e-3, VX, 0.3, VX / tire.R_e, FZ, T20, 1.0, 0.05)
    for _ in range(50):
        out = tr.step(1e-3, VX, 0.3, VX / tire.R_e, 0.0, T20, 1.0, 0.05)
    assert (out.Fx, out.Fy, out.Mz, out.My) == (0.0, 0.0, 0.0, 0.0)
    assert abs(out.Mx) == 0.0


@pytest.mark.parametrize("gamma", [math.nan, math.inf, 0.5 * math.pi, -2.0])
def test_bad_camber_is_refused_and_changes_nothing(grid, gamma):
    """Non-finite or |gamma| >= pi/2: a clear error naming the input, the state unchanged
    (the FMU's guard turns these into input_status bits before they reach the model)."""
    tire = passenger()
    tr = TransientBrushTire(tire, grid)
    tr.step(1e-3, VX, 0.0, VX / tire.R_e, FZ, T20)
    before = tr.state_vector()
    with pytest.raises(InputError, match="gamma"):
        tr.step(1e-3, VX, 0.0, VX / tire.R_e, FZ, T20, 1.0, gamma)
    assert np.array_equal(tr.state_vector(), before, equal_nan=True)
    with pytest.raises(InputError, match="gamma"):
        SteadyBrush(tire, grid).solve(0.0, 0.0, VX, FZ, T20, gamma=gamma)
