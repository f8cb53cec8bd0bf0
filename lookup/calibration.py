r"""Calibration: the friction model's open parameters fitted to measured friction.

What is fitted, and why these unknowns. The viscoelastic master curve, the shift factors and
the road's spectrum are measured; what the theory leaves open is (review sec. 5.1, "Open
problems") the short-wavelength cut-off q1 of the roughness that contributes to mu_visc
("the origin and precise value of this short-wavelength cut-off remain poorly understood";
the rule xi(q1) ~ 1 is an empirical finding) and the frictional shear stress in the real
contact area, for which the review offers only the empirical law of eqs. (21)-(22)
(``sigma_f0``, ``c``, ``v_star`` and its temperature shift: the bulk a_T or an Arrhenius
activation energy). The macroasperity diameter D (flash temperature and the slip distance
s0 = 0.2 D of eq. 28) is a rough estimate as well ("d ~ 1 mm", sec. 5.1). These are the
parameters :func:`fit` adjusts: per compound or shared by all compounds (the adhesive law's
parameters), or once for the road (q1, or the constant xi1 of the rms-slope rule, and D).

Residuals. For point i with measured friction mu_i and weight w_i,
:math:`r_i = \sqrt{w_i}\,[\log_{10}\mu(v_i, T_i, p_i; x) - \log_{10}\mu_i]`. Friction is
measured with an error proportional to the reading (a force transducer's), the model's
misses are factors (the uncalibrated model gives 0.2-0.3 of measured dry friction, and mu
spans decades between glassy and rubbery conditions), so a factor 1.1 counts the same at
mu = 0.1 and mu = 2; the RMS of log10 errors is the measure the tests and the docs quote.
A column of standard uncertainties u_mu gives w_i = [mu_i ln 10 / u_mu,i]^2 (the
uncertainty of log10 mu to first order).

Fitted variables. Scale parameters (sigma_f0, v_star, q1, xi1, D) are fitted as their
decimal logarithms, c as is and the activation energy in eV, so that every variable is of
order one and a step means the same across decades. scipy's ``least_squares`` (trust-region
reflective, bounds) minimises sum r_i^2 with a forward-difference Jacobian of the engine.

Uncertainty. At the optimum the Jacobian J of the residuals with respect to the fitted
variables is recomputed by central differences and the covariance is
:math:`s^2 (J^T J)^{-1}` with the residual variance :math:`s^2 = \sum r_i^2 / (m - n)` (m
fitted points, n free variables; Gauss-Newton, e.g. Seber & Wild, *Nonlinear Regression*,
Wiley 1989, sec. 2.1). It is the spread the parameters would have over repeated measurements
with the scatter the fit leaves, to first order; it includes the model's own misfit (which
s^2 absorbs) and says nothing of errors common to all points (a wrong master curve, a wrong
road spectrum). A variable at one of its bounds is held fixed there and gets no uncertainty.
For a log-scale parameter the standard uncertainty of log10 x is reported, and
x ln(10) sigma as the (first-order) standard uncertainty of x.

Cost. The cold branch is mu = mu_visc + sigma_f(v, T) A/A0 / sigma0 (review eq. 12, text
before eq. 17): mu_visc and A/A0 do not depend on the adhesive law, so they are computed once
per q1 and reused while only the law's parameters change (their Jacobian columns then cost
almost nothing). On the hot branch the law sets the heat and the heat the modulus, so every
evaluation solves the flash-temperature fixed point (to ``SolverSettings.hot_tol``, tighter
than the engine's default so that finite differences are not swamped by the solve's
tolerance). The engine of each compound (its tabulated master curve, q nodes, heat kernels)
is built once per (q1, D) and kept.
"""

from __future__ import annotations

import copy
import hashlib
import time
from collections import OrderedDict
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Literal

import numpy as np

from tirefric import __version__
from tirefric.errors import InputError, InputErrors

from .adhesion import GaussianShearLaw
from .compound import Compound
from .friction import EngineSettings, PerssonFriction
from .roughness import CutoffRule
from .shift import Arrhenius
from .surface import Surface

#: 1 eV in J (the energy unit of eq. 22's activation energy).
EV = 1.602176634e-19


@dataclass(frozen=True)
class ParameterKind:
    """How a fittable parameter is read, fitted and shown.

    Attributes
    ----------
    dimension : str
        Dimension in :mod:`tirefric.units` (for the spec's quantities).
    log : bool
        Fitted as log10 of the SI value (a scale parameter) or linearly in ``unit``.
    unit : str
        Unit in which the value is shown (and, for a linear parameter, fitted).
    scale : float
        SI value of one ``unit``.
    target : {"adhesion", "surface"}
        The compound's adhesive law (eq. 21-22) or the road.
    """

    dimension: str
    log: bool
    unit: str
    scale: float
    target: str

    def to_internal(self, x: float) -> float:
        return float(np.log10(x)) if self.log else float(x / self.scale)

    def to_si(self, u: float) -> float:
        return float(10.0**u) if self.log else float(u * self.scale)


#: The parameters :func:`fit` can adjust: the adhesive law of eqs. (21)-(22) per compound (or
#: shared), and the road's cut-off (q1 itself, or xi1 of the rms-slope rule) and D.
KINDS: dict[str, ParameterKind] = {
    "sigma_f0": ParameterKind("pressure", True, "MPa", 1e6, "adhesion"),
    "c": ParameterKind("dimensionless", False, "1", 1.0, "adhesion"),
    "v_star": ParameterKind("velocity", True, "m/s", 1.0, "adhesion"),
    "activation_energy": ParameterKind("energy", False, "eV", EV, "adhesion"),
    "q1": ParameterKind("wavenumber", True, "1/m", 1.0, "surface"),
    "xi1": ParameterKind("dimensionless", True, "1", 1.0, "surface"),
    "D": ParameterKind("length", True, "mm", 1e-3, "surface"),
}

#: Friction branches a measurement can be compared with.
BRANCHES = ("cold", "hot", "blend")


def file_sha256(path: str | Path) -> str:
    """``"sha256:<hex>"`` of a file's bytes (the data files' provenance)."""
    return "sha256:" + hashlib.sha256(Path(path).read_bytes()).hexdigest()


