"""Validation report: the friction model's prediction against measured friction, before and
after calibration, with the error on data kept out of every fit. Regenerates
docs/validation.md.

Run:  OMP_NUM_THREADS=1 python benchmarks/validation.py [--nexen DIR] [-o docs/validation.md]

Parts:

* **Shippable** (runs on a clean checkout): a recovery check on synthetic data (friction
  computed by tirefric itself from the shipped compounds and road with known adhesive-law
  parameters and q1, rounded to three digits as a laboratory reports it), and the README's
  ``tirefric fit`` example checked against the parameters its text says generated it. Both
  are synthetic: they test the fit, not the physics.
* **Private** (``--nexen DIR``): seven measured tread compounds with master curves, a_T
  tables, strain sweeps, the road spectrum of the proving-ground surface and measured dry
  friction mu(v) of five of them, published without a licence on GitHub
  (k100kan35-dotcom/psfinal_hysteresis_redesign @ e761ecbdc19d3b8c353fd398b1b4361959a35fa4).
  The data are not in this repository: DIR is a checkout of that repository (its
  ``preset_data/`` folder is read) or a folder with byte copies of its files named
  ``<subfolder>__<file>`` in ``raw/``. Without it the part is skipped with a note, and the
  report says that a reader must obtain the data to rerun it. Only aggregate results
  computed by this script (RMS errors, orders, parameters fitted by lookup.calibration) are
  written to the report, never the data's numbers.

Everything is loaded by the package's loaders (lookup.compound, lookup.surface,
lookup.calibration_files) and fitted by lookup.calibration (``predict`` before calibration,
``fit`` after); the data files are only given the headers the loaders need (units the
originals leave out or garble), their numbers untouched.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lookup.calibration import (
    EV,
    CalibrationResult,
    FitSpec,
    HeldOut,
    ParameterSpec,
    fit,
    predict,
)
from lookup.calibration_files import load_fit_spec

ROOT = Path(__file__).resolve().parents[1]

# -- the private data set: files, and how they are handed to the loaders ---------------------
NEXEN_REPO = "github.com/k100kan35-dotcom/psfinal_hysteresis_redesign"
NEXEN_COMMIT = "e761ecbdc19d3b8c353fd398b1b4361959a35fa4"

#: Per compound: master curve, a_T table, strain sweep (None: not in the data), measured dry
#: friction (None: not measured), the master curve's T_ref (where its a_T table is 1: 39.96 C
#: for the S series, 20.14-20.21 C for the R series, within the loader's 0.5 K check).
NEXEN_COMPOUNDS: dict[str, dict[str, Any]] = {
    "S100": {"master": "mastercurve/S100_master_final.txt", "aT": "aT/S100_at_final.txt",
             "sweep": "strain_sweep/S100_Y1_final.txt",
             "mu": "mu_dry/S100_total_mu_exp.txt", "T_ref": "40 degC"},
    "S120": {"master": "mastercurve/S120_master_final.txt", "aT": "aT/S120_at_final.txt",
             "sweep": "strain_sweep/S120.txt", "mu": "mu_dry/S120_total_mu_exp.txt",
             "T_ref": "40 degC"},
    "S140": {"master": "mastercurve/S140_master_final.txt", "aT": "aT/S140_at_final.txt",
             "sweep": "strain_sweep/S140Y1.txt", "mu": "mu_dry/S140_dry_exp.txt",
             "T_ref": "40 degC"},
    "R20": {"master": "mastercurve/R20.txt", "aT": "aT/R20_at.txt", "sweep": None,
            "mu": "mu_dry/R20.txt", "T_ref": "20 degC"},
    "R40": {"master": "mastercurve/R40.txt", "aT": "aT/R40.txt", "sweep": None,
            "mu": "mu_dry/R40.txt", "T_ref": "20 degC"},
}
NEXEN_PSD = "psd/IDIADA_PSD.txt"


def nexen_file(root: Path, rel: str) -> Path:
    """A file of the private data set: ``root/preset_data/<rel>`` (a checkout of the
    repository) or ``root/raw/<sub>__<name>`` (byte copies); an error naming both paths."""
    cands = [root / "preset_data" / rel, root / "raw" / rel.replace("/", "__")]
    for c in cands:
        if c.is_file():
            return c
    raise FileNotFoundError(f"{rel}: tried {cands[0]} and {cands[1]}")


def _rows(path: Path) -> list[list[str]]:
    """The data rows of a white-space separated text table (lines starting with '#' are
    comments)."""
    out = []
    for raw in path.read_bytes().splitlines():
        line = raw.decode("latin-1").strip()
        if line and not line.startswith("#"):
            out.append(line.split())
    return out


def _with_header(src: Path, dst: Path, header: str, note: str,
                 convert=None) -> Path:
    """Copy a table's data rows under a header the loaders read; ``convert`` maps a row."""
    rows = _rows(src)
    how = "rows unchanged" if convert is None else f"rows unchanged but {convert.__doc__}"
    lines = [f"# {note}", f"# from {src.name} ({how})", header]
    for r in rows:
        lines.append(",".join(convert(r) if convert else r))
    dst.write_text("\n".join(lines) + "\n")
    return dst


