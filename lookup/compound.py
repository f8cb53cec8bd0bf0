"""Rubber compounds: master curve, shift factor, strain softening, adhesive shear law and
thermal data, loaded from TOML files under ``models/compounds/``.

File layout (SI unless written as ``"<number> <unit>"``)::

    name = "summer"
    description = "..."
    provenance = "where the numbers come from"
    nu = 0.5                       # Poisson ratio

    [modulus]                      # small-strain master curve at T_ref
    T_ref = "20 degC"
    model = "prony"                # E_inf [Pa], E_k [Pa], tau_k [s]; or, with
                                   # spectrum = "lognormal": E_inf, E_glassy, tau_center,
                                   # width_decades, arms_per_decade (Prony.lognormal), or
                                   # E_inf, arms_per_decade and one [[modulus.component]]
                                   # table per log-normal component (LogNormalSpectrum):
    [[modulus.component]]          #   name = "alpha" (optional label),
    strength = "1.9 GPa"           #   Delta E_i [Pa], E' rises by the sum of the strengths,
    tau_center = 4e-10             #   centre of the component [s] at T_ref,
    width_decades = 1.6            #   standard deviation of log10(tau) [decades]
    # or "single_relaxation" (E0, E1 >= E0, tau: review eq. 4; E1 = E0 is the elastic limit)
    # or "tabulated" (file = CSV with "omega [rad/s]" or "omega [Hz]" (cyclic frequency,
    #                 converted with 2 pi; "1/s" is refused as ambiguous), "E_storage [Pa]",
    #                 "E_loss [Pa]"; outside = "maxwell" | "error", see lookup.modulus)

    [shift]                        # a_T(T), its own reference temperature
    model = "wlf"                  # C1, C2 [K], T_ref; or "tabulated" (file: "T [degC]" and
                                   # "log10_aT [1]" or the plain factor "aT [1]")

    [softening]                    # review eq. (6), applied at the stated strain
    model = "kraus"                # eps_c, m, r_inf, h; or "tabulated" (file); or "none"
    strain = 0.1

    [adhesion]                     # review eq. (21)-(22)
    model = "eq21"                 # sigma_f0 [Pa], c, v_star [m/s], T_ref,
    shift = "arrhenius"            # activation_energy [J or "1 eV"]; or shift = "bulk"
    # or model = "schallamach" (review Appendix A): sigma_star [Pa], v_star [m/s], delta_E
    #    [J or "0.075 eV"], nu1_over_nu0, T_ref, tau0_shift = "bulk"|"arrhenius"|"none",
    #    mean_force = "A5" (eq. A21, default) | "A4"; or "none"

    [thermal]                      # optional: only the hot branch needs it
    rho = 1500.0                   # kg/m^3
    c_v = 1500.0                   # J/(kg K)
    kappa = 0.3                    # W/(m K)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tirefric.config import Table, csv_column_names, read_csv_table
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file

from .adhesion import GaussianShearLaw, NoAdhesion, ShearLaw
from .modulus import (
    LogNormalSpectrum,
    Modulus,
    ModulusTable,
    Prony,
    SingleRelaxation,
    TabulatedMasterCurve,
)
from .shift import WLF, Arrhenius, ShiftFactor, TabulatedShift
from .softening import KrausSoftening, NoSoftening, Softening, TabulatedSoftening


@dataclass(frozen=True)
class RubberThermal:
    """Thermal data of the rubber.

    Attributes
    ----------
    rho : float
        Density [kg/m^3].
    c_v : float
        Specific heat [J/(kg K)].
    kappa : float
        Thermal conductivity [W/(m K)].
    """

    rho: float
    c_v: float
    kappa: float

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity D = kappa / (rho c_v) [m^2/s] (review after eq. 23)."""
        return self.kappa / (self.rho * self.c_v)

    @property
    def effusivity(self) -> float:
        """Thermal effusivity sqrt(kappa rho c_v) [W s^0.5/(m^2 K)]."""
        return float(np.sqrt(self.kappa * self.rho * self.c_v))


