"""Compound screening (tire_brush.screening, docs/screening.md): the sweep, the store, resume,
failures, worker-count independence, and agreement with the single-compound commands."""

from __future__ import annotations

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
# resolution, where they must agree to the last bit; coarse axes only make them fast.
TINY_RESOLUTION = """
[resolution]
v_per_decade = 1
v_min = "1e-3 m/s"
p_nodes = 3
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
