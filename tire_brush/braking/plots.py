"""Plots of a braking study (matplotlib's object API: no pyplot state, no backend switch)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .results import CaseResult

STYLE = {"ocp": ("OCP (optimal)", "C0"), "abs": ("rule-based ABS", "C1"),
         "locked": ("locked wheel", "C3"), "abs_fmu": ("rule-based ABS through the FMU", "C2"),
         "abs_realistic": ("ABS with estimated speed and hydraulics", "C4")}


def _runs(r: CaseResult):
    runs = [("ocp", r.ocp), ("abs", r.abs_sim), ("locked", r.locked)]
    if r.abs_fmu is not None:
        runs.append(("abs_fmu", r.abs_fmu))
    if getattr(r, "abs_realistic", None) is not None:
        runs.append(("abs_realistic", r.abs_realistic))
    return tuple(runs)


def plot_time_histories(r: CaseResult, path: str | Path) -> Path:
    """Speed, slip, mu, brake torque and tread temperature vs time for the strategies of one
    case."""
    fig = Figure(figsize=(8, 11), layout="constrained")
    ax = fig.subplots(5, 1, sharex=True)
    R = r.summary["radius_m"]
    for name, res in _runs(r):
        lab, col = STYLE[name]
        ax[0].plot(res.t, res.v, color=col, label=f"{lab}: v")
        ax[0].plot(res.t, res.omega * R, color=col, ls=":", lw=0.8)
        ax[1].plot(res.t, -res.kappa, color=col, lw=1.0 if name != "ocp" else 1.8, label=lab)
        ax[2].plot(res.t, -res.mu, color=col, lw=1.0 if name != "ocp" else 1.8, label=lab)
        ax[3].plot(res.t, res.brake_torque, color=col, lw=1.0 if name != "ocp" else 1.8,
                   label=lab)
        ax[4].plot(res.t, np.asarray(res.T_tread) - 273.15, color=col,
                   lw=1.0 if name != "ocp" else 1.8, label=lab)
    dp = getattr(r, "slip_dp", None)
    if dp is not None:
        lab = f"global optimum, quasi-steady wheel: {dp['x'][-1]:.2f} m"
        ax[1].plot(dp["t"], -dp["kappa"], color="k", lw=0.8, ls="-.", label=lab)
        ax[2].plot(dp["t"], -dp["mu"], color="k", lw=0.8, ls="-.", label=lab)
        ax[4].plot(dp["t"], dp["T_tread"] - 273.15, color="k", lw=0.8, ls="-.", label=lab)
    ax[1].axhline(-r.summary["optimal_slip"], color="k", ls="--", lw=0.8,
                  label="slip of max force at v0")
    ax[0].set_ylabel("v, omega R (dotted) [m/s]")
    ax[1].set_ylabel("braking slip -kappa [1]")
    ax[2].set_ylabel("braking friction -Fx/Fz [1]")
    ax[3].set_ylabel("brake torque [N m]")
    ax[4].set_ylabel("tread temperature [C]")
    ax[4].set_xlabel("time t [s]")
    ax[1].set_ylim(0, 1.05)
    ax[0].legend(fontsize=8)
    ax[1].legend(fontsize=8)
    s = r.summary
    fmu = "" if r.abs_fmu is None else \
        f",\nrule-based ABS through the FMU {s['stopping_distance_abs_fmu']:.2f} m"
    fig.suptitle(f"{s['case']}: stopping distance OCP {s['stopping_distance_ocp']:.2f} m, "
                 f"ABS {s['stopping_distance_abs']:.2f} m, locked "
                 f"{s['stopping_distance_locked']:.2f} m{fmu}", fontsize=10)
    fig.savefig(path, dpi=110)
    return Path(path)


def plot_mu_slip(r: CaseResult, path: str | Path) -> Path:
    """Braking friction vs slip from the force map with the strategies' operating points."""
    fmap, s = r.force_map, r.summary
    Fz, T = s["Fz_N"], r.case.T_K
    k = -np.linspace(0.0, 1.0, 401)
    fig = Figure(figsize=(7, 5), layout="constrained")
    ax = fig.subplots()
    v0 = float(r.ocp.v[0])
    for v, ls in ((v0, "-"), (0.5 * v0, "--"), (max(float(r.ocp.v[-1]), 0.1 * v0), ":")):
        ax.plot(-k, -fmap(k, v, Fz, T), color="0.3", ls=ls, lw=1.2,
                label=f"force map, v = {v:.3g} m/s")
    # locked first, OCP last: the optimal operating points stay visible on top
    for name, res in reversed(_runs(r)):
        lab, col = STYLE[name]
        ms = {"ocp": 7, "abs": 4, "locked": 9, "abs_fmu": 3, "abs_realistic": 3}[name]
        ax.plot(-res.kappa, -res.mu, "o", ms=ms, mfc="none" if name != "ocp" else col,
                mec=col, alpha=0.6 if name in ("abs", "abs_fmu", "abs_realistic") else 0.9,
                label=f"{lab} operating points")
    ax.axvline(-s["optimal_slip"], color="k", ls="--", lw=0.8,
               label=f"slip of max force at v0: {-s['optimal_slip']:.3f}")
    ax.set_xlabel("braking slip -kappa [1]")
    ax.set_ylabel("braking friction -Fx/Fz [1]")
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.set_title(f"{s['case']}: mu-slip curve and operating points", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    fig.savefig(path, dpi=110)
    return Path(path)


def plot_distances(results: list[CaseResult], path: str | Path) -> Path:
    """Stopping distances by case: OCP, ABS, locked wheel, the ABS through the FMU (when
    the study ran it), the point-mass bound of the OCP's tread temperatures and the bound
    that follows the tread's heating (:mod:`.thermal_dp`)."""
    labels = [r.case.label for r in results]
    x = np.arange(len(results))
    bars = [("ocp", "stopping_distance_ocp"), ("abs", "stopping_distance_abs"),
            ("locked", "stopping_distance_locked")]
    if any(r.abs_fmu is not None for r in results):
        bars.insert(2, ("abs_fmu", "stopping_distance_abs_fmu"))
    if all("stopping_distance_abs_realistic" in r.summary for r in results):
        bars.insert(2, ("abs_realistic", "stopping_distance_abs_realistic"))
    fig = Figure(figsize=(max(6, 1.8 * len(results) + 2), 4.5), layout="constrained")
    ax = fig.subplots()
    w = 0.8 / len(bars)
    for i, (name, key) in enumerate(bars):
        lab, col = STYLE[name]
        ax.bar(x + (i - (len(bars) - 1) / 2) * w, [r.summary[key] for r in results], w,
               color=col, label=lab)
    x_ocp = x - (len(bars) - 1) / 2 * w
    ax.scatter(x_ocp, [r.summary["point_mass_bound"] for r in results], marker="_", s=400,
               color="k", zorder=3, label="point-mass bound, OCP's tread temperatures")
    ax.scatter(x_ocp, [r.summary.get("point_mass_bound_T0", np.nan) for r in results],
               marker="_", s=400, color="0.6", zorder=3, label="point-mass bound at T0")
    if all("thermal_bound" in r.summary for r in results):
        ax.scatter(x_ocp, [r.summary["thermal_bound"] for r in results], marker="_", s=400,
                   color="C5", zorder=3,
                   label="lower bound with tread heating and brake build-up")
    ax.set_xticks(x, labels, rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("stopping distance to v_stop [m]")
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=110)
    return Path(path)


def plot_road(road: str, runs: dict, path: str | Path) -> Path:
    """One road of ``tirefric abs roads``: speed against distance, the yaw moment the steering
    must hold, and each wheel's braking slip, per controller and model (map solid, FMU
    dashed)."""
    from .two_axle import WHEELS

    fig = Figure(figsize=(8, 9), layout="constrained")
    ax = fig.subplots(3, 1)
    colours = {"abs": "C1", "locked": "C3"}
    for (_, ctrl, model), res in runs.items():
        ls = "-" if model == "map" else "--"
        lab = f"{ctrl}, {model}: {res.stopping_distance:.2f} m"
        col = colours.get(ctrl, "C0")
        ax[0].plot(res.x, res.v, color=col, ls=ls, label=lab)
        ax[1].plot(res.t, np.asarray(res.yaw_moment) / 1e3, color=col, ls=ls, label=lab)
        if ctrl == "abs":
            for i, wc in enumerate(("C0", "C2", "C4", "C5")):
                ax[2].plot(res.t, -res.kappa[:, i], color=wc, ls=ls, lw=0.8,
                           label=f"{WHEELS[i]}, {model}")
    ax[0].set_xlabel("distance x [m]")
    ax[0].set_ylabel("speed v [m/s]")
    ax[1].set_ylabel("yaw moment M_z [kN m] (> 0: left)")
    ax[1].set_xlabel("time t [s]")
    ax[2].set_ylabel("braking slip -kappa, ABS [1]")
    ax[2].set_xlabel("time t [s]")
    ax[2].set_ylim(0, 1.05)
    for a in ax:
        a.legend(fontsize=7)
    fig.suptitle(f"road {road}", fontsize=10)
    fig.savefig(path, dpi=110)
    return Path(path)
