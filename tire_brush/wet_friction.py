r"""The brush tire on a wet road: the wet branch of a grid at one water depth and footprint time.

The wet branch of a grid (:mod:`lookup.grid.wet`) tabulates the friction over the water depth
and the drainage time t_drain besides (slip speed, temperature, pressure). A rolling tire
fixes both for all its tread elements at one operating point:

* the water depth d on the road (an input of the test: 1 mm in UN R117 Annex 5);
* the drainage time: the water film between tread and road is carried through the footprint
  at the entrainment speed U = (|v_x| + |V_r|) / 2, the mean of the two surfaces' speeds
  relative to the patch (the wedge term of Reynolds' equation: Reynolds, Phil. Trans. R.
  Soc. 177 (1886) 157; Hamrock, Schmid & Jacobson, *Fundamentals of Fluid Film Lubrication*,
  2nd ed. (2004), ch. 7), so it spends t_fp = 2a / U under the patch (patch length 2a at the
  road-carried load): 2a / v_x when the wheel rolls freely, twice that when it is locked
  (the road moves through the patch, the tread does not), and the water must leave the
  macroasperity contacts within that time. The grid's axis is t_drain = t_fp (D / 2R)^2 with
  R the drainage radius (Stefan's law: only t / R^2 matters; :mod:`lookup.wet.friction`
  item 2). Default R = D / 2: the water leaves each macroasperity contact into the road's
  open macrotexture (which is why the regulation prescribes the texture depth), so
  t_drain = t_fp. A closed road texture that drains only through the tread grooves would
  need R of the order of a tread block's half-width (~10 mm: t_drain ~ t_fp / 400); the
  study spec can set it.

For each operating point (forward speed, slip, road load) this gives a
:class:`~tire_brush.friction.BranchTable` on the dry grid's own nodes (log10 v, T, log10 p):
mu_cold and mu_hot are the wet branch (:meth:`lookup.grid.wet.WetGrid.interpolate` at d and
t_drain, exact at the v, T, p nodes; the tables at the grid's drainage-time nodes are built
once and blended linearly in log10 t_drain, which is exact because the wet branch is
multilinear in it), so
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
from .hydroplaning import lifted_share, load_lift
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


def entrainment_speed(vx: float, V_r: float) -> float:
    """U = (|vx| + |V_r|) / 2 [m/s]: the speed at which the water film is carried through the
    footprint (module docstring), from the forward speed vx and the rolling speed V_r."""
    return 0.5 * (abs(float(vx)) + abs(float(V_r)))


def footprint_time(params: TireParams, Fz: float, U: float) -> float:
    """Time t_fp = 2a / |U| [s] the water film spends under the footprint at load Fz [N] and
    entrainment speed U [m/s] (:func:`entrainment_speed`; patch half-length a of Pacejka
    2012 eq. A3.7)."""
    a, _ = params.patch.size(float(Fz))
    if not (abs(U) > 0 and a > 0):
        raise InputError("needs a load > 0 N and an entrainment speed != 0 m/s", field="U",
                         value=(Fz, U))
    return 2.0 * a / abs(float(U))


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
    partial_lift
        Add the partial lift of the entering film below full hydroplaning (Horne's
        (V / V_p)^2 with Gallaway's V_p, :func:`tire_brush.hydroplaning.load_lift`); default
        False: measured against the regulation's reference-tire windows it lifts far too
        much on the test's 1 mm (docs/physics.md sec. 7a), so it is a study option, not the
        model (the transient core does not carry it).
    n_elements
        Cells of the steady brush (None: its default).
    """

    def __init__(self, params: TireParams, dry_grid: Any, wet_grid: Any, road: WetRoad, *,
                 hydroplaning: bool = True, partial_lift: bool = False,
                 n_elements: int | None = None) -> None:
        if road.water_depth > 0 and wet_grid is None:
            raise InputError("a wet road needs a grid with a wet branch", field="grid")
        self.params, self.dry_grid, self.wet_grid, self.road = params, dry_grid, wet_grid, road
        self.hydroplaning = bool(hydroplaning)
        self.partial_lift = bool(partial_lift)
        self._kw = {} if n_elements is None else {"n_elements": n_elements}
        self._dry = SteadyBrush(params, dry_grid, **self._kw) if road.water_depth == 0 else None
        self._by_point: dict[tuple[float, float, float], SteadyBrush] = {}
        self._node_tables: dict[int, BranchTable] = {}
        self.D = float(dry_grid.meta["D_m"])

    def lifted_share(self, vx: Any) -> np.ndarray:
        """Share of the load carried by the water [1] at forward speed ``vx`` [m/s]."""
        if not self.hydroplaning or self.road.water_depth == 0:
            return np.zeros(np.shape(vx))
        law = load_lift if self.partial_lift else lifted_share
        return law(vx, self.road.water_depth, self.params.patch.p_inflation,
                   self.road.tread_depth, self.params.tread.void_ratio,
                   self.road.texture_depth)

    def t_drain(self, vx: float, Fz_road: float, kappa: float = 0.0) -> float:
        """Drainage time [s] at forward speed ``vx`` [m/s], road load ``Fz_road`` [N] and
        longitudinal slip ``kappa`` (rolling speed V_r = vx (1 + kappa); the film passes the
        footprint at the entrainment speed, module docstring)."""
        U = entrainment_speed(vx, float(vx) * (1.0 + float(kappa)))
        return drainage_time(footprint_time(self.params, Fz_road, U), self.D,
                             self.road.drainage_radius)

    def _node_table(self, i: int) -> BranchTable:
        b = self._node_tables.get(i)
        if b is None:
            t = 10.0 ** float(self.wet_grid.axes["log10_t_drain"][i])
            b = self._node_tables[i] = wet_branch_table(self.dry_grid, self.wet_grid,
                                                        self.road.water_depth, t)
        return b

    def table(self, t_drain: float) -> BranchTable:
        """The wet branch table at ``t_drain`` [s]: the tables at the two neighbouring
        drainage-time nodes blended linearly in log10 t_drain (clamped at the axis ends),
        equal to :func:`wet_branch_table` at ``t_drain`` (the branch is multilinear in it)."""
        ax = self.wet_grid.axes["log10_t_drain"]
        lt = float(np.clip(np.log10(t_drain), ax[0], ax[-1]))
        i = int(np.clip(np.searchsorted(ax, lt, side="right") - 1, 0, ax.size - 2))
        f = (lt - ax[i]) / (ax[i + 1] - ax[i])
        t0, t1 = self._node_table(i), self._node_table(i + 1)
        if f == 0.0:
            return t0
        if f == 1.0:
            return t1
        vals = (1.0 - f) * t0.values + f * t1.values
        vals[..., 2] = t0.values[..., 2]  # dT_flash: the dry grid's at every drainage time
        desc = {**t0.description,
                "wet": {**t0.description["wet"], "t_drain_s": float(t_drain)}}
        return BranchTable(t0.log10_v, t0.T, t0.log10_p, vals, t0.s0, desc)

    def brush(self, vx: float, Fz_road: float, kappa: float = 0.0) -> SteadyBrush:
        """The steady brush with the friction of forward speed ``vx``, road load ``Fz_road``
        and slip ``kappa`` (which set the drainage time)."""
        if self._dry is not None:
            return self._dry
        t = self.t_drain(vx, Fz_road, kappa)
        key = (float(vx), float(Fz_road), float(t))
        b = self._by_point.get(key)
        if b is None:
            b = self._by_point[key] = SteadyBrush(self.params, self.table(t), **self._kw)
        return b

    def __call__(self, kappa: Any, vx: Any, Fz: Any, T_K: Any) -> np.ndarray:
        """``Fx / Fz`` [1] (force per wheel load), numpy broadcasting."""
        k, v, f, t = np.broadcast_arrays(*(np.asarray(a, float) for a in (kappa, vx, Fz, T_K)))
        if (f <= 0).any():
            raise InputError("needs loads > 0 N", field="Fz")
        if (v <= 0).any():
            raise InputError("needs forward speeds > 0 m/s", field="vx")
        out = np.zeros(k.shape)
        cols = [v.ravel(), f.ravel()] if self._dry is not None else [v.ravel(), f.ravel(),
                                                                       k.ravel()]
        for row in np.unique(np.stack(cols, axis=1), axis=0):
            vv, ff = row[0], row[1]
            sel = (v == vv) & (f == ff)
            if self._dry is None:
                sel &= k == row[2]
            keep = 1.0 - float(self.lifted_share(vv))
            if keep <= 0.0:
                continue  # fully hydroplaning: no road contact, no force
            brush = self.brush(vv, keep * ff, float(row[2]) if self._dry is None else 0.0)
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
