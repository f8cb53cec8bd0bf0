r"""Persson friction on a wet road: sealing, squeeze-out and the lubricant, cold and hot.

:class:`WetPerssonFriction` is the dry engine (:class:`lookup.friction.PerssonFriction`,
review eqs. 17-21) with three changes at every evaluation, on both branches:

1. **Sealing** (:mod:`lookup.wet.sealing`): from the dry contact fraction P(q) of the point
   the sealing wavenumber q_c (P(q_c) = 0.42) is found, and the spectrum C(q) is replaced by
   the water-smoothed C_wet(q) = r(q; q_c, d) C(q) of the water film depth d. The same
   integrals (eqs. 17-20) then give mu_visc and the macro-contact fraction P_wet(q_m). The
   smoother spectrum also gives a larger P_wet(q1), but the extra area is rubber pressed on
   the flat water surfaces of the pools, where there is no adhesive shear: the real
   (rubber-road) contact area of the adhesive term stays the dry P(q1) (the road's asperity
   tops, above the pools' fill level, are unchanged). The load the pool water carries would
   lower it further (review sec. 8: ~10 % of the load in sealed regions); that is not
   modelled, so the adhesive term is an upper bound.
2. **Squeeze-out** (:mod:`lookup.wet.squeeze`): the adhesive term sigma_f A/A0 / sigma0 is
   multiplied by the dry share w = w_macro w_asp of the real contact. w_macro: the macro
   contact drained after the available time, the macroasperity contact time D / v for a
   sliding block (``t_contact=None``), or a given time (a tire's tread element in the
   footprint: patch length over the entrainment speed). w_asp: the share of the real
   contact whose film collapses within the asperity contacts' own lifetime at the sliding
   speed v (pi / q1 over v; Stefan's law, :func:`lookup.wet.squeeze.asperity_dry_share`),
   which depends on v, T and the pressure but not on the available time. The water drains
   over the radius R (``drainage_radius``; default D/2, the macroasperity contact). In the
   squeeze-out model the time enters only as t / R^2 (Stefan's law), so a table over the
   *drainage time* t_drain = t (D / 2R)^2 at R = D/2 serves any drainage radius: a tire
   whose water must leave a tread element of half-length R_b during the footprint time t_fp
   reads it at t_drain = t_fp (D / 2 R_b)^2.
3. **Lubricant** (:mod:`lookup.wet.water`): the viscosity law in the squeeze-out; soapy water
   switches the adhesive term off (w = 0).

At water depth 0 none of this applies and the result is the dry engine's, bit for bit.

**Flash temperature on a wet road** (the hot branch). The heat model is the dry one
(:mod:`lookup.flash_temperature`): frictional heat goes into the rubber and, through the
contact, into the road; the water is *not* treated as a heat sink inside the contact. Reason:
inside a macroasperity contact the water left is a film of the interfacial separation u_bar
(micrometres, :mod:`lookup.wet.squeeze`), whose heat capacity per area rho_w c_w u_bar
(~4e6 J/(m^3 K) x 1e-6 m = 4 J/(m^2 K)) is small against what the rubber takes up during the
contact time, e_rubber sqrt(t_c) (~600 W s^0.5/(m^2 K) x sqrt(1e-3 s) ~ 20 J/(m^2 K)), and the
sealed pools lie outside the real contact where the heat is made. Water on the road does
change the *background* temperature T0 of the tread and road (review sec. 5.1: T0 depends on
"whether the road is dry or wet"); that is an input (the grid's T axis), not part of this
model. The squeeze-out weight is evaluated with the water at T0 and with the engine's G(q) at
the evaluated state (the heated modulus on the hot branch).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tirefric.errors import InputError

from ..contact import Phi, contact_fraction
from ..friction import PerssonFriction
from .sealing import SealingSettings, shared_sealed_spectrum
from .squeeze import S_NODES, asperity_dry_share, dry_share, mean_separation
from .water import Lubricant, check_water_depth


@dataclass
class WetPerssonFriction(PerssonFriction):
    """The Persson engine on a wet road (module docstring).

    Parameters
    ----------
    compound, surface, settings
        As :class:`lookup.friction.PerssonFriction`.
    depths : sequence of float
        Water film depths [m] (volume of water per unit nominal road area; 0 = dry) for which
        the sealed spectra are prepared; :attr:`depth_index` selects one.
    lubricant : Lubricant
    sealing : SealingSettings
    t_contact : float or None
        Time available for squeeze-out [s]; None: the sliding block's D / v.
    adhesive_weight : float or None
        Force the dry share w (0 or 1 for the grid's end-point solves); None: squeeze-out.
    drainage_radius : float or None
        Radius [m] over which the water drains; None: D/2.
    """

    depths: Any = (1e-3,)
    lubricant: Lubricant = field(default_factory=Lubricant)
    sealing: SealingSettings = field(default_factory=SealingSettings)
    t_contact: float | None = None
    adhesive_weight: float | None = None
    drainage_radius: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        self.depths = check_water_depth(self.depths)
        self.surface.require_D()  # squeeze-out drains a macroasperity contact of diameter D
        if self.drainage_radius is not None and not (np.isfinite(self.drainage_radius)
                                                     and self.drainage_radius > 0):
            raise InputError("drainage radius must be finite and > 0 [m]",
                             field="wet.drainage_radius", value=self.drainage_radius)
        hm = None
        if getattr(self.surface, "height_map", None) is not None:
            from ..topography import read_height_map

            m = read_height_map(self.surface.height_map)
            hm = (m.heights, m.dx, m.dy)
        # one table per road and process: its rows do not depend on the compound
        self.sealed = shared_sealed_spectrum(self.surface.psd, self.q, self.depths,
                                             self.sealing, hm)
        self.depth_index = 0
        self.last_w = np.zeros(0)
        self.last_squeeze: tuple | None = None
        self.last_asperity = np.ones(0)
        self._cold_state: tuple | None = None  # the last cold evaluation's squeeze-out inputs

    def at(self, depth_index: int, t_contact: float | None = None,
           adhesive_weight: float | None = None) -> WetPerssonFriction:
        """Select the depth node, the available time and an optional forced weight (in place)."""
        if not 0 <= depth_index < self.depths.size:
            raise InputError("no such water-depth node", field="depth_index", value=depth_index)
        if t_contact is not None and not (np.isfinite(t_contact) and t_contact > 0):
            raise InputError("contact time must be finite and > 0 [s]", field="t_contact",
                             value=t_contact)
        self.depth_index, self.t_contact = depth_index, t_contact
        self.adhesive_weight = adhesive_weight
        self.last_squeeze = None
        self._kernels = {}
        return self

    @property
    def depth(self) -> float:
        return float(self.depths[self.depth_index])

    def describe(self) -> dict[str, Any]:
        d = super().describe()
        d["wet"] = {"lubricant": self.lubricant.describe(), "sealing": self.sealed.describe(),
                    "squeeze_out": "lookup.wet.squeeze (Lorenz & Persson, Eur. Phys. J. E 32 "
                                   "(2010) 281; Yang & Persson, J. Phys.: Condens. Matter 20 "
                                   "(2008) 215214)",
                    "flash_temperature": "dry heat model; water not a heat sink in the "
                                         "contact (lookup.wet.friction docstring)"}
        return d

    def _evaluate(self, v: np.ndarray, T0: np.ndarray, sigma0: np.ndarray,
                  dT: np.ndarray | None, outside: bool = False) -> dict[str, np.ndarray]:
        if self.depth == 0.0:
            self.last_w = np.ones(v.size)
            return super()._evaluate(v, T0, sigma0, dT, outside)
        la, T_surf, T_q = self._temperatures(T0, dT)
        ang = self._angular(v, la, T_q, outside)
        A_I, A_2 = ang[0], ang[1]
        s2 = (1.0 / sigma0**2)[:, None]
        G_dry = self._G(0.125 * self.F * A_2 * s2)
        P_dry = contact_fraction(self.area_c * G_dry)
        # sealing wavenumber: the largest q with P >= p_c (P decreases with q), ln-q linear
        p_c = self.sealing.p_c
        above = P_dry >= p_c
        k = above.sum(axis=1) - 1  # last node with P >= p_c (node 0 always: P(q0) = 1)
        kk = np.minimum(k, self.q.size - 2)
        Pa, Pb = P_dry[np.arange(v.size), kk], P_dry[np.arange(v.size), kk + 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = np.clip((Pa - p_c) / (Pa - Pb), 0.0, 1.0)
        lq = np.log(self.q)
        q_c = np.exp(lq[kk] + frac * (lq[kk + 1] - lq[kk]))
        q_c = np.where(k >= self.q.size - 1, self.q[-1], q_c)
        q_c = np.where(k == 0, 0.0, q_c)  # falls below p_c before the first resolved node
        r = self.sealed.ratio(q_c, self.depth_index)
        F_wet = self.F * r
        g = 0.125 * F_wet * A_2 * s2
        G = self._G(g)
        gg = g[:, 1:] + g[:, :-1]
        c_area = self.area_c
        P = contact_fraction(c_area * G)
        ag = A_I / A_2 * g
        with np.errstate(invalid="ignore", divide="ignore"):
            rho = np.where(gg > 0, (ag[:, 1:] + ag[:, :-1]) / gg, 0.0)
        PhiG = Phi(c_area * G, self.settings.gamma) / c_area
        contrib = 4.0 * sigma0[:, None] * rho * np.diff(PhiG, axis=1)
        zero = np.zeros((v.size, 1))
        dmu_w = 0.5 * (np.concatenate([contrib, zero], axis=1)
                       + np.concatenate([zero, contrib], axis=1))
        i = self.i_m
        f = (np.log(self.q_m) - lq[i - 1]) / self.dl[i - 1]
        P_m = P[:, i - 1] + f * (P[:, i] - P[:, i - 1])
        G1 = self.area_c * G_dry[:, -1]  # the real contact's G(q1) (its area is P_dry(q1))
        if dT is None:  # the cold state's squeeze-out inputs (end_points reuses them)
            self._cold_state = (v, T0, sigma0, F_wet, c_area * G, P_m, G1)
        w = self._weight(v, T0, sigma0, F_wet, c_area * G, P_m, G1)
        self.last_w = w
        # real (rubber-road) contact: the dry one (module docstring, item 1); P_dry[:, -1] is
        # the dry engine's area (same G, same operations), so no second dry evaluation
        area = np.minimum(P_dry[:, -1], P[:, -1])
        mu_cont = w * self.compound.adhesion.sigma_f(v, T_surf) * area / sigma0
        out = {"mu_visc": contrib.sum(axis=1), "mu_cont": mu_cont, "area": area,
               "dmu_w": dmu_w, "P_m": P_m}
        if outside:  # extrapolation shares of the sealed spectrum's integrals
            out.update(self._outside_shares(ang, g, gg, np.diff(PhiG, axis=1), sigma0,
                                            out["mu_visc"], mu_cont, G[:, -1]))
        return out

    def _G(self, g: np.ndarray) -> np.ndarray:
        gg = g[:, 1:] + g[:, :-1]
        return np.concatenate([np.zeros((g.shape[0], 1)), np.cumsum(0.5 * gg * self.dl, axis=1)],
                              axis=1)

    def _weight(self, v: np.ndarray, T0: np.ndarray, sigma0: np.ndarray, F: np.ndarray,
                G: np.ndarray, P_m: np.ndarray, G1: np.ndarray) -> np.ndarray:
        """Dry share w = w_macro(t) w_asp(v) of the real contact (:mod:`lookup.wet.squeeze`):
        the macro contact drained within the available time t, times the share of its
        asperity contacts dried within their own contact time at the sliding speed v."""
        if self.adhesive_weight is not None:
            return np.full(v.size, float(self.adhesive_weight))
        if not self.lubricant.adhesion:
            return np.zeros(v.size)
        t = self.D / v if self.t_contact is None else np.full(v.size, self.t_contact)
        u = mean_separation(S_NODES, self.q, F, G, self.i_m, sigma0, P_m,
                            self.settings.gamma)
        R = 0.5 * self.D if self.drainage_radius is None else self.drainage_radius
        eta = self.lubricant.viscosity(T0)
        self.last_squeeze = (eta, R, sigma0, P_m, u)
        self.last_asperity = asperity_dry_share(v, eta, self.q1, sigma0, G1)
        return dry_share(t, *self.last_squeeze) * self.last_asperity

    def end_points(self, v: Any, T0: Any, sigma0: Any, t_drain: Any) -> dict[str, np.ndarray]:
        """Everything the wet branch of a grid needs at the selected depth node (> 0).

        Cold and hot friction with the dry share forced to w = 0 and w = 1, and the dry share
        w = w_macro(t_drain) w_asp(v) after each drainage time ``t_drain`` [s] (cold state,
        lubricant at T0; :meth:`_weight`), for points
        v [m/s], T0 [K], sigma0 [Pa] (arrays broadcast; results have their shape, ``w_dry``
        has ``(len(t_drain),) + shape``).

        The same numbers as :meth:`cold_and_hot` with ``adhesive_weight`` 0 and 1 and as
        :meth:`dry_shares` after a cold evaluation, with less work: the cold friction is
        linear in w and everything else in it (mu_visc, the sealed G(q), P(q_m), the area)
        does not depend on w, so one cold evaluation gives both end points (mu_cont = 0 at
        w = 0 exactly) and starts both hot solves, and its G(q) and P(q_m) are the
        squeeze-out's inputs (:mod:`lookup.wet.squeeze`).
        """
        if self.depth == 0.0:
            raise InputError("end points are for a wet depth node (> 0); depth 0 is the dry "
                             "engine", field="depth_index", value=self.depth_index)
        self._require_hot()
        shape, v, T0, sigma0 = self._prepare(v, T0, sigma0)
        t_drain = np.atleast_1d(np.asarray(t_drain, float))
        saved = (self.adhesive_weight, self.t_contact)
        try:
            self.adhesive_weight = 1.0
            c1 = self._evaluate(v, T0, sigma0, None, outside=self.band is not None)
            state = self._cold_state
            c0 = {**c1, "mu_cont": np.zeros_like(c1["mu_cont"])}
            h1 = self._hot_result(self._fixed_point(v, T0, sigma0, cold=c1), shape)
            self.adhesive_weight = 0.0
            h0 = self._hot_result(self._fixed_point(v, T0, sigma0, cold=c0), shape)
        finally:
            self.adhesive_weight, self.t_contact = saved
        if self.lubricant.adhesion:
            v_, T_, s_, F_, G_, Pm_, G1_ = state
            u = mean_separation(S_NODES, self.q, F_, G_, self.i_m, s_, Pm_,
                                self.settings.gamma)
            R = 0.5 * self.D if self.drainage_radius is None else self.drainage_radius
            eta = self.lubricant.viscosity(T_)
            args = (eta, R, s_, Pm_, u)
            self.last_squeeze = args
            self.last_asperity = asperity_dry_share(v_, eta, self.q1, s_, G1_)
            w = np.stack([dry_share(np.full(v.size, t), *args) * self.last_asperity
                          for t in t_drain])
        else:  # soapy water: no adhesive term at any time
            w = np.zeros((t_drain.size, v.size))
        return {"mu_wet_cold_w0": c1["mu_visc"].reshape(shape),
                "mu_wet_cold_w1": (c1["mu_visc"] + c1["mu_cont"]).reshape(shape),
                "mu_wet_hot_w0": h0.mu, "mu_wet_hot_w1": h1.mu,
                "w_dry": w.reshape((t_drain.size, *shape))}

    def dry_shares(self, t_contact: np.ndarray) -> np.ndarray:
        """Dry share w at other available times [s] for the points of the last squeeze-out
        evaluation (``last_squeeze``, ``last_asperity``): shape (len(t_contact), points). Only
        the time changes, so the separation law u and the asperity share are reused
        (:func:`lookup.wet.squeeze.dry_share` with the same arguments: the values equal a new
        evaluation at each time)."""
        if getattr(self, "last_squeeze", None) is None:
            raise InputError("no squeeze-out evaluated yet (call cold() with a wet depth "
                             "node first)", field="t_contact")
        n = self.last_squeeze[2].size
        return np.stack([dry_share(np.full(n, float(t)), *self.last_squeeze)
                         * self.last_asperity
                         for t in np.atleast_1d(np.asarray(t_contact, float))])

    def wet_table(self, v: Any, T0: float, sigma0: float) -> dict[str, np.ndarray]:
        """Cold and hot branch with the squeeze-out weight (columns of ``tirefric mu --water``).

        Returns arrays over v: mu_wet_cold, mu_wet_hot, mu_visc_wet_cold, mu_cont_wet_cold,
        w_dry_cold (the dry share on the cold branch), area_wet_cold.
        """
        v = np.atleast_1d(np.asarray(v, float))
        c, h = self.cold_and_hot(v, T0, sigma0)
        self.cold(v, T0, sigma0)
        w = self.last_w.copy()
        return {"mu_wet_cold": c.mu, "mu_wet_hot": h.mu, "mu_visc_wet_cold": c.mu_visc,
                "mu_cont_wet_cold": c.mu_cont, "w_dry_cold": w, "area_wet_cold": c.area}
