"""Each interface fact is declared once and every other place derives or is checked against it.

The tire's inputs and outputs are declared in tire_brush/signals.py, the status bits and the
FMU's variables in fmu_src/runtime/interface.py, the guard's conditions in
fmu_src/runtime/guard.py. These tests derive the lists every consumer sees (the guard, the
transient model, the brush outputs, the model description, the native FMU's generated header,
the core's header) and compare them with the table, so that adding an input is one row in the
table plus the physics, and a consumer that did not follow (or a stale generated header) fails
here, by name. The core's layout (sizes, version, constants, the parameter struct) is parsed
from tirecore.h / tirecore.c and compared with its Python mirror and binding.
"""

from __future__ import annotations

import ctypes
import inspect
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from fmu_src.make import native_build, native_header
from fmu_src.runtime import guard, interface
from tire_brush import ccore, element, signals
from tire_brush.params import GROUPS, TireParams, field_table, load_tire, parameter_fields
from tire_brush.slip import BrushOutputs
from tire_brush.transient import TransientBrushTire
from tirefric import units

ROOT = Path(__file__).parents[1]
CORE_H = ROOT / "tire_brush" / "csrc" / "tirecore.h"
CORE_C = ROOT / "tire_brush" / "csrc" / "tirecore.c"
WRAPPER = ROOT / "fmu_src" / "runtime" / "native" / "fmu_wrapper.c"


def _defines(text: str) -> dict[str, float]:
    """Numeric ``#define NAME value`` of a C file."""
    out = {}
    for m in re.finditer(r"^#define\s+(\w+)\s+([-+0-9.eE]+)u?\b", text, re.M):
        out[m.group(1)] = float(m.group(2))
    return out


def _c_strings(text: str, name: str) -> list[str]:
    m = re.search(rf"{name}\[\w+\]\s*=\s*\{{(.*?)\}};", text, re.S)
    assert m, name
    return re.findall(r'"([^"]*)"', m.group(1))


def _c_ints(text: str, name: str) -> list[int]:
    m = re.search(rf"{name}\[\w+\]\s*=\s*\{{(.*?)\}};", text, re.S)
    assert m, name
    return [int(x) for x in m.group(1).replace(" ", "").split(",") if x]


def _model_description_vars() -> list[ET.Element]:
    tire = interface.tire_to_dict(load_tire("passenger"))
    options = {"n_elements": 32, "dt_internal": 2.5e-4, "s0": 2e-4, "v_floor": 0.1,
               "axes": 0, "texture_depth": 0.0, "fidelity": 0}
    info = dict.fromkeys(interface.INFO, "")
    vars_ = interface.variables(tire, options, interface.default_limits(load_tire("passenger")),
                                info)
    root = ET.fromstring(native_build.base_model_description(vars_))
    return list(root.find("ModelVariables"))


# -- inputs and outputs ------------------------------------------------------------------------
def test_every_consumer_reads_the_signal_table() -> None:
    names_in, names_out = signals.INPUT_NAMES, signals.OUTPUT_NAMES
    # the FMU's variable table, the guard and the transient model's step
    assert interface.INPUT_NAMES == names_in and interface.OUTPUT_NAMES == names_out
    assert tuple(guard.NAMES) == names_in
    params = list(inspect.signature(TransientBrushTire.step).parameters)
    assert params[1:] == ["dt", *names_in], "TransientBrushTire.step's arguments"
    assert tuple(f for f in BrushOutputs.__dataclass_fields__) == names_out
    # the binding's sizes
    assert (ccore.N_IN, ccore.N_OUT) == (len(names_in), len(names_out)) == (
        len(names_in), element.N_OUT)
    # the model description: inputs, then outputs, in the table's order, with its units
    md = _model_description_vars()
    got_in = [v.get("name") for v in md if v.get("causality") == "input"]
    got_out = [v.get("name") for v in md if v.get("causality") == "output"]
    assert got_in == list(names_in)
    assert got_out == [*names_out, "input_status"]
    by_name = {v.get("name"): v for v in md}
    for s in (*signals.INPUTS, *signals.OUTPUTS):
        assert by_name[s.name].find("Real").get("unit", s.unit) == s.unit, s.name


