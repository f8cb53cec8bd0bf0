"""Post-processing of the modelDescription.xml that pythonfmu writes.

pythonfmu writes the variables with their causality, variability and description, but no
units, no unit definitions, no InitialUnknowns, a random GUID and the build time. This module
rewrites the file from :mod:`fmu_src.runtime.interface`, the one table the slave registers its
variables from:

* model attributes: name, GUID (derived from the build inputs), description, author, version,
  license, generation tool; no generation time (same inputs give the same bytes) unless
  ``SOURCE_DATE_EPOCH`` is set, the reproducible-builds convention;
* ``CoSimulation`` capabilities: get/set and serialize FMU state, variable communication step;
* ``UnitDefinitions`` with the SI base-unit exponents of every unit used, display units
  (degC, deg, km/h, rpm, kN), and a unit on every Real variable (``relativeQuantity`` for
  temperature differences);
* exact start values (shortest repr that round-trips a float64), checked against the values
  the slave itself reported to pythonfmu;
* ``DefaultExperiment`` (1 ms communication step);
* ``VendorAnnotations`` naming the grid's hash, the tire and the build id;
* ``ModelStructure``: every output under ``Outputs`` with no dependencies (no direct
  feedthrough in co-simulation) and under ``InitialUnknowns`` with the dependencies of
  :data:`fmu_src.runtime.interface.INITIAL_DEPENDENCIES`.

This module runs at build time only.
"""

from __future__ import annotations

import math
import os
import time
import xml.etree.ElementTree as ET
from typing import Any

from fmu_src.runtime.interface import (
    DISPLAY_UNITS,
    INITIAL_DEPENDENCIES,
    MODEL_NAME,
    UNITS,
    Variable,
)
from tirefric.errors import TirefricError

#: FMI 2.0 base units in schema order.
_BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
#: Child elements of fmiModelDescription in schema order.
_ORDER = ("ModelExchange", "CoSimulation", "UnitDefinitions", "TypeDefinitions",
          "LogCategories", "DefaultExperiment", "VendorAnnotations", "ModelVariables",
          "ModelStructure")


class ModelDescriptionError(TirefricError):
    """pythonfmu's modelDescription.xml does not match the interface table."""


def _real(x: Any, where: str) -> str:
    """Exact text of a finite float (shortest round-trip repr)."""
    x = float(x)
    if not math.isfinite(x):
        raise ModelDescriptionError(f"{where}: start value {x!r} is not finite")
    return repr(x)


def _start_text(v: Variable) -> str:
    if v.type == "Real":
        return _real(v.start, v.name)
    if v.type == "Boolean":
        return "true" if v.start else "false"
    if v.type == "Integer":
        return str(int(v.start))
    return str(v.start)


def _same_start(v: Variable, written: str | None) -> bool:
    """Whether pythonfmu's start text (from the slave's getter) agrees with the table."""
    if written is None:
        return False
    if v.type == "Real":
        a, b = float(written), float(v.start)
        return a == b or abs(a - b) <= 1e-15 * max(abs(a), abs(b))
    return written == _start_text(v)


