r"""Road roughness: the 2D isotropic power spectrum C(q) and the large-wavenumber cut-off q1.

Convention (review sec. 4, docs/review-notes.md, Trap 4):
:math:`C(q) = (2\pi)^{-2}\int d^2x\,\langle h(\mathbf{x})h(\mathbf{0})\rangle
e^{-i\mathbf{q}\cdot\mathbf{x}}`,
so that :math:`h_{rms}^2 = 2\pi\int q\,C(q)\,dq` and the cumulative rms slope is
:math:`\xi^2(q) = 2\pi\int_{q_0}^{q} q'^3 C(q')\,dq'`.

Spectra:

* :class:`SelfAffinePSD`: self-affine fractal with roll-off. ``C = C0`` for
  ``q0 <= q < q_r`` and ``C = C0 (q/q_r)^(-2(H+1))`` for ``q >= q_r``; zero below q0.
* :class:`TabulatedPSD`: measured C(q) (CSV), log-log interpolation, zero outside the data.

The cut-off q1 (docs/review-notes.md, Trap 6) is chosen by an explicit :class:`CutoffRule`: by
default the wavenumber where the cumulative rms slope reaches ``xi1 = 1`` (review sec. 5.1, "Open
problems"); or a fixed value. The rule and the resolved q1 are stored with every result.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

from tirefric.errors import InputError


class PowerSpectrum(Protocol):
    """A 2D isotropic roughness power spectrum."""

    q0: float
    q_max: float

    def C(self, q: np.ndarray) -> np.ndarray:
        """Power spectrum C(q) [m^4] at wavenumber q [1/m]."""
        ...

    def describe(self) -> dict:
        ...


@dataclass(frozen=True)
class SelfAffinePSD:
    """Self-affine power spectrum with roll-off.

    Attributes
    ----------
    q0 : float
        Smallest wavenumber with roughness [1/m].
    q_r : float
        Roll-off wavenumber [1/m], ``q_r >= q0``.
    H : float
        Hurst exponent, ``0 < H < 1``.
    C0 : float
        Plateau value of C(q) [m^4] for ``q0 <= q < q_r``.
    """

    q0: float
    q_r: float
    H: float
    C0: float
    q_max: float = np.inf

    def __post_init__(self) -> None:
        if not self.q0 > 0:
            raise InputError("must be > 0", field="psd.q0", value=self.q0)
        if not self.q_r >= self.q0:
            raise InputError("roll-off must be >= q0", field="psd.q_r", value=self.q_r)
        if not 0 < self.H < 1:
            raise InputError("Hurst exponent must be in (0, 1)", field="psd.H", value=self.H)
        if not self.C0 > 0:
            raise InputError("must be > 0", field="psd.C0", value=self.C0)

    @classmethod
    def from_h_rms(cls, q0: float, q_r: float, H: float, h_rms: float) -> SelfAffinePSD:
        """Spectrum with the given rms height [m] (integrated over q0..infinity)."""
        if not h_rms > 0:
            raise InputError("must be > 0", field="psd.h_rms", value=h_rms)
        unit = cls(q0, q_r, H, 1.0)
        return cls(q0, q_r, H, h_rms**2 / unit.h_rms_squared())

    def C(self, q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, float)
        tail = self.C0 * (np.maximum(q, self.q_r) / self.q_r) ** (-2.0 * (self.H + 1.0))
        return np.where(q < self.q0, 0.0, np.where(q < self.q_r, self.C0, tail))

    def h_rms_squared(self) -> float:
        """h_rms^2 = 2 pi int q C dq over q0..infinity, closed form [m^2]."""
        flat = 0.5 * (self.q_r**2 - self.q0**2)
        tail = self.q_r**2 / (2.0 * self.H)
        return 2.0 * np.pi * self.C0 * (flat + tail)

    def xi_squared(self, q: np.ndarray) -> np.ndarray:
        """Cumulative mean-square slope xi^2(q) = 2 pi int_q0^q q'^3 C dq', closed form."""
        q = np.asarray(q, float)
        qa = np.clip(q, self.q0, self.q_r)
        flat = 0.25 * (qa**4 - self.q0**4)
        qb = np.maximum(q, self.q_r)
        e = 2.0 - 2.0 * self.H
        tail = self.q_r ** (2 * self.H + 2) * (qb**e - self.q_r**e) / e
        return 2.0 * np.pi * self.C0 * (flat + tail)

    def describe(self) -> dict:
        return {"model": "self_affine", "q0_per_m": self.q0, "q_r_per_m": self.q_r,
                "H": self.H, "C0_m4": self.C0, "h_rms_m": float(np.sqrt(self.h_rms_squared()))}


@dataclass(frozen=True)
class TabulatedPSD:
    """Measured C(q), interpolated linearly in log C vs log q; zero outside the data.

    Attributes
    ----------
    q : numpy.ndarray
        Wavenumbers [1/m], strictly increasing, > 0.
    C_values : numpy.ndarray
        C(q) [m^4], > 0.
    """

    q: np.ndarray
    C_values: np.ndarray
    source: str = ""

    def __post_init__(self) -> None:
        q = np.asarray(self.q, float)
        c = np.asarray(self.C_values, float)
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "C_values", c)
        src = self.source or None
        if q.size < 2 or q.shape != c.shape:
            raise InputError("C(q) table needs >= 2 rows of (q, C)", source=src)
        if not (np.diff(q) > 0).all() or (q <= 0).any():
            raise InputError("wavenumbers must be > 0 and strictly increasing", source=src,
                             field="q")
        if (c <= 0).any():
            i = int(np.flatnonzero(c <= 0)[0])
            raise InputError("C(q) must be > 0", source=src, field="C", value=float(c[i]))

    @property
    def q0(self) -> float:  # type: ignore[override]
        return float(self.q[0])

    @property
    def q_max(self) -> float:  # type: ignore[override]
        return float(self.q[-1])

    def C(self, q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, float)
        lc = np.interp(np.log(np.maximum(q, 1e-300)), np.log(self.q), np.log(self.C_values))
        inside = (q >= self.q[0]) & (q <= self.q[-1])
        return np.where(inside, np.exp(lc), 0.0)

    def describe(self) -> dict:
        return {"model": "tabulated", "source": self.source, "q_per_m": self.q.tolist(),
                "C_m4": self.C_values.tolist()}


def xi_squared_numeric(psd: PowerSpectrum, q: np.ndarray, points_per_decade: int = 200
                       ) -> np.ndarray:
    """Cumulative mean-square slope xi^2(q) by quadrature (any spectrum), review sec. 4."""
    q = np.atleast_1d(np.asarray(q, float))
    top = float(np.max(q))
    n = max(int(np.log10(top / psd.q0) * points_per_decade), 2) + 1
    qq = np.geomspace(psd.q0, top, n)
    f = 2.0 * np.pi * qq**4 * psd.C(qq)  # integrand in d(ln q)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(np.log(qq)))])
    return np.interp(np.log(q), np.log(qq), cum, left=0.0)


@dataclass(frozen=True)
class CutoffRule:
    """Rule for the large-wavenumber cut-off q1 (docs/review-notes.md, Trap 6).

    Attributes
    ----------
    rule : {"rms_slope", "fixed"}
        ``"rms_slope"``: q1 is where the cumulative rms slope xi(q1) reaches ``xi1``
        (review sec. 5.1: xi ~ 1, typically q1 ~ 1e6 1/m on roads). ``"fixed"``: q1 = ``q1``.
    xi1 : float
        Target rms slope for ``"rms_slope"``.
    q1 : float or None
        Fixed cut-off [1/m] for ``"fixed"``.
    """

    rule: Literal["rms_slope", "fixed"] = "rms_slope"
    xi1: float = 1.0
    q1: float | None = None

    def __post_init__(self) -> None:
        if self.rule not in ("rms_slope", "fixed"):
            raise InputError("must be 'rms_slope' or 'fixed'", field="cutoff.rule",
                             value=self.rule)
        if self.rule == "rms_slope" and not self.xi1 > 0:
            raise InputError("must be > 0", field="cutoff.xi1", value=self.xi1)
        if self.rule == "fixed" and (self.q1 is None or not np.isfinite(self.q1)):
            raise InputError("fixed rule needs a finite q1", field="cutoff.q1", value=self.q1)

    def resolve(self, psd: PowerSpectrum) -> float:
        """The cut-off q1 [1/m] for ``psd``; an error if it lies outside the spectrum."""
        if self.rule == "fixed":
            q1 = float(self.q1)  # type: ignore[arg-type]
            if not q1 > psd.q0:
                raise InputError(f"q1 must exceed q0 = {psd.q0:g} 1/m", field="cutoff.q1",
                                 value=q1)
            if q1 > psd.q_max * (1 + 1e-12):
                raise InputError(f"q1 beyond the spectrum's data (q_max = {psd.q_max:g} 1/m)",
                                 field="cutoff.q1", value=q1)
            return q1
        target = self.xi1**2
        if isinstance(psd, SelfAffinePSD):
            def xi2(q: np.ndarray) -> np.ndarray:
                return psd.xi_squared(q)
        else:
            def xi2(q: np.ndarray) -> np.ndarray:
                return xi_squared_numeric(psd, q)
        top = psd.q_max if np.isfinite(psd.q_max) else psd.q0 * 1e12
        qs = np.geomspace(psd.q0, top, 2001)
        x = xi2(qs)
        if x[-1] < target:
            raise InputError(f"the spectrum never reaches rms slope {self.xi1:g} "
                             f"(xi = {np.sqrt(x[-1]):.3g} at q = {top:.3g} 1/m); "
                             "use a fixed q1", field="cutoff.xi1", value=self.xi1)
        i = int(np.searchsorted(x, target))
        lo, hi = np.log(qs[max(i - 1, 0)]), np.log(qs[i])
        for _ in range(60):  # bisection in log q to machine-level precision
            mid = 0.5 * (lo + hi)
            if xi2(np.array([np.exp(mid)]))[0] < target:
                lo = mid
            else:
                hi = mid
        return float(np.exp(0.5 * (lo + hi)))

    def describe(self) -> dict:
        return {"rule": self.rule, "xi1": self.xi1, "q1_per_m": self.q1}
