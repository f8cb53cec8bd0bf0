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
                                   # width_decades, arms_per_decade (Prony.lognormal)
    # or "single_relaxation" (E0, E1 >= E0, tau: review eq. 4; E1 = E0 is the elastic limit)
    # or "tabulated" (file = a text table of frequency, E' and E'' (or tan delta), see
    #                 "Tables" below; outside = "maxwell" | "error", see lookup.modulus)

    [shift]                        # a_T(T); a_T = 1 at the master curve's T_ref (checked)
    model = "wlf"                  # C1, C2 [K], T_ref; or "tabulated" (file: T and aT or
                                   # log10_aT; T_ref optional, = where the table has aT = 1)

    [softening]                    # review eq. (6), applied at the stated strain
    model = "kraus"                # eps_c, m, r_inf, h; or "tabulated" (file: strain,
                                   # eta_R, eta_I); or "strain_sweep" (file: measured
                                   # sweeps, per temperature); or "none"
    strain = 0.1                   # [1], or "10 %"

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

Tables (``file =``, relative to the TOML file's folder; read by
:class:`tirefric.config.CsvTable`, docs/engine-inputs.md): a header naming the columns,
commented (``# f [Hz]  E' [MPa]  E'' [MPa]``) or not, then rows of numbers separated by
commas, tabs, semicolons or white space. Units in brackets or parentheses; names as below or
an alias of :data:`tirefric.config.COLUMN_ALIASES`:

* master curve: ``omega`` (or ``f``, ``freq``, ``frequency``) in Hz (cyclic, omega = 2 pi f)
  or rad/s (``1/s`` is refused as ambiguous); ``E_storage`` (``E'``) and ``E_loss``
  (``E''``) in Pa, kPa, MPa or GPa, or, instead of ``E_loss``, ``tan_delta`` (``tan delta``,
  E'' = tan delta E');
* shift table: ``T`` in degC, C or K and either ``aT`` or ``log10_aT``;
* tabulated softening: ``strain`` (``%`` or ``1``; no unit = 1), ``eta_R``, ``eta_I``;
* strain sweeps: ``strain`` in ``%`` or ``1`` (no unit is refused: ambiguous), optional
  ``T`` (one sweep per temperature value), optional ``f`` (one frequency per sweep), and
  either ``E_storage`` with ``E_loss`` or ``tan_delta`` (any pressure unit: the factors are
  ratios to the sweep's smallest strain) or ``eta_R`` with ``eta_I`` (the ratios as
  measured).

Checks across tables: the master curve's ``[modulus] T_ref`` must be where its shift factor
is 1, i.e. the WLF's ``T_ref`` or the temperature where the a_T table crosses 1 (linear
interpolation), to 0.5 K (:data:`lookup.shift.T_REF_TOLERANCE`); a mismatch is an
:class:`InputError` naming both temperatures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tirefric.config import CsvTable, Table, describe_column
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file

from .adhesion import GaussianShearLaw, NoAdhesion, ShearLaw
from .modulus import Modulus, ModulusTable, Prony, SingleRelaxation, TabulatedMasterCurve
from .shift import T_REF_TOLERANCE, WLF, Arrhenius, ShiftFactor, TabulatedShift
from .softening import (
    KrausSoftening,
    NoSoftening,
    Softening,
    StrainSweepSoftening,
    TabulatedSoftening,
    factors_at,
    varies_with_T,
)


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

    @property
    def softening_varies_with_T(self) -> bool:
        """Whether the softening factors depend on the temperature (strain sweeps measured
        at several temperatures, :class:`lookup.softening.StrainSweepSoftening`)."""
        return varies_with_T(self.softening)

    def softening_factors(self, T: float | None = None) -> tuple[float, float]:
        """(eta_R, eta_I) at the stated strain (and at temperature ``T`` [K], which a
        temperature-dependent law needs)."""
        if self.softening_varies_with_T:
            if T is None:
                raise InputError("the softening depends on the temperature (strain sweeps at "
                                 "several temperatures): give T", source=self.source or None,
                                 field="softening")
            R, I_ = factors_at(self.softening, self.strain, T)
            return float(R), float(I_)
        return self.softening.factors(self.strain)

    def softening_at(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(eta_R, eta_I) at the stated strain and temperatures ``T`` [K] (any shape)."""
        return factors_at(self.softening, self.strain, T)

    def modulus_table(self, points_per_decade: int = 40, T: float | None = None, *,
                      softened: bool = True) -> ModulusTable:
        """Strain-softened master curve at T_ref tabulated for the friction integrals.

        Parameters
        ----------
        points_per_decade
            Samples per decade of omega.
        T
            Temperature [K] of the softening factors, needed (only) when they depend on it.
        softened
            False: the small-strain curve (factors 1), for a caller that applies the
            factors at each temperature itself (the friction engine, :meth:`softening_at`).
        """
        eta_R, eta_I = self.softening_factors(T) if softened else (1.0, 1.0)
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
    outside = t.string("outside", default="maxwell", choices=("maxwell", "error"))
    tab = CsvTable.read(path)
    omega, E_storage, E_loss, how = _moduli_columns(tab, with_frequency=True)
    return TabulatedMasterCurve(omega, E_storage, E_loss, outside, source=str(path),
                                omega_unit=tab.unit("omega"), columns=how)


def _expected_moduli(with_frequency: bool) -> str:
    """The moduli columns a master curve or strain sweep expects (for error messages)."""
    freq = describe_column("omega", "angular_frequency") + "; " if with_frequency else ""
    return (freq + describe_column("E_storage", "pressure") + "; "
            + describe_column("E_loss", "pressure") + ", or instead "
            + describe_column("tan_delta", "dimensionless") + " (E'' = tan delta E')")


def _moduli_columns(tab: CsvTable, with_frequency: bool, expected: str | None = None
                    ) -> tuple[np.ndarray | None, np.ndarray, np.ndarray, str]:
    """(omega or None, E', E'', how) from a table with E' and E'' or tan delta."""
    expected = expected or _expected_moduli(with_frequency)
    omega = tab.column("omega", "angular_frequency", expected) if with_frequency else None
    E_storage = tab.column("E_storage", "pressure", expected)
    has_loss, has_tan = tab.has("E_loss"), tab.has("tan_delta")
    if has_loss and has_tan:
        raise InputError("both a loss modulus and a tan delta column: keep one (E'' = tan "
                         "delta E')", source=tab.path, field="tan_delta")
    if has_tan:
        tan = tab.column("tan_delta", "dimensionless", expected)
        return omega, E_storage, tan * E_storage, (
            f"E' from '{tab.cells[tab.find('E_storage')]}', E'' = tan delta E' with tan delta "
            f"from '{tab.cells[tab.find('tan_delta')]}'")
    E_loss = tab.column("E_loss", "pressure", expected)
    return omega, E_storage, E_loss, (f"E' from '{tab.cells[tab.find('E_storage')]}', E'' "
                                      f"from '{tab.cells[tab.find('E_loss')]}'")


def _load_shift(t: Table) -> ShiftFactor:
    model = t.string("model", choices=("wlf", "tabulated"))
    if model == "wlf":
        return WLF(t.quantity("C1", "dimensionless", positive=True),
                   t.quantity("C2", "temperature_difference", positive=True),
                   t.quantity("T_ref", "temperature", positive=True))
    path = t.path("file")
    tab = CsvTable.read(path)
    expected = (describe_column("T", "temperature") + "; " + describe_column("aT", "dimensionless")
                + " or " + describe_column("log10_aT", "dimensionless"))
    has_plain, has_log = tab.has("aT"), tab.has("log10_aT")
    if has_plain == has_log:
        raise InputError("the a_T table needs exactly one of the columns 'log10_aT' "
                         "(decimal logarithm) and 'aT' (plain factor); expected columns: "
                         f"{expected}; found {tab.cells}", source=path,
                         field="log10_aT" if has_plain else "aT")
    T = tab.column("T", "temperature", expected)
    if has_plain:
        aT = tab.column("aT", "dimensionless", expected)
        if (aT <= 0).any():
            i = int(np.flatnonzero(aT <= 0)[0])
            raise InputError(f"entry {i}: a plain shift factor must be > 0 (a log10 value? "
                             "then name the column 'log10_aT')", source=path, field="aT",
                             value=float(aT[i]))
        log10_aT = np.log10(aT)
    else:
        log10_aT = tab.column("log10_aT", "dimensionless", expected)
    if T.size > 1 and not (np.diff(T) > 0).all():
        # tables are often written from hot to cold: sort a monotone one
        if (np.diff(T) < 0).all():
            T, log10_aT = T[::-1], log10_aT[::-1]
        else:
            raise InputError("temperature column must be strictly monotonic", source=path,
                             field="T")
    stated = t.quantity("T_ref", "temperature", positive=True) if t.has("T_ref") else None
    unit_T = TabulatedShift(T, log10_aT, math.nan, source=str(path)).unit_temperature(stated)
    if unit_T is None:
        raise InputError("the a_T table never reaches a_T = 1 (log10 a_T from "
                         f"{log10_aT.min():.3g} to {log10_aT.max():.3g}), so it names no "
                         "reference temperature; a master curve's shift table has a_T = 1 "
                         "at the master curve's T_ref", source=path, field="aT" if has_plain
                         else "log10_aT")
    if stated is not None:
        _check_same_reference(t, "T_ref", stated, unit_T, f"where the a_T table {path} has "
                              "a_T = 1 (linear interpolation)")
    return TabulatedShift(T, log10_aT, unit_T if stated is None else stated, source=str(path))


def _check_same_reference(t: Table, key: str, T_ref: float, T_one: float, what: str,
                          hint: str = "") -> None:
    """Refuse a T_ref that is not where the shift factor is 1 (:data:`T_REF_TOLERANCE`)."""
    if abs(T_ref - T_one) > T_REF_TOLERANCE:
        raise t.error(key, f"T_ref = {T_ref - 273.15:.6g} C ({T_ref:.6g} K) is not where the "
                      f"shift factor is 1: that is {T_one - 273.15:.6g} C ({T_one:.6g} K), "
                      f"{what}. A master curve is at the temperature where its shift factor "
                      f"is 1; set T_ref to it{hint} (tolerance {T_REF_TOLERANCE:g} K, "
                      "docs/engine-inputs.md)", t.raw(key))


def _load_softening(t: Table | None) -> tuple[Softening, float]:
    if t is None:
        return NoSoftening(), 0.0
    model = t.string("model", choices=("kraus", "tabulated", "strain_sweep", "none"))
    if model == "none":
        return NoSoftening(), 0.0
    strain = t.quantity("strain", "strain", positive=True)
    if model == "kraus":
        return KrausSoftening(t.quantity("eps_c", "dimensionless", positive=True),
                              t.quantity("m", "dimensionless", positive=True),
                              t.quantity("r_inf", "dimensionless", positive=True, maximum=1.0),
                              t.quantity("h", "dimensionless", positive=True)), strain
    path = t.path("file")
    tab = CsvTable.read(path)
    if model == "strain_sweep":
        return _strain_sweeps(tab), strain
    expected = "; ".join(describe_column(c, d) for c, d in (
        ("strain", "strain"), ("eta_R", "dimensionless"), ("eta_I", "dimensionless")))
    # a strain without unit has always been read as a fraction in this layout
    eps = tab.column("strain", "strain", expected, bare_unit="1")
    return TabulatedSoftening(eps, tab.column("eta_R", "dimensionless", expected),
                              tab.column("eta_I", "dimensionless", expected), str(path)), strain


def _strain_sweeps(tab: CsvTable) -> StrainSweepSoftening:
    """Strain sweeps (module docstring, "Tables"): ratios per temperature."""
    ratios = tab.has("eta_R") or tab.has("eta_I")
    moduli = tab.has("E_storage") or tab.has("E_loss") or tab.has("tan_delta")
    sweep_cols = (describe_column("strain", "strain") + "; optional "
                  + describe_column("T", "temperature") + "; optional "
                  + describe_column("omega", "angular_frequency") + "; ")
    expected = sweep_cols + (_expected_moduli(False) + "; or instead of the moduli "
                             + describe_column("eta_R", "dimensionless") + " and "
                             + describe_column("eta_I", "dimensionless"))
    if ratios and moduli:
        raise InputError("both moduli and ratio columns: give E' and E'' (or tan delta), or "
                         f"eta_R and eta_I; expected columns: {expected}", source=tab.path,
                         field="eta_R")
    eps = tab.column("strain", "strain", expected)
    if ratios:
        R = tab.column("eta_R", "dimensionless", expected)
        I_ = tab.column("eta_I", "dimensionless", expected)
        how = "eta_R, eta_I as in the file"
    else:
        _, Ep, Epp, how = _moduli_columns(tab, False, expected)
        R, I_ = Ep, Epp
        how += "; ratios to the sweep's smallest strain"
    T = tab.column("T", "temperature", expected) if tab.has("T") else None
    f = tab.column("omega", "angular_frequency", expected) if tab.has("omega") else None
    keys = np.zeros(eps.size) if T is None else T
    temps = np.unique(keys)
    strains, etas_R, etas_I = [], [], []
    for Tk in temps:
        sel = np.flatnonzero(keys == Tk)
        at = "" if T is None else f" (sweep at {Tk - 273.15:g} C)"
        if f is not None and np.unique(f[sel]).size > 1:
            raise InputError(f"one sweep per temperature needs one frequency{at}; found "
                             f"{np.unique(f[sel]) / (2 * np.pi)} Hz: keep one frequency per "
                             "temperature", source=tab.path, field="omega")
        order = sel[np.argsort(eps[sel], kind="stable")]
        e = eps[order]
        if e.size < 2 or not (np.diff(e) > 0).all():
            raise InputError(f"a strain sweep needs >= 2 distinct strains{at} (rows with "
                             "one temperature value form one sweep)", source=tab.path,
                             field="strain")
        r, i = R[order], I_[order]
        if not ratios:  # measured moduli: ratios to the smallest strain (review eq. 6)
            if r[0] <= 0 or i[0] <= 0:
                raise InputError(f"moduli must be > 0{at}", source=tab.path,
                                 field="E_storage" if r[0] <= 0 else "E_loss")
            r, i = r / r[0], i / i[0]
        strains.append(e)
        etas_R.append(r)
        etas_I.append(i)
    return StrainSweepSoftening(np.array([]) if T is None else temps, tuple(strains),
                                tuple(etas_R), tuple(etas_I), str(tab.path), how)


def _check_master_curve_reference(mt: Table, st: Table, T_ref: float,
                                  shift: ShiftFactor) -> None:
    """The master curve's T_ref must be where its shift factor is 1 (module docstring).

    For a WLF law that is its own T_ref; constants fitted at another reference (e.g. the
    universal ones at T_g) describe the same law at T_ref with C1' = C1 C2/(C2 + dT),
    C2' = C2 + dT, dT = T_ref - T_r (Ferry, *Viscoelastic Properties of Polymers*, 3rd ed.,
    ch. 11), which the message gives."""
    if isinstance(shift, WLF):
        dT = T_ref - shift.T_ref
        hint = (f", or write the WLF law at the master curve's T_ref: C1 = "
                f"{shift.C1 * shift.C2 / (shift.C2 + dT):.6g}, C2 = {shift.C2 + dT:.6g} K, "
                f"T_ref = {T_ref - 273.15:.6g} C (the same law, Ferry ch. 11)"
                if shift.C2 + dT > 0 else "")
        _check_same_reference(mt, "T_ref", T_ref, shift.T_ref,
                              f"the WLF law's T_ref ([shift] T_ref in {st.source})", hint)
    elif isinstance(shift, TabulatedShift):
        one = shift.unit_temperature(T_ref)
        _check_same_reference(mt, "T_ref", T_ref, one if one is not None else shift.T_ref,
                              f"where the a_T table {shift.source} ([shift] file) has "
                              "a_T = 1 (linear interpolation)")


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
    _check_master_curve_reference(mt, st, T_ref, shift)
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