def postprocess(xml: bytes, variables: list[Variable], *, guid: str, model: dict[str, str],
                vendor: dict[str, str], step_size: float = 1e-3,
                stop_time: float = 1.0, model_identifier: str = MODEL_NAME,
                source_files: tuple[str, ...] = ()) -> bytes:
    """Rewrite pythonfmu's modelDescription.xml (module docstring).

    Parameters
    ----------
    xml
        The file pythonfmu wrote.
    variables
        :func:`fmu_src.runtime.interface.variables` of the build (value-reference order).
    guid
        The FMU's GUID.
    model
        ``description``, ``author``, ``version``, ``license``, ``generationTool`` (and
        optionally ``copyright``).
    vendor
        Attributes of the ``VendorAnnotations/Tool[@name='tirefric']/Build`` element.
    step_size, stop_time
        DefaultExperiment [s].
    model_identifier
        ``CoSimulation/@modelIdentifier`` (name of the binary): :data:`MODEL_NAME` for the
        pythonfmu flavour, ``BrushTireNative`` for the native one (:mod:`fmu_src.make.native_build`,
        which writes the input XML itself in pythonfmu's form).
    source_files
        C files under ``sources/`` to list in ``CoSimulation/SourceFiles`` (native flavour).

    Returns
    -------
    bytes
        The new modelDescription.xml (UTF-8).

    Raises
    ------
    ModelDescriptionError
        The variables pythonfmu wrote differ from the table (names, order, start values).
    """
    root = ET.fromstring(xml)
    if root.get("fmiVersion") != "2.0":
        raise ModelDescriptionError(f"expected an FMI 2.0 model description, got "
                                    f"fmiVersion={root.get('fmiVersion')!r}")
    old = root.find("ModelVariables")
    svs = [] if old is None else old.findall("ScalarVariable")
    names = [sv.get("name") for sv in svs]
    if names != [v.name for v in variables]:
        raise ModelDescriptionError(f"pythonfmu wrote the variables {names}, the interface "
                                    f"table has {[v.name for v in variables]}")

    attrs = {"fmiVersion": "2.0", "modelName": MODEL_NAME, "guid": guid}
    for key in ("description", "author", "version", "copyright", "license", "generationTool"):
        if model.get(key):
            attrs[key] = model[key]
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        attrs["generationDateAndTime"] = time.strftime("%Y-%m-%dT%H:%M:%SZ",
                                                       time.gmtime(int(epoch)))
    attrs.update(variableNamingConvention="structured", numberOfEventIndicators="0")
    new = ET.Element("fmiModelDescription", attrs)

    cs_old = root.find("CoSimulation")
    if cs_old is None or cs_old.get("modelIdentifier") != model_identifier:
        raise ModelDescriptionError(f"expected a CoSimulation element with modelIdentifier "
                                    f"{model_identifier!r}")
    cs = ET.SubElement(new, "CoSimulation", {
        "modelIdentifier": model_identifier,
        "needsExecutionTool": cs_old.get("needsExecutionTool", "true"),
        "canHandleVariableCommunicationStepSize": "true",
        "canInterpolateInputs": "false",
        "canBeInstantiatedOnlyOncePerProcess": "false",
        "canNotUseMemoryManagementFunctions": "true",
        "canGetAndSetFMUstate": "true",
        "canSerializeFMUstate": "true",
        "providesDirectionalDerivative": "false",
    })
    if source_files:
        files = ET.SubElement(cs, "SourceFiles")
        for name in source_files:
            ET.SubElement(files, "File", {"name": name})

    used = [u for u in UNITS if any(v.unit == u for v in variables)]
    defs = ET.SubElement(new, "UnitDefinitions")
    for name in used:
        unit = ET.SubElement(defs, "Unit", {"name": name})
        exps = UNITS[name]
        ET.SubElement(unit, "BaseUnit", {b: str(exps[b]) for b in _BASE_UNITS if b in exps})
        for dname, factor, offset in DISPLAY_UNITS.get(name, ()):
            d = {"name": dname, "factor": repr(factor)}
            if offset:
                d["offset"] = repr(offset)
            ET.SubElement(unit, "DisplayUnit", d)

    cats = root.find("LogCategories")
    if cats is not None:
        new.append(cats)
    ET.SubElement(new, "DefaultExperiment", {"startTime": "0.0", "stopTime": repr(stop_time),
                                             "stepSize": repr(step_size)})
    tool = ET.SubElement(ET.SubElement(new, "VendorAnnotations"), "Tool", {"name": "tirefric"})
    ET.SubElement(tool, "Build", {k: str(v) for k, v in vendor.items()})

    mv = ET.SubElement(new, "ModelVariables")
    for i, (v, sv) in enumerate(zip(variables, svs, strict=True)):
        a = {"name": v.name, "valueReference": str(i), "description": v.description,
             "causality": v.causality}
        for key in ("variability", "initial"):
            if sv.get(key) is not None:
                a[key] = sv.get(key)
        el = ET.SubElement(mv, "ScalarVariable", a)
        t_old = sv.find(v.type)
        if t_old is None:
            raise ModelDescriptionError(f"variable {v.name}: pythonfmu wrote no <{v.type}>")
        t: dict[str, str] = {}
        if v.type == "Real":
            t["unit"] = v.unit or "1"
            if v.relative:
                t["relativeQuantity"] = "true"
        if v.start is not None and v.causality != "output":
            if not _same_start(v, t_old.get("start")):
                raise ModelDescriptionError(
                    f"variable {v.name}: the slave reports start {t_old.get('start')!r}, the "
                    f"build expects {_start_text(v)!r}")
            t["start"] = _start_text(v)
        ET.SubElement(el, v.type, t)

    index = {v.name: i + 1 for i, v in enumerate(variables)}
    ms = ET.SubElement(new, "ModelStructure")
    outs = [v for v in variables if v.causality == "output"]
    o = ET.SubElement(ms, "Outputs")
    for v in outs:
        ET.SubElement(o, "Unknown", {"index": str(index[v.name]), "dependencies": ""})
    iu = ET.SubElement(ms, "InitialUnknowns")
    for v in outs:
        deps = sorted(index[n] for n in INITIAL_DEPENDENCIES.get(v.name, ()))
        ET.SubElement(iu, "Unknown", {"index": str(index[v.name]),
                                      "dependencies": " ".join(map(str, deps))})

    new[:] = sorted(new, key=lambda e: _ORDER.index(e.tag))
    ET.indent(new, space="  ")
    return ET.tostring(new, encoding="UTF-8", xml_declaration=True) + b"\n"
