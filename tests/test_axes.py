"""Axis conventions (tire_brush.axes): the known signs of each convention, on the brush itself,
round trips, the ISO-V rotation, and ``tirefric tire curve --axes``.

Known signs (sources in docs/axes.md): ISO-W (TYDEX W, MF-Tyre) -- a positive slip angle
(contact centre moving towards +y, the left) gives a negative Fy and a positive Mz for a
free-rolling tire, Fz (along z up) is positive; SAE J670 -- y right, z down, a positive slip
angle (moving right) gives a negative Fy and a positive Mz, Fz is negative; Pacejka's adapted
SAE -- positive slip angle gives positive Fy and negative Mz, Fz is the (positive) load. Braking
gives Fx < 0 in all four. Exact sign flips need no tolerance; rotations are compared at 1e-12
(round-off of cos/sin).
"""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest

from tire_brush.axes import (
    AXES,
    BRUSH_AXES,
    SIGNS,
    SlipInputs,
    Wrench,
    check_axes,
    convert_inputs,
    convert_wrench,
    slip_angle,
)
from tire_brush.friction import ConstantFriction
from tire_brush.params import load_tire
from tire_brush.steady import SteadyBrush
from tirefric.cli import main
from tirefric.errors import InputError

FZ = 4000.0
VX = 20.0


@pytest.fixture(scope="module")
def brush() -> SteadyBrush:
    return SteadyBrush(load_tire("passenger"), ConstantFriction(1.0, 0.8))


def _brush_in(brush: SteadyBrush, axes: str, kappa: float, alpha: float) -> Wrench:
    """The brush's wrench for slip ``kappa`` and slip angle ``alpha`` given in ``axes``."""
    a = convert_inputs(SlipInputs(kappa, alpha, VX, 0.0), axes, BRUSH_AXES).alpha
    out = brush.solve(kappa, a, VX, FZ, 293.15)
    return convert_wrench(Wrench(float(out.Fx), float(out.Fy), FZ, 0.0, 0.0, float(out.Mz)),
                          BRUSH_AXES, axes)


def test_brush_is_adapted_sae(brush) -> None:
    """What tire_brush does: alpha > 0 gives Fy > 0 and Mz < 0, braking gives Fx < 0, and the
    lateral force opposes the lateral slip velocity (tan(alpha) = -V_sy / V_x, Pacejka 2012
    eq. (2.12), the adapted SAE slip angle)."""
    out = brush.solve(0.0, math.radians(3.0), VX, FZ, 293.15)
    assert out.Fy > 0 and out.Mz < 0, "adapted SAE: alpha > 0 gives Fy > 0, Mz < 0"
    assert brush.solve(-0.05, 0.0, VX, FZ, 293.15).Fx < 0, "braking gives Fx < 0"
    side = brush.solve_velocities(0.0, 1.0, VX, FZ, 293.15)       # V_sy > 0: sliding to +y
    assert side.Fy < 0, "friction opposes the lateral slip velocity"
    assert slip_angle(VX, 1.0, BRUSH_AXES) < 0, "tan(alpha) = -V_sy / V_x in adapted SAE"


@pytest.mark.parametrize("axes,Fy_sign,Mz_sign,Fz_sign", [
    ("iso-w", -1, 1, 1), ("iso-v", -1, 1, 1), ("sae", -1, 1, -1), ("adapted-sae", 1, -1, 1)])
def test_known_signs_for_positive_slip_angle(brush, axes, Fy_sign, Mz_sign, Fz_sign) -> None:
    w = _brush_in(brush, axes, 0.0, math.radians(3.0))
    assert np.sign(w.Fy) == Fy_sign, f"{axes}: sign of Fy at alpha = +3 deg"
    assert np.sign(w.Mz) == Mz_sign, f"{axes}: sign of Mz at alpha = +3 deg"
    assert np.sign(w.Fz) == Fz_sign, f"{axes}: sign of Fz under load"
    assert _brush_in(brush, axes, -0.05, 0.0).Fx < 0, f"{axes}: braking gives Fx < 0"


@pytest.mark.parametrize("axes", AXES)
def test_lateral_force_opposes_lateral_velocity(brush, axes) -> None:
    """In every convention the side force points against the sideways motion: a contact
    centre moving with vy gets Fy of the opposite sign, and the slip angle of that motion is
    the one :func:`slip_angle` gives."""
    for vy in (-1.0, 1.0):
        alpha = slip_angle(VX, vy, axes)
        w = _brush_in(brush, axes, 0.0, alpha)
        assert w.Fy * vy < 0, f"{axes}: Fy must oppose vy = {vy}"
        back = convert_inputs(SlipInputs(0.0, alpha, VX, vy), axes, "iso-w")
        assert back.alpha == pytest.approx(slip_angle(VX, back.vy, "iso-w"), abs=1e-15)


