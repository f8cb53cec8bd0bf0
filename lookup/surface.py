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
    # ... or model = "tabulated_1d" with file = ... (columns "q [1/m]", "C1D [m^3]": a
    #     line-scan spectrum, turned into the isotropic 2D C(q), lookup.topography),
    # ... or model = "height_map" / "line_scan" with file = ... (lookup.topography: a height
    #     map or profile with its pixel size; a line scan is turned into the isotropic 2D C(q))
    #     and optional bins_per_decade = 10.
    # Every model but self_affine takes an optional q0 = ... [1/m]: the spectrum is cut
    # below it (C = 0 for q < q0, the value at q0 interpolated log-log), so that the
    # largest wavelength in the calculation is a choice, not the scan length.

    [cutoff]                    # rule for q1 (review sec. 5.1)
    rule = "rms_slope"          # or "fixed" with q1 = ...
    xi1 = 1.0

    [macroasperity]             # optional: only the hot branch (and eq. 28) needs it
    D = "1 mm"                  # macroasperity contact diameter (eq. 28, flash temperature)

    [thermal]                   # optional: the road, for the heat partition at the surface
    kappa = 1.0                 # W/(m K)
    rho = 2400.0                # kg/m^3
    c = 900.0                   # J/(kg K)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tirefric.config import Table, read_csv_table
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file

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
    D : float or None
        Macroasperity contact diameter [m] (review sec. 5.3: 0.1-3 mm); s0 = 0.2 D (eq. 28).
        None when the file has no ``[macroasperity]`` table (a cold-branch-only surface):
        the hot branch then refuses to run (:meth:`require_D`).
    thermal : RoadThermal or None
        Road thermal properties; None means the road takes no heat (insulated interface).
    description, provenance : str
        Free text.
    """

    name: str
    psd: PowerSpectrum
    cutoff: CutoffRule
    D: float | None
    thermal: RoadThermal | None
    description: str = ""
    provenance: str = ""
    source: str = ""

    @property
    def q1(self) -> float:
        """The cut-off wavenumber q1 [1/m] given by the rule."""
        return self.cutoff.resolve(self.psd)

    def require_D(self) -> float:
        """D [m], or an :class:`InputError` naming the file and ``[macroasperity]``."""
        if self.D is None:
            raise InputError("the hot branch and the cold/hot blending of eq. (28) need the "
                             "macroasperity contact diameter: add [macroasperity] D = ..., or "
                             "compute the cold branch only", source=self.source or None,
                             field="macroasperity.D")
        return self.D

    @property
    def s0(self) -> float:
        """Slip distance of the cold-to-hot transition in eq. (28), s0 = 0.2 D [m]."""
        return 0.2 * self.require_D()

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
    model = t.string("model", choices=("self_affine", "tabulated", "tabulated_1d",
                                       "height_map", "line_scan"))
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
    q0 = t.quantity("q0", "wavenumber", positive=True) if t.has("q0") else None
    from .topography import psd_2d_from_1d, read_height_map, read_line_scan

    if model == "tabulated":
        cols = read_csv_table(path, {"q": "wavenumber", "C": "psd"})
        q, C = cols["q"], cols["C"]
    elif model == "tabulated_1d":
        # a line-scan spectrum C1D(q) [m^3] -> the review's 2D isotropic C(q) [m^4] by the
        # inverse Abel transform (Persson, Tribol. Lett. 54 (2014) 99; lookup.topography)
        cols = read_csv_table(path, {"q": "wavenumber", "C1D": "psd_1d"})
        q = cols["q"]
        if (cols["C1D"] <= 0).any() or not (np.diff(q) > 0).all():
            raise InputError("C1D must be > 0 and q strictly increasing", source=path,
                             field="C1D")
        C = psd_2d_from_1d(q, cols["C1D"])
    else:  # measured topography -> the review's 2D isotropic C(q) (lookup.topography)
        bins = t.integer("bins_per_decade", 10, minimum=2)
        if model == "height_map":
            q, C = read_height_map(path).psd(bins_per_decade=bins)
        else:
            q1d, C1 = read_line_scan(path).psd(bins_per_decade=bins)
            q, C = q1d, psd_2d_from_1d(q1d, C1)
    if model != "tabulated":
        keep = np.isfinite(C) & (C > 0)
        if keep.sum() < 2:
            raise InputError("the spectrum has fewer than two usable points", source=path,
                             field="file")
        q, C = q[keep], C[keep]
    if q0 is not None:
        try:
            q, C = trim_below(q, C, q0)
        except InputError as exc:
            raise t.error("q0", exc.message, t.raw("q0")) from None
    t.check_unknown()
    return TabulatedPSD(q, C, source=str(path))


def trim_below(q: np.ndarray, C: np.ndarray, q0: float) -> tuple[np.ndarray, np.ndarray]:
    """Cut a tabulated spectrum below ``q0``: keep q > q0 and add the point (q0, C(q0)).

    C(q0) is interpolated linearly in log C vs log q, as :class:`TabulatedPSD` interpolates,
    so the spectrum above q0 is unchanged. This is the small-wavenumber cut-off q0 of the
    review (sec. 4, the integrals start at q0): the largest roughness wavelength 2 pi / q0 that
    takes part, e.g. a macro-texture scale, instead of the length of the measurement.
    """
    q = np.asarray(q, float)
    C = np.asarray(C, float)
    if not q[0] <= q0 < q[-1]:
        raise InputError(f"q0 must lie inside the spectrum's data ({q[0]:.4g} .. "
                         f"{q[-1]:.4g} 1/m)")
    c0 = float(np.exp(np.interp(np.log(q0), np.log(q), np.log(C))))
    keep = q > q0 * (1 + 1e-12)
    return np.concatenate([[q0], q[keep]]), np.concatenate([[c0], C[keep]])


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
    m = t.table("macroasperity", required=False)
    D = None
    if m is not None:
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
