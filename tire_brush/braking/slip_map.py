"""Optimal slip maps: the braking slip that maximises the braking force.

For each operating point (speed, load, temperature) the slip ``kappa*`` in
``[kappa_min, 0]`` that minimises ``Fx/Fz`` (the most negative force ratio, i.e. the largest
braking force) is found by a dense scan of the slip axis (vectorised over all operating points)
followed by a bounded scalar refinement (Brent's method, ``scipy.optimize.minimize_scalar``)
between the neighbours of the best scan point. The map stores ``kappa*``, the peak braking
friction ``mu_max = -Fx/Fz(kappa*)`` and the locked-wheel friction ``mu_locked = -Fx/Fz(-1)``:
the table an ABS controller reads its target slip from (:meth:`SlipMap.to_csv`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tirefric.errors import InputError

from .force_map import FxOverFz

#: CSV header of a slip map (units in brackets, as ``tirefric.config.read_csv_table`` reads them).
CSV_COLUMNS = ("vx [m/s]", "Fz [N]", "T [K]", "kappa_opt [1]", "mu_max [1]", "mu_locked [1]",
               "kappa_peak_stable [1]", "kappa_peak_unstable [1]", "peak_width [1]")
#: Fraction of the peak friction that bounds the peak's width (:attr:`SlipMap.peak_width`).
PEAK_FRACTION = 0.95
#: Points of the stable branch ``kappa in [kappa_opt, 0]`` in the exported maps.
N_STABLE = 21


@dataclass(frozen=True)
class SlipMap:
    """Optimal braking slip on a (speed, load, temperature) grid.

    Attributes
    ----------
    vx, Fz, T_K : numpy.ndarray
        Axes: speed [m/s], load [N], temperature [K].
    kappa_opt : numpy.ndarray
        Slip of maximum braking force [1] (negative), shape ``(len(vx), len(Fz), len(T_K))``.
    mu_max : numpy.ndarray
        Peak braking friction ``-Fx/Fz`` at ``kappa_opt`` [1].
    mu_locked : numpy.ndarray
        Locked-wheel friction ``-Fx/Fz`` at ``kappa = -1`` [1].
    label : str
        Provenance of the friction source.
    kappa_peak : numpy.ndarray or None
        Slips where the braking friction falls to :data:`PEAK_FRACTION` of its peak, on the
        stable side (between ``kappa_opt`` and 0) and on the unstable side (towards -1), shape
        ``(..., 2)``; the peak's width is their difference (:attr:`peak_width`). An ABS that
        holds the slip inside keeps 95 % of the peak force; a wide peak forgives estimation
        errors of the slip.
    stable_mu : numpy.ndarray or None
        Braking friction ``-Fx/Fz`` on the stable branch at ``kappa = kappa_opt * s`` for
        ``s`` in ``linspace(0, 1, N_STABLE)``, shape ``(..., N_STABLE)``: the part of the
        curve a braked wheel can hold (beyond the peak the wheel decelerates into lock).
    """

    vx: np.ndarray
    Fz: np.ndarray
    T_K: np.ndarray
    kappa_opt: np.ndarray
    mu_max: np.ndarray
    mu_locked: np.ndarray
    label: str = ""
    kappa_peak: np.ndarray | None = None
    stable_mu: np.ndarray | None = None

    @property
    def peak_width(self) -> np.ndarray:
        """Width in slip of the peak at :data:`PEAK_FRACTION` of the peak friction [1]."""
        if self.kappa_peak is None:
            return np.full(self.kappa_opt.shape, np.nan)
        return self.kappa_peak[..., 0] - self.kappa_peak[..., 1]

    def interpolate(self, vx, Fz, T_K) -> np.ndarray:
        """Optimal slip at an operating point: multilinear in the axes, clamped at their ends.

        Axes with one node are constants.
        """
        from scipy.interpolate import RegularGridInterpolator

        axes, idx = [], []
        for i, a in enumerate((self.vx, self.Fz, self.T_K)):
            if a.size > 1:
                axes.append(a)
                idx.append(i)
        args = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (vx, Fz, T_K)))
        if not axes:
            return np.full(args[0].shape, float(self.kappa_opt.ravel()[0]))
        values = self.kappa_opt.reshape([a.size for a in axes])
        pts = np.stack([np.clip(args[i], a[0], a[-1]) for i, a in zip(idx, axes, strict=True)],
                       axis=-1)
        return RegularGridInterpolator(axes, values)(pts)

    def rows(self) -> list[tuple[float, ...]]:
        """Table rows in :data:`CSV_COLUMNS` order, temperature fastest varying."""
        out = []
        width = self.peak_width
        kp = (np.full((*self.kappa_opt.shape, 2), np.nan) if self.kappa_peak is None
              else self.kappa_peak)
        for i, v in enumerate(self.vx):
            for j, f in enumerate(self.Fz):
                for k, T in enumerate(self.T_K):
                    out.append((float(v), float(f), float(T), float(self.kappa_opt[i, j, k]),
                                float(self.mu_max[i, j, k]), float(self.mu_locked[i, j, k]),
                                float(kp[i, j, k, 0]), float(kp[i, j, k, 1]),
                                float(width[i, j, k])))
        return out

    def to_json(self, path: str | Path) -> Path:
        """Write the map as JSON: axes, optimum, peak bounds and width, and the stable branch
        of the friction curve per operating point (units in the keys)."""
        import json

        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        points = []
        for idx in np.ndindex(self.kappa_opt.shape):
            i, j, k = idx
            kopt = float(self.kappa_opt[idx])
            pt = {"vx_m_per_s": float(self.vx[i]), "Fz_N": float(self.Fz[j]),
                  "T_K": float(self.T_K[k]), "kappa_opt": kopt,
                  "mu_max": float(self.mu_max[idx]), "mu_locked": float(self.mu_locked[idx])}
            if self.kappa_peak is not None:
                pt.update(kappa_peak_stable=float(self.kappa_peak[(*idx, 0)]),
                          kappa_peak_unstable=float(self.kappa_peak[(*idx, 1)]),
                          peak_width=float(self.peak_width[idx]))
            if self.stable_mu is not None:
                s = np.linspace(0.0, 1.0, self.stable_mu.shape[-1])
                pt["stable_branch"] = {"kappa": (kopt * s).tolist(),
                                       "mu": self.stable_mu[idx].tolist()}
            points.append(pt)
        doc = {"description": "optimal braking slip map: slip of maximum braking force, the "
                              f"slips where the force falls to {PEAK_FRACTION:g} of its peak "
                              "and the stable branch kappa in [kappa_opt, 0] of -Fx/Fz; "
                              "kappa < 0 in braking",
               "friction_source": self.label, "peak_fraction": PEAK_FRACTION,
               "points": points}
        path.write_text(json.dumps(doc, indent=1, allow_nan=False))
        return path

    def to_csv(self, path: str | Path) -> Path:
        """Write the map as CSV with units in the header and a provenance comment."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w") as fh:
            fh.write("# Optimal braking slip map (tire_brush.braking.slip_map): slip of maximum\n"
                     "# braking force per speed, load and temperature; kappa < 0 in braking.\n")
            fh.write(f"# friction source: {self.label}\n")
            fh.write(",".join(CSV_COLUMNS) + "\n")
            for r in self.rows():
                fh.write(",".join(f"{x:.10g}" for x in r) + "\n")
        return path


