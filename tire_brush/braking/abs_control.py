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
a calibration, like a production ABS's: other tires and vehicles may want others. A fixed
slip threshold does not carry over to a tire whose mu-slip curve peaks at a much smaller slip
and falls steeply beyond it (the passenger brush tire on the default grid at 0 C: peak at 4 %
slip above 10 m/s, 8 % less friction at 6 %, a second maximum at 20-25 % slip below 10 m/s);
``slip_schedule`` then sets the release slip per speed from the slip
map of the tire and road (:func:`tire_brush.braking.study.abs_slip_schedule`), which is how
production calibrations are made per tire and road.

An open-loop :class:`TorqueRamp` (constant or ramped torque, no ABS) serves manoeuvres such as
the FMU example's.

Sensing is idealised and sampled: the controller reads the wheel speed every control period,
estimates the wheel's peripheral acceleration ``R d omega / dt`` by the backward difference of
two samples, and knows the vehicle speed (a perfect reference speed; production systems
estimate it from the wheel speeds). :class:`RealisticABS` runs the same phase logic with a
reference speed estimated from the wheel speed, solenoid-valve pulses, a release faster than
the build-up and a hydraulic delay (measured on asphalt: 4.4-7.2 control cycles per second
and 1-5 % longer stops than the idealised controller; 10.7 Hz and 2 % on snow).
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from tirefric.errors import InputError

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
    slip_schedule
        Release slip as a function of the vehicle speed: ``(speeds [m/s], slips [1])``,
        interpolated linearly (e.g. the slip of maximum force from the case's slip map,
        :func:`.study.abs_slip_schedule`); None uses ``params.slip_threshold`` at all
        speeds. A slip of 1 never releases (a locked wheel brakes best there).
    """

    def __init__(self, params: ABSParams, radius: float, rate_max: float, *,
                 slip_schedule: tuple[Sequence[float], Sequence[float]] | None = None) -> None:
        self.params = params
        self.radius = radius
        self.rate_max = rate_max
        self.control_period = params.control_period
        self.slip_schedule = None
        if slip_schedule is not None:
            speeds, slips = (tuple(float(x) for x in a) for a in slip_schedule)
            if len(speeds) != len(slips) or not speeds or \
                    any(b <= a for a, b in itertools.pairwise(speeds)) or \
                    not all(0.0 < s <= 1.0 for s in slips):
                raise InputError("need ascending speeds [m/s] and slips in (0, 1], one per "
                                 "speed", field="abs.slip_schedule", value=slip_schedule)
            self.slip_schedule = (speeds, slips)
        self.reset()

    def slip_threshold(self, v: float) -> float:
        """Release slip [1] at vehicle speed ``v`` [m/s]: the schedule interpolated linearly
        in ``v`` (held constant beyond its ends), else ``params.slip_threshold``."""
        if self.slip_schedule is None:
            return self.params.slip_threshold
        speeds, slips = self.slip_schedule
        i = bisect.bisect_right(speeds, v)
        if i == 0:
            return slips[0]
        if i == len(speeds):
            return slips[-1]
        w = (v - speeds[i - 1]) / (speeds[i] - speeds[i - 1])
        return slips[i - 1] + w * (slips[i] - slips[i - 1])

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
        s_max = self.slip_threshold(v)
        ph = self._phase
        if s > s_max and ph in (APPLY, HOLD, REAPPLY, BOOST):
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
                ph = RELEASE if s > s_max else REAPPLY
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


@dataclass(frozen=True)
class HydraulicsParams:
    """Sensing and actuation of a production-like ABS (:class:`RealisticABS`).

    The numbers are typical of passenger-car systems, not measurements of one: solenoid inlet
    and outlet valves switched in pulses of one control period, a pressure response that lags
    the valve command by ~10 ms, a pressure drop through the outlet valve faster than the
    build-up through the inlet valve, and a reference speed estimated from the wheel speed
    with a plausibility limit on the vehicle deceleration (Bosch, *Automotive Handbook*,
    "Antilock braking system": hydraulic modulator and control cycle; Savaresi & Tanelli,
    *Active Braking Control Systems Design for Vehicles*, Springer 2010, ch. 2-3).

    Attributes
    ----------
    delay : float
        Dead time between a valve command and the brake torque's response [s].
    release_factor : float
        Release (outlet valve) rate over the full apply rate [1], >= 1.
    reference_decel : float
        Largest vehicle deceleration the speed estimate believes [m/s^2]: the cap of the
        reference speed's slope (:class:`RealisticABS`).
    """

    delay: float = 0.010
    release_factor: float = 2.0
    reference_decel: float = 12.0

    def __post_init__(self) -> None:
        for name in ("release_factor", "reference_decel"):
            val = getattr(self, name)
            if not (math.isfinite(val) and val > 0):
                raise InputError("must be a finite number > 0", field=f"hydraulics.{name}",
                                 value=val)
        if not (math.isfinite(self.delay) and self.delay >= 0):
            raise InputError("must be a finite number >= 0", field="hydraulics.delay",
                             value=self.delay)
        if self.release_factor < 1:
            raise InputError("must be >= 1 (release is not slower than apply)",
                             field="hydraulics.release_factor", value=self.release_factor)


class RealisticABS(RuleBasedABS):
    """The rule-based ABS with production-like sensing and hydraulics.

    Differences from :class:`RuleBasedABS` (whose phase logic it runs unchanged):

    * **Speed estimate.** The controller does not know the vehicle speed: it uses the
      reference speed ``v_ref = max(omega R, v_ref,prev - a_ref Tc)``, which equals the
      true speed while the wheel rolls free. Its slope is the deceleration the brake can
      give the car, ``a_ref = T_b / (R m)`` (brake torque from the wheel-pressure model,
      ``m`` the vehicle mass per wheel the ECU is configured with), between 0.5 m/s^2 and
      ``hydraulics.reference_decel``: while the wheel decelerates, the road force is
      ``(T_b - J |d omega/dt|) / R <= T_b / R``, so the reference falls at least as fast as
      the car and the slip is never underestimated for long; a fixed 1.2 g slope (the
      simplest production choice) underestimates the speed on snow by several m/s within
      0.3 s and the wheel never recovers (measured);
    * **Valves.** Apply opens the inlet valve (full rate), release opens the outlet valve
      (``release_factor`` times faster), hold closes both; the slow re-apply is a train of
      one-period apply pulses with the duty cycle ``reapply_fraction``;
    * **Hydraulic delay.** The torque responds ``hydraulics.delay`` after the command (rounded
      to whole control periods).

    Parameters
    ----------
    params, radius, rate_max, slip_schedule
        As :class:`RuleBasedABS`.
    mass
        Vehicle mass per braked wheel [kg] (the quarter car's), for the reference speed.
    hydraulics
        Sensing and actuation.
    """

    def __init__(self, params: ABSParams, radius: float, rate_max: float, mass: float, *,
                 slip_schedule: tuple[Sequence[float], Sequence[float]] | None = None,
                 hydraulics: HydraulicsParams | None = None) -> None:
        if not (math.isfinite(mass) and mass > 0):
            raise InputError("must be a finite number > 0", field="abs.mass", value=mass)
        self.mass = mass
        self.hydraulics = hydraulics or HydraulicsParams()
        super().__init__(params, radius, rate_max, slip_schedule=slip_schedule)

    def reset(self) -> None:
        super().reset()
        n = round(self.hydraulics.delay / self.control_period)
        self._queue = [0.0] * n
        self._v_ref: float | None = None
        self._pulse = 0

    @property
    def reference_speed(self) -> float | None:
        """The last reference (estimated vehicle) speed [m/s]."""
        return self._v_ref

    def torque_rate(self, t: float, v: float, omega: float, brake_torque: float) -> float:
        """One sample: estimate the speed, run the phase logic, switch the valves, delay."""
        wheel = omega * self.radius
        if self._v_ref is None:
            self._v_ref = max(wheel, v)        # at the start the car rolls free: v = omega R
        else:
            a_ref = min(max(brake_torque / (self.radius * self.mass), 0.5),
                        self.hydraulics.reference_decel)
            self._v_ref = max(wheel, self._v_ref - a_ref * self.control_period)
        v_ref = max(self._v_ref, 1e-3)
        cmd = super().torque_rate(t, v_ref, omega, brake_torque)
        if cmd < 0.0:
            valve = -self.hydraulics.release_factor * self.rate_max
        elif cmd == 0.0 or cmd >= self.rate_max:
            valve = cmd
        else:                                  # slow re-apply: pulses of one period
            period = max(1, round(1.0 / self.params.reapply_fraction))
            valve = self.rate_max if self._pulse % period == 0 else 0.0
            self._pulse += 1
        if cmd >= 0.0 and self.phase != REAPPLY:
            self._pulse = 0
        if not self._queue:
            return valve
        self._queue.append(valve)
        return self._queue.pop(0)


class TorqueRamp:
    """Open-loop brake torque: zero until ``t_start``, a linear ramp to ``torque`` reached at
    ``t_end``, then constant (``t_end == t_start`` is a step). No ABS.

    The commanded rate makes the torque follow the ramp exactly at the samples: at a sample
    at ``t`` it is ``(T(t + Tc) - T_b) / Tc`` with ``T`` the ramp and ``Tc`` the control
    period, bounded by the full rate ``rate_max``.

    Parameters
    ----------
    torque
        Final brake torque [N m], >= 0.
    t_start, t_end
        Start and end of the ramp [s], ``0 <= t_start <= t_end``.
    rate_max
        Full brake torque rate [N m/s] (the actuator limit).
    control_period
        Sample time [s].
    """

    def __init__(self, torque: float, t_start: float = 0.0, t_end: float = 0.0, *,
                 rate_max: float = math.inf, control_period: float = 0.001) -> None:
        for name, val in (("torque", torque), ("t_start", t_start), ("t_end", t_end)):
            if not (math.isfinite(val) and val >= 0):
                raise InputError("must be a finite number >= 0", field=f"ramp.{name}",
                                 value=val)
        if t_end < t_start:
            raise InputError("the ramp must end after it starts", field="ramp.t_end",
                             value=(t_start, t_end))
        if not (rate_max > 0 and control_period > 0 and math.isfinite(control_period)):
            raise InputError("need rate_max > 0 and a finite control_period > 0",
                             field="ramp", value=(rate_max, control_period))
        self.torque = float(torque)
        self.t_start = float(t_start)
        self.t_end = float(t_end)
        self.rate_max = float(rate_max)
        self.control_period = float(control_period)

    def reset(self) -> None:
        """Nothing to forget."""

    @property
    def phase(self) -> int:
        """Always APPLY."""
        return APPLY

    def target(self, t: float) -> float:
        """Ramp torque at time ``t`` [N m]."""
        if t <= self.t_start:
            return 0.0
        if t >= self.t_end:
            return self.torque
        return self.torque * (t - self.t_start) / (self.t_end - self.t_start)

    def torque_rate(self, t: float, v: float, omega: float, brake_torque: float) -> float:
        """Rate that reaches the ramp at the next sample, within the actuator limit."""
        rate = (self.target(t + self.control_period) - brake_torque) / self.control_period
        return min(max(rate, -self.rate_max), self.rate_max)


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
