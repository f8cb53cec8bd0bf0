"""Compound screening (tire_brush.screening, docs/screening.md): the sweep, the store, resume,
failures, worker-count independence, and agreement with the single-compound commands."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from tirefric.errors import InputError
from tirefric.paths import resolve_model_file


def _spec(tmp: Path, body: str) -> Path:
    p = tmp / "screen.toml"
    p.write_text(body, encoding="utf-8")
    return p


# -- a screen small enough for tests: coarse grids, small maps, long steps ----------------------
# The physics checks below compare the screen with the single-compound functions at the SAME
# resolution, where they must agree to rounding; coarse axes only make them fast.
TINY_RESOLUTION = """
[resolution]
dry_v_per_decade = 1
wet_v_per_decade = 1
v_min = "1e-3 m/s"
dry_p_nodes = 3
wet_p_nodes = 3
stop_T_step = 0                 # the tiny study's own force-map temperatures and step
stop_dt = 0
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory) -> Path:
    """A folder with a small braking study and wet grip spec (copies of the shipped ones
    with few map nodes and 2 ms steps) for screens that run in seconds."""
    import re

    d = tmp_path_factory.mktemp("tiny")
    st_path = resolve_model_file("abs_default", "studies")
    veh = str(st_path.parent / "vehicles" / "passenger.toml")
    st = st_path.read_text()
    st = st.replace('vehicle = "vehicles/passenger.toml"', f'vehicle = "{veh}"')
    st = st.replace("fmu_abs = true", "fmu_abs = false")
    st = re.sub(r"\n\[fmu\].*", "\n", st, flags=re.S)
    st = re.sub(r"n_kappa = \d+", "n_kappa = 13", st)
    st = re.sub(r"n_v = \d+", "n_v = 4", st)
    st = re.sub(r"temperatures_rel = \[[^\]]*\]", "temperatures_rel = [0.0]", st)
    st = re.sub(r"temperature_step = [0-9.]+", "temperature_step = 10.0", st)
    st = st.replace('dt = "0.5 ms"', 'dt = "2 ms"')
    (d / "study.toml").write_text(st)
    wg = resolve_model_file("wet_grip", "studies").read_text()
    wg = wg.replace('file = "vehicles/passenger.toml"', f'file = "{veh}"')
    wg = re.sub(r"n_kappa = \d+", "n_kappa = 13", wg)
    wg = re.sub(r"n_v = \d+", "n_v = 4", wg)
    wg = wg.replace('dt = "0.5 ms"', 'dt = "2 ms"')
    (d / "wet_grip.toml").write_text(wg)
    return d


def tiny_spec(folder: Path, compounds: str, name: str = "t") -> Path:
    body = f'''name = "{name}"
{compounds}
[roads]
wet_grip = "{folder / 'wet_grip.toml'}"
[braking]
study = "{folder / 'study.toml'}"
[outputs]
peak_temperatures = ["20 degC"]
{TINY_RESOLUTION}'''
    p = folder / f"{name}.toml"
    p.write_text(body, encoding="utf-8")
    return p


# -- fast checks --------------------------------------------------------------------------------
def test_sweep_points_cover_ranges_reproducibly():
    """Factorial: every combination of the levels; LHS: one point per stratum in each
    parameter (the Latin property, McKay et al. 1979); Sobol: 2^m points; the same seed gives
    the same points."""
    from tire_brush.screening.spec import Sweep

    r = {"T_g_shift": (-5.0, 5.0), "E_inf_scale": (0.8, 1.25)}
    f = Sweep("summer", "factorial", 3, 0, r).points()
    assert len(f) == 9
    assert sorted({p["T_g_shift"] for p in f}) == [-5.0, 0.0, 5.0]
    lhs = Sweep("summer", "lhs", 8, 3, r).points()
    for k, (lo, hi) in r.items():
        strata = sorted(int((p[k] - lo) / (hi - lo) * 8) for p in lhs)
        assert strata == list(range(8))
    s1 = Sweep("summer", "sobol", 8, 1, r).points()
    assert s1 == Sweep("summer", "sobol", 8, 1, r).points()
    assert s1 != Sweep("summer", "sobol", 8, 2, r).points()
    assert all(lo <= p[k] <= hi for p in s1 for k, (lo, hi) in r.items())


