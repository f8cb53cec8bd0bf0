"""Quarter-car braking through the brush-tire FMU, driven step by step with fmpy.

This is the vehicle simulator's side of a co-simulation, the way a host drives the FMU:
instantiate once, then at every fixed communication step (1 ms by default)

1. **synchronize**: set the inputs ``vx = v``, ``vy = 0``, ``omega``, ``Fz = m g`` (the
   quarter car's static load), ``T_surface`` (ambient) and ``mu_scale``;
2. **advance** the FMU by one ``doStep`` and read ``Fx``, ``kappa``, ``mu_eff``,
   ``sliding_fraction``, ``dT_flash_max``, ``T_tread``;
3. integrate the quarter car over the step with that force held (explicit coupling).

The vehicle equations and parameters are those of :mod:`tire_brush.braking.quarter_car`
(``m v' = Fx``, ``J omega' = -R Fx - T_b``, ``T_b' = u``), with the FMU's rolling resistance
moment ``My`` (0 when its build has no rolling-resistance table, or for an FMU without the
output) acting on the wheel too: ``J omega' = -R Fx - T_b - My`` (``My`` in the brush's adapted
SAE axes, positive against forward rolling); the brake controller is any
:class:`tire_brush.braking.abs_control.BrakeController` (the rule-based ABS, a locked wheel, or
the open-loop :class:`~tire_brush.braking.abs_control.TorqueRamp`), sampled every
``control_period`` (a whole number of communication steps) with the torque rate held in
between, exactly as :func:`tire_brush.braking.simulation.simulate_braking` does on the steady
force map. This module holds no tire physics: the force comes from the FMU alone.

Integration of the vehicle over a step ``h`` (semi-implicit Euler, first order in ``h``, as
co-simulation with zero-order-hold coupling is):

* ``T_b`` follows the commanded rate and is clamped to ``[0, T_b,max]``; the wheel sees the
  step's mean brake torque;
* ``v`` and ``omega`` advance by one explicit step of the quarter car's right-hand side
  (:func:`tire_brush.braking.quarter_car.rhs`, with ``Fx / Fz`` from the FMU); the distance
  uses the mean of the old and new speed;
* a spin that would turn negative is set to zero: the brake is a friction torque that holds a
  stopped wheel and never drives it backwards. A locked wheel therefore stays at
  ``omega = 0`` while the brake torque exceeds the tire torque (as in
  :func:`tire_brush.braking.simulation.simulate_braking`).

The stop ends when ``v`` reaches ``v_stop``; distance and time are interpolated linearly in
``v`` within the last step (as the steady-map simulation does).

Tread temperature: with ``thermal="vehicle"`` (default) the FMU's lumped tread-temperature
parameters are set from the quarter car's :class:`~tire_brush.braking.quarter_car.ThermalParams`
(heat capacity, cooling conductance, heat fraction; thermal state off when the car has none),
so that the FMU run and the steady-map run share the tread-temperature equation
``C dT/dt = eta P_fric - G (T - T_ambient)``; ``thermal="fmu"`` keeps the FMU's own tire
parameters.

The braking study's FMU simulator factory is :func:`braking_simulator`, handed to
:func:`tire_brush.braking.study.run_study` by ``tirefric abs`` (:mod:`fmu_src.host.abs_cli`)
and the demo: it builds the FMU of a tire and grid once into a work folder and returns a
picklable :class:`FmuBrakingSimulator`.
"""

from __future__ import annotations

import hashlib
import json
import math
import shutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np

from tire_brush.braking.abs_control import BrakeController
from tire_brush.braking.quarter_car import QuarterCar
from tire_brush.braking.quarter_car import rhs as quarter_car_rhs
from tirefric.errors import ConvergenceError, InputError, TirefricError

#: The FMU inputs this straight-line quarter car drives, by name, in the order of its value
#: lists (a selection, not the tire's input list: camber and water keep their start values,
#: and an input added to the tire's table needs no change here).
INPUT_NAMES = ("vx", "vy", "omega", "Fz", "T_surface", "mu_scale")
#: FMU outputs read after every step.
OUTPUT_NAMES = ("Fx", "kappa", "mu_eff", "sliding_fraction", "dT_flash_max", "T_tread")
#: FMU parameters set from the quarter car's thermal model (``thermal="vehicle"``).
THERMAL_PARAMETERS = ("tire.thermal.enabled", "tire.thermal.heat_capacity",
                      "tire.thermal.conductance", "tire.thermal.heat_fraction")


class CosimError(TirefricError, RuntimeError):
    """The FMU refused a step or reported a failure during the co-simulation."""


