"""Closed-form reference solutions of the review and docs/review-notes.md, as package code.

Used by the tests (and the docs) to pin the engine: the elastic-limit contact area of eq. (10),
the angular integrals of the single-relaxation solid of eq. (4), the FWHM of eq. (21), eq. (27)
for the flash temperature, and the layered-solid factor K of sec. 5.1.
"""

from __future__ import annotations

import numpy as np
from scipy.special import erf


def contact_area_elastic(sigma0: np.ndarray, xi: float, E_star: float) -> np.ndarray:
    """Review eq. (10): A/A0 = erf(sqrt(2) sigma0 / (xi E*)) for an elastic solid."""
    return erf(np.sqrt(2.0) * np.asarray(sigma0, float) / (xi * E_star))


def single_relaxation_angular_loss(x: np.ndarray, E0: float, E1: float) -> np.ndarray:
    """int_0^2pi dphi cos(phi) E_I(q v cos phi) for review eq. (4), with x = q v tau'.

    Equals (2 pi Delta E / x) (1 - 1/sqrt(1 + x^2)) with Delta E = E1 - E0 and
    tau' = tau E0/E1 (docs/review-notes.md).
    """
    x = np.asarray(x, float)
    return 2.0 * np.pi * (E1 - E0) / x * (1.0 - 1.0 / np.sqrt(1.0 + x * x))


def single_relaxation_angular_abs2(x: np.ndarray, E0: float, E1: float) -> np.ndarray:
    """int_0^2pi dphi |E(q v cos phi)|^2 = 2 pi [E1^2 - (E1^2 - E0^2)/sqrt(1 + x^2)]."""
    x = np.asarray(x, float)
    return 2.0 * np.pi * (E1**2 - (E1**2 - E0**2) / np.sqrt(1.0 + x * x))


def gaussian_law_fwhm(c: float) -> float:
    """Full width at half maximum of eq. (21) in decades of v: 2 sqrt(ln 2 / c)."""
    return 2.0 * np.sqrt(np.log(2.0) / c)


def layered_K(qd: np.ndarray, E0: float, nu0: float, E1: float, nu1: float) -> np.ndarray:
    """Layered-solid factor K(qd) of review sec. 5.1 (film 0 of thickness d on half-space 1).

    E*(omega) in eqs. (17)-(19) is replaced by E0*(omega)/K. K = 1 for d -> infinity and
    K = E0*/E1* for d = 0.
    """
    qd = np.asarray(qd, float)
    mu0 = E0 / (2.0 * (1.0 + nu0))
    mu1 = E1 / (2.0 * (1.0 + nu1))
    r = mu0 / mu1
    m = (r - 1.0) / (r + 3.0 - 4.0 * nu0)
    n = 1.0 - 4.0 * (1.0 - nu0) / (1.0 + r * (3.0 - 4.0 * nu1))
    e2 = np.exp(-2.0 * qd)
    e4 = e2 * e2
    num = 1.0 + 4.0 * m * qd * e2 - m * n * e4
    den = 1.0 - (m + n + 4.0 * m * qd**2) * e2 + m * n * e4
    return num / den
