"""The FMU's Python parts without the FMI binary: interface table, input guard, state bytes,
packaging checks, and the slave class run in-process against the Python model."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from fmu_support import INPUTS, OUTPUTS, braking_inputs, synthetic_grid
from pythonfmu.enums import Fmi2Status

from fmu_src.make import package
from fmu_src.make.build import stage_resources
from fmu_src.runtime import interface
from fmu_src.runtime import state as state_io
from fmu_src.runtime.guard import InputGuard
from fmu_src.runtime.interface import STATUS_BITS, UNITS
from fmu_src.runtime.slave import BrushTireSlave
from tire_brush.friction import GridFriction
from tire_brush.params import load_tire
from tire_brush.transient import TransientBrushTire

LIMITS = {"limit.v": 150.0, "limit.omega": 1000.0, "limit.Fz": 5e4, "limit.T_min": 200.0,
          "limit.T_max": 500.0, "limit.mu_scale": 5.0, "limit.gamma": 0.5,
          "limit.water_depth": 0.1}
START = [0.0, 0.0, 0.0, 4000.0, 293.15, 1.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def resources(tmp_path_factory):
    d = tmp_path_factory.mktemp("resources")
    stage_resources(load_tire("passenger"), synthetic_grid(), d)
    return d


def make_slave(resources, name="s", **params) -> BrushTireSlave:
    s = BrushTireSlave(instance_name=name, resources=str(resources))
    vr = {v.name: v.value_reference for v in s.vars.values()}
    s.enter_initialization_mode()
    for k, val in params.items():
        s.vars[vr[k]].setter(val)
    s.exit_initialization_mode()
    s.vr = vr
    return s


def step(s: BrushTireSlave, u, dt=1e-3) -> np.ndarray:
    s.set_real([s.vr[n] for n in INPUTS], [float(x) for x in u])
    assert s.do_step(0.0, dt), "do_step returned False (fmi2Discard)"
    return np.array(s.get_real([s.vr[n] for n in OUTPUTS]))


# -- interface table ----------------------------------------------------------------------------
def test_interface_covers_every_tire_parameter():
    assert interface.check_tire_fields() == []


def test_every_real_has_a_known_unit_and_names_are_unique():
    tire = interface.tire_to_dict(load_tire("passenger"))
    opts = {"n_elements": 100, "dt_internal": 1e-3, "s0": 2e-4, "v_floor": 0.1, "axes": 0,
            "texture_depth": 0.0, "fidelity": 0}
    vs = interface.variables(tire, opts, LIMITS, dict.fromkeys(interface.INFO, "x"))
    names = [v.name for v in vs]
    assert len(names) == len(set(names)), "variable names must be unique"
    for v in vs:
        if v.type == "Real":
            assert v.unit in UNITS, f"{v.name}: unit {v.unit!r} has no definition"
        assert v.description, f"{v.name} has no description"
    for out, deps in interface.INITIAL_DEPENDENCIES.items():
        assert out in names and all(d in names for d in deps), out


def test_tire_round_trips_through_flat_parameters():
    tire = load_tire("passenger")
    d = interface.tire_to_dict(tire)
    back = interface.tire_from_parameters(d["name"], d["parameters"],
                                          description=d["description"],
                                          provenance=d["provenance"])
    assert back == tire, "TireParams -> flat FMU parameters -> TireParams must be identity"


# -- state bytes --------------------------------------------------------------------------------
def test_state_bytes_are_exact_and_checked():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((5, 37))
    a[0, 0], a[1, 1], a[2, 2] = math.nan, -math.inf, -0.0
    tree = {"x": 0.1 + 0.2, "nan": math.nan, "inf": math.inf, "i": 7, "b": True, "s": "é",
            "none": None, "arr": a, "nested": {"l": [1.0 / 3.0, 2, "z"], "e": np.zeros(0)}}
    data = state_io.to_bytes(tree)
    back = state_io.from_bytes(data)
    assert back["arr"].tobytes() == a.tobytes(), "array must round-trip bit for bit"
    assert back["x"] == tree["x"] and math.isnan(back["nan"]) and back["inf"] == math.inf
    assert back["nested"]["l"] == [1.0 / 3.0, 2, "z"] and back["s"] == "é"
    assert back["i"] == 7 and back["b"] is True and back["none"] is None
    assert state_io.to_bytes(back) == data, "serialization must be deterministic"
    for bad in (data[:-1], data[:40] + bytes([data[40] ^ 1]) + data[41:], b"junk" + data):
        with pytest.raises(state_io.StateFormatError):
            state_io.from_bytes(bad)
    with pytest.raises(TypeError, match=r"state\.obj"):
        state_io.to_bytes({"obj": object()})


# -- input guard --------------------------------------------------------------------------------
def test_guard_repairs_bad_inputs_and_logs_each_condition_once():
    g = InputGuard(LIMITS, START)
    x, status, msgs = g.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.02, 0.0])
    assert (status, msgs) == (0, []) and x == [20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.02, 0.0]
    x, status, msgs = g.apply([math.nan, 0.0, 1e9, -10.0, 0.0, -1.0, 0.02, 0.0])
    assert x == [20.0, 0.0, 1000.0, 0.0, 200.0, 0.0, 0.02, 0.0], \
        "NaN held, spin/T/mu clamped, Fz >= 0"
    assert status == sum(STATUS_BITS[k] for k in ("nonfinite", "speed_clamped",
                                                  "negative_load", "temperature_clamped",
                                                  "mu_scale_clamped"))
    assert len(msgs) == 5 and all(level == 1 for level, _ in msgs)
    assert any("vx = nan" in m and "holding its last finite value 20" in m for _, m in msgs)
    _, status2, msgs2 = g.apply([math.nan, 0.0, 1e9, -10.0, 0.0, -1.0, 0.02, 0.0])
    assert status2 == status and msgs2 == [], "a persisting condition is logged once"
    x, status, msgs = g.apply([21.0, 0.0, 60.0, 6e4, 300.0, 1.0, 0.02, 0.0])
    assert x[3] == 5e4 and status == STATUS_BITS["load_clamped"]
    cleared = [m for level, m in msgs if level == 0]
    assert len(cleared) == 5 and any("after 2 step(s)" in m for m in cleared)
    x, _, _ = g.apply([-30.0, 0.0, -80.0, 4000.0, 300.0, 1.0, 0.02, 0.0])
    assert x[:3] == [-30.0, 0.0, -80.0], "reversing is a normal input"
    # camber: NaN holds the last finite value, beyond limit.gamma it is clamped (sign kept)
    x, status, msgs = g.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, math.nan, 0.0])
    assert x[6] == 0.02 and status == STATUS_BITS["nonfinite"]
    assert any("gamma = nan" in m for _, m in msgs)
    x, status, msgs = g.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, -2.0, 0.0])
    assert x[6] == -0.5 and status == STATUS_BITS["camber_clamped"]
    # water: negative or beyond limit.water_depth clamped; without a wet branch any water is
    # a dry road (its own bit), with one it passes
    x, status, _ = g.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.0, -1e-3])
    assert x[7] == 0.0 and status == STATUS_BITS["water_clamped"]
    x, status, msgs = g.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.0, 1e-3])
    assert x[7] == 0.0 and status == STATUS_BITS["no_wet_branch"]
    assert any("no wet branch" in m for _, m in msgs)
    wet = InputGuard(LIMITS, START, wet=True)
    x, status, _ = wet.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.0, 1e-3])
    assert x[7] == 1e-3 and status == 0
    x, status, _ = wet.apply([20.0, 0.0, 60.0, 4000.0, 300.0, 1.0, 0.0, 0.5])
    assert x[7] == 0.1 and status == STATUS_BITS["water_clamped"]


# -- packaging ----------------------------------------------------------------------------------
def test_runtime_closure_is_numpy_and_stdlib_only():
    rt = package.build_runtime()
    assert "tire_brush.transient" in rt.modules and "lookup.grid.reader" in rt.modules
    heavy = {"scipy", "xarray", "casadi", "matplotlib", "h5py", "h5netcdf", "dask"}
    for rel, text in rt.files.items():
        for line in text.splitlines():
            words = line.replace(",", " ").split()
            if words[:1] in (["import"], ["from"]):
                assert not heavy & {words[1].split(".")[0]}, f"{rel}: {line}"
                assert words[1].split(".")[0] not in package.PROJECT_PACKAGES, \
                    f"{rel}: import not renamed: {line}"


def test_closure_refuses_a_heavy_module_level_import(tmp_path, monkeypatch):
    pkg = tmp_path / "tfx_fake_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "entry.py").write_text("from tfx_fake_pkg import helper\n")
    (pkg / "helper.py").write_text("import math\n\nimport scipy.special\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(package, "PROJECT_PACKAGES", ("tfx_fake_pkg",))
    with pytest.raises(package.PackagingError, match=r"tfx_fake_pkg\.helper.*scipy"):
        package.closure("tfx_fake_pkg.entry")
    (pkg / "helper.py").write_text("def f():\n    import scipy.special\n")
    sys.modules.pop("tfx_fake_pkg", None)
    assert package.closure("tfx_fake_pkg.entry") == ["tfx_fake_pkg", "tfx_fake_pkg.entry",
                                                     "tfx_fake_pkg.helper"]


# -- slave in-process -----------------------------------------------------------------------------
def test_slave_matches_the_python_model_exactly(resources):
    s = make_slave(resources)
    model = TransientBrushTire(load_tire("passenger"), GridFriction(synthetic_grid()))
    U = braking_inputs(150)
    for k in range(U.shape[1]):
        y = step(s, U[:, k])
        ref = model.step(1e-3, *U[:, k]).as_array()
        assert np.array_equal(y, ref), f"step {k}: slave {y} != model {ref}"


def test_initial_outputs_follow_the_start_inputs(resources):
    s = BrushTireSlave(instance_name="i", resources=str(resources))
    vr = {v.name: v.value_reference for v in s.vars.values()}
    s.set_real([vr["vx"], vr["omega"], vr["T_surface"]], [10.0, 10.0 / 0.31 * 0.9, 280.0])
    s.exit_initialization_mode()
    y = dict(zip(OUTPUTS, s.get_real([vr[n] for n in OUTPUTS]), strict=True))
    assert y["Fx"] == 0.0 and y["T_tread"] == 280.0
    assert y["kappa"] == pytest.approx(-0.1, rel=1e-12), "kappa from the start kinematics"


def test_state_rollback_and_serialization_are_bit_exact(resources):
    s = make_slave(resources)
    U = braking_inputs(120)
    for k in range(60):
        step(s, U[:, k])
    saved = s._get_fmu_state()
    blob = BrushTireSlave._fmu_state_to_bytes(saved)
    first = np.array([step(s, U[:, k]) for k in range(60, 120)])
    s._set_fmu_state(saved)
    again = np.array([step(s, U[:, k]) for k in range(60, 120)])
    assert again.tobytes() == first.tobytes(), "rollback must reproduce the outputs bit for bit"
    other = make_slave(resources, name="other")
    other._set_fmu_state(BrushTireSlave._fmu_state_from_bytes(blob))
    third = np.array([step(other, U[:, k]) for k in range(60, 120)])
    assert third.tobytes() == first.tobytes(), "a deserialized state must continue identically"
    assert np.abs(saved["model"]["elements"]).max() > 0, "the state holds element deflections"


def test_state_of_another_build_or_discretisation_is_refused(resources):
    """Refused states are logged as errors and change nothing (the slave never raises into
    pythonfmu, which would make it fmi2Fatal: fmu_src/runtime/slave.py, module docstring)."""
    s = make_slave(resources)
    step(s, [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0])
    before = state_io.to_bytes(s._get_fmu_state())
    bad = s._get_fmu_state()
    bad["build_id"] = "sha256:" + "0" * 64
    for state, why in ((bad, "another build"), ({"format": "x"}, "not a state"),
                       (s._fmu_state_from_bytes(b"garbage"), "StateFormatError")):
        n = len(s.log_queue)
        s._set_fmu_state(state)
        assert any(why in m.msg and m.status == Fmi2Status.error for m in s.log_queue[n:]), why
        assert state_io.to_bytes(s._get_fmu_state()) == before, f"{why}: the state changed"


def test_contact_age_switch_reaches_the_core(resources):
    """tire.tread.contact_ageing = true before initialisation: the slave equals the Python
    model of the tire with the contact age (and differs from the shipped tire's, off)."""
    import dataclasses

    s = make_slave(resources, **{"tire.tread.contact_ageing": True})
    tire = load_tire("passenger")
    on = TransientBrushTire(dataclasses.replace(tire, tread=dataclasses.replace(
        tire.tread, contact_ageing=True)), GridFriction(synthetic_grid()))
    off = TransientBrushTire(tire, GridFriction(synthetic_grid()))
    U = braking_inputs(60)
    differs = False
    for k in range(U.shape[1]):
        y = step(s, U[:, k])
        assert np.array_equal(y, on.step(1e-3, *U[:, k]).as_array()), f"step {k}"
        differs |= not np.array_equal(y, off.step(1e-3, *U[:, k]).as_array())
    assert differs, "the switch must change the tire"


def test_parameters_set_before_initialization_are_used(resources):
    coarse = make_slave(resources, **{"n_elements": 40, "tire.thermal.enabled": False})
    assert coarse._model.n_elements == 40 and not coarse._model.thermal
    y = step(coarse, [20.0, 0.0, 20.0 / 0.31 * 0.9, 4000.0, 300.0, 1.0, 0.0, 0.0])
    assert y[OUTPUTS.index("T_tread")] == 300.0, "thermal off: T_tread = T_surface"
    coarse.vars[coarse.vr["n_elements"]].setter(80)
    assert coarse._p["n_elements"] == 40, "a fixed parameter cannot change after init"
    assert any("fixed" in m.msg for m in coarse.log_queue)


def test_invalid_parameters_fail_at_initialization_with_the_field_named(resources):
    s = BrushTireSlave(instance_name="bad", resources=str(resources))
    vr = {v.name: v.value_reference for v in s.vars.values()}
    s.set_real([vr["tire.tread.k_x"]], [-1.0])
    s.exit_initialization_mode()                # logged, never raised (slave docstring)
    assert any("TreadParams.k_x" in m.msg and m.status == Fmi2Status.error
               for m in s.log_queue)
    assert s.do_step(0.0, 1e-3) is False, "no model: every step is discarded"


def test_bad_communication_steps_are_discarded_without_advancing(resources):
    s = make_slave(resources)
    u = [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 0.0]
    s.set_real([s.vr[n] for n in INPUTS], u)
    before = s._get_fmu_state()
    for dt in (-1e-3, math.nan, math.inf, 1e3):
        assert s.do_step(0.0, dt) is False, f"dt = {dt} must give fmi2Discard"
    after = s._get_fmu_state()
    assert state_io.to_bytes(after) == state_io.to_bytes(before), "nothing advanced"
    assert sum("communication step" in m.msg for m in s.log_queue) == 4


def test_a_failing_model_step_is_discarded_reset_and_logged(resources, monkeypatch):
    s = make_slave(resources)
    u = [20.0, 0.0, 20.0 / 0.31 * 0.9, 4000.0, 293.15, 1.0, 0.0, 0.0]
    for _ in range(30):
        step(s, u)
    assert np.abs(s._model.get_state()["elements"]).max() > 0

    def broken(*args, **kwargs):
        raise FloatingPointError("overflow in the element step")

    monkeypatch.setattr(s._model, "step", broken)
    s.set_real([s.vr[n] for n in INPUTS], u)
    assert s.do_step(0.03, 1e-3) is False, "a model failure gives fmi2Discard"
    y = np.array(s.get_real([s.vr[n] for n in OUTPUTS]))
    assert np.isfinite(y).all() and y[0] == 0.0, "outputs of the reset tire"
    assert s.get_integer([s.vr["input_status"]])[0] & STATUS_BITS["model_reset"]
    assert not np.abs(s._model.get_state()["elements"]).any(), "the model was reset"
    assert any(m.status == 3 and "overflow in the element step" in m.msg
               for m in s.log_queue), "the failure is logged as an error"