@dataclass(frozen=True)
class CosimSettings:
    """Communication and FMU settings of a co-simulated stop.

    Attributes
    ----------
    step : float
        Communication step [s] (fixed). The controller period must be a whole multiple.
    t_max : float
        Simulated time limit [s]; a run that has not reached ``v_stop`` by then ends there
        (``CosimResult.stopped`` is False).
    record_every : int
        Keep every n-th step in the histories (the last point is always kept).
    parameters : dict
        FMU parameter start values by FMI name, set before initialisation (e.g.
        ``{"dt_internal": 1e-5, "n_elements": 100}``); the thermal parameters of
        ``thermal="vehicle"`` are set after these.
    thermal : {"vehicle", "fmu"}
        Tread-temperature parameters from the quarter car (module docstring) or the FMU's own.
    """

    step: float = 1e-3
    t_max: float = 60.0
    record_every: int = 1
    parameters: Mapping[str, float | int | bool] = field(default_factory=dict)
    thermal: Literal["vehicle", "fmu"] = "vehicle"

    def __post_init__(self) -> None:
        if not (isinstance(self.step, int | float) and math.isfinite(self.step)
                and 0 < self.step <= 0.01):
            raise InputError("must be in (0, 0.01] s", field="cosim.step", value=self.step)
        if not (isinstance(self.t_max, int | float) and math.isfinite(self.t_max)
                and self.t_max > 0):
            raise InputError("must be a finite time > 0 s", field="cosim.t_max",
                             value=self.t_max)
        if isinstance(self.record_every, bool) or not isinstance(self.record_every, int) or \
                self.record_every < 1:
            raise InputError("must be an integer >= 1", field="cosim.record_every",
                             value=self.record_every)
        if self.thermal not in ("vehicle", "fmu"):
            raise InputError("must be 'vehicle' or 'fmu'", field="cosim.thermal",
                             value=self.thermal)
        object.__setattr__(self, "parameters", dict(self.parameters))


@dataclass(frozen=True)
class CosimResult:
    """Histories of a co-simulated stop (one point per recorded communication step: the
    state at the end of the step; the first point is the initial state, the last point is
    at ``v_stop`` when the car stopped).

    Attributes
    ----------
    t, x, v, omega : numpy.ndarray
        Time [s], distance [m], vehicle speed [m/s], wheel spin [rad/s].
    wheel_speed : numpy.ndarray
        Peripheral wheel speed ``omega R`` [m/s].
    brake_torque : numpy.ndarray
        Brake torque [N m].
    kappa : numpy.ndarray
        Slip ``(omega R - v) / v`` [1] of the vehicle state (negative in braking).
    Fx : numpy.ndarray
        Longitudinal tire force from the FMU [N] (the force of the step ending at ``t``).
    mu : numpy.ndarray
        ``Fx / Fz`` [1] (negative in braking; the steady-map simulation's ``mu``).
    mu_eff, sliding_fraction, dT_flash_max, T_tread : numpy.ndarray
        FMU outputs: utilised friction |F|/Fz [1], sliding share of the patch [1], largest
        flash-temperature rise [K], tread temperature [K].
    phase : numpy.ndarray
        Controller phase code (:data:`tire_brush.braking.abs_control.PHASES`).
    stopping_distance : float
        Distance from ``v0`` to ``v_stop`` [m] (NaN if the car did not stop within t_max).
    stop_time : float
        Time to reach ``v_stop`` [s] (NaN likewise).
    stopped : bool
        Whether ``v_stop`` was reached.
    dt : float
        Communication step [s].
    fmu : dict
        GUID, model name, build id (if the FMU has one) and the parameters set.
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    omega: np.ndarray
    wheel_speed: np.ndarray
    brake_torque: np.ndarray
    kappa: np.ndarray
    Fx: np.ndarray
    mu: np.ndarray
    mu_eff: np.ndarray
    sliding_fraction: np.ndarray
    dT_flash_max: np.ndarray
    T_tread: np.ndarray
    phase: np.ndarray
    stopping_distance: float
    stop_time: float
    stopped: bool
    dt: float
    fmu: dict = field(default_factory=dict)

    #: Names of the time histories (arrays), in column order.
    HISTORIES = ("t", "x", "v", "omega", "wheel_speed", "brake_torque", "kappa", "Fx", "mu",
                 "mu_eff", "sliding_fraction", "dT_flash_max", "T_tread", "phase")

    def histories(self) -> dict[str, np.ndarray]:
        """The time histories by name (SI units)."""
        return {k: getattr(self, k) for k in self.HISTORIES}


def _start_values(md: Any, car: QuarterCar, settings: CosimSettings) -> dict[str, Any]:
    """FMU parameters to set before initialisation (user values, then the thermal ones)."""
    names = {v.name for v in md.modelVariables if v.causality == "parameter"}
    values = dict(settings.parameters)
    if settings.thermal == "vehicle":
        th = car.thermal
        values["tire.thermal.enabled"] = th is not None
        if th is not None:
            values.update({"tire.thermal.heat_capacity": th.heat_capacity,
                           "tire.thermal.conductance": th.cooling,
                           "tire.thermal.heat_fraction": th.heat_fraction})
    unknown = sorted(set(values) - names)
    if unknown:
        raise InputError(f"the FMU has no parameter(s) {', '.join(unknown)}",
                         field="cosim.parameters", value=unknown)
    return values


def _my_reader(md_vars: dict[str, Any], start: Mapping[str, Any]) -> tuple[int | None, float]:
    """Value reference of the FMU's ``My`` (None: no such output) and the factor taking it
    into the brush's adapted SAE axes (its ``axes`` parameter: ISO-W flips ``My``)."""
    if "My" not in md_vars:
        return None, 0.0
    axes = start.get("axes", md_vars["axes"].start if "axes" in md_vars else 0)
    return md_vars["My"].valueReference, -1.0 if int(axes) == 1 else 1.0


