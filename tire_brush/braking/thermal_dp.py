"""Globally optimal slip with a heating tread: dynamic programming over speed and temperature.

The OCP of :mod:`.ocp` finds local optima, and on a rough friction map (a glassy compound's
stick-slip ripples, docs/physics.md sec. 7) it has many. This module solves a *relaxation* of
the same stop globally, and from it a lower bound that knows how the tread heats.

Relaxation (quasi-steady wheel)
    The slip ``kappa(t)`` is chosen freely in ``[kappa_lo, 0)`` at every instant: the wheel's
    inertia and the brake torque's rate limit are dropped, everything else is the quarter car
    of :mod:`.quarter_car`:

    * ``m v' = Fz mu(kappa, v, Fz, T)`` (``mu < 0`` braking),
    * ``C T' = eta Fz mu kappa v - G (T - T_amb)`` (the sliding power ``Fx (omega R - v)``
      with ``omega R - v = kappa v``).

    Every slip history of the full model is admissible here, so no stop of the full model is
    shorter than the relaxation's optimum.

Dynamic programming (Bellman 1957)
    With the speed as the independent variable (it falls monotonically while ``mu < 0``), the
    least distance ``J(v, T)`` still to go from speed ``v`` at tread temperature ``T`` obeys,
    over a speed step ``dv``,

        ``J(v + dv, T) = min_kappa [ v_m dt + J(v, T + T' dt) ]``,  ``dt = m dv / (Fz |mu|)``,

    with ``J(v_stop, T) = 0``, ``v_m`` the step's mid speed and the friction at ``(v_m, T)``;
    ``J`` is interpolated linearly in ``T``. The minimum over a grid of candidate slips is
    global for the discretised problem: every local optimum of the map is compared. The
    error of the recursion is of first order in the step sizes; :func:`slip_dp` is solved at
    two resolutions and the difference is reported (``resolution_error``).

    Coasting (``mu = 0``) has no speed step. It cannot pay as long as cooling the tread is
    worth less than the distance it costs, ``J_T G (T - T_amb) / C <= v`` (the
    Hamilton-Jacobi-Bellman inequality of the coasting control), checked on the grid
    (``coast_ratio``: its largest left-hand over right-hand side; <= 1 means coasting never
    pays).

Lower bound with the brake's build-up (:func:`thermal_ramp_bound`)
    Until time ``t1`` every stop keeps ``v(t) >= w(t)``, the speed limit of the brake impulse
    and the peak friction (:func:`.quarter_car.ramp_limited_stopping_distance`); by the time
    its speed is ``v`` its tread has warmed by at most ``eta m (v0^2 - v^2) / (2 C)`` (the
    sliding power ``|Fx| (-kappa) v <= |Fx| v`` integrates to at most the kinetic energy the
    car has lost; cooling only lowers it). So every stop covers at least
    ``int_0^t1 w dt + min J(v, T)`` over ``v >= w(t1)`` and those temperatures, for any
    ``t1``; the bound is the largest over ``t1``. Without the thermal
    state and with a speed-independent peak it is the ramp-limited bound itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tirefric.errors import InputError

from .force_map import ForceMap
from .quarter_car import QuarterCar, tread_temperature_rise_bound

#: Default resolution (speed steps, temperature nodes, candidate slips) of :func:`slip_dp`;
#: the bound is also solved at half of it to estimate the discretisation error.
RESOLUTION = (400, 161, 480)


def _weights(nodes: np.ndarray, q) -> tuple[np.ndarray, np.ndarray]:
    """Left node index and linear weight of the queries ``q`` (clamped to the nodes)."""
    q = np.clip(np.atleast_1d(np.asarray(q, dtype=float)), nodes[0], nodes[-1])
    if nodes.size == 1:
        return np.zeros(q.size, dtype=int), np.zeros(q.size)
    i = np.clip(np.searchsorted(nodes, q, side="right") - 1, 0, nodes.size - 2)
    return i, (q - nodes[i]) / (nodes[i + 1] - nodes[i])


@dataclass(frozen=True)
class SlipDP:
    """Solution of the dynamic programme of the module doc.

    Attributes
    ----------
    v : numpy.ndarray
        Speed nodes, ascending from ``v_stop`` to ``v0`` [m/s].
    T : numpy.ndarray
        Tread temperature nodes, from the ambient temperature up to the largest rise a stop
        can cause [K].
    kappa : numpy.ndarray
        Candidate slips [1].
    J : numpy.ndarray
        Least distance to ``v_stop`` from ``(v[i], T[j])``, shape ``(len(v), len(T))`` [m].
    policy : numpy.ndarray
        Optimal slip of the step from ``v[i + 1]`` to ``v[i]`` at ``T[j]``, shape
        ``(len(v) - 1, len(T))`` [1].
    coast_ratio : float
        Largest ``J_T G (T - T_amb) / (C v)`` on the grid (<= 1: coasting never pays).
    T_ambient : float
        Ambient (initial) tread temperature [K].
    """

    v: np.ndarray
    T: np.ndarray
    kappa: np.ndarray
    J: np.ndarray
    policy: np.ndarray
    coast_ratio: float
    T_ambient: float

    @property
    def distance(self) -> float:
        """Least distance from ``v0`` at the ambient temperature [m]."""
        return float(self.J[-1, 0])

    def values(self, v, T) -> np.ndarray:
        """``J`` [m] on the tensor grid of speeds ``v`` and temperatures ``T`` (1-D arrays),
        bilinear between the nodes and clamped to the grid; shape ``(len(v), len(T))``."""
        jT, sT = _weights(self.T, T)
        JT = self.J[:, jT] * (1.0 - sT) + self.J[:, np.minimum(jT + 1, self.T.size - 1)] * sT
        iv, sv = _weights(self.v, v)
        return JT[iv] * (1.0 - sv)[:, None] + JT[iv + 1] * sv[:, None]

    def values_at(self, v, T) -> np.ndarray:
        """``J`` [m] at the points ``(v[i], T[i])``, bilinear, clamped to the grid."""
        jT, sT = _weights(self.T, T)
        jT1 = np.minimum(jT + 1, self.T.size - 1)
        iv, sv = _weights(self.v, v)
        lo = self.J[iv, jT] * (1.0 - sT) + self.J[iv, jT1] * sT
        hi = self.J[iv + 1, jT] * (1.0 - sT) + self.J[iv + 1, jT1] * sT
        return lo * (1.0 - sv) + hi * sv

    def trajectory(self, car: QuarterCar, fmap: ForceMap) -> dict[str, np.ndarray]:
        """The optimal stop from ``v0`` at the ambient temperature, following the policy.

        Returns ``t`` [s], ``x`` [m], ``v`` [m/s], ``T_tread`` [K], ``kappa`` [1] and ``mu``
        [1] at the speed nodes, from ``v0`` down to ``v_stop`` (``kappa`` and ``mu`` of the
        step that starts there; the last repeats the one before).
        """
        th = car.thermal
        n = self.v.size
        t, x, T = [0.0], [0.0], [self.T_ambient]
        ks, mus = [], []
        for i in range(n - 2, -1, -1):
            Tc = T[-1]
            j = int(np.clip(np.searchsorted(self.T, Tc), 1, self.T.size - 1))
            j = j if Tc - self.T[j - 1] > self.T[j] - Tc else j - 1
            k = float(self.policy[i, j])
            vm = 0.5 * (self.v[i] + self.v[i + 1])
            mu = -float(fmap(k, vm, car.Fz, Tc))
            dt = car.mass * (self.v[i + 1] - self.v[i]) / (car.Fz * max(mu, 1e-9))
            dT = 0.0 if th is None else dt * (
                th.heat_fraction * mu * car.Fz * (-k) * vm
                - th.cooling * (Tc - self.T_ambient)) / th.heat_capacity
            ks.append(k)
            mus.append(-mu)
            t.append(t[-1] + dt)
            x.append(x[-1] + vm * dt)
            T.append(Tc + dT)
        ks.append(ks[-1])
        mus.append(mus[-1])
        return {"t": np.array(t), "x": np.array(x), "v": self.v[::-1].copy(),
                "T_tread": np.array(T), "kappa": np.array(ks), "mu": np.array(mus)}


def slip_dp(car: QuarterCar, fmap: ForceMap, v0: float, v_stop: float, T_ambient: float, *,
            kappa_lo: float = -1.0, resolution: tuple[int, int, int] = RESOLUTION,
            kappa: np.ndarray | None = None) -> SlipDP:
    """The dynamic programme of the module doc on ``fmap`` at the car's load.

    Parameters
    ----------
    car
        Quarter car (its ``thermal`` decides whether the tread temperature is a state; without
        it the temperature grid is the ambient temperature alone).
    fmap
        Force map ``Fx/Fz(kappa, vx, Fz, T)``.
    v0, v_stop
        Initial and final speed [m/s], ``v0 > v_stop > 0``.
    T_ambient
        Ambient and initial tread temperature [K].
    kappa_lo
        Most negative slip allowed [1] (clipped to the map), as the OCP's slip bound.
    resolution
        ``(speed nodes, temperature nodes, candidate slips)``; the candidates are graded
        towards free rolling (``kappa = kappa_lo u^2``, u uniform), where the curves bend.
    kappa
        Candidate slips instead (all < 0), e.g. a single slip for a closed-form check.
    """
    if not (v0 > v_stop > 0):
        raise InputError("need v0 > v_stop > 0 m/s", field="v0, v_stop", value=(v0, v_stop))
    n_v, n_T, n_k = (int(r) for r in resolution)
    if min(n_v, n_k) < 2 or n_T < 2:
        raise InputError("need at least 2 nodes per dimension", field="resolution",
                         value=resolution)
    th = car.thermal
    if kappa is None:
        lo = max(kappa_lo, fmap.bounds("kappa")[0], -1.0)
        kappa = lo * np.linspace(0.0, 1.0, n_k + 1)[1:] ** 2
    kappa = np.asarray(kappa, dtype=float).ravel()
    if kappa.size == 0 or (kappa >= 0).any():
        raise InputError("candidate slips must be < 0", field="kappa", value=kappa.tolist())
    rise = tread_temperature_rise_bound(car, v0)
    T = np.linspace(T_ambient, T_ambient + rise, n_T) if th is not None and rise > 0 \
        else np.array([T_ambient])
    v = np.linspace(v_stop, v0, n_v)
    vm, dv = 0.5 * (v[1:] + v[:-1]), np.diff(v)
    # friction on the grid: (candidate, mid speed, temperature) -> (step, T, candidate)
    mu = -fmap.on_grid(kappa, vm, [car.Fz], T)[:, :, 0, :]
    mu = np.maximum(np.moveaxis(mu, 0, -1), 1e-9)
    J = np.zeros((n_v, T.size))
    policy = np.empty((n_v - 1, T.size))
    rows = np.arange(T.size)
    for i in range(n_v - 1):
        dt = car.mass * dv[i] / (car.Fz * mu[i])                    # (T, candidate)
        cost = vm[i] * dt
        if T.size > 1:
            heat = th.heat_fraction * mu[i] * car.Fz * (-kappa)[None, :] * vm[i]
            Tn = T[:, None] + dt * (heat - th.cooling * (T[:, None] - T_ambient)) \
                / th.heat_capacity
            # the rise bound caps every stop's temperature; interp clamps at the grid's end
            cost = cost + np.interp(Tn.ravel(), T, J[i]).reshape(Tn.shape)
        else:
            cost = cost + J[i, 0]
        best = np.argmin(cost, axis=1)
        policy[i] = kappa[best]
        J[i + 1] = cost[rows, best]
    coast = 0.0
    if T.size > 1 and th.cooling > 0:
        J_T = np.gradient(J, T, axis=1)
        cooling = th.cooling * (T[None, :] - T_ambient) / th.heat_capacity
        coast = float(np.max(J_T * cooling / v[:, None]))
    return SlipDP(v=v, T=T, kappa=kappa, J=J, policy=policy, coast_ratio=coast,
                  T_ambient=float(T_ambient))


@dataclass(frozen=True)
class ThermalBound:
    """Lower bound of :func:`thermal_ramp_bound` with its parts.

    Attributes
    ----------
    distance : float
        The bound [m]: the value at the finer resolution less ``resolution_error``.
    distance_fine, distance_coarse : float
        The bound at the two resolutions [m].
    resolution_error : float
        ``|fine - coarse|``, the estimate of the discretisation error of the fine value [m]
        (first order: the fine value's error is about this, the coarse one's twice).
    relaxed_distance : float
        The relaxation's optimum without the brake's build-up (the dynamic programme's
        ``J(v0, T_amb)``) at the fine resolution [m].
    split_time : float
        The ``t1`` that gives the bound [s].
    coast_ratio : float
        :attr:`SlipDP.coast_ratio` (<= 1: coasting never pays, the relaxation holds).
    dp : SlipDP
        The fine dynamic programme (policy, value function).
    """

    distance: float
    distance_fine: float
    distance_coarse: float
    resolution_error: float
    relaxed_distance: float
    split_time: float
    coast_ratio: float
    dp: SlipDP = field(repr=False)


def _ramp_envelope(car: QuarterCar, v0: float, v_stop: float, mu_max: float,
                   brake_torque_initial: float, dt: float) -> tuple[np.ndarray, np.ndarray,
                                                                     np.ndarray]:
    """Time grid, lowest admissible speed ``w`` and covered distance ``int w`` of every stop
    (:func:`.quarter_car.ramp_limited_stopping_distance`, with a constant peak friction
    ``mu_max``: the largest over every speed and temperature), until ``w`` meets ``v_stop``
    or follows the friction limit alone."""
    R, u = car.radius, car.brake_torque_rate_max
    m_eff = car.mass + car.wheel_inertia / R**2
    T0, T_max = float(brake_torque_initial), car.brake_torque_max
    t_cap = max(T_max - T0, 0.0) / u
    a = car.g * mu_max
    t, w, x = [0.0], [v0], [0.0]
    while w[-1] > v_stop:
        tn = t[-1] + dt
        imp = T0 * tn + 0.5 * u * tn**2 if tn <= t_cap else \
            T0 * t_cap + 0.5 * u * t_cap**2 + T_max * (tn - t_cap)
        r = v0 - imp / (R * m_eff)
        fric = w[-1] - a * dt
        wn = max(r, fric, v_stop)
        x.append(x[-1] + 0.5 * (w[-1] + wn) * dt)
        t.append(tn)
        w.append(wn)
        if fric >= r and tn > t_cap:   # the impulse limit no longer binds
            break
    return np.array(t), np.array(w), np.array(x)


def thermal_ramp_bound(car: QuarterCar, fmap: ForceMap, v0: float, v_stop: float,
                       T_ambient: float, *, brake_torque_initial: float = 0.0,
                       kappa_lo: float = -1.0,
                       resolution: tuple[int, int, int] = RESOLUTION,
                       dt: float = 1e-3) -> ThermalBound:
    """Lower bound [m] on every stop of the quarter car from ``v0`` to ``v_stop`` that starts
    free rolling at the ambient temperature, with the tread's heating and the brake's build-
    up (module doc), from :func:`slip_dp` at ``resolution`` and at half of it.

    The peak friction of the ramp phase is the largest of the map over slip, speed and the
    temperatures a stop can reach (a constant: conservative). ``dt`` is the time step of
    the ramp phase [s].
    """
    th = car.thermal
    res_f = tuple(int(r) for r in resolution)
    res_c = tuple(max(2, (r + 1) // 2) for r in res_f)
    rise = tread_temperature_rise_bound(car, v0)
    T_nodes = np.linspace(T_ambient, T_ambient + rise, 41) if rise > 0 else [T_ambient]
    lo = max(kappa_lo, fmap.bounds("kappa")[0], -1.0)
    k_nodes = lo * np.linspace(0.0, 1.0, 801)[1:] ** 2
    v_nodes = np.geomspace(v_stop, v0, 41)
    mu_max = float(np.max(-fmap.on_grid(k_nodes, v_nodes, [car.Fz], T_nodes)))
    if not mu_max > 0:
        raise InputError("the map has no braking friction", field="force_map")
    t, w, x = _ramp_envelope(car, v0, v_stop, mu_max, brake_torque_initial, dt)
    # the tread heat by speed v: the sliding power |Fx| (-kappa) v <= |Fx| v integrates to
    # at most m (v0^2 - v^2) / 2, of which the share eta reaches the tread
    heat = 0.0 if th is None else th.heat_fraction * car.mass / (2.0 * th.heat_capacity)

    def bound(dp: SlipDP) -> tuple[float, float]:
        best, t_best = -math.inf, 0.0
        for k in range(t.size):
            rest = 0.0
            if w[k] > v_stop:
                vq = np.concatenate(([w[k]], dp.v[dp.v > w[k]]))
                T_hi = np.minimum(T_ambient + heat * (v0**2 - vq**2), dp.T[-1])
                # J is bilinear between the nodes: its least value over the admissible
                # (v, T) (v >= w, T <= T_hi(v)) is at a node or on the edge T = T_hi(v)
                grid = dp.values(vq, dp.T)
                grid[dp.T[None, :] > T_hi[:, None]] = np.inf
                edge = dp.values_at(vq, T_hi)
                rest = float(min(grid.min(), edge.min()))
            if x[k] + rest > best:
                best, t_best = x[k] + rest, float(t[k])
        return best, t_best

    dp_f = slip_dp(car, fmap, v0, v_stop, T_ambient, kappa_lo=kappa_lo, resolution=res_f)
    dp_c = slip_dp(car, fmap, v0, v_stop, T_ambient, kappa_lo=kappa_lo, resolution=res_c)
    fine, t1 = bound(dp_f)
    coarse, _ = bound(dp_c)
    err = abs(fine - coarse)
    return ThermalBound(distance=fine - err, distance_fine=fine, distance_coarse=coarse,
                        resolution_error=err, relaxed_distance=dp_f.distance, split_time=t1,
                        coast_ratio=dp_f.coast_ratio, dp=dp_f)


def describe(b: ThermalBound) -> dict[str, Any]:
    """Plain numbers of a :class:`ThermalBound` for the study's summary."""
    return {"thermal_bound": b.distance, "thermal_bound_error": b.resolution_error,
            "slip_dp_distance": b.relaxed_distance, "thermal_bound_split_s": b.split_time,
            "slip_dp_coast_ratio": b.coast_ratio}
