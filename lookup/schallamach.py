r"""Schallamach binding-breaking-binding model of the adhesive shear stress (review Appendix A).

A molecular patch of the rubber attaches to the substrate at the rate ``1/tau_0 = nu_0 exp(-beta
eps_0)`` (review eq. A7), is stretched like a spring ``k`` while the block slides at speed v and
detaches at the stress-aided rate ``w = nu_1 exp(-beta [eps_1 - k (v t)^2 / 2])`` (eq. A8).
With ``sqrt(R) = v / v*`` (eq. A18) and ``Q = (nu_1/nu_0) exp(-Delta E / k_B T)`` (eq. A13),
``Delta E = eps_1 - eps_0``, the mean attached time is (eqs. A15-A16)

.. math::

    \frac{\tau_1}{\tau_0} = \frac{1}{\sqrt R}\int_0^\infty dx\, e^{-q(x)}, \qquad
    q(x) = \frac{Q}{\sqrt R}\int_0^x dy\, e^{y^2}
         = \frac{Q}{\sqrt R}\, e^{x^2} F(x),

with F the Dawson function (``scipy.special.dawsn``); ``log q = log(Q/sqrt R) + x^2 + log F(x)``
is evaluated in log form, so nothing overflows for large x. The shear stress is, in units of
``sigma* = (2 k c^2 k_B T)^{1/2}`` (eq. A20),

* ``mean_force="A5"`` (the review's, Schallamach's approximation ``<f> ~ k v tau_1``), eq. (A21):
  ``sigma_f/sigma* = (v/v*) (tau_1/tau_0)^2 / (1 + tau_1/tau_0)``;
* ``mean_force="A4"`` (the exact mean spring force of eq. A4 with f = k v t):
  ``sigma_f/sigma* = I_1 / [sqrt(R) (1 + tau_1/tau_0)]``, ``I_1 = int_0^inf x e^{-q(x)} dx``.

Only "A5" reproduces the review's Fig. A2 / docs/review-notes.md check (Delta E / k_B T = 3,
nu_0 = nu_1: Gaussian fit ``a exp(-b log10(v/v*)^2)`` with a = 1.172, b = 0.558; "A4" gives
a = 0.62, b = 0.45): "A5" is the default. The two agree when P(t) is exponential (low speed) and
differ by up to a factor 2 where detachment is stress-driven (P(t) step-like, high speed).

The integrals are computed by Gauss-Legendre quadrature on three sub-intervals of x split where
q = 1 and q = 8 and ending where q = 60 (``e^-60`` truncation); the split points are found by a
monotone Newton iteration. Against adaptive ``scipy.integrate.quad`` at rtol 1e-12 the relative
error is below 1e-10 for 1e-12 <= v/v* <= 1e12 (pinned in ``tests/test_schallamach.py``). The
evaluation is vectorised and takes about 5 us per point, so no table is needed.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

from tirefric.errors import InputError

from .shift import K_B, ShiftFactor

MeanForce = Literal["A5", "A4"]

#: Upper end of the x integration: where q(x) = Q_END, i.e. e^{-q} = e^{-60} ~ 1e-26.
Q_END = 60.0
#: Gauss-Legendre nodes per sub-interval ([q=0, 1], [1, 8], [8, Q_END]).
N_GAUSS = 48
_GL_X, _GL_W = np.polynomial.legendre.leggauss(N_GAUSS)
_Q_SPLITS = (0.0, 1.0, 8.0, Q_END)


def _log_F(x: np.ndarray) -> np.ndarray:
    """log of ``int_0^x e^{y^2} dy = e^{x^2} dawsn(x)`` for x > 0, without overflow."""
    return x * x + np.log(special.dawsn(x))


def _x_at_q(log_A: np.ndarray, q_target: float) -> np.ndarray:
    """Solve ``A int_0^x e^{y^2} dy = q_target`` for x > 0 (eq. A16), vectorised.

    In u = ln x the function ``g(u) = log F(e^u) - c`` is increasing and convex (its slope
    ``x / dawsn(x)`` grows with x), so Newton's method started right of the root converges
    monotonically. ``F(x) >= x`` gives the start ``x = e^c`` for c < 1, and
    ``F(sqrt(c) + 1) >= e^c`` the start ``sqrt(c) + 1`` for c >= 1.
    """
    c = np.log(q_target) - log_A
    x = np.where(c < 1.0, np.exp(np.minimum(c, 1.0)), np.sqrt(np.maximum(c, 1.0)) + 1.0)
    u = np.log(x)
    for _ in range(100):
        x = np.exp(u)
        g = _log_F(x) - c
        du = g * special.dawsn(x) / x
        u = u - du
        if np.all(np.abs(du) <= 1e-14 * np.maximum(1.0, np.abs(u))):
            break
    return np.exp(u)


def _moments(s: np.ndarray, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``I_0 = int_0^inf e^{-q(x)} dx`` and ``I_1 = int_0^inf x e^{-q(x)} dx`` (eq. A15-A16).

    ``s = sqrt(R) = v/v* > 0`` and ``Q > 0`` are broadcast arrays; ``q(x) = (Q/s) F(x)``.
    """
    log_A = np.log(Q) - np.log(s)
    edges = [np.zeros_like(log_A)] + [_x_at_q(log_A, qq) for qq in _Q_SPLITS[1:]]
    I0 = np.zeros_like(log_A)
    I1 = np.zeros_like(log_A)
    for a, b in pairwise(edges):
        half = 0.5 * (b - a)
        x = (0.5 * (a + b))[..., None] + half[..., None] * _GL_X
        e = np.exp(-np.exp(log_A[..., None] + _log_F(x)))
        I0 += half * (e @ _GL_W)
        I1 += half * ((x * e) @ _GL_W)
    return I0, I1