@dataclass(frozen=True)
class Compound:
    """A tread compound.

    Attributes
    ----------
    name : str
    modulus : Modulus
        Small-strain master curve at ``T_ref``.
    T_ref : float
        Temperature of the master curve [K].
    shift : ShiftFactor
        Bulk shift factor a_T(T) (its own reference temperature is allowed).
    softening : Softening
        Strain-softening law (review eq. 6).
    strain : float
        Strain at which the softening factors are applied [1].
    adhesion : ShearLaw
        Frictional shear stress sigma_f(v, T) (review eq. 21).
    nu : float
        Poisson ratio.
    thermal : RubberThermal or None
        None when the file has no ``[thermal]`` table (a cold-branch-only compound); the hot
        branch then refuses to run (:meth:`require_thermal`).
    """

    name: str
    modulus: Modulus
    T_ref: float
    shift: ShiftFactor
    softening: Softening
    strain: float
    adhesion: ShearLaw
    nu: float
    thermal: RubberThermal | None
    description: str = ""
    provenance: str = ""
    source: str = ""

    def require_thermal(self) -> RubberThermal:
        """The thermal data, or an :class:`InputError` naming the file and ``[thermal]``."""
        if self.thermal is None:
            raise InputError("the hot branch (flash temperature) needs the rubber's thermal "
                             "data: add a [thermal] table with rho, c_v, kappa, or compute "
                             "the cold branch only", source=self.source or None,
                             field="thermal")
        return self.thermal

    def softening_factors(self) -> tuple[float, float]:
        """(eta_R, eta_I) at the stated strain."""
        return self.softening.factors(self.strain)

    def modulus_table(self, points_per_decade: int = 40) -> ModulusTable:
        """Strain-softened master curve at T_ref tabulated for the friction integrals."""
        eta_R, eta_I = self.softening_factors()
        return ModulusTable.from_modulus(self.modulus, eta_R, eta_I,
                                         points_per_decade=points_per_decade)

    def log10_aT(self, T: np.ndarray) -> np.ndarray:
        """log10 of the shift from the master curve's T_ref to temperature T [K]."""
        return self.shift.log10_aT(T) - self.shift.log10_aT(np.asarray(self.T_ref))

    def describe(self) -> dict:
        """All parameters as a JSON-able dict (grid provenance)."""
        return {
            "name": self.name, "source": self.source, "description": self.description,
            "provenance": self.provenance, "T_ref_K": self.T_ref,
            "modulus": self.modulus.describe(), "shift": self.shift.describe(),
            "softening": self.softening.describe(), "strain": self.strain,
            "adhesion": self.adhesion.describe(), "nu": self.nu,
            "thermal": None if self.thermal is None else {
                "rho_kg_m3": self.thermal.rho, "c_v_J_kgK": self.thermal.c_v,
                "kappa_W_mK": self.thermal.kappa},
        }


def _load_modulus(t: Table) -> Modulus:
    model = t.string("model", choices=("prony", "single_relaxation", "tabulated"))
    if model == "single_relaxation":
        E0 = t.quantity("E0", "pressure", positive=True)
        E1 = t.quantity("E1", "pressure", positive=True)
        if E1 < E0:
            raise t.error("E1", f"glassy modulus must be >= E0 = {E0:g} Pa (E1 = E0 is the "
                          "elastic limit)", t.raw("E1"))
        return SingleRelaxation(E0, E1, t.quantity("tau", "time", positive=True))
    if model == "prony" and t.has("spectrum") and t.has("component"):
        return _load_lognormal_components(t)
    if model == "prony" and t.has("spectrum"):
        t.string("spectrum", choices=("lognormal",))
        E_inf = t.quantity("E_inf", "pressure", positive=True)
        E_g = t.quantity("E_glassy", "pressure", positive=True)
        if E_g <= E_inf:
            raise t.error("E_glassy", f"must exceed E_inf = {E_inf:g} Pa", t.raw("E_glassy"))
        return Prony.lognormal(E_inf, E_g, t.quantity("tau_center", "time", positive=True),
                               t.quantity("width_decades", "dimensionless", positive=True),
                               t.integer("arms_per_decade", 2, minimum=1))
    if model == "prony":
        E_k = t.array("E_k", "pressure")
        tau_k = t.array("tau_k", "time", positive=True)
        if (E_k < 0).any():
            raise t.error("E_k", "Maxwell-arm moduli must be >= 0 (negative modulus)",
                          t.raw("E_k"))
        if E_k.size != tau_k.size:
            raise t.error("tau_k", f"needs as many entries as E_k ({E_k.size})", t.raw("tau_k"))
        return Prony(t.quantity("E_inf", "pressure", positive=True), E_k, tau_k)
    path = t.path("file")
    units: dict[str, str] = {}
    cols = read_csv_table(path, {"omega": "angular_frequency", "E_storage": "pressure",
                                 "E_loss": "pressure"}, units)
    outside = t.string("outside", default="maxwell", choices=("maxwell", "error"))
    return TabulatedMasterCurve(cols["omega"], cols["E_storage"], cols["E_loss"], outside,
                                source=str(path), omega_unit=units["omega"])


