"""Tire axis systems and sign conventions, with pure conversion functions between them.

Four conventions, all right-handed, origin at the contact centre, ``x`` forward along the
intersection of the wheel plane with the road (docs/axes.md has the figures in words and the
sources):

``"iso-w"``
    ISO 8855 wheel axis system (TYDEX W; the convention of MF-Tyre / ``.tir`` files): ``y`` to
    the left, ``z`` up. Slip angle ``tan(alpha) = V_sy / |V_x|`` (positive when the contact
    centre moves to the left of the wheel heading), so a free-rolling tire with ``alpha > 0``
    has ``Fy < 0`` and the cornering stiffness (``PKY1``) is negative. ``Fz`` (road on tire,
    along ``z`` up) is positive under load.
``"iso-v"``
    ISO 8855 vehicle axes (``y`` left, ``z`` up) with ``x`` along the vehicle's longitudinal
    axis: the ISO-W vectors turned about ``z`` by the wheel's steer angle ``steer`` (flat road).
    Slip angle, slip and camber are wheel quantities and keep their ISO-W values. With
    ``steer = 0`` ISO-V and ISO-W coincide.
``"sae"``
    SAE J670 tire axes: ``y`` to the right, ``z`` down (ISO-W turned by 180 degrees about
    ``x``). Slip angle positive when the contact centre moves to the right of the heading:
    ``alpha > 0`` gives ``Fy < 0`` and ``Mz > 0``; ``Fz`` (along ``z`` down) is negative under
    load.
``"adapted-sae"``
    Pacejka's adapted SAE (Pacejka 2012, *Tire and Vehicle Dynamics*, ch. 1-2): SAE axes, but
    the slip angle is reversed, ``tan(alpha) = -V_cy / V_cx`` (eq. (2.12)), so that
    ``alpha > 0`` gives ``Fy > 0`` (and ``Mz < 0``), and ``Fz`` is the normal load, positive.
    This is the convention of the brush model (:mod:`tire_brush.slip`,
    :mod:`tire_brush.reference`): its outputs are converted from here.

Relative to ISO-W every convention differs by a sign per quantity (a table, :data:`SIGNS`; the
rotation of ISO-V comes on top). In words: ISO <-> SAE flips everything along or about ``y``
and ``z`` (``Fy, Fz, My, Mz``, the lateral velocity, and the slip angle because it is measured
about ``z``); ``Fx``, ``Mx``, the longitudinal slip and the camber (inclination) angle, a
rotation about ``x``, keep their sign. Adapted SAE takes SAE and reverses the slip angle and
``Fz`` -- hence its slip angle equals the ISO one while ``Fy`` and ``Mz`` are opposite.

The longitudinal slip ``kappa = -V_sx / |V_x|`` (positive when driving) is the same in all
four (the older "braking slip", positive when braking, is not used here). Camber is the
inclination angle, a rotation of the wheel plane about ``x`` (right-hand rule: seen from
behind, clockwise, the top of the wheel to the right); the four systems share ``x``, so it
keeps its sign.

Sources for the signs: ISO 8855 and the TYDEX / Standard Tire Interface W-axis system as
described by MSC Adams Tire ("About axis systems and sign conventions": positive slip angle when
the travel direction has a +y component, producing a negative lateral force; ``Fz`` upward);
MF-Tyre 6.1 (``tan(alpha) = V_sy / |V_x|``, ``kappa = -V_sx / V_x``); Pacejka 2012 eq. (2.12)
for the adapted SAE slip angle. Only numpy and the standard library are imported.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from tirefric.errors import InputError

Axes = Literal["iso-w", "iso-v", "sae", "adapted-sae"]

#: The conventions, in the order the CLI lists them.
AXES: tuple[str, ...] = ("iso-w", "iso-v", "sae", "adapted-sae")

#: The brush model's own convention.
BRUSH_AXES = "adapted-sae"

#: Sign of each quantity relative to ISO-W (``value_in_axes = sign * value_in_iso_w``; ISO-V
#: adds the steer rotation of the in-plane vectors). Keys: slip angle ``alpha``, lateral
#: velocity ``vy``, camber ``gamma``, slip ``kappa``, forces and moments of the road on the tire.
SIGNS: dict[str, dict[str, int]] = {
    "iso-w": dict(alpha=1, vy=1, gamma=1, kappa=1, Fx=1, Fy=1, Fz=1, Mx=1, My=1, Mz=1),
    "iso-v": dict(alpha=1, vy=1, gamma=1, kappa=1, Fx=1, Fy=1, Fz=1, Mx=1, My=1, Mz=1),
    "sae": dict(alpha=-1, vy=-1, gamma=1, kappa=1, Fx=1, Fy=-1, Fz=-1, Mx=1, My=-1, Mz=-1),
    "adapted-sae": dict(alpha=1, vy=-1, gamma=1, kappa=1, Fx=1, Fy=-1, Fz=1, Mx=1, My=-1,
                        Mz=-1),
}


def check_axes(name: str, option: str = "axes") -> str:
    """``name`` if it is one of :data:`AXES`, else an :class:`InputError` naming the choices."""
    if name not in SIGNS:
        raise InputError(f"unknown axis convention; expected one of {', '.join(AXES)}",
                         field=option, value=name)
    return name


@dataclass(frozen=True)
class SlipInputs:
    """Wheel inputs in one convention.

    Attributes
    ----------
    kappa : float or ndarray
        Longitudinal slip [1].
    alpha : float or ndarray
        Slip angle [rad].
    vx, vy : float or ndarray
        Velocity of the contact centre [m/s] along the convention's x and y axes.
    gamma : float or ndarray
        Camber (inclination) angle [rad].
    """

    kappa: float | np.ndarray
    alpha: float | np.ndarray
    vx: float | np.ndarray
    vy: float | np.ndarray
    gamma: float | np.ndarray = 0.0


@dataclass(frozen=True)
class Wrench:
    """Forces [N] and moments [N m] of the road on the tire, at the contact centre, in one
    convention (``Fz`` as that convention defines it: see the module docstring)."""

    Fx: float | np.ndarray
    Fy: float | np.ndarray
    Fz: float | np.ndarray
    Mx: float | np.ndarray = 0.0
    My: float | np.ndarray = 0.0
    Mz: float | np.ndarray = 0.0


def _rotate(x, y, angle):
    """Components in the base axes of an in-plane vector whose components are ``(x, y)`` in
    axes turned by ``angle`` [rad] about z (counter-clockwise seen from +z)."""
    c, s = np.cos(angle), np.sin(angle)
    return c * x - s * y, s * x + c * y


def convert_inputs(inp: SlipInputs, frm: str, to: str, steer: float = 0.0) -> SlipInputs:
    """``inp`` given in convention ``frm``, expressed in ``to``.

    ``steer`` [rad] is the wheel's steer angle about the vehicle's ``z`` (ISO, positive to the
    left); it matters only between ISO-V and the others (the velocity ``(vx, vy)`` is turned;
    slip, slip angle and camber are wheel quantities and keep their ISO-W values).
    """
    check_axes(frm, "from")
    check_axes(to, "to")
    sf, st = SIGNS[frm], SIGNS[to]
    vx, vy = np.asarray(inp.vx, float), sf["vy"] * np.asarray(inp.vy, float)
    if frm == "iso-v":                       # vehicle x -> wheel x: turn by -steer
        vx, vy = _rotate(vx, vy, -steer)
    if to == "iso-v":
        vx, vy = _rotate(vx, vy, steer)
    return SlipInputs(kappa=_same(inp.kappa),
                      alpha=_flip(inp.alpha, sf["alpha"] * st["alpha"]),
                      vx=_back(vx), vy=_back(st["vy"] * vy),
                      gamma=_flip(inp.gamma, sf["gamma"] * st["gamma"]))


def convert_wrench(w: Wrench, frm: str, to: str, steer: float = 0.0) -> Wrench:
    """Forces and moments ``w`` given in convention ``frm``, expressed in ``to`` (``steer``
    as in :func:`convert_inputs`: the in-plane components of force and moment turn)."""
    check_axes(frm, "from")
    check_axes(to, "to")
    sf, st = SIGNS[frm], SIGNS[to]
    iso = {k: sf[k] * np.asarray(getattr(w, k), float) for k in ("Fx", "Fy", "Fz", "Mx", "My",
                                                                   "Mz")}
    if frm == "iso-v":
        iso["Fx"], iso["Fy"] = _rotate(iso["Fx"], iso["Fy"], -steer)
        iso["Mx"], iso["My"] = _rotate(iso["Mx"], iso["My"], -steer)
    if to == "iso-v":
        iso["Fx"], iso["Fy"] = _rotate(iso["Fx"], iso["Fy"], steer)
        iso["Mx"], iso["My"] = _rotate(iso["Mx"], iso["My"], steer)
    return Wrench(**{k: _back(st[k] * v) for k, v in iso.items()})


def slip_angle(vx, vy, axes: str):
    """Slip angle [rad] of a contact centre moving with ``(vx, vy)`` [m/s] (``vx > 0``) in the
    axes of convention ``axes``: ``atan(vy / vx)`` in ISO and SAE, ``-atan(vy / vx)`` in
    adapted SAE (Pacejka 2012 eq. (2.12)). In ISO-V ``(vx, vy)`` must be in wheel axes
    (``steer = 0``)."""
    check_axes(axes)
    sign = -1.0 if axes == "adapted-sae" else 1.0
    return _back(sign * np.arctan2(np.asarray(vy, float), np.asarray(vx, float)))


def _flip(x, sign: int):
    return _back(sign * np.asarray(x, float))


def _same(x):
    return _back(np.asarray(x, float))


def _back(x: np.ndarray):
    """A 0-d array back to a float."""
    return float(x) if np.ndim(x) == 0 else x