def _as_positive_array(value: ArrayLike, name: str) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError("must be finite and > 0", field=name, value=value)
    return a


def _Q(delta_E_over_kT: ArrayLike, nu1_over_nu0: ArrayLike) -> np.ndarray:
    """Review eq. (A13): ``Q = (nu_1/nu_0) exp(-Delta E / k_B T)``."""
    return np.asarray(nu1_over_nu0, float) * np.exp(-np.asarray(delta_E_over_kT, float))


def attached_time_ratio(v_over_vstar: ArrayLike, delta_E_over_kT: ArrayLike,
                        nu1_over_nu0: ArrayLike = 1.0) -> np.ndarray:
    """tau_1/tau_0, review eqs. (A15)-(A16), with sqrt(R) = v/v* (eq. A18).

    Parameters
    ----------
    v_over_vstar
        Sliding speed over the reference speed v* of eq. (A19) [-], > 0.
    delta_E_over_kT
        (eps_1 - eps_0) / (k_B T) [-].
    nu1_over_nu0
        Ratio of the attempt frequencies of detachment and attachment [-].

    Returns
    -------
    numpy.ndarray
        tau_1/tau_0 [-]; tends to 1/Q (eq. A13) as v -> 0.
    """
    s = _as_positive_array(v_over_vstar, "v_over_vstar")
    Q = _as_positive_array(_Q(delta_E_over_kT, nu1_over_nu0), "Q")
    s, Q = np.broadcast_arrays(s, Q)
    I0, _ = _moments(s, Q)
    return I0 / s


def attached_fraction(v_over_vstar: ArrayLike, delta_E_over_kT: ArrayLike,
                      nu1_over_nu0: ArrayLike = 1.0) -> np.ndarray:
    """N/N_0 = (tau_1/tau_0) / (1 + tau_1/tau_0), review eq. (A6) [-]."""
    t1 = attached_time_ratio(v_over_vstar, delta_E_over_kT, nu1_over_nu0)
    return t1 / (1.0 + t1)


def normalized_shear_stress(v_over_vstar: ArrayLike, delta_E_over_kT: ArrayLike,
                            nu1_over_nu0: ArrayLike = 1.0,
                            mean_force: MeanForce = "A5") -> np.ndarray:
    """sigma_f / sigma*, review eq. (A21) (``"A5"``) or with the exact <f> of eq. (A4).

    Parameters
    ----------
    v_over_vstar
        v/v* [-] (eq. A18), >= 0; v = 0 gives 0 (sigma_f is linear in v at low speed).
    delta_E_over_kT
        Delta E / (k_B T) [-] (eq. A13).
    nu1_over_nu0
        nu_1/nu_0 [-] (eq. A13).
    mean_force
        ``"A5"``: Schallamach's ``<f> ~ k v tau_1`` (eqs. A5, A21; the review's figures).
        ``"A4"``: the exact mean force,
        ``sigma_f/sigma* = I_1 / (sqrt(R) (1 + tau_1/tau_0))``.

    Returns
    -------
    numpy.ndarray
        sigma_f/sigma* [-], broadcast shape of the inputs.
    """
    if mean_force not in ("A5", "A4"):
        raise InputError("must be 'A5' (review eq. A21) or 'A4' (exact mean force)",
                         field="mean_force", value=mean_force)
    s = np.asarray(v_over_vstar, dtype=float)
    if not np.all(np.isfinite(s)) or np.any(s < 0):
        raise InputError("must be finite and >= 0", field="v_over_vstar", value=v_over_vstar)
    Q = _as_positive_array(_Q(delta_E_over_kT, nu1_over_nu0), "Q")
    s, Q = np.broadcast_arrays(s, Q)
    out = np.zeros(s.shape)
    pos = s > 0
    if np.any(pos):
        sp, Qp = s[pos], Q[pos]
        I0, I1 = _moments(sp, Qp)
        t1 = I0 / sp
        if mean_force == "A5":
            out[pos] = sp * t1 * t1 / (1.0 + t1)
        else:
            out[pos] = I1 / (sp * (1.0 + t1))
    return out


