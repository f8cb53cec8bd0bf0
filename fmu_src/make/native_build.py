"""Build the native (Python-free) brush-tire FMU: the C core plus an FMI 2.0 wrapper.

``tirefric fmu build --native`` (:func:`build_native_fmu`) compiles the tire core
(``tire_brush/csrc/tirecore.c``) with the co-simulation wrapper
``fmu_src/runtime/native/fmu_wrapper.c`` into ``binaries/linux64/BrushTireNative.so`` (and,
where a cross-compiler is found,
``binaries/win64/BrushTireNative.dll``). The host needs nothing but the C runtime: no Python.

Same interface as the pythonfmu flavour (:mod:`fmu_src.make.build`): the variables, units, start
values and model structure come from :func:`fmu_src.runtime.interface.variables` and
:func:`fmu_src.make.model_description.postprocess` (one description generator for both); the
wrapper ports the input guard (:mod:`fmu_src.runtime.guard`) and the slave's life cycle
(:mod:`fmu_src.runtime.slave`). What differs: ``modelIdentifier`` ``BrushTireNative``,
``needsExecutionTool="false"``, ``SourceFiles`` (the C sources are in ``sources/``).

Contents of the FMU:

* ``binaries/<platform>/BrushTireNative.{so,dll}``;
* ``resources/tirefric-table.bin``: the friction table of the grid (format in
  :func:`table_bytes`, read by the wrapper at instantiation);
* ``resources/tirefric-data/build.json``: what the FMU was built from (``tirefric fmu
  info``), as in the pythonfmu flavour (the grid's npz is left out: its nodes are the table);
* ``sources/``: the wrapper, the core, the generated ``tfn_config.h`` (this build's variables)
  and ``tfn_interface.h`` (the interface table: inputs, outputs, status bits, guard
  conditions) and the FMI headers;
* ``documentation/host_example.c``: a minimal C host (dlopen, four tires, timing).

The start values of every variable, the GUID and the mapping of the ``tire.*`` parameters onto
the core's ``tf_params`` are compiled in (``tfn_config.h``, written by :func:`config_header`).
"""

from __future__ import annotations

import hashlib
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

from fmu_src.runtime.interface import (
    INPUT_NAMES,
    INPUTS,
    LIMITS,
    OUTPUT_NAMES,
    OUTPUTS,
    Variable,
    variables,
)
from fmu_src.runtime.slave import BUILD_FILE, DATA_DIR
from fmu_src.runtime.table_file import table_bytes
from tire_brush import ccore
from tire_brush.friction import GridFriction, as_table
from tire_brush.params import GROUPS, TireParams, parameter_fields
from tire_brush.transient import TOL

from .model_description import postprocess
from .native_header import interface_header
from .stage import (
    BuildError,
    BuildOptions,
    BuildReport,
    guid_of,
    json_bytes,
    load_inputs,
    stage_resources,
    write_fmu,
)

#: FMI model identifier (name of the binary) of the native flavour.
MODEL_IDENTIFIER = "BrushTireNative"
#: Folder of the wrapper's C sources and the FMI 2.0 headers.
NATIVE_DIR = Path(__file__).parents[1] / "runtime" / "native"
#: Friction table resource (read by the wrapper).
TABLE_FILE = "tirefric-table.bin"
#: Rolling-resistance table resource (same format; present when the build has one).
ROLLING_TABLE_FILE = "tirefric-rolling.bin"
#: Wet-branch resource (:func:`fmu_src.runtime.table_file.wet_bytes`; when the grid has one).
WET_TABLE_FILE = "tirefric-wet.bin"
#: The real-time fidelity's patch table (:meth:`tire_brush.realtime.PatchTable.to_bytes`; when
#: built with ``fidelity="realtime"``).
PATCH_TABLE_FILE = "tirefric-patch.bin"
#: Compiler flags: the core's own (:data:`tire_brush.ccore.CORE_CFLAGS`: C99, no contraction,
#: no fast-math, so the native FMU rounds as the Python model's core does), as a shared library.
CFLAGS = (*ccore.CORE_CFLAGS, "-shared")
#: C files compiled into the binary (under ``sources/`` in the FMU).
C_SOURCES = ("fmu_wrapper.c", "tfn_model.c", "tfn_files.c", "tirecore.c", "tirert.c")
#: The wrapper's own files in :data:`NATIVE_DIR`: the FMI glue, the model callbacks, the
#: resource readers and their internal header.
WRAPPER_FILES = ("fmu_wrapper.c", "tfn_model.c", "tfn_files.c", "tfn_model.h")
#: The core's files under ``sources/``: the sources compiled into the binary and their headers
#: (the core's other parts, e.g. the braking study's force-map reader, stay out of the FMU).
CORE_FILES = tuple(n for n in (*ccore.SOURCES, *ccore.HEADERS)
                   if n in C_SOURCES or n[:-2] + ".c" in C_SOURCES)