#: What the report assumes where the data are silent (each stated in the report).
NEXEN_T = "20 degC"        # the tool's stored calculation temperature; the data give none
NEXEN_P = "0.3 MPa"        # the tool's stored sigma_0; the data give none
#: "Before calibration": the review's adhesive law (sec. 5.1: "typically c ~ 0.17,
#: sigma_f0 ~ 4-8 MPa, v* ~ 1 cm/s"; sigma_f0 in the middle of the range), shifted with the
#: bulk a_T (text after eq. 21), and q1 by the rms-slope rule xi(q1) = 1 (sec. 5.1).
REVIEW_LAW = {"sigma_f0": "6 MPa", "c": 0.17, "v_star": "1 cm/s"}


def _v_from_log10(r: list[str]) -> list[str]:
    """v = 10**log10(v)"""
    return [f"{10.0 ** float(r[0]):.6g}", r[1]]


def prepare_nexen(root: Path, work: Path) -> dict[str, Path]:
    """Write the compound, road and measured-table files of the private data set into
    ``work`` (pointing at the data's own master curves) and return the compound files
    (name -> TOML) plus ``"surface"``.

    Only headers are supplied: the a_T tables' degree sign is garbled (a Korean code page),
    the strain sweeps' strain column has no unit (its values are percent: the research note
    /work/research/compounds2, and the 0.01-25 % range of a DMA sweep) and says Pa for
    moduli given in MPa (the softening uses ratios, so this does not matter), the spectrum
    calls its column ``C(q)``, and the friction tables give log10 v.
    """
    work.mkdir(parents=True, exist_ok=True)
    out: dict[str, Path] = {}
    for name, f in NEXEN_COMPOUNDS.items():
        master = nexen_file(root, f["master"])
        aT = _with_header(nexen_file(root, f["aT"]), work / f"aT_{name}.csv", "T [degC],aT",
                          "shift factors")
        if f["sweep"]:
            sw = _with_header(nexen_file(root, f["sweep"]), work / f"sweep_{name}.csv",
                              "T [degC],f [Hz],strain [%],E' [MPa],E'' [MPa]", "strain sweeps")
            soft = f'model = "strain_sweep"\nfile = "{sw.name}"\nstrain = "10 %"'
        else:
            typ = ROOT / "models" / "compounds" / "data" / "filled_tread_softening.csv"
            soft = f'model = "tabulated"\nfile = "{typ}"\nstrain = 0.1'
        _with_header(nexen_file(root, f["mu"]), work / f"mu_{name}.csv", "v [m/s],mu [1]",
                     "measured dry friction", _v_from_log10)
        law = REVIEW_LAW
        toml = f'''name = "{name}"
provenance = "{NEXEN_REPO} @ {NEXEN_COMMIT} (no licence): master curve, a_T, strain sweep"
nu = 0.5

[modulus]
T_ref = "{f["T_ref"]}"
model = "tabulated"
file = "{master}"

[shift]
model = "tabulated"
file = "{aT.name}"

[softening]
{soft}

[adhesion]
model = "eq21"
sigma_f0 = "{law["sigma_f0"]}"
c = {law["c"]}
v_star = "{law["v_star"]}"
T_ref = "{NEXEN_T}"
shift = "bulk"

[thermal]                # review sec. 5.1, after eq. (23)
rho = 1500.0
c_v = 1500.0
kappa = 0.3
'''
        (work / f"{name}.toml").write_text(toml)
        out[name] = work / f"{name}.toml"
    psd = _with_header(nexen_file(root, NEXEN_PSD), work / "psd_idiada.csv",
                       "q [1/m],C [m^4]", "road spectrum (2D isotropic)")
    (work / "idiada.toml").write_text(f'''name = "idiada"
provenance = "{NEXEN_REPO} @ {NEXEN_COMMIT} (no licence): preset_data/psd/IDIADA_PSD.txt"

[psd]
model = "tabulated"
file = "{psd.name}"
q0 = 200.0               # 1/m: as the shipped asphalt (wavelength ~3 cm, a judgment)

[cutoff]
rule = "rms_slope"       # review sec. 5.1
xi1 = 1.0

[macroasperity]
D = "1 mm"               # review sec. 5.1

[thermal]                # as the shipped asphalt (typical asphalt concrete)
kappa = 1.0
rho = 2300.0
c = 900.0
''')
    out["surface"] = work / "idiada.toml"
    return out


def write_spec(path: Path, surface: Path, compounds: dict[str, Path], tables: dict[str, Path],
               branch: str, parameters: str = "", held_out: str = "") -> FitSpec:
    """Write a fit spec (lookup/calibration_files.py's layout) and load it."""
    parts = [f'name = "{path.stem}"', f'surface = "{surface}"', f'branch = "{branch}"', ""]
    for name, f in compounds.items():
        parts += ["[[compound]]", f'file = "{f}"', "[[compound.table]]",
                  f'file = "{tables[name]}"', f'temperature = "{NEXEN_T}"',
                  f'pressure = "{NEXEN_P}"', ""]
    parts += [parameters, held_out]
    path.write_text("\n".join(parts) + "\n")
    return load_fit_spec(path)