def _set(fmu: Any, md_vars: dict[str, Any], values: Mapping[str, Any]) -> None:
    for name, val in values.items():
        var = md_vars[name]
        if var.type == "Real":
            fmu.setReal([var.valueReference], [float(val)])
        elif var.type == "Integer":
            fmu.setInteger([var.valueReference], [int(val)])
        elif var.type == "Boolean":
            fmu.setBoolean([var.valueReference], [bool(val)])
        else:
            raise InputError("only Real, Integer and Boolean parameters can be set",
                             field="cosim.parameters", value=name)


def simulate_braking_fmu(
    fmu: str | Path,
    car: QuarterCar,
    controller: BrakeController,
    v0: float,
    T_ambient: float,
    *,
    v_stop: float = 1.0,
    settings: CosimSettings | None = None,
    brake_torque_initial: float = 0.0,
    mu_scale: float | Callable[[float], float] = 1.0,
    unzipdir: str | Path | None = None,
    instance_name: str = "quarter_car",
    water_depth: float = 0.0,
) -> CosimResult:
    """Brake the quarter car from ``v0`` with the tire force from the FMU (module docstring).

    Parameters
    ----------
    fmu
        A brush-tire FMU (``tirefric fmu build``).
    car
        Quarter car; its ``radius`` must equal the FMU's ``tire.R_e`` (the FMU computes the
        slip from it), its ``thermal`` sets the FMU's tread model (``settings.thermal``).
    controller
        Brake controller (reset at the start), e.g. ``RuleBasedABS``, ``LockedWheel``,
        ``TorqueRamp``; its ``control_period`` must be a whole number of communication steps.
    v0
        Initial speed [m/s] (> ``v_stop``); the wheel starts free rolling (``omega = v0/R``).
    T_ambient
        Road/ambient temperature [K]: the FMU's ``T_surface`` and the initial tread
        temperature.
    v_stop
        End speed [m/s] (> 0; slip is singular at standstill).
    settings
        Communication step, time limit, FMU parameters.
    brake_torque_initial
        Brake torque at t = 0 [N m].
    mu_scale
        Road friction scale [1] (FMU input): a number, or a function of the travelled
        distance [m] such as :class:`tire_brush.braking.road.MuProfile` (a road whose friction
        changes along the stop), read at the start of each communication step.
    unzipdir
        An already extracted copy of the FMU (shared between runs); default: extract into a
        temporary folder, removed afterwards.
    instance_name
        FMI instance name.
    water_depth
        Water on the road [m] (FMU input ``water_depth``, held over the stop; read by an FMU
        whose grid has a wet branch).

    Returns
    -------
    CosimResult

    Raises
    ------
    InputError
        Inconsistent inputs (radius, controller period, speeds, unknown FMU parameters).
    CosimError
        The FMU discarded a step or flagged a model reset.
    """
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    settings = settings or CosimSettings()
    h = float(settings.step)
    if not (math.isfinite(v0) and math.isfinite(v_stop) and v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    if not (math.isfinite(T_ambient) and T_ambient > 0):
        raise InputError("must be a temperature > 0 K", field="T_ambient", value=T_ambient)
    if not 0.0 <= brake_torque_initial <= car.brake_torque_max:
        raise InputError("initial brake torque outside [0, brake_torque_max]",
                         field="brake_torque_initial", value=brake_torque_initial)
    n_ctrl = round(controller.control_period / h)
    if n_ctrl < 1 or abs(n_ctrl * h - controller.control_period) > 1e-9 * max(1.0, n_ctrl):
        raise InputError(f"the controller period must be a whole number of communication "
                         f"steps of {h:g} s", field="controller.control_period",
                         value=controller.control_period)

    md = fmpy.read_model_description(str(fmu))
    md_vars = {v.name: v for v in md.modelVariables}
    missing = [n for n in (*INPUT_NAMES, *OUTPUT_NAMES, "tire.R_e") if n not in md_vars]
    if missing:
        raise InputError(f"not a brush-tire FMU: no variable(s) {', '.join(missing)}",
                         source=str(fmu))
    R_fmu = float(md_vars["tire.R_e"].start)
    start = _start_values(md, car, settings)
    R_e = float(start.get("tire.R_e", R_fmu))
    if abs(car.radius - R_e) > 1e-9 * R_e:
        raise InputError(f"the quarter car's radius must equal the FMU's tire.R_e = {R_e:g} m "
                         "(the FMU computes the slip from it)", field="radius",
                         value=car.radius)

    if water_depth and not (math.isfinite(water_depth) and water_depth > 0 and
                            "water_depth" in md_vars):
        raise InputError("needs a finite depth >= 0 m (> 0: an FMU with the input "
                         "water_depth)", field="water_depth", value=water_depth)

    own_dir = unzipdir is None
    unzip = fmpy.extract(str(fmu)) if own_dir else str(unzipdir)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                      modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=instance_name)
    vin = [md_vars[n].valueReference for n in INPUT_NAMES]
    vout = [md_vars[n].valueReference for n in OUTPUT_NAMES]
    status_vr = md_vars["input_status"].valueReference if "input_status" in md_vars else None
    my_vr, my_sign = _my_reader(md_vars, start)
    # the FMU gives the rolling resistance moment: the car's own coefficient is not added
    rhs_car = replace(car, rolling_resistance=0.0)
    R, Fz = car.radius, car.Fz
    Tmax = car.brake_torque_max
    try:
        slave.instantiate()
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        _set(slave, md_vars, start)
        if water_depth:
            slave.setReal([md_vars["water_depth"].valueReference], [float(water_depth)])
        x, v, omega, Tb, t = 0.0, float(v0), float(v0) / R, float(brake_torque_initial), 0.0
        road = mu_scale if callable(mu_scale) else (lambda _x: float(mu_scale))
        slave.setReal(vin, [v, 0.0, omega, Fz, float(T_ambient), float(road(x))])
        slave.exitInitializationMode()
        controller.reset()
        # the initial state: free rolling, undeflected tire
        y0 = dict(zip(OUTPUT_NAMES, slave.getReal(vout), strict=True))
        rows = [(t, x, v, omega, Tb, 0.0, *(y0[n] for n in OUTPUT_NAMES[1:]),
                 controller.phase)]
        u, phase = 0.0, controller.phase
        stopped = False
        k = 0
        n_max = math.ceil(settings.t_max / h - 1e-9)
        while k < n_max:
            if k % n_ctrl == 0:
                u = controller.torque_rate(t, v, omega, Tb)
                phase = controller.phase
            slave.setReal(vin, [v, 0.0, omega, Fz, float(T_ambient), float(road(x))])
            try:
                slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            except Exception as exc:   # fmpy raises FMICallException for fmi2Discard/Error
                raise CosimError(f"the FMU refused the step at t = {t:.6g} s (v = {v:.4g} "
                                 f"m/s, omega = {omega:.4g} rad/s): {exc}") from exc
            if status_vr is not None:
                flags = int(slave.getInteger([status_vr])[0])
                if flags & 64:
                    raise CosimError(f"the FMU reset its tire model at t = {t:.6g} s "
                                     "(input_status bit 64: the model failed in the step)")
            y = dict(zip(OUTPUT_NAMES, slave.getReal(vout), strict=True))
            Fx = y["Fx"]
            Tb_new = min(max(Tb + h * u, 0.0), Tmax)
            _, dv, domega, _, _ = quarter_car_rhs(rhs_car, Fx / Fz, v, omega,
                                                  0.5 * (Tb + Tb_new), u, y["T_tread"],
                                                  T_ambient)
            if my_vr is not None:     # rolling resistance on the wheel
                domega -= my_sign * slave.getReal([my_vr])[0] / car.wheel_inertia
            v_new = v + h * dv
            # the brake removes at most the spin there is: it holds a locked wheel
            omega_new = max(omega + h * domega, 0.0)
            x_new = x + 0.5 * h * (v + v_new)
            k += 1
            if v_new <= v_stop:
                s = (v - v_stop) / (v - v_new)
                t_stop = t + s * h
                x_stop = x + s * (x_new - x)
                omega_stop = omega + s * (omega_new - omega)
                Tb_stop = Tb + s * (Tb_new - Tb)
                rows.append((t_stop, x_stop, v_stop, omega_stop, Tb_stop, Fx,
                             *(y[n] for n in OUTPUT_NAMES[1:]), phase))
                stopped = True
                break
            t, x, v, omega, Tb = k * h, x_new, v_new, omega_new, Tb_new
            if k % settings.record_every == 0 or k == n_max:
                rows.append((t, x, v, omega, Tb, Fx, *(y[n] for n in OUTPUT_NAMES[1:]),
                             phase))
        slave.terminate()
    finally:
        slave.freeInstance()
        if own_dir:
            shutil.rmtree(unzip, ignore_errors=True)

    arr = np.array(rows, dtype=float)
    t_, x_, v_, w_, Tb_, Fx_ = (arr[:, i] for i in range(6))
    cols = {n: arr[:, 6 + i] for i, n in enumerate(OUTPUT_NAMES[1:])}
    kappa = (w_ * R - v_) / v_
    info = {"guid": md.guid, "model_name": md.modelName, "parameters": dict(start),
            "step_s": h}
    build_id = md_vars.get("info.build_id")
    if build_id is not None:
        info["build_id"] = build_id.start
    return CosimResult(
        t=t_, x=x_, v=v_, omega=w_, wheel_speed=w_ * R, brake_torque=Tb_, kappa=kappa,
        Fx=Fx_, mu=Fx_ / Fz, mu_eff=cols["mu_eff"], sliding_fraction=cols["sliding_fraction"],
        dT_flash_max=cols["dT_flash_max"], T_tread=cols["T_tread"],
        phase=arr[:, -1].astype(int),
        stopping_distance=float(x_[-1]) if stopped else math.nan,
        stop_time=float(t_[-1]) if stopped else math.nan, stopped=stopped, dt=h, fmu=info)