def _load_lognormal_components(t: Table) -> LogNormalSpectrum:
    """``spectrum = "lognormal"`` with ``[[modulus.component]]`` tables (several components)."""
    t.string("spectrum", choices=("lognormal",))
    for key in ("E_glassy", "tau_center", "width_decades"):
        if t.has(key):
            raise t.error(key, "belongs to the single-component form; with [[modulus.component]] "
                          "tables give strength, tau_center and width_decades in each "
                          "component", t.raw(key))
    raw = t.raw("component")
    if not isinstance(raw, list) or not raw or not all(isinstance(c, dict) for c in raw):
        raise t.error("component", "expected one or more [[modulus.component]] tables", raw)
    strengths, centres, widths, names = [], [], [], []
    for i, c in enumerate(raw):
        ct = Table(c, t.source, f"{t.name('component')}[{i}]")
        names.append(ct.string("name", default=""))
        strengths.append(ct.quantity("strength", "pressure", positive=True))
        centres.append(ct.quantity("tau_center", "time", positive=True))
        widths.append(ct.quantity("width_decades", "dimensionless", positive=True))
        ct.check_unknown()
    return LogNormalSpectrum(t.quantity("E_inf", "pressure", positive=True),
                             np.array(strengths), np.array(centres), np.array(widths),
                             t.integer("arms_per_decade", 2, minimum=1),
                             tuple(names) if any(names) else ())


def _load_shift(t: Table) -> ShiftFactor:
    model = t.string("model", choices=("wlf", "tabulated"))
    if model == "wlf":
        return WLF(t.quantity("C1", "dimensionless", positive=True),
                   t.quantity("C2", "temperature_difference", positive=True),
                   t.quantity("T_ref", "temperature", positive=True))
    path = t.path("file")
    present = csv_column_names(path)
    if ("aT" in present) == ("log10_aT" in present):
        raise InputError("the a_T table needs exactly one of the columns 'log10_aT [1]' "
                         f"(decimal logarithm) and 'aT [1]' (plain factor); header: {present}",
                         source=path, field="log10_aT" if "aT" in present else "aT")
    if "aT" in present:
        cols = read_csv_table(path, {"T": "temperature", "aT": "dimensionless"})
        if (cols["aT"] <= 0).any():
            i = int(np.flatnonzero(cols["aT"] <= 0)[0])
            raise InputError(f"entry {i}: a plain shift factor must be > 0 (a log10 value? "
                             "then name the column 'log10_aT')", source=path, field="aT",
                             value=float(cols["aT"][i]))
        cols["log10_aT"] = np.log10(cols["aT"])
    else:
        cols = read_csv_table(path, {"T": "temperature", "log10_aT": "dimensionless"})
    if not (np.diff(cols["T"]) > 0).all():
        raise InputError("temperature column must be strictly increasing", source=path,
                         field="T")
    T_ref = t.quantity("T_ref", "temperature", positive=True)
    return TabulatedShift(cols["T"], cols["log10_aT"], T_ref, source=str(path))