# -- one fit and what the report says about it -------------------------------------------------
@dataclass
class Case:
    """A fit to report: its spec (parameters, held-out points) and what it is.

    Attributes
    ----------
    key : str
        Short label (``"R-series"``).
    title : str
        One line: compounds fitted and held out, parameters.
    spec : FitSpec
    notes : list of str
        What the report should say about this case's data.
    groups : list of list of str, optional
        Compounds whose order is compared (measured at the same speeds); default: all.
    """

    key: str
    title: str
    spec: FitSpec
    notes: list[str] = field(default_factory=list)
    groups: list[list[str]] | None = None


@dataclass
class CaseResult:
    """A case after ``lookup.calibration.fit``: the result holds the model at the start
    values too (before calibration) and at the fitted ones."""

    case: Case
    result: CalibrationResult
    seconds: float

    def rms(self, which: str, before: bool = False) -> float | None:
        """RMS log10 error over the fitted (``"fit"``) or held-out points, or all."""
        return self.result.rms_log10(which, start=before)  # type: ignore[arg-type]

    def compounds(self) -> list[dict[str, Any]]:
        """Per compound: points, RMS log10 errors before and after, the adhesive share of
        mu (mu_cont / mu, mean over its points) before and after, held out or not."""
        r = self.result
        m = r.model
        res_a, res_b = r.residual_log10(), r.residual_log10(start=True)
        out = []
        for i, c in enumerate(r.spec.compounds):
            ci = m.compound_index == i
            share_a = r.prediction.mu_cont[ci] / r.prediction.mu[ci]
            share_b = r.start_prediction.mu_cont[ci] / r.start_prediction.mu[ci]
            out.append({"compound": c.name, "n": int(ci.sum()),
                        "held_out": bool(m.held_out[ci].all()),
                        "n_held_out": int(m.held_out[ci].sum()),
                        "rms_before": float(np.sqrt(np.mean(res_b[ci] ** 2))),
                        "rms_after": float(np.sqrt(np.mean(res_a[ci] ** 2))),
                        "adhesive_share_before": (float(share_b.min()), float(share_b.max())),
                        "adhesive_share_after": (float(share_a.min()), float(share_a.max())),
                        "dT_max": float(r.prediction.dT_flash[ci].max())})
        return out

    def order(self, names: list[str] | None = None) -> dict[str, Any]:
        """The order by friction of the compounds ``names`` (default all): geometric mean of
        mu over the speeds (and temperatures, pressures) every one of them was measured at,
        measured, before and after calibration (highest first)."""
        r = self.result
        m = r.model
        allnames = [c.name for c in r.spec.compounds]
        names = allnames if names is None else names
        idx = [allnames.index(n) for n in names]
        key = np.round(np.log10(np.c_[m.v, m.T, m.p]), 3)
        sets = [{tuple(k) for k in key[m.compound_index == i]} for i in idx]
        common = set.intersection(*sets)
        if not common:
            raise ValueError(f"compounds {names} share no measured speed: give Case.groups")
        sel = np.array([tuple(k) in common for k in key])
        means: dict[str, dict[str, float]] = {}
        for label, mu in (("measured", m.mu), ("before", r.start_prediction.mu),
                          ("after", r.prediction.mu)):
            means[label] = {nm: float(np.exp(np.mean(np.log(mu[sel & (m.compound_index == i)]))))
                            for i, nm in zip(idx, names, strict=True)}
        rank = {lb: sorted(names, key=lambda nm, lb=lb: -means[lb][nm]) for lb in means}
        return {"n_common": len(common), "means": means, "rank": rank}


def run_case(case: Case) -> CaseResult:
    """Fit a case (lookup.calibration.fit: the start values are the model before
    calibration)."""
    t0 = time.perf_counter()
    r = fit(case.spec)
    return CaseResult(case, r, time.perf_counter() - t0)


# -- shippable part: a recovery check on synthetic data ------------------------------------
#: The synthetic data's parameters (shared by the compounds; the other adhesive parameters
#: are the compound files' own): what the fit must recover.
SYNTH_TRUTH = {"sigma_f0": 7e6, "xi1": 1.3}
SYNTH_BOUNDS = {"sigma_f0": (5e5, 5e7), "xi1": (0.3, 3.0)}