# -- two-track car: one FMU instance per wheel ----------------------------------------------
def simulate_two_track_fmu(
    fmu: str | Path,
    car: Any,
    controllers: Any,
    v0: float,
    T_ambient: float,
    *,
    v_stop: float = 1.0,
    settings: CosimSettings | None = None,
    road_left: Callable[[float], float] | None = None,
    road_right: Callable[[float], float] | None = None,
    unzipdir: str | Path | None = None,
) -> Any:
    """Brake the four-wheel car of :mod:`tire_brush.braking.two_axle` with four FMU instances.

    The vehicle side of :func:`tire_brush.braking.two_axle.simulate_two_track` (same car,
    controllers per wheel in the order FL, FR, RL, RR, left and right roads as the FMUs'
    ``mu_scale``), the tire forces from one instance of the brush-tire FMU per wheel. At every
    communication step each instance gets its wheel's speed, spin, load and road factor, one
    ``doStep`` gives its ``Fx``; the car and the wheels then advance as in
    :func:`simulate_braking_fmu` (explicit coupling). The loads of a step are those of the
    previous step's deceleration (the transfer lags one step, 1 ms: the load changes by
    ``m h da / (2 L)`` per step, a few N). The tread is isothermal (the FMUs' thermal state
    off), as in the map model.

    Returns a :class:`tire_brush.braking.two_axle.TwoTrackResult` (``mu`` is ``Fx / Fz`` on
    that road).

    Raises
    ------
    InputError
        Inconsistent inputs (radius vs the FMU's ``tire.R_e``, controller periods, speeds).
    CosimError
        An FMU refused a step or reset its model; ``ConvergenceError`` when the car does not
        reach ``v_stop`` within ``settings.t_max``.
    """
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    from tire_brush.braking.two_axle import (
        WHEELS,
        TwoTrackResult,
        wheel_load_split,
        yaw_moment,
    )

    settings = settings or CosimSettings()
    h = float(settings.step)
    controllers = tuple(controllers)
    if len(controllers) != 4:
        raise InputError("need four controllers (FL, FR, RL, RR)", field="controllers",
                         value=len(controllers))
    if not (math.isfinite(v0) and math.isfinite(v_stop) and v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    n_ctrl = []
    for c in controllers:
        n = round(c.control_period / h)
        if n < 1 or abs(n * h - c.control_period) > 1e-9 * max(1.0, n):
            raise InputError(f"the controller period must be a whole number of communication "
                             f"steps of {h:g} s", field="controller.control_period",
                             value=c.control_period)
        n_ctrl.append(n)
    md = fmpy.read_model_description(str(fmu))
    md_vars = {v.name: v for v in md.modelVariables}
    missing = [n for n in (*INPUT_NAMES, *OUTPUT_NAMES, "tire.R_e") if n not in md_vars]
    if missing:
        raise InputError(f"not a brush-tire FMU: no variable(s) {', '.join(missing)}",
                         source=str(fmu))
    start = dict(settings.parameters)
    if settings.thermal == "vehicle":
        start["tire.thermal.enabled"] = False
    unknown = sorted(set(start) - {v.name for v in md.modelVariables
                                   if v.causality == "parameter"})
    if unknown:
        raise InputError(f"the FMU has no parameter(s) {', '.join(unknown)}",
                         field="cosim.parameters", value=unknown)
    R_e = float(start.get("tire.R_e", md_vars["tire.R_e"].start))
    if abs(car.radius - R_e) > 1e-9 * R_e:
        raise InputError(f"the car's radius must equal the FMU's tire.R_e = {R_e:g} m",
                         field="radius", value=car.radius)
    R, J, m = car.radius, car.wheel_inertia, car.mass
    phi = car.brake_balance
    cap = car.brake_torque_max / 2.0 * np.array([phi, phi, 1.0 - phi, 1.0 - phi])

    def factors(x: float) -> np.ndarray:
        fl = 1.0 if road_left is None else float(road_left(x))
        fr = 1.0 if road_right is None else float(road_right(x))
        return np.array([fl, fr, fl, fr])

    own_dir = unzipdir is None
    unzip = fmpy.extract(str(fmu)) if own_dir else str(unzipdir)
    vin = [md_vars[n].valueReference for n in INPUT_NAMES]
    vr_fx = md_vars["Fx"].valueReference
    status_vr = md_vars["input_status"].valueReference if "input_status" in md_vars else None
    my_vr, my_sign = _my_reader(md_vars, start)
    My = np.zeros(4)
    slaves = []
    try:
        x, v, a, t = 0.0, float(v0), 0.0, 0.0
        w = np.full(4, v / R)
        Tb = np.zeros(4)
        Fz = wheel_load_split(car, 0.0)
        f = factors(0.0)
        for name in WHEELS:
            sl = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                           modelIdentifier=md.coSimulation.modelIdentifier,
                           instanceName=f"wheel_{name}")
            slaves.append(sl)
            sl.instantiate()
            sl.setupExperiment(startTime=0.0)
            sl.enterInitializationMode()
            _set(sl, md_vars, start)
        for i, sl in enumerate(slaves):
            sl.setReal(vin, [v, 0.0, float(w[i]), float(Fz[i]), float(T_ambient), float(f[i])])
            sl.exitInitializationMode()
        for c in controllers:
            c.reset()
        u = np.zeros(4)
        Fx = np.zeros(4)
        rows = [np.concatenate(([t, x, v, a], w, Tb, (w * R - v) / v, Fx / Fz, Fz, f))]
        n_max = math.ceil(settings.t_max / h - 1e-9)
        k = 0
        while k < n_max:
            for i, c in enumerate(controllers):
                if k % n_ctrl[i] == 0:
                    u[i] = c.torque_rate(t, v, float(w[i]), float(Tb[i]))
            Fz = wheel_load_split(car, a)
            f = factors(x)
            for i, sl in enumerate(slaves):
                sl.setReal(vin, [v, 0.0, float(w[i]), float(Fz[i]), float(T_ambient),
                                 float(f[i])])
                try:
                    sl.doStep(currentCommunicationPoint=t, communicationStepSize=h)
                except Exception as exc:
                    raise CosimError(f"the FMU of wheel {WHEELS[i]} refused the step at t = "
                                     f"{t:.6g} s: {exc}") from exc
                if status_vr is not None and int(sl.getInteger([status_vr])[0]) & 64:
                    raise CosimError(f"the FMU of wheel {WHEELS[i]} reset its tire model at "
                                     f"t = {t:.6g} s")
                Fx[i] = sl.getReal([vr_fx])[0]
                if my_vr is not None:     # rolling resistance on the wheel
                    My[i] = my_sign * sl.getReal([my_vr])[0]
            Tb_new = np.clip(Tb + h * u, 0.0, cap)
            a = float(np.sum(Fx)) / m
            v_new = v + h * a
            w_new = np.maximum(w + h * (-R * Fx - 0.5 * (Tb + Tb_new) - My) / J, 0.0)
            x_new = x + 0.5 * h * (v + v_new)
            k += 1
            if v_new <= v_stop:
                s_ = (v - v_stop) / (v - v_new)
                x_s, w_s = x + s_ * (x_new - x), w + s_ * (w_new - w)
                Tb_s = Tb + s_ * (Tb_new - Tb)
                rows.append(np.concatenate(([t + s_ * h, x_s, v_stop, a], w_s, Tb_s,
                                            (w_s * R - v_stop) / v_stop, Fx / Fz, Fz, f)))
                break
            t, x, v, w, Tb = k * h, x_new, v_new, w_new, Tb_new
            rows.append(np.concatenate(([t, x, v, a], w, Tb, (w * R - v) / v, Fx / Fz, Fz, f)))
        else:
            raise ConvergenceError(f"the car did not reach {v_stop:g} m/s within "
                                   f"{settings.t_max:g} s through the FMUs (v = {v:.3g} m/s)")
        for sl in slaves:
            sl.terminate()
    finally:
        for sl in slaves:
            sl.freeInstance()
        if own_dir:
            shutil.rmtree(unzip, ignore_errors=True)
    arr = np.array(rows)
    Fx_h = arr[:, 16:20] * arr[:, 20:24]
    return TwoTrackResult(
        t=arr[:, 0], x=arr[:, 1], v=arr[:, 2], a=arr[:, 3], omega=arr[:, 4:8],
        brake_torque=arr[:, 8:12], kappa=arr[:, 12:16], mu=arr[:, 16:20], Fz=arr[:, 20:24],
        Fx=Fx_h, road=arr[:, 24:28], yaw_moment=yaw_moment(car.track, Fx_h),
        stopping_distance=float(arr[-1, 1]), stop_time=float(arr[-1, 0]))


