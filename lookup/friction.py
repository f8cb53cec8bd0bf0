r"""Persson steady-sliding rubber friction: cold branch and self-consistent hot branch.

Cold branch (review eqs. 17-20, temperature T0 everywhere):

.. math::

    \mu_{visc} = \tfrac12 \int_{q_0}^{q_1} dq\, q^3 C(q) S(q) P(q)
                 \int_0^{2\pi} d\phi \cos\phi \frac{E_I(q v\cos\phi, T)}{(1-\nu^2)\sigma_0},

    G(q) = \tfrac18 \int_{q_0}^{q} dq\, q^3 C(q) \int_0^{2\pi} d\phi
           \left|\frac{E(q v \cos\phi, T)}{(1-\nu^2)\sigma_0}\right|^2,\quad
    P(q) = \mathrm{erf}\big(1/(2\sqrt{G(q)})\big),\quad S = \gamma + (1-\gamma) P^2,

with the loss modulus E_I = -Im E >= 0 (docs/review-notes.md, Trap 1: the review writes Im E,
which is negative with its own eq. 4) and the corrected eq. (18) (Trap 2). The angular integrals
use the symmetry of Trap 3: 4 x Gauss-Legendre on [0, pi/2]. G(q) is trapezoidal in ln q;
eq. (17) is integrated in G with the exact Phi(G) = int S P dG (:mod:`lookup.contact`), which
follows the steep fall of P(q) on glassy rubber that no q-quadrature resolves.
The real contact area is A/A0 = P(q1) and mu = mu_visc + sigma_f(v, T) P(q1) / sigma0
(review eq. 12, the text before eq. 17).

Hot branch: the same integrals with the modulus of scale q evaluated at T0 + dT_q and the shear
law at T0 + dT_surface, where the flash temperatures are produced by the friction itself
(:mod:`lookup.flash_temperature`). The fixed point dT = F(dT) is solved per point by relaxed
iteration with Aitken's dynamic relaxation factor (Irons & Tuck, Int. J. Numer. Meth. Eng. 1
(1969) 275; as used for partitioned coupling by Kuettler & Wall, Comput. Mech. 43 (2008) 61),
a secant update along the dominant mode. It copes with the two regimes met here: strong
negative feedback on glassy rubber (heating softens it, the macro-contact fraction P_m grows
and the heat per contact area collapses; slopes down to about -5) and positive feedback with
local gain above 1 far from the fixed point (heating moves the adhesive peak towards the
sliding speed). Only positive relaxation is used, so the solution is the stable steady state of
d(dT)/dt = F(dT) - dT reached from the cold state (dT = 0), i.e. the flash temperature that a
contact heating up from cold would settle to; unstable branches of an S-shaped response are
not reported. Points that Aitken's rule has not converged after ``aitken_iter`` iterations
(near the fold of an S-shaped response the factor can oscillate between regimes) restart from
the cold state with a fixed relaxation, which converges there. The final max-norm residual
|F(dT) - dT| [K] is reported with every hot result.

Strain softening (review eq. 6) enters as factors on E_R and E_I. Factors that do not depend
on the temperature are part of the tabulated master curve (so the cold branch stays a
function of v a_T: time-temperature superposition); factors from strain sweeps measured at
several temperatures are applied at the temperature each scale feels (T0 on the cold branch,
T0 + dT_q on the hot one).

Extrapolation accounting (docs/engine-inputs.md, "What a result took from outside the
data"). A tabulated master curve is known on a measured band of frequencies; every result
reports the share of its integrand evaluated outside it, at the reduced frequencies
omega = q v cos(phi) a_T(T_q) of the quadrature nodes:

* ``outside_visc``: the share of eq. (17) whose angular integrand comes from nodes outside
  the band, i.e. eq. (17) evaluated with E_I set to zero inside the band, divided by
  mu_visc (the same G(q), P(q) and S(q) weights);
* ``outside_area``: the same share of G(q1) (eq. 19, the |E|^2 integrand), on which the
  contact area P(q1) and hence the adhesive term depend;
* ``outside``: the share of mu, (mu_visc outside_visc + mu_cont outside_area) / mu.

A model without a measured band (Prony, single relaxation) reports 0. Above
:data:`OUTSIDE_WARNING_SHARE` the public methods warn (:class:`tirefric.errors.
ExtrapolationWarning`); with the master curve's ``outside = "error"`` they refuse the points
whose integrands reach outside the band (any share > 0), naming the frequencies they need.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from tirefric import __version__
from tirefric.errors import ExtrapolationWarning, InputError

from .compound import Compound
from .contact import Phi, area_rescale, contact_fraction
from .flash_temperature import HeatKernelSettings, heat_kernel, lateral_factor
from .surface import Surface

#: Contact-area laws offered by :class:`EngineSettings` (``contact_area``).
CONTACT_AREA_LAWS: tuple[str, ...] = ("persson", "rescaled_kappa")

#: A result whose share of integrand from outside the measured band (``outside``, module
#: docstring) exceeds this warns. The part taken from outside follows the Maxwell asymptotes
#: of the curve's ends (lookup.modulus.TabulatedMasterCurve), which can be off by a factor of
#: order one (below the data E'' falls in proportion to omega, where a filled tread compound
#: keeps tan delta near 0.1-0.3 over many decades of its rubbery side), so a 5 % share can
#: move the result by a few percent: the scatter of measured master curves and friction
#: data. Below it the extrapolation does not matter at that level.
OUTSIDE_WARNING_SHARE = 0.05

#: Heat kernels shared by the engines of one process (PerssonFriction._kernel), keyed by
#: everything a kernel is computed from; at most this many (a kernel is (nq+1)^2 doubles,
#: ~40 kB at the default settings: at most ~11 MB; a grid's slip-speed axis has ~30-60
#: nodes).
_SHARED_KERNELS: dict[tuple, np.ndarray] = {}
_SHARED_KERNELS_MAX = 256

#: Keys of an evaluation that the flash-temperature iteration carries along.
_PARTS = ("mu_visc", "mu_cont", "area", "dmu_w", "P_m")
#: Keys of the extrapolation accounting (module docstring).
OUTSIDE_KEYS = ("outside", "outside_visc", "outside_area")
_OUTSIDE_ALL = (*OUTSIDE_KEYS, "log10_omega_min", "log10_omega_max")


@dataclass(frozen=True)
class EngineSettings:
    """Numerical settings of the friction engine (chosen by the resolution study in tests).

    Accuracy of the defaults: against a converged run (384 q-nodes per decade) on a glassy
    single-relaxation solid the bias is up to 0.17 % in mu_visc and 0.22 % in A/A0
    (``tests/test_engine_resolution.py``); it comes from the trapezoidal rule for G(q) and
    falls as the square of the q spacing (``q_per_decade = 96``: 0.01 %). Set it from the
    command line (``tirefric mu --q-per-decade 96 --gamma 0.4``) or a grid spec's ``[engine]``
    table. Comparing with a run only 4x finer understates the bias by the 1/16 it still has.

    Attributes
    ----------
    q_per_decade : int
        Wavenumber nodes per decade between q0 and q1 (at least 12 nodes in all).
    n_phi : int
        Gauss-Legendre nodes for the angular integrals on [0, pi/2].
    gamma : float
        The constant of review eq. (20).
    modulus_per_decade : int
        Sampling of the tabulated master curve.
    hot_tol : float
        Convergence tolerance of the flash-temperature fixed point, max-norm [K].
    hot_max_iter : int
        Iteration limit of the fixed point.
    damping : float
        Initial relaxation of the fixed-point iteration.
    omega_min, omega_max : float
        Bounds on the Aitken relaxation factor (kept positive, see module docstring).
    aitken_iter : int
        Iterations with Aitken relaxation before unconverged points restart from the cold
        state with the fixed relaxation ``picard_relaxation``.
    picard_relaxation : float
        Relaxation of the fallback phase.
    road_heat : bool
        Let the road take part of the heat when the surface has thermal data
        (:mod:`lookup.flash_temperature`, item 4).
    tau_per_decade : int
        Quadrature nodes per decade of the heat kernel's time integral.
    contact_area : {"persson", "rescaled_kappa"}
        The contact-area law P(G). ``"persson"`` (default): the corrected eq. (18),
        P = erf(1/(2 sqrt G)), which reduces to eq. (10) in the elastic limit with the
        small-contact slope kappa = (8/pi)^(1/2) = 1.60 of eq. (11). ``"rescaled_kappa"``:
        the same law with the slope set to ``area_kappa``, i.e. A/A0 =
        erf((sqrt(pi) kappa / 2) sigma0 / (xi E*)) in the elastic limit, obtained by
        evaluating P and eq. (17) at G' = c G with c = 8/(pi kappa^2) (see
        :func:`lookup.contact.area_rescale`).
    area_kappa : float
        Small-contact slope kappa for ``contact_area="rescaled_kappa"``. Default 2: the
        "exact" numerical result quoted by the review (text after eq. 11 and its figure of
        A/A0 vs sigma0/(xi E*): "slope parameter kappa ~ 2"; Hyun, Pei, Molinari & Robbins,
        Phys. Rev. E 70 (2004) 026117; Campana & Muser, EPL 77 (2007) 38005; Prodanov, Dapp &
        Muser, Tribol. Lett. 53 (2014) 433, GFMD).
    """

    q_per_decade: int = 24
    n_phi: int = 16
    gamma: float = 0.5
    modulus_per_decade: int = 40
    hot_tol: float = 1e-3
    hot_max_iter: int = 300
    damping: float = 0.5
    omega_min: float = 0.02
    omega_max: float = 2.0
    aitken_iter: int = 60
    picard_relaxation: float = 0.3
    road_heat: bool = True
    tau_per_decade: int = 3
    contact_area: str = "persson"
    area_kappa: float = 2.0

    def __post_init__(self) -> None:
        checks = [("q_per_decade", self.q_per_decade >= 2), ("n_phi", self.n_phi >= 2),
                  ("gamma", 0.0 <= self.gamma <= 1.0),
                  ("modulus_per_decade", self.modulus_per_decade >= 4),
                  ("hot_tol", self.hot_tol > 0), ("hot_max_iter", self.hot_max_iter >= 1),
                  ("damping", 0.0 < self.damping <= 1.0),
                  ("omega_min", 0.0 < self.omega_min <= self.damping),
                  ("omega_max", self.omega_max >= self.damping),
                  ("aitken_iter", self.aitken_iter >= 1),
                  ("picard_relaxation", 0.0 < self.picard_relaxation <= 1.0),
                  ("tau_per_decade", self.tau_per_decade >= 1),
                  ("contact_area", self.contact_area in CONTACT_AREA_LAWS),
                  ("area_kappa", 0.5 <= self.area_kappa <= 5.0)]
        for name, ok in checks:
            if not ok:
                hint = {"contact_area": f" (known: {', '.join(CONTACT_AREA_LAWS)})",
                        "area_kappa": " (must be in 0.5 .. 5)",
                        "gamma": " (must be in 0 .. 1)"}.get(name, "")
                raise InputError("invalid engine setting" + hint, field=f"engine.{name}",
                                 value=getattr(self, name))


@dataclass
class FrictionResult:
    """Friction at a set of points; every field has the broadcast shape of the inputs.

    Attributes
    ----------
    mu, mu_visc, mu_cont : numpy.ndarray
        Total, viscoelastic and contact (adhesive) friction coefficients.
    area : numpy.ndarray
        Relative real contact area A/A0 = P(q1).
    dT_flash : numpy.ndarray
        Contact-time-averaged flash temperature rise at the surface [K] (0 on the cold branch).
    dT_max : numpy.ndarray
        Largest flash temperature rise over the resolved depths [K].
    residual : numpy.ndarray
        Max-norm residual of the flash-temperature fixed point [K] (0 on the cold branch).
    iterations : numpy.ndarray
        Fixed-point iterations used.
    outside, outside_visc, outside_area : numpy.ndarray
        Share of the integrand of mu, of mu_visc (eq. 17) and of G(q1) (eq. 19) evaluated at
        frequencies outside the master curve's measured band (module docstring); 0 for a
        model without a band.
    """

    mu: np.ndarray
    mu_visc: np.ndarray
    mu_cont: np.ndarray
    area: np.ndarray
    dT_flash: np.ndarray
    dT_max: np.ndarray
    residual: np.ndarray
    iterations: np.ndarray
    outside: np.ndarray
    outside_visc: np.ndarray
    outside_area: np.ndarray

    def reshape(self, shape: tuple[int, ...]) -> FrictionResult:
        return FrictionResult(**{k: np.reshape(v, shape) for k, v in asdict(self).items()})


@dataclass
class PerssonFriction:
    """The Persson friction engine for one compound on one surface.

    Parameters
    ----------
    compound : Compound
    surface : Surface
    settings : EngineSettings, optional

    Notes
    -----
    Everything that does not depend on (v, T0, sigma0) is prepared once here: the q and phi
    nodes, C(q), the tabulated master curve. The heat kernel depends on v only and is cached
    per speed. Instances are picklable (for process pools and Dask).
    """

    compound: Compound
    surface: Surface
    settings: EngineSettings = field(default_factory=EngineSettings)

    def __post_init__(self) -> None:
        s = self.settings
        self.q0 = float(self.surface.psd.q0)
        self.q1 = float(self.surface.q1)
        if not self.q1 > self.q0:
            raise InputError(f"q1 = {self.q1:g} 1/m must exceed q0 = {self.q0:g} 1/m",
                             source=self.surface.source, field="cutoff")
        n = max(int(np.ceil(np.log10(self.q1 / self.q0) * s.q_per_decade)), 11) + 1
        self.q = np.geomspace(self.q0, self.q1, n)
        lnq = np.log(self.q)
        # trapezoid weights in ln q for int dq f(q) = int dlnq q f(q)
        dl = np.diff(lnq)
        w = np.zeros(n)
        w[:-1] += 0.5 * dl
        w[1:] += 0.5 * dl
        self.w_lnq = w
        self.dl = dl
        # q^4 C(q): the measure q^3 C dq written per d(ln q)
        self.F = self.q**4 * self.surface.psd.C(self.q)
        x, wx = np.polynomial.legendre.leggauss(s.n_phi)
        phi = 0.25 * np.pi * (x + 1.0)
        self.cos_phi = np.cos(phi)
        self.w_phi = 0.25 * np.pi * wx
        self.log10_qcos = np.log10(self.q)[:, None] + np.log10(self.cos_phi)[None, :]
        # softening factors that depend on T are applied per scale (module docstring)
        self.soft_T = self.compound.softening_varies_with_T
        self.table = self.compound.modulus_table(s.modulus_per_decade, softened=not self.soft_T)
        self.band = self.table.log10_band
        self.inv_1mnu2 = 1.0 / (1.0 - self.compound.nu**2)
        # macroasperity wavenumber q_m = pi / D, clamped to the resolved band; a cold-only
        # study (no [macroasperity] or no rubber [thermal]) leaves the hot-branch data unset
        # and the hot branch refuses to run (_require_hot)
        D = self.surface.D
        self.q_m = float(np.clip(np.pi / D, self.q0, self.q1)) if D is not None else self.q0
        self.i_m = int(np.clip(np.searchsorted(self.q, self.q_m), 1, n - 1))
        th = self.compound.thermal
        self.D_th = th.diffusivity if th is not None else np.nan
        self.rho_c = th.rho * th.c_v if th is not None else np.nan
        if s.road_heat and self.surface.thermal is not None and th is not None:
            e_r, e_s = th.effusivity, self.surface.thermal.effusivity
            self.R_image = (e_r - e_s) / (e_r + e_s)
        else:
            self.R_image = 1.0
        self.z_eval = np.concatenate([[0.0], 1.0 / (2.0 * self.q)])
        self.a_src = np.concatenate([[np.inf], 2.0 * self.q])
        self._kernels: dict[float, np.ndarray] = {}
        self.last_hot_residual = 0.0
        self.area_c = (1.0 if s.contact_area == "persson"
                       else area_rescale(s.area_kappa))

    # -- provenance ---------------------------------------------------------------------------
    @property
    def D(self) -> float:
        """Macroasperity contact diameter [m]."""
        return self.surface.D

    @property
    def s0(self) -> float:
        """Cold-to-hot slip distance of eq. (28), 0.2 D [m]."""
        return self.surface.s0

    def _require_hot(self) -> None:
        """Refuse the hot branch of a cold-only study, naming the missing file table."""
        self.surface.require_D()
        self.compound.require_thermal()

    def describe(self) -> dict[str, Any]:
        """Everything needed to trace a number back: inputs, rule, settings, version."""
        return {"compound": self.compound.describe(), "surface": self.surface.describe(),
                "settings": asdict(self.settings), "q0_per_m": self.q0, "q1_per_m": self.q1,
                "measured_band_rad_s": None if self.band is None else
                [10.0 ** self.band[0], 10.0 ** self.band[1]],
                "q1_rule": self.surface.cutoff.describe(), "D_m": self.D,
                "s0_m": None if self.D is None else self.s0,
                "q_m_per_m": self.q_m, "road_image_R": self.R_image,
                "n_q": int(self.q.size), "tirefric_version": __version__}

    # -- the integrals ------------------------------------------------------------------------
    def _angular(self, v: np.ndarray, log10_aT: np.ndarray, T_q: np.ndarray | None = None,
                 outside: bool = False) -> tuple[np.ndarray, ...]:
        """Angular integrals at every q (Trap 3), normalised by (1 - nu^2).

        Returns (A_I, A_2), shape (B, nq): A_I = int_0^2pi cos(phi) E_I*/... dphi and
        A_2 = int_0^2pi |E*|^2 dphi with E* = E/(1-nu^2). ``T_q`` (B, nq) [K] are the
        temperatures of the scales, needed when the softening depends on T (module
        docstring). With ``outside`` (and a measured band) also the parts of A_I and A_2
        from nodes outside the band and, per point, the lowest and highest log10 omega
        needed: (A_I, A_2, A_I_out, A_2_out, lw_min, lw_max).
        """
        lw = (np.log10(v)[:, None, None] + self.log10_qcos[None, :, :]
              + log10_aT[:, :, None])
        ER, EI = self.table(lw)
        if self.soft_T:
            if T_q is None:
                raise InputError("the softening depends on the temperature: the angular "
                                 "integrals need the scales' temperatures", field="softening")
            eta_R, eta_I = self.compound.softening_at(T_q)
            ER = ER * eta_R[:, :, None]
            EI = EI * eta_I[:, :, None]
        c = self.inv_1mnu2
        wI = self.w_phi * self.cos_phi
        A_I = 4.0 * c * np.einsum("bqk,k->bq", EI, wI)
        E2 = ER * ER + EI * EI
        A_2 = 4.0 * c * c * np.einsum("bqk,k->bq", E2, self.w_phi)
        if not (outside and self.band is not None):
            return A_I, A_2
        out = self.table.outside_band(lw)
        A_I_out = 4.0 * c * np.einsum("bqk,k->bq", np.where(out, EI, 0.0), wI)
        A_2_out = 4.0 * c * c * np.einsum("bqk,k->bq", np.where(out, E2, 0.0), self.w_phi)
        return A_I, A_2, A_I_out, A_2_out, lw.min(axis=(1, 2)), lw.max(axis=(1, 2))

    def _temperatures(self, T0: np.ndarray, dT: np.ndarray | None
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """log10 a_T felt by every scale (B, nq), the surface temperature (B,) [K] and the
        scales' temperatures (B, nq) [K]: the background ``T0`` on the cold branch (``dT``
        None), ``T0`` plus the flash rise of each scale's depth and of the surface on the
        hot one (sec. 5.1, docs/physics.md sec. 3)."""
        if dT is None:
            shape = (T0.size, self.q.size)
            return (np.broadcast_to(self.compound.log10_aT(T0)[:, None], shape), T0,
                    np.broadcast_to(T0[:, None], shape))
        T_q = T0[:, None] + dT[:, 1:]
        return self.compound.log10_aT(T_q), T0 + dT[:, 0], T_q

    def _outside_shares(self, ang: tuple[np.ndarray, ...], g: np.ndarray, gg: np.ndarray,
                        dPhi: np.ndarray, sigma0: np.ndarray, mu_visc: np.ndarray,
                        mu_cont: np.ndarray, G_end: np.ndarray) -> dict[str, np.ndarray]:
        """The extrapolation shares of one evaluation (module docstring).

        ``ang`` is what :meth:`_angular` returns with ``outside``; ``g`` = dG/dln q, ``gg``
        its interval sums and ``dPhi`` the intervals' Phi(G) increments, as in
        :meth:`_evaluate`; ``G_end`` = G(q1)."""
        zero = np.zeros(mu_visc.shape)
        if len(ang) == 2:  # no measured band: nothing comes from outside it
            return {"outside": zero, "outside_visc": zero, "outside_area": zero}
        _, A_2, A_I_out, A_2_out, lw_min, lw_max = ang
        ag = A_I_out / A_2 * g  # eq. (17) with E_I = 0 inside the band, same weights
        with np.errstate(invalid="ignore", divide="ignore"):
            rho = np.where(gg > 0, (ag[:, 1:] + ag[:, :-1]) / gg, 0.0)
            visc = (4.0 * sigma0[:, None] * rho * dPhi).sum(axis=1)
            g_out = g * (A_2_out / A_2)  # eq. (19) from the nodes outside the band
            G_out = (0.5 * (g_out[:, 1:] + g_out[:, :-1]) * self.dl).sum(axis=1)
            s_visc = np.where(mu_visc > 0, visc / mu_visc, 0.0)
            s_area = np.where(G_end > 0, G_out / G_end, 0.0)
            mu = mu_visc + mu_cont
            s_mu = np.where(mu > 0, (visc + mu_cont * s_area) / mu, 0.0)
        # shares of sums of non-negative terms: in [0, 1] up to rounding
        return {"outside": np.clip(s_mu, 0.0, 1.0), "outside_visc": np.clip(s_visc, 0.0, 1.0),
                "outside_area": np.clip(s_area, 0.0, 1.0), "log10_omega_min": lw_min,
                "log10_omega_max": lw_max}

    def _evaluate(self, v: np.ndarray, T0: np.ndarray, sigma0: np.ndarray,
                  dT: np.ndarray | None, outside: bool = False) -> dict[str, np.ndarray]:
        """Friction at flat arrays (B,) with flash temperatures dT (B, nq+1) or None (cold);
        with ``outside`` also the extrapolation shares (:meth:`_outside_shares`)."""
        la, T_surf, T_q = self._temperatures(T0, dT)
        ang = self._angular(v, la, T_q, outside)
        A_I, A_2 = ang[0], ang[1]
        s2 = (1.0 / sigma0**2)[:, None]
        g = 0.125 * self.F * A_2 * s2  # dG/dln q, eq. (19)
        gg = g[:, 1:] + g[:, :-1]
        G = np.concatenate([np.zeros((v.size, 1)), np.cumsum(0.5 * gg * self.dl, axis=1)],
                           axis=1)
        c_area = self.area_c
        P = contact_fraction(G if c_area == 1.0 else c_area * G)
        # eq. (17) as 4 sigma0 int (A_I/A_2) S P dG, interval by interval with the exact
        # Phi(G) = int S P dG and the g-weighted mean of A_I/A_2 (lookup.contact docstring)
        ag = A_I / A_2 * g
        with np.errstate(invalid="ignore", divide="ignore"):
            rho = np.where(gg > 0, (ag[:, 1:] + ag[:, :-1]) / gg, 0.0)
        if c_area == 1.0:
            PhiG = Phi(G, self.settings.gamma)
        else:  # int S P(c g) dg = Phi(c G) / c
            PhiG = Phi(c_area * G, self.settings.gamma) / c_area
        contrib = 4.0 * sigma0[:, None] * rho * np.diff(PhiG, axis=1)
        zero = np.zeros((v.size, 1))
        dmu_w = 0.5 * (np.concatenate([contrib, zero], axis=1)
                       + np.concatenate([zero, contrib], axis=1))  # per q node
        mu_visc = contrib.sum(axis=1)
        area = P[:, -1]
        sig_f = self.compound.adhesion.sigma_f(v, T_surf)
        mu_cont = sig_f * area / sigma0
        # P at the macroasperity scale, interpolated in ln q
        i = self.i_m
        f = (np.log(self.q_m) - np.log(self.q[i - 1])) / self.dl[i - 1]
        P_m = P[:, i - 1] + f * (P[:, i] - P[:, i - 1])
        out = {"mu_visc": mu_visc, "mu_cont": mu_cont, "area": area, "dmu_w": dmu_w,
               "P_m": P_m}
        if outside:
            out.update(self._outside_shares(ang, g, gg, np.diff(PhiG, axis=1), sigma0, mu_visc,
                                            mu_cont, G[:, -1]))
        return out

    def _kernel(self, v: float) -> np.ndarray:
        """Heat kernel with lateral factor for speed v (cached), shape (nq+1, nq+1).

        Cached per engine and, by everything it is computed from (the wavenumbers, the
        macro-contact size, the rubber's diffusivity and heat capacity, the image strength,
        the quadrature and v), per process (:data:`_SHARED_KERNELS`): the dry and the wet
        engine of one road, and compounds that differ in anything but their thermal data,
        share it. The same function of the same numbers: the same array bit for bit.
        """
        key = float(v)
        K = self._kernels.get(key)
        if K is None:
            ident = self.__dict__.get("_kernel_ident")
            if ident is None:
                import hashlib

                ident = (hashlib.sha256(np.ascontiguousarray(self.q, float).tobytes())
                         .hexdigest(), float(self.D), float(self.D_th), float(self.rho_c),
                         float(self.R_image), int(self.settings.tau_per_decade))
                self._kernel_ident = ident
            K = _SHARED_KERNELS.get((ident, key))
            if K is None:
                t_c = self.D / key
                K = heat_kernel(self.z_eval, self.a_src, t_c, self.D_th, self.rho_c,
                                self.R_image, HeatKernelSettings(self.settings.tau_per_decade))
                K = K * lateral_factor(key * self.D / self.D_th)
                K.setflags(write=False)
                if len(_SHARED_KERNELS) >= _SHARED_KERNELS_MAX:
                    _SHARED_KERNELS.pop(next(iter(_SHARED_KERNELS)))    # the oldest
                _SHARED_KERNELS[(ident, key)] = K
            if len(self._kernels) > 256:
                self._kernels.clear()
            self._kernels[key] = K
        return K

    def heat_sources(self, v: np.ndarray, sigma0: np.ndarray, parts: dict[str, np.ndarray]
                     ) -> np.ndarray:
        """Source powers per unit macro-contact area [W/m^2], shape (B, nq+1).

        Column 0 is the adhesive surface flux mu_cont sigma0 v / P_m, columns 1.. the
        viscoelastic power of each scale, sigma0 v dmu_q / P_m (module docstring of
        :mod:`lookup.flash_temperature`, items 1 and 3).
        """
        scale = (sigma0 * v / parts["P_m"])[:, None]
        return np.concatenate([parts["mu_cont"][:, None], parts["dmu_w"]], axis=1) * scale

    def _fixed_point(self, v: np.ndarray, T0: np.ndarray, sigma0: np.ndarray,
                     cold: dict[str, np.ndarray] | None = None
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """Solve dT = F(dT) for every point (vectorised over points sharing nothing but code).

        ``cold`` is the evaluation at dT = 0 (the cold branch) when the caller already has it;
        the iteration starts from it instead of evaluating it again.
        """
        s = self.settings
        B, n = v.size, self.q.size + 1
        uv, inv = np.unique(v, return_inverse=True)
        kernels = np.stack([self._kernel(x) for x in uv])
        # with a measured band every evaluation also gives the extrapolation shares (the
        # table lookups dominate its cost, the shares add two masked sums), so the final
        # iterate's are at hand
        track = self.band is not None
        keys = _PARTS + (_OUTSIDE_ALL if track else ())

        def F(x: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
            parts = self._evaluate(v[idx], T0[idx], sigma0[idx], x, outside=track)
            W = self.heat_sources(v[idx], sigma0[idx], parts)
            return np.einsum("bij,bj->bi", kernels[inv[idx]], W), parts

        x = np.zeros((B, n))
        if cold is None:
            fx, parts = F(x, np.arange(B))
        else:
            parts = {k: cold[k].copy() for k in keys}  # the loop updates it in place
            W = self.heat_sources(v, sigma0, parts)
            fx = np.einsum("bij,bj->bi", kernels[inv], W)
        res = fx - x
        rnorm = np.abs(res).max(axis=1)
        iters = np.ones(B, dtype=int)
        omega = np.full(B, s.damping)  # per-point relaxation, updated by Aitken's rule
        plain = np.zeros(B, bool)  # points in the fallback phase (fixed relaxation)
        active = rnorm > s.hot_tol
        for it in range(s.hot_max_iter):
            if not active.any():
                break
            if it == s.aitken_iter:
                # fallback: Aitken's factor can oscillate between the regimes of an S-shaped
                # response; restart such points from the cold state with fixed relaxation,
                # which converges to the stable state reached from cold (module docstring)
                sw = np.flatnonzero(active)
                plain[sw] = True
                x[sw] = 0.0
                f0, p0 = F(x[sw], sw)
                res[sw] = f0
                for k in parts:
                    parts[k][sw] = p0[k]
                omega[sw] = s.picard_relaxation
            idx = np.flatnonzero(active)
            xa, ra, wa = x[idx], res[idx], omega[idx]
            new = np.clip(xa + wa[:, None] * ra, 0.0, 5000.0)
            fn, pn = F(new, idx)
            rn = fn - new
            # Aitken / Irons-Tuck dynamic relaxation: a secant estimate of the best
            # relaxation along the dominant mode, w <- -w (r_k . dr) / |dr|^2
            dr = rn - ra
            dd = np.einsum("bn,bn->b", dr, dr)
            with np.errstate(invalid="ignore", divide="ignore"):
                w_new = -wa * np.einsum("bn,bn->b", ra, dr) / dd
            w_new = np.where(np.isfinite(w_new) & (dd > 0), w_new, wa)
            # positive relaxation only: the physical hot state is a stable steady state of
            # d(dT)/dt = F(dT) - dT reached from the cold start (a negative factor would also
            # converge to unstable branches)
            omega[idx] = np.where(plain[idx], omega[idx],
                                  np.clip(w_new, s.omega_min, s.omega_max))
            x[idx], res[idx] = new, rn
            for k in parts:
                parts[k][idx] = pn[k]
            rnorm[idx] = np.abs(rn).max(axis=1)
            iters[idx] += 1
            active = rnorm > s.hot_tol
        # report the friction at the final iterate together with its residual (and, with a
        # measured band, the extrapolation shares at the final temperatures)
        return x, rnorm, iters, parts

    # -- public API -----------------------------------------------------------------------------
    def _prepare(self, v: Any, T0: Any, sigma0: Any) -> tuple[tuple[int, ...], np.ndarray, ...]:
        v, T0, sigma0 = np.broadcast_arrays(np.asarray(v, float), np.asarray(T0, float),
                                            np.asarray(sigma0, float))
        shape = v.shape
        v, T0, sigma0 = (np.ravel(a).copy() for a in (v, T0, sigma0))
        for name, a, ok in (("v", v, v > 0), ("T0", T0, T0 > 0), ("sigma0", sigma0, sigma0 > 0)):
            bad = ~(np.isfinite(a) & ok)
            if bad.any():
                raise InputError("must be finite and > 0 (SI units: m/s, K, Pa)", field=name,
                                 value=float(a[np.flatnonzero(bad)[0]]))
        return shape, v, T0, sigma0

    def cold(self, v: Any, T0: Any, sigma0: Any, *, warn: bool = True) -> FrictionResult:
        """Cold branch (no flash heating) at slip speed v [m/s], temperature T0 [K] and nominal
        pressure sigma0 [Pa]; arrays broadcast. Review eqs. (17)-(21). ``warn``: whether a
        large share of the integrand from outside the measured master curve warns (module
        docstring; the share is in the result either way)."""
        shape, v, T0, sigma0 = self._prepare(v, T0, sigma0)
        c = self._evaluate(v, T0, sigma0, None, outside=self.band is not None)
        self._account(c, v, T0, sigma0, "cold", warn)
        return self._cold_result(c, shape)

    def hot(self, v: Any, T0: Any, sigma0: Any, *, warn: bool = True) -> FrictionResult:
        """Hot branch: flash temperature fully developed and self-consistent (module docstring
        and :mod:`lookup.flash_temperature`); residual [K] reported per point. ``warn`` as in
        :meth:`cold`."""
        self._require_hot()
        shape, v, T0, sigma0 = self._prepare(v, T0, sigma0)
        solved = self._fixed_point(v, T0, sigma0)
        self._account(solved[3], v, T0, sigma0, "hot", warn)
        return self._hot_result(solved, shape)

    def cold_and_hot(self, v: Any, T0: Any, sigma0: Any, *, warn: bool = True
                     ) -> tuple[FrictionResult, FrictionResult]:
        """Both branches; the hot solve starts from the cold evaluation (its dT = 0 state)
        instead of repeating it. Same numbers as :meth:`cold` and :meth:`hot`. ``warn``:
        whether a large extrapolation share warns (module docstring; a grid build reports it
        in the grid instead)."""
        self._require_hot()
        shape, v, T0, sigma0 = self._prepare(v, T0, sigma0)
        c = self._evaluate(v, T0, sigma0, None, outside=self.band is not None)
        self._account(c, v, T0, sigma0, "cold", warn)
        solved = self._fixed_point(v, T0, sigma0, cold=c)
        self._account(solved[3], v, T0, sigma0, "hot", warn)
        return self._cold_result(c, shape), self._hot_result(solved, shape)

    def _account(self, p: dict[str, np.ndarray], v: np.ndarray, T0: np.ndarray,
                 sigma0: np.ndarray, branch: str, warn: bool = True) -> None:
        """Refuse (master curve's ``outside = "error"``) or warn about the points whose
        integrands reach outside the measured band (module docstring)."""
        if self.band is None or "outside" not in p:
            return
        lo, hi = (10.0 ** b for b in self.band)
        needs = (p["outside_visc"] > 0) | (p["outside_area"] > 0)
        if self.table.outside == "error" and needs.any():
            bad = np.flatnonzero(needs)
            pts = "; ".join(
                f"v = {v[i]:.4g} m/s, T = {T0[i] - 273.15:.4g} C, p = {sigma0[i]:.4g} Pa: "
                f"omega a_T from {10 ** p['log10_omega_min'][i]:.3g} to "
                f"{10 ** p['log10_omega_max'][i]:.3g} rad/s, {100 * p['outside'][i]:.3g} % "
                "of the integrand outside" for i in bad[:3])
            more = f" (and {bad.size - 3} more)" if bad.size > 3 else ""
            raise InputError(
                f"{bad.size} of {v.size} point(s) of the {branch} branch need the master "
                f"curve outside its data ({lo:.3g}..{hi:.3g} rad/s at T_ref), and its policy "
                f"is 'error': {pts}{more}. Measure further, or set outside = \"maxwell\" "
                "(then the share taken from outside is reported with each result)",
                source=self.table.source or self.compound.source or None,
                field="modulus.outside", value="error")
        worst = int(np.argmax(p["outside"])) if p["outside"].size else 0
        if warn and p["outside"].size and p["outside"][worst] > OUTSIDE_WARNING_SHARE:
            n = int((p["outside"] > OUTSIDE_WARNING_SHARE).sum())
            warnings.warn(ExtrapolationWarning(
                f"{self.compound.source or self.compound.name}: {n} of {v.size} point(s) of "
                f"the {branch} branch take more than {100 * OUTSIDE_WARNING_SHARE:g} % of "
                f"their friction integrand from outside the measured master curve "
                f"({lo:.3g}..{hi:.3g} rad/s at T_ref; Maxwell asymptotes there): up to "
                f"{100 * p['outside'][worst]:.3g} % at v = {v[worst]:.4g} m/s, "
                f"T = {T0[worst] - 273.15:.4g} C, p = {sigma0[worst]:.4g} Pa "
                "(docs/engine-inputs.md)"), stacklevel=3)

    @staticmethod
    def _shares(p: dict[str, np.ndarray]) -> tuple[np.ndarray, ...]:
        z = np.zeros_like(p["mu_visc"])
        return tuple(p.get(k, z) for k in OUTSIDE_KEYS)

    @classmethod
    def _cold_result(cls, p: dict[str, np.ndarray], shape: tuple[int, ...]) -> FrictionResult:
        z = np.zeros_like(p["mu_visc"])
        return FrictionResult(p["mu_visc"] + p["mu_cont"], p["mu_visc"], p["mu_cont"],
                              p["area"], z, z, z, np.zeros(z.size, int),
                              *cls._shares(p)).reshape(shape)

    def _hot_result(self, solved: tuple, shape: tuple[int, ...]) -> FrictionResult:
        x, rnorm, iters, p = solved
        self.last_hot_residual = float(rnorm.max()) if rnorm.size else 0.0
        return FrictionResult(p["mu_visc"] + p["mu_cont"], p["mu_visc"], p["mu_cont"],
                              p["area"], x[:, 0], x.max(axis=1), rnorm, iters,
                              *self._shares(p)).reshape(shape)

    def grid_slice(self, v: float, T0: np.ndarray, sigma0: np.ndarray) -> dict[str, np.ndarray]:
        """All grid variables at one slip speed over T0 (nT,) x sigma0 (np,) -> (nT, np), with
        the extrapolation shares ``outside_cold``, ``outside_hot`` (module docstring) when the
        master curve has a measured band."""
        T = np.asarray(T0, float)[:, None]
        p = np.asarray(sigma0, float)[None, :]
        c, h = self.cold_and_hot(v, T, p, warn=False)
        out = {"mu_cold": c.mu, "mu_hot": h.mu, "mu_visc_cold": c.mu_visc,
               "mu_cont_cold": c.mu_cont, "mu_visc_hot": h.mu_visc, "mu_cont_hot": h.mu_cont,
               "area_cold": c.area, "area_hot": h.area, "dT_flash": h.dT_flash,
               "residual_hot": h.residual}
        if self.band is not None:
            out.update(outside_cold=c.outside, outside_hot=h.outside)
        return out

    def mu_table(self, v: Any, T0: float, sigma0: float) -> tuple[np.ndarray, ...]:
        """Columns of ``tirefric mu``: v, mu_cold, mu_hot, mu_visc_cold, mu_cont_cold,
        area_cold, area_hot, dT_flash."""
        v = np.atleast_1d(np.asarray(v, float))
        c, h = self.cold_and_hot(v, T0, sigma0)
        return (v, c.mu, h.mu, c.mu_visc, c.mu_cont, c.area, h.area, h.dT_flash)
