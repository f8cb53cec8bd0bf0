"""Plots of the friction engine's inputs and results (matplotlib, Agg backend).

What a tire engineer looks at first: mu(v) on the cold and hot branch at several temperatures,
the flash temperature and the real contact area against slip speed, the compound's master
curve (E', E'', tan delta) and the surface's power spectrum with its cut-off q1.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .compound import Compound
from .friction import PerssonFriction
from .roughness import xi_squared_numeric
from .surface import Surface


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _finish(fig, axes, path: str | Path) -> Path:
    """Grid and legend on every panel, tight layout, save as PNG, close."""
    for a in axes:
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    _plt().close(fig)
    return path


def plot_friction(model: PerssonFriction, T_C: Sequence[float], p: float, path: str | Path,
                  v: np.ndarray | None = None) -> Path:
    """mu(v) cold (dashed) and hot (solid), flash temperature and A/A0 vs v at several T."""
    plt = _plt()
    v = np.logspace(-6, np.log10(40.0), 61) if v is None else np.asarray(v, float)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    colors = plt.cm.coolwarm(np.linspace(0, 1, len(T_C)))
    for T, col in zip(T_C, colors, strict=True):
        c = model.cold(v, T + 273.15, p)
        h = model.hot(v, T + 273.15, p)
        ax[0].semilogx(v, c.mu, "--", color=col)
        ax[0].semilogx(v, h.mu, "-", color=col, label=f"{T:g} C")
        ax[1].loglog(v, np.maximum(h.dT_flash, 1e-3), "-", color=col, label=f"{T:g} C")
        ax[2].loglog(v, c.area, "--", color=col)
        ax[2].loglog(v, h.area, "-", color=col, label=f"{T:g} C")
    ax[0].set(xlabel="slip speed v [m/s]", ylabel="friction coefficient mu [1]",
              title=f"{model.compound.name} on {model.surface.name}, p = {p / 1e6:g} MPa\n"
                    "solid: hot branch, dashed: cold branch")
    ax[1].set(xlabel="slip speed v [m/s]", ylabel="flash temperature dT [K]",
              title="flash temperature (hot branch, surface)")
    ax[2].set(xlabel="slip speed v [m/s]", ylabel="real contact area A/A0 [1]",
              title=f"contact area (q1 = {model.q1:.3g} 1/m)")
    return _finish(fig, ax, path)


def plot_compound(compound: Compound, path: str | Path, T_C: Sequence[float] = (20.0,)) -> Path:
    """E', E'' (strain-softened, as used) and tan delta of a compound vs angular frequency."""
    plt = _plt()
    w = np.logspace(-6, 16, 400)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    for T in T_C:
        eta_R, eta_I = compound.softening_factors(T + 273.15)  # strain sweeps depend on T
        la = compound.log10_aT(np.array(T + 273.15))
        ER, EI = compound.modulus.storage_loss(w * 10.0**la)
        ax[0].loglog(w, ER * eta_R, label=f"E' {T:g} C")
        ax[0].loglog(w, EI * eta_I, "--", label=f"E'' {T:g} C")
        ax[1].semilogx(w, EI * eta_I / (ER * eta_R), label=f"{T:g} C")
    ax[0].set(xlabel="angular frequency w [rad/s]", ylabel="modulus [Pa]",
              title=f"{compound.name}: master curve at strain {compound.strain:g} (eq. 6)")
    ax[1].set(xlabel="angular frequency w [rad/s]", ylabel="tan delta [1]", title="loss tangent")
    return _finish(fig, ax, path)


def plot_surface(surface: Surface, path: str | Path) -> Path:
    """C(q) and the cumulative rms slope xi(q) with q1 marked."""
    plt = _plt()
    q1 = surface.q1
    top = surface.psd.q_max if np.isfinite(surface.psd.q_max) else 30 * q1
    q = np.geomspace(surface.psd.q0, top, 400)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    ax[0].loglog(q, surface.psd.C(q))
    ax[0].axvline(q1, color="k", ls=":", label=f"q1 = {q1:.3g} 1/m")
    ax[0].set(xlabel="wavenumber q [1/m]", ylabel="power spectrum C(q) [m^4]",
              title=f"{surface.name}: 2D isotropic C(q)")
    ax[1].loglog(q, np.sqrt(xi_squared_numeric(surface.psd, q)))
    ax[1].axvline(q1, color="k", ls=":", label=f"rule: {surface.cutoff.rule}")
    ax[1].set(xlabel="wavenumber q [1/m]", ylabel="cumulative rms slope xi(q) [1]",
              title="rms slope (q1 rule, review sec. 5.1)")
    return _finish(fig, ax, path)


def plot_rolling(compound: Compound, T_C: Sequence[float], v: np.ndarray, mu_of, title: str,
                 path: str | Path) -> Path:
    """Rolling-friction master curve: mu against log10 v at each temperature [C], and the same
    against log10(v a_T) (a_T to the master curve's T_ref), where the curves collapse (review
    sec. 6, Fig. of the tread compound: linear response, no heating). ``mu_of(v, T [K])``."""
    plt = _plt()
    v = np.asarray(v, float)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    colors = plt.cm.coolwarm(np.linspace(0, 1, max(len(T_C), 2)))
    for T, col in zip(T_C, colors, strict=False):
        mu = mu_of(v, T + 273.15)
        la = float(compound.log10_aT(np.array(T + 273.15)))
        ax[0].plot(np.log10(v), mu, color=col, label=f"{T:g} C")
        ax[1].plot(np.log10(v) + la, mu, color=col, label=f"{T:g} C")
    ax[0].set(xlabel="log10 rolling speed v [m/s]", ylabel="rolling friction mu [1]",
              title=f"rolling friction: {title}")
    T_ref = compound.T_ref - 273.15
    ax[1].set(xlabel=f"log10 (v a_T) [m/s], reduced to T_ref = {T_ref:g} C",
              ylabel="rolling friction mu [1]", title="shifted with a_T: master curve")
    return _finish(fig, ax, path)