# -- study plug-in ---------------------------------------------------------------------------
@dataclass(frozen=True)
class FmuBrakingSimulator:
    """A built FMU and the co-simulation settings: the braking simulator a study calls per
    case (picklable, so that cases can run as Dask tasks).

    Attributes
    ----------
    fmu : str
        The FMU file.
    settings : CosimSettings
        Communication step and FMU parameters.
    """

    fmu: str
    settings: CosimSettings = field(default_factory=CosimSettings)

    @property
    def label(self) -> str:
        """Short description for the results' provenance."""
        return f"brush-tire FMU {Path(self.fmu).name} through fmpy"

    def __call__(self, car: QuarterCar, controller: BrakeController, v0: float,
                 v_stop: float, T_ambient: float, *,
                 brake_torque_initial: float = 0.0) -> CosimResult:
        """One stop (:func:`simulate_braking_fmu`); the car must reach ``v_stop``."""
        res = simulate_braking_fmu(self.fmu, car, controller, v0, T_ambient, v_stop=v_stop,
                                   settings=self.settings,
                                   brake_torque_initial=brake_torque_initial)
        if not res.stopped:
            raise ConvergenceError(f"the car did not reach {v_stop:g} m/s within "
                                   f"{self.settings.t_max:g} s through the FMU "
                                   f"(v = {res.v[-1]:.3g} m/s)")
        return res

    def two_track(self, car: Any, controllers: Any, v0: float, v_stop: float,
                  T_ambient: float, *, road_left: Callable[[float], float] | None = None,
                  road_right: Callable[[float], float] | None = None) -> Any:
        """One stop of the four-wheel car (:func:`simulate_two_track_fmu`, one FMU instance
        per wheel) with this simulator's settings."""
        return simulate_two_track_fmu(self.fmu, car, controllers, v0, T_ambient,
                                      v_stop=v_stop, settings=self.settings,
                                      road_left=road_left, road_right=road_right)


