"""Helpers of the FMU tests: a synthetic grid, a built FMU and an fmpy driver with a logger.

The grid here is synthetic (analytic shapes, no Persson physics): the FMU tests check the
packaging, the FMI behaviour and that the FMU computes exactly what the Python model computes,
for which any grid with a speed, temperature and pressure dependence serves.
"""

from __future__ import annotations

import math
from ctypes import byref
from pathlib import Path
from typing import Any

import numpy as np


def __getattr__(name: str) -> Any:
    """``INPUTS`` and ``OUTPUTS``: the tire's inputs and outputs in order, from the one table
    (tire_brush.signals), imported when first asked for: :class:`FmuDriver` itself reads them
    from the FMU's model description, as a host does, and so runs where the project's
    packages are not importable (the isolation test poisons their names)."""
    if name in ("INPUTS", "OUTPUTS"):
        from tire_brush.signals import INPUT_NAMES, OUTPUT_NAMES

        return INPUT_NAMES if name == "INPUTS" else OUTPUT_NAMES
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def synthetic_grid() -> Any:
    """A small grid with velocity weakening, a flash-temperature rise and a pressure and
    temperature dependence (mu_cold peaks near 0.03 m/s at 20 C and shifts with T; mu_hot
    falls below it with speed; dT_flash rises to 80 K)."""
    from lookup.grid import FrictionGrid  # here: the isolation test imports this module only

    v = np.logspace(-6, 1.6, 39)
    T = np.linspace(253.15, 393.15, 8)
    p = np.logspace(4.5, 6.5, 5)
    V, TT, P = np.meshgrid(v, T, p, indexing="ij")
    x = np.log10(V) - 0.02 * (TT - 293.15)
    mu_cold = 0.5 + 0.7 * np.exp(-(((x + 1.5) / 2.0) ** 2)) - 0.03 * np.log10(P / 3e5)
    mu_hot = mu_cold - 0.25 * V / (V + 0.3)
    dT = 80.0 * V / (V + 0.1)
    return FrictionGrid.from_arrays(v, T, p, {"mu_cold": mu_cold, "mu_hot": mu_hot,
                                              "dT_flash": dT},
                                    s0_m=2e-4, D_m=1e-3, meta={"kind": "synthetic test grid"})


def build_test_fmu(directory: Path, name: str = "BrushTire.fmu", **options: Any) -> Path:
    """Build the FMU of the shipped passenger tire on :func:`synthetic_grid`."""
    from fmu_src.make.build import BuildOptions, build_fmu

    return build_fmu("passenger", synthetic_grid(), Path(directory) / name,
                     BuildOptions(**options)).path


class FmuDriver:
    """One FMU instance driven step by step through fmpy, with the FMI log captured.

    Parameters
    ----------
    fmu
        The FMU file.
    unzipdir
        An extracted copy (shared by several instances), default: extract here.
    name
        Instance name.
    logging
        ``loggingOn`` of fmi2Instantiate (pythonfmu forwards messages only when on).
    """

    def __init__(self, fmu: Path, unzipdir: str | None = None, name: str = "tire",
                 logging: bool = True, start_values: dict[str, Any] | None = None) -> None:
        import fmpy
        from fmpy.fmi2 import (
            FMU2Slave,
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )
        from fmpy.logging import addLoggerProxy

        self.md = fmpy.read_model_description(str(fmu))
        self.unzipdir = unzipdir or fmpy.extract(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.types = {v.name: v.type for v in self.md.modelVariables}
        self.messages: list[tuple[int, str, str]] = []

        def log(env, instance, status, category, message):
            self.messages.append((int(status), (category or b"").decode(),
                                  (message or b"").decode()))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy.free)
        addLoggerProxy(byref(cb))
        self._callbacks = cb
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzipdir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier,
                             instanceName=name)
        self.fmu.instantiate(callbacks=cb, loggingOn=logging)
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for key, val in (start_values or {}).items():
            self.set({key: val})
        self.fmu.exitInitializationMode()
        self.time = 0.0
        #: the FMU's inputs and Real outputs in the order its model description declares them
        self.inputs = [v.name for v in self.md.modelVariables if v.causality == "input"]
        self.output_names = [v.name for v in self.md.modelVariables
                             if v.causality == "output" and v.type == "Real"]
        self._vin = [self.vr[n] for n in self.inputs]
        self._vout = [self.vr[n] for n in self.output_names]

    def set(self, values: dict[str, Any]) -> None:
        """Set variables by name."""
        for key, val in values.items():
            t = self.types[key]
            if t == "Real":
                self.fmu.setReal([self.vr[key]], [float(val)])
            elif t == "Integer":
                self.fmu.setInteger([self.vr[key]], [int(val)])
            elif t == "Boolean":
                self.fmu.setBoolean([self.vr[key]], [bool(val)])

    def outputs(self) -> np.ndarray:
        """The Real outputs in the model description's order (the table's, :data:`OUTPUTS`)."""
        return np.array(self.fmu.getReal(self._vout))

    def status(self) -> int:
        """The output ``input_status``."""
        return int(self.fmu.getInteger([self.vr["input_status"]])[0])

    def step(self, u: list[float], dt: float = 1e-3) -> np.ndarray:
        """Set the inputs (:data:`INPUTS` order), take one step, return the outputs."""
        self.fmu.setReal(self._vin, [float(x) for x in u])
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=dt)
        self.time += dt
        return self.outputs()

    def close(self) -> None:
        """Terminate and free the instance."""
        self.fmu.terminate()
        self.fmu.freeInstance()


