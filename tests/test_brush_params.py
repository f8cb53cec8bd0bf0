"""Tire parameter files: the shipped passenger tire and the errors for bad files."""

from __future__ import annotations

import dataclasses

import pytest

from tire_brush.params import PatchLaw, TireParams, load_tire
from tirefric.errors import InputError
from tirefric.paths import models_dir

PASSENGER = (models_dir() / "tires" / "passenger.toml").read_text()


def test_passenger_reproduces_its_provenance() -> None:
    """The numbers the provenance note derives: a = 66 mm and b = 141 mm at 4 kN (eqs. A3.7-8),
    the longitudinal slip stiffness of the MF-Tyre example (86.7 kN) to 0.5% (the cornering
    stiffness, which the belt's twist shapes, is checked against the same tire's curve in
    test_tire_realism.py)."""
    t = load_tire("passenger")
    a, b = t.patch.size(4000.0)
    assert a == pytest.approx(0.0660, abs=2e-4)
    assert b == pytest.approx(0.1409, abs=2e-4)
    C_kappa, _ = t.slip_stiffness(4000.0)
    assert C_kappa == pytest.approx(86.7e3, rel=5e-3)
    assert t.name == "passenger" and t.provenance


def test_patch_law_grows_and_caps() -> None:
    t = load_tire("passenger")
    sizes = [t.patch.size(F) for F in (0.0, 1000.0, 4000.0, 10000.0, 20000.0)]
    assert sizes[0] == (0.0, 0.0)
    assert sizes[1][0] < sizes[2][0] < sizes[3][0], "longer patch with load"
    assert sizes[3] == sizes[4], "patch size frozen above Fz_max"


def _write(tmp_path, text):
    p = tmp_path / "tire.toml"
    p.write_text(text)
    return p


def test_bad_files_name_file_field_value(tmp_path) -> None:
    p = _write(tmp_path, PASSENGER.replace('k_x = "7.07e7 N/m^3"', 'k_x = "-7 N/m^3"'))
    with pytest.raises(InputError) as exc:
        load_tire(p)
    assert "tread.k_x" in str(exc.value) and str(p) in str(exc.value)
    p = _write(tmp_path, PASSENGER.replace('mass = "2.8 kg/m^2"', 'mass = "2.8 kg"'))
    with pytest.raises(InputError, match="unknown unit 'kg'"):
        load_tire(p)
    p = _write(tmp_path, PASSENGER.replace("void_ratio = 0.3", "void_ratio = 0.3\nvoids = 1"))
    with pytest.raises(InputError, match="voids"):
        load_tire(p)
    p = _write(tmp_path, PASSENGER.replace('Fz_max = "10000 N"', 'Fz_max = "30000 N"'))
    with pytest.raises(InputError, match="growing with the load"):
        load_tire(p)
    with pytest.raises(InputError, match="shipped"):
        load_tire("no-such-tire")


def test_dataclass_validation_reports_all_problems() -> None:
    t = load_tire("passenger")
    with pytest.raises(InputError) as exc:
        dataclasses.replace(t.tread, k_x=0.0, mass=-1.0)
    assert "k_x" in str(exc.value) and "mass" in str(exc.value)
    with pytest.raises(InputError, match="Fz_nom"):
        dataclasses.replace(t, Fz_nom=2e4)
    assert isinstance(t, TireParams) and isinstance(t.patch, PatchLaw)


def test_parameter_docs_are_written_from_the_fields() -> None:
    """docs/tire-parameters.md is the table the fields' metadata gives (one source of truth:
    the loader, the validation and the FMU read the same metadata)."""
    from pathlib import Path

    from fmu_src.runtime.interface import TIRE_FIELDS
    from tire_brush.params import field_table, parameters_markdown

    doc = Path(__file__).parents[1] / "docs" / "tire-parameters.md"
    assert doc.read_text() == parameters_markdown(), "regenerate docs/tire-parameters.md"
    assert TIRE_FIELDS == field_table()
    for path, (unit, desc) in field_table().items():
        assert f"`{path}`" in doc.read_text() and desc in doc.read_text()
        assert unit is None or unit in desc, f"{path}: the description names its unit"