#: Headers shipped under ``sources/``.
HEADERS = ("tirecore.h", "tirert.h", "tfn_model.h", "tfn_config.h", "tfn_interface.h",
           "fmi2Functions.h",
           "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")

# -- tfn_config.h ------------------------------------------------------------------------------
def _c_string(s: str) -> str:
    out = []
    for ch in s:
        if ch in "\\\"":
            out.append("\\" + ch)
        elif 32 <= ord(ch) < 127:
            out.append(ch)
        else:
            out.extend(f"\\{b:03o}" for b in ch.encode())
    return '"' + "".join(out) + '"'


def _c_double(x: float) -> str:
    x = float(x)
    if math.isinf(x):
        return "INFINITY" if x > 0 else "(-INFINITY)"
    if math.isnan(x):
        return "NAN"
    return x.hex() if x != int(x) or abs(x) > 2**52 else repr(x)


def _bounds() -> dict[str, dict[str, Any]]:
    """Bounds metadata of every tire parameter, by dotted path."""
    out = {f.name: f.metadata["bounds"] for f in parameter_fields(TireParams)}
    for group, cls in GROUPS.items():
        out |= {f"{group}.{f.name}": f.metadata["bounds"] for f in parameter_fields(cls)}
    return out


def _param_assignments(index: dict[str, int]) -> list[str]:
    """C statements filling ``tf_params`` from the values array ``v``: the numeric fields
    follow :func:`tire_brush.ccore.core_params` itself (run on value references instead of
    values), the three switches are mapped by name."""
    groups: dict[str, dict[str, float]] = {g: {} for g in GROUPS}
    top: dict[str, float] = {}
    for name, vr in index.items():
        if not name.startswith("tire."):
            continue
        head, _, rest = name[5:].partition(".")
        if rest:
            groups[head][rest] = float(vr)
        else:
            top[head] = float(vr)
    fake = SimpleNamespace(**top, **{g: SimpleNamespace(**d) for g, d in groups.items()})
    P = ccore.core_params(fake, n_elements=index["n_elements"],
                          dt_internal=index["dt_internal"], tol=TOL,
                          v_floor=index["v_floor"], thermal=False, rigid=False)
    lines = []
    for fname, _ctype in ccore.Params._fields_:
        if fname in ("tol",):
            continue
        if fname == "rigid":
            lines.append(f"    P->rigid = v[{index['tire.carcass.rigid']}] != 0.0;")
        elif fname == "thermal":
            lines.append(f"    P->thermal = v[{index['tire.thermal.enabled']}] != 0.0;")
        elif fname == "contact_ageing":
            lines.append(f"    P->contact_ageing = v[{index['tire.tread.contact_ageing']}] != 0.0;")
        elif fname == "n_elements":
            lines.append(f"    P->n_elements = (int)v[{index['n_elements']}];")
        else:
            vr = getattr(P, fname)
            if not float(vr).is_integer():
                raise BuildError(f"tf_params.{fname} has no FMU variable (value {vr})")
            lines.append(f"    P->{fname} = v[{int(vr)}];")
    return lines


