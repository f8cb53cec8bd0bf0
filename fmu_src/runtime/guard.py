"""The FMU's input envelope: what reaches the tire model when a master sends bad inputs.

A vehicle simulator can send anything: NaN after a solver blow-up, a negative load when the
wheel leaves the ground, a spin of 1e9 rad/s. The transient model refuses non-finite inputs
(:class:`tirefric.errors.InputError`); inside an FMU that would end the simulation with a fatal
error. :class:`InputGuard` sits between the FMI inputs and the model and makes every step
well defined:

=====================================  ===========================================  =====
input                                  passed to the model                          bit
=====================================  ===========================================  =====
NaN or +-inf (any input)               its last finite value (start value at first)    1
``Fz < 0``                             0 (lift-off: the model gives zero forces)       2
``|vx|, |vy| > limit.v``,              clamped to the limit, sign kept                 4
``|omega| > limit.omega``
``Fz > limit.Fz``                      ``limit.Fz``                                    8
``T_surface`` outside                  clamped into ``[limit.T_min, limit.T_max]``    16
``[limit.T_min, limit.T_max]``
``mu_scale < 0`` or ``> limit.mu_scale``  clamped into ``[0, limit.mu_scale]``         32
``|gamma| > limit.gamma``              clamped to the limit, sign kept                128
``water_depth < 0`` or                 clamped into ``[0, limit.water_depth]``        256
``> limit.water_depth``
``water_depth > 0`` without a wet      0 (the FMU's grid has no wet branch: dry)      512
branch
=====================================  ===========================================  =====

Two conditions come from the model rather than the inputs (:class:`ModelConditions`, from the
tire core's flags of the step; docs/tire-core.md):

=====================================  ===========================================  =====
condition                              what the step did                            bit
=====================================  ===========================================  =====
the work budget of an outer step was   its remaining elements finished it with one   1024
spent                                  implicit Euler stage ("work budget")
the friction was read at a             read at the axis' edge                       2048
temperature outside the grid's axis
=====================================  ===========================================  =====

The bits of a step add up to the FMU output ``input_status``. Each condition is reported once
when it starts (warning) and once when it clears (with the number of steps it lasted), so a
master stepping at 1 kHz is not flooded. Standstill (``vx = omega = 0``), creeping and
reversing (negative ``vx`` and ``omega``) are normal inputs and pass unchanged.

This module imports only the standard library: it runs inside the FMU.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

from fmu_src.runtime.interface import INPUT_NAMES, INPUTS, MODEL_FLAGS, STATUS_BITS

#: Input names in the order the guard takes them (the tire's, :mod:`tire_brush.signals`).
NAMES = INPUT_NAMES
#: Units of the inputs (for messages; none for a dimensionless one).
_UNITS = tuple("" if s.unit == "1" else s.unit for s in INPUTS)

#: Every condition the guard can find, in a fixed order: (key, input it concerns). The key's
#: part before ":" is its :data:`~fmu_src.runtime.interface.STATUS_BITS` name. The native FMU
#: keeps one counter per condition in this order (its generated header
#: ``tfn_interface.h``, and its serialized state): append new conditions at the end.
CONDITIONS: tuple[tuple[str, str], ...] = (
    *((f"nonfinite:{n}", n) for n in ("vx", "vy", "omega", "Fz", "T_surface", "mu_scale")),
    ("speed_clamped:vx", "vx"), ("speed_clamped:vy", "vy"), ("speed_clamped:omega", "omega"),
    ("negative_load", "Fz"), ("load_clamped", "Fz"), ("temperature_clamped", "T_surface"),
    ("mu_scale_clamped", "mu_scale"),
    ("nonfinite:gamma", "gamma"), ("camber_clamped", "gamma"),
    ("nonfinite:water_depth", "water_depth"), ("water_clamped", "water_depth"),
    ("no_wet_branch", "water_depth"),
)

#: FMI status codes used for messages (fmi2OK, fmi2Warning).
OK, WARNING = 0, 1


class InputGuard:
    """Keeps the inputs of each step inside the model's envelope (module docstring).

    Parameters
    ----------
    limits
        ``limit.*`` values of :data:`fmu_src.runtime.interface.LIMITS` [SI].
    start
        Start values of the inputs (the substitute for a non-finite input before any finite
        one has been seen), in :data:`NAMES` order.
    wet
        Whether the model has a wet branch (else water on the road is taken as 0, bit 512).
    """

    def __init__(self, limits: dict[str, float], start: list[float], wet: bool = False) -> None:
        self.wet = bool(wet)
        self.v_max = float(limits["limit.v"])
        self.omega_max = float(limits["limit.omega"])
        self.Fz_max = float(limits["limit.Fz"])
        self.T_min = float(limits["limit.T_min"])
        self.T_max = float(limits["limit.T_max"])
        self.mu_max = float(limits["limit.mu_scale"])
        self.gamma_max = float(limits["limit.gamma"])
        self.water_max = float(limits["limit.water_depth"])
        if not self.gamma_max < 0.5 * math.pi:
            raise ValueError(f"input envelope: limit.gamma must be < pi/2 (got "
                             f"{self.gamma_max})")
        bad = [k for k, v in limits.items() if not (math.isfinite(v) and v > 0)]
        if bad or not self.T_min < self.T_max:
            raise ValueError(f"input envelope: {', '.join(bad) or 'limit.T_min'} must be "
                             f"finite and > 0, and limit.T_min < limit.T_max (got {limits})")
        self.last = [float(x) for x in start]
        #: active conditions: key -> number of steps it has lasted
        self.active: dict[str, int] = {}

    def apply(self, u: list[float]) -> tuple[list[float], int, list[tuple[int, str]]]:
        """Inputs for the model, the status bits and the messages to log for one step.

        Parameters
        ----------
        u
            Inputs in :data:`NAMES` order, as the master set them.

        Returns
        -------
        values, status, messages
            Inputs to pass to the model, the sum of :data:`~fmu_src.runtime.interface.STATUS_BITS`
            of this step, and ``(fmi status, text)`` pairs to log.
        """
        x = list(u)
        found: dict[str, str] = {}
        last = self.last
        for i in range(len(NAMES)):
            if math.isfinite(x[i]):
                last[i] = x[i]
            else:
                found[f"nonfinite:{NAMES[i]}"] = (
                    f"input {NAMES[i]} = {x[i]!r} is not finite: holding its last finite "
                    f"value {last[i]:g} {_UNITS[i]}".rstrip())
                x[i] = last[i]
        Fz, T, mu = x[3], x[4], x[5]
        for i, lim in ((0, self.v_max), (1, self.v_max), (2, self.omega_max)):
            if abs(x[i]) > lim:
                found[f"speed_clamped:{NAMES[i]}"] = (
                    f"input {NAMES[i]} = {x[i]:g} {_UNITS[i]} is beyond the envelope "
                    f"(limit {lim:g}): clamped")
                x[i] = math.copysign(lim, x[i])
        if Fz < 0.0:
            found["negative_load"] = (f"input Fz = {Fz:g} N is negative: taken as lift-off "
                                      f"(Fz = 0, no forces)")
            x[3] = 0.0
        elif Fz > self.Fz_max:
            found["load_clamped"] = (f"input Fz = {Fz:g} N is beyond the envelope (limit.Fz "
                                     f"= {self.Fz_max:g} N): clamped")
            x[3] = self.Fz_max
        if not self.T_min <= T <= self.T_max:
            found["temperature_clamped"] = (
                f"input T_surface = {T:g} K is outside [{self.T_min:g}, {self.T_max:g}] K: "
                f"clamped")
            x[4] = min(max(T, self.T_min), self.T_max)
        if not 0.0 <= mu <= self.mu_max:
            found["mu_scale_clamped"] = (f"input mu_scale = {mu:g} is outside [0, "
                                         f"{self.mu_max:g}]: clamped")
            x[5] = min(max(mu, 0.0), self.mu_max)
        if abs(x[6]) > self.gamma_max:
            found["camber_clamped"] = (f"input gamma = {x[6]:g} rad is beyond the envelope "
                                       f"(limit.gamma = {self.gamma_max:g} rad): clamped")
            x[6] = math.copysign(self.gamma_max, x[6])
        d = x[7]
        if not 0.0 <= d <= self.water_max:
            found["water_clamped"] = (f"input water_depth = {d:g} m is outside [0, "
                                      f"{self.water_max:g}] m: clamped")
            x[7] = min(max(d, 0.0), self.water_max)
        if x[7] > 0.0 and not self.wet:
            found["no_wet_branch"] = (f"input water_depth = {x[7]:g} m: this FMU's grid has "
                                      f"no wet branch, the road is taken as dry (build the "
                                      f"FMU with a grid that has one, e.g. r117_wet)")
            x[7] = 0.0
        if not found and not self.active:
            return x, 0, []
        return x, self._status(found), self._messages(found)

    @staticmethod
    def _status(found: dict[str, str]) -> int:
        """Sum of the status bits of the conditions found."""
        bits = 0
        for key in found:
            bits |= STATUS_BITS[key.partition(":")[0]]
        return bits

    def _messages(self, found: dict[str, str]) -> list[tuple[int, str]]:
        """Messages for conditions that start or clear in this step; updates the counters."""
        msgs = []
        for key, text in found.items():
            if key in self.active:
                self.active[key] += 1
            else:
                self.active[key] = 1
                bit = STATUS_BITS[key.partition(":")[0]]
                msgs.append((WARNING, f"{text} (input_status bit {bit}; logged once until "
                                      f"it clears)"))
        for key in [k for k in self.active if k not in found]:
            n = self.active.pop(key)
            msgs.append((OK, f"input condition '{key}' cleared after {n} step(s)"))
        return msgs

    # -- state (part of the FMU state) -------------------------------------------------------
    def get_state(self) -> dict[str, Any]:
        """Last finite inputs and active conditions (copies)."""
        return {"last": list(self.last), "active": dict(self.active)}

    def set_state(self, state: dict[str, Any]) -> None:
        """Restore :meth:`get_state`."""
        last = [float(v) for v in state["last"]]
        if len(last) != len(NAMES):
            raise ValueError(f"input guard state has {len(last)} inputs, expected "
                             f"{len(NAMES)}")
        self.last = last
        self.active = {str(k): int(v) for k, v in state["active"].items()}


class ModelConditions:
    """Conditions of the model's own step (module docstring): the tire core's flags as
    ``input_status`` bits, with a message when a condition starts (warning) and when it
    clears (with the number of steps it lasted), like :class:`InputGuard`'s."""

    _TEXT: ClassVar[dict[str, str]] = {
        "work_budget": ("the element integrator's work budget of an outer step was spent: "
                        "its remaining elements finished it with one implicit Euler stage "
                        "(docs/tire-core.md, \"work budget\")"),
        "temperature_range": ("the friction was read at a temperature outside the friction "
                              "grid's temperature range [{T_min:g}, {T_max:g}] K, at its "
                              "edge's values (T_tread = {T:g} K)"),
    }

    def __init__(self, T_min: float, T_max: float) -> None:
        self.T_range = (float(T_min), float(T_max))
        #: active conditions: key -> number of steps it has lasted
        self.active: dict[str, int] = {}

    def apply(self, flags: int, T: float) -> tuple[int, list[tuple[int, str]]]:
        """Status bits and messages of a step whose core flags are ``flags`` and tread
        temperature (the friction's, at its end) ``T`` [K]."""
        found = [key for bit, key in MODEL_FLAGS.items() if flags & bit]
        bits = 0
        for key in found:
            bits |= STATUS_BITS[key]
        msgs = []
        for key in found:
            if key in self.active:
                self.active[key] += 1
            else:
                self.active[key] = 1
                text = self._TEXT[key].format(T_min=self.T_range[0], T_max=self.T_range[1],
                                              T=T)
                msgs.append((WARNING, f"{text} (input_status bit {STATUS_BITS[key]}; logged "
                                      f"once until it clears)"))
        for key in [k for k in self.active if k not in found]:
            n = self.active.pop(key)
            msgs.append((OK, f"model condition '{key}' cleared after {n} step(s)"))
        return bits, msgs

    def get_state(self) -> dict[str, int]:
        """Active conditions (a copy)."""
        return dict(self.active)

    def set_state(self, state: dict[str, int]) -> None:
        """Restore :meth:`get_state`."""
        self.active = {str(k): int(v) for k, v in state.items()}
