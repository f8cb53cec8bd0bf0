r"""Rolling resistance of the brush tire: tread hysteresis (review eq. 29) plus a carcass term.

A rolling tire dissipates, per unit distance travelled, the energy its rubber loses in the
deformation cycle every material element goes through once per revolution. The resistance
force is that energy per unit distance, :math:`F_r = f_r F_z`, and in ISO-W wheel axes the
road's moment on the tire for forward rolling is :math:`M_y = -f_r F_z R_e` (``docs/axes.md``).
Two parts are added:

**Tread** (the physics route of the review). The footprint pressure p(x) of
:class:`~tire_brush.params.PatchLaw` passes through the tread layer at the rolling speed V.
Review eq. (29) for a line load, with the half-space compliance replaced by that of a layer of
thickness h (:func:`lookup.rolling.tread_rolling_resistance`), gives the energy the tread
dissipates per unit distance:

.. math:: f_{\rm tread} = \frac{1}{\pi f_N}\int_0^\infty dq\, q\,
          \mathrm{Im}\,C(q, qV)\,|P(q)|^2 ,

with the compound's master curve read at :math:`qV a_T(T)` (review eqs. 1-6 and the WLF
shift), T the tread temperature. For a grooved tread (``tread_support = "winkler"``) the
pressure on the rubber is :math:`p/(1-\phi)` over the land share :math:`1-\phi` of the
footprint; the loss being quadratic in the pressure, the coefficient is divided by
:math:`1-\phi`. Because time-temperature superposition holds for eq. (29), the tread term
depends on V and T only through the reduced speed :math:`V a_T(T)`; it is evaluated once per
load for all reduced speeds.

**Carcass** (belt, plies, sidewalls, bead: what the tread's compression cannot explain; a
passenger tire's tread layer contributes roughly half of the losses, Walter & Conant, *Tire Sci.
Technol.* 2, 235 (1974); Schuring, *Rubber Chem. Technol.* 53, 600 (1980)). The deflection-
energy argument: each material element of the structure is strained by the passage through the
footprint, a pulse repeated once per revolution (angular frequency :math:`\Omega = V/R_e`).
For a linear material with loss modulus :math:`E'' = \eta(\omega) E'`, a strain
:math:`c\cos\omega t` loses :math:`\pi E'' c^2` per cycle; a periodic strain
:math:`\varepsilon(t) = \sum_n \hat\varepsilon_n e^{in\Omega t}` goes through n cycles of
its n-th harmonic per revolution and so loses
:math:`4\pi\sum_{n\ge1} n\,\eta(n\Omega)\,E'|\hat\varepsilon_n|^2` per revolution, where
:math:`E'|\hat\varepsilon_n|^2` is the time-averaged energy stored in harmonic n. Summed over
all elements (every phase of the pulse is present at any instant) the stored energy is the
tire's deflection energy :math:`U = \chi F_z^2/(2 C_z')` (:math:`C_z'` the vertical stiffness
at the inflation pressure, :math:`\chi` the share of it stored in the lossy structure rather
than in the inflation gas), split over the harmonics as the pulse shape g is, so that

.. math:: E_{\rm rev} = 4\pi U \sum_{n\ge1} n\,w_n\,\eta(n\Omega),\qquad
          w_n = \frac{2|\hat g_n|^2}{\langle g^2\rangle},\qquad
          f_{\rm carcass} = \frac{E_{\rm rev}}{2\pi R_e F_z}
          = \chi\,\frac{F_z}{C_z' R_e}\sum_{n\ge1} n\,w_n\,\eta(n\Omega) .

The pulse is that of a radial-spring (Winkler) ring flattened over the patch length 2a of the
patch law, :math:`g = 1 - x^2/a^2` for :math:`|x| < a` (travel coordinate x, period
:math:`2\pi R_e`). Each element thus goes through one load-unload cycle per revolution, and
the loss per revolution is of the order of :math:`\pi\eta` times the sum of the elements'
peak energies, :math:`U` times :math:`\sim\pi R_e/a` (:math:`\sum n w_n` grows as R/a).
Two cases integrate by hand (tests): :math:`\sum_n w_n = 1 - 5a/(6\pi R_e)` (the mean
:math:`\hat g_0` carries no loss), and for a Kelvin-Voigt material, :math:`\eta = \omega\tau`,
Parseval gives :math:`\sum n^2 w_n = R_e^2\langle (dg/dx)^2\rangle/\langle g^2\rangle
= 5R_e^2/(2a^2)`, i.e. :math:`f = (5/2)\chi\tau\rho V/a^2`
(:math:`\rho = F_z/C_z'`), the time-domain loss :math:`\int E\tau\dot\varepsilon^2 dt`.
The same "loss = hysteresis times strain energy" bookkeeping is what finite-element
rolling-resistance and tire-temperature models apply element by element (Lin & Hwang, *Math.
Comput. Simul.* 67, 235 (2004)).

The carcass loss tangent follows the rubbery-side power law
:math:`\eta(\omega, T) = \eta_{\rm ref}\,(\omega a_c(T)/(\omega_{\rm ref} a_c(T_{\rm ref})))^m`,
capped at 1, with the WLF shift of the "universal" constants referred to the carcass rubber's
glass temperature (Williams, Landel & Ferry, *J. Am. Chem. Soc.* 77, 3701 (1955)),
:math:`\log_{10} a_c = -17.44 (T - T_g)/(51.6 + T - T_g)`. Its parameters are in the tire
file's ``[rolling_resistance]`` table, each with its source or marked as a judgment.

**Belt and tread band** (:func:`belt_coefficient`): every belt section is flattened over the
patch and bent back beyond it once per revolution, whatever the load; its bending energy
follows the contact length, not the deflection squared, and is lost through the belt skim's
loss tangent; the tread rubber on the belt bends with it (the tread compound's E''). Their
energy is taken out of the structure's deflection work, the sidewalls keep the rest.

**The tread between belt and road** (``tread_loading = "series"``, :func:`tread_coefficient`):
the road imposes the tread surface's deflection, which the tread and the belt share in series
(:func:`belt_compliance`, :func:`series_factor`), so the footprint loss lies between
stress-controlled (E''/|E|^2) and strain-controlled (E''): Futamura's deformation index
(:func:`deformation_index`) from the two compliances. The structure stores the share
:func:`structure_share` of the deflection work (its stiffness does not change with the
inflation; the pneumatic part is lossless). :func:`iso28580` evaluates the ISO point at the
tire's thermal equilibrium (:func:`steady_temperature`), as the standard measures.

The vertical spring whose deflection and work the carcass term uses is MF 6.1/6.2's
progressive one (:func:`deflection`, :func:`structure_energy`; ``q_fz2``).

Limits (approximate physics, said so; docs/rolling.md, "Limits"): the sidewalls' deflection
energy grows nearly as :math:`F_z^2` (as :math:`F_z^{1.9}` on the MF spring): the whole
tire's load exponent (1.10 at 25 C, 1.07 warm) stays above the measured ~0.85-1; the change
per K (-0.36 %/K at 25 C, -0.29 %/K of the ambient warm) is short of ISO 28580's
-0.8 %/K. One temperature (the tread's) stands for the whole tire; the frequency content is
that of a ring, not of a shell; standing waves (above ~150 km/h) are not modelled.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from lookup.compound import Compound
from lookup.rolling import (
    EffectiveModulus,
    _check_profile,
    _profile_integral,
    bonded_layer_factor,
    layer_weight,
)
from tirefric.errors import ConvergenceError, InputError

from .params import TireParams

#: Speed below which the coefficient is held at its value (creep limit) [m/s]: the rolling
#: frequency is then below 0.05 Hz, quasi-static for the rubber on the rubbery side.
V_CREEP = 0.1

#: Default node vectors of :func:`core_table` (rolling speed 0.1-70 m/s, tread temperature
#: 230-400 K, load 200-12000 N).
CORE_LOG10_V = np.linspace(-1.0, math.log10(70.0), 15)
CORE_T_K = np.linspace(230.0, 400.0, 18)
CORE_LOG10_FZ = np.linspace(math.log10(200.0), math.log10(12000.0), 12)

#: ISO 28580 test conditions (passenger tires): 80 km/h, 25 C, 80 % of the load-index load.
ISO_SPEED = 80.0 / 3.6
ISO_T_K = 298.15
ISO_LOAD_SHARE = 0.8

#: EU tire label (Regulation (EU) 2020/740, C1 tires): upper bound of the RRC [N/kN] of each
#: class, the RRC taken to one decimal; above the last bound: class E.
EU_CLASS_BOUNDS = (("A", 6.5), ("B", 7.7), ("C", 9.0), ("D", 10.5))

#: WLF "universal" constants referred to T_g (Williams, Landel & Ferry 1955).
_WLF_C1, _WLF_C2 = 17.44, 51.6

#: Samples of the footprint profile (eq. 29) and of one revolution (carcass harmonics).
_N_PROFILE = 81
_N_REV = 4096


@dataclass(frozen=True)
class RollingResistanceParams:
    """Parameters of the rolling-resistance model (the tire TOML's ``[rolling_resistance]``).

    Attributes
    ----------
    tread_depth : float
        Tread thickness h [m] of eq. (29)'s layer.
    tread_support : str
        ``"winkler"`` (blocks free to bulge) or ``"bonded"`` (continuous layer on the belt).
    deflection_energy_share : float
        chi [1]: share of the deflection energy Fz^2/(2 C_z) stored in lossy material at the
        nominal pressure p_nom of the patch law; the structure's stiffness chi C_z does not
        change with the pressure (:func:`structure_share`).
    carcass_loss_tangent : float
        eta_ref [1] at the reference frequency and temperature.
    carcass_reference_frequency : float
        omega_ref [rad/s].
    carcass_reference_temperature : float
        T_ref [K].
    carcass_loss_slope : float
        m [1] of eta ~ (omega a_T)^m.
    carcass_T_g : float
        Glass temperature [K] of the carcass rubber's WLF shift.
    size : str
        Size designation (for the report).
    load_index : int
        Load index.
    load_index_load : float
        Maximum load of the load index [N].
    iso_inflation : float
        Inflation pressure of the ISO 28580 test [Pa].
    provenance : str
        Where the numbers come from.
    carcass_compound : str
        Compound file or shipped name of the carcass rubber (sidewall, ply skim): its master
        curve's loss tangent E''/E' at omega a_T(T), with its own shift, replaces the power
        law of the four ``carcass_*`` loss parameters above (then unused). Empty: the power
        law.
    carcass_pulse : str
        ``"ring"``: the radial deflection of a tensioned ring on the sidewalls' foundation,
        flattened over the patch and decaying beyond it (:func:`ring_pulse`); ``"footprint"``:
        the Winkler pulse confined to the patch (:func:`harmonic_weights`).
    belt_bending_stiffness : float
        EI [N m^2] of the belt package (steel belts, cap ply, skim and the tread band) for
        bending about the lateral axis; 0: no belt-bending term (:func:`belt_coefficient`).
        Needs ``carcass_pulse = "ring"``.
    belt_width : float
        Width [m] of the belt that carries the inflation's hoop tension T = p R0 b_belt, which
        sets the bending boundary layer sqrt(EI/T) at the patch edges.
    belt_compound : str
        Compound file or shipped name of the belt skim; empty: the carcass compound's loss.
    tread_loading : str
        How the footprint loads the tread (:func:`tread_coefficient`): ``"pressure"``, the
        patch law's pressure imposed on the tread whatever its modulus (stress-controlled,
        loss ~ E''/|E|^2); ``"series"``, the tread's compliance in series with the belt's
        (:func:`belt_compliance`) under the deflection imposed by the road, the patch law's
        pressure being the static one (the deformation index of :func:`deformation_index`).
        ``"series"`` needs ``belt_width`` > 0.
    q_fz2 : float
        [1] quadratic term of the MF 6.1/6.2 load-deflection law (MF ``Q_FZ2``) of the
        vertical spring whose deflection and work the carcass term uses (:func:`deflection`,
        :func:`structure_energy`); 0: the linear spring Fz = C_z' rho.
    """

    tread_depth: float
    tread_support: str
    deflection_energy_share: float
    carcass_loss_tangent: float
    carcass_reference_frequency: float
    carcass_reference_temperature: float
    carcass_loss_slope: float
    carcass_T_g: float
    size: str = ""
    load_index: int = 0
    load_index_load: float = 0.0
    iso_inflation: float = 0.0
    provenance: str = ""
    carcass_compound: str = ""
    carcass_pulse: str = "ring"
    belt_bending_stiffness: float = 0.0
    belt_width: float = 0.0
    belt_compound: str = ""
    tread_loading: str = "pressure"
    q_fz2: float = 0.0

    def __post_init__(self) -> None:
        if self.tread_loading not in ("pressure", "series"):
            raise InputError("must be 'pressure' or 'series'",
                             field="RollingResistanceParams.tread_loading",
                             value=self.tread_loading)
        if self.tread_loading == "series" and not (isinstance(self.belt_width, int | float)
                                                   and self.belt_width > 0):
            raise InputError("the series loading of the tread needs the belt width (> 0)",
                             field="RollingResistanceParams.belt_width", value=self.belt_width)
        for name in ("belt_bending_stiffness", "belt_width", "q_fz2"):
            x = getattr(self, name)
            if isinstance(x, bool) or not (isinstance(x, int | float) and math.isfinite(x)
                                           and x >= 0):
                raise InputError("must be a finite number >= 0",
                                 field=f"RollingResistanceParams.{name}", value=x)
        if self.belt_bending_stiffness > 0:
            if self.belt_width <= 0:
                raise InputError("a belt-bending term needs the belt width (> 0)",
                                 field="RollingResistanceParams.belt_width",
                                 value=self.belt_width)
            if self.carcass_pulse != "ring":
                raise InputError("the belt-bending term needs carcass_pulse = 'ring'",
                                 field="RollingResistanceParams.carcass_pulse",
                                 value=self.carcass_pulse)
        if self.carcass_pulse not in ("ring", "footprint"):
            raise InputError("must be 'ring' or 'footprint'",
                             field="RollingResistanceParams.carcass_pulse",
                             value=self.carcass_pulse)
        for name in ("tread_depth", "carcass_reference_frequency",
                     "carcass_reference_temperature", "carcass_T_g"):
            _positive(getattr(self, name), f"RollingResistanceParams.{name}")
        for name in ("deflection_energy_share", "carcass_loss_tangent", "carcass_loss_slope",
                     "load_index_load", "iso_inflation"):
            x = getattr(self, name)
            if not (isinstance(x, int | float) and math.isfinite(x) and x >= 0):
                raise InputError("must be a finite number >= 0",
                                 field=f"RollingResistanceParams.{name}", value=x)
        if self.tread_support not in ("winkler", "bonded"):
            raise InputError("must be 'winkler' or 'bonded'",
                             field="RollingResistanceParams.tread_support",
                             value=self.tread_support)
        if not self.carcass_reference_temperature - self.carcass_T_g > -_WLF_C2 + 1.0:
            raise InputError("reference temperature too far below T_g for the WLF shift",
                             field="RollingResistanceParams.carcass_reference_temperature",
                             value=self.carcass_reference_temperature)

    def carcass_log10_aT(self, T: np.ndarray) -> np.ndarray:
        """log10 a_c(T) - log10 a_c(T_ref): WLF with the universal constants at T_g."""
        def wlf(t):
            d = np.asarray(t, float) - self.carcass_T_g
            return -_WLF_C1 * d / (_WLF_C2 + d)
        return wlf(T) - wlf(self.carcass_reference_temperature)

    def carcass_loss(self, omega: np.ndarray, T: np.ndarray) -> np.ndarray:
        """Carcass loss tangent eta(omega, T) [1]: the carcass compound's E''/E' at
        omega a_T(T) (its small-strain master curve and shift), or the power law on the
        rubbery side, capped at 1.

        omega [rad/s] > 0 and T [K] broadcast together.
        """
        if self.carcass_compound:
            return _compound_loss(self.carcass_compound, omega, T)
        x = (np.log10(np.asarray(omega, float) / self.carcass_reference_frequency)
             + self.carcass_log10_aT(T))
        return np.minimum(self.carcass_loss_tangent * 10.0 ** (self.carcass_loss_slope * x),
                          1.0)


    def belt_loss(self, omega: np.ndarray, T: np.ndarray) -> np.ndarray:
        """Belt-skim loss tangent eta(omega, T) [1]: E''/E' of ``belt_compound``'s master
        curve at omega a_T(T), or the carcass loss (:meth:`carcass_loss`) without one."""
        if self.belt_compound:
            return _compound_loss(self.belt_compound, omega, T)
        return self.carcass_loss(omega, T)


def _compound_loss(name: str, omega: np.ndarray, T: np.ndarray) -> np.ndarray:
    """E''/E' of a compound's small-strain master curve at omega a_T(T) (its own shift)."""
    c = _carcass_compound(name)
    om, TT = np.broadcast_arrays(np.asarray(omega, float), np.asarray(T, float))
    lred = np.log10(om) + np.asarray(c.log10_aT(TT), float)
    lw, ltan = _loss_tangent_table(name)
    return 10.0 ** np.interp(lred, lw, ltan)


@functools.lru_cache(maxsize=8)
def _carcass_compound(name: str) -> Compound:
    from lookup.compound import load_compound

    return load_compound(name)


@functools.lru_cache(maxsize=8)
def _loss_tangent_table(name: str) -> tuple[np.ndarray, np.ndarray]:
    """log10 of E''/E' of a carcass compound's master curve on log10 omega (reduced to its
    T_ref) from 1e-10 to 1e18 rad/s, 200 nodes per decade, read linearly in log-log (within
    1e-5 of the master curve for a Prony series; held at the end values outside)."""
    c = _carcass_compound(name)
    lw = np.linspace(-10.0, 18.0, 28 * 200 + 1)
    Er, Ei = c.modulus.storage_loss(10.0 ** lw)
    return lw, np.log10(np.maximum(np.asarray(Ei) / np.asarray(Er), 1e-300))


def _positive(x: object, name: str) -> float:
    if isinstance(x, bool) or not isinstance(x, int | float) or not (math.isfinite(x) and x > 0):
        raise InputError("must be a finite number > 0", field=name, value=x)
    return float(x)


@functools.lru_cache(maxsize=16)
def _load_from_file(path: str) -> RollingResistanceParams:
    from tirefric.config import Table

    t = Table.load(path)
    tab = t.table("rolling_resistance", required=False)
    if tab is None:
        raise InputError("the tire file has no [rolling_resistance] table (the parameters of "
                         "tire_brush.rolling_resistance)", source=Path(path),
                         field="rolling_resistance")
    T = "temperature"
    comp = tab.string("carcass_compound", "")
    if comp:  # the compound's loss replaces the power law: its parameters are optional
        law = {"carcass_loss_tangent": 0.0, "carcass_reference_frequency": 2 * math.pi,
               "carcass_reference_temperature": 333.15, "carcass_loss_slope": 0.0,
               "carcass_T_g": 213.15}
        cpath = Path(path).parent / comp
        comp = str(cpath) if cpath.suffix == ".toml" and cpath.is_file() else comp
    else:
        law = {}
    bcomp = tab.string("belt_compound", "")
    if bcomp:
        bpath = Path(path).parent / bcomp
        bcomp = str(bpath) if bpath.suffix == ".toml" and bpath.is_file() else bcomp
    try:
        _carcass_compound(comp) if comp else None
        _carcass_compound(bcomp) if bcomp else None
        out = RollingResistanceParams(
            tread_depth=tab.quantity("tread_depth", "length", positive=True),
            tread_support=tab.string("tread_support", choices=("winkler", "bonded")),
            deflection_energy_share=tab.quantity("deflection_energy_share", "dimensionless",
                                                 nonnegative=True, maximum=1.0),
            carcass_loss_tangent=tab.quantity("carcass_loss_tangent", "dimensionless",
                                              law.get("carcass_loss_tangent", ...),
                                              nonnegative=True, maximum=1.0),
            carcass_reference_frequency=tab.quantity(
                "carcass_reference_frequency", "angular_frequency",
                law.get("carcass_reference_frequency", ...), positive=True),
            carcass_reference_temperature=tab.quantity(
                "carcass_reference_temperature", T, law.get("carcass_reference_temperature", ...),
                positive=True),
            carcass_loss_slope=tab.quantity("carcass_loss_slope", "dimensionless",
                                            law.get("carcass_loss_slope", ...), nonnegative=True,
                                            maximum=1.0),
            carcass_T_g=tab.quantity("carcass_T_g", T, law.get("carcass_T_g", ...), positive=True),
            carcass_compound=comp,
            carcass_pulse=tab.string("carcass_pulse", "ring", choices=("ring", "footprint")),
            belt_bending_stiffness=tab.quantity("belt_bending_stiffness", "bending_stiffness",
                                                0.0, nonnegative=True),
            belt_width=tab.quantity("belt_width", "length", 0.0, nonnegative=True),
            belt_compound=bcomp,
            tread_loading=tab.string("tread_loading", "pressure",
                                     choices=("pressure", "series")),
            q_fz2=tab.quantity("q_fz2", "dimensionless", 0.0, nonnegative=True),
            size=tab.string("size", ""),
            load_index=tab.integer("load_index", 0, minimum=0),
            load_index_load=tab.quantity("load_index_load", "force", 0.0, nonnegative=True),
            iso_inflation=tab.quantity("iso_inflation", "pressure", 0.0, nonnegative=True),
            provenance=tab.string("provenance", ""),
        )
    except InputError as exc:
        raise InputError(exc.message, source=Path(path), field=exc.field,
                         value=exc.value) from None
    tab.check_unknown()
    return out


def load_rolling_params(params: TireParams) -> RollingResistanceParams:
    """The ``[rolling_resistance]`` table of the file ``params`` was read from."""
    if not params.source:
        raise InputError("tire parameters built in code carry no [rolling_resistance] table: "
                         "pass rr=RollingResistanceParams(...)", field="rolling_resistance")
    return _load_from_file(str(params.source))


@dataclass(frozen=True)
class RollingResistance:
    """Result of :func:`rolling_resistance` (arrays of the broadcast input shape).

    Attributes
    ----------
    f_r : numpy.ndarray
        Coefficient F_r / Fz [1] (0 where Fz = 0).
    f_tread, f_carcass : numpy.ndarray
        Its tread (eq. 29) and carcass parts [1] (the carcass part: the sidewalls'
        deflection energy plus the belt's bending, f_belt).
    F_r : numpy.ndarray
        Resistance force f_r Fz [N] (>= 0, opposing the motion).
    My : numpy.ndarray
        Rolling-resistance moment of the road on the tire [N m], ISO-W:
        -sign(V) f_r Fz R_e (negative for forward rolling, 0 at V = 0 or Fz = 0).
    heat_rate : numpy.ndarray
        Power dissipated, F_r |V| [W].
    tread_share : numpy.ndarray
        Share of heat_rate dissipated in the tread layer, f_tread / f_r [1] (0 where f_r = 0).
    f_belt : numpy.ndarray or None
        The belt package's bending loss [1] (:func:`belt_coefficient`); f_carcass includes
        it.
    f_band : numpy.ndarray or None
        The tread band's bending loss [1] (:func:`belt_coefficient`); f_tread includes it
        (it heats the tread).
    """

    f_r: np.ndarray
    f_tread: np.ndarray
    f_carcass: np.ndarray
    F_r: np.ndarray
    My: np.ndarray
    heat_rate: np.ndarray
    tread_share: np.ndarray
    f_belt: np.ndarray | None = None
    f_band: np.ndarray | None = None

    @property
    def rrc_N_per_kN(self) -> np.ndarray:
        """Rolling-resistance coefficient in N/kN (1000 f_r)."""
        return 1000.0 * self.f_r


# -- the parts ---------------------------------------------------------------------------------
def footprint_profile(params: TireParams, Fz: float, n: int = _N_PROFILE
                      ) -> tuple[np.ndarray, np.ndarray, float]:
    """Pressure along the footprint of :class:`~tire_brush.params.PatchLaw` at load ``Fz``.

    Flat at ``p_peak`` over ``|x| <= c`` with parabolic ends ``p_peak (1 - t^2)``,
    ``t = (|x| - c)/(a - c)``; ``p_peak = 3 Fz / (2 a b (2 + c/a))`` so that the mean pressure
    is ``Fz / (2 a b)`` (the PatchLaw docstring).

    Returns
    -------
    x : numpy.ndarray
        Positions [m] from -a to a.
    p : numpy.ndarray
        Gross pressure [Pa].
    b : float
        Patch width [m].
    """
    law = params.patch
    a, b = law.size(Fz)
    c = law.flat_share(Fz) * a
    p_peak = 3.0 * Fz / (2.0 * a * b * (2.0 + c / a))
    x = np.linspace(-a, a, n)
    t = np.clip((np.abs(x) - c) / (a - c), 0.0, 1.0)
    return x, p_peak * (1.0 - t * t), b


def belt_compliance(params: TireParams, rr: RollingResistanceParams, Fz: float,
                    q: np.ndarray) -> np.ndarray:
    r"""Compliance [m/Pa] of the belt under a footprint-pressure component of wavenumber q.

    The belt is the tensioned ring of :func:`ring_pulse` with the bending stiffness EI of
    ``belt_bending_stiffness``: a beam of hoop tension :math:`T = p R_0 b_{\rm belt}` on the
    sidewalls' radial foundation :math:`k = T/\lambda^2` (the decay length of the ring's
    deflection beyond the patch). Under a pressure :math:`\hat p\cos qx` acting over the patch
    width b its deflection is :math:`\hat p\,b/(EI q^4 + T q^2 + k)` (a tensioned beam on an
    elastic foundation; the flexible-ring tire models: Gong, PhD thesis TU Delft (1993);
    Pacejka 2012, sec. 9.2), so

    .. math:: c_b(q) = \frac{b}{EI\,q^4 + T\,(q^2 + \lambda^{-2})} .

    The belt's own loss is left out here (it is :func:`belt_coefficient`'s). ``lambda = 0``
    (no tail, :func:`ring_pulse`) drops the foundation term.
    """
    a, b = params.patch.size(Fz)
    rho = deflection(params, rr, min(Fz, params.patch.Fz_max))
    _, lam = ring_pulse(a, rho, params.patch.R0)
    tension = params.patch.p_inflation * params.patch.R0 * rr.belt_width
    q = np.asarray(q, float)
    k = tension / lam**2 if lam > 0 else 0.0
    return b / (rr.belt_bending_stiffness * q**4 + tension * q * q + k)


def deformation_index(c_t: float | np.ndarray, c_b: float | np.ndarray
                      ) -> float | np.ndarray:
    r"""Deformation index n of the tread under the series loading (:func:`series_factor`).

    Futamura (*Rubber Chem. Technol.* 64, 57 (1991)) writes the hysteresis loss of a rubber
    part under a mixed loading as :math:`E''/|E|^n`: n = 0 where the deformation is imposed
    (strain-controlled), 1 where the energy is (loss ~ tan delta), 2 where the stress is. For
    the tread (compliance :math:`c_t = s/E`) in series with the belt (:math:`c_b`, elastic)
    under an imposed deflection d, the loss :math:`\omega\,\mathrm{Im}(c_t)\,|d|^2/|c_t +
    c_b|^2` scales at small tan delta as :math:`\tan\delta\,|E|/(s + c_b|E|)^2`, i.e. as
    :math:`E''/|E|^n` with the local exponent

    .. math:: n = \frac{2 c_b}{c_b + |c_t|} :

    0 on a rigid belt (:math:`c_b \to 0`: the belt imposes the tread's compression), 2 on a
    belt much softer than the tread (:math:`c_b \to \infty`: the pressure is imposed).
    """
    c_t = np.asarray(c_t, float)
    c_b = np.asarray(c_b, float)
    return 2.0 * c_b / (c_b + c_t)


def series_factor(c_t: np.ndarray, c_t_ref: np.ndarray, c_b: np.ndarray) -> np.ndarray:
    r"""Ratio :math:`|\hat p(q)|^2/|\hat p_{\rm ref}(q)|^2` of a footprint-pressure component
    under an imposed deflection to its value in the reference state.

    The road imposes the tread surface's deflection in the patch (the tire's circle cut by
    the road); the tread (complex compliance :math:`c_t` per unit footprint area, at the
    rolling frequency qV) and the belt (:math:`c_b`, elastic) share it in series,
    :math:`\hat d = (c_t + c_b)\hat p`. With the deflection of the reference state
    (:math:`c_{t,\rm ref}`), the pressure component changes by

    .. math:: \frac{|\hat p|^2}{|\hat p_{\rm ref}|^2} = \frac{|c_{t,\rm ref} + c_b|^2}
              {|c_t + c_b|^2} :

    1 on a belt much softer than the tread (the pressure imposed: review eq. 29 as it stands)
    and :math:`|c_{t,\rm ref}|^2/|c_t|^2` on a rigid belt (the tread's compression imposed).
    ``c_t``, ``c_t_ref`` complex, ``c_b`` real, broadcast together.
    """
    return np.abs(c_t_ref + c_b) ** 2 / np.abs(c_t + c_b) ** 2


def tread_coefficient(params: TireParams, compound: Compound, rr: RollingResistanceParams,
                      Fz: float, V_reduced: np.ndarray) -> np.ndarray:
    r"""Tread part of f_r at one load for rolling speeds already reduced to the compound's T_ref.

    Review eq. (29) through a layer (see the module doc and
    :func:`lookup.rolling.tread_rolling_resistance`, which this reproduces for one speed),
    :math:`V_{\rm red} = V a_T(T)`. Divided by the land share for the Winkler (grooved) tread.

    With ``tread_loading = "series"`` each pressure component :math:`|\hat p(q)|^2` is
    multiplied by :func:`series_factor` at :math:`\omega = qV_{\rm red}`: the tread's compliance
    per unit gross footprint area, :math:`c_t = h/((1-\phi)E(\omega))` (Winkler) or
    :math:`2K(qh)/(qE_{\rm eff}(\omega))` (bonded), in series with the belt's
    (:func:`belt_compliance`) under the deflection the road imposes. The patch law's pressure
    is taken as the rolling tire's at the ISO 28580 point (80 km/h, 25 C; a judgment,
    docs/rolling.md: the footprint is characterised at one state, and the tread's modulus
    there sets how the deflection splits); away from it the pressure components follow the
    tread's modulus through the series factor. The belt's compliance depends on q only and
    the reference is one reduced speed, so the tread part still depends on V and T only
    through :math:`V a_T(T)`.
    """
    x, p, _ = footprint_profile(params, Fz)
    land = 1.0 - params.tread.void_ratio if rr.tread_support == "winkler" else 1.0
    x, p_rubber, f_N = _check_profile(x, p / land)
    mod = EffectiveModulus(compound, compound.T_ref)
    if rr.tread_loading == "series":
        weight = _series_weight(params, rr, compound, mod, Fz, land)
    else:
        weight = layer_weight(mod, rr.tread_depth, compound.nu, rr.tread_support)
    V_reduced = np.asarray(V_reduced, float)
    return _profile_integral(x, p_rubber, f_N, V_reduced.ravel(), weight).reshape(
        V_reduced.shape)


def _tread_shape(rr: RollingResistanceParams, nu: float, land: float, q: np.ndarray
                 ) -> np.ndarray:
    """s(q) [m] of the tread's compliance per unit gross footprint area, c_t = s/E_eff(omega):
    h/((1 - nu^2)(1 - phi)) for the Winkler columns (Young's modulus (1 - nu^2) E_eff, the
    pressure on the land share 1 - phi), 2 K(qh)/q for the bonded layer (review sec. 5.1)."""
    if rr.tread_support == "bonded":
        return 2.0 * bonded_layer_factor(q * rr.tread_depth, nu) / q
    return rr.tread_depth / ((1.0 - nu**2) * land) + 0.0 * q


def _series_weight(params: TireParams, rr: RollingResistanceParams, compound: Compound,
                   mod: EffectiveModulus, Fz: float, land: float):
    """eq. (29)'s weight q Im C(q, omega) times :func:`series_factor`, the reference state
    the rolling tire at the ISO 28580 speed and temperature (:func:`tread_coefficient`)."""
    nu = compound.nu
    log10_v_ref = math.log10(ISO_SPEED) + float(compound.log10_aT(np.asarray(ISO_T_K)))

    def compliance(q, w):  # c_t per unit gross area, Im > 0 (review eq. 4 convention)
        Er, Ei = mod.storage_loss(w)
        return _tread_shape(rr, nu, land, q) * (Er + 1j * Ei) / (Er * Er + Ei * Ei)

    def weight(q, w):
        c_t = compliance(q, w)
        fac = series_factor(c_t, compliance(q, q * 10.0**log10_v_ref),
                            belt_compliance(params, rr, Fz, q))
        # q Im C per unit rubber pressure (as layer_weight): q land Im(c_t)
        return q * land * c_t.imag * fac
    return weight


def harmonic_weights(a: float, R: float, n_rev: int = _N_REV) -> np.ndarray:
    """Weights w_n (n = 1 .. n_rev/2) of the deflection pulse's harmonics (module doc).

    The pulse ``g = 1 - x^2/a^2`` on ``|x| < a`` of a revolution of length ``2 pi R``;
    ``w_n = 2 |g_n|^2 / <g^2>``, so that ``sum w_n = 1 - g_0^2/<g^2> = 1 - 5a/(6 pi R)``.
    """
    L = 2.0 * math.pi * R
    s = (np.arange(n_rev) + 0.5) * (L / n_rev) - 0.5 * L
    g = np.clip(1.0 - (s / a) ** 2, 0.0, None)
    gh = np.fft.rfft(g) / n_rev
    mean_sq = float(np.mean(g * g))
    w = 2.0 * np.abs(gh[1:]) ** 2 / mean_sq
    if n_rev % 2 == 0:  # the Nyquist term is not paired
        w[-1] *= 0.5
    return w


def ring_pulse(a: float, rho: float, R0: float) -> tuple[float, float]:
    r"""Edge deflection w_a [m] and decay length lambda [m] of the ring's radial deflection.

    A tensioned ring (the belt under the inflation's hoop tension) on the sidewalls' radial
    foundation, pressed flat over the patch |x| < a by the deflection rho: inside the patch
    its radial deflection is that of the circle of radius R0 cut by the road,
    :math:`\delta = \rho - x^2/(2R_0)`; outside, a string on an elastic foundation
    (:math:`T\delta'' = k\delta`) decays as :math:`w_a e^{-(|x| - a)/\lambda}`,
    :math:`\lambda = \sqrt{T/k}` (the flexible-ring/string tire models: Clark (ed.),
    *Mechanics of Pneumatic Tires*, NHTSA/US DOT (1981); Gong, *A study of in-plane dynamics
    of tires*, PhD thesis, TU Delft (1993); Pacejka 2012, sec. 9.2). The ring has no kink at
    the patch edge, so the slopes match, :math:`w_a/\lambda = a/R_0`, with
    :math:`w_a = \rho - a^2/(2R_0)`: the deformed zone's length follows from the measured
    patch length a(Fz) and deflection rho = Fz/C_z' (the tire file's patch law and vertical
    stiffness), not from a judged parameter. ``w_a = 0`` (no tail) if the patch law's a
    reaches the circle's chord.
    """
    w_a = max(rho - a * a / (2.0 * R0), 0.0)
    return w_a, (w_a * R0 / a if a > 0 else 0.0)


def ring_pulse_weights(a: float, rho: float, R0: float, R: float, n_rev: int = _N_REV
                       ) -> np.ndarray:
    """Weights w_n (n = 1 .. n_rev/2) of the ring pulse's harmonics (:func:`ring_pulse`):
    ``g = delta / rho`` on a revolution of length 2 pi R, ``w_n = 2 |g_n|^2 / <g^2>``."""
    w_a, lam = ring_pulse(a, rho, R0)
    L = 2.0 * math.pi * R
    s = (np.arange(n_rev) + 0.5) * (L / n_rev) - 0.5 * L
    inside = np.abs(s) <= a
    tail = w_a * np.exp(-(np.abs(s) - a) / lam) if lam > 0 else np.zeros_like(s)
    g = np.where(inside, rho - s * s / (2.0 * R0), tail) / rho
    gh = np.fft.rfft(g) / n_rev
    w = 2.0 * np.abs(gh[1:]) ** 2 / float(np.mean(g * g))
    if n_rev % 2 == 0:
        w[-1] *= 0.5
    return w


def belt_curvature(a: float, rho: float, R0: float, R: float, l_b: float,
                   n_rev: int = _N_REV) -> tuple[np.ndarray, np.ndarray]:
    r"""Change of the belt's curvature kappa(s) [1/m] over one revolution of length 2 pi R.

    The belt follows the ring's radial deflection delta(s) (:func:`ring_pulse`), and for a
    deflection small against R0 its curvature changes by :math:`\kappa = \delta''`: -1/R0
    over the flattened patch |s| < a (the curvature 1/R0 is removed), and
    :math:`(w_a/\lambda^2) e^{-(|s|-a)/\lambda}` in the transition zones beyond it, where the
    belt bends back more sharply than the circle (the overshoot, which grows with the
    deflection); the two integrate to zero (:math:`w_a/\lambda = a/R_0`), the ring closes.
    The string solution jumps in curvature at the patch edge; the belt's bending stiffness EI
    under the hoop tension T spreads the jump over the boundary layer
    :math:`l_b = \sqrt{EI/T}` (a tensioned beam, :math:`(1 - l_b^2 d^2/ds^2)\kappa =
    \kappa_{\rm string}`; the flexible-ring models, Gong, PhD thesis TU Delft (1993);
    Pacejka 2012, sec. 9.2), i.e. harmonic n is divided by :math:`1 + (n l_b/R)^2`.
    ``l_b = 0`` keeps the string's jump. The curvature change :math:`\delta/R_0^2` of the
    undeflected part of the ring is neglected (relative size :math:`(\lambda/R_0)^2`).

    Returns
    -------
    s : numpy.ndarray
        Travel coordinate [m] of the ``n_rev`` samples, from -pi R to pi R.
    kappa : numpy.ndarray
        Curvature change [1/m] at s (its mean removed).
    """
    w_a, lam = ring_pulse(a, rho, R0)
    L = 2.0 * math.pi * R
    s = (np.arange(n_rev) + 0.5) * (L / n_rev) - 0.5 * L
    tail = (w_a / lam**2) * np.exp(-(np.abs(s) - a) / lam) if lam > 0 else np.zeros_like(s)
    kappa = np.where(np.abs(s) <= a, -1.0 / R0, tail)
    kh = np.fft.rfft(kappa)
    kh[0] = 0.0
    if l_b > 0:
        n = np.arange(kh.size, dtype=float)
        kh /= 1.0 + (n * l_b / R) ** 2
    return s, np.fft.irfft(kh, n_rev)


def belt_harmonics(a: float, rho: float, R0: float, R: float, l_b: float,
                   n_rev: int = _N_REV) -> np.ndarray:
    """Mean-square curvature change of each harmonic, c_n = 2|kappa_n|^2 [1/m^2]
    (n = 1 .. n_rev/2) of :func:`belt_curvature`, so that sum c_n = <kappa^2>: the belt's
    bending energy at any instant is U_b = (EI/2) 2 pi R sum c_n. For l_b -> 0,
    U_b -> EI/R0^2 (a + a^2/(2 lambda)): the flattened patch plus the two transition zones."""
    _, kappa = belt_curvature(a, rho, R0, R, l_b, n_rev)
    kh = np.fft.rfft(kappa) / n_rev
    c = 2.0 * np.abs(kh[1:]) ** 2
    if n_rev % 2 == 0:  # the Nyquist term is not paired
        c[-1] *= 0.5
    return c


@dataclass(frozen=True)
class BeltBending:
    """Result of :func:`belt_coefficient` at one load (arrays of the broadcast V, T shape)."""

    f_belt: np.ndarray
    """Loss of the belt package's bending (its skim compound) over F_z [1]."""
    f_band: np.ndarray
    """Loss of the tread band bent with the belt (the tread compound's E'') over F_z [1]."""
    U: np.ndarray
    """Bending energy of belt and tread band at any instant [J]."""
    l_b: float
    """Bending boundary layer sqrt(EI/T) at the patch edges [m]."""