def _load_softening(t: Table | None) -> tuple[Softening, float]:
    if t is None:
        return NoSoftening(), 0.0
    model = t.string("model", choices=("kraus", "tabulated", "none"))
    if model == "none":
        return NoSoftening(), 0.0
    strain = t.quantity("strain", "dimensionless", positive=True)
    if model == "kraus":
        return KrausSoftening(t.quantity("eps_c", "dimensionless", positive=True),
                              t.quantity("m", "dimensionless", positive=True),
                              t.quantity("r_inf", "dimensionless", positive=True, maximum=1.0),
                              t.quantity("h", "dimensionless", positive=True)), strain
    path = t.path("file")
    cols = read_csv_table(path, {"strain": "dimensionless", "eta_R": "dimensionless",
                                 "eta_I": "dimensionless"})
    return TabulatedSoftening(cols["strain"], cols["eta_R"], cols["eta_I"], str(path)), strain


def _load_adhesion(t: Table | None, bulk: ShiftFactor) -> ShearLaw:
    if t is None:
        return NoAdhesion()
    model = t.string("model", choices=("eq21", "schallamach", "none"))
    if model == "none":
        return NoAdhesion()
    if model == "schallamach":
        from .schallamach import SchallamachShearLaw

        T_ref = t.quantity("T_ref", "temperature", positive=True)
        kind = t.string("tau0_shift", choices=("bulk", "arrhenius", "none"))
        tau0: ShiftFactor | None = None
        if kind == "bulk":
            tau0 = bulk
        elif kind == "arrhenius":
            tau0 = Arrhenius(t.quantity("activation_energy", "energy", positive=True), T_ref)
        return SchallamachShearLaw.from_energies(
            t.quantity("sigma_star", "pressure", nonnegative=True),
            t.quantity("v_star", "velocity", positive=True),
            t.quantity("delta_E", "energy"),
            t.quantity("nu1_over_nu0", "dimensionless", 1.0, positive=True), T_ref, tau0,
            t.string("mean_force", "A5", choices=("A5", "A4")))
    T_ref = t.quantity("T_ref", "temperature", positive=True)
    shift_kind = t.string("shift", choices=("arrhenius", "bulk"))
    shift: ShiftFactor
    if shift_kind == "arrhenius":
        shift = Arrhenius(t.quantity("activation_energy", "energy", positive=True), T_ref)
    else:
        shift = bulk
    return GaussianShearLaw(t.quantity("sigma_f0", "pressure", nonnegative=True),
                            t.quantity("c", "dimensionless", positive=True),
                            t.quantity("v_star", "velocity", positive=True), T_ref, shift)


def load_compound(name_or_path: str | Path) -> Compound:
    """Load a compound TOML (a path or a shipped name such as ``"summer"``)."""
    path = resolve_model_file(name_or_path, "compounds")
    t = Table.load(path)
    name = t.string("name", default=path.stem)
    description = t.string("description", default="")
    provenance = t.string("provenance", default="")
    nu = t.quantity("nu", "dimensionless", 0.5, minimum=0.0, maximum=0.5)
    mt = t.table("modulus")
    T_ref = mt.quantity("T_ref", "temperature", positive=True)
    modulus = _load_modulus(mt)
    mt.check_unknown()
    st = t.table("shift")
    shift = _load_shift(st)
    st.check_unknown()
    sft = t.table("softening", required=False)
    softening, strain = _load_softening(sft)
    if sft is not None:
        sft.check_unknown()
    at = t.table("adhesion", required=False)
    adhesion = _load_adhesion(at, shift)
    if at is not None:
        at.check_unknown()
    th = t.table("thermal", required=False)
    thermal = None
    if th is not None:
        thermal = RubberThermal(th.quantity("rho", "density", positive=True),
                                th.quantity("c_v", "heat_capacity", positive=True),
                                th.quantity("kappa", "conductivity", positive=True))
        th.check_unknown()
    t.check_unknown()
    return Compound(name, modulus, T_ref, shift, softening, strain, adhesion, nu, thermal,
                    description, provenance, str(path))
