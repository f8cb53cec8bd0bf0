r"""Lubricants on a wet road: viscosity, spreading pressure and what they do to adhesion.

Water viscosity. Vogel-type correlation

.. math:: \eta(T) = A \, 10^{B / (T - C)},\quad A = 2.414\times10^{-5}\ \mathrm{Pa\,s},\
          B = 247.8\ \mathrm{K},\ C = 140\ \mathrm{K},

(the form of Vogel, Phys. Z. 22 (1921) 645, with the constants quoted for liquid water in
Al-Shemmeri, *Engineering Fluid Mechanics* (Ventus, 2012), sec. 1.5, within 2.5 % over
0-370 C). Checked in the tests against the IAPWS 2008 reference formulation (Huber et al.,
J. Phys. Chem. Ref. Data 38 (2009) 101): 1.7914, 1.0016 and 0.6527 mPa s at 0, 20 and 40 C.

Lubricants (review sec. 5.2 and sec. 8):

* ``"water"``: the adhesive (real-contact) term survives where the water has been squeezed out
  of the asperity contacts (forced dewetting, review sec. 8: at low speed wet and dry friction
  agree); the share that is dry is :mod:`lookup.wet.squeeze`.
* ``"soapy_water"``: the adhesive term is off at every speed. The review's figure of rubber on
  asphalt in soapy water (sec. 5.2) agrees with the viscoelastic contribution alone: a soap
  film stabilised by electrical double layers separates the surfaces (sec. 8, Roberts' SDS
  experiment). Viscosity that of water.
* ``"custom"``: a lubricant given by its viscosity eta [Pa s] (temperature independent) and,
  optionally, its spreading pressure S [J/m^2] (review eq. 36). With S < 0 (dewetting) the
  contact is dry below the forced-wetting speed of review eq. (38)
  (:func:`lookup.wet.wetting.forced_wetting_speed`); with S > 0 a film separates the solids
  unless squeezed out (:mod:`lookup.wet.squeeze`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tirefric.errors import InputError

#: Constants of the Vogel-type water viscosity correlation (module docstring).
VOGEL_A_PA_S = 2.414e-5
VOGEL_B_K = 247.8
VOGEL_C_K = 140.0
#: Validity range of the correlation [K] (liquid water at ambient pressure).
WATER_T_RANGE_K = (273.15, 373.15)

LUBRICANTS: tuple[str, ...] = ("water", "soapy_water", "custom")


def water_viscosity(T: np.ndarray | float) -> np.ndarray:
    """Dynamic viscosity of liquid water [Pa s] at temperature ``T`` [K] (module docstring).

    Outside 0-100 C the temperature is clamped to that range (supercooled or superheated
    water is not modelled; a flash-heated interface above 100 C is held at the 100 C value).
    """
    T = np.clip(np.asarray(T, float), *WATER_T_RANGE_K)
    return VOGEL_A_PA_S * 10.0 ** (VOGEL_B_K / (T - VOGEL_C_K))


@dataclass(frozen=True)
class Lubricant:
    """The fluid on the road.

    Attributes
    ----------
    name : {"water", "soapy_water", "custom"}
    eta : float or None
        Viscosity [Pa s] of a ``"custom"`` lubricant (water and soapy water: the water law).
    S : float or None
        Spreading pressure [J/m^2] of review eq. (36) (``"custom"`` only; None: not given).
    """

    name: str = "water"
    eta: float | None = None
    S: float | None = None

    def __post_init__(self) -> None:
        if self.name not in LUBRICANTS:
            raise InputError(f"unknown lubricant (known: {', '.join(LUBRICANTS)})",
                             field="wet.lubricant", value=self.name)
        if self.name == "custom":
            if self.eta is None or not (math.isfinite(self.eta) and self.eta > 0):
                raise InputError("viscosity of a custom lubricant must be finite and > 0 "
                                 "[Pa s]", field="wet.eta", value=self.eta)
            if self.S is not None and not math.isfinite(self.S):
                raise InputError("spreading pressure must be finite [J/m^2]", field="wet.S",
                                 value=self.S)
        elif self.eta is not None or self.S is not None:
            raise InputError(f"eta and S are given only for a 'custom' lubricant, not for "
                             f"{self.name!r}", field="wet.eta" if self.eta is not None
                             else "wet.S", value=self.eta if self.eta is not None else self.S)

    @property
    def adhesion(self) -> bool:
        """Whether the adhesive term can survive at all (False for soapy water)."""
        return self.name != "soapy_water"

    def viscosity(self, T: np.ndarray | float) -> np.ndarray:
        """Viscosity [Pa s] at temperature ``T`` [K]."""
        if self.name == "custom":
            return np.full(np.shape(T), float(self.eta))
        return water_viscosity(T)

    def describe(self) -> dict:
        law = ("constant" if self.name == "custom" else
               f"water, Vogel: eta = {VOGEL_A_PA_S:g} Pa s * 10^({VOGEL_B_K:g} K/(T - "
               f"{VOGEL_C_K:g} K)) (Al-Shemmeri 2012; IAPWS 2008 within 2.5 %)")
        return {"name": self.name, "eta_Pa_s": self.eta, "S_J_m2": self.S,
                "viscosity_law": law, "adhesion": self.adhesion}


def check_water_depth(d: np.ndarray | float, source: str | None = None) -> np.ndarray:
    """Water film depths [m] as an array; negative or non-finite values are an InputError."""
    a = np.atleast_1d(np.asarray(d, float))
    bad = ~(np.isfinite(a) & (a >= 0))
    if bad.any():
        raise InputError("water film depth must be finite and >= 0 [m] (0 = dry)",
                         source=source, field="water_depth", value=float(a[bad][0]))
    return a
