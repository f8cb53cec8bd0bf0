r"""Strain softening of filled rubber, review eq. (6).

:math:`\mathrm{Re}\,E_{\rm eff} = E_R(\omega, T)\,\eta_R(\epsilon)`,
:math:`\mathrm{Im}\,E_{\rm eff} = E_I(\omega, T)\,\eta_I(\epsilon)`, both factors normalised to 1
at small strain. The compound states the strain at which they are applied.

* :class:`NoSoftening`: eta_R = eta_I = 1.
* :class:`KrausSoftening`: Kraus' model of the Payne effect (G. Kraus, J. Appl. Polym. Sci.
  Appl. Polym. Symp. 39 (1984) 75; form as in Ulmer, Rubber Chem. Technol. 69 (1996) 15),
  normalised by the small-strain values.
* :class:`TabulatedSoftening`: eta_R(eps), eta_I(eps) measured, interpolated in log10 eps.
* :class:`StrainSweepSoftening`: measured strain sweeps, one per temperature, as the ratios
  of E' and E'' to their values at the sweep's smallest strain; eta_R(eps, T) and
  eta_I(eps, T), linear in T between the sweeps' temperatures (held at the nearest sweep
  outside them). With one sweep (or no temperature column) it is the tabulated law.

A law whose factors depend on the temperature says so with ``varies_with_T = True`` and
gives them with ``factors_at(strain, T)`` (vectorised in T); the friction engine then applies
them at the temperature each roughness scale feels (:mod:`lookup.friction`). The other laws
have ``factors(strain)`` only (:func:`varies_with_T`).
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


def varies_with_T(softening: Softening) -> bool:
    """Whether a softening law's factors depend on the temperature (module docstring)."""
    return bool(getattr(softening, "varies_with_T", False))


def factors_at(softening: Softening, strain: float, T: np.ndarray | float
               ) -> tuple[np.ndarray, np.ndarray]:
    """(eta_R, eta_I) of any law at ``strain`` [1] and temperatures ``T`` [K] (any shape)."""
    T = np.asarray(T, float)
    if varies_with_T(softening):
        return softening.factors_at(strain, T)  # type: ignore[attr-defined]
    R, I_ = softening.factors(strain)
    return np.full(T.shape, R), np.full(T.shape, I_)


@dataclass(frozen=True)
class StrainSweepSoftening:
    r"""Strain softening from measured strain sweeps, one per temperature (review eq. 6).

    Each sweep gives :math:`\eta_R(\epsilon) = E'(\epsilon)/E'(\epsilon_0)` and
    :math:`\eta_I(\epsilon) = E''(\epsilon)/E''(\epsilon_0)` with :math:`\epsilon_0` its
    smallest strain (the small-strain values of review eq. 6), or the ratios as the file
    states them. Between strains: linear in log10 eps, held at the sweep's ends outside it
    (as :class:`TabulatedSoftening`). Between temperatures: linear in T of the factors at the
    strain asked for; below the lowest and above the highest sweep temperature the nearest
    sweep's factors are used (held, not extrapolated: the Payne ratios of tread compounds
    change slowly with T, and a linear extrapolation could leave the range of
    the data). The strain
    sweep is taken as valid at every frequency (review eq. 6 factors do not depend on omega).

    Attributes
    ----------
    T : numpy.ndarray
        Sweep temperatures [K], strictly increasing; empty when the file has no temperature
        column (one sweep, valid at every temperature).
    strain : tuple of numpy.ndarray
        Strain amplitudes [1] of each sweep, strictly increasing, > 0.
    eta_R, eta_I : tuple of numpy.ndarray
        The factors of each sweep, > 0.
    source : str
        The file the sweeps came from.
    columns : str
        How the file's columns were read (moduli or ratios), for :meth:`describe`.
    """

    T: np.ndarray
    strain: tuple[np.ndarray, ...]
    eta_R: tuple[np.ndarray, ...]
    eta_I: tuple[np.ndarray, ...]
    source: str = ""
    columns: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        T = np.atleast_1d(np.asarray(self.T, float))
        object.__setattr__(self, "T", T)
        n = len(self.strain)
        if n == 0 or len(self.eta_R) != n or len(self.eta_I) != n or T.size not in (0, n) or (
                T.size == 0 and n != 1):
            raise InputError("strain sweeps need one temperature per sweep (or one sweep "
                             "without a temperature)", source=src, field="T")
        if T.size > 1 and not (np.diff(T) > 0).all():
            raise InputError("sweep temperatures must be strictly increasing", source=src,
                             field="T")
        for name in ("strain", "eta_R", "eta_I"):
            object.__setattr__(self, name, tuple(np.asarray(a, float) for a in
                                                 getattr(self, name)))
        for k in range(n):
            at = f" (sweep at {T[k] - 273.15:g} C)" if T.size else ""
            e = self.strain[k]
            if e.size < 2 or not (np.diff(e) > 0).all() or (e <= 0).any():
                raise InputError(f"a strain sweep needs >= 2 strains > 0, strictly "
                                 f"increasing{at}", source=src, field="strain")
            if self.eta_R[k].shape != e.shape or self.eta_I[k].shape != e.shape:
                raise InputError(f"columns of unequal length{at}", source=src)
            if (self.eta_R[k] <= 0).any() or (self.eta_I[k] <= 0).any():
                raise InputError(f"softening factors must be > 0{at}", source=src)

    @property
    def varies_with_T(self) -> bool:
        """True with sweeps at two or more temperatures."""
        return self.T.size > 1

    def _at_strain(self, strain: float) -> tuple[np.ndarray, np.ndarray]:
        """Each sweep's (eta_R, eta_I) at ``strain``, shape (n_sweeps,)."""
        ls = np.log10(strain)
        R = np.array([np.interp(ls, np.log10(e), r)
                      for e, r in zip(self.strain, self.eta_R, strict=True)])
        I_ = np.array([np.interp(ls, np.log10(e), i)
                       for e, i in zip(self.strain, self.eta_I, strict=True)])
        return R, I_

    def factors(self, strain: float, T: float | None = None) -> tuple[float, float]:
        """(eta_R, eta_I) at ``strain`` [1] and, for sweeps at several temperatures, ``T`` [K]."""
        if self.varies_with_T and T is None:
            raise InputError("these strain sweeps depend on the temperature: give T",
                             source=self.source or None, field="softening")
        R, I_ = self.factors_at(strain, np.asarray(0.0 if T is None else T, float))
        return float(R), float(I_)

    def factors_at(self, strain: float, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(eta_R, eta_I) at ``strain`` [1] and temperatures ``T`` [K] (any shape)."""
        R, I_ = self._at_strain(strain)
        T = np.asarray(T, float)
        if not self.varies_with_T:
            return np.full(T.shape, R[0]), np.full(T.shape, I_[0])
        return np.interp(T, self.T, R), np.interp(T, self.T, I_)

    def describe(self) -> dict:
        return {"model": "strain_sweep", "source": self.source, "columns": self.columns,
                "T_K": self.T.tolist(), "strain": [e.tolist() for e in self.strain],
                "eta_R": [r.tolist() for r in self.eta_R],
                "eta_I": [i.tolist() for i in self.eta_I],
                "between_temperatures": "linear in T; held at the nearest sweep outside"}
