"""The validation report's arithmetic (benchmarks/validation.py) on a tiny synthetic set.

The report's RMS log10 errors are recomputed here from the per-point table, independently of
lookup.calibration's bookkeeping; a held-out point planted wrong must move the held-out error
and leave the fitted parameters exactly as they were (it never enters the fit), while the
same error planted on a fitted point must move them (so that the check can fail). The set is
the cold branch at <= 1 mm/s on the shipped compounds and road: a fit takes well under a
second.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def V():
    spec = importlib.util.spec_from_file_location("validation_report",
                                                  ROOT / "benchmarks" / "validation.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def tiny(V):
    # summer fitted at 10 and 20 C; its 30 C points and all of winter held out
    return V.synthetic_case(compounds=("summer", "winter"), speeds=(1e-4, 1e-3),
                            temperatures_C=(10.0, 20.0, 30.0), held_compounds=("winter",),
                            held_temperatures_C=(30.0,))


def plant(case, compound: str, T_C: float, factor: float):
    """The case with the first point of ``compound`` at ``T_C`` multiplied by ``factor``."""
    comps = []
    for c in case.spec.compounds:
        if c.name == compound:
            t = c.tables[0]
            k = int(np.flatnonzero(np.abs(t.T - (T_C + 273.15)) < 0.01)[0])
            mu = t.mu.copy()
            mu[k] *= factor
            c = dataclasses.replace(c, tables=(dataclasses.replace(t, mu=mu),))
        comps.append(c)
    return dataclasses.replace(case, spec=dataclasses.replace(case.spec, compounds=tuple(comps)))


def _rms(x) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def test_rms_log10_recomputed_from_the_points(V) -> None:
    cr = V.run_case(tiny(V))
    pts = cr.result.points()
    assert {p["set"] for p in pts} == {"fit", "held_out"}
    for which in ("fit", "held_out"):
        sel = [p for p in pts if p["set"] == which]
        after = _rms([np.log10(p["mu_predicted"]) - np.log10(p["mu_measured"]) for p in sel])
        before = _rms([np.log10(p["mu_start"]) - np.log10(p["mu_measured"]) for p in sel])
        # the same formula on the same numbers: agreement to rounding
        assert cr.rms(which) == pytest.approx(after, rel=1e-12)
        assert cr.rms(which, before=True) == pytest.approx(before, rel=1e-12)
    for row in cr.compounds():
        sel = [p for p in pts if p["compound"] == row["compound"]]
        assert row["rms_after"] == pytest.approx(
            _rms([np.log10(p["mu_predicted"] / p["mu_measured"]) for p in sel]), rel=1e-12)
        assert row["held_out"] == all(p["set"] == "held_out" for p in sel)
    # the held-out compound counts as held out, the fitted one's 30 C points too
    assert [p["set"] for p in pts if p["compound"] == "winter"] == ["held_out"] * 6
    assert sum(p["set"] == "held_out" for p in pts if p["compound"] == "summer") == 2
    # the report prints these numbers (3 decimals)
    text = V.render(cr, {"n": 0, "rms_at_stated_parameters": 0.0,
                         "max_at_stated_parameters": 0.0, "fitted": {}}, None, "skipped", 0.0)
    assert f"{cr.rms('fit', True):.3f} -> {cr.rms('fit'):.3f}" in text
    assert f"{cr.rms('held_out', True):.3f} -> {cr.rms('held_out'):.3f}" in text
    assert "Not run: skipped" in text


def test_a_wrong_held_out_point_moves_only_the_held_out_error(V) -> None:
    case = tiny(V)
    base = V.run_case(case)
    # a held-out point 3x off (log10 3 = 0.48): far beyond the rounding of the data
    bad = V.run_case(plant(case, "summer", 30.0, 3.0))
    for p, q in zip(base.result.parameters, bad.result.parameters, strict=True):
        assert q.value == p.value and q.std == p.std, p.label  # never entered the fit
    assert bad.rms("fit") == base.rms("fit")
    assert bad.rms("held_out") > base.rms("held_out") + 0.1
    # the same error on a fitted point does move the parameters
    moved = V.run_case(plant(case, "summer", 20.0, 3.0))
    assert any(abs(q.value / p.value - 1) > 1e-3 for p, q in
               zip(base.result.parameters, moved.result.parameters, strict=True))


def test_synthetic_recovery_and_order(V) -> None:
    cr = V.run_case(tiny(V))
    # data rounded to 3 digits (relative error <= 5e-3): the fitted values lie within a few
    # standard uncertainties of the truth
    for row in V.recovery(cr):
        assert abs(row["miss_in_std"]) < 3, row
    o = cr.order()
    assert o["n_common"] == 6
    m = cr.result.model
    for i, name in enumerate(("summer", "winter")):
        gm = float(np.exp(np.mean(np.log(m.mu[m.compound_index == i]))))
        assert o["means"]["measured"][name] == pytest.approx(gm, rel=1e-12)
    assert o["rank"]["measured"] == sorted(("summer", "winter"),
                                           key=lambda n: -o["means"]["measured"][n])


def test_script_runs_without_the_private_data(V, tmp_path, capsys) -> None:
    out = tmp_path / "validation.md"
    assert V.main(["-o", str(out)]) == 0
    assert "measured part skipped" in capsys.readouterr().out
    text = out.read_text()
    assert "Not run: no `--nexen DIR` given" in text and "## Synthetic recovery check" in text
    assert V.main(["--nexen", str(tmp_path / "absent"), "-o", str(out)]) == 2
    assert "tried" in capsys.readouterr().err
