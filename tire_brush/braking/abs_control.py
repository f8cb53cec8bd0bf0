"""Brake controllers for the quarter-car simulation: rule-based ABS and a locked wheel.

The rule-based ABS follows the threshold logic of production systems: wheel deceleration and
acceleration thresholds ``-a``, ``+a``, ``+A`` and a slip threshold, with pressure (here: brake
torque) build-up, hold and release phases. The cycle is the one of the Bosch ABS on a high
friction road (Robert Bosch GmbH, *Bosch Automotive Handbook*, "Antilock braking system",
control cycle phases 1-8; also Savaresi & Tanelli, *Active Braking Control Systems Design for
Vehicles*, Springer 2010, sec. 2.3):

1. APPLY: torque rises at the full rate. A wheel peripheral deceleration beyond ``-a``
   (the wheel falls behind the car faster than any car decelerates) switches to HOLD.
2. HOLD: torque held. When the deceleration recovers above ``-a`` (the tire is still on the
   stable side of its peak and the wheel settled), the build-up continues: at the full rate
   in the first cycle (stepped fast build-up), slowly (REAPPLY) in later cycles.
3. RELEASE: whenever the slip passes the slip threshold (during APPLY, HOLD, REAPPLY or BOOST)
   the torque falls at the full rate until the deceleration recovers above ``-a``.
4. HOLD (recover): torque held while the wheel re-accelerates; an acceleration above ``+A``
   (wheel much too free) calls for BOOST, falling below ``+a`` (wheel re-synchronised) for
   REAPPLY, or for RELEASE again if the slip is still past its threshold (the wheel stopped
   recovering: release more).
5. BOOST: torque rises at the full rate until the acceleration falls below ``+A``, then HOLD.
6. REAPPLY: torque rises slowly (a fraction of the full rate, the stepped pressure build-up
   of production systems); a deceleration beyond ``-a`` holds it (2), the slip threshold
   releases it (3), and the next cycle starts.

Unlike the Bosch cycle, a deceleration beyond ``-a`` during the slow re-apply holds instead of
releasing: with a continuous re-apply the wheel deceleration includes ``v d kappa / dt``,
which at high speed passes ``-a`` well before the friction peak (release at ~6 % slip on dry
asphalt, measured), so the slip threshold is the release criterion and ``-a`` limits the
build-up. The default thresholds were chosen by a sweep on the Burckhardt (dry, wet asphalt,
snow) and Magic Formula (dry, wet) curves from 100 km/h with the shipped passenger quarter car:
the stopping distance then stays within 3 to 7 % of the point-mass bound on all five. They are
a calibration, like a production ABS's: other tires and vehicles may want others.

Sensing is idealised and sampled: the controller reads the wheel speed every control period,
estimates the wheel's peripheral acceleration ``R d omega / dt`` by the backward difference of
two samples, and knows the vehicle speed (a perfect reference speed; production systems
estimate it from the wheel speeds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

from lookup.errors import InputError

#: Phase names of the rule-based ABS, indexed by the phase code stored in the trajectories.
PHASES = ("apply", "hold", "release", "hold_recover", "boost", "reapply")
APPLY, HOLD, RELEASE, HOLD_RECOVER, BOOST, REAPPLY = range(6)


class BrakeController(Protocol):
    """What the simulation needs from a controller (sampled every ``control_period``)."""

    control_period: float

    def reset(self) -> None:
        """Forget any internal state (start of a stop)."""

    def torque_rate(self, t: float, v: float, omega: float, brake_torque: float) -> float:
        """Commanded brake torque rate [N m/s] until the next sample."""

    @property
    def phase(self) -> int:
        """Current phase code (index into :data:`PHASES`)."""


@dataclass(frozen=True)
class ABSParams:
    """Thresholds and timing of the rule-based ABS.

    Attributes
    ----------
    slip_threshold : float
        Slip magnitude past which the torque is released [1].
    decel_threshold : float
        Wheel peripheral deceleration threshold ``a`` (the ``-a`` of the cycle) [m/s^2].
    accel_threshold : float
        Wheel peripheral acceleration threshold ``+a`` [m/s^2].
    accel_threshold_high : float
        Large acceleration threshold ``+A`` [m/s^2], > ``accel_threshold``.
    reapply_fraction : float
        Slow re-apply rate as a fraction of the full torque rate [1].
    control_period : float
        Controller sample time [s] (production ABS ECUs: 5 to 10 ms).
    """

    slip_threshold: float = 0.2
    decel_threshold: float = 20.0
    accel_threshold: float = 3.0
    accel_threshold_high: float = 30.0
    reapply_fraction: float = 0.2
    control_period: float = 0.005

    def __post_init__(self) -> None:
        for name in ("slip_threshold", "decel_threshold", "accel_threshold",
                     "accel_threshold_high", "reapply_fraction", "control_period"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise InputError("must be a finite number > 0", field=f"abs.{name}", value=val)
        if self.slip_threshold >= 1:
            raise InputError("must be < 1", field="abs.slip_threshold",
                             value=self.slip_threshold)
        if self.reapply_fraction > 1:
            raise InputError("must be <= 1", field="abs.reapply_fraction",
                             value=self.reapply_fraction)
        if self.accel_threshold_high <= self.accel_threshold:
            raise InputError("must exceed abs.accel_threshold", field="abs.accel_threshold_high",
                             value=self.accel_threshold_high)


class RuleBasedABS:
    """Threshold ABS (module doc) acting on the brake torque rate.

    Parameters
    ----------
    params
        Thresholds and sample time.
    radius
        Wheel rolling radius [m] (peripheral acceleration ``R d omega / dt``).
    rate_max
        Full brake torque rate [N m/s].
    """

    def __init__(self, params: ABSParams, radius: float, rate_max: float) -> None:
        self.params = params
        self.radius = radius
        self.rate_max = rate_max
        self.control_period = params.control_period
        self.reset()

    def reset(self) -> None:
        """Start a stop in APPLY with no wheel-speed history."""
        self._phase = APPLY
        self._omega_prev: float | None = None
        self._cycles = 0

    @property
    def phase(self) -> int:
        """Current phase code."""
        return self._phase

    def torque_rate(self, t: float, v: float, omega: float, brake_torque: float) -> float:
        """One controller sample: update the phase and return the torque rate [N m/s]."""
        p = self.params
        a_w = 0.0 if self._omega_prev is None else (
            self.radius * (omega - self._omega_prev) / self.control_period)
        self._omega_prev = omega
        s = (v - omega * self.radius) / v          # slip magnitude, > 0 in braking
        ph = self._phase
        if s > p.slip_threshold and ph in (APPLY, HOLD, REAPPLY, BOOST):
            ph = RELEASE
        elif ph in (APPLY, REAPPLY) and a_w < -p.decel_threshold:
            ph = HOLD
        elif ph == HOLD and a_w > -p.decel_threshold:
            ph = REAPPLY if self._cycles else APPLY
        elif ph == RELEASE and a_w > -p.decel_threshold:
            ph = HOLD_RECOVER
            self._cycles += 1
        elif ph == HOLD_RECOVER:
            if a_w > p.accel_threshold_high:
                ph = BOOST
            elif a_w < p.accel_threshold:
                ph = RELEASE if s > p.slip_threshold else REAPPLY
        elif ph == BOOST and a_w < p.accel_threshold_high:
            ph = HOLD_RECOVER
        self._phase = ph
        if ph in (APPLY, BOOST):
            return self.rate_max
        if ph == REAPPLY:
            return p.reapply_fraction * self.rate_max
        if ph == RELEASE:
            return -self.rate_max
        return 0.0


class LockedWheel:
    """No ABS: the brake torque rises at the full rate to its maximum and stays there.

    Parameters
    ----------
    rate_max
        Full brake torque rate [N m/s].
    control_period
        Sample time [s] (only sets how often the simulation asks).
    """

    def __init__(self, rate_max: float, control_period: float = 0.005) -> None:
        self.rate_max = rate_max
        self.control_period = control_period

    def reset(self) -> None:
        """Nothing to forget."""

    @property
    def phase(self) -> int:
        """Always APPLY."""
        return APPLY

    def torque_rate(self, t: float, v: float, omega: float, brake_torque: float) -> float:
        """Full apply rate; the actuator saturates at the maximum torque."""
        return self.rate_max
