"""Contact patch: size from the load and the pressure carried by each brush element.

The patch half-length ``a`` and width ``b`` follow :class:`~tire_brush.params.PatchLaw`
(Pacejka 2012, eqs. (A3.7)-(A3.8)). Along the patch the vertical load is distributed
parabolically, ``q_z(x) = 3 Fz / (4a) (1 - x^2/a^2)`` (Pacejka 2012, ch. 3;
docs/review-notes.md), and uniformly across the width, so the nominal (gross-footprint)
pressure is ``q_z(x) / b``. The pressure on the rubber, which the friction tables are read at,
is ``p / (1 - void_ratio)``.

On a discrete set of elements the parabola is sampled at the element positions and scaled so
that the element pressures add up to ``Fz`` exactly (then full sliding gives exactly
``mu Fz``).

This module imports only numpy: it runs inside an FMU.
"""

from __future__ import annotations

import numpy as np

from .params import PatchLaw


def parabolic_pressure(x: np.ndarray, a: float, Fz: float, area: float) -> np.ndarray:
    """Gross nominal pressure [Pa] of elements at positions ``x`` [m].

    Parameters
    ----------
    x
        Element positions along the patch [m], shape ``(n,)``.
    a
        Patch half-length [m].
    Fz
        Vertical load [N].
    area
        Footprint area of one element, ``b dx`` [m^2].

    Returns
    -------
    ndarray
        ``p_i = Fz w_i / (area sum_j w_j)`` with ``w = max(1 - x^2/a^2, 0)``; zeros where the
        patch is empty (``a = 0``, ``Fz <= 0`` or no element inside).
    """
    if not (a > 0.0 and Fz > 0.0 and area > 0.0):
        return np.zeros_like(x)
    w = x * (1.0 / a)
    w *= w
    np.subtract(1.0, w, out=w)
    np.maximum(w, 0.0, out=w)
    total = float(w.sum())
    if not total > 0.0:
        return w
    w *= Fz / (area * total)
    return w


def midpoint_weights(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions ``xi_j = 1 - (2j + 1)/n`` (cell midpoints from the leading edge, in units of
    ``a``) of ``n`` equal cells across the patch, and parabolic weights ``1 - xi^2`` scaled to
    sum to 1 (the share of ``Fz`` each cell carries)."""
    xi = 1.0 - (2.0 * np.arange(n) + 1.0) / n
    w = 1.0 - xi * xi
    return xi, w / w.sum()


def patch_size(law: PatchLaw, Fz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised :meth:`PatchLaw.size`: half-length ``a`` [m] and width ``b`` [m] at loads
    ``Fz`` [N] (zero where ``Fz <= 0``); Pacejka 2012 eqs. (A3.7)-(A3.8)."""
    Fz = np.asarray(Fz, float)
    r = np.clip(Fz, 0.0, law.Fz_max) / (law.C_z * law.R0)
    a = law.R0 * (law.q_ra2 * r + law.q_ra1 * np.sqrt(r))
    b = 2.0 * law.width * (law.q_rb2 * r + law.q_rb1 * np.cbrt(r))
    return a, np.where(r > 0, b, 0.0)
