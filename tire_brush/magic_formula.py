"""Magic Formula 6.1 (PAC2002 family) steady-state forces, for the coefficients that
:mod:`tire_brush.mf_fit` fits and :mod:`tire_brush.tir` writes.

The equations are those of Pacejka 2012, *Tire and Vehicle Dynamics*, 3rd ed., sec. 4.3.2
(eqs. (4.E1)-(4.E78)), in the ISO-W sign convention that MF-Tyre and ``.tir`` files use
(:mod:`tire_brush.axes`): ``tan(alpha) = V_sy / |V_x|``, ``kappa = -V_sx / |V_x|``, so the
cornering stiffness ``PKY1`` is negative and ``Mz = -t Fy + M_zr + s Fx`` (4.E71).

Scope -- what the brush model can be fitted to -- and the choices that make the result what an
MF-Tyre reader computes from the same file:

* inflation pressure = nominal (``dpi = 0``), no turn slip, forward rolling (``V_x > 0``), all
  scaling factors ``lambda = 1`` and no friction decay with slip speed (``LMUV = 0``);
* camber ``gamma`` acts on the pure side force only, through the camber stiffness
  ``K_yg0 = Fz (PKY6 + PKY7 dfz)`` (4.E30) and the vertical shift ``S_Vyg = Fz (PVY3 + PVY4
  dfz) gamma*`` (4.E28) in the horizontal shift ``S_Hy = PHY1 + PHY2 dfz + (K_yg0 gamma* -
  S_Vyg) / K_ya`` (4.E27) and in ``S_Vy`` (4.E29), with ``gamma* = sin(gamma)`` (4.E4), as in
  the MF-Tyre 6.1 equation manual; the other camber coefficients (``PDY3, PEY3..PEY5, PKY3,
  PKY5``, the camber terms of ``Fx``, of the combined-slip weights and of ``Mz``) are not
  evaluated (the fit writes them as 0). The aligning moment is evaluated at ``gamma = 0``:
  its pneumatic-trail term takes ``F_y0`` at ``gamma = 0`` (eqs. (4.E31)-(4.E32), (4.E74) in
  the MF-Tyre 6.1 form, which MFeval reproduces) and, its camber coefficients being 0, the
  rest has no camber dependence either; at ``gamma = 0`` every result is bit for bit what it
  was without camber;
* the slip angle enters as ``alpha`` itself (as MF-Tyre and the MFeval reproduction of it do),
  not as ``tan(alpha)`` (the book's ``alpha*``, eq. (4.E3));
* ``cos(alpha')`` of eqs. (4.E33) and (4.E36) is ``cos(alpha)`` (``V_c = V_x / cos(alpha)``);
* the curvature factors are clipped at 1 as the equations require (``E <= 1``, (4.E14),
  (4.E24), (4.E44), (4.E56), (4.E64));
* the cornering stiffness is eq. (4.E25) with ``PKY4`` (``= 2`` in PAC2002, where it is fixed),
  so MF 6.1 and PAC2002 readers compute the same ``K_ya`` when ``PKY4 = 2``;
* the overturning moment is the ``QSX1..QSX3`` part of eq. (4.E69) and the rolling-resistance
  moment eq. (4.E70) without pressure dependence (:func:`overturning_mx`,
  :func:`rolling_my`), both with the ISO-W sign (``M_y < 0`` rolling forward);
* the combined-slip aligning moment uses ``F_y' = G_yk F_y0`` (``F_y - S_Vyk``: the two agree
  when ``RVY* = 0``, as here) and the equivalent slip angles in the form
  ``atan(sqrt(tan^2(alpha) + (K_xk/K_ya)^2 kappa^2))`` of the MF-Tyre equation manual
  (reproduced by MFeval; for small angles eqs. (4.E77)-(4.E78)).

Only numpy is needed. Coefficients are given as a mapping from the ``.tir`` key (``"PKY1"``)
to its value; keys not given count as 0 (the MF-Tyre default), except ``PKY4`` (2, its PAC2002
value). ``FNOMIN`` and ``UNLOADED_RADIUS`` are required.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

#: Small number keeping the divisions of eqs. (4.E16), (4.E26), (4.E39) finite at zero load.
EPS = 1e-9


@dataclass(frozen=True)
class MFForces:
    """Forces [N] and aligning moment [N m] in ISO-W."""

    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray


def _get(p: Mapping[str, float]):
    return lambda k: float(p.get(k, 0.0))


def _mf(B, C, D, E, x):
    """The Magic Formula ``D sin(C atan(Bx - E (Bx - atan(Bx))))`` (Pacejka 2012 eq. (4.49))."""
    bx = B * x
    return D * np.sin(C * np.arctan(bx - E * (bx - np.arctan(bx))))


def _weight(B, C, E, x, shift):
    """Combined-slip weighting ``G = cos(C atan(Bx_s - E(...))) / G_0`` with ``x_s = x +
    shift`` (Pacejka 2012 eqs. (4.E51)-(4.E52), (4.E59)-(4.E60))."""

    def g(s):
        bs = B * s
        return np.cos(C * np.arctan(bs - E * (bs - np.arctan(bs))))

    return g(x + shift) / g(shift)


def dfz(p: Mapping[str, float], Fz):
    """Normalised change of load ``(Fz - Fz0') / Fz0'`` with ``Fz0' = FNOMIN`` (4.E1)-(4.E2a)."""
    return (np.asarray(Fz, float) - p["FNOMIN"]) / p["FNOMIN"]


def pure_fx(p: Mapping[str, float], kappa, Fz):
    """Pure longitudinal slip: ``(Fx0 [N], K_xk [N])``, Pacejka 2012 eqs. (4.E9)-(4.E18)."""
    q = _get(p)
    kappa = np.asarray(kappa, float)
    Fz = np.asarray(Fz, float)
    d = dfz(p, Fz)
    Shx = q("PHX1") + q("PHX2") * d                                           # (4.E17)
    kx = kappa + Shx                                                          # (4.E10)
    Cx = q("PCX1")                                                            # (4.E11)
    Dx = (q("PDX1") + q("PDX2") * d) * Fz                                     # (4.E12-13)
    Ex = np.minimum((q("PEX1") + q("PEX2") * d + q("PEX3") * d * d)
                    * (1.0 - q("PEX4") * np.sign(kx)), 1.0)                   # (4.E14)
    Kx = Fz * (q("PKX1") + q("PKX2") * d) * np.exp(q("PKX3") * d)             # (4.E15)
    Bx = Kx / (Cx * Dx + EPS)                                                 # (4.E16)
    Svx = Fz * (q("PVX1") + q("PVX2") * d)                                    # (4.E18)
    return _mf(Bx, Cx, Dx, Ex, kx) + Svx, Kx


def pure_fy(p: Mapping[str, float], alpha, Fz, gamma=0.0):
    """Pure side slip: ``(Fy0 [N], K_ya [N/rad], B_y, C_y, S_Hy, S_Vy)`` at inclination
    ``gamma`` [rad], Pacejka 2012 eqs. (4.E19)-(4.E30) with the camber terms of the module
    docstring (``PKY6, PKY7, PVY3, PVY4``)."""
    q = _get(p)
    alpha = np.asarray(alpha, float)
    Fz = np.asarray(Fz, float)
    d = dfz(p, Fz)
    Fz0 = p["FNOMIN"]
    gs = np.sin(np.asarray(gamma, float))                                     # (4.E4)
    pky4 = q("PKY4") if "PKY4" in p else 2.0
    Kya = q("PKY1") * Fz0 * np.sin(pky4 * np.arctan(Fz / (q("PKY2") * Fz0)))  # (4.E25)
    Kya_p = Kya + EPS * np.where(Kya < 0, -1.0, 1.0)                          # eps_K
    Kyg0 = Fz * (q("PKY6") + q("PKY7") * d)                                   # (4.E30)
    Svyg = Fz * (q("PVY3") + q("PVY4") * d) * gs                              # (4.E28)
    Shy = q("PHY1") + q("PHY2") * d + (Kyg0 * gs - Svyg) / Kya_p              # (4.E27)
    Svy = Fz * (q("PVY1") + q("PVY2") * d) + Svyg                             # (4.E29)
    ay = alpha + Shy                                                          # (4.E20)
    Cy = q("PCY1")                                                            # (4.E21)
    Dy = (q("PDY1") + q("PDY2") * d) * Fz                                     # (4.E22-23)
    Ey = np.minimum((q("PEY1") + q("PEY2") * d) * (1.0 - q("PEY3") * np.sign(ay)), 1.0)
    By = Kya / (Cy * Dy + EPS)                                                # (4.E26)
    return _mf(By, Cy, Dy, Ey, ay) + Svy, Kya, By, Cy, Shy, Svy


def overturning_mx(p: Mapping[str, float], Fy, Fz, gamma=0.0):
    """Overturning moment [N m], ISO-W: ``R0 Fz (QSX1 - QSX2 gamma + QSX3 Fy / Fz0)``, the
    terms of Pacejka 2012 eq. (4.E69) the fit writes (``QSX4..QSX14`` are not evaluated)."""
    q = _get(p)
    Fz = np.asarray(Fz, float)
    return p["UNLOADED_RADIUS"] * Fz * (q("QSX1") - q("QSX2") * np.asarray(gamma, float)
                                        + q("QSX3") * np.asarray(Fy, float) / p["FNOMIN"])


def rolling_my(p: Mapping[str, float], Fz, Vx, v_ref: float, Fx=0.0, gamma=0.0):
    """Rolling-resistance moment [N m], ISO-W (negative rolling forward), Pacejka 2012 eq.
    (4.E70) at nominal pressure with the sign of MF-Tyre:
    ``-R0 Fz (QSY1 + QSY2 Fx/Fz0 + QSY3 |Vx/V_ref| + QSY4 (Vx/V_ref)^4
    + (QSY5 + QSY6 Fz/Fz0) gamma^2) (Fz/Fz0)^QSY7`` with ``V_ref = LONGVL`` [m/s] (PAC2002,
    which has no ``QSY5..QSY8``, is the case ``QSY5 = QSY6 = QSY7 = 0``)."""
    q = _get(p)
    Fz = np.asarray(Fz, float)
    Fz0 = p["FNOMIN"]
    v = np.asarray(Vx, float) / v_ref
    g = np.asarray(gamma, float)
    inner = (q("QSY1") + q("QSY2") * np.asarray(Fx, float) / Fz0 + q("QSY3") * np.abs(v)
             + q("QSY4") * v**4 + (q("QSY5") + q("QSY6") * Fz / Fz0) * g * g)
    return -p["UNLOADED_RADIUS"] * Fz * inner * (Fz / Fz0) ** q("QSY7")


def evaluate(p: Mapping[str, float], kappa, alpha, Fz, *, combined: bool = True,
             gamma=0.0) -> MFForces:
    """``Fx``, ``Fy`` [N] and ``Mz`` [N m] in ISO-W at slip ``kappa`` [1], slip angle ``alpha``
    [rad], load ``Fz`` [N] and inclination ``gamma`` [rad] (numpy broadcasting);
    ``combined=False`` gives the pure-slip forces of each input alone (``Fx0(kappa)``,
    ``Fy0(alpha, gamma)``, ``Mz0(alpha)``). Camber enters ``Fy`` only (module docstring)."""
    q = _get(p)
    kappa, alpha, Fz, gamma = np.broadcast_arrays(*(np.asarray(x, float)
                                                    for x in (kappa, alpha, Fz, gamma)))
    d = dfz(p, Fz)
    R0 = p["UNLOADED_RADIUS"]
    Fx0, Kx = pure_fx(p, kappa, Fz)
    Fy0, Kya, By, Cy, Shy, Svy = pure_fy(p, alpha, Fz)       # gamma = 0: the Mz terms
    Fy0g = pure_fy(p, alpha, Fz, gamma)[0] if np.any(gamma != 0) else Fy0
    Kya_p = Kya + EPS * np.where(Kya < 0, -1.0, 1.0)                          # (4.E39)
    # aligning moment: pneumatic trail and residual moment (4.E31)-(4.E47)
    Sht = q("QHZ1") + q("QHZ2") * d                                           # (4.E35)
    at = alpha + Sht                                                          # (4.E34)
    ar = alpha + Shy + Svy / Kya_p                                            # (4.E37-38)
    Bt = q("QBZ1") + q("QBZ2") * d + q("QBZ3") * d * d                        # (4.E40)
    Ct = q("QCZ1")                                                            # (4.E41)
    Dt = Fz * (R0 / p["FNOMIN"]) * (q("QDZ1") + q("QDZ2") * d)                # (4.E42-43)
    Et_load = q("QEZ1") + q("QEZ2") * d + q("QEZ3") * d * d
    Br = q("QBZ9") + q("QBZ10") * By * Cy                                     # (4.E45)
    Dr = Fz * R0 * (q("QDZ6") + q("QDZ7") * d) * np.cos(alpha)                # (4.E47)
    cos_a = np.cos(alpha)

    def trail(a):
        Et = np.minimum(Et_load * (1.0 + q("QEZ4") * (2.0 / np.pi) * np.arctan(Bt * Ct * a)),
                        1.0)                                                  # (4.E44)
        ba = Bt * a
        return Dt * np.cos(Ct * np.arctan(ba - Et * (ba - np.arctan(ba)))) * cos_a  # (4.E33)

    if not combined:
        Mz0 = -trail(at) * Fy0 + Dr * np.cos(np.arctan(Br * ar)) * cos_a      # (4.E31-36)
        return MFForces(Fx0, Fy0g, Mz0)
    # combined slip: weighting functions (4.E50)-(4.E67)
    Bxa = q("RBX1") * np.cos(np.arctan(q("RBX2") * kappa))                    # (4.E54)
    Exa = np.minimum(q("REX1") + q("REX2") * d, 1.0)                          # (4.E56)
    Fx = _weight(Bxa, q("RCX1"), Exa, alpha, q("RHX1")) * Fx0                 # (4.E50-53)
    Byk = q("RBY1") * np.cos(np.arctan(q("RBY2") * (alpha - q("RBY3"))))      # (4.E62)
    Eyk = np.minimum(q("REY1") + q("REY2") * d, 1.0)                          # (4.E64)
    Shyk = q("RHY1") + q("RHY2") * d                                          # (4.E65)
    Gyk = _weight(Byk, q("RCY1"), Eyk, kappa, Shyk)                           # (4.E59-61)
    Fy = Gyk * Fy0g                                                           # (4.E58), S_Vyk = 0
    # combined aligning moment (4.E71)-(4.E78)
    r = (Kx / Kya_p) * kappa
    at_eq = np.arctan(np.sqrt(np.tan(at) ** 2 + r * r)) * np.sign(at)         # (4.E77)
    ar_eq = np.arctan(np.sqrt(np.tan(ar) ** 2 + r * r)) * np.sign(ar)         # (4.E78)
    s = R0 * (q("SSZ1") + q("SSZ2") * (Fy / p["FNOMIN"]))                     # (4.E76)
    Mzr = Dr * np.cos(np.arctan(Br * ar_eq)) * cos_a                          # (4.E75)
    Mz = -trail(at_eq) * (Gyk * Fy0) + Mzr + s * Fx                           # (4.E71-74)
    return MFForces(Fx, Fy, Mz)
