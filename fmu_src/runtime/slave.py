"""The pythonfmu slave: a thin FMI 2.0 co-simulation shell over the transient brush tire.

:class:`BrushTireSlave` holds no physics. It

* registers the variables of :mod:`fmu_src.runtime.interface` (inputs, outputs, tire
  parameters, model options, input envelope, provenance strings);
* builds a :class:`tire_brush.transient.TransientBrushTire` on the grid in its resources when
  initialisation ends (parameters are ``fixed``: set them before that);
* per ``doStep``: passes the inputs through :class:`fmu_src.runtime.guard.InputGuard`, advances the
  model by the communication step (the model splits it into sub-steps of at most
  ``dt_internal``) and publishes the model's outputs;
* saves and restores its full state (:meth:`_get_fmu_state`), serialized exactly by
  :mod:`fmu_src.runtime.state`.

Status of ``doStep`` (pythonfmu can return fmi2OK or fmi2Discard):

* fmi2OK -- the step was taken. If inputs had to be repaired (NaN, negative load, beyond the
  envelope), or the model spent an outer step's work budget or read the friction outside the
  grid's temperature range, the output ``input_status`` says which (bits of
  :data:`fmu_src.runtime.interface.STATUS_BITS`) and a warning goes to the FMI logger when the
  condition starts (logging on: fmpy ``debug_logging=True``).
* fmi2Discard -- nothing was advanced because the communication step is negative, not finite
  or longer than :data:`MAX_SUBSTEPS` internal steps; or the model failed inside the step
  (an error in tirefric): it is then reset to an undeflected tire at rest, ``input_status``
  has bit 64, and the error is logged. Outputs stay finite in every case.

Misuse never raises. pythonfmu (0.7) turns every Python exception in a slave method into
fmi2Fatal *and* releases the Python instance, so the host's next call on it (or the
``fmi2FreeInstance`` at the end, which releases it again) crashes the process; an exception
anywhere in a run of the pythonfmu FMU was the cause of crashes at exit. So every method the
wrapper calls catches its errors: a get/set of an unknown value reference, of the wrong type,
a set of an output, a constant or a fixed parameter after initialisation, a corrupt or foreign
state blob, bad parameters at initialisation are logged with status fmi2Error and change
nothing, and the call returns fmi2OK (pythonfmu cannot return fmi2Error without the Fatal
path; the native FMU returns fmi2Error for the same cases). Getters of invalid references
return zeros. Messages reach the host only with logging on.

In the FMU this file is the slave module (renamed, imports pointing at the FMU's private copy
of the packages, see :mod:`fmu_src.make.package`); in a source checkout it runs as is, given a
resources folder made by :func:`fmu_src.make.build.stage_resources`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from pythonfmu import (
    Boolean,
    Fmi2Causality,
    Fmi2Initial,
    Fmi2Slave,
    Fmi2Variability,
    Integer,
    Real,
    String,
)
from pythonfmu.enums import Fmi2Status

try:
    from fmu_src.runtime import state as state_io
    from fmu_src.runtime.guard import InputGuard, ModelConditions
    from fmu_src.runtime.interface import (
        INPUT_NAMES,
        LIMITS,
        MODEL_NAME,
        OUTPUT_NAMES,
        STATUS_BITS,
        TIRE_FIELDS,
        Variable,
        axis_signs,
        realtime_parameters,
        tire_from_parameters,
        variables,
    )
    from fmu_src.runtime.table_file import read_table_bytes, read_wet_bytes
    from lookup.grid.reader import FrictionGrid
    from tire_brush import ccore
    from tire_brush.friction import GridFriction
    from tire_brush.realtime import PatchTable
    from tire_brush.slip import BrushOutputs, slip_from_kinematics
    from tire_brush.transient import TransientBrushTire
except ImportError as exc:      # numpy missing in the host's Python: say so at instantiation
    _MISSING: ImportError | None = exc
    OUTPUT_NAMES = ()
else:
    _MISSING = None

#: Folder inside the FMU's resources with build.json and the grid.
DATA_DIR = "tirefric-data"
#: Folder inside :data:`DATA_DIR` with the compiled tire core (``<platform>/<library>``) and
#: its C sources.
CORE_DIR = "tirecore"
#: Name of the build description inside :data:`DATA_DIR`.
BUILD_FILE = "build.json"
#: Name of the rolling-resistance table inside :data:`DATA_DIR` (when the build has one;
#: format of :mod:`fmu_src.runtime.table_file`).
ROLLING_FILE = "rolling.bin"
#: Name of the wet branch inside :data:`DATA_DIR` (when the grid has one;
#: :func:`fmu_src.runtime.table_file.wet_bytes`).
WET_FILE = "wet.bin"
#: Name of the real-time fidelity's patch table inside :data:`DATA_DIR` (when the build has
#: one; :meth:`tire_brush.realtime.PatchTable.to_bytes`).
PATCH_FILE = "patch.bin"
#: Tag of the FMU state.
STATE_FORMAT = "tirefric-brush-tire-fmu-state"
#: Tag of a state blob that failed its checks (:meth:`BrushTireSlave._fmu_state_from_bytes`).
_REFUSED = "refused"
#: Longest communication step, in internal steps (a guard against a step that would run for
#: minutes: 1e5 steps of 1 ms is 100 s of simulated time).
MAX_SUBSTEPS = 100_000

_CAUSALITY = {"input": Fmi2Causality.input, "output": Fmi2Causality.output,
              "parameter": Fmi2Causality.parameter, "local": Fmi2Causality.local}


def _resource(data_dir: Path, spec: dict[str, Any], what: str) -> bytes | None:
    """The bytes of an optional resource the build recorded in build.json (``spec``: its
    ``file`` and ``sha256``), or None when the build has none.

    Raises
    ------
    ValueError
        The file is missing, corrupt or not the one the build recorded.
    """
    import hashlib

    if not spec.get("file"):
        return None
    path = data_dir / spec["file"]
    data = path.read_bytes()
    if "sha256:" + hashlib.sha256(data).hexdigest() != spec.get("sha256"):
        raise ValueError(f"{path}: not the {what} of this build")
    return data


def _read_rolling(data_dir: Path, spec: dict[str, Any]) -> Any:
    """The build's rolling-resistance table as the object
    :meth:`tire_brush.transient.TransientBrushTire.set_rolling` takes, or None."""
    from types import SimpleNamespace

    data = _resource(data_dir, spec, "rolling-resistance table")
    if data is None:
        return None
    t = read_table_bytes(data)
    return SimpleNamespace(log10_v=t["log10_v"], T=t["T"], log10_Fz=t["log10_p"],
                           f_r=t["values"][..., 0], tread_share=t["values"][..., 1])


def _read_wet(data_dir: Path, spec: dict[str, Any]) -> dict[str, Any] | None:
    """The build's wet branch as the arrays of
    :func:`fmu_src.runtime.table_file.read_wet_bytes`, or None."""
    data = _resource(data_dir, spec, "wet branch")
    return None if data is None else read_wet_bytes(data)


def read_build(resources: str | Path) -> dict[str, Any]:
    """The build description (``build.json``) in a resources folder."""
    path = Path(resources) / DATA_DIR / BUILD_FILE
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise FileNotFoundError(f"{path}: cannot read the FMU's build description "
                                f"({exc})") from None


class BrushTireSlave(Fmi2Slave):
    """FMI 2.0 co-simulation slave of the transient brush tire (module docstring).

    Parameters
    ----------
    **kwargs
        From pythonfmu: ``instance_name``, ``resources`` (the FMU's resources folder),
        ``visible``, ``logger``.
    """

    def __init__(self, **kwargs: Any) -> None:
        if _MISSING is not None:
            import sys

            raise RuntimeError(
                f"the tirefric brush-tire FMU (pythonfmu flavour) runs in the host's Python "
                f"and needs numpy there; this host's Python {sys.version.split()[0]} "
                f"({sys.executable}) cannot import it ({_MISSING}). Install numpy >= 1.26 "
                f"for that Python, or use the native FMU (tirefric fmu build --native), "
                f"which needs no Python.")
        super().__init__(**kwargs)
        if self.resources is None:
            raise ValueError("BrushTireSlave needs its resources folder (resources=...)")
        build = read_build(self.resources)
        core = build.get("core")
        if core is not None:                          # the FMU's own build of the tire core
            ccore.use_library(Path(self.resources) / DATA_DIR / core["library"])
        self._build = build
        self.modelName = MODEL_NAME
        for key in ("author", "description", "version", "license", "copyright"):
            if key in build["model"]:
                setattr(self, key, build["model"][key])
        grid_path = Path(self.resources) / DATA_DIR / build["grid"]["file"]
        self._grid = FrictionGrid.load_npz(grid_path)
        self._rolling = _read_rolling(Path(self.resources) / DATA_DIR,
                                      build.get("rolling") or {})
        self._wet = _read_wet(Path(self.resources) / DATA_DIR, build.get("wet") or {})
        patch = _resource(Path(self.resources) / DATA_DIR, build.get("realtime") or {},
                          "real-time patch table")
        # the checksum is the sha256 just checked; the FNV trailer is the native reader's
        self._patch = None if patch is None else PatchTable.from_bytes(patch, verify=False)
        if self._grid.hash != build["grid"]["hash"]:
            raise ValueError(f"{grid_path}: grid hash {self._grid.hash} differs from the build's "
                             f"{build['grid']['hash']}")
        info = {"info.tire": build["tire"]["name"], "info.grid_hash": self._grid.hash,
                "info.build_id": build["build_id"]}
        self._vars: list[Variable] = variables(build["tire"], build["options"],
                                               build["limits"], info)
        self._u = [float(v.start) for v in self._vars if v.causality == "input"]
        self._u_start = list(self._u)
        self._p: dict[str, Any] = {v.name: v.start for v in self._vars
                                   if v.causality == "parameter"}
        self._out = BrushOutputs(*([0.0] * len(OUTPUT_NAMES)))
        self._status = 0
        self._model: TransientBrushTire | None = None
        self._guard: InputGuard | None = None
        self._conditions: ModelConditions | None = None
        self._model_key = ""
        self._signs = {"vy": 1, "Fy": 1, "Mz": 1, "My": 1, "alpha": 1}
        for i, v in enumerate(self._vars):
            self.register_variable(self._fmi_variable(v, i, info))

    # -- variables ------------------------------------------------------------------------------
    def _fmi_variable(self, v: Variable, i: int, info: dict[str, str]) -> Any:
        """The pythonfmu variable of ``v`` with its getter and setter."""
        kw: dict[str, Any] = {"causality": _CAUSALITY[v.causality],
                              "description": v.description}
        if v.causality == "input":
            kw.update(variability=Fmi2Variability.continuous,
                      getter=lambda: self._u[i], setter=lambda x: self._u.__setitem__(i, x))
        elif v.causality == "output" and v.type == "Real":
            kw.update(variability=Fmi2Variability.continuous, initial=Fmi2Initial.calculated,
                      getter=lambda: self._signs.get(v.name, 1) * getattr(self._out, v.name))
        elif v.causality == "output":
            kw.update(variability=Fmi2Variability.discrete, initial=Fmi2Initial.calculated,
                      getter=lambda: self._status)
        elif v.causality == "parameter":
            kw.update(variability=Fmi2Variability.fixed, initial=Fmi2Initial.exact,
                      getter=lambda: self._p[v.name],
                      setter=lambda x: self._set_parameter(v.name, x))
        else:
            kw.update(variability=Fmi2Variability.constant, initial=Fmi2Initial.exact,
                      getter=lambda: info[v.name])
        cls = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}[v.type]
        return cls(v.name, **kw)

    def _set_parameter(self, name: str, value: Any) -> None:
        """Set a fixed parameter (only before the model is built)."""
        if self._model is not None:
            self.log(f"parameter {name} is fixed: it cannot change after initialization "
                     f"(ignored)", Fmi2Status.error)
            return
        self._p[name] = value

    # -- FMI life cycle -------------------------------------------------------------------------
    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        """Nothing to set up: the model's time starts at zero and advances with the steps."""

    def exit_initialization_mode(self) -> None:
        """Build the model from the parameters; outputs of the undeflected tire. Parameters
        the model refuses are logged (fmi2Error) and every ``doStep`` then returns
        fmi2Discard until a state with valid parameters is restored."""
        try:
            self._build_model()
            self._initial_outputs()
        except Exception as exc:  # never raise into pythonfmu (module docstring)
            self._model = self._guard = None
            self.log(f"initialization: the parameters do not make a tire model "
                     f"({type(exc).__name__}: {exc})", Fmi2Status.error)

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance by one communication step (status: module docstring)."""
        try:
            return self._do_step(current_time, step_size)
        except Exception as exc:  # never raise into pythonfmu (module docstring)
            self.log(f"doStep at t = {current_time!r} s failed ({type(exc).__name__}: {exc}); "
                     f"nothing was advanced", Fmi2Status.error)
            return False

    def _do_step(self, current_time: float, step_size: float) -> bool:
        if self._model is None:
            try:
                self._build_model()
            except Exception as exc:
                self._model = self._guard = None
                self.log(f"doStep at t = {current_time!r} s: no tire model (the parameters "
                         f"are refused: {type(exc).__name__}: {exc}); nothing was advanced",
                         Fmi2Status.error)
                return False
        model, guard = self._model, self._guard
        if not (math.isfinite(step_size) and step_size >= 0.0) or \
                step_size > MAX_SUBSTEPS * model.dt_internal:
            self.log(f"doStep at t = {current_time!r} s: communication step {step_size!r} s "
                     f"is not finite, negative or longer than {MAX_SUBSTEPS} internal steps "
                     f"of {model.dt_internal:g} s; nothing was advanced", Fmi2Status.error)
            return False
        x, status, messages = guard.apply(self._u)
        for level, text in messages:
            self.log(f"t = {current_time:.6g} s: {text}", Fmi2Status(level))
        x = self._to_model(x)
        try:
            out = model.step(step_size, *x)
            ok = all(map(math.isfinite, out.__dict__.values()))
            why = "non-finite outputs"
        except Exception as exc:  # a failure of the model must not end the co-simulation
            ok, why = False, f"{type(exc).__name__}: {exc}"
        if ok:
            bits, messages = self._conditions.apply(model.flags, out.T_tread)
            for level, text in messages:
                self.log(f"t = {current_time:.6g} s: {text}", Fmi2Status(level))
            self._out, self._status = out, status | bits
            return True
        model.reset()
        self._initial_outputs(x)
        self._status = status | STATUS_BITS["model_reset"]
        self.log(f"doStep at t = {current_time:.6g} s: the tire model failed ({why}) with "
                 f"inputs {dict(zip(INPUT_NAMES, x, strict=True))}; it was reset "
                 f"to an undeflected tire at rest (input_status bit 64)", Fmi2Status.error)
        return False

    # -- model ----------------------------------------------------------------------------------
    def _build_model(self) -> None:
        """Transient brush tire and input guard from the current parameters."""
        p = self._p
        text = self._build["tire"]
        tire = tire_from_parameters(text["name"], {f: p[f"tire.{f}"] for f in TIRE_FIELDS},
                                    description=text["description"],
                                    provenance=text["provenance"])
        n_elements = p["n_elements"]
        if isinstance(n_elements, float) and n_elements.is_integer():
            n_elements = int(n_elements)
        patch = self._realtime_patch(p)
        self._model = TransientBrushTire(tire, GridFriction(self._grid, s0=float(p["s0"])),
                                         n_elements=n_elements,
                                         dt_internal=float(p["dt_internal"]),
                                         v_floor=float(p["v_floor"]), patch=patch)
        if self._rolling is not None:
            self._model.set_rolling(self._rolling)
        if self._wet is not None:
            w = self._wet
            self._model.set_wet_arrays(w["depth"], w["log10_t"], w["mu"], w["w_dry"],
                                       texture_depth=float(p["texture_depth"]),
                                       d_full=w["d_full"], drain_scale=w["drain_scale"])
        T_axis = self._grid.axes["T"]
        self._conditions = ModelConditions(float(T_axis[0]), float(T_axis[-1]))
        self._guard = InputGuard({k: float(p[k]) for k in LIMITS}, self._u_start,
                                 wet=self._wet is not None)
        axes = p["axes"]
        if isinstance(axes, float) and axes.is_integer():
            axes = int(axes)
        self._signs = axis_signs(axes)
        self._model_key = json.dumps(p, sort_keys=True)

    def _realtime_patch(self, p: dict[str, Any]) -> Any:
        """The patch table for parameter ``fidelity`` = 1 (None for 0).

        Raises
        ------
        ValueError
            ``fidelity`` is not 0 or 1, the FMU was built without the table, or a parameter
            the table was built from differs from the value it was built with.
        """
        fid = p["fidelity"]
        if fid not in (0, 1) or isinstance(fid, bool):
            raise ValueError(f"fidelity = {fid!r} must be 0 (full) or 1 (real-time)")
        if fid == 0:
            return None
        if self._patch is None:
            raise ValueError("fidelity = 1 needs the real-time patch table, which this FMU "
                             "was built without (tirefric fmu build --fidelity realtime)")
        start = {v.name: v.start for v in self._vars if v.causality == "parameter"}
        changed = [n for n in realtime_parameters(start) if p[n] != start[n]]
        if changed:
            raise ValueError(f"fidelity = 1: the patch table was built for the start values "
                             f"of {', '.join(changed)} (rebuild the FMU for other values)")
        return self._patch

    def _to_model(self, x: list[float]) -> list[float]:
        """Guarded inputs in the brush model's axes (``vy`` by the ``axes`` parameter)."""
        return [x[0], self._signs["vy"] * x[1], *x[2:]]

    def _initial_outputs(self, x: list[float] | None = None) -> None:
        """Outputs of the undeflected tire at inputs ``x`` (default: the current inputs,
        through the guard): zero forces, the reported slips, T_tread = T_surface."""
        if x is None:
            x, self._status, messages = self._guard.apply(self._u)
            for level, text in messages:
                self.log(f"initialization: {text}", Fmi2Status(level))
            x = self._to_model(x)
        vx, vy, omega, _, T_surface, *_ = x
        model = self._model
        kappa, alpha = slip_from_kinematics(vx, vy, omega, model.params.R_e, model.v_floor)
        self._out = BrushOutputs(0.0, 0.0, 0.0, kappa, alpha, 0.0, 0.0, 0.0, 0.0, T_surface)

    # -- FMU state --------------------------------------------------------------------------------
    def _get_fmu_state(self) -> dict[str, Any]:
        """The full state (copies): inputs, parameters, outputs, input guard and model."""
        model, guard = self._model, self._guard
        return {"format": STATE_FORMAT, "build_id": self._build["build_id"],
                "inputs": list(self._u), "parameters": dict(self._p),
                "outputs": [getattr(self._out, n) for n in OUTPUT_NAMES],
                "status": self._status,
                "guard": None if guard is None else guard.get_state(),
                "conditions": None if guard is None else self._conditions.get_state(),
                "model": None if model is None else model.get_state()}

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """Restore a state of :meth:`_get_fmu_state` (bit for bit); a state that is refused
        (corrupt, foreign, other build) is logged (fmi2Error) and changes nothing."""
        backup = self._get_fmu_state()
        try:
            self._restore(state)
        except Exception as exc:  # never raise into pythonfmu (module docstring)
            self._restore(backup)
            self.log(f"setFMUstate: state refused, nothing changed ({exc})", Fmi2Status.error)

    def _restore(self, state: Any) -> None:
        if isinstance(state, dict) and state.get("format") == _REFUSED:
            raise ValueError(state.get("why", "not a state of this FMU"))
        if not isinstance(state, dict) or state.get("format") != STATE_FORMAT:
            raise ValueError("not a state of the tirefric brush-tire FMU")
        if state["build_id"] != self._build["build_id"]:
            raise ValueError(f"the state comes from another build of the FMU (build "
                             f"{state['build_id']}, this FMU {self._build['build_id']})")
        params = dict(state["parameters"])
        if set(params) != set(self._p):
            raise ValueError("the state's parameters do not match this FMU's")
        self._p = params
        if state["model"] is None:
            self._model = self._guard = None
        else:
            if self._model is None or json.dumps(params, sort_keys=True) != self._model_key:
                self._build_model()
            self._model.set_state(state["model"])
            self._guard.set_state(state["guard"])
            self._conditions.set_state(state["conditions"])
        self._u = [float(x) for x in state["inputs"]]
        self._out = BrushOutputs(*(float(x) for x in state["outputs"]))
        self._status = int(state["status"])

    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        """Exact serialization (numpy arrays included): :func:`fmu_src.runtime.state.to_bytes`."""
        return state_io.to_bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes) -> dict[str, Any]:
        """Inverse of :meth:`_fmu_state_to_bytes`; bytes that fail the magic, checksum or
        size checks give a "refused" state that :meth:`_set_fmu_state` logs and ignores."""
        try:
            return state_io.from_bytes(state)
        except Exception as exc:  # never raise into pythonfmu (module docstring)
            return {"format": _REFUSED, "why": f"{type(exc).__name__}: {exc}"}

    # -- variable access that never raises (module docstring) ----------------------------------
    def _misuse(self, vrs: Any, cls: type, write: bool) -> str | None:
        """Why the access to ``vrs`` as ``cls`` is refused, or None."""
        try:
            refs = [int(vr) for vr in vrs]
        except (TypeError, ValueError):
            return f"value references {vrs!r} are not integers"
        for vr in refs:
            var = self.vars.get(vr)
            if var is None:
                return f"unknown value reference {vr}"
            if not isinstance(var, cls):
                return (f"{var.name} (value reference {vr}) is a {type(var).__name__}, not "
                        f"a {cls.__name__}")
            if write:
                if var.causality in (Fmi2Causality.output, Fmi2Causality.local) or \
                        var.variability == Fmi2Variability.constant or var.setter is None:
                    return f"{var.name} (value reference {vr}) cannot be set"
                if var.causality == Fmi2Causality.parameter and self._model is not None:
                    return (f"parameter {var.name} is fixed: it cannot change after "
                            f"initialization")
        return None

    def _get(self, vrs: Any, cls: type, conv: Any, zero: Any) -> list[Any]:
        try:
            why = self._misuse(vrs, cls, False)
            if why is None:
                return [conv(self.vars[int(vr)].getter()) for vr in vrs]
        except Exception as exc:
            why = f"{type(exc).__name__}: {exc}"
        self.log(f"get{cls.__name__}: refused ({why}); zeros returned", Fmi2Status.error)
        try:
            return [zero] * len(vrs)
        except TypeError:
            return []

    def _set(self, vrs: Any, values: Any, cls: type, conv: Any) -> None:
        try:
            why = self._misuse(vrs, cls, True)
            if why is None:
                pairs = [(self.vars[int(vr)], conv(x)) for vr, x in zip(vrs, values,
                                                                        strict=True)]
                for var, x in pairs:
                    var.setter(x)
                return
        except Exception as exc:
            why = f"{type(exc).__name__}: {exc}"
        self.log(f"set{cls.__name__}: refused ({why}); nothing was set", Fmi2Status.error)

    def get_real(self, vrs: list[int]) -> list[float]:
        return self._get(vrs, Real, float, 0.0)

    def get_integer(self, vrs: list[int]) -> list[int]:
        return self._get(vrs, Integer, int, 0)

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        return self._get(vrs, Boolean, bool, False)

    def get_string(self, vrs: list[int]) -> list[str]:
        return self._get(vrs, String, str, "")

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        self._set(vrs, values, Real, float)

    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        self._set(vrs, values, Integer, int)

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        self._set(vrs, values, Boolean, bool)

    def set_string(self, vrs: list[int], values: list[str]) -> None:
        self._set(vrs, values, String, str)
