"""Build the FMU into a temp dir, validate it with fmpy, check the post-processed model
description, simulate it with fmpy and compare with the Python model stepped directly."""

from __future__ import annotations

import hashlib
import json
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmu_support import INPUTS, OUTPUTS, braking_inputs, build_test_fmu, synthetic_grid
from test_fmu_units import _si_exponents

from fmu_src.make.build import BuildError, BuildOptions, build_fmu, guid_of
from fmu_src.runtime.interface import UNITS
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.transient import TransientBrushTire
from tirefric.cli import main
from tirefric.errors import TirefricError


@pytest.fixture(scope="module")
def fmu(tmp_path_factory):
    return build_test_fmu(tmp_path_factory.mktemp("fmu"))


def test_fmu_passes_fmpy_validation(fmu):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == [], "fmpy must report no problems"


def test_model_description_has_units_structure_and_metadata(fmu):
    import fmpy

    md = fmpy.read_model_description(str(fmu), validate=True)
    units = {u.name for u in md.unitDefinitions}
    reals = [v for v in md.modelVariables if v.type == "Real"]
    assert reals and all(v.unit in units for v in reals), "every Real needs a defined unit"
    assert units <= set(UNITS)
    base = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
    for u in md.unitDefinitions:  # as written into the FMU, against SI parsed from the name
        written = {b: getattr(u.baseUnit, b) for b in base if getattr(u.baseUnit, b)}
        assert written == _si_exponents(u.name), f"base-unit exponents of {u.name} in the FMU"
    degC = [d for u in md.unitDefinitions if u.name == "K" for d in u.displayUnits]
    assert [d.name for d in degC] == ["degC"]
    assert degC[0].factor * 373.15 + degC[0].offset == pytest.approx(100.0, abs=1e-9), \
        "373.15 K is shown as 100 degC"
    by = {v.name: v for v in md.modelVariables}
    assert by["T_surface"].unit == "K" and by["omega"].unit == "rad/s"
    assert by["Mz"].unit == "N.m"
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    dT = root.find("ModelVariables/ScalarVariable[@name='dT_flash_max']/Real")
    assert dT.get("relativeQuantity") == "true", "a temperature rise takes no degC offset"
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert {u.variable.name for u in md.outputs} == {v.name for v in outputs}
    assert {u.variable.name for u in md.initialUnknowns} == {v.name for v in outputs}
    iu = {u.variable.name: {d.name for d in u.dependencies} for u in md.initialUnknowns}
    assert iu["Fx"] == set() and {"vx", "omega", "tire.R_e"} <= iu["kappa"]
    assert all(not u.dependencies for u in md.outputs), "no direct feedthrough"
    assert md.defaultExperiment.stepSize == "0.001"
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert md.modelName == "BrushTire" and md.author and md.version
    grid_hash = synthetic_grid().hash
    assert grid_hash in md.description, "the description names the grid's hash"
    assert by["info.grid_hash"].start == grid_hash
    params = {v.name for v in md.modelVariables if v.causality == "parameter"}
    assert {"tire.R_e", "tire.tread.k_x", "n_elements", "dt_internal", "s0"} <= params
    assert all(by[p].start is not None and by[p].description for p in params)
    assert float(by["tire.tread.k_x"].start) == load_tire("passenger").tread.k_x


def test_fmu_carries_its_requirements_and_private_modules(fmu):
    with zipfile.ZipFile(fmu) as z:
        names = z.namelist()
        req = z.read("resources/requirements.txt").decode().split()
        build = json.loads(z.read("resources/tirefric-data/build.json"))
    assert req == ["numpy>=1.26"], "the host needs numpy only"
    pkg = build["runtime"]["package"]
    assert pkg.startswith("tirefric_fmu_runtime_")
    tops = {n.split("/")[1] for n in names if n.startswith("resources/") and n.count("/") > 1}
    assert tops == {pkg, "pythonfmu", "tirefric-data"}, f"top-level resources: {tops}"
    assert not any(n.startswith(("resources/lookup", "resources/tire_brush")) for n in names)


def test_same_inputs_give_the_same_fmu(fmu, tmp_path):
    again = build_test_fmu(tmp_path, "again.fmu")
    assert hashlib.sha256(again.read_bytes()).digest() == \
        hashlib.sha256(fmu.read_bytes()).digest(), "same build inputs must give the same bytes"
    other = build_fmu("passenger", synthetic_grid(), tmp_path / "other.fmu",
                      BuildOptions(n_elements=60))
    import fmpy

    assert other.guid != fmpy.read_model_description(str(fmu)).guid
    assert other.guid == guid_of(other.build_id)


def test_round_trip_simulate_fmu_equals_the_python_model(fmu):
    """fmpy.simulate_fmu with an input table; the FMU runs a copy of the same code in the same
    interpreter, so the numbers must be identical (tolerance 0)."""
    import fmpy

    n, dt = 400, 1e-3
    U = braking_inputs(n + 1, dt)
    table = np.zeros(n + 1, dtype=[("time", float)] + [(k, float) for k in INPUTS])
    table["time"] = np.arange(n + 1) * dt
    for i, k in enumerate(INPUTS):
        table[k] = U[i]
    res = fmpy.simulate_fmu(str(fmu), stop_time=n * dt, step_size=dt, output_interval=dt,
                            input=table, output=list(INPUTS) + list(OUTPUTS))
    model = TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()))
    assert len(res) == n + 1
    for k in range(1, len(res)):
        row = res[k]
        h = row["time"] - res[k - 1]["time"]
        ref = model.step(h, *(float(row[name]) for name in INPUTS)).as_array()
        got = np.array([row[name] for name in OUTPUTS])
        assert np.array_equal(got, ref), f"t = {row['time']}: FMU {got} != model {ref}"
    assert res["Fx"].min() < -1000.0 and res["T_tread"][-1] > 293.15, "the manoeuvre brakes"


def test_cli_build_and_info(tmp_path, capsys):
    grid = tmp_path / "g.npz"
    synthetic_grid().save_npz(grid)
    out = tmp_path / "cli.fmu"
    assert main(["fmu", "build", "--tire", "passenger", "--grid", str(grid), "-o", str(out),
                 "--n-elements", "50", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["path"] == str(out) and report["grid_hash"] == synthetic_grid().hash
    assert main(["fmu", "info", str(out), "--json", "--validate"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["options"]["n_elements"] == 50 and info["validation_problems"] == []
    assert info["guid"] == report["guid"]
    assert main(["fmu", "build", "--grid", str(tmp_path / "missing.nc"), "-o",
                 str(tmp_path / "x.fmu")]) == 2
    assert "missing.nc" in capsys.readouterr().err
    assert main(["fmu", "build", "--grid", str(grid), "-o", str(tmp_path / "x.zip")]) == 2


def test_build_refuses_bad_options():
    with pytest.raises(ValueError, match="n_elements"):
        BuildOptions(n_elements=1)
    with pytest.raises(ValueError, match="dt_internal"):
        BuildOptions(dt_internal=0.0)
    assert issubclass(BuildError, TirefricError), "build errors are in the domain hierarchy"