def synthetic_case(compounds: tuple[str, ...] = ("summer", "winter", "racing"),
                   surface: str = "asphalt",
                   speeds: tuple[float, ...] = (1e-5, 1e-4, 1e-3),
                   temperatures_C: tuple[float, ...] = (0.0, 10.0, 20.0, 30.0),
                   held_compounds: tuple[str, ...] = ("racing",),
                   held_temperatures_C: tuple[float, ...] = (30.0,),
                   truth: dict[str, float] | None = None, digits: int = 3,
                   pressure: float = 3e5) -> Case:
    """Friction computed by tirefric (cold branch) for shipped compounds on a shipped road
    with known ``truth`` (sigma_f0 of eq. 21 and xi1 of the q1 rule, sec. 5.1), rounded to
    ``digits`` significant digits, and the fit of those two from the compound and road
    files' values, with compounds and temperatures held out.

    Speeds up to 1 mm/s: the flash heating there stays at a few K, the cold branch is the
    friction a slow tester measures (docs/calibration.md)."""
    from lookup.calibration import Branch, CompoundData, MeasuredTable
    from lookup.compound import load_compound
    from lookup.surface import load_surface

    truth = dict(SYNTH_TRUTH if truth is None else truth)
    surf = load_surface(surface)
    v, T = (a.ravel() for a in np.meshgrid(np.asarray(speeds, float),
                                           np.asarray(temperatures_C, float) + 273.15))
    p = np.full(v.size, pressure)
    comps = [load_compound(c) for c in compounds]
    dummy = tuple(CompoundData(c.name, c, (MeasuredTable("synthetic", v, T, p, np.ones(v.size),
                                                         np.ones(v.size)),)) for c in comps)
    params_truth = tuple(ParameterSpec(n, *SYNTH_BOUNDS[n], start=x) for n, x in truth.items())
    gen = predict(FitSpec("truth", surf, dummy, params_truth, Branch("cold")))
    mu = gen.prediction.mu
    data = []
    for i, c in enumerate(comps):
        x = mu[gen.model.compound_index == i]
        x = np.array([float(f"{a:.{digits}g}") for a in x])
        data.append(CompoundData(c.name, c, (MeasuredTable(f"synthetic:{c.name}", v, T, p, x,
                                                           np.ones(v.size)),)))
    params = tuple(ParameterSpec(n, *SYNTH_BOUNDS[n]) for n in truth)
    spec = FitSpec("synthetic", surf, tuple(data), params, Branch("cold"),
                   HeldOut(held_compounds, tuple(t + 273.15 for t in held_temperatures_C)))
    held = ", ".join([*held_compounds, *(f"{t:g} C" for t in held_temperatures_C)])
    return Case("synthetic",
                f"{', '.join(compounds)} on {surface}, cold branch, {v.size} points each; "
                f"fitted: {', '.join(truth)} (shared); held out: {held}",
                spec, [f"truth: {', '.join(f'{k} = {x:g}' for k, x in truth.items())} (SI)",
                       f"friction rounded to {digits} significant digits"])


def recovery(cr: CaseResult, truth: dict[str, float] | None = None) -> list[dict[str, Any]]:
    """Fitted against true values: the miss in standard uncertainties."""
    truth = SYNTH_TRUTH if truth is None else truth
    out = []
    for p in cr.result.parameters:
        t = truth[p.name]
        miss = math.log10(p.value / t) if p.log else (p.value - t) / p.scale
        out.append({"parameter": p.label, "true": t, "fitted": p.value, "std_log10_or_unit":
                    p.std_internal, "miss_in_std": miss / p.std_internal if p.std_internal
                    else float("nan"), "relative_miss": p.value / t - 1})
    return out


# -- shippable part: the README's calibration example -----------------------------------------
#: The parameters the README's text says its "measured" table was computed with.
README_TRUTH = {"sigma_f0": 6e6, "v_star": 0.03, "activation_energy": 0.8 * EV, "q1": 1e4}


def readme_example(work: Path) -> dict[str, Any]:
    """The README's ``tirefric fit`` example: its files (the README's blocks headed
    ``# file: NAME``) written to ``work``; the model at the parameters the text says made the
    table (cold branch), against the table; and the fit of the README, against them."""
    import re

    text = (ROOT / "README.md").read_text()
    work.mkdir(parents=True, exist_ok=True)
    for m in re.finditer(r"```(?:csv|toml)\n(.*?)```", text, re.S):
        first = m[1].splitlines()[0] if m[1] else ""
        if first.startswith("# file: "):
            (work / first.removeprefix("# file: ").strip()).write_text(m[1])
    spec = load_fit_spec(work / "fit_lab.toml")
    at_truth = predict(dataclasses.replace(spec, parameters=tuple(
        dataclasses.replace(p, start=README_TRUTH[p.name]) for p in spec.parameters)))
    fitted = fit(spec)
    return {"n": int(at_truth.model.mu.size),
            "rms_at_stated_parameters": at_truth.rms_log10("all", start=True),
            "max_at_stated_parameters": float(np.max(np.abs(at_truth.residual_log10(True)))),
            "fitted": {p.label: (p.value / p.scale, p.std / p.scale,
                                 README_TRUTH[p.name] / p.scale, p.unit)
                       for p in fitted.parameters},
            "rms_fit": fitted.rms_log10("fit"), "rms_held_out": fitted.rms_log10("held_out")}


# -- private part: the seven-compound set --------------------------------------------------
NEXEN_LAW = '''
[[parameter]]
name = "sigma_f0"
min = "0.5 MPa"
max = "50 MPa"

[[parameter]]
name = "c"
min = 0.02
max = 1.0

[[parameter]]
name = "v_star"
min = "1 um/s"
max = "100 m/s"
'''
NEXEN_XI1 = '''
[[parameter]]
name = "xi1"
min = 0.3
max = 3.0
'''


