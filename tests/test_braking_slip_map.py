"""Optimal slip maps against brute-force argmax; CSV export readable by tirefric.config."""

from __future__ import annotations

import numpy as np
import pytest

from tire_brush.braking import ForceMap, default_axes, optimal_slip
from tire_brush.braking.reference import burckhardt_road, magic_formula_road
from tirefric.config import read_csv_table

K = -np.linspace(0.0, 1.0, 100_001)   # brute-force grid, step 1e-5


def load_temperature_curve(kappa, vx, Fz, T_K):
    """Peak slip and height moving with speed (c4), load and temperature (a made-up law)."""
    c = burckhardt_road("asphalt_dry", c4=0.03)
    s = 1.0 + 0.2 * (Fz - 4000.0) / 4000.0 + 0.3 * (T_K - 300.0) / 100.0
    return c(kappa * s, vx) * (1.0 - 0.1 * (T_K - 300.0) / 100.0)


@pytest.mark.parametrize("source", [burckhardt_road("asphalt_wet", c4=0.03),
                                    magic_formula_road("asphalt_dry"), load_temperature_curve],
                         ids=["burckhardt-c4", "magic-formula", "load-temperature"])
def test_slip_map_maximises_braking_force(source):
    vx, Fz, T = np.array([2.0, 10.0, 30.0]), np.array([3000.0, 5000.0]), np.array([280., 330.])
    sm = optimal_slip(source, vx, Fz, T)
    for idx in np.ndindex(sm.kappa_opt.shape):
        v, f, t = vx[idx[0]], Fz[idx[1]], T[idx[2]]
        mu = source(K, v, f, t)
        i = np.argmin(mu)
        # 2e-5: twice the brute-force step; the map's refinement is finer
        assert abs(sm.kappa_opt[idx] - K[i]) < 2e-5, f"slip at {v, f, t} vs brute-force argmax"
        assert sm.mu_max[idx] >= -mu[i] - 1e-12, "the map's force is at least the brute force"
        assert sm.mu_locked[idx] == pytest.approx(-float(source(-1.0, v, f, t)), abs=1e-14)


def test_slip_map_on_force_map_and_csv(tmp_path):
    curve = burckhardt_road("asphalt_dry")
    fm = ForceMap.build(curve, **default_axes(30.0, 1.0, 4000.0, 293.0))
    sm = optimal_slip(fm, [5.0, 20.0], [4000.0], [293.0], label="Burckhardt dry")
    # 1e-4: the spline's peak vs the closed form (map resolution)
    np.testing.assert_allclose(sm.kappa_opt, -curve.peak_slip(), atol=1e-4,
                               err_msg="slip map on the force map vs closed-form peak")
    path = sm.to_csv(tmp_path / "slip.csv")
    cols = read_csv_table(path, {"vx": "velocity", "Fz": "force", "T": "temperature",
                                 "kappa_opt": "dimensionless", "mu_max": "dimensionless",
                                 "mu_locked": "dimensionless"})
    np.testing.assert_allclose(cols["kappa_opt"], sm.kappa_opt.ravel(), rtol=1e-9,
                               err_msg="CSV round trip")
    assert sm.interpolate(10.0, 4000.0, 293.0) == pytest.approx(sm.kappa_opt.mean(), abs=1e-9)


def test_peak_width_and_stable_branch_against_the_burckhardt_curve(tmp_path):
    """The slips where the braking friction falls to 95 % of its peak, found independently by
    bisection on the closed-form Burckhardt curve (to 1e-10), and the map's bounds from its
    801-point scan (linear between points: 1e-4 in slip, an eighth of the spacing 1.25e-3 on
    this gently curved peak); the stable branch is the closed-form curve on [kappa_opt, 0]
    and rises monotonically to the peak; the JSON export carries all of it."""
    import json

    from scipy.optimize import brentq

    curve = burckhardt_road("asphalt_dry")
    sm = optimal_slip(curve, [10.0], [4000.0], [293.0], label="Burckhardt dry")
    s_opt, mu_pk = curve.peak_slip(), curve.peak_mu()
    f = lambda s: -float(curve(-s, 10.0)) - 0.95 * mu_pk  # noqa: E731
    s_lo = brentq(f, 1e-9, s_opt, xtol=1e-12)
    s_hi = brentq(f, s_opt, 1.0, xtol=1e-12) if f(1.0) < 0 else 1.0
    kp = sm.kappa_peak[0, 0, 0]
    assert kp[0] == pytest.approx(-s_lo, abs=1e-4) and kp[1] == pytest.approx(-s_hi, abs=1e-4)
    assert sm.peak_width[0, 0, 0] == pytest.approx(s_hi - s_lo, abs=2e-4)
    branch = sm.stable_mu[0, 0, 0]
    kk = sm.kappa_opt[0, 0, 0] * np.linspace(0.0, 1.0, branch.size)
    np.testing.assert_allclose(branch, -curve(kk, 10.0), rtol=1e-12)
    assert np.all(np.diff(branch) > 0), "the stable branch rises to the peak"
    doc = json.loads(sm.to_json(tmp_path / "slip.json").read_text())
    pt = doc["points"][0]
    assert pt["peak_width"] == pytest.approx(s_hi - s_lo, abs=2e-4)
    assert len(pt["stable_branch"]["kappa"]) == branch.size
    assert min(pt["stable_branch"]["kappa"]) == pytest.approx(sm.kappa_opt[0, 0, 0])