def slave_outputs(resources: Path, u: list[float], n: int, dt: float = 1e-3) -> np.ndarray:
    """The pythonfmu slave on a staged resources folder, in process: ``n`` steps of ``dt``
    with the inputs ``u`` held (:data:`INPUTS` order); the Real outputs of each step."""
    from fmu_src.runtime.slave import BrushTireSlave
    from tire_brush.signals import INPUT_NAMES, OUTPUT_NAMES

    s = BrushTireSlave(instance_name="s", resources=str(resources))
    vr = {v.name: v.value_reference for v in s.vars.values()}
    s.enter_initialization_mode()
    s.exit_initialization_mode()
    got = []
    for _ in range(n):
        s.set_real([vr[k] for k in INPUT_NAMES], u)
        assert s.do_step(0.0, dt), "do_step returned False (fmi2Discard)"
        got.append(s.get_real([vr[k] for k in OUTPUT_NAMES]))
    return np.array(got)


#: Non-finite, huge, zero, subnormal and negative values the fuzz puts into the inputs.
FUZZ_GARBAGE = (math.nan, math.inf, -math.inf, 1e30, -1e30, 1e308, 0.0, -0.0, 5e-324, -4000.0)
#: Communication steps of the fuzz: mostly 1 ms; tiny, subnormal, zero, odd, negative, NaN,
#: infinite ones; and long ones up to 0.3 s (a master's long first step, a slow co-simulation).
FUZZ_STEPS = ((1e-3,) * 24 + (1e-12, 5e-324, 0.0, 2e-4, 3e-3, 1e-7, -1e-3, math.nan, math.inf)
              + (0.05, 0.1, 0.3))


def fuzz_inputs(rng: np.random.Generator, vx: float = 20.0, Fz: float = 4000.0,
                R_e: float = 0.31, wet: bool = False) -> list[float]:
    """Adversarial inputs (:data:`INPUTS` order) of the FMU fuzz: braking, cornering and
    driving around ``vx`` and ``Fz`` with wide scatter, and in 4 % of the inputs a value of
    :data:`FUZZ_GARBAGE` (which the input guard clamps to the envelope's edges: 150 m/s,
    1000 rad/s, five times the largest load), in 2 % a zero speed, spin or load. ``wet``:
    also camber (0.03 rad scatter) and, in a third of the steps, water up to 5 mm."""
    u = [rng.normal(vx, 15.0), rng.normal(0.0, 3.0), rng.normal(vx / R_e, 40.0),
         rng.normal(Fz, 3000.0), rng.uniform(240.0, 360.0), rng.uniform(0.0, 1.5), 0.0, 0.0]
    n = 6
    if wet:
        u[6] = rng.normal(0.0, 0.03)
        u[7] = rng.uniform(0.0, 5e-3) if rng.random() < 1.0 / 3.0 else 0.0
        n = 8
    for i in range(n):
        r = rng.random()
        if r < 0.04:
            u[i] = float(rng.choice(FUZZ_GARBAGE))
        elif r < 0.06:
            u[i] = 0.0                                  # zero speed, spin, load
    return [float(x) for x in u]


def braking_inputs(n: int, dt: float = 1e-3, seed: int = 5) -> np.ndarray:
    """A manoeuvre of ``n`` steps: rolling at 20 m/s, a braking slip ramp with steer, a load
    change, a temperature change, a low-friction patch and camber; a dry road (rows:
    :data:`INPUTS`)."""
    t = np.arange(n) * dt
    R_e = 0.31
    vx = 20.0 - 5.0 * t
    kappa = -np.clip((t - 0.05) * 1.5, 0.0, 0.3)
    omega = vx * (1.0 + kappa) / R_e
    vy = 0.6 * np.sin(2 * math.pi * 2.0 * t)
    Fz = 4000.0 + 800.0 * np.sin(2 * math.pi * 3.0 * t)
    T = 293.15 + 30.0 * (t > 0.2)
    mu = np.where((t > 0.25) & (t < 0.3), 0.6, 1.0)
    rng = np.random.default_rng(seed)
    vx = vx + 0.01 * rng.standard_normal(n)
    gamma = 0.03 * np.sin(2 * math.pi * 1.5 * t)
    return np.stack([vx, vy, omega, Fz, T, mu, gamma, np.zeros(n)])