def config_header(vars_: list[Variable], guid: str, rolling: bool = False,
                  wet: bool = False, patch: bool = False) -> str:
    """``tfn_config.h``: GUID, variable table (start values, bounds), value references of the
    variables the wrapper uses by name, and the parameter mapping onto ``tf_params``."""
    index = {v.name: i for i, v in enumerate(vars_)}
    n_in, n_out = len(INPUTS), len(OUTPUTS)
    names = [v.name for v in vars_]
    if names[:n_in] != list(INPUT_NAMES) or \
            names[n_in:n_in + n_out] != list(OUTPUT_NAMES) or \
            names[n_in + n_out] != "input_status":
        raise BuildError("the native wrapper expects inputs, outputs and input_status first")
    bounds = _bounds()
    types = {"Real": "TFN_REAL", "Integer": "TFN_INTEGER", "Boolean": "TFN_BOOLEAN",
             "String": "TFN_STRING"}
    caus = {"input": "TFN_INPUT", "output": "TFN_OUTPUT", "parameter": "TFN_PARAMETER",
            "local": "TFN_LOCAL"}
    rows = []
    for v in vars_:
        start = 0.0 if v.start is None or v.type == "String" else float(v.start)
        flags, maximum = [], 0.0
        if v.causality == "parameter" and v.type == "Real":
            b = bounds.get(v.name[5:]) if v.name.startswith("tire.") else None
            if b is not None:
                flags.append("TFN_FINITE")
                if b["positive"]:
                    flags.append("TFN_POSITIVE")
                if b["nonnegative"]:
                    flags.append("TFN_NONNEGATIVE")
                if b["maximum"] is not None:
                    flags.append("TFN_MAXIMUM")
                    maximum = float(b["maximum"])
            elif v.name in ("dt_internal", "v_floor") or v.name in LIMITS:
                flags += ["TFN_FINITE", "TFN_POSITIVE"]
        s = _c_string(str(v.start)) if v.type == "String" else "0"
        rows.append(f"    {{{_c_string(v.name)}, {types[v.type]}, {caus[v.causality]}, "
                    f"{_c_double(start)}, {s}, {'|'.join(flags) or '0'}, "
                    f"{_c_double(maximum)}}},")
    named = {"INPUT0": 0, "OUTPUT0": n_in, "STATUS": n_in + n_out,
             "R_E": index["tire.R_e"], "FZ_NOM": index["tire.Fz_nom"],
             "FZ_MAX": index["tire.patch.Fz_max"], "N_ELEMENTS": index["n_elements"],
             "DT_INTERNAL": index["dt_internal"], "S0": index["s0"],
             "V_FLOOR": index["v_floor"], "AXES": index["axes"],
             "TEXTURE_DEPTH": index["texture_depth"], "FIDELITY": index["fidelity"]}
    named |= {"LIMIT_" + k[6:].upper(): index[k] for k in LIMITS}
    defines = [f"#define TFN_VR_{k} {i}" for k, i in named.items()]
    return "\n".join([
        "/* Generated by fmu_src/make/native_build.py: do not edit. */",
        "#ifndef TFN_CONFIG_H", "#define TFN_CONFIG_H", "#include <math.h>",
        '#include "tirecore.h"', "",
        f"#define TFN_GUID {_c_string(guid)}",
        f"#define TFN_MODEL_IDENTIFIER {_c_string(MODEL_IDENTIFIER)}",
        f"#define TFN_TABLE_FILE {_c_string(TABLE_FILE)}",
        f"#define TFN_HAS_ROLLING {int(bool(rolling))}",
        f"#define TFN_ROLLING_FILE {_c_string(ROLLING_TABLE_FILE)}",
        f"#define TFN_HAS_WET {int(bool(wet))}",
        f"#define TFN_WET_FILE {_c_string(WET_TABLE_FILE)}",
        f"#define TFN_HAS_PATCH {int(bool(patch))}",
        f"#define TFN_PATCH_FILE {_c_string(PATCH_TABLE_FILE)}",
        f"#define TFN_TOL {_c_double(TOL)}",
        f"#define TFN_NV {len(vars_)}",
        "enum { TFN_REAL, TFN_INTEGER, TFN_BOOLEAN, TFN_STRING };",
        "enum { TFN_INPUT, TFN_OUTPUT, TFN_PARAMETER, TFN_LOCAL };",
        "enum { TFN_FINITE = 1, TFN_POSITIVE = 2, TFN_NONNEGATIVE = 4, TFN_MAXIMUM = 8 };",
        "typedef struct { const char *name; int type, causality; double start; "
        "const char *str; int bounds; double maximum; } tfn_var;",
        *defines, "",
        "static const tfn_var TFN_VARS[TFN_NV] = {", *rows, "};", "",
        "static inline void tfn_fill_params(const double *v, tf_params *P) {",
        *_param_assignments(index), "}", "#endif", ""])