def test_glass_temperature_shift_is_time_temperature_superposition(tmp_path):
    """A variant with T_g moved by dT at temperature T has the base's loss modulus at
    T - dT (Ferry ch. 11). The spectrum's Prony arms sit on a decade-aligned grid (4 per
    decade, lookup.modulus._lognormal_arms), so a moved centre is re-sampled: 1 % covers that
    sampling (measured 0.06-0.4 % at 10 K of shift); a wrong WLF re-reference is off by
    factors."""
    from lookup.compound import load_compound
    from tire_brush.screening.compounds import write_compound

    base = str(resolve_model_file("summer", "compounds"))
    c0 = load_compound(base)
    w = np.logspace(-2, 8, 21)
    for dT in (-5.0, 5.0):
        c = load_compound(write_compound({"name": "v", "base": base,
                                          "params": {"T_g_shift": dT}}, tmp_path / "v.toml"))
        for T in (273.15, 293.15, 323.15):
            a_new = 10 ** c.log10_aT(np.array(T))
            a_old = 10 ** c0.log10_aT(np.array(T - dT))
            e_new = c.modulus.storage_loss(w * a_new)[1]
            e_old = c0.modulus.storage_loss(w * a_old)[1]
            np.testing.assert_allclose(e_new, e_old, rtol=1e-2)
        # the adhesion (eq. 21, shifted with the bulk a_T) moves with it
        v = np.logspace(-4, 1, 7)
        np.testing.assert_allclose(c.adhesion.sigma_f(v, np.full(7, 303.15)),
                                   c0.adhesion.sigma_f(v, np.full(7, 303.15 - dT)),
                                   rtol=1e-9)


def test_other_parameters_change_only_their_number(tmp_path):
    from lookup.compound import load_compound
    from tire_brush.screening.compounds import write_compound

    base = str(resolve_model_file("summer", "compounds"))
    c0 = load_compound(base)
    c = load_compound(write_compound({"name": "v", "base": base, "params": {
        "E_inf_scale": 1.2, "breadth_scale": 0.9, "sigma_f0_scale": 0.5,
        "softening_strain": 0.2}}, tmp_path / "v.toml"))
    assert c.modulus.E_inf == pytest.approx(1.2 * c0.modulus.E_inf, rel=1e-12)
    assert c.modulus.widths[0] == pytest.approx(0.9 * c0.modulus.widths[0], rel=1e-12)
    assert c.modulus.widths[1] == c0.modulus.widths[1]
    assert c.adhesion.sigma_f0 == pytest.approx(0.5 * c0.adhesion.sigma_f0, rel=1e-12)
    assert c.strain == 0.2
    with pytest.raises(InputError, match="unknown design parameter"):
        write_compound({"name": "v", "base": base, "params": {"Tg": 1.0}}, tmp_path / "w.toml")


def test_pareto_front():
    from tire_brush.screening.run import pareto_front

    G = [1.2, 1.3, 1.1, 1.3, math.nan]
    rr = [8.0, 9.0, 7.0, 9.5, 6.0]
    assert pareto_front(G, rr) == [True, True, True, False, False]


def test_sensitivity_recovers_a_linear_response():
    """On a linear response y = 3 x1 - x2 (x3 inert) over an LHS sample the standardised
    regression coefficients are b_j s_j / s_y exactly and R^2 = 1 (Saltelli et al. 2008,
    sec. 1.2.5); Spearman's rho has the signs and the order."""
    from tire_brush.screening.run import sensitivity
    from tire_brush.screening.spec import Sweep

    pts = Sweep("b", "lhs", 32, 5, {"a": (0, 1), "b": (0, 1), "c": (0, 1)}).points()
    rows = [{"status": "ok", **p, "y": 3 * p["a"] - p["b"]} for p in pts]
    s = sensitivity(rows, ["a", "b", "c"], ["y"])["y"]
    X = np.array([[p["a"], p["b"]] for p in pts])
    y = np.array([r["y"] for r in rows])
    sd = y.std(ddof=1)
    assert s["r2"] == pytest.approx(1.0, abs=1e-12)
    assert s["src"]["a"] == pytest.approx(3 * X[:, 0].std(ddof=1) / sd, rel=1e-9)
    assert s["src"]["b"] == pytest.approx(-X[:, 1].std(ddof=1) / sd, rel=1e-9)
    assert abs(s["src"]["c"]) < 1e-9
    assert s["spearman"]["a"] > 0.8 > abs(s["spearman"]["c"])
    assert s["spearman"]["b"] < 0