def nexen_cases(root: Path, work: Path) -> list[Case]:
    """The fits of the private data set (hot branch: a block or tire sliding centimetres to
    metres, far beyond s0 = 0.2 D; docs/calibration.md). S120 and R40 are kept out of every
    fit."""
    files = prepare_nexen(root, work)
    tabs = {n: work / f"mu_{n}.csv" for n in NEXEN_COMPOUNDS}
    comp = {n: files[n] for n in NEXEN_COMPOUNDS}

    def spec(name: str, names: list[str], params: str, held: list[str]) -> FitSpec:
        ho = "[held_out]\ncompounds = [" + ", ".join(f'"{h}"' for h in held) + "]\n"
        return write_spec(work / f"{name}.toml", files["surface"],
                          {n: comp[n] for n in names}, tabs, "hot", params, ho)

    law = "sigma_f0, c, v_star of eq. (21), shared"
    return [
        Case("resin series", f"R20 fitted, R40 held out; {law}; q1 by the rule xi(q1) = 1",
             spec("nexen_R", ["R20", "R40"], NEXEN_LAW, ["R40"]),
             ["six speeds per compound over about three decades, below 1 m/s"]),
        Case("silica series", f"S100, S140 fitted, S120 held out; {law}, and xi1 of the q1 "
             "rule", spec("nexen_S", ["S100", "S120", "S140"], NEXEN_LAW + NEXEN_XI1,
                          ["S120"]),
             ["five speeds per compound over about three decades up to tens of m/s; S120 "
              "has two more below them, outside the fitted compounds' speeds"]),
        Case("both series", f"S100, S140, R20 fitted, S120 and R40 held out; {law}, and xi1 "
             "(one road, one law)", spec("nexen_all", list(NEXEN_COMPOUNDS),
                                         NEXEN_LAW + NEXEN_XI1, ["S120", "R40"]),
             ["the two series on one road with one adhesive law"],
             [["S100", "S120", "S140"], ["R20", "R40"]]),
    ]


# -- the report ------------------------------------------------------------------------------
def _f(x: float | None, fmt: str = ".3f") -> str:
    return "-" if x is None or not np.isfinite(x) else format(x, fmt)


def _param_rows(cr: CaseResult) -> list[str]:
    rows = ["| parameter | before | fitted | std. uncertainty | note |", "|---|---|---|---|---|"]
    for p in cr.result.parameters:
        u = "" if p.unit == "1" else f" {p.unit}"
        unc = (f"{p.std / p.scale:.3g}{u} (factor {10 ** p.std_internal:.4f})" if p.log
               else f"{p.std / p.scale:.3g}{u}") if np.isfinite(p.std) else "-"
        note = f"at its {p.at_bound} bound {getattr(p, p.at_bound) / p.scale:g}{u}" \
            if p.at_bound else ""
        rows.append(f"| {p.label} | {p.start / p.scale:.4g}{u} | "
                    f"{p.value / p.scale:.4g}{u} | {unc} | {note} |")
    d = cr.result.to_dict(points=False)
    rows.append(f"| q1 (resulting) | {cr.result.spec.surface.q1:.3g} 1/m | "
                f"{d['q1_per_m']:.3g} 1/m | | |")
    return rows


def _order_line(cr: CaseResult, names: list[str] | None = None) -> list[str]:
    o = cr.order(names)
    ranks = o["rank"]
    ok = {lb: ranks[lb] == ranks["measured"] for lb in ("before", "after")}
    ratio = {lb: {n: o["means"][lb][n] / o["means"]["measured"][n] for n in ranks["measured"]}
             for lb in ("before", "after")}
    lines = [f"Order by friction of {', '.join(ranks['measured'])} (geometric mean over the "
             f"{o['n_common']} speeds all of them were measured at, highest first):", "",
             f"- measured: {' > '.join(ranks['measured'])}",
             f"- before calibration: {' > '.join(ranks['before'])} "
             f"({'same' if ok['before'] else 'NOT the measured order'})",
             f"- after: {' > '.join(ranks['after'])} "
             f"({'same' if ok['after'] else 'NOT the measured order'})", "",
             "Model over measured friction (same geometric means): " + "; ".join(
                 f"{n} {ratio['before'][n]:.2f} before, {ratio['after'][n]:.2f} after"
                 for n in ranks["measured"]) + "."]
    return lines