def test_core_header_lists_the_inputs_and_outputs_in_the_table_order() -> None:
    h = CORE_H.read_text()
    d = _defines(h)
    assert d["TF_NIN"] == len(signals.INPUTS) and d["TF_NOUT"] == len(signals.OUTPUTS)
    for what, names in (("Inputs of tf_tire_step", signals.INPUT_NAMES),
                        ("Outputs of tf_tire_step", signals.OUTPUT_NAMES)):
        comment = h[h.index(what):]
        comment = comment[:comment.index("*/")]
        pos = [re.search(rf"\b{n}\b", comment) for n in names]
        assert all(pos), f"tirecore.h's comment '{what}' misses {names}"
        starts = [p.start() for p in pos]
        assert starts == sorted(starts), f"tirecore.h's comment '{what}' is out of order"


def test_no_hand_written_copy_of_the_ordered_input_list() -> None:
    # the full ordered input list written out anywhere but the table (and the header generated
    # from it) is a copy that will drift; selections of a few inputs by name are fine
    pattern = re.compile(r'\s*,\s*'.join(f'"{n}"' for n in signals.INPUT_NAMES))
    allowed = {ROOT / "tire_brush" / "signals.py",
               ROOT / "fmu_src" / "runtime" / "native" / "tfn_interface.h"}
    offenders = []
    for folder in ("tire_brush", "fmu_src", "lookup", "tirefric", "benchmarks", "tests"):
        for path in (ROOT / folder).rglob("*"):
            if path.suffix in (".py", ".c", ".h") and path not in allowed and \
                    pattern.search(path.read_text(errors="replace")):
                offenders.append(str(path.relative_to(ROOT)))
    assert not offenders, f"the input list is written out again in {offenders}"


# -- status bits and the guard's conditions ----------------------------------------------------
def test_status_bits_are_distinct_powers_of_two_and_cover_the_core_flags() -> None:
    values = sorted(interface.STATUS_BITS.values())
    assert values == [1 << k for k in range(len(values))]
    flags = {v for k, v in _defines(CORE_H.read_text()).items() if k.startswith("TF_FLAG_")}
    assert flags == set(interface.MODEL_FLAGS), "tirecore.h TF_FLAG_* against MODEL_FLAGS"
    assert {element.FLAG_BUDGET, element.FLAG_T_RANGE} == flags
    assert set(interface.MODEL_FLAGS.values()) <= set(interface.STATUS_BITS)


def test_every_guard_condition_is_in_the_table_and_reachable() -> None:
    limits = interface.default_limits(load_tire("passenger"))
    start = [4000.0 if s.start is None else s.start for s in signals.INPUTS]
    seen: set[str] = set()
    cases = [[math.nan] * len(start),                                       # not finite
             [1e9, 1e9, 1e9, 1e9, 1.0, 1e9, 1.4, 1.0],                      # beyond limits
             [-1e9, -1e9, -1e9, -5.0, 1e4, -1.0, -1.4, -1.0],               # below limits
             [20.0, 0.0, 60.0, 4000.0, 293.15, 1.0, 0.0, 1e-3]]             # water, dry FMU
    for u in cases:
        g = guard.InputGuard(limits, start, wet=False)
        g.apply(u)
        seen |= set(g.active)
    keys = [k for k, _ in guard.CONDITIONS]
    assert seen == set(keys), f"conditions not in CONDITIONS: {seen - set(keys)}; never " \
                              f"found: {set(keys) - seen}"
    assert len(keys) == len(set(keys))
    assert all(k.partition(":")[0] in interface.STATUS_BITS for k in keys)
    assert all(n in signals.INPUT_NAMES for _, n in guard.CONDITIONS)