def test_spec_errors_name_file_field_and_value(tmp_path):
    from tire_brush.screening.spec import load_screen_spec

    bad = {
        "method": ('[sweep]\nbase = "summer"\nmethod = "grid"\nn = 4\n'
                   '[sweep.parameters]\nT_g_shift = ["-1 K", "1 K"]\n', "sweep.method"),
        "sobol": ('[sweep]\nbase = "summer"\nn = 6\n[sweep.parameters]\n'
                  'T_g_shift = ["-1 K", "1 K"]\n', "sweep.n"),
        "param": ('[sweep]\nbase = "summer"\nn = 4\n[sweep.parameters]\n'
                  'Tg = ["-1 K", "1 K"]\n', "sweep.parameters.Tg"),
        "range": ('[sweep]\nbase = "summer"\nn = 4\n[sweep.parameters]\n'
                  'T_g_shift = ["1 K", "-1 K"]\n', "sweep.parameters.T_g_shift"),
        "unit": ('[sweep]\nbase = "summer"\nn = 4\n[sweep.parameters]\n'
                 'T_g_shift = ["1 bar", "2 bar"]\n', "sweep.parameters.T_g_shift"),
        "none": ("", "compounds"),
        "dt": ('[compounds]\nfiles = ["summer"]\n[resolution]\nstop_dt = "20 ms"\n',
               "resolution.stop_dt"),
        "T_step": ('[compounds]\nfiles = ["summer"]\n[resolution]\nstop_T_step = "-1 K"\n',
                   "resolution.stop_T_step"),
    }
    for what, (body, field) in bad.items():
        p = _spec(tmp_path, f'name = "x"\n{body}[roads]\n')
        with pytest.raises(InputError) as e:
            load_screen_spec(p)
        assert e.value.field == field, what
        assert str(p) in str(e.value), what


def test_bad_compounds_are_named_and_fail_fast(tmp_path):
    """A missing file and a compound whose T_ref is not where its shift factor is 1 fail
    with their reason in the record; evaluate_compound never raises."""
    from tire_brush.screening.evaluate import evaluate_compound
    from tire_brush.screening.spec import load_screen_spec, screen_settings

    src = resolve_model_file("summer", "compounds").read_text()
    wrong = src.replace('[modulus]\nT_ref = "20 degC"', '[modulus]\nT_ref = "40 degC"')
    assert wrong != src
    (tmp_path / "wrong_tref.toml").write_text(wrong.replace(
        'file = "data/', f'file = "{resolve_model_file("summer", "compounds").parent}/data/'))
    p = _spec(tmp_path, 'name = "x"\n[compounds]\nfiles = ["missing.toml", "wrong_tref.toml"]\n'
                        '[roads]\n')
    spec = load_screen_spec(p)
    settings = screen_settings(spec)
    recs = [evaluate_compound(settings, d, "k") for d in spec.compounds()]
    assert [r["name"] for r in recs] == ["missing", "wrong_tref"]
    assert all(r["status"] == "failed" for r in recs)
    assert "file not found" in recs[0]["error"] and "missing.toml" in recs[0]["error"]
    assert "T_ref" in recs[1]["error"] and "modulus.T_ref" in recs[1]["error"]


def test_store_key_follows_inputs(tmp_path):
    """The key changes with the compound, a file it reads and the settings; not otherwise."""
    from tire_brush.screening.store import compound_key

    f = tmp_path / "c.toml"
    f.write_text(resolve_model_file("summer", "compounds").read_text().replace(
        'file = "data/', f'file = "{resolve_model_file("summer", "compounds").parent}/data/'))
    d = {"name": "c", "file": str(f)}
    s = {"tire": "x", "v0_m_s": 27.0}
    k = compound_key(d, s)
    assert k == compound_key(dict(d), dict(s))
    assert k != compound_key(d, {**s, "v0_m_s": 28.0})
    assert k != compound_key({**d, "name": "d"}, s)
    f.write_text(f.read_text().replace('sigma_f0 = "4 MPa"', 'sigma_f0 = "5 MPa"'))
    assert k != compound_key(d, s)