def test_iso_against_sae_flips_y_and_z_only() -> None:
    w = Wrench(1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    s = convert_wrench(w, "iso-w", "sae")
    assert (s.Fx, s.Fy, s.Fz, s.Mx, s.My, s.Mz) == (1.0, -2.0, -3.0, 4.0, -5.0, -6.0)
    i = convert_inputs(SlipInputs(0.1, 0.2, 20.0, 1.5, 0.03), "iso-w", "sae")
    assert (i.kappa, i.alpha, i.vx, i.vy, i.gamma) == (0.1, -0.2, 20.0, -1.5, 0.03), \
        "slip and camber keep their sign, slip angle and lateral velocity flip"
    a = convert_inputs(SlipInputs(0.1, 0.2, 20.0, 1.5, 0.03), "sae", "adapted-sae")
    assert (a.alpha, a.vy, a.gamma) == (-0.2, 1.5, 0.03), \
        "adapted SAE: SAE axes with the slip angle reversed"
    assert convert_wrench(w, "sae", "adapted-sae").Fz == -3.0, "adapted SAE: Fz is the load"


@pytest.mark.parametrize("frm,to", list(itertools.permutations(AXES, 2)))
def test_round_trips_and_composition(frm, to) -> None:
    rng = np.random.default_rng(7)
    w = Wrench(*rng.normal(size=(6, 5)))
    inp = SlipInputs(*rng.normal(size=(5, 5)))
    steer = 0.3
    w2 = convert_wrench(convert_wrench(w, frm, to, steer), to, frm, steer)
    i2 = convert_inputs(convert_inputs(inp, frm, to, steer), to, frm, steer)
    for k in ("Fx", "Fy", "Fz", "Mx", "My", "Mz"):
        np.testing.assert_allclose(getattr(w2, k), getattr(w, k), rtol=0, atol=1e-12,
                                   err_msg=f"{frm}->{to}->{frm}: {k}")
    for k in ("kappa", "alpha", "vx", "vy", "gamma"):
        np.testing.assert_allclose(getattr(i2, k), getattr(inp, k), rtol=0, atol=1e-12,
                                   err_msg=f"{frm}->{to}->{frm}: {k}")
    for mid in AXES:
        via = convert_wrench(convert_wrench(w, frm, mid, steer), mid, to, steer)
        direct = convert_wrench(w, frm, to, steer)
        for k in ("Fx", "Fy", "Fz", "Mx", "My", "Mz"):
            np.testing.assert_allclose(getattr(via, k), getattr(direct, k), atol=1e-12,
                                       err_msg=f"{frm}->{mid}->{to} against {frm}->{to}")


def test_iso_v_turns_by_the_steer_angle() -> None:
    w = Wrench(100.0, -40.0, 4000.0, 5.0, -7.0, 12.0)
    same = convert_wrench(w, "iso-w", "iso-v", 0.0)
    assert (same.Fx, same.Fy, same.Mx, same.My) == (100.0, -40.0, 5.0, -7.0)
    v = convert_wrench(w, "iso-w", "iso-v", math.pi / 2)       # wheel steered 90 deg left
    np.testing.assert_allclose([v.Fx, v.Fy, v.Mx, v.My], [40.0, 100.0, 7.0, 5.0], atol=1e-12,
                               err_msg="wheel x points along vehicle y")
    assert (v.Fz, v.Mz) == (4000.0, 12.0), "z components do not turn"
    i = convert_inputs(SlipInputs(0.1, 0.05, 20.0, 1.0, 0.02), "iso-w", "iso-v", 0.2)
    assert (i.kappa, i.alpha, i.gamma) == (0.1, 0.05, 0.02), "wheel quantities keep values"
    assert math.hypot(i.vx, i.vy) == pytest.approx(math.hypot(20.0, 1.0), rel=1e-14)


def test_every_convention_has_every_quantity_and_unit_signs() -> None:
    keys = set(SIGNS["iso-w"])
    for name, signs in SIGNS.items():
        assert set(signs) == keys, name
        assert set(signs.values()) <= {-1, 1}, name
    with pytest.raises(InputError, match="iso-w"):
        check_axes("iso")


def test_curve_cli_axes(capsys) -> None:
    base = ["tire", "curve", "--tire", "passenger", "--grid", "constant:1.0", "--Fz", "4000",
            "--vx", "20", "--T", "20", "--alpha-deg", "4:4:1", "--json"]
    got = {}
    for axes in AXES:
        assert main([*base, "--axes", axes]) == 0
        got[axes] = json.loads(capsys.readouterr().out)
        assert got[axes]["axes"] == axes
    assert main(base) == 0
    assert json.loads(capsys.readouterr().out)["axes"] == "adapted-sae", "default unchanged"
    p = {k: v["points"][0] for k, v in got.items()}
    assert p["adapted-sae"]["Fy"] > 0 and p["iso-w"]["Fy"] < 0 and p["sae"]["Fy"] < 0
    assert p["iso-w"]["Fy"] == -p["adapted-sae"]["Fy"], "same alpha, opposite Fy"
    assert p["sae"]["Fy"] == pytest.approx(-p["adapted-sae"]["Fy"], rel=1e-12), \
        "SAE alpha = -adapted alpha, and the brush is odd in alpha"
    assert p["iso-w"]["Mz"] > 0 and p["sae"]["Mz"] > 0 and p["adapted-sae"]["Mz"] < 0
    assert all(v["alpha"] == pytest.approx(math.radians(4)) for v in p.values())
