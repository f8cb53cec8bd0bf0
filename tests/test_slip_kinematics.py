"""Slip kinematics against hand values (Pacejka 2012, sec. 2.2 and 3.2).

Longitudinal slip kappa = -V_sx / V_x with V_sx = V_x - omega R_e: the forward speed V_x
(not the rolling speed) is the denominator, so a locked wheel has kappa = -1 and a wheel
spinning at twice the rolling speed kappa = +1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tire_brush.slip import slip_from_kinematics, velocities_from_slip


@pytest.mark.parametrize("vx,omega,R_e,kappa", [
    (20.0, 0.0, 0.3, -1.0),              # locked wheel
    (20.0, 20.0 / 0.3, 0.3, 0.0),        # free rolling
    (20.0, 0.9 * 20.0 / 0.3, 0.3, -0.1),  # 10 % braking slip
    (10.0, 2.0 * 10.0 / 0.3, 0.3, 1.0),  # spinning at twice the rolling speed
])
def test_longitudinal_slip_hand_values(vx: float, omega: float, R_e: float,
                                       kappa: float) -> None:
    k, a = slip_from_kinematics(vx, 0.0, omega, R_e)
    assert k == pytest.approx(kappa, abs=1e-12), "kappa = (omega R_e - vx)/vx"
    assert a == 0.0


def test_slip_angle_hand_value() -> None:
    """tan(alpha) = -V_y / V_x: vy = -1 m/s at 10 m/s gives alpha = atan(0.1)."""
    _, a = slip_from_kinematics(10.0, -1.0, 10.0 / 0.3, 0.3)
    assert a == pytest.approx(math.atan(0.1), rel=1e-12)


def test_velocities_from_slip_hand_values() -> None:
    """kappa = -0.2 at 25 m/s: V_sx = 5 m/s, V_r = 20 m/s; alpha = 0.1 rad: V_sy = -25 tan 0.1."""
    V_sx, V_sy, V_r = velocities_from_slip(np.array(-0.2), np.array(0.1), np.array(25.0))
    np.testing.assert_allclose([V_sx, V_sy, V_r], [5.0, -25.0 * math.tan(0.1), 20.0],
                               rtol=1e-12, err_msg="slip velocities")
