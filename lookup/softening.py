r"""Strain softening of filled rubber, review eq. (6).

:math:`\mathrm{Re}\,E_{\rm eff} = E_R(\omega, T)\,\eta_R(\epsilon)`,
:math:`\mathrm{Im}\,E_{\rm eff} = E_I(\omega, T)\,\eta_I(\epsilon)`, both factors normalised to 1
at small strain. The compound states the strain at which they are applied.

* :class:`NoSoftening`: eta_R = eta_I = 1.
* :class:`KrausSoftening`: Kraus' model of the Payne effect (G. Kraus, J. Appl. Polym. Sci.
  Appl. Polym. Symp. 39 (1984) 75; form as in Ulmer, Rubber Chem. Technol. 69 (1996) 15),
  normalised by the small-strain values.
* :class:`TabulatedSoftening`: eta_R(eps), eta_I(eps) measured, interpolated in log10 eps.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from tirefric.errors import InputError


class Softening(Protocol):
    def factors(self, strain: float) -> tuple[float, float]:
        """(eta_R, eta_I) at ``strain`` [1]."""
        ...

    def describe(self) -> dict:
        ...


@dataclass(frozen=True)
class NoSoftening:
    """Linear response: no strain softening."""

    def factors(self, strain: float) -> tuple[float, float]:
        return 1.0, 1.0

    def describe(self) -> dict:
        return {"model": "none"}


@dataclass(frozen=True)
class KrausSoftening:
    r"""Kraus-type Payne-effect law, normalised to the small-strain modulus.

    With :math:`x = (\epsilon/\epsilon_c)^{m}`:
    :math:`\eta_R = r_\infty + (1 - r_\infty)/(1 + x^2)` and
    :math:`\eta_I = 1 + 2 (h - 1)\, x/(1 + x^2)`.

    Attributes
    ----------
    eps_c : float
        Characteristic strain [1].
    m : float
        Kraus exponent (about 0.5-0.6 for carbon-black filled rubber).
    r_inf : float
        eta_R at very large strain (E'_inf / E'_0), in (0, 1].
    h : float
        Peak value of eta_I (reached at eps = eps_c); >= 1 for filled rubber.
    """

    eps_c: float
    m: float
    r_inf: float
    h: float

    def __post_init__(self) -> None:
        if not (self.eps_c > 0 and self.m > 0 and 0 < self.r_inf <= 1 and self.h > 0):
            raise InputError("Kraus softening needs eps_c > 0, m > 0, 0 < r_inf <= 1, h > 0",
                             field="softening")

    def factors(self, strain: float) -> tuple[float, float]:
        x = (strain / self.eps_c) ** self.m
        eta_R = self.r_inf + (1.0 - self.r_inf) / (1.0 + x * x)
        eta_I = 1.0 + 2.0 * (self.h - 1.0) * x / (1.0 + x * x)
        return float(eta_R), float(eta_I)

    def describe(self) -> dict:
        return {"model": "kraus", "eps_c": self.eps_c, "m": self.m, "r_inf": self.r_inf,
                "h": self.h}


@dataclass(frozen=True)
class TabulatedSoftening:
    """Measured eta_R(eps), eta_I(eps); linear in log10 eps, clamped at the table ends."""

    strain: np.ndarray
    eta_R: np.ndarray
    eta_I: np.ndarray
    source: str = ""

    def __post_init__(self) -> None:
        for nm in ("strain", "eta_R", "eta_I"):
            object.__setattr__(self, nm, np.asarray(getattr(self, nm), float))
        if self.strain.size < 2 or not (np.diff(self.strain) > 0).all() or (self.strain <= 0).any():
            raise InputError("strain column must be > 0 and strictly increasing",
                             source=self.source or None, field="strain")
        if (self.eta_R <= 0).any() or (self.eta_I <= 0).any():
            raise InputError("softening factors must be > 0", source=self.source or None)

    def factors(self, strain: float) -> tuple[float, float]:
        ls = np.log10(strain)
        x = np.log10(self.strain)
        return float(np.interp(ls, x, self.eta_R)), float(np.interp(ls, x, self.eta_I))

    def describe(self) -> dict:
        return {"model": "tabulated", "source": self.source, "strain": self.strain.tolist(),
                "eta_R": self.eta_R.tolist(), "eta_I": self.eta_I.tolist()}