def _case_section(cr: CaseResult, private: bool) -> list[str]:
    r = cr.result
    m = r.model
    lines = [f"### {cr.case.key}: {cr.case.title}", ""]
    lines += [f"- {n}" for n in cr.case.notes]
    lines += [f"- branch: {r.spec.branch.kind}; {int(m.fitted.sum())} fitted and "
              f"{int(m.held_out.sum())} held-out points; the fit took {cr.seconds:.1f} s "
              f"({r.solver.get('model_evaluations', 0)} model evaluations)", ""]
    lines += ["| RMS log10 error | fitted points | held-out points |", "|---|---|---|",
              f"| before calibration | {_f(cr.rms('fit', True))} | "
              f"{_f(cr.rms('held_out', True))} |",
              f"| after | {_f(cr.rms('fit'))} | {_f(cr.rms('held_out'))} |", ""]
    lines += [*_param_rows(cr), ""]
    if r.correlation.size:
        labels = r.free_labels
        pairs = [f"{labels[a]}/{labels[b]} {r.correlation[a, b]:+.2f}"
                 for a in range(len(labels)) for b in range(a + 1, len(labels))]
        lines += [f"Correlations of the fitted variables: {'; '.join(pairs)}.", ""]
    lines += ["| compound | points | set | RMS log10 before | after | adhesive share of mu "
              "before | after | largest flash dT after [K] |", "|---|---|---|---|---|---|---|---|"]
    for c in cr.compounds():
        sb, sa = c["adhesive_share_before"], c["adhesive_share_after"]
        lines.append(f"| {c['compound']} | {c['n']} | {'held out' if c['held_out'] else 'fitted'}"
                     f" | {c['rms_before']:.3f} | {c['rms_after']:.3f} | {sb[0]:.2f}-{sb[1]:.2f} "
                     f"| {sa[0]:.2f}-{sa[1]:.2f} | {c['dT_max']:.0f} |")
    lines += [""]
    for g in cr.case.groups or [[c.name for c in r.spec.compounds]]:
        if len(g) > 1:
            lines += [*_order_line(cr, g), ""]
    for w in r.warnings:
        lines.append(f"- fit warning: {w}")
    if r.warnings:
        lines.append("")
    return lines


#: Candidate data sets found by the project's searches of public repositories and web pages
#: (two rounds of research notes), as rows of DATASET_COLUMNS.
DATASET_COLUMNS = ('data set', 'compound data', 'road spectrum', 'measured friction',
                   'licence', 'used here as')
DATASETS: tuple[tuple[str, ...], ...] = (
    ('seven tread compounds S100-S140, R00-R60 ({repo} @ {commit_short})',
     'master curves, a_T tables, strain sweeps (S series)',
     'the IDIADA proving-ground surface',
     'dry mu(v) of S100, S120, S140, R20, R40',
     'none',
     'the validation (private part, `--nexen`)'),
    ('README / docs/calibration.md `tirefric fit` example',
     "README's example compound",
     "README's example road",
     'computed by tirefric, not measured',
     "project's",
     'recovery check (synthetic)'),
    ('synthetic set of this script',
     'shipped `summer`, `winter`, `racing`',
     'shipped `asphalt`',
     'computed by tirefric',
     "project's",
     'recovery check (synthetic)'),
    ('perssonmodelling example (k100kan35-dotcom/perssonmodelling)',
     'one master curve, no T_ref or a_T',
     'one PSD',
     'none (a mu_visc curve from a program)',
     'none',
     'not used: no measured friction'),
    ('CAPTIF SLP road profiles (MIT)',
     'none',
     'macrotexture only',
     'none',
     'MIT',
     'not used: no compound, no friction'),
    ('Hentschke & Plagge, Sci. Rep. 11 (2021), Fig. 1 (CC BY 4.0)',
     'fit parameters of one master curve',
     'none',
     'fitted, in another paper',
     'CC BY 4.0',
     'not used: no road, friction not readable'),
    ('Tolpekina & Persson, Lubricants 7 (2019) 20; Lorenz et al., J. Chem. Phys. 142 '
     '(2015) 194701; Sun et al., Materials 18 (2025) 3643',
     'in the papers',
     'in the papers',
     "in the papers' figures",
     'CC BY 4.0 / AIP / CC BY 4.0',
     'not used: their tables and figures could not be read here (only abstracts)'),
)


def _datasets_table() -> str:
    rows = [DATASET_COLUMNS, tuple("---" for _ in DATASET_COLUMNS), *DATASETS]
    return "\n".join("| " + " | ".join(r) + " |" for r in rows).format(
        repo=NEXEN_REPO, commit_short=NEXEN_COMMIT[:8]) + "\n"


