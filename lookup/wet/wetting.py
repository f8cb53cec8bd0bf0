r"""Forced wetting: the sliding speed above which a non-wetting liquid invades a dry contact.

Review eq. (38) (Martin, Buguin & Brochard-Wyart's scaling for a smooth lens of radius R
sliding on a smooth rubber, review ref. [dewet1]):

.. math:: v_c \sim \frac{|S|}{\eta} \left(\frac{|S|}{E R}\right)^{1/3},\qquad S < 0,

with S the spreading pressure of eq. (36). A scaling law (prefactor 1, "derived using simple
and approximate arguments"; the experiments showed v_c ~ eta^(-3/4) rather than eta^(-1)).
The review's example: |S*| = 0.01 J/m^2, eta = 1 Pa s, E = 10 MPa, R = 26 mm give
v_c ~ 0.03 m/s for glycerol on concrete (sec. 8, "Forced dewetting").
"""

from __future__ import annotations

import math

from tirefric.errors import InputError


def forced_wetting_speed(S: float, eta: float, E: float, R: float) -> float:
    """v_c [m/s] of review eq. (38) for spreading pressure S < 0 [J/m^2], viscosity eta
    [Pa s], rubber modulus E [Pa] and asperity radius of curvature R [m]."""
    for name, x in (("eta", eta), ("E", E), ("R", R)):
        if not (math.isfinite(x) and x > 0):
            raise InputError("must be finite and > 0", field=f"wet.{name}", value=x)
    if not (math.isfinite(S) and S < 0):
        raise InputError("forced wetting needs a dewetting liquid, S < 0 [J/m^2] (eq. 36)",
                         field="wet.S", value=S)
    a = abs(S)
    return a / eta * (a / (E * R)) ** (1.0 / 3.0)
