"""Road surfaces: a roughness power spectrum, its cut-off rule, the macroasperity size and the
road's thermal properties, loaded from TOML files under ``models/surfaces/``.

File layout (all quantities SI unless written as ``"<number> <unit>"``)::

    name = "concrete"
    description = "..."
    provenance = "where the numbers come from"

    [psd]                       # self-affine with roll-off ...
    model = "self_affine"
    q0 = 300.0                  # smallest wavenumber [1/m]
    q_r = 3000.0                # roll-off [1/m]
    H = 0.9                     # Hurst exponent
    h_rms = "0.25 mm"           # or C0 = ... [m^4]
    # ... or model = "tabulated" with file = "data/x.csv" (columns "q [1/m]", "C [m^4]"),
    # ... or model = "height_map" / "line_scan" with file = ... (lookup.topography: a height
    #     map or profile with its pixel size; a line scan is turned into the isotropic 2D C(q))
    #     and optional bins_per_decade = 10

    [cutoff]                    # rule for q1 (review sec. 5.1)
    rule = "rms_slope"          # or "fixed" with q1 = ...
    xi1 = 1.0

    [macroasperity]
    D = "1 mm"                  # macroasperity contact diameter (eq. 28, flash temperature)

    [thermal]                   # the road, for the heat partition at the surface
    kappa = 1.0                 # W/(m K)
    rho = 2400.0                # kg/m^3
    c = 900.0                   # J/(kg K)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .config import Table, read_csv_table
from .errors import InputError
from .paths import resolve_model_file
from .roughness import CutoffRule, PowerSpectrum, SelfAffinePSD, TabulatedPSD


@dataclass(frozen=True)
class RoadThermal:
    """Thermal properties of the road.

    Attributes
    ----------
    kappa : float
        Thermal conductivity [W/(m K)].
    rho : float
        Density [kg/m^3].
    c : float
        Specific heat [J/(kg K)].
    """

    kappa: float
    rho: float
    c: float

    @property
    def effusivity(self) -> float:
        """Thermal effusivity sqrt(kappa rho c) [W s^0.5/(m^2 K)]."""
        return float(np.sqrt(self.kappa * self.rho * self.c))


@dataclass(frozen=True)
class Surface:
    """A road surface.

    Attributes
    ----------
    name : str
        Short name.
    psd : PowerSpectrum
        2D isotropic roughness power spectrum C(q).
    cutoff : CutoffRule
        Rule that fixes q1.
    D : float
        Macroasperity contact diameter [m] (review sec. 5.3: 0.1-3 mm); s0 = 0.2 D (eq. 28).
    thermal : RoadThermal or None
        Road thermal properties; None means the road takes no heat (insulated interface).
    description, provenance : str
        Free text.
    """

    name: str
    psd: PowerSpectrum
    cutoff: CutoffRule
    D: float
    thermal: RoadThermal | None
    description: str = ""
    provenance: str = ""
    source: str = ""

    @property
    def q1(self) -> float:
        """The cut-off wavenumber q1 [1/m] given by the rule."""
        return self.cutoff.resolve(self.psd)

    @property
    def s0(self) -> float:
        """Slip distance of the cold-to-hot transition in eq. (28), s0 = 0.2 D [m]."""
        return 0.2 * self.D

    def describe(self) -> dict:
        """All parameters as a JSON-able dict (grid provenance)."""
        return {
            "name": self.name, "source": self.source, "description": self.description,
            "provenance": self.provenance, "psd": self.psd.describe(),
            "cutoff": self.cutoff.describe(), "D_m": self.D,
            "thermal": None if self.thermal is None else {
                "kappa_W_mK": self.thermal.kappa, "rho_kg_m3": self.thermal.rho,
                "c_J_kgK": self.thermal.c},
        }


def _load_psd(t: Table) -> PowerSpectrum:
    model = t.string("model", choices=("self_affine", "tabulated", "height_map", "line_scan"))
    if model == "self_affine":
        q0 = t.quantity("q0", "wavenumber", positive=True)
        q_r = t.quantity("q_r", "wavenumber", positive=True)
        H = t.quantity("H", "dimensionless", minimum=1e-6, maximum=0.999999)
        if q_r < q0:
            raise t.error("q_r", f"roll-off must be >= q0 = {q0:g} 1/m", t.raw("q_r"))
        if t.has("C0") == t.has("h_rms"):
            raise t.error("h_rms", "give exactly one of h_rms and C0")
        if t.has("C0"):
            psd: PowerSpectrum = SelfAffinePSD(q0, q_r, H, t.quantity("C0", "psd", positive=True))
        else:
            psd = SelfAffinePSD.from_h_rms(q0, q_r, H, t.quantity("h_rms", "length",
                                                                   positive=True))
        t.check_unknown()
        return psd
    path = t.path("file")
    if model == "tabulated":
        cols = read_csv_table(path, {"q": "wavenumber", "C": "psd"})
        t.check_unknown()
        return TabulatedPSD(cols["q"], cols["C"], source=str(path))
    # measured topography -> the review's 2D isotropic C(q) (lookup.topography)
    from .topography import psd_2d_from_1d, read_height_map, read_line_scan

    bins = t.integer("bins_per_decade", 10, minimum=2)
    if model == "height_map":
        q, C = read_height_map(path).psd(bins_per_decade=bins)
    else:
        q1d, C1 = read_line_scan(path).psd(bins_per_decade=bins)
        q, C = q1d, psd_2d_from_1d(q1d, C1)
    keep = np.isfinite(C) & (C > 0)
    if keep.sum() < 2:
        raise InputError("topography gives fewer than two usable spectrum points",
                         source=path, field="file")
    t.check_unknown()
    return TabulatedPSD(q[keep], C[keep], source=str(path))


def load_surface(name_or_path: str | Path) -> Surface:
    """Load a surface TOML (a path or a shipped name such as ``"asphalt"``)."""
    path = resolve_model_file(name_or_path, "surfaces")
    t = Table.load(path)
    name = t.string("name", default=path.stem)
    description = t.string("description", default="")
    provenance = t.string("provenance", default="")
    psd = _load_psd(t.table("psd"))
    c = t.table("cutoff", required=False)
    if c is None:
        cutoff = CutoffRule()
    else:
        rule = c.string("rule", default="rms_slope", choices=("rms_slope", "fixed"))
        if rule == "fixed":
            cutoff = CutoffRule("fixed", q1=c.quantity("q1", "wavenumber", positive=True))
        else:
            cutoff = CutoffRule("rms_slope", xi1=c.quantity("xi1", "dimensionless", 1.0,
                                                            positive=True))
        c.check_unknown()
    try:
        cutoff.resolve(psd)
    except InputError as exc:
        raise InputError(exc.message, source=path, field=exc.field, value=exc.value) from None
    m = t.table("macroasperity")
    D = m.quantity("D", "length", positive=True, maximum=0.05)
    m.check_unknown()
    th = t.table("thermal", required=False)
    thermal = None
    if th is not None:
        thermal = RoadThermal(th.quantity("kappa", "conductivity", positive=True),
                              th.quantity("rho", "density", positive=True),
                              th.quantity("c", "heat_capacity", positive=True))
        th.check_unknown()
    t.check_unknown()
    return Surface(name, psd, cutoff, D, thermal, description, provenance, str(path))
