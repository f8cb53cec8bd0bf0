r"""Dynamic hydroplaning: the share of a tire's load carried by water pressure.

Horne & Dreher (NASA TN D-2056, 1963) found that a tire on water deeper than its tread can
drain hydroplanes fully at the speed

.. math:: V_p = 6.35 \sqrt{p_i / \mathrm{kPa}}\ \mathrm{km/h}

(9 sqrt(p_i / psi) knots), p_i the inflation pressure. Their derivation: the water wedge in
front of the footprint produces a lift F_h = (1/2) rho C_L V^2 A on the footprint area A,
and the footprint's mean contact pressure is about p_i (F_z = p_i A); V_p is where F_h = F_z.
With rho = 1000 kg/m^3 the formula implies C_L = 2 p_i / (rho V_p^2) = 0.643.

Model here (this function, and the same formula in the transient tire core, ``tirecore.h``):

* the share of the footprint load lifted by the water is
  lift = s(d) min(1, (V / V_p)^2), i.e. F_h / F_z with Horne's lift coefficient;
* s(d) is the depth factor: water the tread grooves and the road's texture can take does not
  build up the wedge; the excess depth d_e = max(d - d_drain, 0), with
  d_drain = groove_void_ratio * tread_depth + texture_depth (volume per area the grooves and
  the road texture hold), raises s linearly to 1 at d_e = d_full.

Limits: Horne's formula is for water deeper than the tread grooves and for the pressure
ranges of aircraft and truck tires; it ignores the tire's shape, load and carcass stiffness
(light-load passenger tires hydroplane at lower speeds than it gives, the "Horne-Gallaway"
refinements). The linear depth factor and d_full (the excess depth at which the wedge is
fully developed; TN D-2056 reports full hydroplaning for water depths above the groove depth,
of the order of a few millimetres) are model assumptions of this module, not results of the
report. The lift is quasi-steady (no spin-down of the wheel, no viscous hydroplaning).
"""

from __future__ import annotations

import math

import numpy as np

from tirefric.errors import InputError

#: Horne's constant [km/h per sqrt(kPa)] (NASA TN D-2056).
HORNE_KMH_PER_SQRT_KPA = 6.35
RHO_WATER = 1000.0  # kg/m^3
#: Excess water depth [m] at which the wedge is fully developed (model assumption, module
#: docstring); the tire core uses the same value.
D_FULL = 2.5e-3


def horne_speed(p_inflation: float) -> float:
    """Full dynamic-hydroplaning speed V_p [m/s] for inflation pressure [Pa] (Horne)."""
    if not (math.isfinite(p_inflation) and p_inflation > 0):
        raise InputError("must be finite and > 0 [Pa]", field="p_inflation", value=p_inflation)
    return HORNE_KMH_PER_SQRT_KPA * math.sqrt(p_inflation / 1e3) / 3.6


def lift_coefficient() -> float:
    """Horne's implied lift coefficient C_L = 2 p / (rho V_p^2) (module docstring)."""
    return 2e3 / (RHO_WATER * (HORNE_KMH_PER_SQRT_KPA / 3.6) ** 2)


def lifted_share(V: np.ndarray, water_depth: np.ndarray, p_inflation: float,
                 tread_depth: float, groove_void_ratio: float = 0.3,
                 texture_depth: float = 0.0, d_full: float = D_FULL) -> np.ndarray:
    """Share of the footprint load carried by water pressure (module docstring), in [0, 1].

    Parameters
    ----------
    V : array
        Forward speed [m/s] (its magnitude is used).
    water_depth : array
        Water film depth on the road [m] (volume per area), >= 0.
    p_inflation : float
        Inflation pressure [Pa].
    tread_depth : float
        Groove depth [m], >= 0.
    groove_void_ratio : float
        Groove area share of the tread pattern, in [0, 1).
    texture_depth : float
        The road's mean texture depth [m] (water the texture holds), >= 0.
    d_full : float
        Excess depth [m] at which the wedge is fully developed (> 0).
    """
    V = np.abs(np.asarray(V, float))
    d = np.asarray(water_depth, float)
    checks = [("water_depth", d, np.all(np.isfinite(d) & (d >= 0))),
              ("tread_depth", tread_depth, math.isfinite(tread_depth) and tread_depth >= 0),
              ("groove_void_ratio", groove_void_ratio, 0 <= groove_void_ratio < 1),
              ("texture_depth", texture_depth, math.isfinite(texture_depth)
               and texture_depth >= 0),
              ("d_full", d_full, math.isfinite(d_full) and d_full > 0)]
    for name, val, ok in checks:
        if not ok:
            raise InputError("out of range", field=name, value=val)
    Vp = horne_speed(p_inflation)
    d_e = np.maximum(d - (groove_void_ratio * tread_depth + texture_depth), 0.0)
    s = np.minimum(d_e / d_full, 1.0)
    return s * np.minimum((V / Vp) ** 2, 1.0)
