"""Roads whose friction changes along the stop: a friction factor against travelled distance.

A :class:`MuProfile` is piecewise constant in the distance ``x`` travelled since the brake
was hit: ``factors[i]`` for ``positions[i] <= x < positions[i + 1]`` (the last factor to the
end). It multiplies the friction of the force map (:func:`.simulation.simulate_braking`) and
is the FMU's ``mu_scale`` input (:func:`fmu_src.host.cosim.simulate_braking_fmu`), so the same
road brakes the car through the map and through the FMU: a patch of lower friction (water,
ice, polished stones) scales the whole mu-slip curve. That is an approximation: a wet or icy
patch changes the curve's shape too (docs/physics.md), which a grid of that road would give.
"""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass

from tirefric.errors import InputError


@dataclass(frozen=True)
class MuProfile:
    """Friction factor against travelled distance (module docstring).

    Attributes
    ----------
    positions : tuple of float
        Distances where a section starts [m], ascending, the first 0.
    factors : tuple of float
        Friction factor of each section [1], > 0.
    """

    positions: tuple[float, ...]
    factors: tuple[float, ...]

    def __post_init__(self) -> None:
        pos = tuple(float(x) for x in self.positions)
        fac = tuple(float(x) for x in self.factors)
        if len(pos) != len(fac) or not pos or pos[0] != 0.0 or \
                any(not (b > a) for a, b in itertools.pairwise(pos)) or \
                not all(math.isfinite(x) for x in pos):
            raise InputError("need ascending section starts from 0 m, one factor each",
                             field="road.positions", value=self.positions)
        if not all(math.isfinite(f) and f > 0.0 for f in fac):
            raise InputError("friction factors must be finite and > 0", field="road.factors",
                             value=self.factors)
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "factors", fac)

    @classmethod
    def uniform(cls, factor: float = 1.0) -> MuProfile:
        """The same friction everywhere."""
        return cls((0.0,), (factor,))

    @classmethod
    def patch(cls, start: float, end: float, factor: float, base: float = 1.0) -> MuProfile:
        """A section ``[start, end)`` [m] of friction factor ``factor`` on a road of ``base``:
        the mu-jump from high to low and back."""
        if not (0.0 < start < end):
            raise InputError("need 0 < start < end", field="road.patch", value=(start, end))
        return cls((0.0, start, end), (base, factor, base))

    def __call__(self, x: float) -> float:
        """Friction factor at distance ``x`` [m]."""
        i = bisect.bisect_right(self.positions, x) - 1
        return self.factors[max(i, 0)]

    def describe(self) -> list[dict[str, float]]:
        """Sections as ``{"from_m", "factor"}`` records (for results files)."""
        return [{"from_m": p, "factor": f} for p, f in zip(self.positions, self.factors,
                                                             strict=True)]
