"""Brute-force Persson friction for the tests, written from the review's equations alone.

Nothing here imports the engine (:mod:`lookup`): the modulus of review eq. (4), the self-affine
spectrum, eqs. (17)-(20) and the angular integrals are coded again in the most direct way
(fine trapezoidal quadrature in ln q, midpoint rule over the full angle 0..2 pi), so that a
wrong prefactor, argument or sign in the engine cannot be shared by this reference.
"""

from __future__ import annotations

import numpy as np
from scipy.special import erf


def single_relaxation_modulus(omega: np.ndarray, E0: float, E1: float, tau: float) -> np.ndarray:
    """Review eq. (4): 1/E = 1/E1 + (1/E0 - 1/E1)/(1 - i omega tau) [Pa]."""
    return 1.0 / (1.0 / E1 + (1.0 / E0 - 1.0 / E1) / (1.0 - 1j * omega * tau))


def self_affine_C(q: np.ndarray, q0: float, H: float, h_rms: float) -> np.ndarray:
    """C(q) = C0 (q/q0)^(-2(1+H)) for q >= q0 [m^4], C0 from h_rms^2 = 2 pi int q C dq.

    int_q0^inf q (q/q0)^(-2-2H) dq = q0^2 / (2H), hence C0 = 2 H h_rms^2 / (2 pi q0^2).
    """
    C0 = 2.0 * H * h_rms**2 / (2.0 * np.pi * q0**2)
    return np.where(q >= q0, C0 * (q / q0) ** (-2.0 * (1.0 + H)), 0.0)


def prony_modulus(omega: np.ndarray, E_inf: float, E_k: np.ndarray,
                  tau_k: np.ndarray) -> np.ndarray:
    """Generalised Maxwell solid, E = E_inf + sum_k E_k (-i w tau_k)/(1 - i w tau_k) [Pa]
    (the e^{-i w t} convention of review eq. 4: Im E < 0 for w > 0)."""
    x = -1j * np.asarray(omega)[..., None] * tau_k
    return E_inf + np.sum(E_k * x / (1.0 + x), axis=-1)


def rolloff_C(q: np.ndarray, q0: float, q_r: float, H: float, h_rms: float) -> np.ndarray:
    """C = C0 on [q0, q_r), C0 (q/q_r)^(-2(1+H)) above [m^4], C0 from
    h_rms^2 = 2 pi C0 [(q_r^2 - q0^2)/2 + q_r^2/(2H)]."""
    C0 = h_rms**2 / (2.0 * np.pi * (0.5 * (q_r**2 - q0**2) + q_r**2 / (2.0 * H)))
    return np.where(q < q0, 0.0, np.where(q < q_r, C0, C0 * (q / q_r) ** (-2.0 * (1.0 + H))))


def mu_visc_general(v: float, sigma0: float, nu: float, modulus, C, q0: float, q1: float,
                    gamma: float = 0.5, per_decade: int = 400,
                    n_phi: int = 2000) -> tuple[float, float]:
    """mu_visc and P(q1) of review eqs. (17)-(20) for any complex modulus E(omega) and
    spectrum C(q) (callables), by the quadrature of :func:`mu_visc_bruteforce`."""
    n = round(np.log10(q1 / q0) * per_decade) + 1
    q = np.geomspace(q0, q1, n)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    dphi = 2.0 * np.pi / n_phi
    Es = modulus(q[:, None] * v * np.cos(phi)[None, :]) / ((1.0 - nu**2) * sigma0)
    ang_loss = np.sum(np.cos(phi)[None, :] * (-Es.imag), axis=1) * dphi
    ang_abs2 = np.sum(np.abs(Es) ** 2, axis=1) * dphi
    Cq = C(q)
    lnq = np.log(q)
    dG = 0.125 * q**4 * Cq * ang_abs2
    G = np.concatenate([[0.0], np.cumsum(0.5 * (dG[1:] + dG[:-1]) * np.diff(lnq))])
    with np.errstate(divide="ignore"):
        P = erf(1.0 / (2.0 * np.sqrt(G)))
    S = gamma + (1.0 - gamma) * P**2
    integrand = 0.5 * q**4 * Cq * S * P * ang_loss
    return float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(lnq))), float(P[-1])


def mu_visc_bruteforce(v: float, sigma0: float, nu: float, E0: float, E1: float, tau: float,
                       q0: float, q1: float, H: float, h_rms: float, gamma: float = 0.5,
                       per_decade: int = 400, n_phi: int = 2000, eta_R: float = 1.0,
                       eta_I: float = 1.0) -> tuple[float, float]:
    """mu_visc (review eq. 17) and A/A0 = P(q1) by direct quadrature.

    eq. (17): mu = 1/2 int dq q^3 C S P int_0^2pi dphi cos(phi) Im[-E(q v cos phi)]
    / ((1 - nu^2) sigma0); eq. (19): G = 1/8 int dq q^3 C int dphi |E/((1 - nu^2) sigma0)|^2;
    eq. (18) with the erf argument 1/(2 sqrt G); eq. (20) S = gamma + (1 - gamma) P^2.
    The loss part enters as -Im E, positive with eq. (4)'s e^{-i omega t} convention.
    Strain softening (review eq. 6) multiplies Re E by ``eta_R`` and Im E by ``eta_I``.
    """
    n = round(np.log10(q1 / q0) * per_decade) + 1
    q = np.geomspace(q0, q1, n)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    dphi = 2.0 * np.pi / n_phi
    E = single_relaxation_modulus(q[:, None] * v * np.cos(phi)[None, :], E0, E1, tau)
    E = eta_R * E.real + 1j * eta_I * E.imag
    Es = E / ((1.0 - nu**2) * sigma0)
    ang_loss = np.sum(np.cos(phi)[None, :] * (-Es.imag), axis=1) * dphi
    ang_abs2 = np.sum(np.abs(Es) ** 2, axis=1) * dphi
    C = self_affine_C(q, q0, H, h_rms)
    lnq = np.log(q)
    dG = 0.125 * q**4 * C * ang_abs2  # per d ln q
    G = np.concatenate([[0.0], np.cumsum(0.5 * (dG[1:] + dG[:-1]) * np.diff(lnq))])
    with np.errstate(divide="ignore"):
        P = erf(1.0 / (2.0 * np.sqrt(G)))
    S = gamma + (1.0 - gamma) * P**2
    integrand = 0.5 * q**4 * C * S * P * ang_loss  # per d ln q
    mu = float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(lnq)))
    return mu, float(P[-1])
