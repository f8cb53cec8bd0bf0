"""Wet roads: Persson friction with water (review sec. 5.2 and sec. 8).

* :mod:`lookup.wet.water` -- lubricants: water viscosity (temperature dependent), soapy water,
  custom lubricants; water-depth validation;
* :mod:`lookup.wet.sealing` -- the sealing effect: the water-smoothed spectrum C_wet(q) <= C(q);
* :mod:`lookup.wet.squeeze` -- squeeze-out: the dry share of the real contact after the time
  available, which weights the adhesive term;
* :mod:`lookup.wet.wetting` -- the forced-wetting speed of review eq. (38);
* :mod:`lookup.wet.friction` -- :class:`WetPerssonFriction`, the engine with all of it, cold
  and hot branch (and what is assumed about the flash temperature on a wet road).
"""

from __future__ import annotations

from .water import LUBRICANTS, Lubricant, check_water_depth, water_viscosity

__all__ = ["LUBRICANTS", "Lubricant", "check_water_depth", "water_viscosity"]
