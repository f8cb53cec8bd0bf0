"""Closed-form brush model (Pacejka 2012, *Tire and Vehicle Dynamics*, ch. 3), as package code.

Rigid carcass, parabolic pressure ``q_z(x) = 3 Fz / (4a) (1 - x^2/a^2)`` on ``-a <= x <= a``,
tread stiffness ``c_p`` per unit length (per unit area times the width), friction ``mu``. These
are the limits the numerical brush (:mod:`tire_brush.steady`, :mod:`tire_brush.transient`) must
reproduce with constant friction; the formulas and their conventions are those listed in
docs/review-notes.md ("The brush model's closed forms"):

* slip ``kappa = -V_sx / V_x``; theoretical slip ``sigma_x = kappa / (1 + kappa)``,
  ``sigma_y = tan(alpha) / (1 + kappa)``; an element stuck since the leading edge is deflected
  by ``sigma (a - x)``;
* ``theta = 2 c_p a^2 / (3 mu Fz)``, ``lambda = theta |sigma|``; for ``lambda < 1``
  ``F = mu Fz [1 - (1 - lambda)^3] sign(sigma)``,
  ``Mz = -mu Fz a theta sigma_y (1 - lambda)^3``; for ``lambda >= 1`` ``|F| = mu Fz``, ``Mz = 0``;
* combined slip (isotropic ``c_p``): ``F`` along the slip vector with the magnitude law of
  ``sigma = |(sigma_x, sigma_y)|``, ``Mz = (sigma_y / sigma) Mz_pure(sigma)``;
* static ``mu_s`` / kinetic ``mu_k`` (``theta_s`` built with ``mu_s``, ``lambda = theta_s sigma``):
  ``F = 3 mu_s Fz lambda (1 - lambda)^2 + mu_k Fz lambda^2 (3 - 2 lambda)`` for ``lambda < 1``,
  ``mu_k Fz`` beyond.

Signs: ``F = integral of c_p u dx`` with ``u`` the element deflection (tip minus base): braking
(``kappa < 0``) gives ``Fx < 0``; positive ``alpha`` gives ``Fy > 0`` and ``Mz < 0``.
"""

from __future__ import annotations

import numpy as np


def theoretical_slip(kappa: np.ndarray, alpha: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(sigma_x, sigma_y) = (kappa, tan alpha) / (1 + kappa)`` (Pacejka 2012, sec. 3.2)."""
    kappa = np.asarray(kappa, float)
    return kappa / (1.0 + kappa), np.tan(np.asarray(alpha, float)) / (1.0 + kappa)


def _magnitude(sigma: np.ndarray, mu: float, Fz: float, a: float,
               c_p: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(|F|, (1 - lambda)^3 clipped at 0, theta) for slip magnitudes ``sigma >= 0``."""
    theta = 2.0 * c_p * a * a / (3.0 * mu * Fz)
    lam = np.minimum(theta * sigma, 1.0)
    r3 = (1.0 - lam) ** 3
    return mu * Fz * (1.0 - r3), r3, theta


def brush_force(sigma: np.ndarray, mu: float, Fz: float, a: float, c_p: float) -> np.ndarray:
    """Force of the constant-friction brush in pure slip [N]: ``mu Fz [1 - (1-lambda)^3]
    sign(sigma)``, saturating at ``mu Fz`` (Pacejka 2012, sec. 3.2.2).

    Parameters
    ----------
    sigma
        Theoretical slip (``sigma_x`` or ``sigma_y``) [1].
    mu
        Friction coefficient [1].
    Fz
        Vertical load [N].
    a
        Contact half-length [m].
    c_p
        Tread stiffness per unit length [N/m^2] (``k b``).
    """
    sigma = np.asarray(sigma, float)
    F, _, _ = _magnitude(np.abs(sigma), mu, Fz, a, c_p)
    return F * np.sign(sigma)


def brush_moment(sigma_y: np.ndarray, mu: float, Fz: float, a: float,
                 c_py: float) -> np.ndarray:
    """Aligning moment in pure side slip [N m]: ``-mu Fz a theta sigma_y (1 - lambda)^3``,
    zero at full sliding (Pacejka 2012, sec. 3.2.2)."""
    sigma_y = np.asarray(sigma_y, float)
    _, r3, theta = _magnitude(np.abs(sigma_y), mu, Fz, a, c_py)
    return -mu * Fz * a * theta * sigma_y * r3


def brush_combined(sigma_x: np.ndarray, sigma_y: np.ndarray, mu: float, Fz: float, a: float,
                   c_p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Isotropic combined slip ``(Fx, Fy, Mz)``: the pure-slip magnitude law of
    ``sigma = |(sigma_x, sigma_y)|`` along the slip vector, ``Mz = (sigma_y/sigma)
    Mz_pure(sigma)`` (Pacejka 2012, sec. 3.2.3)."""
    sx, sy = np.broadcast_arrays(np.asarray(sigma_x, float), np.asarray(sigma_y, float))
    sigma = np.hypot(sx, sy)
    F, r3, theta = _magnitude(sigma, mu, Fz, a, c_p)
    safe = np.where(sigma > 0, sigma, 1.0)
    Fx = np.where(sigma > 0, F * sx / safe, 0.0)
    Fy = np.where(sigma > 0, F * sy / safe, 0.0)
    Mz = -mu * Fz * a * theta * sy * r3
    return Fx, Fy, Mz


def brush_static_kinetic(sigma: np.ndarray, mu_s: float, mu_k: float, Fz: float, a: float,
                         c_p: float) -> np.ndarray:
    """Pure-slip force with static ``mu_s`` and kinetic ``mu_k`` friction [N].

    ``F = 3 mu_s Fz lambda (1-lambda)^2 + mu_k Fz lambda^2 (3 - 2 lambda)`` with
    ``lambda = theta_s |sigma| < 1`` (``theta_s`` built with ``mu_s``), ``mu_k Fz`` beyond
    (docs/review-notes.md; the adhesion region ends where ``c_p sigma (a - x) = mu_s q_z``, the
    sliding region carries ``mu_k q_z``).
    """
    sigma = np.asarray(sigma, float)
    theta = 2.0 * c_p * a * a / (3.0 * mu_s * Fz)
    lam = np.minimum(theta * np.abs(sigma), 1.0)
    F = 3.0 * mu_s * Fz * lam * (1.0 - lam) ** 2 + mu_k * Fz * lam * lam * (3.0 - 2.0 * lam)
    return F * np.sign(sigma)


def rigid_brush_buildup(distance: np.ndarray, a: float) -> np.ndarray:
    """Force after a step in slip from rest, relative to its steady value, of the rigid-carcass
    brush without sliding, as a function of the rolled ``distance`` [m].

    Elements that entered after the step carry ``sigma (a - x)``, the others ``sigma d``:
    ``F/F_ss = (2 a d - d^2/2) / (2 a^2)`` for ``d <= 2a`` and 1 beyond. The initial slope
    gives a relaxation length of ``a`` (Pacejka 2012, sec. 7.2, brush with rigid carcass).
    """
    d = np.minimum(np.asarray(distance, float), 2.0 * a)
    return (2.0 * a * d - 0.5 * d * d) / (2.0 * a * a)
