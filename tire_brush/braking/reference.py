"""Closed-form friction curves and stopping-distance limits for the braking studies.

Package code (not test scaffolding; ``docs/design.md``, "Dependency direction"): the tests, the
study runner's analytic friction option and the docs all use these.

Sign convention (Pacejka 2012, sec. 2.2; ``docs/review-notes.md``, "Brush-model closed forms"):
longitudinal slip ``kappa = (omega R_e - v_x) / v_x``, negative in braking, -1 for a locked wheel;
the force ratio ``Fx/Fz`` has the sign of ``kappa``. Every curve here is odd in ``kappa``.

References
----------
.. [Burckhardt1993] M. Burckhardt, *Fahrwerktechnik: Radschlupf-Regelsysteme*, Vogel, 1993.
   The form and the road parameter sets used here are as reproduced in U. Kiencke and
   L. Nielsen, *Automotive Control Systems*, 2nd ed., Springer, 2005 (tyre-road friction
   models, Burckhardt model with its velocity term).
.. [Pacejka2012] H. B. Pacejka, *Tire and Vehicle Dynamics*, 3rd ed., Butterworth-Heinemann,
   2012, sec. 4.3 (the Magic Formula ``y = D sin[C arctan{B x - E (B x - arctan B x)}]``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tirefric.errors import InputError

#: Standard gravity [m/s^2].
G_STANDARD = 9.80665


def _check(name: str, value: float, *, positive: bool = False, nonnegative: bool = False) -> None:
    if not math.isfinite(value):
        raise InputError("must be a finite number", field=name, value=value)
    if positive and not value > 0:
        raise InputError("must be > 0", field=name, value=value)
    if nonnegative and not value >= 0:
        raise InputError("must be >= 0", field=name, value=value)


@dataclass(frozen=True)
class Burckhardt:
    """Burckhardt tyre-road friction curve with its velocity term [Burckhardt1993]_.

    ``mu(s, v) = [c1 (1 - exp(-c2 s)) - c3 s] exp(-c4 s v)``, ``s = |kappa|`` clipped to
    ``[0, 1]``, applied with the sign of ``kappa``.

    Attributes
    ----------
    c1 : float
        Friction scale [1] (the ``c1 - c3`` limit is the locked-wheel friction without c4).
    c2 : float
        Shape (rise rate) of the curve [1].
    c3 : float
        Linear fall of friction with slip [1].
    c4 : float
        Velocity term [s/m]: friction falls with the slip speed ``s v``; Kiencke & Nielsen give
        0.02 to 0.04 s/m. Zero (the default) is the speed-independent curve.
    name : str
        Label (road type).
    """

    c1: float
    c2: float
    c3: float
    c4: float = 0.0
    name: str = "burckhardt"

    def __post_init__(self) -> None:
        _check("c1", self.c1, positive=True)
        _check("c2", self.c2, positive=True)
        _check("c3", self.c3, nonnegative=True)
        _check("c4", self.c4, nonnegative=True)

    def __call__(self, kappa, vx=0.0, Fz=0.0, T_K=0.0) -> np.ndarray:
        """Force ratio ``Fx/Fz`` [1] at slip ``kappa`` [1] and speed ``vx`` [m/s].

        ``Fz`` and ``T_K`` are accepted for the common ``fx_over_fz`` signature and do not
        enter this curve. Broadcasts like numpy.
        """
        kappa, vx, Fz, T_K = np.broadcast_arrays(*(np.asarray(a, dtype=float)
                                                   for a in (kappa, vx, Fz, T_K)))
        s = np.clip(np.abs(kappa), 0.0, 1.0)
        mu = (self.c1 * (1.0 - np.exp(-self.c2 * s)) - self.c3 * s) * np.exp(
            -self.c4 * s * np.abs(vx))
        return np.sign(kappa) * mu

    def peak_slip(self) -> float:
        """Magnitude of the slip of maximum friction [1] for ``c4 = 0``.

        From ``d mu / d s = c1 c2 exp(-c2 s) - c3 = 0``: ``s* = ln(c1 c2 / c3) / c2``,
        clipped to 1 (``c3 = 0`` has its maximum at full slip).
        """
        if self.c3 == 0.0 or self.c1 * self.c2 <= self.c3:
            return 1.0 if self.c3 == 0.0 else 0.0
        return min(1.0, math.log(self.c1 * self.c2 / self.c3) / self.c2)

    def peak_mu(self) -> float:
        """Maximum friction ``mu(s*)`` [1] for ``c4 = 0``."""
        s = self.peak_slip()
        return self.c1 * (1.0 - math.exp(-self.c2 * s)) - self.c3 * s


#: Burckhardt parameter sets ``(c1, c2, c3)`` by road, as tabulated by Kiencke & Nielsen (2005)
#: after [Burckhardt1993]_.
BURCKHARDT_ROADS: dict[str, tuple[float, float, float]] = {
    "asphalt_dry": (1.2801, 23.99, 0.52),
    "asphalt_wet": (0.857, 33.822, 0.347),
    "concrete_dry": (1.1973, 25.168, 0.5373),
    "cobblestone_dry": (1.3713, 6.4565, 0.6691),
    "cobblestone_wet": (0.4004, 33.708, 0.1204),
    "snow": (0.1946, 94.129, 0.0646),
    "ice": (0.05, 306.39, 0.0),
}


def burckhardt_road(road: str, c4: float = 0.0) -> Burckhardt:
    """The Burckhardt curve of a named road (a key of :data:`BURCKHARDT_ROADS`)."""
    if road not in BURCKHARDT_ROADS:
        raise InputError(f"unknown road for the Burckhardt model (known: "
                         f"{', '.join(BURCKHARDT_ROADS)})", field="road", value=road)
    c1, c2, c3 = BURCKHARDT_ROADS[road]
    return Burckhardt(c1, c2, c3, c4, name=road)


@dataclass(frozen=True)
class MagicFormula:
    """Pure longitudinal Magic Formula [Pacejka2012]_ sec. 4.3, scaled by the load.

    ``Fx/Fz = D sin[C arctan{B kappa - E (B kappa - arctan(B kappa))}]``; with ``E <= 1`` the
    curve is odd in ``kappa``.

    Attributes
    ----------
    B : float
        Stiffness factor [1].
    C : float
        Shape factor [1], ``1 < C < 2`` for a curve with a peak that falls towards lock.
    D : float
        Peak factor [1] (the peak force ratio).
    E : float
        Curvature factor [1], ``E <= 1``.
    name : str
        Label (road type).
    """

    B: float
    C: float
    D: float
    E: float
    name: str = "magic_formula"

    def __post_init__(self) -> None:
        _check("B", self.B, positive=True)
        _check("C", self.C, positive=True)
        _check("D", self.D, positive=True)
        _check("E", self.E)
        if self.E > 1.0:
            raise InputError("must be <= 1 (Pacejka 2012 sec. 4.3)", field="E", value=self.E)

    def __call__(self, kappa, vx=0.0, Fz=0.0, T_K=0.0) -> np.ndarray:
        """Force ratio ``Fx/Fz`` [1] at slip ``kappa`` [1]; other inputs do not enter."""
        kappa, vx, Fz, T_K = np.broadcast_arrays(*(np.asarray(a, dtype=float)
                                                   for a in (kappa, vx, Fz, T_K)))
        bx = self.B * np.clip(kappa, -1.0, 1.0)
        return self.D * np.sin(self.C * np.arctan(bx - self.E * (bx - np.arctan(bx))))

    def peak_slip(self) -> float:
        """Magnitude of the slip of maximum force [1] (``C >= 1``).

        The peak is where ``C arctan(phi) = pi / 2``, ``phi = B k - E (B k - arctan(B k))``;
        ``phi`` grows monotonically in ``k`` for ``E <= 1``, so this solves
        ``phi(k) = tan(pi / (2 C))`` by bisection on ``[0, 1]``.
        """
        if self.C <= 1.0:
            return 1.0
        target = math.tan(math.pi / (2.0 * self.C))
        lo, hi = 0.0, 1.0

        def phi(k: float) -> float:
            bx = self.B * k
            return bx - self.E * (bx - math.atan(bx))

        if phi(hi) <= target:
            return 1.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if phi(mid) < target else (lo, mid)
        return 0.5 * (lo + hi)

    def peak_mu(self) -> float:
        """Maximum force ratio [1]."""
        return float(abs(self(-self.peak_slip())))


#: Magic Formula longitudinal coefficients ``(B, C, D, E)`` by road: the typical values after
#: Pacejka tabulated in the MathWorks Simscape Driveline "Tire (Magic Formula)" documentation.
MAGIC_FORMULA_ROADS: dict[str, tuple[float, float, float, float]] = {
    "asphalt_dry": (10.0, 1.9, 1.0, 0.97),
    "asphalt_wet": (12.0, 2.3, 0.82, 1.0),
    "snow": (5.0, 2.0, 0.3, 1.0),
    "ice": (4.0, 2.0, 0.1, 1.0),
}


def magic_formula_road(road: str) -> MagicFormula:
    """The Magic Formula curve of a named road (a key of :data:`MAGIC_FORMULA_ROADS`)."""
    if road not in MAGIC_FORMULA_ROADS:
        raise InputError(f"unknown road for the Magic Formula (known: "
                         f"{', '.join(MAGIC_FORMULA_ROADS)})", field="road", value=road)
    return MagicFormula(*MAGIC_FORMULA_ROADS[road], name=road)


def point_mass_stopping_distance(v0: float, mu: float, v_end: float = 0.0,
                                 g: float = G_STANDARD) -> float:
    """Distance [m] to brake a point mass from ``v0`` to ``v_end`` [m/s] at friction ``mu``.

    Constant deceleration ``mu g``: ``d = (v0^2 - v_end^2) / (2 mu g)``. With ``mu`` the peak
    friction this is the lower bound no controller on a quarter car with a static load can beat
    (the tire force never exceeds ``mu_max Fz``); with the locked-wheel friction it is the
    locked-wheel distance without wheel dynamics.
    """
    if not (v0 > v_end >= 0.0):
        raise InputError("need v0 > v_end >= 0", field="v0, v_end", value=(v0, v_end))
    if not mu > 0:
        raise InputError("friction must be > 0", field="mu", value=mu)
    return (v0**2 - v_end**2) / (2.0 * mu * g)
