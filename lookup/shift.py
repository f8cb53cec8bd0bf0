r"""Temperature shift factors a_T(T): E(omega, T) = E(omega a_T(T), T_ref).

* :class:`WLF`, review eq. (5) with its own reference temperature,
  :math:`\log_{10} a_T = -C_1 (T - T_r)/(C_2 + T - T_r)`. The universal constants
  C1 = 17.44, C2 = 51.6 K hold only with T_r = T_g (docs/review-notes.md, Trap 5).
* :class:`TabulatedShift`, log10 a_T(T) measured, interpolated linearly in T.
* :class:`Arrhenius`, review eq. (22), :math:`\ln a_T = (\epsilon/k_B)(1/T - 1/T_r)`, used for
  the adhesive shear law.

All temperatures are in kelvin. ``a_T < 1`` above the reference temperature.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from tirefric.errors import InputError

K_B = 1.380649e-23  # Boltzmann constant [J/K]


class ShiftFactor(Protocol):
    """A shift factor with its own reference temperature."""

    T_ref: float

    def log10_aT(self, T: np.ndarray) -> np.ndarray:
        """log10 a_T at temperature ``T`` [K]."""
        ...

    def describe(self) -> dict:
        """Parameters as a JSON-able dict."""
        ...


@dataclass(frozen=True)
class WLF:
    """Williams-Landel-Ferry shift, review eq. (5).

    Attributes
    ----------
    C1 : float
        Dimensionless constant.
    C2 : float
        Constant [K].
    T_ref : float
        Reference temperature of the constants [K].

    Notes
    -----
    The law diverges at T = T_ref - C2. Below ``T_ref - 0.9 C2`` the law is not used: it is
    continued linearly in T with the slope it has there (stated, bounded behaviour far below
    any tire operating point).
    """

    C1: float
    C2: float
    T_ref: float

    def __post_init__(self) -> None:
        if not (self.C1 > 0 and self.C2 > 0 and self.T_ref > 0):
            raise InputError("WLF needs C1 > 0, C2 > 0 K, T_ref > 0 K", field="shift",
                             value=(self.C1, self.C2, self.T_ref))

    def log10_aT(self, T: np.ndarray) -> np.ndarray:
        T = np.asarray(T, float)
        dT = T - self.T_ref
        d_min = -0.9 * self.C2
        dTc = np.maximum(dT, d_min)
        val = -self.C1 * dTc / (self.C2 + dTc)
        slope = -self.C1 * self.C2 / (self.C2 + d_min) ** 2
        return np.where(dT < d_min, val + slope * (dT - d_min), val)

    def describe(self) -> dict:
        return {"model": "wlf", "C1": self.C1, "C2_K": self.C2, "T_ref_K": self.T_ref}


@dataclass(frozen=True)
class TabulatedShift:
    """Measured log10 a_T(T), linear in T between the points.

    Outside the table the end segments are continued linearly (log10 a_T linear in T), which
    is how such tables are usually extended; the range is part of the provenance.
    """

    T: np.ndarray
    log10_a: np.ndarray
    T_ref: float
    source: str = ""

    def __post_init__(self) -> None:
        T = np.asarray(self.T, float)
        la = np.asarray(self.log10_a, float)
        object.__setattr__(self, "T", T)
        object.__setattr__(self, "log10_a", la)
        if T.size < 2 or T.shape != la.shape:
            raise InputError("a_T table needs >= 2 rows of (T, log10 a_T)",
                             source=self.source or None)
        if not (np.diff(T) > 0).all():
            raise InputError("temperature column must be strictly increasing",
                             source=self.source or None, field="T")

    def log10_aT(self, T: np.ndarray) -> np.ndarray:
        T = np.asarray(T, float)
        x, y = self.T, self.log10_a
        out = np.interp(T, x, y)
        s0 = (y[1] - y[0]) / (x[1] - x[0])
        s1 = (y[-1] - y[-2]) / (x[-1] - x[-2])
        out = np.where(T < x[0], y[0] + s0 * (T - x[0]), out)
        return np.where(T > x[-1], y[-1] + s1 * (T - x[-1]), out)

    def describe(self) -> dict:
        return {"model": "tabulated", "source": self.source, "T_K": self.T.tolist(),
                "log10_aT": self.log10_a.tolist(), "T_ref_K": self.T_ref}


@dataclass(frozen=True)
class Arrhenius:
    """Arrhenius shift, review eq. (22): ln a_T = (epsilon / k_B) (1/T - 1/T_ref).

    Attributes
    ----------
    activation_energy : float
        epsilon [J] (the review: about 1 eV).
    T_ref : float
        Reference temperature [K].
    """

    activation_energy: float
    T_ref: float

    def __post_init__(self) -> None:
        if not (self.activation_energy > 0 and self.T_ref > 0):
            raise InputError("Arrhenius needs activation energy > 0 and T_ref > 0",
                             field="adhesion.shift")

    def log10_aT(self, T: np.ndarray) -> np.ndarray:
        T = np.asarray(T, float)
        return (self.activation_energy / K_B) * (1.0 / T - 1.0 / self.T_ref) / np.log(10.0)

    def describe(self) -> dict:
        return {"model": "arrhenius", "activation_energy_J": self.activation_energy,
                "T_ref_K": self.T_ref}


def relative_log10_aT(shift: ShiftFactor, T: np.ndarray, T_master: float) -> np.ndarray:
    """log10 of the shift from ``T_master`` (the master curve's temperature) to ``T``."""
    return shift.log10_aT(T) - shift.log10_aT(np.asarray(T_master, float))