# -- inputs -------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeasuredTable:
    """Measured steady-sliding friction of one compound: mu at (v, T, p), with weights.

    Attributes
    ----------
    source : str
        The file the table came from (named in errors and outputs).
    v, T, p, mu, weight : numpy.ndarray
        Sliding speed [m/s], background temperature [K], nominal pressure [Pa], friction
        coefficient [1] and the weight of each point's squared residual [1], all > 0.
    sha256 : str
        Hash of the file's bytes (``"sha256:..."``), for the provenance of fitted files.
    """

    source: str
    v: np.ndarray
    T: np.ndarray
    p: np.ndarray
    mu: np.ndarray
    weight: np.ndarray
    sha256: str = ""

    def __post_init__(self) -> None:
        arrays = {}
        for nm in ("v", "T", "p", "mu", "weight"):
            a = np.atleast_1d(np.asarray(getattr(self, nm), float))
            arrays[nm] = a
        n = arrays["v"].size
        for nm, a in arrays.items():
            if a.ndim != 1 or a.size != n:
                raise InputError(f"column of {a.size} values where the table has {n} rows",
                                 source=self.source or None, field=nm)
            bad = ~(np.isfinite(a) & (a > 0))
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                raise InputError(f"row {i + 1}: must be a finite number > 0", source=self.source
                                 or None, field=nm, value=float(a[i]))
            object.__setattr__(self, nm, a)
        if n == 0:
            raise InputError("no measured points", source=self.source or None)

    @property
    def n(self) -> int:
        return int(self.v.size)


@dataclass(frozen=True)
class CompoundData:
    """A compound and its measured friction tables (all on the spec's road)."""

    name: str
    compound: Compound
    tables: tuple[MeasuredTable, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "tables", tuple(self.tables))
        if not self.name:
            raise InputError("a compound needs a name", field="compound.name")
        if not self.tables:
            raise InputError("no measured friction table", field=f"compound {self.name}.table")


@dataclass(frozen=True)
class ParameterSpec:
    """One fitted parameter with its bounds and start value (SI).

    Attributes
    ----------
    name : str
        One of :data:`KINDS`.
    lower, upper : float
        Bounds [SI], 0 < lower < upper.
    start : float or None
        Start value [SI]; None takes it from the model files (per compound for a
        per-compound parameter; for a shared adhesive parameter the mean of the compounds'
        values in the fitted variable, i.e. the geometric mean of a scale parameter).
    per_compound : bool
        One value per compound (adhesive parameters only) or one shared by all.
    """

    name: str
    lower: float
    upper: float
    start: float | None = None
    per_compound: bool = False

    def __post_init__(self) -> None:
        f = f"parameter.{self.name}"
        if self.name not in KINDS:
            raise InputError(f"unknown parameter (fittable: {', '.join(KINDS)})",
                             field="parameter.name", value=self.name)
        for nm in ("lower", "upper"):
            x = getattr(self, nm)
            if not (np.isfinite(x) and x > 0):
                raise InputError("bounds must be finite and > 0 (every fittable parameter is "
                                 "positive)", field=f"{f}.{'min' if nm == 'lower' else 'max'}",
                                 value=x)
        if not self.lower < self.upper:
            raise InputError(f"min must be below max = {self.upper:g}", field=f"{f}.min",
                             value=self.lower)
        if self.start is not None and not self.lower <= self.start <= self.upper:
            raise InputError(f"start must lie within [{self.lower:g}, {self.upper:g}]",
                             field=f"{f}.start", value=self.start)
        if self.per_compound and self.kind.target != "adhesion":
            raise InputError("a road parameter is one for all compounds; per_compound is for "
                             "the adhesive law's parameters", field=f"{f}.per_compound",
                             value=True)

    @property
    def kind(self) -> ParameterKind:
        return KINDS[self.name]


@dataclass(frozen=True)
class Branch:
    """Which friction the measurement is compared with.

    ``"cold"``: no flash heating (short slip distances, or speeds below ~1e-4 m/s where both
    branches agree). ``"hot"``: the flash temperature fully developed, the steady state of a
    block sliding far beyond s0 = 0.2 D (a laboratory block sliding centimetres to metres).
    ``"blend"``: eq. (28) at the slip distance ``slip_distance`` [m],
    mu = mu_cold exp(-s/s0) + mu_hot (1 - exp(-s/s0)).
    """

    kind: str = "hot"
    slip_distance: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in BRANCHES:
            raise InputError(f"must be one of {list(BRANCHES)}", field="branch", value=self.kind)
        if self.kind == "blend":
            if self.slip_distance is None or not (np.isfinite(self.slip_distance)
                                                  and self.slip_distance > 0):
                raise InputError("the eq. (28) blend needs slip_distance > 0",
                                 field="slip_distance", value=self.slip_distance)
        elif self.slip_distance is not None:
            raise InputError(f"slip_distance belongs to branch = 'blend' (branch is "
                             f"'{self.kind}')", field="slip_distance", value=self.slip_distance)


@dataclass(frozen=True)
class HeldOut:
    """Points kept out of the fit and predicted with the fitted parameters (the honest test).

    Attributes
    ----------
    compounds : tuple of str
        Compounds none of whose points is fitted.
    temperatures : tuple of float
        Temperatures [K] whose points are not fitted (matched within 0.01 K).
    per_compound : {"mean", "file"}
        What a compound without fitted points gets for a per-compound parameter: the mean of
        the fitted compounds' values in the fitted variable (geometric mean of a scale
        parameter), i.e. the prediction for a new compound from its master curve alone; or
        the value of its own file.
    """

    compounds: tuple[str, ...] = ()
    temperatures: tuple[float, ...] = ()
    per_compound: str = "mean"

    def __post_init__(self) -> None:
        object.__setattr__(self, "compounds", tuple(self.compounds))
        object.__setattr__(self, "temperatures", tuple(float(t) for t in self.temperatures))
        if self.per_compound not in ("mean", "file"):
            raise InputError("must be 'mean' or 'file'", field="held_out.per_compound",
                             value=self.per_compound)
        for t in self.temperatures:
            if not (np.isfinite(t) and t > 0):
                raise InputError("must be a temperature above 0 K",
                                 field="held_out.temperatures", value=t)

    def holds(self, compound: str, T: np.ndarray) -> np.ndarray:
        """Mask of the points of ``compound`` at temperatures ``T`` [K] that are held out."""
        out = np.full(T.shape, compound in self.compounds)
        for t in self.temperatures:
            out |= np.abs(T - t) < 0.01
        return out