def braking_simulator(tire: str | Path, grid: str | Path, work_dir: str | Path,
                      options: Mapping[str, Any] | None = None) -> FmuBrakingSimulator:
    """The braking study's FMU simulator factory: build the FMU once, return the
    simulator.

    The FMU of ``tire`` on ``grid`` (names or files, as ``tirefric fmu build`` takes them)
    is built into ``work_dir`` as ``BrushTire_<tire>_<key>.fmu`` unless a file of that name
    exists: ``key`` hashes the tire and grid files' contents, so a changed input gives a new
    build and an unchanged one is reused.

    Parameters
    ----------
    tire, grid
        Tire and grid (``tirefric fmu build --tire ... --grid ...``).
    work_dir
        Folder for the FMU (created).
    options
        Co-simulation settings: ``step`` [s], ``t_max`` [s], ``thermal``
        (``"vehicle"``/``"fmu"``) and FMU parameter start values by name (``n_elements``,
        ``dt_internal``, ...).
    """
    from fmu_src.make.build import build_fmu
    from lookup.grid import load_grid
    from tire_brush.params import load_tire

    opts = dict(options or {})
    kw = {k: opts.pop(k) for k in ("step", "t_max", "thermal") if k in opts}
    settings = CosimSettings(parameters=opts, **kw)
    tire_p = load_tire(tire)
    grid_o = load_grid(grid)
    key = hashlib.sha256(json.dumps({"tire": _file_digest(tire_p.source) or str(tire),
                                     "grid": grid_o.hash}, sort_keys=True).encode())
    work = Path(work_dir)
    work.mkdir(parents=True, exist_ok=True)
    path = work / f"BrushTire_{tire_p.name}_{key.hexdigest()[:12]}.fmu"
    if not path.is_file():
        build_fmu(tire_p, grid_o, path)
    return FmuBrakingSimulator(str(path), settings)