# -- model description -------------------------------------------------------------------------
def base_model_description(vars_: list[Variable]) -> bytes:
    """A modelDescription.xml in the form pythonfmu writes (causality, variability, initial,
    start values), for :func:`fmu_src.make.model_description.postprocess` to finish exactly as it
    finishes pythonfmu's."""
    import xml.etree.ElementTree as ET

    from .model_description import _start_text

    root = ET.Element("fmiModelDescription", {"fmiVersion": "2.0", "modelName": "BrushTire",
                                              "guid": "{00000000-0000-0000-0000-000000000000}"})
    ET.SubElement(root, "CoSimulation", {"modelIdentifier": MODEL_IDENTIFIER,
                                         "needsExecutionTool": "false"})
    cats = ET.SubElement(root, "LogCategories")
    for name, desc in (("logStatusWarning", "Log messages with fmi2Warning status."),
                       ("logStatusDiscard", "Log messages with fmi2Discard status."),
                       ("logStatusError", "Log messages with fmi2Error status."),
                       ("logAll", "Log all messages.")):
        ET.SubElement(cats, "Category", {"name": name, "description": desc})
    mv = ET.SubElement(root, "ModelVariables")
    for i, v in enumerate(vars_):
        a = {"name": v.name, "valueReference": str(i), "causality": v.causality}
        if v.causality == "input":
            a["variability"] = "continuous"
        elif v.causality == "output":
            a.update(variability="continuous" if v.type == "Real" else "discrete",
                     initial="calculated")
        elif v.causality == "parameter":
            a.update(variability="fixed", initial="exact")
        else:
            a.update(variability="constant", initial="exact")
        sv = ET.SubElement(mv, "ScalarVariable", a)
        t = {} if v.start is None or v.causality == "output" else {"start": _start_text(v)}
        ET.SubElement(sv, v.type, t)
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


# -- compilers ---------------------------------------------------------------------------------
def _zig() -> list[str] | None:
    """``zig cc`` from the ``ziglang`` wheel or the PATH, if available."""
    try:
        import ziglang  # noqa: F401

        return [sys.executable, "-m", "ziglang", "cc"]
    except ImportError:
        z = shutil.which("zig")
        return [z, "cc"] if z else None


def compilers() -> dict[str, list[str]]:
    """Compilers found for each FMI platform: ``linux64`` (``$CC``, cc, gcc, clang), ``win64``
    (x86_64-w64-mingw32-gcc, or ``zig cc -target x86_64-windows-gnu``)."""
    out: dict[str, list[str]] = {}
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or \
        shutil.which("clang")
    if cc and sys.platform.startswith("linux"):
        out["linux64"] = cc.split()
    mingw = shutil.which("x86_64-w64-mingw32-gcc")
    zig = _zig()
    if mingw:
        out["win64"] = [mingw]
    elif zig:
        out["win64"] = [*zig, "-target", "x86_64-windows-gnu"]
    return out