def _modulus_loglog(compound: Compound, log10_omega: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """E'(omega), E''(omega) of the compound's small-strain master curve (at its T_ref) at
    log10 omega, read linearly in log-log from fixed nodes 0.01 decade apart over the range
    asked (within 1e-5 of the master curve for the shipped summer compound; one evaluation
    of the spectrum per node instead of per point)."""
    # nodes on the fixed lattice k/100 decades, so that a point reads the same two nodes
    # whatever else is asked with it (the result does not depend on the batch)
    k0 = math.floor(float(np.min(log10_omega)) * 100.0)
    k1 = max(math.ceil(float(np.max(log10_omega)) * 100.0), k0 + 1)
    lw = np.arange(k0, k1 + 1) / 100.0
    Er, Ei = compound.modulus.storage_loss(10.0 ** lw)
    lr = np.log10(np.maximum(np.asarray(Er, float), 1e-300))
    li = np.log10(np.maximum(np.asarray(Ei, float), 1e-300))
    return 10.0 ** np.interp(log10_omega, lw, lr), 10.0 ** np.interp(log10_omega, lw, li)


def belt_coefficient(params: TireParams, rr: RollingResistanceParams, Fz: float,
                     V: np.ndarray, T: np.ndarray, compound: Compound | None = None,
                     n_rev: int = _N_REV) -> BeltBending:
    r"""Bending losses of the belt and of the tread band on it, at one load.

    Every section of the belt is flattened once per revolution, whatever the load, and bent
    back beyond the patch more sharply than the circle (:func:`belt_curvature`). For a
    bending stiffness with loss, :math:`B = B' + iB''`, a curvature harmonic
    :math:`\kappa_n` loses :math:`\pi B''|	ext{amplitude}|^2` per cycle and per unit length
    and goes through n cycles per revolution (as the carcass, module doc), so that with
    :math:`c_n = 2|\hat\kappa_n|^2` and :math:`L = 2\pi R_e`

    .. math:: f = rac{E_{
m rev}}{L F_z} = rac{L}{R_e F_z}\sum_{n\ge1} n\,c_n\,
              B''(n V/R_e, T) .

    Two layers bend: the belt package, :math:`B'' = EI\,\eta_b` (its skim compound's loss
    tangent, :meth:`RollingResistanceParams.belt_loss`); and the tread rubber bonded on it,
    whose neutral axis is the (circumferentially inextensible) steel belt:
    :math:`B = I_t E(\omega a_T)/(1-
u^2)`, :math:`I_t = (1-\phi) b_{
m belt} h^3/3`
    (tread depth h, void ratio phi, plane strain across the belt's width), with the tread
    compound's small-strain master curve: this part of the tread's loss is strain-imposed
    (loss ~ E''), unlike the footprint-pressure part (eq. 29, loss ~ E''/|E|^2). The hoop
    tension is :math:`T = p R_0 b_{
m belt}` (the ring's pretension by the inflation
    pressure p; Gong 1993; Pacejka 2012, sec. 9.2). Zero without a belt EI.
    """
    V = np.asarray(V, float)
    T_K = np.asarray(T, float)
    Vb, Tb = np.broadcast_arrays(V, T_K)
    EI = rr.belt_bending_stiffness
    zero = np.zeros(Vb.shape)
    if EI <= 0.0:
        return BeltBending(zero, zero, zero, 0.0)
    a, _ = params.patch.size(Fz)
    rho = deflection(params, rr, min(Fz, params.patch.Fz_max))
    tension = params.patch.p_inflation * params.patch.R0 * rr.belt_width
    l_b = math.sqrt(EI / tension) if tension > 0 else 0.0
    c = belt_harmonics(a, rho, params.patch.R0, params.R_e, l_b, n_rev)
    n = np.arange(1, c.size + 1, dtype=float)
    # the boundary layer makes c_n fall as n^-6 beyond R/l_b: drop the harmonics whose
    # share of sum n c_n is below 1e-10 (the loss factors are bounded, so is their error)
    tail = np.cumsum((n * c)[::-1])[::-1]
    keep = max(int(np.count_nonzero(tail > 1e-10 * tail[0])), 1)
    c, n = c[:keep], n[:keep]
    L = 2.0 * math.pi * params.R_e
    omega = Vb[..., None] / params.R_e * n
    f_belt = EI * L / (params.R_e * Fz) * np.sum(n * c * rr.belt_loss(omega, Tb[..., None]),
                                                  axis=-1)
    U = 0.5 * EI * L * float(c.sum()) + zero
    f_band = zero.copy()
    if compound is not None:
        land = 1.0 - params.tread.void_ratio
        I_t = land * rr.belt_width * rr.tread_depth ** 3 / 3.0
        lred = np.log10(omega) + np.asarray(compound.log10_aT(Tb), float)[..., None]
        Er, Ei = _modulus_loglog(compound, lred)
        k = I_t / (1.0 - compound.nu ** 2)
        f_band = k * L / (params.R_e * Fz) * np.sum(n * c * Ei, axis=-1)
        U = U + 0.5 * k * L * np.sum(c * Er, axis=-1)
    return BeltBending(f_belt, f_band, U, l_b)


def structure_share(params: TireParams, rr: RollingResistanceParams) -> float:
    r"""Share of the deflection work :math:`F_z^2/(2C_z')` stored in the lossy structure at
    the inflation pressure p.

    The MF 6.2 pressure law of the vertical stiffness, :math:`C_z' = C_z(1 + p_{fz1}(p -
    p_{nom})/p_{nom})` (Pacejka 2012, sec. 4.3.2 / MF 6.2 PFZ1), is a pressure-independent
    structural spring :math:`C_s = \chi C_z` (:math:`\chi = 1 - p_{fz1}` at p_nom:
    ``deflection_energy_share``) in parallel with a pneumatic one proportional to p (the
    radial carcass carries that part of the load by its inflation tension: Clark (ed.),
    *Mechanics of Pneumatic Tires* (1981); Gent & Walter, *The Pneumatic Tire*, NHTSA
    (2006)), whose work the gas stores without loss. Both take the deflection
    :math:`\rho = F_z/C_z'`, so the structure stores :math:`C_s\rho^2/2` and its share is

    .. math:: \chi_p = \chi\,C_z/C_z' ,

    :math:`\chi` at p = p_nom, less above it (the pneumatic spring takes more of the load).
    """
    return rr.deflection_energy_share * params.patch.C_z / params.patch.vertical_stiffness


def _mf_vertical(params: TireParams, rr: RollingResistanceParams) -> tuple[float, float]:
    """(q_Fz1, q_Fz2) of the MF 6.1/6.2 load-deflection law (:func:`deflection`)."""
    patch = params.patch
    c = patch.C_z * patch.R0 / params.Fz_nom
    disc = c * c - 4.0 * rr.q_fz2
    if not disc > 0.0:
        raise InputError(f"the MF load-deflection law needs (C_z R0/Fz_nom)^2 = {c * c:.4g} "
                         "> 4 q_fz2", field="RollingResistanceParams.q_fz2", value=rr.q_fz2)
    return math.sqrt(disc), rr.q_fz2


def deflection(params: TireParams, rr: RollingResistanceParams, Fz: float) -> float:
    r"""Vertical deflection rho [m] of the tire under the load Fz [N] at its inflation pressure.

    The MF-Tyre 6.1/6.2 vertical force on a flat road, free rolling, without camber, speed or
    horizontal-force terms (Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), eq. (A3.3);
    Besselink, Schmeitz & Pacejka, *Veh. Syst. Dyn.* 48, suppl. 1, 337 (2010), which adds the
    pressure factor):

    .. math:: F_z = \bigl(1 + p_{Fz1}\,dp_i\bigr)\,F_{z0}\,
              \bigl(q_{Fz1}\,\xi + q_{Fz2}\,\xi^2\bigr),\qquad \xi = \rho/R_0,
              \qquad q_{Fz1} = \sqrt{(C_z R_0/F_{z0})^2 - 4 q_{Fz2}} ,

    dp_i = (p - p_nom)/p_nom; q_Fz1 is not a file parameter but follows from the vertical
    stiffness C_z, which is the slope dFz/drho at the nominal load F_z0 and pressure (the
    relation MFeval and TNO's MF-Tyre use for FITTYP 61/62). The spring stiffens with the
    deflection: at F_z0 the local exponent d ln F_z / d ln rho is above 1. Solved for xi in the
    form without cancellation, :math:`\xi = 2\tilde F/(q_{Fz1} + \sqrt{q_{Fz1}^2 +
    4 q_{Fz2}\tilde F})`, :math:`\tilde F = F_z/((1 + p_{Fz1} dp_i) F_{z0})`. With
    q_Fz2 = 0 it is the linear spring :math:`\rho = F_z/C_z'` of
    :attr:`~tire_brush.params.PatchLaw.vertical_stiffness`.
    """
    q1, q2 = _mf_vertical(params, rr)
    patch = params.patch
    F = max(float(Fz), 0.0) / (params.Fz_nom * patch.vertical_stiffness / patch.C_z)
    return patch.R0 * 2.0 * F / (q1 + math.sqrt(q1 * q1 + 4.0 * q2 * F))


def structure_energy(params: TireParams, rr: RollingResistanceParams, Fz: float) -> float:
    r"""Deflection work [J] stored in the lossy structure at the load Fz [N].

    The MF pressure factor multiplies the whole load-deflection law (:func:`deflection`), so the
    structural spring (the share :math:`\chi` = ``deflection_energy_share`` of the force at
    p_nom, which does not change with the pressure; :func:`structure_share`) carries
    :math:`\chi F_{z0}(q_{Fz1}\xi + q_{Fz2}\xi^2)` at the deflection :math:`\xi = \rho/R_0`
    and stores its integral over the deflection,

    .. math:: U_s = \chi\,F_{z0} R_0\,\bigl(q_{Fz1}\xi^2/2 + q_{Fz2}\xi^3/3\bigr) ,

    which for q_Fz2 = 0 is :math:`\chi_p F_z^2/(2C_z')` of the linear spring. A progressive
    spring stores less than that at a load above the one where its secant stiffness equals
    C_z': the work grows more slowly than :math:`F_z^2`.
    """
    q1, q2 = _mf_vertical(params, rr)
    xi = deflection(params, rr, Fz) / params.patch.R0
    return (rr.deflection_energy_share * params.Fz_nom * params.patch.R0
            * (0.5 * q1 * xi * xi + q2 * xi ** 3 / 3.0))


def carcass_coefficient(params: TireParams, rr: RollingResistanceParams, Fz: float,
                        V: np.ndarray, T: np.ndarray, n_rev: int = _N_REV,
                        U_belt: float | np.ndarray = 0.0) -> np.ndarray:
    r"""Carcass part of f_r at one load: :math:`\chi_p F_z/(C_z' R_e)\sum_n n w_n
    \eta(nV/R_e, T)`, :math:`\chi_p` the structure's share at the inflation pressure
    (:func:`structure_share`).

    ``V`` [m/s] > 0 and ``T`` [K] broadcast together; ``n_rev`` samples of a revolution
    (harmonics up to n_rev/2). ``U_belt`` [J], the belt's and tread band's bending energy
    (:func:`belt_coefficient`, broadcast with V and T), is taken out of the structure's
    deflection energy chi Fz^2/(2 C_z') (it is part of it: the belt is flattened by the
    load), leaving the sidewalls' share (not below 0).
    """
    a, _ = params.patch.size(Fz)
    if rr.carcass_pulse == "ring":
        rho = deflection(params, rr, min(Fz, params.patch.Fz_max))
        w = ring_pulse_weights(a, rho, params.patch.R0, params.R_e, n_rev)
    else:
        w = harmonic_weights(a, params.R_e, n_rev)
    n = np.arange(1, w.size + 1, dtype=float)
    V = np.asarray(V, float)
    T = np.asarray(T, float)
    Vb, Tb = np.broadcast_arrays(V, T)
    omega = Vb[..., None] / params.R_e * n
    eta = rr.carcass_loss(omega, Tb[..., None])
    U = structure_energy(params, rr, Fz)
    base = 2.0 * U / (Fz * params.R_e) if Fz > 0 else 0.0
    # the belt's and tread band's bending energy is part of the structure's deflection work
    share = np.maximum(U - np.asarray(U_belt, float), 0.0) / U if U > 0 else 0.0
    return base * share * np.sum(n * w * eta, axis=-1)


# -- the public functions ------------------------------------------------------------------------
def _check_inputs(V, Fz, T_K) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    V, Fz, T = (np.asarray(v, dtype=float) for v in (V, Fz, T_K))
    for arr, name, unit in ((V, "V", "m/s"), (Fz, "Fz", "N"), (T, "T_K", "K")):
        bad = ~np.isfinite(arr)
        if bad.any():
            raise InputError(f"must be finite [{unit}]", field=name,
                             value=float(arr[bad][0]) if arr.ndim else float(arr))
    if (Fz < 0).any():
        raise InputError("the load must be >= 0 N", field="Fz", value=float(Fz.min()))
    if (T <= 0).any():
        raise InputError("the temperature must be > 0 K", field="T_K", value=float(T.min()))
    return np.broadcast_arrays(V, Fz, T)


def rolling_resistance(params: TireParams, compound: Compound,
                       V: float | Sequence[float] | np.ndarray,
                       Fz: float | Sequence[float] | np.ndarray,
                       T_K: float | Sequence[float] | np.ndarray,
                       rr: RollingResistanceParams | None = None) -> RollingResistance:
    """Rolling resistance of the brush tire (module doc: tread eq. 29 plus carcass term).

    Parameters
    ----------
    params : TireParams
        The tire (patch law, R_e, void ratio; its file's ``[rolling_resistance]`` table).
    compound : Compound
        The tread compound (master curve, a_T).
    V : float or array
        Rolling speed [m/s] (sign: direction of rolling; |V| below :data:`V_CREEP` is
        evaluated at V_CREEP, the creep limit).
    Fz : float or array
        Load [N], >= 0.
    T_K : float or array
        Tread temperature [K], > 0 (also stands for the carcass temperature).
    rr : RollingResistanceParams, optional
        Overrides the tire file's table.

    Returns
    -------
    RollingResistance
        Arrays of the broadcast shape of V, Fz, T_K.
    """
    Vb, Fzb, Tb = _check_inputs(V, Fz, T_K)
    if rr is None:
        rr = load_rolling_params(params)
    shape = Vb.shape
    Vf, Ff, Tf = (a.ravel() for a in (Vb, Fzb, Tb))
    Vabs = np.maximum(np.abs(Vf), V_CREEP)
    f_t = np.zeros(Vf.size)
    f_c = np.zeros(Vf.size)
    f_b = np.zeros(Vf.size)
    f_band = np.zeros(Vf.size)
    log10_aT = np.asarray(compound.log10_aT(Tf), float)
    for load in np.unique(Ff[Ff > 0]):
        sel = Ff == load
        f_t[sel] = tread_coefficient(params, compound, rr, float(load),
                                     Vabs[sel] * 10.0 ** log10_aT[sel])
        bb = belt_coefficient(params, rr, float(load), Vabs[sel], Tf[sel], compound)
        f_b[sel] = bb.f_belt
        f_band[sel] = bb.f_band
        f_t[sel] += bb.f_band
        f_c[sel] = bb.f_belt + carcass_coefficient(params, rr, float(load), Vabs[sel],
                                                   Tf[sel], U_belt=bb.U)
    f_r = f_t + f_c
    F_r = f_r * Ff
    My = -np.sign(Vf) * F_r * params.R_e
    heat = F_r * np.abs(Vf)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(f_r > 0, f_t / np.where(f_r > 0, f_r, 1.0), 0.0)
    return RollingResistance(*(v.reshape(shape) for v in (f_r, f_t, f_c, F_r, My + 0.0, heat,
                                                          share, f_b, f_band)))


def core_table(params: TireParams, compound: Compound, log10_V: np.ndarray, T_K: np.ndarray,
               log10_Fz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tables of (f_r, tread_share) on the nodes (log10 V, T, log10 Fz) for the C tire core.

    Parameters
    ----------
    params : TireParams
    compound : Compound
    log10_V : array, shape (nV,)
        log10 of the rolling speed |V| [m/s] (default nodes :data:`CORE_LOG10_V`).
    T_K : array, shape (nT,)
        Tread temperature [K] (:data:`CORE_T_K`).
    log10_Fz : array, shape (nFz,)
        log10 of the load [N] (:data:`CORE_LOG10_FZ`).

    Returns
    -------
    f_r : numpy.ndarray, shape (nV, nT, nFz)
        Rolling-resistance coefficient [1]; ``f_r[i, j, k]`` is
        ``rolling_resistance(params, compound, 10**log10_V[i], 10**log10_Fz[k], T_K[j]).f_r``.
    tread_share : numpy.ndarray, shape (nV, nT, nFz)
        Share of the dissipated power that goes into the tread layer [1].
    """
    lv, tk, lf = (np.atleast_1d(np.asarray(a, float)) for a in (log10_V, T_K, log10_Fz))
    for arr, name in ((lv, "log10_V"), (tk, "T_K"), (lf, "log10_Fz")):
        if arr.ndim != 1 or arr.size == 0 or not np.isfinite(arr).all():
            raise InputError("must be a non-empty 1-D array of finite numbers", field=name)
    V, T, Fz = np.meshgrid(10.0**lv, tk, 10.0**lf, indexing="ij")
    res = rolling_resistance(params, compound, V, Fz, T)
    return res.f_r, res.tread_share


# -- ISO 28580 and the EU label ------------------------------------------------------------------
def eu_label_class(rrc_N_per_kN: float) -> str:
    """EU label fuel-efficiency class of a passenger (C1) tire from its RRC [N/kN].

    A <= 6.5, B 6.6-7.7, C 7.8-9.0, D 9.1-10.5, E >= 10.6 (Regulation (EU) 2020/740, Annex I);
    the RRC is taken to one decimal (half up) first.
    """
    try:
        x = float(rrc_N_per_kN)
    except (TypeError, ValueError):
        raise InputError("not a number", field="rrc_N_per_kN", value=rrc_N_per_kN) from None
    if not (math.isfinite(x) and x >= 0):
        raise InputError("must be a finite number >= 0 [N/kN]", field="rrc_N_per_kN",
                         value=rrc_N_per_kN)
    r = math.floor(x * 10.0 + 0.5 + 1e-9) / 10.0
    for cls, upper in EU_CLASS_BOUNDS:
        if r <= upper + 1e-9:
            return cls
    return "E"


def steady_temperature(params: TireParams, compound: Compound, V: float, Fz: float,
                       T_ambient_K: float | Sequence[float] | np.ndarray,
                       rr: RollingResistanceParams | None = None,
                       conductance: float | None = None) -> float | np.ndarray:
    r"""Tread temperature [K] of a tire rolling at thermal equilibrium with its surroundings.

    The tread layer generates ``tread_share`` of the rolling loss :math:`F_r|V|` (its footprint
    and bending hysteresis) and loses heat to the air and the road through the conductance G
    of the tire file's lumped tread temperature (``[thermal] conductance``, the transient
    model's :math:`C\,dT/dt = Q - G(T - T_{\rm amb})`), so that at equilibrium

    .. math:: G\,(T - T_{\rm amb}) = s(T)\,f_r(T)\,F_z\,|V| .

    The root is bracketed on a 4 K lattice of tread temperatures (one vectorised evaluation per
    100 K) and refined to 1e-6 K by the Illinois method, all ambient temperatures in one
    vectorised evaluation per iteration (:func:`_bracketed_roots`): the root, not the lattice
    or the iteration count, is the result; with several roots the lowest (the one reached by
    warming up from the ambient). ISO 28580 measures at this equilibrium (the tire runs until
    its rolling resistance is steady, at 25 C ambient) and corrects for the ambient
    temperature. One temperature, the tread's, stands for the whole tire (as in
    :func:`rolling_resistance`).

    Parameters
    ----------
    params, compound
        The tire and its tread compound.
    V : float
        Rolling speed [m/s].
    Fz : float
        Load [N], > 0.
    T_ambient_K : float or array
        Ambient (and road or drum) temperature(s) [K].
    rr : RollingResistanceParams, optional
    conductance : float, optional
        G [W/K]; default the tire file's ``[thermal] conductance``.

    Returns
    -------
    float or numpy.ndarray
        The tread temperature [K] for each ambient temperature.
    """
    if rr is None:
        rr = load_rolling_params(params)
    G = params.thermal.conductance if conductance is None else conductance
    G = _positive(G, "thermal.conductance")
    _positive(Fz, "Fz")
    T_amb = np.asarray(T_ambient_K, float)
    for t in T_amb.ravel():
        _positive(float(t), "T_ambient_K")

    def heat(T):
        res = rolling_resistance(params, compound, V, Fz, T, rr=rr)
        return res.tread_share * res.heat_rate

    step, block = 4.0, 25  # lattice spacing [K], nodes per evaluation
    lattice = np.empty(0)
    q = np.empty(0)
    t0s = T_amb.ravel()
    lo = np.empty(t0s.size)
    hi = np.empty(t0s.size)
    for i, t0 in enumerate(t0s):
        while True:
            g = G * (lattice - t0) - q
            up = np.nonzero((lattice > t0) & (g >= 0.0))[0]
            if up.size:
                break
            if lattice.size and lattice[-1] > float(T_amb.max()) + 1000.0:
                raise InputError("no thermal equilibrium within 1000 K of the ambient",
                                 field="thermal.conductance", value=G)
            start = float(T_amb.min()) if not lattice.size else lattice[-1] + step
            new = start + step * np.arange(block)
            lattice = np.concatenate([lattice, new])
            q = np.concatenate([q, heat(new)])
        hi[i] = float(lattice[up[0]])
        lo[i] = max(hi[i] - step, float(t0))
    out = _bracketed_roots(lambda T: G * (T - t0s) - heat(T), lo, hi, xtol=1e-6)
    return float(out[0]) if T_amb.ndim == 0 else out.reshape(T_amb.shape)


def _bracketed_roots(fun: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray,
                     xtol: float) -> np.ndarray:
    """Roots of the vectorised ``fun`` (one function per component, evaluated together) in
    the brackets ``[lo, hi]`` with ``fun(lo) < 0 <= fun(hi)``, each to ``xtol``: the Illinois
    variant of regula falsi (Dowell & Jarratt, BIT 11 (1971) 168), which keeps the bracket
    and converges superlinearly; one vectorised evaluation per iteration for all roots (the
    rolling-resistance model costs nearly the same for one temperature as for many). The
    result is the root to ``xtol``, not an iterate: the iteration stops on the bracket's
    width."""
    a, b = np.array(lo, float), np.array(hi, float)
    fa, fb = fun(a), fun(b)
    fa = np.array(fa, float)
    fb = np.array(fb, float)
    side = np.zeros(a.size, int)            # which end the last iterate replaced
    x = b.copy()
    for _ in range(200):
        active = (b - a) > xtol
        if not active.any():
            return x
        denom = fb - fa
        xs = np.where(denom != 0.0, b - fb * (b - a) / np.where(denom != 0.0, denom, 1.0),
                      0.5 * (a + b))
        # the secant point strictly inside the bracket, else the midpoint
        xs = np.where((xs > a) & (xs < b), xs, 0.5 * (a + b))
        x = np.where(active, xs, x)
        fx = np.asarray(fun(x), float)
        upper = active & (fx >= 0.0)
        lower = active & (fx < 0.0)
        # Illinois: an end kept twice in a row has its value halved
        fa = np.where(upper & (side == 1), 0.5 * fa, fa)
        fb = np.where(lower & (side == -1), 0.5 * fb, fb)
        b = np.where(upper, x, b)
        fb = np.where(upper, fx, fb)
        a = np.where(lower, x, a)
        fa = np.where(lower, fx, fa)
        side = np.where(upper, 1, np.where(lower, -1, side))
        done_exact = active & (fx == 0.0)
        a = np.where(done_exact, x, a)
        b = np.where(done_exact, x, b)
    raise ConvergenceError("the thermal equilibrium's root did not converge in 200 iterations")


@dataclass(frozen=True)
class IsoResult:
    """ISO 28580 numbers of a tire (see :func:`iso28580`)."""

    rrc_N_per_kN: float
    label_class: str
    load_N: float
    inflation_Pa: float
    speed_m_s: float
    T_K: float
    """Ambient temperature of the test [K]."""
    tread_share: float
    per_K: float
    """Relative change of the RRC per K of the ambient temperature over ``T_K -+ 5 K`` [1/K]
    (what ISO 28580's correction, about -0.008, stands for)."""
    T_tire_K: float = 0.0
    """Tread temperature the RRC is evaluated at [K] (:func:`steady_temperature`; T_K
    without the warm-up)."""
    per_K_isothermal: float = 0.0
    """Relative change per K of the whole tire's temperature at T_K, held isothermal [1/K]."""

    def as_dict(self) -> dict:
        """JSON-able form."""
        return dict(self.__dict__)


def iso28580(params: TireParams, compound: Compound, load_index_load: float | None = None,
             rr: RollingResistanceParams | None = None, T_K: float = ISO_T_K,
             warm_up: bool = True) -> IsoResult:
    """Rolling-resistance coefficient at the ISO 28580 conditions and its EU label class.

    80 km/h, 25 C ambient, 80 % of the load-index load, at the ISO inflation pressure of the
    tire file (210 kPa for a standard-load passenger tire); the patch law is evaluated at that
    pressure. ISO 28580 measures once the tire has reached thermal equilibrium: with
    ``warm_up`` (default) the tread temperature is :func:`steady_temperature` at the ambient
    T_K and the change per K is that of the ambient temperature (the tire's equilibrium
    temperature follows it), as the standard's correction; without it the tire is at T_K.
    Not modelled: the drum curvature (ISO 28580 corrects to a 2 m drum; a flat road gives
    less).

    Parameters
    ----------
    params, compound
        The tire and its tread compound.
    load_index_load : float, optional
        Maximum load of the load index [N]; default: the tire file's ``load_index_load``.
    rr : RollingResistanceParams, optional
    T_K : float
        Ambient temperature of the test [K] (default 298.15).
    warm_up : bool
        Evaluate at the equilibrium tread temperature (needs the tire file's
        ``[thermal] conductance`` > 0).

    Returns
    -------
    IsoResult
        RRC [N/kN], class, conditions, tread share, the tread temperature, the change per K of
        the ambient over T_K -+ 5 K and the isothermal one at T_K.
    """
    if rr is None:
        rr = load_rolling_params(params)
    LI = rr.load_index_load if load_index_load is None else load_index_load
    LI = _positive(LI, "load_index_load")
    T0 = _positive(T_K, "T_K")
    tire = params
    if rr.iso_inflation > 0:
        tire = replace(params, patch=replace(params.patch, p_inflation=rr.iso_inflation))
    Fz = ISO_LOAD_SHARE * LI
    ambient = np.array([T0, T0 - 5.0, T0 + 5.0])
    res = rolling_resistance(tire, compound, ISO_SPEED, Fz, ambient, rr=rr)
    f0, f_lo, f_hi = (float(v) for v in res.f_r)
    per_K_iso = (f_hi - f_lo) / (10.0 * f0)
    if warm_up:
        T_tire = steady_temperature(tire, compound, ISO_SPEED, Fz, ambient, rr=rr)
        res = rolling_resistance(tire, compound, ISO_SPEED, Fz, T_tire, rr=rr)
        f0, f_lo, f_hi = (float(v) for v in res.f_r)
    else:
        T_tire = ambient
    rrc = 1000.0 * f0
    return IsoResult(rrc_N_per_kN=rrc, label_class=eu_label_class(rrc), load_N=Fz,
                     inflation_Pa=tire.patch.p_inflation, speed_m_s=ISO_SPEED, T_K=T0,
                     tread_share=float(res.tread_share[0]), per_K=(f_hi - f_lo) / (10.0 * f0),
                     T_tire_K=float(T_tire[0]), per_K_isothermal=per_K_iso)


# -- the table the tire core reads ------------------------------------------------------------
@dataclass(frozen=True)
class RollingTable:
    """Rolling resistance tabulated for the tire core (``tf_tire_set_rolling``).

    The core interpolates trilinearly in (log10 |V_r|, T_tread, log10 Fz), clamped to the
    nodes, except below the first speed node, where it takes ``f_r`` proportional to |V_r|
    (a viscoelastic solid's loss modulus is linear in the frequency at low frequency), so that
    ``My`` is continuous through standstill; :func:`rolling_resistance` itself holds the value
    below :data:`V_CREEP`.

    Attributes
    ----------
    log10_v, T, log10_Fz : numpy.ndarray
        Node axes: log10 of |V_r| [m/s], tread temperature [K], log10 of the load [N].
    f_r, tread_share : numpy.ndarray
        Shape ``(nV, nT, nFz)`` (:func:`core_table`).
    compound : str
        Name of the compound the tread term was computed with.
    """

    log10_v: np.ndarray
    T: np.ndarray
    log10_Fz: np.ndarray
    f_r: np.ndarray
    tread_share: np.ndarray
    compound: str = ""

    @property
    def log10_p(self) -> np.ndarray:
        """The third axis under the name of the friction table's (file format)."""
        return self.log10_Fz

    @property
    def values(self) -> np.ndarray:
        """Node values ``(f_r, tread_share, 0)``, shape ``(nV, nT, nFz, 3)`` (file format)."""
        return np.stack([self.f_r, self.tread_share, np.zeros_like(self.f_r)], axis=-1)


def _numbers(d: object, path: str = "") -> dict[str, object]:
    """The numbers and model names of a nested describe() dict by path (text fields, which
    change with documentation edits, left out)."""
    if isinstance(d, dict):
        out: dict[str, object] = {}
        for k, v in d.items():
            if k not in ("source", "provenance", "description"):
                out |= _numbers(v, f"{path}.{k}")
        return out
    if isinstance(d, list | tuple):
        out = {}
        for i, v in enumerate(d):
            out |= _numbers(v, f"{path}[{i}]")
        return out
    return {path: d}


def _same_compound(a: dict, b: dict) -> bool:
    """Two :meth:`~lookup.compound.Compound.describe` dicts hold the same model: the same
    keys, names and numbers to 1e-12 relative (text fields ignored)."""
    na, nb = _numbers(a), _numbers(b)
    if na.keys() != nb.keys():
        return False
    for k, x in na.items():
        y = nb[k]
        if isinstance(x, int | float) and isinstance(y, int | float) and \
                not isinstance(x, bool) and not isinstance(y, bool):
            if not math.isclose(x, y, rel_tol=1e-12, abs_tol=0.0):
                return False
        elif x != y:
            return False
    return True


def grid_compound(grid) -> tuple[Compound | None, str]:
    """The compound a friction grid was built from, loaded by the name in its provenance
    and checked against the parameters recorded there (:func:`rolling_table`), or ``None``
    and the reason."""
    from lookup.compound import load_compound

    meta = getattr(grid, "meta", {}) or {}
    name = meta.get("compound_name")
    if not name or not isinstance(meta.get("compound"), dict):
        return None, "the grid records no compound (the tread term needs its master curve)"
    try:
        compound = load_compound(name)
    except InputError as exc:
        return None, f"the grid's compound {name!r} cannot be loaded ({exc})"
    if not _same_compound(compound.describe(), meta["compound"]):
        return None, (f"the shipped compound {name!r} differs from the one the grid was built "
                      f"with")
    return compound, ""


def rolling_table(params: TireParams, grid) -> tuple[RollingTable | None, str]:
    """The rolling-resistance table of a tire on a friction grid (for an FMU), or ``None``
    and the reason.

    The tread term needs the compound the grid was built from: it is loaded by the name in the
    grid's provenance and must agree with the parameters recorded there (a grid of another
    compound of the same name is refused). The tire needs its file's ``[rolling_resistance]``
    table.
    """
    compound, why = grid_compound(grid)
    if compound is None:
        return None, why
    name = grid.meta["compound_name"]
    try:
        load_rolling_params(params)
    except InputError as exc:
        return None, f"the tire has no rolling-resistance parameters ({exc.message})"
    f_r, share = core_table(params, compound, CORE_LOG10_V, CORE_T_K, CORE_LOG10_FZ)
    return RollingTable(CORE_LOG10_V.copy(), CORE_T_K.copy(), CORE_LOG10_FZ.copy(), f_r, share,
                        compound=name), ""
