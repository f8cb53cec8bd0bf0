r"""Contact-mechanics pieces of Persson theory: P(G), S(P) and the integral Phi(G).

Review eqs. (18) and (20): :math:`P = \mathrm{erf}(1/(2\sqrt G))` (docs/review-notes.md, Trap 2: the
printed middle expression of eq. 18 is a typo), :math:`S = \gamma + (1-\gamma)P^2`.

Why :func:`Phi` exists. With :math:`g = dG/d\ln q = \tfrac18 q^4 C A_2/\sigma_0^2` (eq. 19) the
q-integrand of eq. (17) is :math:`\tfrac12 q^4 C S P A_I/\sigma_0 = 4\sigma_0 (A_I/A_2)\,S P\,g`,
so that

.. math:: \mu_{visc} = 4\sigma_0 \int (A_I/A_2)\, S(P(G))\,P(G)\,dG .

On stiff (glassy) rubber G jumps from 0 to 1e6 within a few percent of q above q0 and P falls
from 1 to 1e-3 there: a quadrature in q cannot follow it. The ratio A_I/A_2 varies slowly, so
each q-interval is integrated as :math:`\bar\rho_i\,[\Phi(G_{i+1}) - \Phi(G_i)]` with the exact
:math:`\Phi(G) = \int_0^G S(P(g))P(g)\,dg`, tabulated once here to ~1e-10 relative accuracy.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.special import erf

_LOG_G_MIN = -16.0
_LOG_G_MAX = 24.0
_PER_DECADE = 200


def contact_fraction(G: np.ndarray) -> np.ndarray:
    """P(G) = erf(1/(2 sqrt G)) (review eq. 18, corrected), P(0) = 1."""
    G = np.asarray(G, float)
    with np.errstate(divide="ignore"):
        return erf(0.5 / np.sqrt(G))


def area_rescale(kappa: float) -> float:
    r"""Factor c with which P(c G) has the small-contact slope ``kappa`` (eq. 11).

    In the elastic limit G(q1) = xi^2 E*^2 / (8 sigma0^2) (eq. 10 with the corrected eq. 18),
    so erf(1/(2 sqrt(c G))) = erf((sqrt(pi) kappa / 2) sigma0 / (xi E*)) for
    :math:`c = 8/(\pi\kappa^2)`; Persson's own slope kappa = (8/pi)^(1/2) gives c = 1.
    kappa = 2, the "exact" numerical value quoted by the review after eq. (11) (Hyun et al.,
    Phys. Rev. E 70 (2004) 026117; Prodanov, Dapp & Muser, Tribol. Lett. 53 (2014) 433),
    gives c = 2/pi and 1.25 times Persson's area at small contact.

    Limits: the rescaling is calibrated on the small-contact slope of elastic, non-adhesive
    contacts of isotropic self-affine surfaces; the numerical studies find kappa weakly
    dependent on H and on the resolution of the roughness, which a single kappa ignores. It is
    applied to P(q) at every scale (also inside eq. 17 and eq. 20), an assumption of this
    option, not a result of those studies. Near full contact (P -> 1) it changes little.
    """
    return 8.0 / (np.pi * kappa * kappa)


@lru_cache(maxsize=8)
def _phi_table(gamma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln Phi, its derivative d ln Phi / d ln G on a uniform ln G grid."""
    n = int((_LOG_G_MAX - _LOG_G_MIN) * _PER_DECADE) + 1
    lnG = np.linspace(_LOG_G_MIN, _LOG_G_MAX, n) * np.log(10.0)
    # integrate on a grid 8x finer with Simpson's rule in ln G (integrand f(G) G, smooth)
    m = 8 * (n - 1) + 1
    lf = np.linspace(lnG[0], lnG[-1], m)
    Gf = np.exp(lf)
    P = contact_fraction(Gf)
    h = (S := gamma + (1.0 - gamma) * P * P) * P * Gf
    del S
    dl = lf[1] - lf[0]
    # Phi(G_min) = G_min to 1e-16 relative (P = 1 below)
    pair = dl / 3.0 * (h[:-2:2] + 4.0 * h[1:-1:2] + h[2::2])  # Simpson over each 2 steps
    cum = np.concatenate([[0.0], np.cumsum(pair)]) + Gf[0]
    Phi = cum[::4]  # every 8 fine steps = 4 Simpson pairs
    G = np.exp(lnG)
    Pn = contact_fraction(G)
    f = (gamma + (1.0 - gamma) * Pn * Pn) * Pn
    return lnG, np.log(Phi), f * G / Phi


def Phi(G: np.ndarray, gamma: float = 0.5) -> np.ndarray:
    r"""Phi(G) = int_0^G S(P(g)) P(g) dg (module docstring), cubic Hermite in ln-ln.

    Below G = 1e-16, Phi = G (P = 1 to machine precision). Above 1e24 the large-G asymptote
    Phi ~ Phi(G_max) + (2 gamma/sqrt(pi)) (sqrt(G) - sqrt(G_max)) is used.
    """
    G = np.asarray(G, float)
    lnG_t, lnPhi, dlnPhi = _phi_table(float(gamma))
    h = lnG_t[1] - lnG_t[0]
    with np.errstate(divide="ignore"):
        x = np.log(np.maximum(G, 1e-300))
    u = np.clip((x - lnG_t[0]) / h, 0.0, lnG_t.size - 1.000001)
    i = u.astype(np.intp)
    t = u - i
    y0, y1 = lnPhi[i], lnPhi[i + 1]
    m0, m1 = dlnPhi[i] * h, dlnPhi[i + 1] * h
    t2, t3 = t * t, t * t * t
    y = ((2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * y1
         + (t3 - t2) * m1)
    out = np.exp(y)
    G_max = np.exp(lnG_t[-1])
    big = G > G_max
    if big.any():
        out = np.where(big, np.exp(lnPhi[-1]) + 2.0 * gamma / np.sqrt(np.pi)
                       * (np.sqrt(np.maximum(G, G_max)) - np.sqrt(G_max)), out)
    return np.where(G < np.exp(lnG_t[0]), G, out)