def optimal_slip(
    fx_over_fz: FxOverFz,
    vx,
    Fz,
    T_K,
    *,
    kappa_min: float = -1.0,
    n_scan: int = 801,
    xatol: float = 1e-7,
    label: str = "",
) -> SlipMap:
    """Slip of maximum braking force on the tensor grid of ``vx``, ``Fz``, ``T_K``.

    Parameters
    ----------
    fx_over_fz
        Friction source ``Fx/Fz(kappa, vx, Fz, T_K)``, numpy broadcasting.
    vx, Fz, T_K
        Axes of the map [m/s], [N], [K].
    kappa_min
        Lower end of the searched slip range [1], ``-1 <= kappa_min < 0``.
    n_scan
        Points of the dense scan on ``[kappa_min, 0]``.
    xatol
        Absolute slip tolerance of the refinement.
    label
        Provenance text.
    """
    from scipy.optimize import minimize_scalar

    if not -1.0 <= kappa_min < 0.0:
        raise InputError("must be in [-1, 0)", field="kappa_min", value=kappa_min)
    if n_scan < 11:
        raise InputError("need at least 11 scan points", field="n_scan", value=n_scan)
    axes = [np.atleast_1d(np.asarray(a, dtype=float)) for a in (vx, Fz, T_K)]
    for name, a in zip(("vx", "Fz", "T_K"), axes, strict=True):
        if a.ndim != 1 or not np.isfinite(a).all():
            raise InputError("expected a 1-D axis of finite numbers", field=name,
                             value=a.tolist())
    k = np.linspace(kappa_min, 0.0, n_scan)
    K, V, F, T = np.meshgrid(k, *axes, indexing="ij")
    mu = np.asarray(fx_over_fz(K, V, F, T), dtype=float)
    if not np.isfinite(mu).all():
        raise InputError("friction source gave non-finite values on the slip scan",
                         field="fx_over_fz")
    i_best = np.argmin(mu, axis=0)
    shape = i_best.shape
    kappa_opt = np.empty(shape)
    mu_min = np.empty(shape)
    for idx in np.ndindex(shape):
        i = int(i_best[idx])
        lo, hi = k[max(i - 1, 0)], k[min(i + 1, n_scan - 1)]
        v, f, t = (float(a[j]) for a, j in zip(axes, idx, strict=True))

        def fun(kk, v=v, f=f, t=t):
            return float(np.asarray(fx_over_fz(np.array(kk), v, f, t)))

        res = minimize_scalar(fun, bounds=(lo, hi), method="bounded",
                              options={"xatol": xatol})
        best_k, best_mu = float(k[i]), float(mu[(i, *idx)])
        if res.fun < best_mu:
            best_k, best_mu = float(res.x), float(res.fun)
        kappa_opt[idx] = best_k
        mu_min[idx] = best_mu
    Kl, Vl, Fl, Tl = np.meshgrid(np.array([-1.0]), *axes, indexing="ij")
    mu_locked = -np.asarray(fx_over_fz(Kl, Vl, Fl, Tl), dtype=float)[0]
    # the peak's bounds at PEAK_FRACTION of the peak, from the scan (linear between points)
    kappa_peak = np.empty((*shape, 2))
    for idx in np.ndindex(shape):
        braking = -mu[(slice(None), *idx)]
        level = PEAK_FRACTION * -mu_min[idx]
        i = int(i_best[idx])
        bounds = []
        for step, end in ((1, n_scan - 1), (-1, 0)):          # stable side first (k -> 0)
            j = i
            while j != end and braking[j + step] >= level:
                j += step
            if j == end:
                bounds.append(float(k[end]))
            else:                                          # crossing between j and j + step
                a, b = braking[j], braking[j + step]
                bounds.append(float(k[j] + (k[j + step] - k[j]) * (a - level) / (a - b)))
        kappa_peak[idx] = bounds
    s = np.linspace(0.0, 1.0, N_STABLE)
    Ks = kappa_opt[None, ...] * s.reshape(-1, 1, 1, 1)
    Vs, Fs, Ts = np.meshgrid(*axes, indexing="ij")
    stable_mu = -np.asarray(fx_over_fz(Ks, Vs[None], Fs[None], Ts[None]), dtype=float)
    return SlipMap(vx=axes[0], Fz=axes[1], T_K=axes[2], kappa_opt=kappa_opt, mu_max=-mu_min,
                   mu_locked=mu_locked, label=label, kappa_peak=kappa_peak,
                   stable_mu=np.moveaxis(stable_mu, 0, -1))
