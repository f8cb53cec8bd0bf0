r"""The brush tire on a wet road: the wet branch of a grid at one water depth and footprint time.

The wet branch of a grid (:mod:`lookup.grid.wet`) tabulates the friction over the water depth
and the drainage time t_drain besides (slip speed, temperature, pressure). A rolling tire
fixes both for all its tread elements at one operating point:

* the water depth d on the road (an input of the test: 1 mm in UN R117 Annex 5);
* the drainage time: a tread element stays in the footprint for t_fp = 2a / V_r (patch
  length 2a at the road-carried load, rolling speed V_r), and the water must leave its
  macroasperity contacts within that time. The grid's axis is t_drain = t_fp (D / 2R)^2 with
  R the drainage radius (Stefan's law: only t / R^2 matters; :mod:`lookup.wet.friction`
  item 2). Default R = D / 2: the water leaves each macroasperity contact into the road's
  open macrotexture (which is why the regulation prescribes the texture depth), so
  t_drain = t_fp. A closed road texture that drains only through the tread grooves would
  need R of the order of a tread block's half-width (~10 mm: t_drain ~ t_fp / 400); the
  study spec can set it.

For each rolling speed this gives a :class:`~tire_brush.friction.BranchTable` on the dry
grid's own nodes (log10 v, T, log10 p): mu_cold and mu_hot are the wet branch
(:meth:`lookup.grid.wet.WetGrid.interpolate` at d and t_drain, exact at the v, T, p nodes), so
the steady brush reads the wet friction with the same multilinear interpolation and clamping
as the dry one. dT_flash is the dry grid's (the wet branch does not store a flash temperature;
the steady brush reports it and does not use it).

Hydroplaning (:mod:`tire_brush.hydroplaning`, Horne's lift): the share L of the load carried
by the water wedge does not press the tread on the road. The tire is solved at the road load
(1 - L) Fz, and the force it transmits, divided by the wheel load Fz, is

.. math:: F_x / F_z = (1 - L)\, \mu_{brush}(\kappa, V, (1 - L) F_z, T).

With the regulation's 1 mm of water and a new tread (grooves 8 mm deep, void ratio 0.3,
road texture 0.7 mm) the grooves and the texture take all the water (2.4 + 0.7 mm > 1 mm), so
L = 0 in the test: the lift acts on deeper water or worn treads.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from tirefric.errors import InputError

from .friction import BranchTable, GridFriction
from .hydroplaning import lifted_share
from .params import TireParams
from .steady import SteadyBrush


@dataclass(frozen=True)
class WetRoad:
    """Water on the road and what drains it.

    Attributes
    ----------
    water_depth : float
        Water film depth [m] (volume per nominal road area), >= 0; 0 is the dry road.
    texture_depth : float
        Mean texture depth of the road [m] (water it holds below the tire), >= 0.
    tread_depth : float
        Groove depth of the tire [m], >= 0 (the hydroplaning depth factor).
    drainage_radius : float or None
        Radius [m] over which the water leaves a contact (module docstring); None: D / 2.
    """

    water_depth: float
    texture_depth: float = 0.0
    tread_depth: float = 8e-3
    drainage_radius: float | None = None

    def __post_init__(self) -> None:
        for name in ("water_depth", "texture_depth", "tread_depth"):
            x = getattr(self, name)
            if not (isinstance(x, int | float) and math.isfinite(x) and x >= 0):
                raise InputError("must be a finite length >= 0 [m]", field=name, value=x)
        r = self.drainage_radius
        if r is not None and not (math.isfinite(r) and r > 0):
            raise InputError("must be a finite length > 0 [m]", field="drainage_radius",
                             value=r)


def footprint_time(params: TireParams, Fz: float, V: float) -> float:
    """Time t_fp = 2a / |V| [s] a tread element spends in the footprint at load Fz [N] and
    rolling speed V [m/s] (patch half-length a of Pacejka 2012 eq. A3.7)."""
    a, _ = params.patch.size(float(Fz))
    if not (abs(V) > 0 and a > 0):
        raise InputError("needs a load > 0 N and a rolling speed != 0 m/s", field="V",
                         value=(Fz, V))
    return 2.0 * a / abs(float(V))


def drainage_time(t_fp: float, D: float, drainage_radius: float | None = None) -> float:
    """The grid's drainage time t_drain = t_fp (D / 2R)^2 [s] (:mod:`lookup.grid.wet`)."""
    R = 0.5 * D if drainage_radius is None else drainage_radius
    return t_fp * (D / (2.0 * R)) ** 2


def wet_branch_table(dry_grid: Any, wet_grid: Any, water_depth: float, t_drain: float,
                     s0: float | None = None) -> BranchTable:
    """Branch table of the wet friction at ``water_depth`` [m] and ``t_drain`` [s] on the dry
    grid's nodes (module docstring). ``s0``: blending length [m], default the grid's."""
    src = GridFriction(dry_grid, s0=s0)
    lv, T, lp = src.table_nodes()
    for name, a, b in (("log10_v", lv, wet_grid.axes["log10_v"]), ("T", T, wet_grid.axes["T"]),
                       ("log10_p", lp, wet_grid.axes["log10_p"])):
        if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-9):
            raise InputError("the wet branch has other nodes than the dry grid", field=name)
    V, TT, P = np.meshgrid(10.0 ** lv, T, 10.0 ** lp, indexing="ij")
    w = wet_grid.interpolate(V, TT, P, water_depth, t_drain)
    dry = src.node_values()
    values = np.stack([w["mu_wet_cold"], w["mu_wet_hot"], dry[..., 2]], axis=-1)
    desc = {**src.describe(), "wet": {"water_depth_m": float(water_depth),
                                      "t_drain_s": float(t_drain),
                                      "wet_hash": str(wet_grid.meta.get("hash", ""))}}
    return BranchTable(lv, T, lp, values, src.s0, desc)


