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

Partial lift on thin films (:func:`gallaway_speed`, :func:`partial_lift`, :func:`load_lift`)
----------------------------------------------------------------------------------------------
Below full hydroplaning the water met at the footprint's entry still carries part of the
load: the leading zone of Moore's three zones (D.F. Moore, *The Friction of Pneumatic Tyres*,
Elsevier (1975), ch. on wet friction), where the tread rides on the entering film before the
grooves and the texture have taken it. Horne & Dreher's dynamic-pressure argument gives its
size: the lift is (1/2) rho C_L V^2 A, so the lifted share grows as (V / V_p)^2 and reaches
the whole load at the hydroplaning speed V_p of the same water, tread and road. What the
grooves and the texture drain lowers the lift coefficient, i.e. raises V_p; Gallaway et al.
(B.M. Gallaway, D.L. Ivey, G. Hayes et al., *Pavement and Geometric Design Criteria for
Minimizing Hydroplaning*, FHWA-RD-79-31, Texas Transportation Institute (1979)) measured V_p
(10 % wheel spin-down of a free-rolling treaded car tire) over water-film thickness, tread
depth, texture depth and inflation and fitted

.. math:: V_p = SD^{0.04} P^{0.3} (TD + 1)^{0.06} A,\quad
          A = \max\left(\frac{10.409}{WD^{0.06}} + 3.507,\
          \left(\frac{28.952}{WD^{0.06}} - 7.817\right) TXD^{0.14}\right)

in mph, with SD the spin-down [%], P the inflation [psi], TD the tread depth [1/32 in], WD
the water-film thickness above the top of the texture [in] and TXD the texture depth [in]
(the constants as quoted by the FHWA hydroplaning literature; read from a secondary source,
not from the report itself). So the lift on water of depth d (volume per road area, as
everywhere here) is

.. math:: L_p = \min\left(1, (V / V_p(d - TXD))^2\right),

zero when the water stays within the texture (WD = 0: V_p is infinite), rising with the
speed and the film, falling with tread depth, texture depth and inflation. Gallaway's tires
were ribbed passenger tires and his fit has no void term: the groove volume enters only in
Horne's flooded lift above, and the load lifted is the larger of the two,
L = max(L_p, L_Horne) (:func:`load_lift`; on the shipped tires and roads L_p is the larger at
every depth tried). Limits: Gallaway's speeds come from a spin-down trailer in a
hydroplaning trough (the report's abstract), i.e. standing water; the R117 test's 0.3 mm
film above a 0.7 mm texture is far thinner, and the spin-down criterion marks where the
free-rolling wheel loses its drive, which this law takes as full lift.

Status: measured on the shipped tires (docs/physics.md sec. 7a) this law lifts far too much
on the R117 test's 1 mm: the reference tire's trailer peak at 65 km/h falls out of the
regulation's window, so it is not the model. It is a study option of the steady brush
(:class:`tire_brush.wet_friction.WetTireFriction`, ``partial_lift``); the transient tire
core (``tirecore.h``) and the FMUs keep Horne's flooded lift alone.
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
#: Gallaway's spin-down criterion of hydroplaning [%] (FHWA-RD-79-31).
GALLAWAY_SPIN_DOWN = 10.0
_IN = 0.0254            # m per inch
_PSI = 6894.757293168   # Pa per psi
_MPH = 0.44704          # m/s per mph


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


def gallaway_speed(water_film: float, p_inflation: float, tread_depth: float,
                   texture_depth: float, spin_down: float = GALLAWAY_SPIN_DOWN) -> float:
    """Gallaway's hydroplaning speed V_p [m/s] (module docstring, FHWA-RD-79-31).

    Parameters
    ----------
    water_film : float
        Water-film thickness above the top of the texture [m], >= 0 (0: infinite V_p).
    p_inflation : float
        Inflation pressure [Pa], > 0.
    tread_depth : float
        Groove depth [m], >= 0.
    texture_depth : float
        Mean texture depth of the road [m], >= 0.
    spin_down : float
        Wheel spin-down that defines hydroplaning [%], > 0 (Gallaway: 10).
    """
    for name, val, ok in (("water_film", water_film, water_film >= 0),
                          ("p_inflation", p_inflation, p_inflation > 0),
                          ("tread_depth", tread_depth, tread_depth >= 0),
                          ("texture_depth", texture_depth, texture_depth >= 0),
                          ("spin_down", spin_down, spin_down > 0)):
        if not (math.isfinite(val) and ok):
            raise InputError("out of range", field=name, value=val)
    if water_film <= 0.0:
        return math.inf
    return float(_gallaway(water_film, p_inflation, tread_depth, texture_depth, spin_down))


def _gallaway(wf: float, p: float, td: float, txd: float, sd: float) -> float:
    """Gallaway's V_p [m/s] for a film wf > 0 [m] (array or float; inputs checked by the
    callers)."""
    w6 = np.power(wf / _IN, 0.06)
    A = np.maximum(10.409 / w6 + 3.507, (28.952 / w6 - 7.817) * math.pow(txd / _IN, 0.14))
    mph = (math.pow(sd, 0.04) * math.pow(p / _PSI, 0.3) * math.pow(td / _IN * 32.0 + 1.0, 0.06)
           * A)
    return mph * _MPH


def partial_lift(V: np.ndarray, water_depth: np.ndarray, p_inflation: float,
                 tread_depth: float, texture_depth: float = 0.0,
                 spin_down: float = GALLAWAY_SPIN_DOWN) -> np.ndarray:
    """Share L_p = min(1, (V / V_p)^2) of the load the entering film carries, V_p Gallaway's
    speed for the film d - texture_depth above the texture (module docstring), in [0, 1].

    ``V``: forward speed [m/s] (magnitude used); ``water_depth``: water depth [m] (volume per
    road area); the other parameters as :func:`gallaway_speed`.
    """
    V = np.abs(np.asarray(V, float))
    d = np.asarray(water_depth, float)
    if not np.all(np.isfinite(d) & (d >= 0)):
        raise InputError("out of range", field="water_depth", value=d)
    gallaway_speed(0.0, p_inflation, tread_depth, texture_depth, spin_down)  # validates
    film = np.maximum(d - texture_depth, 0.0)
    wet = film > 0.0
    vp = _gallaway(np.where(wet, film, 1.0), p_inflation, tread_depth, texture_depth,
                   spin_down)
    r = V / vp
    return np.where(wet, np.minimum(r * r, 1.0), 0.0)


def load_lift(V: np.ndarray, water_depth: np.ndarray, p_inflation: float,
              tread_depth: float, groove_void_ratio: float = 0.3,
              texture_depth: float = 0.0, d_full: float = D_FULL,
              spin_down: float = GALLAWAY_SPIN_DOWN) -> np.ndarray:
    """Share of the load carried by the water: max(L_p, L_Horne) (module docstring), the
    partial lift of the entering film (:func:`partial_lift`) and Horne's flooded lift
    (:func:`lifted_share`)."""
    return np.maximum(partial_lift(V, water_depth, p_inflation, tread_depth, texture_depth,
                                   spin_down),
                      lifted_share(V, water_depth, p_inflation, tread_depth,
                                   groove_void_ratio, texture_depth, d_full))
