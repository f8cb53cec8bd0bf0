"""Fit Magic Formula 6.1 / PAC2002 coefficients to the steady brush model.

The steady brush (:class:`~tire_brush.steady.SteadyBrush`, its converged defaults) is sampled in
one vectorised call at a few loads (default 0.5, 1 and 1.5 times the nominal load) over pure
longitudinal slip, pure slip angle and a combined-slip grid, at one speed and background
temperature. Its outputs (adapted SAE, :mod:`tire_brush.axes`) are turned into ISO-W, the
convention of ``.tir`` files, and the coefficients are fitted with
:func:`scipy.optimize.least_squares` in the usual stages (Pacejka 2012, *Tire and Vehicle
Dynamics*, sec. 4.3.2; each stage against what the earlier ones predict, as a simulator will
evaluate them):

1. pure ``Fx``: ``PCX1, PDX1, PDX2, PEX1..PEX4, PKX1..PKX3``;
2. pure ``Fy``: ``PCY1, PDY1, PDY2, PEY1, PEY2, PKY1, PKY2`` (``PKY4 = 2``: the PAC2002 form,
   which MF 6.1 readers evaluate the same way);
3. pure ``Mz``: pneumatic trail ``QBZ1..QBZ3, QCZ1, QDZ1, QDZ2, QEZ1..QEZ3``;
4. combined ``Fx``: ``RBX1, RBX2, RCX1, REX1, REX2``;
5. combined ``Fy``: ``RBY1, RBY2, RCY1, REY1, REY2, RHY1, RHY2``;
6. combined ``Mz``: ``SSZ2`` (moment arm of ``Fx`` growing with ``Fy``);
7. camber: ``PKY6, PKY7`` from the brush's camber stiffness at the fit loads, ``Mx``: ``QSX3``
   (closed form), ``My``: ``QSY1, QSY3, QSY7`` from :mod:`tire_brush.rolling_resistance`
   (:func:`fit_camber`, :func:`fit_rolling`).

Coefficients that stay 0, and why (checked by the tests on the brush itself): the brush is
mirror-symmetric in the slip angle (``Fy(-alpha) = -Fy(alpha)``, ``Mz(-alpha) = -Mz(alpha)``,
``Fx(kappa, -alpha) = Fx(kappa, alpha)``) and gives no force at zero slip, so the shifts
``PHX*, PVX*, PHY*, PVY*, QHZ*, RHX1, RBY3``, the asymmetry ``PEY3, QEZ4``, the kappa-induced
side force ``RVY*``, the residual moment ``QDZ6, QDZ7, QBZ9, QBZ10`` (an even function of the
slip angle at zero camber) and ``SSZ1`` (a moment at pure longitudinal slip) are all zero. The
brush is not symmetric in ``kappa`` (``sigma_x = kappa / (1 + kappa)``: braking and driving
differ), which ``PEX4`` and ``RHY1, RHY2`` take up. It has no pressure or turn-slip model, and
its camber acts on ``Fy`` through the camber stiffness alone (the other camber coefficients,
``QSX1, QSX2`` and ``QSY2, QSY4..QSY6, QSY8`` are 0; docs/mf-fit.md): those coefficients are 0
too.

The curvature factors are kept ``<= 1`` over the fitted load range (a penalty in the fit), as
the MF equations require, so readers that clip ``E`` and readers that do not agree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tirefric.errors import InputError

from . import magic_formula as mf
from .axes import BRUSH_AXES, Wrench, convert_wrench

#: Channels of the fit error, in report order.
CHANNELS = ("Fx_pure", "Fy_pure", "Mz_pure", "Fx_combined", "Fy_combined", "Mz_combined")


@dataclass(frozen=True)
class FitSettings:
    """Where the brush is sampled.

    Attributes
    ----------
    loads : tuple of float
        Loads as multiples of the nominal load ``Fz_nom`` [1].
    kappa_max : float
        Largest ``|kappa|`` of the pure longitudinal sweep [1] (< 1: ``-1`` is a locked wheel).
    n_kappa : int
        Points of the pure longitudinal sweep, denser near 0 (an odd number includes 0).
    alpha_max_deg : float
        Largest ``|alpha|`` of the pure side-slip sweep [deg].
    n_alpha : int
        Points of the pure side-slip sweep, denser near 0 (odd: includes 0).
    combined_kappa_max : float
        Largest ``|kappa|`` of the combined grid [1].
    n_combined_kappa : int
        Slips of the combined grid.
    combined_alpha_deg : tuple of float
        Slip angles of the combined grid [deg] (each with both signs).
    camber_max : float
        Largest ``|gamma|`` of the camber check [rad] (the file's ``CAMMIN, CAMMAX``).
    camber_step : float
        Inclination of the central difference for the camber stiffness [rad].
    n_camber : int
        Inclinations of the camber check, equally spaced in ``[-camber_max, camber_max]``.
    camber_alpha_deg : tuple of float
        Slip angles of the camber check besides 0 [deg] (each with both signs).
    rolling_speeds : tuple of float
        Speeds of the rolling-resistance fit as multiples of ``vx`` [1].
    """

    loads: tuple[float, ...] = (0.5, 1.0, 1.5)
    kappa_max: float = 0.95
    n_kappa: int = 41
    alpha_max_deg: float = 15.0
    n_alpha: int = 31
    combined_kappa_max: float = 0.5
    n_combined_kappa: int = 21
    combined_alpha_deg: tuple[float, ...] = (2.0, 5.0, 10.0)
    camber_max: float = 0.1
    camber_step: float = 0.01
    n_camber: int = 9
    camber_alpha_deg: tuple[float, ...] = (2.0, 5.0)
    rolling_speeds: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0)

    def __post_init__(self) -> None:
        problems = []
        if not self.loads or any(not (math.isfinite(x) and x > 0) for x in self.loads):
            problems.append(("loads", self.loads, "must be positive multiples of Fz_nom"))
        if len(set(self.loads)) < 2:
            problems.append(("loads", self.loads, "need at least two different loads "
                                                  "(the load dependence is fitted)"))
        if not 0 < self.kappa_max < 1:
            problems.append(("kappa_max", self.kappa_max, "must lie in (0, 1)"))
        if not 0 < self.alpha_max_deg < 60:
            problems.append(("alpha_max_deg", self.alpha_max_deg, "must lie in (0, 60) deg"))
        if not 0 < self.combined_kappa_max < 1:
            problems.append(("combined_kappa_max", self.combined_kappa_max,
                             "must lie in (0, 1)"))
        for name in ("n_kappa", "n_alpha", "n_combined_kappa"):
            if not 5 <= getattr(self, name) <= 2001:
                problems.append((name, getattr(self, name), "must lie in 5..2001"))
        if not self.combined_alpha_deg or any(
                not 0 < a < self.alpha_max_deg for a in self.combined_alpha_deg):
            problems.append(("combined_alpha_deg", self.combined_alpha_deg,
                             "must lie in (0, alpha_max_deg)"))
        if not 0 < self.camber_max <= 0.3:
            problems.append(("camber_max", self.camber_max, "must lie in (0, 0.3] rad"))
        if not 0 < self.camber_step <= self.camber_max / 2:
            problems.append(("camber_step", self.camber_step,
                             "must lie in (0, camber_max / 2] rad"))
        if not (3 <= self.n_camber <= 201 and self.n_camber % 2 == 1):
            problems.append(("n_camber", self.n_camber,
                             "must be odd (includes gamma = 0) and lie in 3..201"))
        if any(not 0 < a < self.alpha_max_deg for a in self.camber_alpha_deg):
            problems.append(("camber_alpha_deg", self.camber_alpha_deg,
                             "must lie in (0, alpha_max_deg)"))
        if len(self.rolling_speeds) < 3 or any(
                not (math.isfinite(v) and 0 < v <= 5) for v in self.rolling_speeds):
            problems.append(("rolling_speeds", self.rolling_speeds,
                             "need at least three multiples of vx in (0, 5]"))
        if problems:
            name, value, msg = problems[0]
            raise InputError(msg, field=f"FitSettings.{name}", value=value)


@dataclass
class FitPoints:
    """The sampled operating points and the brush's forces there, in ISO-W.

    ``kind`` is ``"kappa"`` (pure longitudinal), ``"alpha"`` (pure side slip) or
    ``"combined"``; ``Fx, Fy`` [N], ``Mz`` [N m]; ``kappa`` [1], ``alpha`` [rad], ``Fz`` [N].
    """

    kind: np.ndarray
    kappa: np.ndarray
    alpha: np.ndarray
    Fz: np.ndarray
    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray


@dataclass
class MFFit:
    """Result of :func:`fit_mf`.

    Attributes
    ----------
    coefficients : dict
        Every coefficient the ``.tir`` file carries (``FNOMIN``, ``UNLOADED_RADIUS`` and the
        MF coefficients), ISO-W.
    fitted : list of str
        The coefficients the fit adjusted (the rest are fixed; module docstring).
    errors : dict
        Per channel (:data:`CHANNELS`): ``rms`` and ``max`` of ``|MF - brush| / Fz`` (``[1]``
        for forces, ``[m]`` for ``Mz``), ``max_abs`` [N or N m] and the number of points.
    points : FitPoints
        The brush samples.
    mf : dict
        The MF's ``Fx, Fy, Mz`` at the points (arrays, same order).
    load_dependence : list of dict
        Per load: slip stiffnesses, peak friction and the pneumatic trail at small slip
        angle, brush against MF.
    at_bounds : list of str
        Fitted coefficients that ended on a bound of the fit (the data push them beyond what
        the MF form allows, e.g. ``PKY2`` when the cornering stiffness grows faster than
        linearly with the load).
    settings : FitSettings
        The sampling used.
    camber : dict
        Camber fit (:func:`fit_camber`): per load the camber stiffness of brush and MF, and the
        ``Fy``, ``Mz`` errors over the camber check grid.
    overturning : dict
        ``QSX3`` and the largest ``|Mx_MF - Mx_brush|`` on the camber check grid.
    rolling : dict
        Rolling-resistance fit (:func:`fit_rolling`), or why there is none.
    """

    coefficients: dict[str, float]
    fitted: list[str]
    errors: dict[str, dict[str, float]]
    points: FitPoints
    mf: dict[str, np.ndarray]
    load_dependence: list[dict[str, float]]
    at_bounds: list[str] = field(default_factory=list)
    settings: FitSettings = field(default_factory=FitSettings)
    camber: dict = field(default_factory=dict)
    overturning: dict = field(default_factory=dict)
    rolling: dict = field(default_factory=dict)


def _spaced(vmax: float, n: int, power: float) -> np.ndarray:
    """``n`` values in ``[-vmax, vmax]``, symmetric, denser near 0 (``sign(u) |u|^power``)."""
    u = np.linspace(-1.0, 1.0, n)
    return vmax * np.sign(u) * np.abs(u) ** power


def sample_brush(model, vx: float, T_K: float, settings: FitSettings) -> FitPoints:
    """Brush forces at the fit points (one vectorised call of the steady model), in ISO-W."""
    s = settings
    Fz_nom = model.params.Fz_nom
    kap = _spaced(s.kappa_max, s.n_kappa, 1.7)
    alp = np.radians(_spaced(s.alpha_max_deg, s.n_alpha, 1.5))
    ck = _spaced(s.combined_kappa_max, s.n_combined_kappa, 1.5)
    ca = np.radians(np.concatenate([-np.asarray(s.combined_alpha_deg),
                                    np.asarray(s.combined_alpha_deg)]))
    CK, CA = (x.ravel() for x in np.meshgrid(ck, ca))
    one = (np.concatenate([kap, np.zeros_like(alp), CK]),
           np.concatenate([np.zeros_like(kap), alp, CA]),
           np.array(["kappa"] * kap.size + ["alpha"] * alp.size + ["combined"] * CK.size))
    kappa = np.concatenate([one[0]] * len(s.loads))
    alpha = np.concatenate([one[1]] * len(s.loads))
    kind = np.concatenate([one[2]] * len(s.loads))
    Fz = np.repeat(np.asarray(s.loads, float) * Fz_nom, one[0].size)
    out = model.solve(kappa, alpha, vx, Fz, T_K)
    w = convert_wrench(Wrench(out.Fx, out.Fy, Fz, 0.0, 0.0, out.Mz), BRUSH_AXES, "iso-w")
    return FitPoints(kind, kappa, alpha, Fz, np.asarray(w.Fx), np.asarray(w.Fy),
                     np.asarray(w.Mz))


# -- the fit ----------------------------------------------------------------------------------
# (name, start, lower bound, upper bound); starts that depend on the data are filled in below.
_FX = [("PCX1", 1.6, 1.0, 3.0), ("PDX1", None, 0.05, 5.0), ("PDX2", 0.0, -2.0, 2.0),
       ("PEX1", 0.0, -20.0, 1.0), ("PEX2", 0.0, -20.0, 20.0), ("PEX3", 0.0, -20.0, 20.0),
       ("PEX4", 0.0, -1.0, 1.0), ("PKX1", None, 0.5, 200.0), ("PKX2", 0.0, -50.0, 50.0),
       ("PKX3", 0.0, -5.0, 5.0)]
_FY = [("PCY1", 1.3, 1.0, 3.0), ("PDY1", None, 0.05, 5.0), ("PDY2", 0.0, -2.0, 2.0),
       ("PEY1", 0.0, -20.0, 1.0), ("PEY2", 0.0, -20.0, 20.0), ("PKY1", None, -200.0, -0.1),
       ("PKY2", 2.0, 0.2, 20.0)]
_MZ = [("QBZ1", 10.0, 0.1, 100.0), ("QBZ2", 0.0, -50.0, 50.0), ("QBZ3", 0.0, -50.0, 50.0),
       ("QCZ1", 1.2, 0.5, 3.0), ("QDZ1", None, 0.0, 1.0), ("QDZ2", 0.0, -1.0, 1.0),
       ("QEZ1", 0.0, -50.0, 1.0), ("QEZ2", 0.0, -50.0, 50.0), ("QEZ3", 0.0, -50.0, 50.0)]
_GX = [("RBX1", 10.0, 0.0, 200.0), ("RBX2", 5.0, -100.0, 100.0), ("RCX1", 1.0, 0.2, 2.0),
       ("REX1", 0.0, -20.0, 1.0), ("REX2", 0.0, -20.0, 20.0)]
_GY = [("RBY1", 5.0, 0.0, 200.0), ("RBY2", 2.0, -100.0, 100.0), ("RCY1", 1.0, 0.2, 2.0),
       ("REY1", 0.0, -20.0, 1.0), ("REY2", 0.0, -20.0, 20.0), ("RHY1", 0.0, -0.5, 0.5),
       ("RHY2", 0.0, -0.5, 0.5)]
_SZ = [("SSZ2", 0.0, -5.0, 5.0)]

#: Weight of the penalty that keeps the curvature factors <= 1.
_E_PENALTY = 10.0


def _stage(coef: dict, spec: list, starts: dict, residual) -> list[str]:
    """Fit the coefficients of ``spec`` (others in ``coef`` fixed) by least squares, starting
    from their values in ``coef``, else in ``starts``, else in ``spec``; write them into
    ``coef``. Returns the names of those that ended on a bound."""
    from scipy.optimize import least_squares

    names = [n for n, *_ in spec]
    x0 = np.array([coef.get(n, starts.get(n, s)) for n, s, _, _ in spec], float)
    lo = np.array([b for _, _, b, _ in spec])
    hi = np.array([b for _, _, _, b in spec])
    x0 = np.clip(x0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))

    def fun(x):
        trial = dict(coef)
        trial.update(zip(names, x, strict=True))
        return residual(trial)

    res = least_squares(fun, x0, bounds=(lo, hi), x_scale="jac", method="trf",
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=4000)
    coef.update(zip(names, (float(v) for v in res.x), strict=True))
    span = hi - lo
    return [n for n, v, a, b, w in zip(names, res.x, lo, hi, span, strict=True)
            if min(v - a, b - v) <= 1e-6 * w]


def _curvature_excess(values) -> np.ndarray:
    """Penalty entries ``max(0, E - 1)`` (the MF curvature factors must be <= 1)."""
    return _E_PENALTY * np.maximum(np.concatenate([np.ravel(v) for v in values]) - 1.0, 0.0)


def fit_mf(model, vx: float, T_K: float, settings: FitSettings | None = None, *,
           grid=None, fittyp: int = 61) -> MFFit:
    """Fit MF 6.1 coefficients (ISO-W) to ``model`` (a
    :class:`~tire_brush.steady.SteadyBrush`) at forward speed ``vx`` [m/s] and background
    temperature ``T_K`` [K] (module docstring).

    ``grid`` is the friction grid the model runs on (:class:`lookup.grid.FrictionGrid`, or
    ``None``): its compound gives the tread part of the rolling resistance
    (:func:`fit_rolling`). ``fittyp`` 6 (PAC2002) fits the rolling-resistance moment without
    the load exponent ``QSY7``, which PAC2002 readers do not evaluate.
    """
    settings = settings or FitSettings()
    if fittyp not in (6, 61):
        raise InputError("must be 61 (MF 6.1) or 6 (PAC2002)", field="fittyp", value=fittyp)
    if not (math.isfinite(vx) and vx > 0):
        raise InputError("forward speed must be > 0 m/s", field="vx", value=vx)
    tire = model.params
    pts = sample_brush(model, vx, T_K, settings)
    Fz0, R0 = tire.Fz_nom, tire.patch.R0
    coef: dict[str, float] = {"FNOMIN": Fz0, "UNLOADED_RADIUS": R0, "PKY4": 2.0}
    d_grid = (np.linspace(min(settings.loads), max(settings.loads), 21) - 1.0)
    sgn = np.array([-1.0, 1.0])

    k = pts.kind == "kappa"
    a = pts.kind == "alpha"
    c = pts.kind == "combined"
    nom = np.isclose(pts.Fz, Fz0 * min(settings.loads, key=lambda x: abs(x - 1.0)))
    # starts from the data at the load nearest the nominal one
    lo_k = k & nom & (np.abs(pts.kappa) > 0)
    i = np.flatnonzero(lo_k)[np.argmin(np.abs(pts.kappa[lo_k]))]
    lo_a = a & nom & (np.abs(pts.alpha) > 0)
    j = np.flatnonzero(lo_a)[np.argmin(np.abs(pts.alpha[lo_a]))]
    Fzn = pts.Fz[i]
    starts = {
        "PDX1": float(np.max(np.abs(pts.Fx[k & nom])) / Fzn),
        "PKX1": float(pts.Fx[i] / pts.kappa[i] / Fzn),
        "PDY1": float(np.max(np.abs(pts.Fy[a & nom])) / Fzn),
        "PKY1": float(pts.Fy[j] / pts.alpha[j] / Fz0),
        "QDZ1": float(-pts.Mz[j] / pts.Fy[j] / R0),
    }

    def r_fx(p):
        q = mf._get(p)
        ex = [(q("PEX1") + q("PEX2") * d_grid + q("PEX3") * d_grid**2)
              * (1.0 - q("PEX4") * s) for s in sgn]
        return np.concatenate([(mf.pure_fx(p, pts.kappa[k], pts.Fz[k])[0] - pts.Fx[k])
                               / pts.Fz[k], _curvature_excess(ex)])

    def r_fy(p):
        q = mf._get(p)
        ey = q("PEY1") + q("PEY2") * d_grid
        return np.concatenate([(mf.pure_fy(p, pts.alpha[a], pts.Fz[a])[0] - pts.Fy[a])
                               / pts.Fz[a], _curvature_excess([ey])])

    def r_mz(p):
        q = mf._get(p)
        et = q("QEZ1") + q("QEZ2") * d_grid + q("QEZ3") * d_grid**2
        m = mf.evaluate(p, 0.0, pts.alpha[a], pts.Fz[a], combined=False).Mz
        return np.concatenate([(m - pts.Mz[a]) / (pts.Fz[a] * R0), _curvature_excess([et])])

    def r_gx(p):
        q = mf._get(p)
        e = q("REX1") + q("REX2") * d_grid
        f = mf.evaluate(p, pts.kappa[c], pts.alpha[c], pts.Fz[c]).Fx
        return np.concatenate([(f - pts.Fx[c]) / pts.Fz[c], _curvature_excess([e])])

    def r_gy(p):
        q = mf._get(p)
        e = q("REY1") + q("REY2") * d_grid
        f = mf.evaluate(p, pts.kappa[c], pts.alpha[c], pts.Fz[c]).Fy
        return np.concatenate([(f - pts.Fy[c]) / pts.Fz[c], _curvature_excess([e])])

    def r_sz(p):
        m = mf.evaluate(p, pts.kappa[c], pts.alpha[c], pts.Fz[c]).Mz
        return (m - pts.Mz[c]) / (pts.Fz[c] * R0)

    fitted: list[str] = []
    at_bounds: list[str] = []
    for spec, res in ((_FX, r_fx), (_FY, r_fy), (_MZ, r_mz), (_GX, r_gx), (_GY, r_gy),
                      (_SZ, r_sz)):
        at_bounds += _stage(coef, spec, starts, res)
        fitted += [n for n, *_ in spec]

    model_out = _evaluate_points(coef, pts)
    camber, overturning = fit_camber(model, coef, vx, T_K, settings)
    fitted += camber["fitted"]
    rolling = fit_rolling(tire, grid, coef, vx, T_K, settings, fittyp)
    fitted += rolling["fitted"]
    return MFFit(coefficients=coef, fitted=fitted, errors=fit_errors(pts, model_out),
                 points=pts, mf=model_out,
                 load_dependence=_load_dependence(model, coef, vx, T_K, settings),
                 at_bounds=at_bounds, settings=settings, camber=camber,
                 overturning=overturning, rolling=rolling)


# -- camber and overturning moment -------------------------------------------------------------
def _stats(x: np.ndarray) -> dict[str, float]:
    """RMS and largest absolute value of ``x``."""
    x = np.abs(np.asarray(x, float))
    return {"rms": float(np.sqrt(np.mean(x**2))), "max": float(x.max())}


def camber_points(model, vx: float, T_K: float, settings: FitSettings) -> dict[str, np.ndarray]:
    """The camber check grid and the brush there (one vectorised call), ISO-W.

    Rows: per load, the two inclinations ``+-camber_step`` at zero slip (the camber
    stiffness), then ``n_camber`` inclinations in ``[-camber_max, camber_max]`` at the slip
    angles ``0, +-camber_alpha_deg`` (``kappa = 0``). Keys ``kind`` (``"stiffness"`` or
    ``"grid"``), ``alpha``, ``gamma`` [rad], ``Fz``, ``Fy`` [N], ``Mx``, ``Mz`` [N m].
    """
    s = settings
    loads = np.asarray(s.loads, float) * model.params.Fz_nom
    h = s.camber_step
    g = np.linspace(-s.camber_max, s.camber_max, s.n_camber)
    a = np.radians(np.concatenate([-np.asarray(s.camber_alpha_deg)[::-1], [0.0],
                                   np.asarray(s.camber_alpha_deg)]))
    G, A = (x.ravel() for x in np.meshgrid(g, a))
    one_g = np.concatenate([[h, -h], G])
    one_a = np.concatenate([[0.0, 0.0], A])
    kind = np.array(["stiffness"] * 2 + ["grid"] * G.size)
    gamma = np.tile(one_g, loads.size)
    alpha = np.tile(one_a, loads.size)
    Fz = np.repeat(loads, one_g.size)
    out = model.solve(0.0, alpha, vx, Fz, T_K, gamma=gamma)
    w = convert_wrench(Wrench(out.Fx, out.Fy, Fz, out.Mx, 0.0, out.Mz), BRUSH_AXES, "iso-w")
    return {"kind": np.tile(kind, loads.size), "alpha": alpha, "gamma": gamma, "Fz": Fz,
            "Fy": np.asarray(w.Fy), "Mx": np.asarray(w.Mx), "Mz": np.asarray(w.Mz)}


def fit_camber(model, coef: dict, vx: float, T_K: float,
               settings: FitSettings) -> tuple[dict, dict]:
    """Camber stiffness ``PKY6, PKY7`` and the overturning couple ``QSX3``; writes them into
    ``coef`` and returns the camber and overturning reports.

    The brush's camber stiffness at each fit load, ``K_yg = dFy/d(sin gamma)`` at zero slip
    (central difference at ``+-camber_step``), is MF 6.1's ``K_yg0 = Fz (PKY6 + PKY7 dfz)``
    (Pacejka 2012 eq. (4.E30)): with ``PVY3 = PVY4 = 0`` the camber acts through the horizontal
    shift ``S_Hy = K_yg0 sin(gamma) / K_ya`` (4.E27), whose slope of ``Fy`` at zero slip is
    ``K_yg0`` exactly. ``PKY6, PKY7`` are the linear least-squares fit of ``K_yg / Fz``
    against ``dfz``. The fit is then checked over ``[-camber_max, camber_max]`` at the slip
    angles of :class:`FitSettings`: the side force (all of it, and the camber part
    ``Fy(alpha, gamma) - Fy(alpha, 0)``), and the brush's camber aligning moment, which the
    MF (its ``Mz`` camber terms 0) does not carry.

    The brush's overturning moment is ``Mx = Fy Fz / k_y`` in ISO-W (the lateral deflection of
    the belt ``Fy / k_y`` moves the load off the wheel plane; :mod:`tire_brush.steady`), which
    is the ``QSX3`` term of eq. (4.E69), ``Mx = R0 Fz QSX3 Fy / Fz0``, with
    ``QSX3 = Fz0 / (R0 k_y)`` (0 for a rigid carcass, whose ``Mx`` is 0).
    """
    tire = model.params
    Fz0, R0 = coef["FNOMIN"], coef["UNLOADED_RADIUS"]
    cp = camber_points(model, vx, T_K, settings)
    st = cp["kind"] == "stiffness"
    Fzs = cp["Fz"][st][::2]
    d = (Fzs - Fz0) / Fz0
    Fy_pm = cp["Fy"][st].reshape(-1, 2)
    K_brush = (Fy_pm[:, 0] - Fy_pm[:, 1]) / (2.0 * math.sin(settings.camber_step))
    design = np.stack([np.ones_like(d), d], axis=1)
    (pky6, pky7), *_ = np.linalg.lstsq(design, K_brush / Fzs, rcond=None)
    coef.update({"PKY6": float(pky6), "PKY7": float(pky7), "PVY3": 0.0, "PVY4": 0.0})
    K_mf = Fzs * (coef["PKY6"] + coef["PKY7"] * d)
    Mz_pm = cp["Mz"][st].reshape(-1, 2)
    rows = [{"Fz_N": float(F), "K_ygamma_per_Fz_brush": float(kb / F),
             "K_ygamma_per_Fz_mf": float(km / F), "rel_error": float(abs(km - kb) / abs(kb)),
             "camber_trail_m_brush": float(-(mz[0] - mz[1]) / (fy[0] - fy[1]))}
            for F, kb, km, mz, fy in zip(Fzs, K_brush, K_mf, Mz_pm, Fy_pm, strict=True)]
    # the check over the camber range
    gr = cp["kind"] == "grid"
    a, g, F = cp["alpha"][gr], cp["gamma"][gr], cp["Fz"][gr]
    Fy_b, Mz_b = cp["Fy"][gr], cp["Mz"][gr]
    mfo = mf.evaluate(coef, 0.0, a, F, gamma=g)
    ref = np.flatnonzero(g == 0.0)
    key = {(x, f): i for i, x, f in zip(ref, a[ref], F[ref], strict=True)}
    i0 = np.array([key[(x, f)] for x, f in zip(a, F, strict=True)])
    dFy_b, dFy_mf = Fy_b - Fy_b[i0], mfo.Fy - mfo.Fy[i0]
    camber = {
        "fitted": ["PKY6", "PKY7"], "gamma_max_rad": settings.camber_max, "loads": rows,
        "stiffness_rel_error_max": max(r["rel_error"] for r in rows),
        "errors": {"Fy": _stats((mfo.Fy - Fy_b) / F),
                   "Fy_camber_part": _stats((dFy_mf - dFy_b) / F),
                   "Mz": _stats((mfo.Mz - Mz_b) / F),
                   "Mz_camber_part_brush": _stats((Mz_b - Mz_b[i0]) / F)},
        "points": {"alpha_rad": a.tolist(), "gamma_rad": g.tolist(), "Fz_N": F.tolist()},
    }
    # overturning moment
    coef.update({"QSX1": 0.0, "QSX2": 0.0,
                 "QSX3": 0.0 if model.rigid_carcass else Fz0 / (R0 * tire.carcass.k_y)})
    Mx_mf = mf.overturning_mx(coef, cp["Fy"], cp["Fz"], cp["gamma"])
    overturning = {"QSX3": coef["QSX3"], "k_y_N_per_m": tire.carcass.k_y,
                   "rigid_carcass": bool(model.rigid_carcass),
                   "max_abs_error_Nm": float(np.max(np.abs(Mx_mf - cp["Mx"]))),
                   "max_abs_Mx_Nm": float(np.max(np.abs(cp["Mx"])))}
    return camber, overturning


# -- rolling resistance ------------------------------------------------------------------------
def fit_rolling(params, grid, coef: dict, vx: float, T_K: float, settings: FitSettings,
                fittyp: int = 61) -> dict:
    """``QSY1, QSY3`` and (MF 6.1) ``QSY7`` of the rolling-resistance moment, written into
    ``coef``; returns the report.

    The model is :func:`tire_brush.rolling_resistance.rolling_resistance` at the fit
    temperature (tread and carcass at ``T_K``), ``My = -f_r Fz R_e`` in ISO-W, at the fit
    loads and the speeds ``rolling_speeds * vx``; the MF is eq. (4.E70)
    (:func:`~tire_brush.magic_formula.rolling_my`) with ``V_ref = LONGVL = vx``, fitted by
    least squares on ``dMy / (R0 Fz)``. The compound of the tread term is the one
    :func:`~tire_brush.rolling_resistance.rolling_table` accepts for the tire on ``grid``
    (the grid's compound, checked against its recorded parameters; the tire file's
    ``[rolling_resistance]`` table needed): when it gives none, ``QSY*`` stay 0 and the report
    says why. PAC2002 (``fittyp`` 6) has no load exponent: ``QSY7`` stays 0.
    """
    from scipy.optimize import least_squares

    from lookup.compound import load_compound

    from .rolling_resistance import rolling_resistance, rolling_table

    names = ["QSY1", "QSY3", "QSY7"] if fittyp == 61 else ["QSY1", "QSY3"]
    table, why = rolling_table(params, grid)
    if table is None:
        return {"fitted": [], "why": why}
    compound = load_compound(table.compound)
    V = np.asarray(settings.rolling_speeds, float) * vx
    loads = np.asarray(settings.loads, float) * params.Fz_nom
    VV, FF = (x.ravel() for x in np.meshgrid(V, loads))
    rr = rolling_resistance(params, compound, VV, FF, T_K)
    My = np.asarray(rr.My)
    R0 = coef["UNLOADED_RADIUS"]

    def residual(x):
        trial = dict(coef, **dict(zip(names, x, strict=True)))
        return (mf.rolling_my(trial, FF, VV, vx) - My) / (R0 * FF)

    f_nom = float(np.median(rr.f_r)) * params.R_e / R0
    x0 = np.array([f_nom, 0.0, 1.0][:len(names)])
    res = least_squares(residual, x0, x_scale="jac", method="trf", xtol=1e-14, ftol=1e-14,
                        gtol=1e-14, max_nfev=2000)
    coef.update({n: float(v) for n, v in zip(names, res.x, strict=True)})
    diff = mf.rolling_my(coef, FF, VV, vx) - My
    return {"fitted": names, "compound": table.compound, "T_K": float(T_K),
            "R_e_m": float(params.R_e), "speeds_m_s": V.tolist(), "loads_N": loads.tolist(),
            "errors": {**_stats(diff / (R0 * FF)), "rel_max": float(np.max(np.abs(diff / My))),
                       "max_abs_Nm": float(np.max(np.abs(diff)))},
            "f_r_min": float(rr.f_r.min()), "f_r_max": float(rr.f_r.max())}


def _evaluate_points(coef: dict, pts: FitPoints) -> dict[str, np.ndarray]:
    """MF forces at the fit points (the combined-slip equations, which reduce to the pure-slip
    ones at the pure points: the weights are 1 there and ``S_H = S_V = 0``)."""
    out = mf.evaluate(coef, pts.kappa, pts.alpha, pts.Fz)
    return {"Fx": np.asarray(out.Fx), "Fy": np.asarray(out.Fy), "Mz": np.asarray(out.Mz)}


def fit_errors(pts: FitPoints, model_out: dict[str, np.ndarray]) -> dict[str, dict]:
    """RMS and largest ``|MF - brush| / Fz`` per channel (:data:`CHANNELS`)."""
    errors = {}
    for ch in CHANNELS:
        q, kind = ch.split("_")
        sel = pts.kind == kind if kind == "combined" else pts.kind == (
            "kappa" if q == "Fx" else "alpha")
        diff = model_out[q][sel] - getattr(pts, q)[sel]
        rel = np.abs(diff) / pts.Fz[sel]
        errors[ch] = {"rms": float(np.sqrt(np.mean(rel**2))), "max": float(rel.max()),
                      "max_abs": float(np.abs(diff).max()), "n": int(sel.sum()),
                      "unit": "m" if q == "Mz" else "1"}
    return errors


def _load_dependence(model, coef: dict, vx: float, T_K: float,
                     settings: FitSettings) -> list[dict[str, float]]:
    """Slip stiffnesses (central differences at 1e-3), peak friction over the sampled sweep and
    the pneumatic trail at 1e-3 rad, brush against MF, per load."""
    h = 1e-3
    loads = np.asarray(settings.loads, float) * model.params.Fz_nom
    kap = np.concatenate([np.tile([h, -h, 0.0, 0.0], loads.size)])
    alp = np.concatenate([np.tile([0.0, 0.0, h, -h], loads.size)])
    Fz = np.repeat(loads, 4)
    out = model.solve(kap, alp, vx, Fz, T_K)
    w = convert_wrench(Wrench(out.Fx, out.Fy, Fz, 0.0, 0.0, out.Mz), BRUSH_AXES, "iso-w")
    Fx, Fy, Mz = (np.asarray(x).reshape(-1, 4) for x in (w.Fx, w.Fy, w.Mz))
    pts = sample_brush(model, vx, T_K, FitSettings(
        loads=settings.loads, kappa_max=settings.kappa_max, n_kappa=201,
        alpha_max_deg=settings.alpha_max_deg, n_alpha=201,
        combined_kappa_max=settings.combined_kappa_max, n_combined_kappa=5,
        combined_alpha_deg=settings.combined_alpha_deg[:1]))
    mfo = _evaluate_points(coef, pts)
    rows = []
    for n, F in enumerate(loads):
        kx = (pts.kind == "kappa") & (pts.Fz == F)
        ay = (pts.kind == "alpha") & (pts.Fz == F)
        _, Kx = mf.pure_fx(coef, 0.0, F)
        _, Ky, *_ = mf.pure_fy(coef, 0.0, F)
        t_mf = -mf.evaluate(coef, 0.0, h, F, combined=False).Mz / mf.pure_fy(coef, h, F)[0]
        rows.append({
            "Fz_N": float(F),
            "C_Fkappa_per_Fz_brush": float((Fx[n, 0] - Fx[n, 1]) / (2 * h) / F),
            "C_Fkappa_per_Fz_mf": float(Kx / F),
            "C_Falpha_per_Fz_brush": float(-(Fy[n, 2] - Fy[n, 3]) / (2 * h) / F),
            "C_Falpha_per_Fz_mf": float(-Ky / F),
            "mu_x_peak_brush": float(np.max(np.abs(pts.Fx[kx])) / F),
            "mu_x_peak_mf": float(np.max(np.abs(mfo["Fx"][kx])) / F),
            "mu_y_peak_brush": float(np.max(np.abs(pts.Fy[ay])) / F),
            "mu_y_peak_mf": float(np.max(np.abs(mfo["Fy"][ay])) / F),
            "trail_m_brush": float(-(Mz[n, 2] - Mz[n, 3]) / (Fy[n, 2] - Fy[n, 3])),
            "trail_m_mf": float(t_mf),
        })
    return rows