def test_braking_resolution_enters_the_key():
    """The screen's braking settings change the numbers, so they change the cache key (a
    finished compound at other settings is not reused)."""
    import dataclasses

    from tire_brush.screening.spec import load_screen_spec, screen_settings
    from tire_brush.screening.store import compound_key

    s = screen_settings(load_screen_spec("screen_example"))
    d = {"name": "summer", "file": str(resolve_model_file("summer", "compounds"))}
    keys = {compound_key(d, x.describe()) for x in
            (s, dataclasses.replace(s, stop_dt=1e-3), dataclasses.replace(s, stop_T_step=4.0))}
    assert len(keys) == 3


def _pressure_grid(p):
    """A small friction grid on the pressure nodes ``p`` [Pa] whose friction varies with the
    pressure (velocity weakening, a flash-temperature rise), the same formula at every node."""
    from lookup.grid import FrictionGrid

    v = np.logspace(-6, 1.6, 20)
    T = np.array([283.15, 303.15])
    V, TT, P = np.meshgrid(v, T, p, indexing="ij")
    x = np.log10(V) - 0.02 * (TT - 293.15)
    mu_cold = 0.6 + 0.6 * np.exp(-(((x + 1.5) / 2.0) ** 2)) - 0.1 * np.log10(P / 3e5)
    return FrictionGrid.from_arrays(v, T, p, {"mu_cold": mu_cold,
                                              "mu_hot": mu_cold - 0.25 * V / (V + 0.3),
                                              "dT_flash": 80.0 * V / (V + 0.1)},
                                    s0_m=2e-4, D_m=1e-3, meta={"kind": "test grid"})


def test_pressure_axis_ends_at_the_first_node_the_tire_reads():
    """The screening grids' pressure axes end at their first node at or above the largest
    pressure the tire core reads (tire_brush.screening.spec.rubber_pressure_max): the steady
    brush's braking force on such a grid equals the one on the whole axis to rounding (the
    cell position computed from other axis ends: 1e-12 relative), and one node fewer moves
    it (the patch's centre reads the last cell), so the bound is the core's own."""
    from tire_brush.params import load_tire
    from tire_brush.screening.spec import pressure_axis_to, rubber_pressure_max
    from tire_brush.steady import SteadyBrush

    tire = load_tire("passenger")
    Fz = 4413.0
    p = np.geomspace(5e4, 2e6, 10)
    cut = pressure_axis_to(p, rubber_pressure_max(tire, Fz))
    assert 2 <= cut.size < p.size and cut[-1] >= rubber_pressure_max(tire, Fz) > cut[-2]
    kappa = np.array([-0.02, -0.08, -0.3, -1.0])
    force = [SteadyBrush(tire, _pressure_grid(q)).fx_over_fz(kappa, 20.0, Fz, 293.15)
             for q in (p, cut, cut[:-1])]
    np.testing.assert_allclose(force[1], force[0], rtol=1e-12, atol=0.0)
    assert np.max(np.abs(force[2] / force[0] - 1.0)) > 1e-4
    assert np.array_equal(pressure_axis_to(p, 3e6), p)           # beyond the axis: all of it
    assert np.array_equal(pressure_axis_to(p, 1e3), p[:2])       # an axis keeps two nodes


# -- whole screens (slow: each compound builds two grids and brakes four times) -----------------
THREE = '''[compounds]
files = ["summer", "missing.toml"]
[sweep]
base = "summer"
method = "factorial"
n = 2
[sweep.parameters]
T_g_shift = ["-4 K", "4 K"]
'''


class Stop(Exception):
    """Raised by a callback to simulate a run killed after some compounds."""


@pytest.fixture(scope="module")
def screen_a(tiny, tmp_path_factory):
    """An uninterrupted serial screen of three compounds and a missing file."""
    from tire_brush.screening import run_screen

    out = tmp_path_factory.mktemp("a")
    return run_screen(tiny_spec(tiny, THREE), out, workers=1, progress=False,
                      keep_grids=True)


def _outputs(res) -> dict[str, dict]:
    return {r["name"]: r.get("outputs") for r in res.records}