def sigma_star_patch(E: float, R: float, T: float) -> float:
    """sigma* ~ (2 E k_B T / R^3)^{1/2} [Pa], review eq. (A22) (k ~ E R, c = 1/R^2).

    Parameters
    ----------
    E
        Elastic modulus of the rubber [Pa].
    R
        Radius of the adhering patch [m] (the review: ~1 nm, one bead unit).
    T
        Temperature [K].
    """
    for name, val in (("E", E), ("R", R), ("T", T)):
        if not (np.isfinite(val) and val > 0):
            raise InputError("must be finite and > 0", field=name, value=val)
    return float(np.sqrt(2.0 * E * K_B * T / R**3))


def v_star_patch(E: float, R: float, T: float, tau0: float) -> float:
    """v* = (2 k_B T / (E R tau_0^2))^{1/2} [m/s], review eq. (A23) (eq. A19 with k ~ E R).

    Parameters
    ----------
    E
        Elastic modulus [Pa].
    R
        Patch radius [m].
    T
        Temperature [K].
    tau0
        Mean time in the detached state [s] (the review: shortest Rouse time, ~1e-6 s).
    """
    for name, val in (("E", E), ("R", R), ("T", T), ("tau0", tau0)):
        if not (np.isfinite(val) and val > 0):
            raise InputError("must be finite and > 0", field=name, value=val)
    return float(np.sqrt(2.0 * K_B * T / (E * R * tau0**2)))


