"""Slip kinematics and the outputs of the brush models.

Conventions (Pacejka 2012, ch. 2 and 3; docs/review-notes.md): wheel-centre velocity ``vx`` (in the
wheel plane) and ``vy`` (lateral), spin ``omega``, effective rolling radius ``R_e``; rolling
speed ``V_r = omega R_e``; slip velocity of the contact point ``V_sx = vx - V_r``,
``V_sy = vy``; longitudinal slip ``kappa = -V_sx / vx``, slip angle ``tan(alpha) = -vy / vx``.
Braking gives ``kappa < 0`` and ``Fx < 0``; ``alpha > 0`` gives ``Fy > 0``.

The brush models themselves never divide by a speed: the transient model integrates in time
and the steady model in rolled distance. Only the reported ``kappa`` and ``alpha`` need a
low-speed treatment: the speed in their denominators is ``max(|vx|, v_floor)`` (documented
regularisation, default ``v_floor = 0.1 m/s``), so standstill, creeping and reversing give
finite values; when reversing, ``kappa`` keeps the sign of ``V_r - vx`` relative to the
direction of travel.

This module imports only numpy, the standard library and :mod:`tire_brush.signals`: it runs
inside an FMU.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from . import signals

#: Speed floor [m/s] of the reported slips (module docstring).
V_FLOOR = 0.1

#: Output names of the brush models, in order, with units (the tire's signal table).
OUTPUT_UNITS = signals.OUTPUT_UNITS


def velocities_from_slip(kappa: np.ndarray, alpha: np.ndarray,
                         vx: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(V_sx, V_sy, V_r)`` [m/s] for slip ``kappa``, slip angle ``alpha`` [rad] and forward
    speed ``vx`` [m/s]: ``V_r = vx (1 + kappa)``, ``V_sx = -kappa vx``,
    ``V_sy = -vx tan(alpha)``."""
    kappa = np.asarray(kappa, float)
    vx = np.asarray(vx, float)
    return -kappa * vx, -vx * np.tan(np.asarray(alpha, float)), vx * (1.0 + kappa)


def slip_from_kinematics(vx: float, vy: float, omega: float, R_e: float,
                         v_floor: float = V_FLOOR) -> tuple[float, float]:
    """Reported ``(kappa, alpha)`` with the low-speed floor of the module docstring."""
    ref = max(abs(vx), v_floor)
    kappa = (omega * R_e - vx) / ref
    if vx < 0.0:
        kappa = -kappa
    alpha = math.atan2(-vy, ref)
    return kappa, alpha


@dataclass
class BrushOutputs:
    """Outputs of the brush models (floats for one state, arrays for a batch).

    Attributes
    ----------
    Fx, Fy : float or ndarray
        Longitudinal and lateral force on the tire from the road [N].
    Mz : float or ndarray
        Aligning moment about the vertical axis through the patch centre [N m].
    kappa, alpha : float or ndarray
        Longitudinal slip [1] and slip angle [rad].
    mu_eff : float or ndarray
        Utilised friction ``|F| / Fz`` [1] (0 without load).
    mu_slide : float or ndarray
        Pressure-weighted mean friction coefficient of eq. (28) over the sliding elements [1]
        (0 if none slides).
    sliding_fraction : float or ndarray
        Share of the patch length where elements slide faster than
        :data:`~tire_brush.element.CREEP_SPEED` [1].
    dT_flash_max : float or ndarray
        Largest flash-temperature rise in the patch [K]: the hot branch's ``dT_flash`` at the
        element's slip speed times its developed share ``1 - exp(-s/s0)``.
    T_tread : float or ndarray
        Background (tread) temperature the friction was read at [K].
    Mx : float or ndarray
        Overturning moment about the x axis through the contact centre [N m]: the load
        shifted sideways by the belt's lateral deflection ``delta_y``, ``Mx = -delta_y Fz``
        (0 with a rigid carcass). Same sign in ISO-W and adapted SAE (docs/axes.md).
    My : float or ndarray
        Rolling resistance moment [N m], ``f_r Fz R_e`` against the spin (adapted SAE:
        positive when rolling forward; ISO-W flips it), 0 without a rolling-resistance
        model.
    """

    Fx: float | np.ndarray
    Fy: float | np.ndarray
    Mz: float | np.ndarray
    kappa: float | np.ndarray
    alpha: float | np.ndarray
    mu_eff: float | np.ndarray
    mu_slide: float | np.ndarray
    sliding_fraction: float | np.ndarray
    dT_flash_max: float | np.ndarray
    T_tread: float | np.ndarray
    Mx: float | np.ndarray = 0.0
    My: float | np.ndarray = 0.0

    def as_dict(self) -> dict:
        """Name -> value (floats, or lists for arrays), in :data:`OUTPUT_UNITS` order."""
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            out[f.name] = v.tolist() if isinstance(v, np.ndarray) else float(v)
        return out

    def as_array(self) -> np.ndarray:
        """The outputs of one state as a float array in :data:`OUTPUT_UNITS` order."""
        return np.array([float(getattr(self, n)) for n in OUTPUT_UNITS])

    @classmethod
    def from_array(cls, values: np.ndarray) -> BrushOutputs:
        """Inverse of :meth:`as_array`."""
        return cls(*(float(x) for x in values))