@dataclass(frozen=True)
class SolverSettings:
    """Settings of the least-squares solve.

    Attributes
    ----------
    max_evaluations : int
        Limit on residual evaluations of the optimiser (``least_squares``' ``max_nfev``).
    diff_step : float or None
        Relative step of the forward-difference Jacobian in the fitted variables; None: 1e-6
        on the cold branch, 1e-4 on the hot one and the blend (the hot solve is converged to
        ``hot_tol``, which a smaller step would amplify).
    covariance_step : float
        Relative step of the central-difference Jacobian at the optimum (the covariance).
    hot_tol : float
        Tolerance [K] of the flash-temperature fixed point during the fit (the engine's
        default 1e-3 K would put noise of ~1e-5 into log10 mu).
    tol : float
        ``ftol``, ``xtol`` and ``gtol`` of ``least_squares``.
    """

    max_evaluations: int = 200
    diff_step: float | None = None
    covariance_step: float = 1e-4
    hot_tol: float = 1e-6
    tol: float = 1e-10

    def __post_init__(self) -> None:
        checks = (("max_evaluations", self.max_evaluations >= 1),
                  ("diff_step", self.diff_step is None or 0 < self.diff_step < 0.1),
                  ("covariance_step", 0 < self.covariance_step < 0.1),
                  ("hot_tol", self.hot_tol > 0), ("tol", 0 < self.tol < 1))
        for name, ok in checks:
            if not ok:
                raise InputError("invalid solver setting", field=f"solver.{name}",
                                 value=getattr(self, name))

    def step(self, branch: str) -> float:
        if self.diff_step is not None:
            return self.diff_step
        return 1e-6 if branch == "cold" else 1e-4


@dataclass(frozen=True)
class FitSpec:
    """Everything a calibration needs: the road, the compounds with their measured tables,
    the parameters to fit, the branch, the held-out points and the settings.

    Attributes
    ----------
    name : str
    surface : Surface
        The road all tables were measured on.
    compounds : tuple of CompoundData
    parameters : tuple of ParameterSpec
        Empty for a prediction (:func:`predict`).
    branch : Branch
    held_out : HeldOut
    adhesion_shift : {"file", "bulk", "arrhenius"}
        The temperature shift a'_T of the adhesive law (text after eq. 21): as in each
        compound file, the compound's bulk a_T, or eq. (22) (Arrhenius).
    activation_energy : float or None
        eq. (22)'s activation energy [J] for compounds whose file has none, when
        ``adhesion_shift = "arrhenius"`` and it is not fitted with a start value.
    settings : EngineSettings
    solver : SolverSettings
    source : str
        The spec file (named in errors and the provenance).
    """

    name: str
    surface: Surface
    compounds: tuple[CompoundData, ...]
    parameters: tuple[ParameterSpec, ...] = ()
    branch: Branch = field(default_factory=Branch)
    held_out: HeldOut = field(default_factory=HeldOut)
    adhesion_shift: str = "file"
    activation_energy: float | None = None
    settings: EngineSettings = field(default_factory=EngineSettings)
    solver: SolverSettings = field(default_factory=SolverSettings)
    source: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "compounds", tuple(self.compounds))
        object.__setattr__(self, "parameters", tuple(self.parameters))
        errors: list[InputError] = []
        src = self.source or None

        def err(message: str, fld: str, value: object = ...) -> None:
            errors.append(InputError(message, source=src, field=fld, value=value))

        if not self.compounds:
            err("no compound", "compound")
        names = [c.name for c in self.compounds]
        for nm in {n for n in names if names.count(n) > 1}:
            err("two compounds with the same name (give each a distinct 'name')",
                "compound.name", nm)
        pnames = [p.name for p in self.parameters]
        for nm in {n for n in pnames if pnames.count(n) > 1}:
            err("parameter listed twice", "parameter.name", nm)
        if "q1" in pnames and "xi1" in pnames:
            err("fit either q1 or xi1 (the rms-slope rule's constant), not both",
                "parameter.name", "xi1")
        if self.adhesion_shift not in ("file", "bulk", "arrhenius"):
            err("must be 'file', 'bulk' or 'arrhenius'", "adhesion.shift", self.adhesion_shift)
        for nm in self.held_out.compounds:
            if nm not in names:
                err(f"no such compound in the spec (compounds: {', '.join(names)})",
                    "held_out.compounds", nm)
        T_all = np.concatenate([t.T for c in self.compounds for t in c.tables] or [[]])
        for t in self.held_out.temperatures:
            if not (np.abs(T_all - t) < 0.01).any():
                err(f"no measured point at {t - 273.15:g} degC", "held_out.temperatures",
                    f"{t - 273.15:g} degC")
        needs_law = any(p.kind.target == "adhesion" for p in self.parameters) or \
            self.adhesion_shift != "file"
        for c in self.compounds:
            law = c.compound.adhesion
            csrc = c.compound.source or None
            if needs_law and not isinstance(law, GaussianShearLaw):
                errors.append(InputError(
                    "fitting the adhesive law needs the law of eq. (21) (model = 'eq21') in "
                    f"the compound file (compound '{c.name}' has {law.describe()['model']})",
                    source=csrc, field="adhesion.model", value=law.describe()["model"]))
                continue
            if self.branch.kind != "cold" and c.compound.thermal is None:
                errors.append(InputError(
                    f"branch '{self.branch.kind}' solves the flash temperature and needs the "
                    "rubber's [thermal] table", source=csrc, field="thermal"))
            if isinstance(law, GaussianShearLaw):
                arr = isinstance(law.shift, Arrhenius)
                if "activation_energy" in pnames and not arr and \
                        self.adhesion_shift != "arrhenius":
                    err(f"activation_energy belongs to the Arrhenius shift of eq. (22), and "
                        f"compound '{c.name}' ({csrc}) shifts its law with the bulk a_T: set "
                        "[adhesion] shift = 'arrhenius' in the spec (or in the compound file)",
                        "adhesion.shift", self.adhesion_shift)
                if self.adhesion_shift == "arrhenius" and not arr and \
                        self.activation_energy is None and not any(
                            p.name == "activation_energy" and p.start is not None
                            for p in self.parameters):
                    errors.append(InputError(
                        f"compound '{c.name}' has no activation energy: give [adhesion] "
                        "activation_energy in the spec (or a start value of the fitted "
                        "activation_energy)", source=src, field="adhesion.activation_energy"))
        if self.branch.kind != "cold" and self.surface.D is None and not any(
                p.name == "D" and p.start is not None for p in self.parameters):
            errors.append(InputError(
                f"branch '{self.branch.kind}' needs the macroasperity diameter: add "
                "[macroasperity] D to the surface file, or fit D with a start value",
                source=self.surface.source or None, field="macroasperity.D"))
        for p in self.parameters:
            if p.name in ("q1",):
                q0, qmax = self.surface.psd.q0, self.surface.psd.q_max
                if p.lower <= q0 or p.upper > qmax * (1 + 1e-12):
                    err(f"q1 must lie inside the road spectrum's data ({q0:.4g} < q1 <= "
                        f"{qmax:.4g} 1/m)", "parameter.q1.min" if p.lower <= q0
                        else "parameter.q1.max", p.lower if p.lower <= q0 else p.upper)
            if p.name == "xi1":
                for bound, x in (("min", p.lower), ("max", p.upper)):
                    try:
                        CutoffRule("rms_slope", xi1=x).resolve(self.surface.psd)
                    except InputError as exc:
                        err(exc.message, f"parameter.xi1.{bound}", x)
            if p.name == "xi1" and p.start is None and self.surface.cutoff.rule != "rms_slope":
                err("the surface's cut-off is fixed: fitting xi1 needs a start value",
                    "parameter.xi1.start")
            if p.name == "D" and p.start is None and self.surface.D is None:
                err("the surface has no [macroasperity] D: give a start value",
                    "parameter.D.start")
        if errors:
            raise errors[0] if len(errors) == 1 else InputErrors(errors)

    def describe(self) -> dict[str, Any]:
        """The spec as a JSON-able dict (outputs and provenance)."""
        return {
            "name": self.name, "source": self.source,
            "sha256": file_sha256(self.source) if self.source and Path(self.source).is_file()
            else None,
            "surface": {"name": self.surface.name, "source": self.surface.source},
            "compounds": [{"name": c.name, "source": c.compound.source,
                           "tables": [{"file": t.source, "sha256": t.sha256, "n_points": t.n}
                                      for t in c.tables]} for c in self.compounds],
            "parameters": [{"name": p.name, "per_compound": p.per_compound, "min": p.lower,
                            "max": p.upper, "start": p.start, "unit": "SI",
                            "fitted_as": "log10" if p.kind.log else p.kind.unit}
                           for p in self.parameters],
            "branch": {"kind": self.branch.kind, "slip_distance_m": self.branch.slip_distance},
            "held_out": {"compounds": list(self.held_out.compounds),
                         "temperatures_C": [t - 273.15 for t in self.held_out.temperatures],
                         "per_compound": self.held_out.per_compound},
            "adhesion_shift": self.adhesion_shift,
            "residual": "sqrt(w) (log10 mu_model - log10 mu_measured)",
        }