def _file_digest(path: Any) -> str:
    try:
        return hashlib.sha256(Path(str(path)).read_bytes()).hexdigest()
    except (OSError, TypeError):
        return ""


# -- demo manoeuvre --------------------------------------------------------------------------
def demo_manoeuvre(fmu: str | Path, out_dir: str | Path, *, v0: float = 100.0 / 3.6,
                   T_ambient: float = 293.15,
                   settings: CosimSettings | None = None) -> tuple[list[Path], dict[str, Any]]:
    """Straight-line stops of the shipped passenger quarter car through the FMU (``tirefric
    demo``): the rule-based ABS and a locked wheel from ``v0`` [m/s] at ``T_ambient`` [K].

    Writes ``quarter_car_fmu.png`` (speed and wheel speed, slip, braking friction and brake
    torque, flash-temperature rise and tread temperature, both stops) into ``out_dir``.

    Returns
    -------
    figures, numbers
        The plot's path in a list; stopping distances [m], stop times [s], peak flash
        temperature rise [K], tread temperature rise [K], distance-weighted mean slip [1]
        per stop, and the wall time per communication step [s].
    """
    import time

    from tire_brush.braking.abs_control import ABSParams, LockedWheel, RuleBasedABS
    from tire_brush.braking.quarter_car import load_quarter_car
    from tirefric.paths import models_dir

    settings = settings or CosimSettings()      # the FMU's own (converged) defaults
    car = load_quarter_car(models_dir() / "studies" / "vehicles" / "passenger.toml")
    runs: dict[str, CosimResult] = {}
    numbers: dict[str, Any] = {"v0_m_per_s": v0, "T_ambient_K": T_ambient,
                               "fmu_parameters": dict(settings.parameters),
                               "step_s": settings.step}
    wall, steps = 0.0, 0
    for name, ctrl in (("abs", RuleBasedABS(ABSParams(), car.radius,
                                            car.brake_torque_rate_max)),
                       ("locked", LockedWheel(car.brake_torque_rate_max))):
        t0 = time.perf_counter()
        res = simulate_braking_fmu(fmu, car, ctrl, v0, T_ambient, settings=settings)
        wall += time.perf_counter() - t0
        steps += res.t.size
        runs[name] = res
        dx = np.diff(res.x)
        numbers[name] = {
            "stopping_distance_m": res.stopping_distance, "stop_time_s": res.stop_time,
            "dT_flash_max_K": float(res.dT_flash_max.max()),
            "T_tread_rise_K": float(res.T_tread.max() - T_ambient),
            "mean_slip": float(np.sum(0.5 * (res.kappa[1:] + res.kappa[:-1]) * dx)
                               / np.sum(dx))}
    numbers["wall_time_per_step_s"] = wall / max(steps, 1)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "quarter_car_fmu.png"
    _plot_stops(runs, path, f"Passenger quarter car through the brush-tire FMU from "
                            f"{3.6 * v0:.0f} km/h at {T_ambient - 273.15:.0f} C")
    return [path], numbers


