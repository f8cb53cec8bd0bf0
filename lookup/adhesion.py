r"""Frictional shear stress sigma_f(v, T) in the area of real contact.

:class:`GaussianShearLaw` is the empirical law of review eq. (21),
:math:`\sigma_f(v) = \sigma_{f0} \exp(-c [\log_{10}(v/v^*)]^2)`, valid at T_ref; at another
temperature v is replaced by v a'_T(T) (review text after eq. 21), with a'_T either the
Arrhenius law of eq. (22) or the compound's bulk viscoelastic a_T. Its full width at half
maximum in log10 v is :math:`2\sqrt{\ln 2 / c}` decades (about 4 for c = 0.17).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from tirefric.errors import InputError

from .shift import ShiftFactor


class ShearLaw(Protocol):
    def sigma_f(self, v: np.ndarray, T: np.ndarray) -> np.ndarray:
        """Shear stress [Pa] at sliding speed ``v`` [m/s] and temperature ``T`` [K]."""
        ...

    def describe(self) -> dict:
        ...


@dataclass(frozen=True)
class GaussianShearLaw:
    """Review eq. (21) with the temperature shift of eq. (22) or the bulk a_T.

    Attributes
    ----------
    sigma_f0 : float
        Peak shear stress [Pa] (review: 4-8 MPa for passenger tread rubber).
    c : float
        Width parameter (review: about 0.17).
    v_star : float
        Speed of the maximum at T_ref [m/s] (review: about 1 cm/s at 20 C).
    T_ref : float
        Temperature at which v_star holds [K].
    shift : ShiftFactor
        a'_T used to shift v: :class:`~lookup.shift.Arrhenius` (eq. 22) or the bulk a_T.
    """

    sigma_f0: float
    c: float
    v_star: float
    T_ref: float
    shift: ShiftFactor

    def __post_init__(self) -> None:
        if not (self.sigma_f0 >= 0 and self.c > 0 and self.v_star > 0 and self.T_ref > 0):
            raise InputError("eq. (21) needs sigma_f0 >= 0, c > 0, v_star > 0, T_ref > 0",
                             field="adhesion")

    def sigma_f(self, v: np.ndarray, T: np.ndarray) -> np.ndarray:
        v = np.maximum(np.abs(np.asarray(v, float)), 1e-300)
        la = self.shift.log10_aT(T) - self.shift.log10_aT(np.asarray(self.T_ref))
        x = np.log10(v / self.v_star) + la
        return self.sigma_f0 * np.exp(-self.c * x * x)

    def fwhm_decades(self) -> float:
        """Full width at half maximum of sigma_f(log10 v) [decades] (review after eq. 21)."""
        return 2.0 * np.sqrt(np.log(2.0) / self.c)

    def describe(self) -> dict:
        return {"model": "gaussian_eq21", "sigma_f0_Pa": self.sigma_f0, "c": self.c,
                "v_star_m_s": self.v_star, "T_ref_K": self.T_ref,
                "shift": self.shift.describe()}


@dataclass(frozen=True)
class NoAdhesion:
    """sigma_f = 0: friction from viscoelastic hysteresis only (e.g. a wet road)."""

    def sigma_f(self, v: np.ndarray, T: np.ndarray) -> np.ndarray:
        return np.zeros(np.broadcast(np.asarray(v), np.asarray(T)).shape)

    def describe(self) -> dict:
        return {"model": "none"}