def compile_binary(sources: Path, platform: str, cc: list[str], out_dir: Path) -> Path:
    """Compile the staged ``sources/`` folder into ``out_dir/<platform>/`` for ``platform``.

    Raises
    ------
    BuildError
        The compile failed (its output is in the message).
    """
    ext = ".dll" if platform.startswith("win") else ".so"
    target = out_dir / platform / (MODEL_IDENTIFIER + ext)
    target.parent.mkdir(parents=True, exist_ok=True)
    cmd = [*cc, *CFLAGS, "-I", str(sources), "-o", str(target),
           *(str(sources / s) for s in C_SOURCES)]
    if platform.startswith("linux"):
        exports = out_dir / "exports.map"
        exports.write_text("{ global: fmi2*; local: *; };\n")
        cmd[len(cc):len(cc)] = ["-fPIC"]
        cmd += [f"-Wl,--version-script={exports}", "-lm"]
    res = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if res.returncode != 0 or not target.is_file():
        raise BuildError(f"compiling the native FMU for {platform} failed ({' '.join(cmd)}):\n"
                         f"{res.stdout}{res.stderr}")
    return target


def stage_sources(directory: Path, vars_: list[Variable], guid: str,
                  rolling: bool = False, wet: bool = False,
                  patch: bool = False) -> dict[str, bytes]:
    """Write the C sources, the FMI headers and the generated ``tfn_config.h`` and
    ``tfn_interface.h`` (:mod:`fmu_src.make.native_header`) into
    ``directory``; returns them by name."""
    files = {name: (NATIVE_DIR / name).read_bytes() for name in WRAPPER_FILES}
    files |= {name: (ccore.SOURCE_DIR / name).read_bytes() for name in CORE_FILES}
    files |= {"tfn_config.h": config_header(vars_, guid, rolling, wet, patch).encode(),
             "tfn_interface.h": interface_header().encode()}
    for h in ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"):
        files[h] = (NATIVE_DIR / "fmi2" / h).read_bytes()
    directory.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (directory / name).write_bytes(data)
    return files


