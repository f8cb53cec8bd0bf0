"""Figures of a friction grid (matplotlib, Agg backend): what a user checks first.

* cold and hot mu(v) at several background temperatures,
* the flash temperature rise dT_flash(v) at the same temperatures,
* the hot/cold ratio mu_hot / mu_cold as a map over (log10 v, T),
* the relative contact area A/A0 of both branches.

All at one nominal pressure (interpolated in log10 p when it is not a node).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .reader import FrictionGrid

KELVIN = 273.15


def pick_temperatures(grid: FrictionGrid, n: int = 5) -> np.ndarray:
    """About ``n`` temperature nodes spread over the axis [K]."""
    idx = np.unique(np.round(np.linspace(0, grid.T.size - 1, min(n, grid.T.size))).astype(int))
    return grid.T[idx]


def plot_grid(grid: FrictionGrid, output: str | Path, *, p_Pa: float | None = None,
              n_temperatures: int = 5, dpi: int = 120) -> Path:
    """Draw the overview figure of ``grid`` into ``output`` (PNG, PDF, SVG by suffix).

    Parameters
    ----------
    grid
        The grid.
    output
        Image file.
    p_Pa
        Nominal pressure [Pa] of the curves; default: the pressure node nearest 0.3 MPa.
    n_temperatures
        Number of temperature curves.
    dpi
        Resolution of raster output.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if p_Pa is None:
        p_Pa = float(grid.p[np.argmin(np.abs(grid.log10_p - np.log10(3e5)))])
    v = grid.v
    Ts = pick_temperatures(grid, n_temperatures)
    names = ("mu_cold", "mu_hot", "dT_flash", "area_cold", "area_hot")
    fig, axs = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    colors = plt.cm.plasma(np.linspace(0.0, 0.85, Ts.size))  # cold = dark, hot = yellow
    for T, c in zip(Ts, colors, strict=True):
        r = grid.interpolate(v, T, p_Pa, names=names)
        label = f"{T - KELVIN:.0f} C"
        axs[0, 0].semilogx(v, r["mu_cold"], "--", color=c)
        axs[0, 0].semilogx(v, r["mu_hot"], "-", color=c, label=label)
        axs[0, 1].semilogx(v, r["dT_flash"], "-", color=c, label=label)
        axs[1, 1].semilogx(v, r["area_cold"], "--", color=c)
        axs[1, 1].semilogx(v, r["area_hot"], "-", color=c, label=label)
    axs[0, 0].set(xlabel="slip speed v [m/s]", ylabel="friction coefficient mu [1]",
                  title="mu(v): hot (solid) and cold (dashed)")
    axs[0, 0].legend(title="T0", fontsize="small")
    axs[0, 1].set(xlabel="slip speed v [m/s]", ylabel="flash temperature rise dT_flash [K]",
                  title="flash temperature (hot branch)")
    axs[1, 1].set(xlabel="slip speed v [m/s]", ylabel="relative contact area A/A0 [1]",
                  title="contact area: hot (solid) and cold (dashed)")
    # ratio map on the (log10 v, T) nodes
    LV, TT = np.meshgrid(grid.log10_v, grid.T, indexing="ij")
    r = grid.interpolate(10.0**LV, TT, p_Pa, names=("mu_cold", "mu_hot"))
    ratio = r["mu_hot"] / np.where(r["mu_cold"] > 0, r["mu_cold"], np.nan)
    span = max(float(np.nanmax(np.abs(ratio - 1.0))), 1e-6) if np.isfinite(ratio).any() else 1
    m = axs[1, 0].pcolormesh(grid.log10_v, grid.T - KELVIN, ratio.T, shading="nearest",
                             cmap="RdBu_r", vmin=1 - span, vmax=1 + span)
    fig.colorbar(m, ax=axs[1, 0], label="mu_hot / mu_cold [1]")
    axs[1, 0].set(xlabel="log10(v / (m/s))", ylabel="background temperature T0 [C]",
                  title="hot/cold friction ratio")
    for ax in axs.flat:
        ax.grid(True, which="major", alpha=0.3)
    meta = grid.meta
    who = f"{meta.get('compound_name', '?')} on {meta.get('surface_name', '?')}"
    fig.suptitle(f"Friction grid: {who}, p = {p_Pa / 1e6:.3g} MPa  ({grid.hash[:19]})")
    output = Path(output)
    fig.savefig(output, dpi=dpi)
    plt.close(fig)
    return output
