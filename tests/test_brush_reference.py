"""Pacejka's closed-form brush (tire_brush.reference) against its own known limits
(docs/review-notes.md: stiffnesses, trail, sliding thresholds, static/kinetic reduction)."""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush import reference as ref

MU, FZ, A, CP = 0.9, 4000.0, 0.066, 1.0e7


def test_small_slip_stiffness_and_trail() -> None:
    """C_F = 2 c_p a^2, C_Malpha = (2/3) c_p a^3: pneumatic trail a/3."""
    s = 1e-7
    assert ref.brush_force(s, MU, FZ, A, CP) / s == pytest.approx(2 * CP * A**2, rel=1e-5)
    Mz = ref.brush_moment(s, MU, FZ, A, CP)
    assert -Mz / s == pytest.approx(2.0 / 3.0 * CP * A**3, rel=1e-5)
    assert -Mz / ref.brush_force(s, MU, FZ, A, CP) == pytest.approx(A / 3, rel=1e-5)


def test_full_sliding_thresholds() -> None:
    """Braking: kappa_sl = -1/(1 + theta); lateral: tan(alpha_sl) = 1/theta."""
    theta = 2 * CP * A**2 / (3 * MU * FZ)
    k_sl = -1.0 / (1.0 + theta)
    sx, _ = ref.theoretical_slip(k_sl, 0.0)
    assert ref.brush_force(sx, MU, FZ, A, CP) == pytest.approx(-MU * FZ, rel=1e-12)
    sx, _ = ref.theoretical_slip(0.999 * k_sl, 0.0)
    assert abs(ref.brush_force(sx, MU, FZ, A, CP)) < MU * FZ
    _, sy = ref.theoretical_slip(0.0, np.arctan(1.0 / theta))
    assert ref.brush_force(sy, MU, FZ, A, CP) == pytest.approx(MU * FZ, rel=1e-12)
    assert ref.brush_moment(sy, MU, FZ, A, CP) == pytest.approx(0.0, abs=1e-9)


def test_static_kinetic_reduces_to_constant() -> None:
    s = np.linspace(-0.2, 0.2, 41)
    np.testing.assert_allclose(ref.brush_static_kinetic(s, MU, MU, FZ, A, CP),
                               ref.brush_force(s, MU, FZ, A, CP), rtol=1e-12, atol=1e-9)


def test_combined_reduces_to_pure() -> None:
    s = np.linspace(-0.1, 0.1, 21)
    Fx, Fy, Mz = ref.brush_combined(s, 0.0, MU, FZ, A, CP)
    np.testing.assert_allclose(Fx, ref.brush_force(s, MU, FZ, A, CP), rtol=1e-12, atol=1e-9)
    assert np.all(Fy == 0) and np.all(Mz == 0)
    Fx, Fy, Mz = ref.brush_combined(0.0, s, MU, FZ, A, CP)
    np.testing.assert_allclose(Mz, ref.brush_moment(s, MU, FZ, A, CP), rtol=1e-12, atol=1e-9)


def test_rigid_buildup_limits() -> None:
    d = np.array([0.0, 1e-6, 2 * A, 5 * A])
    r = ref.rigid_brush_buildup(d, A)
    assert r[0] == 0 and r[2] == pytest.approx(1.0) and r[3] == pytest.approx(1.0)
    assert r[1] / 1e-6 == pytest.approx(1.0 / A, rel=1e-4), "initial slope 1/a"
