"""What a braking study produces: the trajectory record of a stop and a case's results.

:class:`Trajectory` is the one record of a stop's time histories; the optimal control
(:class:`.ocp.OCPResult`), the simulated strategies (:class:`.simulation.SimResult`) and the
two-axle and two-track cars (:class:`.two_axle.TwoAxleResult`,
:class:`.two_axle.TwoTrackResult`) extend it with what only they have. :class:`CaseResult`
holds everything one case of a study produced (numbers for the table, trajectories for the
plots), :class:`CaseFailure` a case that failed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .force_map import ForceMap
from .friction import Case
from .slip_map import SlipMap


@dataclass(frozen=True, kw_only=True)
class Trajectory:
    """A stop's time histories (recorded points; the last one is at the end speed).

    Attributes
    ----------
    t, x, v : numpy.ndarray
        Time [s], distance [m], speed [m/s].
    omega, brake_torque, kappa, mu : numpy.ndarray
        Wheel spin [rad/s], brake torque [N m], slip [1], force ratio Fx/Fz [1]; one column
        per wheel where the car has several.
    stopping_distance : float
        Distance from the initial to the end speed [m].
    stop_time : float
        Time to reach the end speed [s].
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    omega: np.ndarray
    brake_torque: np.ndarray
    kappa: np.ndarray
    mu: np.ndarray
    stopping_distance: float
    stop_time: float


@dataclass(frozen=True)
class CaseResult:
    """Everything a case produced (numbers for the table, trajectories for the plots)."""

    case: Case
    summary: dict[str, Any]
    ocp: Trajectory
    abs_sim: Trajectory
    locked: Trajectory
    slip_map: SlipMap
    force_map: ForceMap
    provenance: dict[str, Any]
    abs_fmu: Trajectory | None = None
    abs_realistic: Trajectory | None = None
    #: the global optimum of the stop with a quasi-steady wheel (:mod:`.thermal_dp`): ``t``,
    #: ``x``, ``v``, ``T_tread``, ``kappa``, ``mu`` along it
    slip_dp: dict[str, Any] | None = None


@dataclass
class CaseFailure:
    """A case that failed: its error, reported while the study goes on (the other cases'
    results are still written; ``results.json`` lists the failures under ``failed``)."""

    case: Case
    error: str