def render(synth: CaseResult, readme: dict[str, Any], nexen: list[CaseResult] | None,
           nexen_note: str, seconds: float) -> str:
    """docs/validation.md."""
    from tirefric import __version__

    L = ["# Validation: predicted against measured friction", "",
         "<!-- generated by benchmarks/validation.py; do not edit by hand -->", "",
         f"Generated by `python benchmarks/validation.py{' --nexen DIR' if nexen else ''}` "
         f"(tirefric {__version__}, {seconds:.0f} s on one core). Equation numbers are the "
         "review's (Persson & Xu, *Rubber Friction: Theory, Mechanisms, and Challenges*). "
         "The error measure is the RMS of log10 mu_model - log10 mu_measured "
         "(docs/calibration.md: 0.05 is a 12 % typical miss); \"before calibration\" is the "
         "model with the review's adhesive law and q1 by the rms-slope rule, \"after\" the "
         "fit of lookup.calibration (`tirefric fit`). Held-out points never enter a fit: "
         "they are predicted with the fitted values.", ""]
    L += ["## Headline", ""]
    L += ["| data | fitted points: before -> after | held out (what) | held-out: before -> "
          "after | target <= 0.05 on the fitted points |", "|---|---|---|---|---|"]
    if nexen:
        for cr in nexen:
            held = ", ".join(cr.result.spec.held_out.compounds)
            L.append(f"| measured, {cr.case.key} | {_f(cr.rms('fit', True))} -> "
                     f"{_f(cr.rms('fit'))} | {held} | {_f(cr.rms('held_out', True))} -> "
                     f"{_f(cr.rms('held_out'))} | "
                     f"{'met' if (cr.rms('fit') or 1) <= 0.05 else 'not met'} |")
    else:
        L.append("| measured (private part) | not run: " + nexen_note + " | | | |")
    L.append(f"| synthetic recovery | {_f(synth.rms('fit', True))} -> {_f(synth.rms('fit'))} "
             f"| {', '.join(synth.result.spec.held_out.compounds)} and "
             f"{', '.join(f'{t - 273.15:g} C' for t in synth.result.spec.held_out.temperatures)}"
             f" | {_f(synth.rms('held_out', True))} -> {_f(synth.rms('held_out'))} | "
             f"{'met' if (synth.rms('fit') or 1) <= 0.05 else 'not met'} |")
    if nexen:
        orders = [(g, cr.order(g)["rank"]) for cr in nexen[:2]
                  for g in (cr.case.groups or [[c.name for c in cr.result.spec.compounds]])]
        right = [" > ".join(r["measured"]) for _, r in orders if r["after"] == r["measured"]]
        wrong = [f"{' > '.join(r['measured'])} measured, {' > '.join(r['after'])} predicted"
                 for _, r in orders if r["after"] != r["measured"]]
        L += ["", "Reading: calibration brings the fitted points to the target in each series "
              "fitted on its own, and the held-out compound closer than before, but not to "
              "the target; one law for both series does not fit. The compounds' order, "
              "predicted from their master curves with a shared adhesive law, is "
              + (f"right in {', '.join(right)}" if right else "right in no series")
              + (f" and wrong in {'; '.join(wrong)}" if wrong else "")
              + ": what separates these compounds is not in their master curves as the "
              "model reads them (the adhesive law would have to be fitted per compound, "
              "which fits the order instead of predicting it)."]
    L += ["", "## Which data qualify", "",
          "A validation needs, for the same compounds, the master curve with its shift "
          "factors, the road's roughness spectrum and measured friction. Searched: public "
          "repositories and stored web pages (research notes of the project, two rounds, "
          "~225 look-ups).", "",
          _datasets_table(),
          "Only the first is measured friction, and it has no licence: its files are not in "
          "this repository and no number of it is written here; this page reports only what "
          "this script computes from it (RMS errors, orders, the ratio of mean model to mean "
          "measured friction, fitted parameters). **A reader cannot rerun the measured part "
          f"without obtaining the data**: a checkout of {NEXEN_REPO} at {NEXEN_COMMIT}, "
          "passed as `--nexen DIR`. No shippable data set with all three parts was found, so "
          "what a clean checkout reruns is synthetic: it checks the fit and the report, not "
          "the physics.", ""]
    L += ["## The measured data set", ""]
    if nexen:
        L += [
            "Seven tread compounds of what the files call a silica series (S100, S120, S140) "
            "and a resin series (R00-R60) from a tire maker's Persson-theory tool (branded "
            "NEXEN; the data look like a thesis's measurements). Their master curves and a_T "
            "tables are read by `lookup.compound` as the files are (the master curves in "
            "their own layout; the a_T tables, strain sweeps, spectrum and friction tables "
            "with a header the loaders read, their rows unchanged; "
            "`prepare_nexen` says why each). The files do not state the friction tester, "
            "the temperature, the load or the road of the friction measurements. Assumed, "
            "and so a part of every result below:", "",
            f"- temperature {NEXEN_T} and nominal pressure {NEXEN_P}: the values the tool "
            "stores with its calculations;",
            "- the road: the IDIADA spectrum shipped with the data, for both series (the "
            "tool uses it for both; the S series' folder names IDIADA), cut below "
            "q0 = 200 1/m as the shipped asphalt (a judgment: the tester's block size is not "
            "given);",
            "- branch: **hot** (flash temperature fully developed): a tester sliding "
            "centimetres to metres, far beyond s0 = 0.2 D = 0.2 mm (docs/calibration.md). "
            "At the S series' highest speeds the model's flash temperature is tens of K or more;",
            "- strain softening: the measured strain sweeps at 10 % strain (S series; "
            "review sec. 2: 0.1-0.5 matter); the R series has no sweep in the data and gets "
            "the shipped typical filled-tread table at strain 0.1;",
            "- rubber thermal data: the review's (sec. 5.1, after eq. 23); road: the shipped "
            "asphalt's; D = 1 mm (review sec. 5.1).", "",
            "Held out of every fit: **S120 and R40**. S120 is the silica compound whose "
            "speeds extend below the others'; R40 the second resin compound.", ""]
        for cr in nexen:
            L += _case_section(cr, private=True)
    else:
        L += [f"Not run: {nexen_note}.", ""]
    L += ["## What the theory leaves open, and how it was set", "",
          "- **q1**, the short-wavelength cut-off (review sec. 5.1, \"Open problems\"): "
          "before calibration the rms-slope rule xi(q1) = 1 (sec. 5.1); after, the rule's "
          "constant xi1 fitted where listed (q1 then follows from the spectrum), else the "
          "rule as before.",
          "- **The adhesive law** sigma_f(v) of eq. (21), shifted with the bulk a_T (text "
          "after eq. 21): before calibration the review's values (sec. 5.1: c ~ 0.17, "
          "sigma_f0 ~ 4-8 MPa, taken as 6 MPa, v* ~ 1 cm/s at 20 C); after, sigma_f0, c "
          "and v* fitted, shared by the compounds of a fit (so the compounds' order is the "
          "master curves' prediction, not fitted).",
          "- **D** (flash temperature, s0 = 0.2 D): 1 mm (review sec. 5.1), not fitted: the "
          "friction data cannot separate it from the law (docs/calibration.md).",
          "- **The adhesive share** sigma_f A/A0 / sigma0 over mu is in each compound table "
          "(eq. 12); the rest is mu_visc (eqs. 17, 19).", ""]
    L += ["## Synthetic recovery check (shippable)", ""]
    L += _case_section(synth, private=False)
    rec = recovery(synth)
    L += ["| parameter | true | fitted | miss / std. uncertainty |", "|---|---|---|---|"]
    for row in rec:
        L.append(f"| {row['parameter']} | {row['true']:.4g} | {row['fitted']:.4g} | "
                 f"{row['miss_in_std']:+.2f} |")
    L += ["", "The data are the model's own output rounded to three digits: the fit must "
          "find the true values within a few standard uncertainties and predict the held-out "
          "points to the rounding. It shows that the fit and the held-out bookkeeping work, "
          "not that the physics is right.", ""]
    L += ["## The README's `tirefric fit` example", "",
          "Its table is synthetic: the README says it was computed by tirefric with "
          "sigma_f0 = 6 MPa, v* = 3 cm/s, an activation energy of 0.8 eV and q1 = 1e4 1/m, "
          "rounded to three digits. Recomputed with those values on the example compound as "
          f"it now reads: RMS log10 error {readme['rms_at_stated_parameters']:.3f} over its "
          f"{readme['n']} points (largest {readme['max_at_stated_parameters']:.3f}), where "
          "the rounding alone gives < 0.002.", ""]
    L += ["| parameter | stated | fitted (README's spec) |", "|---|---|---|"]
    for lb, (x, s, t, u) in readme["fitted"].items():
        L.append(f"| {lb} | {t:.4g} {u} | {x:.4g} +- {s:.2g} {u} |")
    consistent = readme["rms_at_stated_parameters"] < 0.002
    L += ["", ("The table is what the stated parameters give: the example is a recovery "
               "check." if consistent else
               "**The table no longer follows from the stated parameters**: it was "
               "computed on the example compound of the branch that added the calibration; "
               "the example compound read from measured-layout tables came from a parallel "
               "branch (commit 3b2fe0a), and the merge kept the table. The fit therefore "
               "does not recover the stated values; the example shows how the command "
               "works, and is neither a recovery check nor a validation."), ""]
    return "\n".join(L) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nexen", type=Path, help="the private data set (module docstring)")
    ap.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "validation.md")
    ap.add_argument("--work", type=Path, help="keep the generated model and spec files here")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        work = a.work or Path(tmp)
        synth = run_case(synthetic_case())
        print(f"synthetic: RMS log10 fitted {synth.rms('fit'):.4f}, held out "
              f"{synth.rms('held_out'):.4f}")
        readme = readme_example(work / "readme")
        print(f"README example at its stated parameters: RMS log10 "
              f"{readme['rms_at_stated_parameters']:.4f}")
        nexen = None
        note = "no `--nexen DIR` given (the data are not in this repository)"
        if a.nexen is not None:
            try:
                cases = nexen_cases(a.nexen, work / "nexen")
            except FileNotFoundError as exc:
                print(f"validation: --nexen {a.nexen}: {exc}", file=sys.stderr)
                return 2
            nexen = []
            for c in cases:
                cr = run_case(c)
                nexen.append(cr)
                print(f"{c.key}: RMS log10 fitted {_f(cr.rms('fit', True))} -> "
                      f"{_f(cr.rms('fit'))}, held out {_f(cr.rms('held_out', True))} -> "
                      f"{_f(cr.rms('held_out'))} ({cr.seconds:.1f} s)")
        else:
            print(f"note: measured part skipped: {note}")
        text = render(synth, readme, nexen, note, time.perf_counter() - t0)
    a.output.write_text(text)
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
