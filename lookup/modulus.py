r"""Viscoelastic modulus E(omega) of a rubber compound at its reference temperature.

Convention (review eqs. 1-3): time dependence :math:`e^{-i\omega t}`, so the complex modulus is
:math:`E(\omega) = E_R(\omega) - i E_I(\omega)` and, for a passive material, ``Im E < 0`` for
``omega > 0``. This package works throughout with the **loss modulus** ``E_I = -Im E``, which is
``>= 0`` for ``omega > 0`` and odd in ``omega`` (docs/review-notes.md, Trap 1). ``E_R`` is even in
``omega``.

Three models of the small-strain master curve are provided:

* :class:`SingleRelaxation`, review eq. (4);
* :class:`Prony`, a generalised Maxwell (Prony) series;
* :class:`TabulatedMasterCurve`, a DMA master curve (omega, E', E'') interpolated log-log,
  with an explicit policy outside the measured band (no blind extrapolation).

All of them are turned into a :class:`ModulusTable` for the friction integrals: log10 E_R and
log10 E_I sampled on a uniform log10(omega) grid and interpolated linearly, with strain
softening (review eq. 6) applied. Evaluation is then a vectorised index computation, the
dominant cost of the Persson integrals.

A model that is known only on a measured band (the tabulated curve) says so: it has a
``measured_band`` (omega_min, omega_max) [rad/s] and a ``continued(omega)`` evaluation that
follows its stated continuation outside the band whatever its policy. The table keeps that
band, so that the friction engine can say which part of each result came from outside the
data and refuse, under ``outside = "error"``, only the results that need it
(:mod:`lookup.friction`, docs/engine-inputs.md). Analytic models (Prony, single relaxation)
have no band: they are defined at every frequency.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol

import numpy as np

from tirefric.errors import InputError


class Modulus(Protocol):
    """A small-strain viscoelastic modulus at the compound's reference temperature."""

    def storage_loss(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return (E_R, E_I) [Pa] at angular frequency ``omega`` [rad/s] (``omega > 0``)."""
        ...

    def describe(self) -> dict:
        """Parameters as a JSON-able dict (for grid provenance)."""
        ...


@dataclass(frozen=True)
class SingleRelaxation:
    r"""Single-relaxation-time solid, review eq. (4).

    :math:`1/E = 1/E_1 + (1/E_0 - 1/E_1) / (1 - i\omega\tau)`, equivalently
    :math:`E = E_1 - \Delta E/(1 - i\omega\tau')` with :math:`\Delta E = E_1 - E_0` and
    :math:`\tau' = \tau E_0/E_1` (docs/review-notes.md).

    Attributes
    ----------
    E0 : float
        Rubbery (low-frequency) modulus [Pa].
    E1 : float
        Glassy (high-frequency) modulus [Pa], ``E1 >= E0``. ``E1 == E0`` is the elastic limit
        (E real and constant, no loss): the case of review eq. (10).
    tau : float
        Relaxation time of eq. (4) [s].
    """

    E0: float
    E1: float
    tau: float

    def __post_init__(self) -> None:
        if not (self.E0 > 0 and self.E1 >= self.E0 and self.tau > 0):
            raise InputError("single relaxation needs 0 < E0 <= E1 and tau > 0",
                             field="modulus", value=(self.E0, self.E1, self.tau))

    def complex_modulus(self, omega: np.ndarray) -> np.ndarray:
        """Complex E(omega) with the review's sign convention (Im E < 0 for omega > 0)."""
        omega = np.asarray(omega, dtype=float)
        inv = 1.0 / self.E1 + (1.0 / self.E0 - 1.0 / self.E1) / (1.0 - 1j * omega * self.tau)
        return 1.0 / inv

    def storage_loss(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(E_R, E_I) [Pa] with E_I = -Im E >= 0 for omega > 0."""
        E = self.complex_modulus(omega)
        return E.real, -E.imag

    def describe(self) -> dict:
        return {"model": "single_relaxation", "E0_Pa": self.E0, "E1_Pa": self.E1,
                "tau_s": self.tau}


@dataclass(frozen=True)
class Prony:
    r"""Generalised Maxwell (Prony) series.

    :math:`E_R = E_\infty + \sum_k E_k \omega^2\tau_k^2/(1+\omega^2\tau_k^2)`,
    :math:`E_I = \sum_k E_k \omega\tau_k/(1+\omega^2\tau_k^2)` (loss modulus, odd in omega).

    Attributes
    ----------
    E_inf : float
        Equilibrium (rubbery) modulus [Pa].
    E_k : numpy.ndarray
        Spring moduli of the Maxwell arms [Pa], all ``>= 0``.
    tau_k : numpy.ndarray
        Relaxation times [s], all ``> 0``.
    """

    E_inf: float
    E_k: np.ndarray
    tau_k: np.ndarray

    def __post_init__(self) -> None:
        E_k = np.asarray(self.E_k, float)
        tau_k = np.asarray(self.tau_k, float)
        if E_k.shape != tau_k.shape or E_k.ndim != 1 or E_k.size == 0:
            raise InputError("Prony series needs equally long, non-empty E_k and tau_k",
                             field="modulus")
        if not (self.E_inf > 0 and (E_k >= 0).all() and (tau_k > 0).all()):
            raise InputError("Prony series needs E_inf > 0, E_k >= 0, tau_k > 0",
                             field="modulus")
        object.__setattr__(self, "E_k", E_k)
        object.__setattr__(self, "tau_k", tau_k)

    @classmethod
    def lognormal(cls, E_inf: float, E_glassy: float, tau_center: float,
                  width_decades: float, arms_per_decade: int = 2) -> Prony:
        r"""Prony series sampling a log-normal relaxation spectrum.

        Arms at ``arms_per_decade`` per decade of tau within +-4 widths of ``tau_center``, with
        :math:`E_k \propto \exp(-\tfrac12[(\log_{10}\tau_k - \log_{10}\tau_c)/w]^2)` and
        :math:`\sum_k E_k = E_{glassy} - E_\infty`, so that E' runs from E_inf (rubbery) to
        E_glassy. A broad (w ~ 2 decades) log-normal spectrum is a common smooth model of
        filled tread compounds (Ferry, *Viscoelastic Properties of Polymers*, ch. 3-4).
        """
        if not (E_glassy > E_inf > 0 and tau_center > 0 and width_decades > 0
                and arms_per_decade >= 1):
            raise InputError("log-normal spectrum needs E_glassy > E_inf > 0, tau_center > 0, "
                             "width_decades > 0, arms_per_decade >= 1", field="modulus",
                             value=(E_inf, E_glassy, tau_center, width_decades))
        c = np.log10(tau_center)
        step = 1.0 / arms_per_decade
        lt = np.arange(np.floor(c - 4 * width_decades), np.ceil(c + 4 * width_decades) + step / 2,
                       step)
        w = np.exp(-0.5 * ((lt - c) / width_decades) ** 2)
        return cls(E_inf, (E_glassy - E_inf) * w / w.sum(), 10.0**lt)

    def storage_loss(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        omega = np.asarray(omega, dtype=float)
        wt = omega[..., None] * self.tau_k
        d = 1.0 + wt * wt
        E_R = self.E_inf + np.sum(self.E_k * wt * wt / d, axis=-1)
        E_I = np.sum(self.E_k * wt / d, axis=-1)
        return E_R, E_I

    def describe(self) -> dict:
        return {"model": "prony", "E_inf_Pa": self.E_inf, "E_k_Pa": self.E_k.tolist(),
                "tau_k_s": self.tau_k.tolist()}


OutsidePolicy = Literal["maxwell", "error"]


@dataclass(frozen=True)
class TabulatedMasterCurve:
    r"""Measured DMA master curve (omega, E', E'') at the reference temperature.

    Inside the data: linear interpolation of log10 E' and log10 E'' in log10 omega.

    Outside the data, ``outside="maxwell"`` (default) continues the curve with the asymptotes
    that every generalised Maxwell solid has beyond its slowest and fastest relaxation times:
    below the lowest frequency E' stays at its end value and E'' falls proportional to omega;
    above the highest frequency E' stays at its end value and E'' falls proportional to
    1/omega. (Ferry, *Viscoelastic Properties of Polymers*, 3rd ed., ch. 3: terminal and glassy
    behaviour of a relaxation spectrum of finite width.) This never invents a new transition
    and is bounded. ``outside="error"`` refuses any direct evaluation outside the data
    (:meth:`storage_loss`); the friction engine samples the continuation (:meth:`continued`)
    and refuses only the results whose integrands reach outside :attr:`measured_band`.

    Attributes
    ----------
    omega : numpy.ndarray
        Angular frequencies [rad/s], strictly increasing, > 0.
    E_storage, E_loss : numpy.ndarray
        E' and E'' [Pa], > 0.
    outside : {"maxwell", "error"}
        Policy outside the measured band.
    source : str
        The file the table came from.
    omega_unit : str
        The frequency unit of the file's column, reported in :meth:`describe`: ``"rad/s"``
        (angular frequency, used as is) or ``"Hz"`` (cyclic frequency f, converted to
        omega = 2 pi f); "1/s" is refused as ambiguous when the file is read.
    columns : str
        How the file's columns were read, for :meth:`describe` (e.g. the loss modulus
        computed from a tan delta column), "" when not from a file.
    """

    omega: np.ndarray
    E_storage: np.ndarray
    E_loss: np.ndarray
    outside: OutsidePolicy = "maxwell"
    source: str = ""
    omega_unit: str = "rad/s"
    columns: str = ""

    def __post_init__(self) -> None:
        for nm in ("omega", "E_storage", "E_loss"):
            object.__setattr__(self, nm, np.asarray(getattr(self, nm), float))
        src = self.source or None
        if self.omega.ndim != 1 or self.omega.size < 2:
            raise InputError("master curve needs at least two rows", source=src, field="omega")
        if not (self.omega.shape == self.E_storage.shape == self.E_loss.shape):
            raise InputError("columns of unequal length", source=src)
        if not (np.diff(self.omega) > 0).all():
            i = int(np.flatnonzero(np.diff(self.omega) <= 0)[0]) + 1
            raise InputError("frequency column must be strictly increasing", source=src,
                             field="omega", value=float(self.omega[i]))
        for nm in ("omega", "E_storage", "E_loss"):
            a = getattr(self, nm)
            if (a <= 0).any():
                i = int(np.flatnonzero(a <= 0)[0])
                raise InputError("must be > 0 (negative or zero modulus/frequency)",
                                 source=src, field=nm, value=float(a[i]))
        if self.outside not in ("maxwell", "error"):
            raise InputError("unknown policy", source=src, field="outside", value=self.outside)

    @property
    def measured_band(self) -> tuple[float, float]:
        """(omega_min, omega_max) of the data [rad/s]."""
        return float(self.omega[0]), float(self.omega[-1])

    def storage_loss(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(E', E'') [Pa]; outside the data as the policy says (class docstring)."""
        omega = np.asarray(omega, dtype=float)
        if self.outside == "error":
            lw = np.log10(omega)
            x = np.log10(self.omega)
            if (lw < x[0] - 1e-12).any() or (lw > x[-1] + 1e-12).any():
                raise InputError(
                    f"frequency outside the master curve's data ({self.omega[0]:.3g}.."
                    f"{self.omega[-1]:.3g} rad/s) and policy is 'error'",
                    source=self.source or None, field="outside")
        return self.continued(omega)

    def continued(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(E', E'') [Pa]: the data inside, the Maxwell asymptotes outside (whatever the
        policy; the friction engine accounts for what it takes from outside)."""
        omega = np.asarray(omega, dtype=float)
        lw = np.log10(omega)
        x = np.log10(self.omega)
        lo, hi = x[0], x[-1]
        lER = np.interp(lw, x, np.log10(self.E_storage))
        lEI = np.interp(lw, x, np.log10(self.E_loss))
        lEI = np.where(lw < lo, lEI + (lw - lo), lEI)
        lEI = np.where(lw > hi, lEI - (lw - hi), lEI)
        return 10.0**lER, 10.0**lEI

    def describe(self) -> dict:
        how = ("angular frequency omega [rad/s], used as is" if self.omega_unit == "rad/s"
               else f"cyclic frequency f [{self.omega_unit}], converted to omega = 2 pi f")
        return {"model": "tabulated", "source": self.source, "outside": self.outside,
                "frequency_column": how, "columns": self.columns,
                "measured_band_rad_s": list(self.measured_band),
                "omega_rad_s": self.omega.tolist(), "E_storage_Pa": self.E_storage.tolist(),
                "E_loss_Pa": self.E_loss.tolist()}


@dataclass(frozen=True)
class ModulusTable:
    """log10 E_R and log10 E_I [Pa] on a uniform log10(omega) grid, for fast evaluation.

    Built from a :class:`Modulus` with the strain-softening factors of review eq. (6) applied.
    Evaluation interpolates linearly in log10 omega; arguments beyond the table are clamped to
    its ends (the table spans far more decades than any Persson integral reaches, see
    :meth:`from_modulus`).

    Attributes
    ----------
    log10_band : tuple of float or None
        log10 of the measured band (omega_min, omega_max) [rad/s] of a tabulated master curve
        (module docstring); None for an analytic model, which has no band.
    outside : {"maxwell", "error"}
        The master curve's policy outside its band (the engine refuses, under "error", the
        results that need frequencies outside it).
    source : str
        The master curve's file, for messages.
    """

    log10_omega0: float
    d_log10_omega: float
    log10_ER: np.ndarray
    log10_EI: np.ndarray
    log10_band: tuple[float, float] | None = None
    outside: str = "maxwell"
    source: str = ""

    @classmethod
    def from_modulus(cls, modulus: Modulus, eta_R: float = 1.0, eta_I: float = 1.0,
                     log10_omega_range: tuple[float, float] = (-40.0, 40.0),
                     points_per_decade: int = 40) -> ModulusTable:
        """Sample ``modulus`` (times the softening factors eta_R, eta_I) on a log grid.

        A model with a measured band is sampled through its continuation (``continued``) and
        its band and policy are kept (module docstring)."""
        lo, hi = log10_omega_range
        n = round((hi - lo) * points_per_decade) + 1
        lw = np.linspace(lo, hi, n)
        band = getattr(modulus, "measured_band", None)
        sample = modulus.storage_loss if band is None else modulus.continued
        ER, EI = sample(10.0**lw)
        ER = np.asarray(ER) * eta_R
        EI = np.maximum(np.asarray(EI) * eta_I, 1e-300)
        log10_band = None if band is None else (float(np.log10(band[0])),
                                                float(np.log10(band[1])))
        return cls(lo, (hi - lo) / (n - 1), np.log10(ER), np.log10(EI), log10_band,
                   str(getattr(modulus, "outside", "maxwell")),
                   str(getattr(modulus, "source", "")))

    def outside_band(self, log10_omega: np.ndarray) -> np.ndarray:
        """Where reduced frequencies (log10 omega [rad/s]) lie outside the measured band
        (all False without a band). The band's ends count as inside (to 1e-9 decades)."""
        lw = np.asarray(log10_omega, float)
        if self.log10_band is None:
            return np.zeros(lw.shape, bool)
        lo, hi = self.log10_band
        return (lw < lo - 1e-9) | (lw > hi + 1e-9)

    def __call__(self, log10_omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(E_R, E_I) [Pa] at reduced angular frequencies given as log10(omega [rad/s])."""
        u = (np.asarray(log10_omega, float) - self.log10_omega0) / self.d_log10_omega
        n = self.log10_ER.size
        u = np.clip(u, 0.0, n - 1.000001)
        i = u.astype(np.intp)
        f = u - i
        lER = self.log10_ER[i] + f * (self.log10_ER[i + 1] - self.log10_ER[i])
        lEI = self.log10_EI[i] + f * (self.log10_EI[i + 1] - self.log10_EI[i])
        return 10.0**lER, 10.0**lEI