# -- the model as a function of the fitted variables ----------------------------------------
@dataclass(frozen=True)
class Entry:
    """One fitted variable: a parameter, and the compound it belongs to (None: shared)."""

    parameter: ParameterSpec
    compound: int | None
    label: str


@dataclass
class Prediction:
    """Model friction at a set of points (arrays of the points' shape)."""

    mu: np.ndarray
    mu_visc: np.ndarray
    mu_cont: np.ndarray
    area: np.ndarray
    dT_flash: np.ndarray
    hot_residual: float = 0.0


def _law_values(law: GaussianShearLaw) -> dict[str, float]:
    out = {"sigma_f0": law.sigma_f0, "c": law.c, "v_star": law.v_star}
    if isinstance(law.shift, Arrhenius):
        out["activation_energy"] = law.shift.activation_energy
    return out


class CalibrationModel:
    """The engine as a function of the fitted variables u, with what does not change cached.

    Parameters
    ----------
    spec : FitSpec

    Attributes
    ----------
    entries : list of Entry
        The fitted variables, in the order of u.
    u0, lower, upper : numpy.ndarray
        Start values and bounds of u.
    compound_index, v, T, p, mu, weight, held_out, table_index : numpy.ndarray
        The measured points of all compounds, concatenated.
    n_evaluations : int
        Model evaluations so far; ``eval_seconds`` their total time.
    """

    def __init__(self, spec: FitSpec) -> None:
        self.spec = spec
        self.settings = replace(spec.settings,
                                hot_tol=min(spec.settings.hot_tol, spec.solver.hot_tol))
        ci, ti, cols = [], [], {k: [] for k in ("v", "T", "p", "mu", "weight")}
        held = []
        self.tables: list[tuple[int, MeasuredTable]] = []
        for i, c in enumerate(spec.compounds):
            for t in c.tables:
                self.tables.append((i, t))
                ci.append(np.full(t.n, i))
                ti.append(np.full(t.n, len(self.tables) - 1))
                for k in cols:
                    cols[k].append(getattr(t, k))
                held.append(spec.held_out.holds(c.name, t.T))
        self.compound_index = np.concatenate(ci)
        self.table_index = np.concatenate(ti)
        self.v, self.T, self.p, self.mu, self.weight = (np.concatenate(cols[k]) for k in cols)
        self.held_out = np.concatenate(held)
        self.fitted = ~self.held_out
        has_fit = [bool(self.fitted[self.compound_index == i].any())
                   for i in range(len(spec.compounds))]
        self.has_fit = has_fit
        # the shift of each compound's adhesive law: "bulk" or "arrhenius"
        self.shift_kind: list[str] = []
        self.file_values: list[dict[str, float]] = []
        for c in spec.compounds:
            law = c.compound.adhesion
            vals = _law_values(law) if isinstance(law, GaussianShearLaw) else {}
            kind = "arrhenius" if "activation_energy" in vals else "bulk"
            if spec.adhesion_shift != "file":
                kind = spec.adhesion_shift
            if kind == "arrhenius" and "activation_energy" not in vals:
                pa = next((p for p in spec.parameters if p.name == "activation_energy"), None)
                vals["activation_energy"] = (spec.activation_energy if spec.activation_energy
                                             is not None else pa.start)  # type: ignore[union-attr]
            self.shift_kind.append(kind)
            self.file_values.append(vals)
        self.entries: list[Entry] = []
        u0, lo, hi = [], [], []
        for p in spec.parameters:
            k = p.kind
            if p.per_compound:
                for i, c in enumerate(spec.compounds):
                    if not has_fit[i]:
                        continue
                    start = p.start if p.start is not None else self.file_values[i][p.name]
                    self._check_start(p, start, c)
                    self.entries.append(Entry(p, i, f"{p.name}[{c.name}]"))
                    u0.append(k.to_internal(start))
            else:
                if p.start is not None:
                    us = k.to_internal(p.start)
                elif k.target == "adhesion":
                    us = float(np.mean([k.to_internal(fv[p.name]) for fv in self.file_values]))
                    self._check_start(p, k.to_si(us), None)
                else:
                    us = k.to_internal(self._surface_value(p.name))
                    self._check_start(p, k.to_si(us), None)
                self.entries.append(Entry(p, None, p.name))
                u0.append(us)
            lo += [k.to_internal(p.lower)] * (len(u0) - len(lo))
            hi += [k.to_internal(p.upper)] * (len(u0) - len(hi))
        self.lower = np.asarray(lo, float)
        self.upper = np.asarray(hi, float)
        # (a start on a bound may round outside it in the fitted variable)
        self.u0 = np.clip(np.asarray(u0, float), self.lower, self.upper)
        self._base_q1 = float(spec.surface.q1)
        self._q1_cache: dict[float, float] = {}
        self._engines: OrderedDict[tuple, PerssonFriction] = OrderedDict()
        self._kernel_pool: OrderedDict[tuple, dict] = OrderedDict()
        self._cold_cache: OrderedDict[tuple, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        self._cache_size = 4 * len(spec.compounds) + 4
        self.n_evaluations = 0
        self.eval_seconds = 0.0

    # -- parameters ---------------------------------------------------------------------------
    def _surface_value(self, name: str) -> float:
        s = self.spec.surface
        if name == "q1":
            return float(s.q1)
        if name == "xi1":
            return float(s.cutoff.xi1)
        return float(s.D)  # type: ignore[arg-type]

    def _check_start(self, p: ParameterSpec, start: float, c: CompoundData | None) -> None:
        if p.lower * (1 - 1e-12) <= start <= p.upper * (1 + 1e-12):
            return
        where = (f"compound '{c.name}' ({c.compound.source or 'no file'}) has "
                 f"adhesion.{p.name}" if c is not None else "the start value taken from the "
                 "model files is")
        raise InputError(f"{where} = {start:g}, outside [{p.lower:g}, {p.upper:g}]: give a "
                         "start value or wider bounds", source=self.spec.source or None,
                         field=f"parameter.{p.name}.start")

    def values(self, u: np.ndarray, start: bool = False
               ) -> tuple[list[dict[str, float]], dict[str, float]]:
        """Parameter values [SI] at u: per compound (the adhesive law) and the road's.

        A compound without fitted points gets the held-out rule's values of the per-compound
        parameters; with ``start`` (the model before calibration) its own start values."""
        comp = [dict(fv) for fv in self.file_values]
        road: dict[str, float] = {}
        per: dict[str, list[float]] = {}
        for e, x in zip(self.entries, u, strict=True):
            k = e.parameter.kind
            if k.target == "surface":
                road[e.parameter.name] = k.to_si(x)
            elif e.compound is None:
                for cv in comp:
                    cv[e.parameter.name] = k.to_si(x)
            else:
                comp[e.compound][e.parameter.name] = k.to_si(x)
                per.setdefault(e.parameter.name, []).append(float(x))
        if self.spec.held_out.per_compound == "mean" and not start:
            for name, us in per.items():
                for i, cv in enumerate(comp):
                    if not self.has_fit[i]:
                        cv[name] = KINDS[name].to_si(float(np.mean(us)))
        else:
            for p in self.spec.parameters:
                if p.per_compound and p.start is not None:
                    for i, cv in enumerate(comp):
                        if not self.has_fit[i]:
                            cv[p.name] = p.start
        return comp, road

    def law(self, i: int, values: dict[str, float]) -> GaussianShearLaw:
        """The adhesive law of eqs. (21)-(22) of compound ``i`` with ``values``."""
        base = self.spec.compounds[i].compound
        old = base.adhesion
        T_ref = old.T_ref if isinstance(old, GaussianShearLaw) else base.T_ref
        if self.shift_kind[i] == "arrhenius":
            shift = Arrhenius(values["activation_energy"], T_ref)
        else:
            shift = base.shift
        return GaussianShearLaw(values["sigma_f0"], values["c"], values["v_star"], T_ref, shift)

    def road(self, road: dict[str, float]) -> tuple[float, float | None]:
        """(q1 [1/m], D [m] or None) for the road's fitted values."""
        if "q1" in road:
            q1 = road["q1"]
        elif "xi1" in road:
            xi1 = road["xi1"]
            q1 = self._q1_cache.get(xi1)
            if q1 is None:
                q1 = CutoffRule("rms_slope", xi1=xi1).resolve(self.spec.surface.psd)
                if len(self._q1_cache) > 64:
                    self._q1_cache.clear()
                self._q1_cache[xi1] = q1
        else:
            q1 = self._base_q1
        return float(q1), road.get("D", self.spec.surface.D)

    # -- evaluation -------------------------------------------------------------------------------
    def engine(self, i: int, q1: float, D: float | None) -> PerssonFriction:
        """The engine of compound ``i`` on the road with cut-off q1 and diameter D (cached)."""
        key = (i, q1, D)
        eng = self._engines.get(key)
        if eng is None:
            surf = replace(self.spec.surface, cutoff=CutoffRule("fixed", q1=q1), D=D)
            eng = PerssonFriction(self.spec.compounds[i].compound, surf, self.settings)
            # the heat kernels depend on the q nodes, D and the thermal data, not on the
            # modulus: compounds with the same thermal data share them (one dict per kind)
            sig = (q1, D, eng.q.size, eng.D_th, eng.rho_c, eng.R_image,
                   self.settings.tau_per_decade)
            pool = self._kernel_pool.get(sig)
            if pool is None:
                self._kernel_pool[sig] = eng._kernels
                if len(self._kernel_pool) > self._cache_size:
                    self._kernel_pool.popitem(last=False)
            else:
                eng._kernels = pool
            self._engines[key] = eng
            if len(self._engines) > self._cache_size:
                self._engines.popitem(last=False)
        else:
            self._engines.move_to_end(key)
        return eng

    @staticmethod
    def with_adhesion(engine: PerssonFriction, law: GaussianShearLaw) -> PerssonFriction:
        """The engine with another adhesive law. The engine reads the law only when it
        evaluates (``PerssonFriction._evaluate``); the modulus table, q nodes and heat kernels
        it prepared do not depend on it and are shared (a shallow copy)."""
        e = copy.copy(engine)
        e.compound = replace(engine.compound, adhesion=law)
        return e

    def _cold_parts(self, i: int, q1: float, D: float | None, idx: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
        """(mu_visc, A/A0) on the cold branch at points ``idx`` of compound ``i``: they do not
        depend on the adhesive law (review eq. 12), so they are kept per q1."""
        key = (i, q1, idx.tobytes())
        hit = self._cold_cache.get(key)
        if hit is None:
            r = self.engine(i, q1, D).cold(self.v[idx], self.T[idx], self.p[idx])
            hit = (r.mu_visc, r.area)
            self._cold_cache[key] = hit
            if len(self._cold_cache) > self._cache_size:
                self._cold_cache.popitem(last=False)
        else:
            self._cold_cache.move_to_end(key)
        return hit

    def predict(self, u: np.ndarray, mask: np.ndarray | None = None, start: bool = False
                ) -> Prediction:
        """Model friction at the points selected by ``mask`` (all points if None); ``start``:
        held-out compounds with their own start values (see :meth:`values`)."""
        t0 = time.perf_counter()
        mask = np.ones(self.v.size, bool) if mask is None else mask
        comp, road = self.values(np.asarray(u, float), start)
        q1, D = self.road(road)
        n = int(mask.sum())
        out = {k: np.zeros(n) for k in ("mu", "mu_visc", "mu_cont", "area", "dT_flash")}
        pos = np.flatnonzero(mask)
        hot_res = 0.0
        kind = self.spec.branch.kind
        for i in range(len(self.spec.compounds)):
            idx = pos[self.compound_index[pos] == i]
            if idx.size == 0:
                continue
            sel = np.searchsorted(pos, idx)
            law = self.law(i, comp[i])
            v, T, p = self.v[idx], self.T[idx], self.p[idx]
            parts: dict[str, np.ndarray] = {}
            if kind in ("cold", "blend"):
                mv, area = self._cold_parts(i, q1, D, idx)
                mc = law.sigma_f(v, T) * area / p  # eq. (12): sigma_f A / (sigma0 A0)
                parts = {"mu": mv + mc, "mu_visc": mv, "mu_cont": mc, "area": area,
                         "dT_flash": np.zeros(idx.size)}
            if kind in ("hot", "blend"):
                eng = self.with_adhesion(self.engine(i, q1, D), law)
                h = eng.hot(v, T, p)
                hot_res = max(hot_res, float(np.max(h.residual)))
                hp = {"mu": h.mu, "mu_visc": h.mu_visc, "mu_cont": h.mu_cont, "area": h.area,
                      "dT_flash": h.dT_flash}
                if kind == "hot":
                    parts = hp
                else:  # eq. (28) at the slip distance s, s0 = 0.2 D
                    w = np.exp(-self.spec.branch.slip_distance / eng.s0)  # type: ignore[operator]
                    parts = {k: w * parts[k] + (1 - w) * hp[k] for k in parts}
                    parts["dT_flash"] = hp["dT_flash"]
            for k in out:
                out[k][sel] = parts[k]
        self.n_evaluations += 1
        self.eval_seconds += time.perf_counter() - t0
        return Prediction(**out, hot_residual=hot_res)

    def residuals(self, u: np.ndarray) -> np.ndarray:
        """sqrt(w) (log10 mu_model - log10 mu_measured) at the fitted points."""
        m = self.fitted
        mu = self.predict(u, m).mu
        if not (np.isfinite(mu) & (mu > 0)).all():
            bad = int(np.flatnonzero(~(np.isfinite(mu) & (mu > 0)))[0])
            raise InputError("the model gives a friction that is not finite and > 0 at "
                             f"v = {self.v[m][bad]:g} m/s, T = {self.T[m][bad]:g} K",
                             source=self.spec.source or None,
                             field="parameters", value=dict(zip(
                                 [e.label for e in self.entries], u.tolist(), strict=True)))
        return np.sqrt(self.weight[m]) * (np.log10(mu) - np.log10(self.mu[m]))


def central_jacobian(fun, u: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                     rel_step: float) -> np.ndarray:
    """Jacobian of ``fun`` at ``u`` by central differences, one-sided at a bound, with the
    step rel_step max(1, |u_j|) (the variables are of order one)."""
    f0 = fun(u)
    J = np.empty((f0.size, u.size))
    for j in range(u.size):
        h = rel_step * max(1.0, abs(u[j]))
        up, dn = u.copy(), u.copy()
        if u[j] + h <= upper[j] and u[j] - h >= lower[j]:
            up[j] += h
            dn[j] -= h
            J[:, j] = (fun(up) - fun(dn)) / (2 * h)
        elif u[j] + h <= upper[j]:
            up[j] += h
            J[:, j] = (fun(up) - f0) / h
        else:
            dn[j] -= h
            J[:, j] = (f0 - fun(dn)) / h
    return J


# -- results ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class FittedParameter:
    """A fitted variable's value and standard uncertainty.

    Attributes
    ----------
    label : str
        ``name`` or ``name[compound]``.
    name : str
    compound : str or None
        None for a shared or road parameter.
    value, start, lower, upper : float
        SI.
    std : float
        Standard uncertainty [SI] (first order: x ln 10 std_log10 for a log parameter); NaN
        at a bound or in a prediction.
    std_internal : float
        Standard uncertainty of the fitted variable (log10 x, or x in ``unit``).
    at_bound : str
        "", "lower" or "upper".
    log : bool
        Fitted as log10.
    unit : str, scale : float
        Display unit and its SI value.
    """

    label: str
    name: str
    compound: str | None
    value: float
    start: float
    lower: float
    upper: float
    std: float
    std_internal: float
    at_bound: str
    log: bool
    unit: str
    scale: float

    def to_dict(self) -> dict[str, Any]:
        return {"label": self.label, "name": self.name, "compound": self.compound,
                "value": self.value, "std": _num(self.std), "start": self.start,
                "min": self.lower, "max": self.upper, "at_bound": self.at_bound or None,
                "fitted_as": "log10" if self.log else self.unit,
                "std_log10": _num(self.std_internal) if self.log else None,
                "factor_1sigma": _num(10 ** self.std_internal) if self.log else None,
                "unit": "SI", "display_unit": self.unit}


def _num(x: float) -> float | None:
    return None if x is None or not np.isfinite(x) else float(x)


def rms(x: np.ndarray) -> float | None:
    """Root mean square, None for no points."""
    return float(np.sqrt(np.mean(np.square(x)))) if np.size(x) else None


@dataclass
class CalibrationResult:
    """A fit (or a prediction without fitting) and everything it reports.

    Attributes
    ----------
    spec : FitSpec
    mode : {"fit", "predict"}
    parameters : list of FittedParameter
        The fitted variables (start values in a prediction).
    held_out_values : dict
        Per-compound parameters of compounds without fitted points: compound -> {name: SI}.
    covariance, correlation : numpy.ndarray
        Of the free fitted variables (``free_labels``), in the fitted variables (log10 x or x
        in its unit); empty in a prediction.
    s2 : float
        Residual variance sum r^2 / (m - n).
    dof : int
    condition_number : float
        Of the Jacobian at the optimum (free variables).
    prediction, start_prediction : Prediction
        The model at all points with the fitted and the start values.
    model : CalibrationModel
        Its points and caches (``model.v``, ``model.held_out``, ...).
    solver : dict
        least_squares' status, message, evaluations; timings.
    warnings : list of str
    """

    spec: FitSpec
    mode: str
    parameters: list[FittedParameter]
    held_out_values: dict[str, dict[str, float]]
    free_labels: list[str]
    covariance: np.ndarray
    correlation: np.ndarray
    s2: float
    dof: int
    condition_number: float
    prediction: Prediction
    start_prediction: Prediction
    model: CalibrationModel
    u: np.ndarray
    solver: dict[str, Any]
    warnings: list[str]

    # -- measures -----------------------------------------------------------------------------
    def residual_log10(self, start: bool = False) -> np.ndarray:
        """log10 mu_model - log10 mu_measured at every point (unweighted)."""
        p = self.start_prediction if start else self.prediction
        return np.log10(p.mu) - np.log10(self.model.mu)

    def rms_log10(self, which: Literal["fit", "held_out", "all"] = "fit",
                  start: bool = False) -> float | None:
        """RMS of log10 mu_model - log10 mu_measured over the fitted points, the held-out
        points or all points (unweighted); None when the set is empty."""
        r = self.residual_log10(start)
        m = {"fit": self.model.fitted, "held_out": self.model.held_out,
             "all": np.ones(r.size, bool)}[which]
        return rms(r[m])

    @property
    def rms_log10_fit(self) -> float | None:
        return self.rms_log10("fit")

    @property
    def rms_log10_held_out(self) -> float | None:
        return self.rms_log10("held_out")

    def parameter(self, label: str) -> FittedParameter:
        """The fitted parameter with this label (``"q1"``, ``"sigma_f0[S100]"``)."""
        for p in self.parameters:
            if p.label == label:
                return p
        raise KeyError(label)

    def compound_summary(self) -> list[dict[str, Any]]:
        """Per compound: points fitted and held out, RMS log10 errors, mean measured and
        predicted friction (the compounds' order)."""
        m = self.model
        r, r0 = self.residual_log10(), self.residual_log10(start=True)
        out = []
        for i, c in enumerate(self.spec.compounds):
            ci = m.compound_index == i
            out.append({"compound": c.name, "n_fit": int((ci & m.fitted).sum()),
                        "n_held_out": int((ci & m.held_out).sum()),
                        "rms_log10_fit": rms(r[ci & m.fitted]),
                        "rms_log10_held_out": rms(r[ci & m.held_out]),
                        "rms_log10_start": rms(r0[ci]),
                        "mean_mu_measured": float(np.mean(m.mu[ci])),
                        "mean_mu_predicted": float(np.mean(self.prediction.mu[ci])),
                        "mean_mu_start": float(np.mean(self.start_prediction.mu[ci]))})
        return out

    def points(self) -> list[dict[str, Any]]:
        """The per-point table: measured, predicted, residual, set."""
        m, p = self.model, self.prediction
        r = self.residual_log10()
        rows = []
        for k in range(m.v.size):
            i, t = m.tables[int(m.table_index[k])]
            rows.append({"compound": self.spec.compounds[i].name,
                         "table": Path(t.source).name, "v": float(m.v[k]),
                         "T_C": float(m.T[k] - 273.15), "p": float(m.p[k]),
                         "mu_measured": float(m.mu[k]), "mu_predicted": float(p.mu[k]),
                         "residual_log10": float(r[k]), "weight": float(m.weight[k]),
                         "set": "held_out" if m.held_out[k] else "fit",
                         "mu_start": float(self.start_prediction.mu[k]),
                         "mu_visc": float(p.mu_visc[k]), "mu_cont": float(p.mu_cont[k]),
                         "area": float(p.area[k]), "dT_flash": float(p.dT_flash[k])})
        return rows

    # -- fitted model objects ---------------------------------------------------------------
    def compound_values(self) -> dict[str, dict[str, float]]:
        """The adhesive law's parameters [SI] of every compound at the result."""
        comp, _ = self.model.values(self.u, self.mode == "predict")
        return {c.name: comp[i] for i, c in enumerate(self.spec.compounds)}

    def fitted_compound(self, name: str) -> Compound:
        """The compound with its fitted adhesive law (held-out compounds: as predicted)."""
        i = [c.name for c in self.spec.compounds].index(name)
        comp, _ = self.model.values(self.u, self.mode == "predict")
        base = self.spec.compounds[i].compound
        return replace(base, adhesion=self.model.law(i, comp[i]))

    def fitted_surface(self) -> Surface:
        """The road with its fitted cut-off and D."""
        _, road = self.model.values(self.u)
        s = self.spec.surface
        if "q1" in road:
            s = replace(s, cutoff=CutoffRule("fixed", q1=road["q1"]))
        elif "xi1" in road:
            s = replace(s, cutoff=CutoffRule("rms_slope", xi1=road["xi1"]))
        if "D" in road:
            s = replace(s, D=road["D"])
        return s

    def to_dict(self, points: bool = True) -> dict[str, Any]:
        """Everything as a JSON-able dict."""
        cond = self.condition_number
        out: dict[str, Any] = {
            "tirefric_version": __version__, "mode": self.mode, "spec": self.spec.describe(),
            "q1_per_m": self.model.road(self.model.values(self.u)[1])[0],
            "parameters": [p.to_dict() for p in self.parameters],
            "held_out_values": self.held_out_values,
            "covariance": {"labels": self.free_labels,
                           "variables": [_variable(self.parameter(lb)) for lb in
                                         self.free_labels],
                           "matrix": _matrix(self.covariance),
                           "formula": "s^2 (J^T J)^-1, J by central differences at the optimum"},
            "correlation": {"labels": self.free_labels, "matrix": _matrix(self.correlation)},
            "s2": _num(self.s2), "dof": self.dof,
            "condition_number": _num(cond),
            "rms_log10": {"fit": self.rms_log10("fit"), "held_out": self.rms_log10("held_out"),
                          "fit_start": self.rms_log10("fit", start=True),
                          "held_out_start": self.rms_log10("held_out", start=True)},
            "n_points": {"fit": int(self.model.fitted.sum()),
                         "held_out": int(self.model.held_out.sum())},
            "compounds": self.compound_summary(),
            "solver": self.solver, "warnings": self.warnings,
            "hot_residual_K": self.prediction.hot_residual,
        }
        if points:
            out["points"] = self.points()
        return out


def _matrix(a: np.ndarray) -> list[list[float | None]]:
    """A matrix for JSON: non-finite entries (undetermined variables) as null."""
    return [[_num(x) for x in row] for row in np.asarray(a, float)]


def _variable(p: FittedParameter) -> str:
    return f"log10({p.name} [SI])" if p.log else f"{p.name} [{p.unit}]"


# -- the fit --------------------------------------------------------------------------------
def _parameters(model: CalibrationModel, u: np.ndarray, std: np.ndarray,
                at: list[str]) -> list[FittedParameter]:
    out = []
    for j, e in enumerate(model.entries):
        k = e.parameter.kind
        x = k.to_si(u[j])
        s = std[j]
        std_si = x * np.log(10) * s if k.log else s * k.scale
        out.append(FittedParameter(
            e.label, e.parameter.name,
            None if e.compound is None else model.spec.compounds[e.compound].name,
            x, k.to_si(model.u0[j]), e.parameter.lower, e.parameter.upper, float(std_si),
            float(s), at[j], k.log, k.unit, k.scale))
    return out


def _held_out_values(model: CalibrationModel, u: np.ndarray, start: bool = False
                     ) -> dict[str, dict[str, float]]:
    comp, _ = model.values(u, start)
    per = {p.name for p in model.spec.parameters if p.per_compound}
    return {c.name: {k: comp[i][k] for k in sorted(per)}
            for i, c in enumerate(model.spec.compounds) if not model.has_fit[i] and per}


def predict(spec: FitSpec) -> CalibrationResult:
    """The engine against the measured tables with the start values, no fitting (the
    numbers "before calibration")."""
    model = CalibrationModel(spec)
    t0 = time.perf_counter()
    pred = model.predict(model.u0, start=True)
    n = model.u0.size
    return CalibrationResult(
        spec, "predict", _parameters(model, model.u0, np.full(n, np.nan), [""] * n),
        _held_out_values(model, model.u0, start=True), [], np.zeros((0, 0)), np.zeros((0, 0)),
        float("nan"), 0, float("nan"), pred, pred, model, model.u0.copy(),
        {"seconds": time.perf_counter() - t0, "evaluations": model.n_evaluations}, [])


def fit(spec: FitSpec) -> CalibrationResult:
    """Fit the spec's parameters to its measured tables (module docstring).

    Returns
    -------
    CalibrationResult
        Fitted values with standard uncertainties and correlations, the model at every
        point with the fitted and the start values, RMS log10 errors on the fitted and the
        held-out points.

    Raises
    ------
    InputError
        No parameter to fit, or no more fitted points than fitted variables.
    """
    from scipy.optimize import least_squares

    model = CalibrationModel(spec)
    n = model.u0.size
    m = int(model.fitted.sum())
    if m == 0:
        raise InputError("every point is held out: nothing to fit", source=spec.source or None,
                         field="held_out")
    if n == 0:
        raise InputError("no parameter to fit (use predict for the model without fitting)",
                         source=spec.source or None, field="parameter")
    if m <= n:
        raise InputError(f"{m} fitted points for {n} fitted variables: the fit needs more "
                         "points than variables", source=spec.source or None,
                         field="held_out")
    t0 = time.perf_counter()
    start = model.predict(model.u0, start=True)
    tol = spec.solver.tol
    res = least_squares(model.residuals, model.u0, bounds=(model.lower, model.upper),
                        method="trf", x_scale=1.0, diff_step=spec.solver.step(spec.branch.kind),
                        max_nfev=spec.solver.max_evaluations, ftol=tol, xtol=tol, gtol=tol)
    t_opt = time.perf_counter() - t0
    evals_opt = model.n_evaluations
    u = res.x
    span = model.upper - model.lower
    act = res.active_mask
    at = ["lower" if act[j] < 0 or u[j] - model.lower[j] <= 1e-9 * span[j] else
          "upper" if act[j] > 0 or model.upper[j] - u[j] <= 1e-9 * span[j] else ""
          for j in range(n)]
    free = np.array([a == "" for a in at])
    t1 = time.perf_counter()
    J = central_jacobian(model.residuals, u, model.lower, model.upper,
                         spec.solver.covariance_step)
    r = model.residuals(u)
    t_cov = time.perf_counter() - t1
    nf = int(free.sum())
    dof = m - nf
    s2 = float(r @ r / dof)
    Jf = J[:, free]
    warnings: list[str] = []
    std = np.full(n, np.nan)
    cov = np.zeros((nf, nf))
    corr = np.zeros((nf, nf))
    cond = float("nan")
    if nf:
        _, S, Vt = np.linalg.svd(Jf, full_matrices=False)
        cond = float(S[0] / S[-1]) if S[-1] > 0 else float("inf")
        if not np.isfinite(cond) or cond > 1e8:
            warnings.append(f"the Jacobian is (nearly) singular (condition number {cond:.3g}): "
                            "some parameters are not identifiable from these data")
        keep = S > S[0] * 1e-12
        inv = np.zeros_like(S)
        inv[keep] = 1.0 / S[keep] ** 2
        cov = s2 * (Vt.T * inv) @ Vt
        sd = np.sqrt(np.diag(cov))
        if not keep.all():
            # a direction the data do not see: the variables along it are undetermined
            blind = np.abs(Vt[~keep]).max(axis=0) > 1e-6
            sd[blind] = np.inf
            cov[blind, :] = np.nan
            cov[:, blind] = np.nan
            labels_blind = [e.label for e, f in zip(model.entries, free, strict=True) if f]
            warnings.append("not determined by these data (no uncertainty can be given): "
                            + ", ".join(lb for lb, b in zip(labels_blind, blind, strict=True)
                                        if b))
        std[free] = sd
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = cov / np.outer(sd, sd)
        labels = [e.label for e, f in zip(model.entries, free, strict=True) if f]
        for a in range(nf):
            for b in range(a + 1, nf):
                if abs(corr[a, b]) > 0.95:
                    warnings.append(f"{labels[a]} and {labels[b]} are correlated "
                                    f"({corr[a, b]:+.3f}): the data fix mostly a combination "
                                    "of them")
    for j, a in enumerate(at):
        if a:
            warnings.append(f"{model.entries[j].label} ended at its {a} bound "
                            f"({model.entries[j].parameter.lower if a == 'lower' else model.entries[j].parameter.upper:g} SI): "  # noqa: E501
                            "it is held there and has no uncertainty")
    if not res.success:
        warnings.append(f"least_squares did not converge: {res.message}")
    pred = model.predict(u)
    if pred.hot_residual > 10 * model.settings.hot_tol:
        warnings.append(f"the flash-temperature solve left a residual of "
                        f"{pred.hot_residual:.3g} K (tolerance {model.settings.hot_tol:g} K)")
    solver = {"method": "scipy.optimize.least_squares (trf, bounds)",
              "status": int(res.status), "message": str(res.message),
              "success": bool(res.success), "nfev": int(res.nfev),
              "njev": None if res.njev is None else int(res.njev),
              "model_evaluations": model.n_evaluations,
              "evaluations_optimiser": evals_opt,
              "diff_step": spec.solver.step(spec.branch.kind),
              "covariance_step": spec.solver.covariance_step,
              "hot_tol_K": model.settings.hot_tol,
              "seconds_optimiser": t_opt, "seconds_covariance": t_cov,
              "seconds_total": time.perf_counter() - t0,
              "seconds_per_evaluation": model.eval_seconds / max(model.n_evaluations, 1),
              "cost": float(res.cost)}
    return CalibrationResult(
        spec, "fit", _parameters(model, u, std, at), _held_out_values(model, u),
        [e.label for e, f in zip(model.entries, free, strict=True) if f], cov, corr, s2, dof,
        cond, pred, start, model, u.copy(), solver, warnings)