@pytest.mark.slow
def test_screen_writes_results_and_names_the_bad_compound(screen_a):
    res = screen_a
    names = [r["name"] for r in res.records]
    assert names == ["summer", "missing", "summer_0", "summer_1"]
    bad = [r for r in res.records if r["status"] != "ok"]
    assert [r["name"] for r in bad] == ["missing"]
    assert "file not found" in bad[0]["error"]
    for f in ("csv", "json", "netcdf", "pareto", "report"):
        assert Path(res.files[f]).is_file(), f
    doc = json.loads(Path(res.files["json"]).read_text())
    rows = {r["name"]: r for r in doc["compounds"]}
    assert rows["missing"]["status"] == "failed" and rows["missing"]["G"] is None
    assert "missing" in Path(res.files["report"]).read_text()
    import xarray as xr

    ds = xr.open_dataset(res.files["netcdf"], engine="h5netcdf")
    assert "T_g_shift" in ds.coords
    np.testing.assert_array_equal(ds["G"].values, [r["G"] for r in res.rows()])
    # the design parameter reached the physics: the variants' numbers differ from the base's
    o = _outputs(res)
    assert o["summer_0"]["bfc_wet"] != o["summer"]["bfc_wet"] != o["summer_1"]["bfc_wet"]


def _study_stops(study_file: str | Path, grid: str | Path, compound_file: str | Path,
                 name: str, T_K: float = 293.15) -> tuple[float, float]:
    """The dry ABS and locked stops of the braking study's own path (its force map,
    tire_brush.braking.study.case_force_map, and simulate_braking on it, as run_case) at
    load 1 on ``grid``."""
    import dataclasses

    from lookup.compound import load_compound
    from tire_brush.braking.abs_control import LockedWheel, RuleBasedABS
    from tire_brush.braking.friction import Case
    from tire_brush.braking.simulation import simulate_braking
    from tire_brush.braking.slip_map import optimal_slip
    from tire_brush.braking.study import abs_slip_schedule, case_force_map, load_study
    from tire_brush.params import load_tire
    from tire_brush.rolling_resistance import rolling_resistance

    st = load_study(study_file)
    st = dataclasses.replace(st, friction={"source": "brush", "tire": "passenger",
                                           "grid": str(grid)},
                             maps=dataclasses.replace(st.maps, loads_rel=(1.0,)))
    case = Case("asphalt", name, T_K)
    fmap, _, _ = case_force_map(st, case)
    f_r = float(rolling_resistance(load_tire("passenger"), load_compound(compound_file),
                                   0.5 * st.v0, st.car.Fz, case.T_K).f_r)
    car = dataclasses.replace(st.car, rolling_resistance=f_r)
    sm = optimal_slip(fmap, np.geomspace(st.v_stop, st.v0, 25), [car.Fz], [case.T_K])
    sched = abs_slip_schedule(sm) if st.abs_slip_from_map else None
    locked = simulate_braking(car, fmap, LockedWheel(car.brake_torque_rate_max,
                                                     st.abs_params.control_period),
                              st.v0, st.v_stop, case.T_K, settings=st.simulation)
    abs_sim = simulate_braking(car, fmap, RuleBasedABS(st.abs_params, car.radius,
                                                       car.brake_torque_rate_max,
                                                       slip_schedule=sched),
                               st.v0, st.v_stop, case.T_K, settings=st.simulation)
    return abs_sim.stopping_distance, locked.stopping_distance


#: The screen evaluates the same force-map spline one point at a time
#: (ForceMap.point_evaluator: the same sum in another order), so at the same resolution its
#: stops and wet grip runs equal the single-compound commands' to rounding; a stop
#: integrates ~1e4 steps and an ABS decision amplifies a difference, hence 1e-9, far below
#: any screening tolerance and far above rounding.
SAME_RESOLUTION = 1e-9


