"""The wet-grip braking test (tirefric abs wet-grip): BFC bookkeeping, wet vs dry, G, classes,
hydroplaning lift in the tire friction, CLI."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest

from tire_brush.braking.simulation import SimResult
from tire_brush.braking.wet_grip_test import (
    _grids,
    bfc_distance,
    friction_source,
    load_wet_grip_spec,
    run_wet_grip,
)
from tire_brush.params import load_tire
from tire_brush.wet_friction import (
    WetRoad,
    WetTireFriction,
    footprint_time,
    peak_fx_over_fz,
)
from tire_brush.wet_grip import G_ACCEL, braking_force_coefficient, label_class
from tirefric.errors import InputError

KMH = 1 / 3.6


@pytest.fixture(scope="module")
def spec():
    return load_wet_grip_spec()


@pytest.fixture(scope="module")
def grids(spec):
    return _grids(spec.grid)


def _constant_deceleration_run(a: float, v0: float, v_end: float, dt: float = 1e-3) -> SimResult:
    t = np.arange(0.0, (v0 - v_end) / a, dt)
    t = np.append(t, (v0 - v_end) / a)
    v = v0 - a * t
    x = v0 * t - 0.5 * a * t**2
    z = np.zeros_like(t)
    return SimResult(t=t, x=x, v=v, omega=z, brake_torque=z, kappa=z, mu=z, T_tread=z,
                     phase=z.astype(int), stopping_distance=float(x[-1]),
                     stop_time=float(t[-1]), dt=dt)


def test_bfc_of_constant_deceleration_is_its_g_multiple():
    # closed form: a run at constant deceleration a from 90 to 20 km/h has BFC = a / g between
    # 80 and 20 km/h, whatever happened before 80 (here nothing: the same a from the start)
    for mu in (0.45, 0.7, 0.93):
        sim = _constant_deceleration_run(mu * G_ACCEL, 90 * KMH, 20 * KMH)
        d = bfc_distance(sim, 80 * KMH)
        d_exact = ((80 * KMH) ** 2 - (20 * KMH) ** 2) / (2 * mu * G_ACCEL)
        # the passing point is interpolated linearly in v between 1 ms steps (x is quadratic
        # in t, v linear: the interpolation error is below a^2 dt^2 / 8 v ~ 1e-7 m)
        assert d == pytest.approx(d_exact, abs=1e-5), "distance v1 -> v2"
        bfc = braking_force_coefficient(80 * KMH, 20 * KMH, d)
        assert bfc == pytest.approx(mu, rel=1e-5), "BFC of a constant deceleration"


def test_bfc_distance_refuses_a_run_below_v1():
    sim = _constant_deceleration_run(5.0, 70 * KMH, 20 * KMH)
    with pytest.raises(InputError, match="v1"):
        bfc_distance(sim, 80 * KMH)


@pytest.mark.parametrize("G,cls", [(1.56, "A"), (1.55, "A"), (1.5449, "B"), (1.40, "B"),
                                   (1.3949, "C"), (1.25, "C"), (1.2449, "D"), (1.10, "D"),
                                   (1.0949, "E")])
def test_label_class_boundaries(G, cls):
    # Regulation (EU) 2020/740, C1: A >= 1.55, B 1.40-1.54, C 1.25-1.39, D 1.10-1.24, E <= 1.09
    assert label_class(G) == cls


def test_footprint_time_of_the_srtt():
    # 2a / V with Pacejka eq. (A3.7): at 4.41 kN and 80 km/h about 7 ms for a 0.15 m patch
    p = load_tire("srtt")
    a, _ = p.patch.size(4413.0)
    assert footprint_time(p, 4413.0, 80 * KMH) == pytest.approx(2 * a / (80 * KMH), rel=1e-12)
    assert 0.06 < a < 0.09, a


def test_wet_below_dry_on_the_brush(spec, grids):
    # the steady brush at 65 km/h, 20 C: wet friction (1 mm) below dry at every slip, and the
    # peak clearly lower (the grid's wet branch lowers the adhesive term by squeeze-out)
    dry = friction_source(spec, "passenger", 0.0, grids)
    wet = friction_source(spec, "passenger", 1e-3, grids)
    k = -np.geomspace(1e-3, 1.0, 25)
    fd, fw = dry(k, 65 * KMH, 4400.0, 293.15), wet(k, 65 * KMH, 4400.0, 293.15)
    assert np.all(-fw <= -fd * (1 + 1e-9)), "wet force above dry"
    pd = peak_fx_over_fz(dry, 65 * KMH, 4400.0, 293.15)[0]
    pw = peak_fx_over_fz(wet, 65 * KMH, 4400.0, 293.15)[0]
    assert pw < 0.97 * pd, (pw, pd)


def test_hydroplaning_lift_reduces_the_force(grids):
    # deep water (10 mm) on a worn tread (2 mm) at 110 km/h: Horne's lift at 230 kPa
    # (V_p = 96.3 km/h) carries the whole load: no force. At 40 km/h the lift share is
    # (40 / 96.3)^2 = 0.17 and the force is (1 - 0.17) x the brush force at the reduced load
    p = load_tire("passenger")
    dry, wet = grids
    road = WetRoad(10e-3, 0.7e-3, 2e-3)
    on = WetTireFriction(p, dry, wet, road)
    off = WetTireFriction(p, dry, wet, road, hydroplaning=False)
    k = np.array([-0.05, -0.1])
    assert np.all(on(k, 110 * KMH, 4000.0, 293.15) == 0.0), "full hydroplaning: no force"
    assert np.all(-off(k, 110 * KMH, 4000.0, 293.15) > 0.3)
    share = float(on.lifted_share(40 * KMH))
    assert share == pytest.approx((40 / 96.31) ** 2, rel=2e-3)
    f_on = on(k, 40 * KMH, 4000.0, 293.15)
    f_ref = (1 - share) * off.brush(40 * KMH, (1 - share) * 4000.0).fx_over_fz(
        k, 40 * KMH, (1 - share) * 4000.0, 293.15)
    np.testing.assert_allclose(f_on, f_ref, rtol=1e-12)
    assert np.all(-f_on < -off(k, 40 * KMH, 4000.0, 293.15)), "lift must lower the force"
    # the test's 1 mm on a new tread: grooves and texture take the water, no lift
    assert float(WetTireFriction(p, dry, wet, WetRoad(1e-3, 0.7e-3, 8e-3))
                 .lifted_share(200 * KMH)) == 0.0


def test_bad_inputs_name_the_field(spec):
    with pytest.raises(InputError) as e:
        WetRoad(-1e-3)
    assert e.value.field == "water_depth"
    with pytest.raises(InputError) as e:
        run_wet_grip(spec, "passenger", water_depth=-1e-3)
    assert e.value.field == "water_depth"
    with pytest.raises(InputError) as e:
        run_wet_grip(spec, "no_such_tire")
    assert "no_such_tire" in str(e.value)
    with pytest.raises(InputError) as e:
        run_wet_grip(spec, "passenger", T_C=80.0)
    assert e.value.field == "temperature"


@pytest.mark.slow
def test_candidate_equal_to_reference_gives_1_25(spec):
    doc, _ = run_wet_grip(dataclasses.replace(spec, reference_tire="srtt"), "srtt")
    assert doc["G"] == pytest.approx(1.25, abs=1e-12)
    assert doc["G_trailer"] == pytest.approx(1.25, abs=1e-12)
    assert doc["label_class"] == "C"


@pytest.mark.slow
def test_wet_bfc_below_dry_and_reference_windows(spec):
    doc, _ = run_wet_grip(spec, "passenger")
    for who in ("candidate", "reference"):
        r = doc[who]
        assert r["bfc_wet"] < 0.95 * r["bfc_dry"], (who, r["bfc_wet"], r["bfc_dry"])
        assert r["peak_wet"] < r["peak_dry"], who
        # the BFC is a mean deceleration under ABS: below the tire's peak over the speeds
        assert r["bfc_wet"] < r["peak_wet"] * 1.02, who
    ref = doc["reference"]
    # measured on the shipped models (docs/physics.md, wet grip): BFC 0.66, peak 0.74 (0.69
    # and 0.75 on the realistic compound before the asperity squeeze-out, 0.73 and 0.79 on the
    # previous synthetic compound); a change of more than a few hundredths is a change of the
    # physics, not noise
    assert ref["bfc_wet"] == pytest.approx(0.659, abs=0.02)
    assert ref["peak_wet"] == pytest.approx(0.739, abs=0.02)
    G = 1.25 * doc["candidate"]["bfc_wet"] / ref["bfc_wet"]  # same temperature: no correction
    assert doc["G"] == pytest.approx(G, rel=1e-12)
    assert doc["label_class"] == label_class(G)


@pytest.mark.slow
def test_cli_json_keys_and_errors(tmp_path):
    base = [sys.executable, "-m", "tirefric.cli", "abs", "wet-grip"]
    out = subprocess.run([*base, "--json", "--plot", str(tmp_path / "w.png")],
                         capture_output=True, text=True, check=True).stdout
    doc = json.loads(out)
    assert {"G", "G_trailer", "label_class", "candidate", "reference", "water_depth_m",
            "T_C", "bfc_candidate_20C", "bfc_reference_20C", "reference_windows"} <= set(doc)
    assert {"bfc_wet", "bfc_dry", "peak_wet", "peak_dry", "distance_v1_v2_wet_m",
            "hydroplaning_share_v1_wet"} <= set(doc["candidate"])
    assert doc["candidate"]["tire"] == "passenger" and doc["reference"]["tire"] == "srtt"
    assert (tmp_path / "w.png").stat().st_size > 10_000
    for args, word in ((["--water-depth=-1"], "water_depth"), (["--tire", "nope"], "nope")):
        r = subprocess.run(base + args, capture_output=True, text=True)
        assert r.returncode == 2 and word in r.stderr, r.stderr