@dataclass(frozen=True)
class SchallamachShearLaw:
    r"""Adhesive shear stress sigma_f(v, T) of the Schallamach model (review Appendix A).

    ``sigma_f(v, T) = sigma*(T) g(v / v*(T); Delta E / k_B T, nu_1/nu_0)`` with g from
    :func:`normalized_shear_stress`. The temperature dependence is the one eqs. (A7), (A13),
    (A19) and (A20) imply when k, c, eps_0, eps_1, nu_0, nu_1 do not depend on T:

    * ``sigma*(T) = sigma*_ref (T / T_ref)^{1/2}`` (eq. A20). With k ~ E R (eq. A22) and an
      entropic rubber modulus E ~ T the exponent would be 1; that is not included.
    * ``v*(T) = v*_ref (T / T_ref)^{1/2} tau_0(T_ref) / tau_0(T)`` (eq. A19), with
      ``tau_0(T) / tau_0(T_ref) = a_T(T) / a_T(T_ref)`` from ``tau0_shift``. An
      :class:`~lookup.shift.Arrhenius` shift with activation energy eps_0 is eq. (A7) exactly;
      the bulk WLF a_T treats tau_0 as a Rouse time (review text after eq. A23); ``None`` means
      eps_0 = 0 (tau_0 = 1/nu_0 independent of T).
    * ``Delta E / k_B T = (Delta E / k_B T_ref) (T_ref / T)`` in Q (eq. A13).

    Attributes
    ----------
    sigma_star : float
        sigma* at T_ref [Pa] (eq. A20/A22; the review: ~9 MPa for R = 1 nm, E = 10 MPa).
    v_star : float
        v* at T_ref [m/s] (eq. A19/A23; the review: ~1 mm/s for tau_0 = 1 us).
    delta_E_over_kBT_ref : float
        (eps_1 - eps_0) / (k_B T_ref) [-] (the review's example: 3).
    nu1_over_nu0 : float
        Ratio of attempt frequencies nu_1/nu_0 [-] (the review's figures: 1).
    T_ref : float
        Temperature at which sigma_star and v_star hold [K].
    tau0_shift : ShiftFactor or None
        Temperature dependence of tau_0 (see above); ``None`` for eps_0 = 0.
    mean_force : {"A5", "A4"}
        Mean bond force: Schallamach's approximation (eq. A21, the review's) or exact (eq. A4).
    """

    sigma_star: float
    v_star: float
    delta_E_over_kBT_ref: float
    nu1_over_nu0: float
    T_ref: float
    tau0_shift: ShiftFactor | None
    mean_force: MeanForce = "A5"

    def __post_init__(self) -> None:
        checks = (
            ("sigma_star", self.sigma_star, "must be finite and >= 0 [Pa]", self.sigma_star >= 0),
            ("v_star", self.v_star, "must be finite and > 0 [m/s]", self.v_star > 0),
            ("delta_E_over_kBT_ref", self.delta_E_over_kBT_ref, "must be a finite number",
             True),
            ("nu1_over_nu0", self.nu1_over_nu0, "must be finite and > 0", self.nu1_over_nu0 > 0),
            ("T_ref", self.T_ref, "must be finite and > 0 [K]", self.T_ref > 0),
        )
        for name, value, message, ok in checks:
            if not (np.isfinite(value) and ok):
                raise InputError(message, field=f"adhesion.{name}", value=value)
        if self.mean_force not in ("A5", "A4"):
            raise InputError("must be 'A5' (review eq. A21) or 'A4' (exact mean force)",
                             field="adhesion.mean_force", value=self.mean_force)

    @classmethod
    def from_energies(cls, sigma_star: float, v_star: float, delta_E: float,
                      nu1_over_nu0: float, T_ref: float, tau0_shift: ShiftFactor | None,
                      mean_force: MeanForce = "A5") -> SchallamachShearLaw:
        """Build from Delta E = eps_1 - eps_0 in joules instead of Delta E / (k_B T_ref)."""
        if not (np.isfinite(T_ref) and T_ref > 0):
            raise InputError("must be finite and > 0 [K]", field="adhesion.T_ref", value=T_ref)
        return cls(sigma_star, v_star, delta_E / (K_B * T_ref), nu1_over_nu0, T_ref,
                   tau0_shift, mean_force)

    @property
    def delta_E(self) -> float:
        """Delta E = eps_1 - eps_0 [J]."""
        return self.delta_E_over_kBT_ref * K_B * self.T_ref

    def sigma_star_at(self, T: ArrayLike) -> np.ndarray:
        """sigma*(T) [Pa], eq. (A20) with k and c independent of T."""
        return self.sigma_star * np.sqrt(np.asarray(T, float) / self.T_ref)

    def v_star_at(self, T: ArrayLike) -> np.ndarray:
        """v*(T) [m/s], eq. (A19) with tau_0(T) from ``tau0_shift`` (eq. A7)."""
        T = np.asarray(T, float)
        out = self.v_star * np.sqrt(T / self.T_ref)
        if self.tau0_shift is not None:
            log10_ratio = (self.tau0_shift.log10_aT(T)
                           - self.tau0_shift.log10_aT(np.asarray(self.T_ref, float)))
            out = out * 10.0 ** (-log10_ratio)
        return out

    def sigma_f(self, v: ArrayLike, T: ArrayLike) -> np.ndarray:
        """Shear stress [Pa] at sliding speed ``v`` [m/s] (sign ignored) and ``T`` [K]."""
        T = np.asarray(T, float)
        if not np.all(np.isfinite(T)) or np.any(T <= 0):
            raise InputError("temperature must be finite and > 0 K", field="T", value=T)
        v = np.abs(np.asarray(v, float))
        s = v / self.v_star_at(T)
        g = normalized_shear_stress(s, self.delta_E_over_kBT_ref * self.T_ref / T,
                                    self.nu1_over_nu0, self.mean_force)
        return self.sigma_star_at(T) * g

    def describe(self) -> dict:
        return {"model": "schallamach_appendix_A", "sigma_star_Pa": self.sigma_star,
                "v_star_m_s": self.v_star, "delta_E_over_kBT_ref": self.delta_E_over_kBT_ref,
                "delta_E_J": self.delta_E, "nu1_over_nu0": self.nu1_over_nu0,
                "T_ref_K": self.T_ref, "mean_force": self.mean_force,
                "tau0_shift": None if self.tau0_shift is None else self.tau0_shift.describe()}