# -- the native FMU's generated header ---------------------------------------------------------
def test_the_committed_native_header_is_the_generated_one() -> None:
    committed = native_header.HEADER_PATH.read_text()
    assert committed == native_header.interface_header(), (
        "fmu_src/runtime/native/tfn_interface.h is stale: run "
        "`python -m fmu_src.make.native_header`")


def test_the_native_header_derives_its_lists_from_the_table() -> None:
    h = native_header.interface_header()
    assert _c_strings(h, "TFN_IN_NAME") == list(signals.INPUT_NAMES)
    keys = [k for k, _ in guard.CONDITIONS]
    assert _c_strings(h, "TFN_GUARD_NAME") == keys
    assert _c_ints(h, "TFN_GUARD_BIT") == [interface.STATUS_BITS[k.partition(":")[0]]
                                          for k in keys]
    assert _c_ints(h, "TFN_GUARD_INPUT") == [signals.INPUT_NAMES.index(n)
                                            for _, n in guard.CONDITIONS]
    assert _c_ints(h, "TFN_MODEL_FLAG") == list(interface.MODEL_FLAGS)
    assert _c_strings(h, "TFN_MODEL_NAME") == list(interface.MODEL_FLAGS.values())
    # the wrapper holds none of these as literals of its own
    c = WRAPPER.read_text()
    for name in ("GUARD_BIT", "GUARD_NAME", "GUARD_INPUT", "MODEL_BIT", "MODEL_NAME",
                 "IN_NAME", "NONFINITE"):
        assert not re.search(rf"(?<!TFN_){name}\[\w+\]\s*=", c), f"fmu_wrapper.c defines {name}"
    assert not re.search(r"found\[\d+\]", c), "fmu_wrapper.c indexes conditions by number"


def test_a_new_input_reaches_the_generated_header(monkeypatch: pytest.MonkeyPatch) -> None:
    # what "adding an input is one row in the table" means for the native flavour: the header
    # follows the table with no edit of the generator (the physics and the guard rule for the
    # new input are the other edits)
    new = signals.Signal("road_grade", "angle", "test input", 0.0)
    names = (*signals.INPUT_NAMES, new.name)
    monkeypatch.setattr(native_header, "INPUT_NAMES", names)
    monkeypatch.setattr(native_header, "CONDITIONS",
                        (*guard.CONDITIONS, (f"nonfinite:{new.name}", new.name)))
    h = native_header.interface_header()
    assert "#define TFN_NIN 9" in h and "TFN_IN_ROAD_GRADE = 8" in h
    assert _c_strings(h, "TFN_IN_NAME")[-1] == "road_grade"
    assert _c_ints(h, "TFN_NONFINITE")[-1] == len(guard.CONDITIONS)
    assert h != native_header.HEADER_PATH.read_text(), "a stale header must differ"


# -- the core's layout -------------------------------------------------------------------------
#: C constant -> its Python mirror in tire_brush.element (or the binding).
MIRRORED = {
    "TF_VERSION": element.STATE_VERSION, "TF_DT_FLOOR": element.DT_FLOOR,
    "TF_ELEM": element.N_ELEM, "TF_NOUT": element.N_OUT, "TF_BUDGET": element.BUDGET,
    "TF_FLAG_BUDGET": element.FLAG_BUDGET, "TF_FLAG_T_RANGE": element.FLAG_T_RANGE,
    "TF_NCOUNT": ccore.N_COUNT, "TF_STEADY_IN": ccore.STEADY_IN,
    "TF_STEADY_OUT": ccore.STEADY_OUT, "GAMMA": element.GAMMA,
    "CREEP_SPEED": element.CREEP_SPEED, "H_MIN": element.H_MIN, "S_MAX": element.S_MAX,
    "V_ROLL_MIN": element.V_ROLL_MIN, "HALF_PI": element.HALF_PI,
    "TIP_STEP": element.TIP_STEP, "BELT_GAIN_MAX": element.BELT_GAIN_MAX,
    "WALK_MARGIN": element.WALK_MARGIN, "YAW_MAX_IT": element.YAW_MAX_IT,
    "STATE_HEAD": element.STATE_HEAD,
}