class WetTireFriction:
    """``Fx/Fz(kappa, vx, Fz, T_K)`` of the steady brush tire on a wet road (module docstring).

    One steady brush per rolling speed (its table at that speed's drainage time), built on
    first use and kept. A dry road (``water_depth = 0``) reads the dry grid itself.

    Parameters
    ----------
    params
        Tire parameters.
    dry_grid, wet_grid
        The grid (:class:`lookup.grid.FrictionGrid`) and its wet branch
        (:class:`lookup.grid.wet.WetGrid`; None allowed for a dry road).
    road
        Water depth, texture and drainage.
    hydroplaning
        Apply the lift of :mod:`tire_brush.hydroplaning` (default True).
    n_elements
        Cells of the steady brush (None: its default).
    """

    def __init__(self, params: TireParams, dry_grid: Any, wet_grid: Any, road: WetRoad, *,
                 hydroplaning: bool = True, n_elements: int | None = None) -> None:
        if road.water_depth > 0 and wet_grid is None:
            raise InputError("a wet road needs a grid with a wet branch", field="grid")
        self.params, self.dry_grid, self.wet_grid, self.road = params, dry_grid, wet_grid, road
        self.hydroplaning = bool(hydroplaning)
        self._kw = {} if n_elements is None else {"n_elements": n_elements}
        self._dry = SteadyBrush(params, dry_grid, **self._kw) if road.water_depth == 0 else None
        self._by_speed: dict[tuple[float, float], SteadyBrush] = {}
        self.D = float(dry_grid.meta["D_m"])

    def lifted_share(self, vx: Any) -> np.ndarray:
        """Share of the load carried by the water [1] at forward speed ``vx`` [m/s]."""
        if not self.hydroplaning or self.road.water_depth == 0:
            return np.zeros(np.shape(vx))
        return lifted_share(vx, self.road.water_depth, self.params.patch.p_inflation,
                            self.road.tread_depth, self.params.tread.void_ratio,
                            self.road.texture_depth)

    def t_drain(self, vx: float, Fz_road: float) -> float:
        """Drainage time [s] at forward speed ``vx`` [m/s] and road load ``Fz_road`` [N]."""
        return drainage_time(footprint_time(self.params, Fz_road, vx), self.D,
                             self.road.drainage_radius)

    def brush(self, vx: float, Fz_road: float) -> SteadyBrush:
        """The steady brush with the friction of speed ``vx`` and road load ``Fz_road``."""
        if self._dry is not None:
            return self._dry
        key = (float(vx), float(Fz_road))
        b = self._by_speed.get(key)
        if b is None:
            table = wet_branch_table(self.dry_grid, self.wet_grid, self.road.water_depth,
                                     self.t_drain(vx, Fz_road))
            b = self._by_speed[key] = SteadyBrush(self.params, table, **self._kw)
        return b

    def __call__(self, kappa: Any, vx: Any, Fz: Any, T_K: Any) -> np.ndarray:
        """``Fx / Fz`` [1] (force per wheel load), numpy broadcasting."""
        k, v, f, t = np.broadcast_arrays(*(np.asarray(a, float) for a in (kappa, vx, Fz, T_K)))
        if (f <= 0).any():
            raise InputError("needs loads > 0 N", field="Fz")
        if (v <= 0).any():
            raise InputError("needs forward speeds > 0 m/s", field="vx")
        out = np.zeros(k.shape)
        pairs = np.stack([v.ravel(), f.ravel()], axis=1)
        for vv, ff in np.unique(pairs, axis=0):
            sel = (v == vv) & (f == ff)
            keep = 1.0 - float(self.lifted_share(vv))
            if keep <= 0.0:
                continue  # fully hydroplaning: no road contact, no force
            brush = self.brush(vv, keep * ff)
            out[sel] = keep * brush.fx_over_fz(k[sel], vv, keep * ff, t[sel])
        return out


def peak_fx_over_fz(fx_over_fz: Callable, vx: float, Fz: float, T_K: float,
                     n_scan: int = 121) -> tuple[float, float]:
    """Peak braking ``|Fx/Fz|`` and its slip on ``kappa`` in [-1, 0] (a scan graded towards
    small slip, then 41 points between the neighbours of the best): the trailer method's
    peak BFC."""
    k = -np.linspace(0.0, 1.0, n_scan) ** 2
    mu = -np.asarray(fx_over_fz(k, vx, Fz, T_K), float)
    i = int(np.argmax(mu))
    if 0 < i < n_scan - 1:
        lo, hi = k[i + 1], k[i - 1]
        kk = np.linspace(lo, hi, 41)
        m2 = -np.asarray(fx_over_fz(kk, vx, Fz, T_K), float)
        j = int(np.argmax(m2))
        return float(m2[j]), float(kk[j])
    return float(mu[i]), float(k[i])