@pytest.mark.slow
def test_screen_equals_single_compound_commands(screen_a, tiny):
    """Each compound's numbers are those of `tirefric label` (wet grip BFC, trailer peak,
    RRC) and of the braking study's own force map and simulations (ABS, locked) on the same
    grid files and at the same braking resolution (the tiny spec keeps the study's): the same
    functions on the same inputs, equal to rounding (SAME_RESOLUTION). The summer tread is
    the reference compound, so its wet grip index is the label's."""
    from tire_brush.label import tyre_label_document

    res = screen_a
    rows = {r["name"]: r for r in res.rows()}
    work = res.out / "work"
    for rec in res.records:
        if rec["status"] != "ok":
            continue
        folder = work / f"{rec['name']}-{rec['key'][:12]}"
        doc = tyre_label_document("passenger", grid=str(folder / "wet.nc"),
                                  compound=str(folder / "compound.toml"),
                                  spec=str(tiny / "wet_grip.toml"))
        o = rec["outputs"]
        assert o["bfc_wet"] == pytest.approx(doc["wet_grip"]["bfc_candidate"],
                                             rel=SAME_RESOLUTION)
        assert o["rrc_N_per_kN"] == doc["rolling_resistance"]["rrc_N_per_kN"]
        assert rows[rec["name"]]["rr_class"] == doc["rolling_resistance"]["class"]
        if rec["name"] == "summer":
            assert rows["summer"]["G"] == pytest.approx(doc["wet_grip"]["G"],
                                                        rel=SAME_RESOLUTION)
            assert rows["summer"]["G_trailer"] == pytest.approx(doc["wet_grip"]["G_trailer"],
                                                                rel=1e-12)
        # the dry stops through the braking study's own force map
        abs_m, locked_m = _study_stops(tiny / "study.toml", folder / "dry.nc",
                                       folder / "compound.toml", rec["name"])
        assert o["stop_dry_locked_m"] == pytest.approx(locked_m, rel=SAME_RESOLUTION)
        assert o["stop_dry_abs_m"] == pytest.approx(abs_m, rel=SAME_RESOLUTION)


#: Largest relative difference the screen's braking settings (the dry stop's force map
#: every 7 K from the case temperature, the quarter car's largest step 5 ms) make against
#: the braking study's and the wet grip test's own (every 2 K from 4 K below, 0.5 ms) on the
#: same grid files, measured on the summer tread on the shipped grids (docs/screening.md):
#: dry ABS +0.265 % (the rule-based controller's cycles respond to the friction differences
#: between temperature nodes; 4 K gave +0.019 %, 5 K -0.155 %, 10 K +0.287 %: no trend, the
#: ABS stop's own scatter), dry locked -0.024 %; the wet stops and the BFC, whose maps have
#: one temperature, move with the step only: 1e-6 between 0.25 and 5 ms, the BFC by 1.6e-4
#: between 0.25 and 0.5 ms (an ABS release decision).
BRAKING_TOLERANCE: dict[str, float] = {
    "stop_dry_abs_m": 5e-3, "stop_dry_locked_m": 5e-4, "stop_wet_abs_m": 1e-4,
    "stop_wet_locked_m": 1e-4, "bfc_wet": 1e-3, "peak_wet_trailer": 1e-12,
}


@pytest.mark.slow
def test_screen_braking_settings_reproduce_the_study_stops():
    """On the summer tread and the shipped grid files: the screen at the study's own braking
    settings (stop_T_step = stop_dt = 0) gives the braking study's dry stops to rounding,
    and at its coarser default settings stays within BRAKING_TOLERANCE of them (ABS and
    locked, dry and wet, and the wet grip test's BFC). A coarser default (fewer temperature
    nodes, a longer step) or a step control that no longer converges fails here."""
    import dataclasses

    from tire_brush.screening.evaluate import evaluate_on_grids
    from tire_brush.screening.spec import load_screen_spec, screen_settings

    settings = screen_settings(load_screen_spec("screen_example"))
    assert settings.stop_T_step > 0 and settings.stop_dt > 0
    full = dataclasses.replace(settings, stop_T_step=0.0, stop_dt=0.0)
    dry = resolve_model_file("default", "grids", ".nc")
    wet = resolve_model_file("r117_wet", "grids", ".nc")
    compound = resolve_model_file("summer", "compounds")
    coarse = evaluate_on_grids(settings, compound, dry, wet, "summer")["outputs"]
    ref = evaluate_on_grids(full, compound, dry, wet, "summer")["outputs"]
    abs_m, locked_m = _study_stops(settings.study, dry, compound, "summer")
    assert ref["stop_dry_abs_m"] == pytest.approx(abs_m, rel=SAME_RESOLUTION)
    assert ref["stop_dry_locked_m"] == pytest.approx(locked_m, rel=SAME_RESOLUTION)
    for k, tol in BRAKING_TOLERANCE.items():
        assert abs(coarse[k] / ref[k] - 1.0) <= tol, (k, coarse[k], ref[k], tol)


