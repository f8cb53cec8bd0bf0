"""Braking studies: force maps -> CasADi optimal control, optimal slip maps, rule-based ABS.

Modules (imports stay lazy for scipy/casadi/matplotlib where they are heavy):

- :mod:`.reference`: Burckhardt and Magic Formula mu(kappa), the point-mass stopping bound.
- :mod:`.force_map`: tabulated Fx/Fz(kappa, vx, Fz, T) as a tensor B-spline and a CasADi
  function.
- :mod:`.quarter_car`: quarter-car parameters and equations of motion.
- :mod:`.ocp`: minimum-stopping-distance optimal control (direct collocation, IPOPT).
- :mod:`.slip_map`: slip of maximum braking force vs speed, load, temperature; CSV export.
- :mod:`.abs_control`, :mod:`.simulation`: rule-based ABS, locked wheel, torque ramp,
  fixed-step simulation.
- :mod:`.friction`: friction sources (analytic curves; the brush tire on a grid).
- :mod:`.study`, :mod:`.cli`: study runner and ``tirefric abs study``.
"""

from .abs_control import (
    ABSParams,
    HydraulicsParams,
    LockedWheel,
    RealisticABS,
    RuleBasedABS,
    TorqueRamp,
)
from .force_map import ForceMap, default_axes
from .friction import Case, FrictionSource, make_friction_source, register_friction_source
from .ocp import OCPResult, OCPSettings, solve_braking_ocp
from .quarter_car import (
    QuarterCar,
    ThermalParams,
    load_quarter_car,
    tread_temperature_rise_bound,
)
from .reference import Burckhardt, MagicFormula, point_mass_stopping_distance
from .road import MuProfile
from .simulation import SimResult, SimSettings, simulate_braking
from .slip_map import SlipMap, optimal_slip

__all__ = [
    "ABSParams", "Burckhardt", "Case", "ForceMap", "FrictionSource", "HydraulicsParams",
    "LockedWheel", "MagicFormula", "MuProfile", "OCPResult", "OCPSettings", "QuarterCar",
    "RealisticABS", "RuleBasedABS", "SimResult",
    "SimSettings", "SlipMap", "ThermalParams", "TorqueRamp", "default_axes",
    "load_quarter_car", "make_friction_source", "optimal_slip",
    "point_mass_stopping_distance", "register_friction_source", "simulate_braking",
    "solve_braking_ocp", "tread_temperature_rise_bound",
]