def _plot_stops(runs: Mapping[str, CosimResult], path: Path, title: str) -> Path:
    """Time histories of co-simulated stops (matplotlib's object API, no pyplot state)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 10), layout="constrained")
    ax = fig.subplots(4, 1, sharex=True)
    tb, tt = ax[2].twinx(), ax[3].twinx()
    labels = {"abs": "rule-based ABS", "locked": "locked wheel"}
    for i, (name, r) in enumerate(runs.items()):
        col = f"C{i}"
        lab = f"{labels.get(name, name)}: {r.stopping_distance:.2f} m"
        ax[0].plot(r.t, r.v, color=col, label=lab)
        ax[0].plot(r.t, r.wheel_speed, color=col, ls=":", lw=0.8)
        ax[1].plot(r.t, -r.kappa, color=col, lw=0.9)
        ax[2].plot(r.t, -r.mu, color=col, lw=0.9)
        tb.plot(r.t, r.brake_torque, color=col, ls="--", lw=0.6)
        ax[3].plot(r.t, r.dT_flash_max, color=col, lw=0.8)
        tt.plot(r.t, r.T_tread - 273.15, color=col, ls="--", lw=1.2)
    ax[0].set_ylabel("v, omega R (dotted) [m/s]")
    ax[0].legend(fontsize=8)
    ax[1].set_ylabel("braking slip -kappa [1]")
    ax[1].set_ylim(0, 1.05)
    ax[2].set_ylabel("braking friction -Fx/Fz [1]")
    tb.set_ylabel("brake torque (dashed) [N m]")
    ax[3].set_ylabel("flash temperature rise dT_flash_max [K]")
    tt.set_ylabel("tread temperature (dashed) [C]")
    ax[3].set_xlabel("time t [s]")
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=110)
    return path