@pytest.mark.slow
def test_resume_after_a_killed_run_computes_only_the_rest(screen_a, tiny, tmp_path):
    """A run stopped after two records, then run again: the second run computes only what
    the first did not finish, and the results equal the uninterrupted run's bit for bit."""
    from tire_brush.screening import run_screen

    spec = tiny_spec(tiny, THREE)
    first: list[str] = []

    def stop_after_two(rec):
        first.append(rec["name"])
        if len(first) == 2:
            raise Stop

    with pytest.raises(Stop):
        run_screen(spec, tmp_path, workers=1, progress=False, on_record=stop_after_two)
    assert len(list((tmp_path / "compounds").glob("*.json"))) == 2
    second: list[str] = []
    res = run_screen(spec, tmp_path, workers=1, progress=False,
                     on_record=lambda r: second.append(r["name"]))
    all_tasks = {r["name"] for r in res.records} | {res.reference["name"]}
    ok_first = [n for n in first if n != "missing"]
    # failed compounds are tried again (their cause may be fixed); finished ones never
    assert set(second) == (all_tasks - set(ok_first))
    assert not set(second) & set(ok_first)
    assert _outputs(res) == _outputs(screen_a)
    third: list[str] = []
    run_screen(spec, tmp_path, workers=1, progress=False,
               on_record=lambda r: third.append(r["name"]), write=False)
    assert third == ["missing"]


@pytest.mark.slow
def test_two_workers_give_the_same_numbers_as_one(screen_a, tiny, tmp_path):
    from tire_brush.screening import run_screen

    res = run_screen(tiny_spec(tiny, THREE), tmp_path, workers=2, progress=False)
    assert _outputs(res) == _outputs(screen_a)
    assert res.reference["outputs"] == screen_a.reference["outputs"]


#: Largest relative difference of each output between the screening resolution and the full
#: one (the shipped grid specs' speed and pressure axes, the braking study's and the wet grip
#: test's own force-map temperatures and step), per output, as measured on the shipped tread
#: compounds (benchmarks/screen_resolution.py, docs/screening.md) with a margin.
SCREENING_TOLERANCE: dict[str, float] = {
    # the wet grid keeps the full axes; the trailer peak reads it directly: the same number
    "peak_wet_trailer": 1e-12,
    # the quarter car's 5 ms largest step against 0.5 ms: measured at most 5e-7 (wet
    # locked, summer); an ABS stop can flip one release decision, which moved the BFC by
    # 1.6e-4 between 0.25 and 0.5 ms steps (docs/screening.md): 1e-3 on the ABS outputs
    "bfc_wet": 1e-3, "stop_wet_abs_m": 1e-3, "stop_wet_locked_m": 1e-5,
    # measured at most 0.165 % (racing), 0.396 % (racing at 50 C), 0.194 % (summer)
    "stop_dry_locked_m": 5e-3, "mu_peak_0C": 1e-2, "mu_peak_20C": 1e-2, "mu_peak_50C": 1e-2,
    "stop_dry_abs_m": 5e-3,
}

#: Outputs that are not continuous in the friction on a compound (docs/screening.md: the
#: rule-based ABS on the racing tread, dry at 20 C, moved by 6.9 % when the force map was
#: scaled by 1.001), so no resolution bounds them.
ILL_CONDITIONED: dict[str, set[str]] = {"racing": {"stop_dry_abs_m"}}


@pytest.mark.slow
@pytest.mark.parametrize("compound", ["summer", "winter", "racing"])
def test_screening_resolution_tolerance_on_shipped_compounds(compound):
    """The screening resolution keeps every output within its stated tolerance of the full
    resolution on the shipped compounds (docs/screening.md: the table of measured
    differences). A coarser default (or a change of the engine that makes the friction less
    smooth) fails here."""
    from tire_brush.screening.resolution import compare
    from tire_brush.screening.spec import load_screen_spec, screen_settings

    settings = screen_settings(load_screen_spec("screen_example"))
    desc = {"name": compound, "file": str(resolve_model_file(compound, "compounds"))}
    rel = compare(settings, [desc], workers=1)[compound]["rel"]
    for k, tol in SCREENING_TOLERANCE.items():
        if k in ILL_CONDITIONED.get(compound, set()):
            continue
        assert abs(rel[k]) <= tol, (k, rel[k], tol)
