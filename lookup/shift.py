r"""Temperature shift factors a_T(T): E(omega, T) = E(omega a_T(T), T_ref).

* :class:`WLF`, review eq. (5) with its own reference temperature,
  :math:`\log_{10} a_T = -C_1 (T - T_r)/(C_2 + T - T_r)`. The universal constants
  C1 = 17.44, C2 = 51.6 K hold only with T_r = T_g (docs/review-notes.md, Trap 5).
* :class:`TabulatedShift`, log10 a_T(T) measured, interpolated linearly in T.
* :class:`Arrhenius`, review eq. (22), :math:`\ln a_T = (\epsilon/k_B)(1/T - 1/T_r)`, used for
  the adhesive shear law.

All temperatures are in kelvin. ``a_T < 1`` above the reference temperature.

A master curve is measured at the temperature where its own shift factor is 1: the
compound's loader checks that the master curve's T_ref is where the table (or the WLF law)
has a_T = 1, to :data:`T_REF_TOLERANCE` (:meth:`TabulatedShift.unit_temperature`,
docs/engine-inputs.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from tirefric.errors import InputError

K_B = 1.380649e-23  # Boltzmann constant [J/K]

#: How far [K] the master curve's stated T_ref may lie from where its shift factor is 1. A
#: reference temperature is written to the whole degree (a stated "40 C" stands for
#: 39.5-40.5 C; measured tables put a_T = 1 at the oven's reading, e.g. 39.96 C), and 0.5 K
#: moves the master curve by |d log10 a_T/dT| x 0.5 K = 0.02-0.1 decades of frequency
#: (|d log10 a_T/dT| = C1/C2 = 0.04-0.2 per K for WLF fits at 20-40 C with C1 ~ 10-25,
#: C2 ~ 130-260 K, docs/review-notes.md), less than the spacing of the points of a measured
#: master curve (5-10 per decade). A larger mismatch is a wrong T_ref: a table at 40 C read
#: as 20 C moves the curve by 1-4 decades.
T_REF_TOLERANCE = 0.5


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

    def unit_temperature(self, near: float | None = None) -> float | None:
        """The temperature [K] where the table has a_T = 1 (log10 a_T = 0), linear in T
        between its points and along the continued end segments (as :meth:`log10_aT`).

        A table that crosses 1 several times (measurement noise) gives the crossing nearest
        ``near`` (default: the first); one that never does gives None."""
        x, y = self.T, self.log10_a
        hits: list[float] = []
        for i in range(x.size - 1):
            a, b = y[i], y[i + 1]
            if a == 0.0:
                hits.append(float(x[i]))
            elif a * b < 0.0:
                hits.append(float(x[i] - a * (x[i + 1] - x[i]) / (b - a)))
        if y[-1] == 0.0:
            hits.append(float(x[-1]))
        for end, nb, out in ((0, 1, -1.0), (-1, -2, 1.0)):
            slope = (y[end] - y[nb]) / (x[end] - x[nb])
            if slope != 0.0 and y[end] != 0.0:
                t = float(x[end] - y[end] / slope)
                if (t - x[end]) * out > 0.0:
                    hits.append(t)
        if not hits:
            return None
        ref = hits[0] if near is None else near
        return min(hits, key=lambda t: abs(t - ref))

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