def test_realtime_constants_equal_their_mirror() -> None:
    """The real-time fidelity's table layout (tirert.h) against tire_brush.realtime and the
    binding."""
    from tire_brush import realtime
    d = _defines((ROOT / "tire_brush" / "csrc" / "tirert.h").read_text())
    assert d["TF_PATCH_NV"] == realtime.N_VALUES == len(realtime.VALUE_NAMES)
    assert d["TF_PATCH_NAX"] == len(realtime.AXIS_NAMES)
    assert d["TF_PATCH_NOUT"] == ccore.PATCH_NOUT


def test_core_constants_equal_their_mirror() -> None:
    d = _defines(CORE_H.read_text()) | _defines(CORE_C.read_text())
    missing = [k for k in MIRRORED if k not in d]
    assert not missing, f"not defined in the core any more: {missing}"
    wrong = {k: (d[k], v) for k, v in MIRRORED.items() if d[k] != v}
    assert not wrong, f"core constant != its Python mirror (C, Python): {wrong}"
    assert d["TF_ELEM"] == ccore.N_ELEM and d["TF_NIN"] == ccore.N_IN


def test_tf_params_struct_equals_the_binding() -> None:
    h = CORE_H.read_text()
    body = re.search(r"typedef struct \{(.*?)\} tf_params;", h, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    fields = []
    for decl in body.split(";"):
        decl = decl.strip()
        if not decl:
            continue
        ctype, _, names = decl.partition(" ")
        fields += [(n.strip(), ctype) for n in names.split(",")]
    types = {"double": ctypes.c_double, "int": ctypes.c_int}
    binding = [(n, t) for n, t in ccore.Params._fields_]
    assert [(n, types[t]) for n, t in fields] == binding, \
        "tirecore.h tf_params and tire_brush.ccore.Params differ (name, order or type)"


def test_one_place_for_the_compiler_flags() -> None:
    # setup.py's own reading of the flags (its source up to the setup() call)
    ns: dict = {"__file__": str(ROOT / "setup.py")}
    exec((ROOT / "setup.py").read_text().split("\nif sys.platform")[0], ns)
    assert tuple(ns["core_cflags"]()) == ccore.CORE_CFLAGS
    assert native_build.CFLAGS[:len(ccore.CORE_CFLAGS)] == ccore.CORE_CFLAGS
    assert ccore.CFLAGS[:len(ccore.CORE_CFLAGS)] == ccore.CORE_CFLAGS
    # nowhere else is the rounding-relevant flag written out
    offenders = [str(p.relative_to(ROOT)) for folder in ("tire_brush", "fmu_src", "benchmarks",
                                                          "tests", "tirefric", "lookup")
                 for p in (ROOT / folder).rglob("*.py")
                 if p.name != "ccore.py" and p != Path(__file__)
                 and "-ffp-contract=off" in p.read_text()]
    assert not offenders, offenders


# -- units --------------------------------------------------------------------------------------
def test_one_unit_vocabulary() -> None:
    # every SI unit reads back as itself (factor 1) in the dimension it belongs to
    for dim, (unit, _) in units.SI_UNITS.items():
        assert units.to_si(2.5, unit, dim) == 2.5, dim
    # a tire parameter's unit is the SI unit of its dimension; the FMU's unit definitions are
    # derived from the same table
    for cls in [TireParams, *GROUPS.values()]:
        for f in parameter_fields(cls):
            if f.metadata["dimension"] is not None:
                assert f.metadata["unit"] == units.si_unit(f.metadata["dimension"]), f.name
    for path, (unit, _) in field_table().items():
        assert unit is None or unit in interface.UNITS, path
    for unit, exps in interface.UNITS.items():
        assert exps == units.base_units(unit), unit
    # the human spelling and the FMI one are the same entry
    assert units.to_si(3.0, "N s/m^3", "damping_per_area") == \
        units.to_si(3.0, "N.s/m3", "damping_per_area")