# -- the build ---------------------------------------------------------------------------------
def build_native_fmu(tire: str | Path | TireParams, grid: str | Path | Any,
                     output: str | Path, options: BuildOptions | None = None, *,
                     validate: bool = True, platforms: tuple[str, ...] | None = None,
                     require: tuple[str, ...] = ("linux64",)) -> BuildReport:
    """Build the native brush-tire FMU (module docstring).

    Parameters
    ----------
    tire, grid, output, options, validate
        As :func:`fmu_src.make.build.build_fmu`.
    platforms
        FMI platforms to compile for (default: every one a compiler is found for, see
        :func:`compilers`).
    require
        Platforms that must be built (a missing compiler is an error for these only).

    Raises
    ------
    BuildError
        No compiler for a required platform, a compile failed, or validation failed.
    """
    from tirefric.errors import InputError

    t0 = time.perf_counter()
    output = Path(output)
    if output.suffix != ".fmu":
        raise InputError("the FMU file name must end in .fmu", source="-o", value=str(output))
    tire_p, grid_o, grid_source = load_inputs(tire, grid)
    options = options or BuildOptions()
    found = compilers()
    wanted = tuple(found) if platforms is None else tuple(platforms)
    missing = [p for p in (*require, *wanted) if p not in found]
    if missing:
        raise BuildError(f"no C compiler for {', '.join(sorted(set(missing)))} (linux64: gcc "
                         f"or clang or $CC; win64: x86_64-w64-mingw32-gcc or `pip install "
                         f"ziglang`)")
    with tempfile.TemporaryDirectory(prefix="tirefric_native_") as tmp:
        stage = Path(tmp) / "stage"
        build = stage_resources(tire_p, grid_o, stage / "resources", options,
                                grid_source=grid_source)
        s0 = build["options"]["s0"]
        table = table_bytes(as_table(GridFriction(grid_o, s0=s0)))
        rolling = wet = patch = b""
        if build["realtime"]["file"]:
            patch = (stage / "resources" / DATA_DIR / build["realtime"]["file"]).read_bytes()
        if build["rolling"]["file"]:
            rolling = (stage / "resources" / DATA_DIR / build["rolling"]["file"]).read_bytes()
        if build["wet"]["file"]:
            wet = (stage / "resources" / DATA_DIR / build["wet"]["file"]).read_bytes()
        h = hashlib.sha256(b"tirefric-native-fmu\0" + build["build_id"].encode() + table
                           + rolling + wet + patch)
        for name in (*WRAPPER_FILES, *CORE_FILES):
            src = NATIVE_DIR / name if name in WRAPPER_FILES else ccore.SOURCE_DIR / name
            h.update(name.encode() + b"\0" + src.read_bytes())
        h.update(" ".join(CFLAGS).encode())
        build_id = "sha256:" + h.hexdigest()
        guid = guid_of(build_id)
        build["build_id"] = build_id
        build["flavour"] = "native"
        build["requirements"] = []
        build["model"]["generationTool"] = (f"tirefric {build['versions']['tirefric']} "
                                            f"(native C wrapper)")
        build["native"] = {"model_identifier": MODEL_IDENTIFIER, "table": TABLE_FILE,
                           "table_sha256": "sha256:" + hashlib.sha256(table).hexdigest(),
                           "cflags": list(CFLAGS), "tol": TOL}
        info = {"info.tire": tire_p.name, "info.grid_hash": grid_o.hash,
                "info.build_id": build_id}
        vars_ = variables(build["tire"], build["options"], build["limits"], info)
        sources = stage_sources(stage / "sources", vars_, guid, rolling=bool(rolling),
                                wet=bool(wet), patch=bool(patch))
        bins = {p: compile_binary(stage / "sources", p, found[p], Path(tmp) / "bin")
                for p in wanted}
        build["native"]["platforms"] = sorted(bins)
        # the grid's nodes are in the table resource; the npz (same data) is left out
        build["grid"]["file"] = None
        build["grid"]["table"] = TABLE_FILE
        entries: dict[str, bytes] = {f"resources/{TABLE_FILE}": table}
        if rolling:
            build["rolling"]["file"] = None
            build["rolling"]["table"] = ROLLING_TABLE_FILE
            entries[f"resources/{ROLLING_TABLE_FILE}"] = rolling
        if wet:
            build["wet"]["file"] = None
            build["wet"]["table"] = WET_TABLE_FILE
            entries[f"resources/{WET_TABLE_FILE}"] = wet
        if patch:
            build["realtime"]["file"] = None
            build["realtime"]["table"] = PATCH_TABLE_FILE
            entries[f"resources/{PATCH_TABLE_FILE}"] = patch
        entries[f"resources/{DATA_DIR}/{BUILD_FILE}"] = json_bytes(build)
        entries |= {f"sources/{n}": b for n, b in sources.items()}
        entries["documentation/host_example.c"] = (NATIVE_DIR / "host_example.c").read_bytes()
        entries |= {f"binaries/{p}/{path.name}": path.read_bytes() for p, path in bins.items()}
        vendor = {"build_id": build_id, "grid_hash": grid_o.hash, "grid_source": grid_source,
                  "tire": tire_p.name, "tire_file": build["tire"]["file"],
                  "flavour": "native", "tirefric_version": build["versions"]["tirefric"]}
        entries["modelDescription.xml"] = postprocess(
            base_model_description(vars_), vars_, guid=guid, model=build["model"],
            vendor=vendor, step_size=1e-3, model_identifier=MODEL_IDENTIFIER,
            source_files=C_SOURCES)
        data = write_fmu(entries, output, validate=validate, what="the native FMU")
    return BuildReport(path=output, guid=guid, build_id=build_id,
                       sha256="sha256:" + hashlib.sha256(data).hexdigest(),
                       size_bytes=len(data), tire=tire_p.name, grid_hash=grid_o.hash,
                       grid_source=grid_source, runtime_package="(native: "
                       + ", ".join(sorted(bins)) + ")", n_variables=len(vars_),
                       seconds=time.perf_counter() - t0)
