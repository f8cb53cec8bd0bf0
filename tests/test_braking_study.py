"""Study spec reading, the brush friction hook and ``tirefric abs study`` end to end."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from tire_brush.braking.friction import Case, brush_fx_over_fz, make_friction_source
from tire_brush.braking.study import RESULT_KEYS, load_study
from tirefric.cli import main
from tirefric.errors import InputError, InputErrors
from tirefric.paths import models_dir

VEHICLE = models_dir() / "studies" / "vehicles" / "passenger.toml"


def write_spec(tmp_path: Path, *, extra: str = "", roads='["snow"]', intervals: int = 40) -> Path:
    text = f"""
[study]
name = "tiny"
v0 = "50 km/h"
v_stop = "1 m/s"
vehicle = "{VEHICLE.as_posix()}"

[friction]
source = "analytic"
model = "burckhardt"

[cases]
roads = {roads}
temperatures = ["20 degC"]

[ocp]
intervals = {intervals}

[simulation]
dt = "1 ms"
{extra}
"""
    p = tmp_path / "tiny.toml"
    p.write_text(text)
    return p


def test_shipped_spec_loads():
    spec = load_study("abs_analytic")
    assert [c.road for c in spec.cases] == ["asphalt_dry", "asphalt_wet", "snow"]
    assert spec.v0 == pytest.approx(100 / 3.6) and spec.car.thermal is not None


def test_spec_errors_name_file_field_value(tmp_path):
    p = write_spec(tmp_path, extra="[abs]\nslip_treshold = 0.2\n", roads="[]")
    with pytest.raises(InputErrors) as info:
        load_study(p)
    text = str(info.value)
    assert "tiny.toml" in text and "abs.slip_treshold" in text, "misspelt key named"
    assert "cases.roads" in text, "an empty road list is reported in the same run"


def test_analytic_source_refuses_compounds():
    with pytest.raises(InputError, match="no compounds"):
        make_friction_source({"source": "analytic"}, Case("asphalt_dry", "summer", 293.15))


def test_brush_adapter_vectorised_and_pointwise():
    """The hook for the brush tire: any steady_state(params, friction, ...) -> {'Fx': ...}."""

    def steady_state(params, friction, kappa, alpha, vx, Fz, T_K):
        # Pacejka 2012 ch. 3 brush, static/kinetic friction (docs/review-notes.md), pure kappa
        sigma = np.abs(kappa) / (1.0 + kappa)
        lam = np.minimum(params["theta"] * sigma, 1.0)
        mu_s, mu_k = friction
        F = 3 * mu_s * lam * (1 - lam) ** 2 + mu_k * lam**2 * (3 - 2 * lam)
        return {"Fx": np.sign(kappa) * Fz * F}

    vec = brush_fx_over_fz(steady_state, {"theta": 8.0}, (1.1, 0.8))
    pt = brush_fx_over_fz(steady_state, {"theta": 8.0}, (1.1, 0.8), vectorized=False)
    k = np.linspace(-0.9, 0.0, 7)[:, None]
    a, b = vec(k, 20.0, np.array([3000.0, 5000.0]), 300.0), pt(k, 20.0, [3000.0, 5000.0], 300.0)
    np.testing.assert_allclose(a, b, rtol=1e-14, err_msg="vectorised vs pointwise adapter")
    assert a.shape == (7, 2) and a[-1, 0] == 0.0 and a[0, 0] == pytest.approx(-0.8)
    with pytest.raises(InputError, match="loads > 0"):
        vec(-0.1, 20.0, 0.0, 300.0)


def test_cli_study_end_to_end(tmp_path, capsys):
    spec = write_spec(tmp_path)
    out = tmp_path / "out"
    assert main(["abs", "study", str(spec), "-o", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    case = doc["cases"][0]
    for key in ("stopping_distance_ocp", "stopping_distance_abs", "stopping_distance_locked"):
        assert 0 < case[key] < 200, f"JSON key {key}: a stopping distance in metres"
    assert -1 < case["optimal_slip"] < 0, "braking slip of the force maximum, in (-1, 0)"
    assert case["point_mass_bound"] <= case["stopping_distance_ocp"] * 1.001
    # the bound with the brake torque's build-up is tighter and still holds (0.1 %: the
    # spline's error at the peak and the collocation error at 40 intervals)
    assert case["point_mass_bound"] < case["ramp_bound"] \
        <= case["stopping_distance_ocp"] * 1.001
    assert case["ramp_bound_reachable"] <= case["ramp_bound"]
    # the bound that follows the tread (here isothermal: the analytic curve has no
    # temperature) is the same construction by dynamic programming: it agrees with the ramp
    # bound to its resolution, and nothing stops shorter
    assert case["thermal_bound"] == pytest.approx(case["ramp_bound_reachable"], rel=3e-3)
    assert case["thermal_bound"] <= case["stopping_distance_ocp"] * 1.001
    assert case["ocp_bound_gap"] == pytest.approx(
        case["stopping_distance_ocp"] / max(case["ramp_bound_reachable"],
                                            case["thermal_bound"]) - 1.0, rel=1e-9)
    assert case["stopping_distance_ocp"] < case["stopping_distance_abs"] \
        < case["stopping_distance_locked"], "OCP < ABS < locked on the snow curve"
    with open(out / "results.csv") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    assert tuple(rows[0]) == RESULT_KEYS and len(rows) == 2
    assert float(rows[1][RESULT_KEYS.index("stopping_distance_ocp")]) == pytest.approx(
        case["stopping_distance_ocp"], rel=1e-7), "CSV and JSON agree"
    for name in ("snow_20C_time.png", "snow_20C_mu_slip.png", "distances.png"):
        assert (out / "plots" / name).stat().st_size > 1000, f"plot {name}"
    assert (out / "slip_maps" / "snow_20C.csv").is_file()
    assert (out / "trajectories" / "snow_20C.csv").is_file()


def test_spec_reads_ocp_jit(tmp_path):
    p = write_spec(tmp_path)
    assert load_study(p).ocp.jit
    p.write_text(p.read_text().replace("intervals = 40", "intervals = 40\njit = false"))
    assert not load_study(p).ocp.jit


def test_cli_bad_spec_exits_2(tmp_path, capsys):
    p = write_spec(tmp_path, extra="[map]\nloads_rel = [0.5, 0.8]\n")
    assert main(["abs", "study", str(p), "-o", str(tmp_path / "o")]) == 2
    assert "must contain 1" in capsys.readouterr().err


@pytest.mark.slow
def test_study_on_dask_cluster(tmp_path):
    """The same results through a Dask scheduler (in-process cluster)."""
    from dask.distributed import LocalCluster

    from tire_brush.braking.study import run_study

    spec = load_study(write_spec(tmp_path, roads='["snow", "asphalt_wet"]'))
    local = run_study(spec)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                      dashboard_address=None) as cluster:
        remote = run_study(spec, scheduler=cluster.scheduler_address)
    for a, b in zip(local, remote, strict=True):
        assert a.summary["stopping_distance_abs"] == b.summary["stopping_distance_abs"]
        assert a.summary["stopping_distance_ocp"] == pytest.approx(
            b.summary["stopping_distance_ocp"], rel=1e-9)


@pytest.fixture(scope="module")
def shipped_study(tmp_path_factory):
    """``abs_default`` run end to end: its exit status and results document."""
    pytest.importorskip("tire_brush.steady")
    if not (models_dir() / "grids" / "default.nc").is_file():
        pytest.skip("default grid not built")
    out = tmp_path_factory.mktemp("abs_default") / "out"
    status = main(["abs", "study", "abs_default", "-o", str(out), "--no-plots"])
    return status, json.loads((out / "results.json").read_text())


def _check_verified_case(c):
    assert c["stopping_distance_ocp"] < c["stopping_distance_abs"], c["case"]
    assert c["stopping_distance_ocp"] < c["stopping_distance_locked"], c["case"]
    assert -1.0 < c["optimal_slip"] < 0.0, c["case"]
    # the kept optimum beats every simulated strategy (idealised and realistic ABS,
    # locked) and respects the lower bound with the brake's ramp at its tread
    # temperatures (0.2 %), which is tighter than the point-mass bound
    assert c["ocp_optimality"] == "verified", (c["case"], c["ocp_optimality"])
    assert c["point_mass_bound"] < c["ramp_bound"] < c["stopping_distance_ocp"], c["case"]
    assert c["stopping_distance_ocp"] < c["stopping_distance_abs_realistic"], c["case"]
    # the bound that follows the tread's heating holds for every strategy, coasting
    # never pays (its relaxation holds), and it leaves the OCP within 5 % of the best
    # possible stop (measured 0.8-1.2 % at 20 and 40 C: the rest is the wheel's spin-down)
    assert c["slip_dp_coast_ratio"] < 1.0, c["case"]
    assert c["thermal_bound"] <= c["stopping_distance_ocp"] * 1.002, c["case"]
    assert c["thermal_bound"] < c["stopping_distance_locked"], c["case"]
    assert c["ocp_bound_gap"] < 0.05, c["case"]


@pytest.mark.slow
def test_shipped_brush_study_runs(shipped_study):
    """``abs_default``: the brush tire on the default grid, end to end; at 20 and 40 C the
    optimum is verified (README's table). The 0 C case is the next test's."""
    status, doc = shipped_study
    warm = [c for c in doc["cases"] if c["T_C"] > 10.0]
    assert sorted(c["T_C"] for c in warm) == [20.0, 40.0]
    for c in warm:
        _check_verified_case(c)
    # the 0 C case is written or listed as failed, never lost; the exit status says which
    cold = [c for c in doc["cases"] if c["T_C"] < 10.0] + doc.get("failed", [])
    assert len(cold) == 1
    assert status == (1 if doc.get("failed") else 0)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "at 0 C the braking OCP on the cold brush map does not converge within IPOPT's 120 s "
    "(or, in an earlier run, ends on a sliding local optimum longer than the idealised "
    "ABS): the cold map's local extrema (README, 'At 0 C the OCP does not converge')"))
def test_shipped_brush_study_cold_case_is_verified(shipped_study):
    _, doc = shipped_study
    cold = [c for c in doc["cases"] if c["T_C"] < 10.0]
    assert len(cold) == 1
    _check_verified_case(cold[0])


def test_a_failed_case_is_reported_and_the_study_goes_on(tmp_path, monkeypatch, capsys):
    """One of two cases fails (its run raises): the other is solved and written, the failure
    is listed in results.json and results.csv with its message, and the command exits 1."""
    from tire_brush.braking import study

    real = study.run_case

    def flaky(spec, case, fmu_simulator=None):
        if case.label.startswith("snow"):
            raise RuntimeError("solver exploded (test)")
        return real(spec, case, fmu_simulator)

    monkeypatch.setattr(study, "run_case", flaky)
    spec = write_spec(tmp_path, roads='["snow", "asphalt_wet"]')
    out = tmp_path / "out"
    assert main(["abs", "study", str(spec), "-o", str(out), "--no-plots", "--jobs", "1"]) == 1
    doc = json.loads((out / "results.json").read_text())
    assert [c["case"] for c in doc["cases"]] == ["asphalt_wet_20C"]
    assert doc["failed"] == [{"case": "snow_20C", "error": "RuntimeError: solver exploded (test)"}]
    text = (out / "results.csv").read_text()
    assert "# case snow_20C FAILED: RuntimeError: solver exploded (test)" in text
    assert "FAILED" in capsys.readouterr().err
    assert (out / "trajectories" / "asphalt_wet_20C.csv").is_file()


@pytest.mark.slow
def test_cases_in_parallel_give_the_same_results(tmp_path, capsys):
    """Two cases in two worker processes (--jobs 2) and in this process (--jobs 1): the same
    numbers to the last digit (a case depends on nothing but its inputs), in the cases'
    order; a case that fails in a worker is reported like one in this process. (~25 s:
    each worker process imports CasADi and SciPy afresh.)"""
    spec = write_spec(tmp_path, roads='["snow", "asphalt_wet"]')
    docs = []
    for jobs in ("1", "2"):
        out = tmp_path / f"out{jobs}"
        assert main(["abs", "study", str(spec), "-o", str(out), "--no-plots", "--jobs", jobs,
                     "--json"]) == 0
        docs.append(json.loads(capsys.readouterr().out))
    for a, b in zip(docs[0]["cases"], docs[1]["cases"], strict=True):
        assert a["case"] == b["case"]
        for key in ("stopping_distance_ocp", "stopping_distance_abs",
                    "stopping_distance_abs_realistic", "stopping_distance_locked"):
            assert a[key] == b[key], (a["case"], key)
    assert [c["case"] for c in docs[1]["cases"]] == ["snow_20C", "asphalt_wet_20C"]
    bad = write_spec(tmp_path, roads='["snow", "asphalt_wet"]',
                     extra="[abs]\nslip_threshold = 0.2\n")
    # a valid spec whose second case cannot stop within t_max: a failure inside a worker
    bad.write_text(bad.read_text().replace('dt = "1 ms"', 'dt = "1 ms"\nt_max = "0.2 s"'))
    out = tmp_path / "outbad"
    assert main(["abs", "study", str(bad), "-o", str(out), "--no-plots", "--jobs", "2"]) == 1
    doc = json.loads((out / "results.json").read_text())
    assert {f["case"] for f in doc["failed"]} == {"snow_20C", "asphalt_wet_20C"}
    assert all("did not reach" in f["error"] for f in doc["failed"])
