"""Files of a calibration: the fit spec (TOML), the measured tables (CSV), the report (text,
JSON, CSV) and the calibrated compound and surface files with their provenance.

Fit spec layout (quantities SI or ``"<number> <unit>"``; files relative to the spec's folder,
or shipped names)::

    name = "my_fit"
    surface = "my_road.toml"        # the road all tables were measured on
    branch = "hot"                  # "cold" | "hot" | "blend" (eq. 28 at slip_distance)
    # slip_distance = "2 mm"        # blend only

    [[compound]]
    file = "my_compound.toml"       # a compound file (adhesion model = "eq21") or shipped name
    name = "A"                      # optional: the label in the outputs (default: its name)
    [[compound.table]]
    file = "mu_A.csv"               # columns v, mu; optional T, p, weight or u_mu
    temperature = "20 degC"         # when the table has no T column
    pressure = "0.3 MPa"            # when the table has no p column
    weight = 1.0                    # optional: multiplies the weight of every point

    [[parameter]]                   # one per fitted parameter (lookup.calibration.KINDS)
    name = "sigma_f0"               # sigma_f0, c, v_star, activation_energy, q1, xi1, D
    min = "1 MPa"
    max = "30 MPa"
    start = "5 MPa"                 # optional: default from the model files
    per_compound = true             # optional (adhesive parameters): one value per compound

    [adhesion]                      # optional: the adhesive law's temperature shift
    shift = "arrhenius"             # "file" (default), "bulk" or "arrhenius" (eq. 22)
    activation_energy = "1 eV"      # for compounds whose file has none

    [held_out]                      # optional: the honest test
    compounds = ["B"]
    temperatures = ["40 degC"]
    per_compound = "mean"           # or "file": a held-out compound's per-compound values

    [engine]                        # optional: lookup.friction.EngineSettings fields
    [solver]                        # optional: lookup.calibration.SolverSettings fields

Measured table (CSV, ``name [unit]`` headers, :func:`tirefric.config.read_csv_table`):
``v [m/s]`` and ``mu [1]``, optionally ``T [degC]`` and ``p [MPa]`` (otherwise the table's
``temperature`` and ``pressure`` in the spec), and either ``weight [1]`` (the weight of the
point's squared log10 residual) or ``u_mu [1]`` (the standard uncertainty of mu, turned into
the weight (mu ln 10 / u_mu)^2).
"""

from __future__ import annotations

import csv
import json
import os
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from tirefric import __version__
from tirefric.config import Table, csv_column_names, read_csv_table
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file
from tirefric.toml_writer import dumps

from .calibration import (
    KINDS,
    Branch,
    CalibrationResult,
    CompoundData,
    FitSpec,
    HeldOut,
    MeasuredTable,
    ParameterSpec,
    SolverSettings,
    file_sha256,
)
from .compound import load_compound
from .friction import EngineSettings
from .surface import load_surface


# -- reading ----------------------------------------------------------------------------------
def read_measured_table(path: str | Path, temperature: float | None = None,
                        pressure: float | None = None, weight: float = 1.0,
                        spec_source: str | Path | None = None,
                        spec_field: str = "table") -> MeasuredTable:
    """Read a measured friction table (module docstring).

    Parameters
    ----------
    path
        CSV file.
    temperature, pressure
        [K], [Pa] for every row when the file has no ``T`` / ``p`` column.
    weight
        Multiplies every point's weight.
    spec_source, spec_field
        Where ``temperature`` / ``pressure`` came from (named in errors).
    """
    path = Path(path)
    present = csv_column_names(path)
    cols = {"v": "velocity", "mu": "dimensionless"}
    for nm, dim in (("T", "temperature"), ("p", "pressure"), ("weight", "dimensionless"),
                    ("u_mu", "dimensionless")):
        if nm in present:
            cols[nm] = dim
    if "weight" in cols and "u_mu" in cols:
        raise InputError("give either 'weight' or 'u_mu' (standard uncertainty of mu), not "
                         "both", source=path, field="u_mu")
    data = read_csv_table(path, cols)
    n = data["v"].size
    out: dict[str, np.ndarray] = {"v": data["v"], "mu": data["mu"]}
    for nm, given, what in (("T", temperature, "temperature"), ("p", pressure, "pressure")):
        if nm in data and given is not None:
            raise InputError(f"the table has a '{nm}' column and the spec gives a {what}: "
                             "give it once", source=spec_source, field=f"{spec_field}.{what}",
                             value=given)
        if nm not in data and given is None:
            raise InputError(f"the table has no '{nm}' column: give the {what} of its points "
                             f"in the spec ({spec_field}.{what}), or add a column "
                             f"'{nm} [{'degC' if nm == 'T' else 'MPa'}]' (columns found: "
                             f"{present})", source=path, field=nm)
        out[nm] = data[nm] if nm in data else np.full(n, float(given))  # type: ignore[arg-type]
    if not (np.isfinite(weight) and weight > 0):
        raise InputError("must be > 0", source=spec_source, field=f"{spec_field}.weight",
                         value=weight)
    w = np.full(n, float(weight))
    if "weight" in data:
        w = w * data["weight"]
    if "u_mu" in data:
        u = data["u_mu"]
        if (u <= 0).any():
            i = int(np.flatnonzero(u <= 0)[0])
            raise InputError(f"row {i + 1}: an uncertainty must be > 0", source=path,
                             field="u_mu", value=float(u[i]))
        w = w * (out["mu"] * np.log(10) / u) ** 2
    return MeasuredTable(str(path), out["v"], out["T"], out["p"], out["mu"], w,
                         file_sha256(path))


def _resolve(t: Table, key: str, kind: str) -> Path:
    """A model file named by ``key``: relative to the spec's folder, or a shipped name."""
    value = t.string(key)
    p = Path(value)
    local = p if p.is_absolute() else t.source.parent / p
    if local.is_file():
        return local
    try:
        return resolve_model_file(value, kind)
    except InputError:
        raise t.error(key, f"file not found (tried {local.resolve()}) and not a shipped "
                      f"{kind[:-1]} name", value) from None


def _data_file(t: Table, key: str) -> Path:
    """A data file named by ``key``, relative to the spec's folder; the error names the path
    tried."""
    value = t.string(key)
    p = Path(value)
    p = p if p.is_absolute() else t.source.parent / p
    if not p.is_file():
        raise t.error(key, f"file not found (tried {p.resolve()})", value)
    return p


def _sub_tables(t: Table, key: str) -> list[Table]:
    raw = t.raw(key, [])
    if isinstance(raw, dict):
        raw = [raw]
    if not isinstance(raw, list) or not all(isinstance(x, dict) for x in raw):
        raise t.error(key, f"expected [[{t.name(key)}]] tables", raw)
    return [Table(x, t.source, f"{t.name(key)}[{i}]") for i, x in enumerate(raw)]


def _settings(t: Table | None, cls: type, dims: dict[str, str]) -> Any:
    if t is None:
        return cls()
    kw: dict[str, Any] = {}
    for f in fields(cls):
        if not t.has(f.name):
            continue
        default = f.default
        if f.name in dims:
            kw[f.name] = t.quantity(f.name, dims[f.name])
        elif isinstance(default, bool):
            kw[f.name] = t.boolean(f.name)
        elif isinstance(default, int):
            kw[f.name] = t.integer(f.name)
        elif isinstance(default, str):
            kw[f.name] = t.string(f.name)
        else:
            kw[f.name] = t.quantity(f.name, "dimensionless")
    t.check_unknown()
    try:
        return cls(**kw)
    except InputError as exc:
        raise InputError(exc.message, source=t.source, field=exc.field, value=exc.value) \
            from None


def load_fit_spec(path: str | Path) -> FitSpec:
    """Load a fit spec (module docstring); every bad field is an :class:`InputError` naming
    the spec (or data) file, the field and the value."""
    path = Path(path)
    t = Table.load(path)
    name = t.string("name", default=path.stem)
    surface = load_surface(_resolve(t, "surface", "surfaces"))
    kind = t.string("branch", choices=("cold", "hot", "blend"))
    slip = t.quantity("slip_distance", "length", positive=True) if t.has("slip_distance") \
        else None
    try:
        branch = Branch(kind, slip)
    except InputError as exc:
        raise InputError(exc.message, source=path, field=exc.field, value=exc.value) from None
    compounds = []
    ctabs = _sub_tables(t, "compound")
    if not ctabs:
        raise t.error("compound", "required: at least one [[compound]] with its measured "
                      "tables")
    for ct in ctabs:
        comp = load_compound(_resolve(ct, "file", "compounds"))
        cname = ct.string("name", default=comp.name)
        tables = []
        ttabs = _sub_tables(ct, "table")
        if not ttabs:
            raise ct.error("table", "required: at least one [[compound.table]] of measured "
                           "friction")
        for tt in ttabs:
            tables.append(read_measured_table(
                _data_file(tt, "file"),
                tt.quantity("temperature", "temperature", positive=True)
                if tt.has("temperature") else None,
                tt.quantity("pressure", "pressure", positive=True)
                if tt.has("pressure") else None,
                tt.quantity("weight", "dimensionless", 1.0, positive=True),
                spec_source=path, spec_field=tt.prefix))
            tt.check_unknown()
        ct.check_unknown()
        compounds.append(CompoundData(cname, comp, tuple(tables)))
    params = []
    for pt in _sub_tables(t, "parameter"):
        pname = pt.string("name", choices=tuple(KINDS))
        k = KINDS[pname]
        try:
            params.append(ParameterSpec(
                pname, pt.quantity("min", k.dimension, positive=True),
                pt.quantity("max", k.dimension, positive=True),
                pt.quantity("start", k.dimension, positive=True) if pt.has("start") else None,
                pt.boolean("per_compound", False)))
        except InputError as exc:
            raise InputError(exc.message, source=path, field=f"{pt.prefix}.{exc.field.rsplit('.', 1)[-1]}"  # noqa: E501
                             if exc.field else pt.prefix, value=exc.value) from None
        pt.check_unknown()
    at = t.table("adhesion", required=False)
    shift, ea = "file", None
    if at is not None:
        shift = at.string("shift", "file", choices=("file", "bulk", "arrhenius"))
        if at.has("activation_energy"):
            ea = at.quantity("activation_energy", "energy", positive=True)
        at.check_unknown()
    ht = t.table("held_out", required=False)
    held = HeldOut()
    if ht is not None:
        comps = ht.raw("compounds", [])
        if not isinstance(comps, list) or not all(isinstance(c, str) for c in comps):
            raise ht.error("compounds", "expected a list of compound names", comps)
        temps = ht.raw("temperatures", [])
        if not isinstance(temps, list):
            raise ht.error("temperatures", "expected a list of temperatures", temps)
        from tirefric.units import parse_quantity

        Ts = [parse_quantity(x, "temperature",
                             lambda msg, x=x: ht.error("temperatures", msg, x)) for x in temps]
        held = HeldOut(tuple(comps), tuple(Ts),
                       ht.string("per_compound", "mean", choices=("mean", "file")))
        ht.check_unknown()
    settings = _settings(t.table("engine", required=False), EngineSettings,
                         {"hot_tol": "temperature_difference"})
    solver = _settings(t.table("solver", required=False), SolverSettings,
                       {"hot_tol": "temperature_difference"})
    t.check_unknown()
    return FitSpec(name, surface, tuple(compounds), tuple(params), branch, held, shift, ea,
                   settings, solver, str(path))


# -- reports ----------------------------------------------------------------------------------
def report(result: CalibrationResult) -> str:
    """The result as text: parameters, correlations, RMS errors, per compound, per point."""
    s = result.spec
    m = result.model
    lines = []
    mode = "fit" if result.mode == "fit" else "prediction (no fitting)"
    lines.append(f"# tirefric fit {__version__}: {mode} of spec '{s.name}'"
                 + (f" ({s.source})" if s.source else ""))
    br = s.branch.kind + (f" (eq. 28 at slip distance {s.branch.slip_distance:g} m)"
                          if s.branch.kind == "blend" else "")
    lines.append(f"# road '{s.surface.name}', branch {br}, {len(s.compounds)} compound(s), "
                 f"{int(m.fitted.sum())} fitted and {int(m.held_out.sum())} held-out points")
    q1 = m.road(m.values(result.u)[1])[0]
    lines.append(f"# residual sqrt(w) (log10 mu_model - log10 mu_measured); q1 = {q1:.5g} 1/m")
    if result.mode == "fit":
        sv = result.solver
        lines.append(f"# least_squares: {sv['message']} ({sv['nfev']} steps, "
                     f"{sv['model_evaluations']} model evaluations, "
                     f"{sv['seconds_total']:.2f} s, {1e3 * sv['seconds_per_evaluation']:.1f} "
                     "ms per evaluation)")
        lines.append(f"# covariance s^2 (J^T J)^-1 at the optimum (central differences): "
                     f"s^2 = {result.s2:.4g}, dof = {result.dof}, condition number "
                     f"{result.condition_number:.3g}")
    lines.append("")
    lines.append("parameters (std: standard uncertainty; for a log10-fitted one also the "
                 "1-sigma factor)")
    lines.append(f"  {'parameter':24s} {'value':>14s} {'std':>12s} {'factor':>8s} "
                 f"{'start':>12s} {'min':>10s} {'max':>10s} unit")
    for p in result.parameters:
        fac = f"{10 ** p.std_internal:.4f}" if p.log and np.isfinite(p.std_internal) else "-"
        std = f"{p.std / p.scale:.4g}" if np.isfinite(p.std) else "-"
        lines.append(f"  {p.label:24s} {p.value / p.scale:14.6g} {std:>12s} {fac:>8s} "
                     f"{p.start / p.scale:12.5g} {p.lower / p.scale:10.4g} "
                     f"{p.upper / p.scale:10.4g} {p.unit}"
                     + (f"  (at {p.at_bound} bound)" if p.at_bound else ""))
    if result.held_out_values:
        lines.append("")
        lines.append(f"held-out compounds' per-compound parameters ({s.held_out.per_compound}"
                     " of the fitted compounds)" if s.held_out.per_compound == "mean" else
                     "held-out compounds' per-compound parameters (their files)")
        for c, vals in result.held_out_values.items():
            txt = ", ".join(f"{k} = {v / KINDS[k].scale:.5g} {KINDS[k].unit}"
                            for k, v in vals.items())
            lines.append(f"  {c}: {txt}")
    if result.free_labels:
        lines.append("")
        lines.append("correlation")
        lab = result.free_labels
        w = max(len(x) for x in lab)
        lines.append(" " * (w + 3) + " ".join(f"{x[:9]:>9s}" for x in lab))
        for i, x in enumerate(lab):
            lines.append(f"  {x:{w}s} " + " ".join(f"{c:9.3f}" for c in result.correlation[i]))
    lines.append("")

    def f(x: float | None) -> str:
        return "-" if x is None else f"{x:.4f}"

    lines.append("RMS log10 error   fitted points   held-out points")
    if result.mode == "fit":
        lines.append(f"  start           {f(result.rms_log10('fit', True)):>13s}   "
                     f"{f(result.rms_log10('held_out', True)):>15s}")
        lines.append(f"  fitted          {f(result.rms_log10('fit')):>13s}   "
                     f"{f(result.rms_log10('held_out')):>15s}")
    else:
        lines.append(f"  model           {f(result.rms_log10('fit')):>13s}   "
                     f"{f(result.rms_log10('held_out')):>15s}")
    lines.append("")
    lines.append("per compound")
    lines.append(f"  {'compound':16s} {'n_fit':>5s} {'n_held':>6s} {'rms_fit':>8s} "
                 f"{'rms_held':>8s} {'rms_start':>9s} {'mu_meas':>8s} {'mu_model':>8s}")
    for c in result.compound_summary():
        lines.append(f"  {c['compound']:16s} {c['n_fit']:5d} {c['n_held_out']:6d} "
                     f"{f(c['rms_log10_fit']):>8s} {f(c['rms_log10_held_out']):>8s} "
                     f"{f(c['rms_log10_start']):>9s} {c['mean_mu_measured']:8.4f} "
                     f"{c['mean_mu_predicted']:8.4f}")
    lines.append("")
    lines.append("points")
    lines.append(f"  {'compound':12s} {'v [m/s]':>10s} {'T [C]':>7s} {'p [MPa]':>8s} "
                 f"{'mu_meas':>8s} {'mu_model':>8s} {'resid':>8s} {'mu_visc':>8s} "
                 f"{'mu_cont':>8s} {'dT [K]':>7s} set")
    for r in result.points():
        lines.append(f"  {r['compound'][:12]:12s} {r['v']:10.4g} {r['T_C']:7.2f} "
                     f"{r['p'] / 1e6:8.4g} {r['mu_measured']:8.4f} {r['mu_predicted']:8.4f} "
                     f"{r['residual_log10']:+8.4f} {r['mu_visc']:8.4f} {r['mu_cont']:8.4f} "
                     f"{r['dT_flash']:7.2f} {r['set']}")
    if result.warnings:
        lines.append("")
        lines.extend(f"warning: {w}" for w in result.warnings)
    return "\n".join(lines) + "\n"


POINT_COLUMNS = (("compound", ""), ("table", ""), ("v", "m/s"), ("T_C", "degC"), ("p", "Pa"),
                 ("mu_measured", "1"), ("mu_predicted", "1"), ("residual_log10", "1"),
                 ("weight", "1"), ("set", ""), ("mu_start", "1"), ("mu_visc", "1"),
                 ("mu_cont", "1"), ("area", "1"), ("dT_flash", "K"))


def write_points_csv(result: CalibrationResult, path: str | Path) -> Path:
    """The per-point table as CSV (``name [unit]`` headers)."""
    path = Path(path)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([(k.removesuffix("_C") if k == "T_C" else k) + (f" [{u}]" if u else "")
                    for k, u in POINT_COLUMNS])
        for r in result.points():
            w.writerow([r[k] if isinstance(r[k], str) else repr(float(r[k]))
                        for k, _ in POINT_COLUMNS])
    return path


def write_outputs(result: CalibrationResult, outdir: str | Path) -> dict[str, Path]:
    """``fit.txt``/``fit.json`` (or ``predict.*``) and ``points.csv`` in ``outdir``."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    stem = result.mode
    txt = out / f"{stem}.txt"
    txt.write_text(report(result))
    js = out / f"{stem}.json"
    js.write_text(json.dumps(result.to_dict(), indent=2, allow_nan=False) + "\n")
    return {"report": txt, "json": js, "points": write_points_csv(result, out / "points.csv")}


# -- calibrated model files -------------------------------------------------------------------
def _relocate(data: Any, src_dir: Path, dst_dir: Path) -> Any:
    """Copy of a parsed TOML dict whose ``file`` entries point to the same files from
    ``dst_dir`` (relative where possible)."""
    if isinstance(data, dict):
        out = {}
        for k, v in data.items():
            if k == "file" and isinstance(v, str):
                p = Path(v)
                p = p if p.is_absolute() else (src_dir / p).resolve()
                try:
                    v = os.path.relpath(p, dst_dir.resolve())
                except ValueError:  # another drive (Windows)
                    v = str(p)
            out[k] = _relocate(v, src_dir, dst_dir)
        return out
    if isinstance(data, list):
        return [_relocate(x, src_dir, dst_dir) for x in data]
    return data


def _load_toml(path: str) -> dict[str, Any]:
    import tomllib

    if not path or not Path(path).is_file():
        raise InputError("the model has no source file to write a calibrated copy from",
                         source=path or None)
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def provenance_block(result: CalibrationResult, target: str | None) -> str:
    """What was fitted, from which data (hashes), with which error; ``target`` is the
    compound's name (None: the road)."""
    s = result.spec
    lines = [f"Calibrated with tirefric {__version__} (tirefric fit, lookup.calibration) "
             f"from spec '{s.name}'" + (f" ({Path(s.source).name}, "
                                        f"{file_sha256(s.source)})" if s.source and
                                        Path(s.source).is_file() else "") + ".",
             f"Branch {s.branch.kind}"
             + (f" (eq. 28 at slip distance {s.branch.slip_distance:g} m)"
                if s.branch.kind == "blend" else "")
             + "; residuals sqrt(w) (log10 mu_model - log10 mu_measured); "
             "scipy least_squares (trf); standard uncertainties from s^2 (J^T J)^-1.",
             "Fitted for this file (value +- standard uncertainty, bounds, start):"]

    def mine(p) -> bool:
        if target is None:
            return p.compound is None and KINDS[p.name].target == "surface"
        return p.compound == target or (p.compound is None
                                        and KINDS[p.name].target == "adhesion")

    for p in result.parameters:
        if not mine(p):
            continue
        std = f" +- {p.std / p.scale:.3g}" if np.isfinite(p.std) else ""
        shared = " (shared by all compounds)" if p.compound is None and \
            KINDS[p.name].target == "adhesion" else ""
        lines.append(f"  {p.label} = {p.value / p.scale:.6g}{std} {p.unit}{shared} "
                     f"(bounds {p.lower / p.scale:.4g} .. {p.upper / p.scale:.4g}, start "
                     f"{p.start / p.scale:.4g}){' at its ' + p.at_bound + ' bound' if p.at_bound else ''}")  # noqa: E501
    if not any(mine(p) for p in result.parameters) and target not in result.held_out_values:
        lines.append("  nothing: the values are those of the original file")
    if target in result.held_out_values:
        vals = ", ".join(f"{k} = {v / KINDS[k].scale:.5g} {KINDS[k].unit}"
                         for k, v in result.held_out_values[target].items())
        lines.append(f"  not fitted (held out): {vals} ("
                     + ("mean of the fitted compounds" if s.held_out.per_compound == "mean"
                        else "its file's values") + ")")
    others = [f"{p.label} = {p.value / p.scale:.4g} {p.unit}" for p in result.parameters
              if not mine(p)]
    if others:
        lines.append(f"Fitted together with: {', '.join(others)}.")
    lines.append("Data (measured friction tables):")
    for c in s.compounds:
        for t in c.tables:
            lines.append(f"  {c.name}: {Path(t.source).name} ({t.n} points, {t.sha256})")
    f, h = result.rms_log10("fit"), result.rms_log10("held_out")
    f0, h0 = result.rms_log10("fit", True), result.rms_log10("held_out", True)
    lines.append(f"RMS log10 error: fitted points {f:.4f} (start {f0:.4f})"
                 + (f", held-out points {h:.4f} (start {h0:.4f}; held out: "
                    f"compounds {list(s.held_out.compounds)}, temperatures "
                    f"{[round(t - 273.15, 2) for t in s.held_out.temperatures]} degC)"
                    if h is not None else ", no held-out points") + ".")
    return "\n".join(lines)


def write_models(result: CalibrationResult, outdir: str | Path) -> dict[str, Path]:
    """The calibrated compound files (one per compound) and surface file in ``outdir``,
    loadable by :func:`lookup.compound.load_compound` and :func:`lookup.surface.load_surface`.

    Each is its original file with the fitted values (SI numbers) and a provenance that
    says what was fitted, from which data files (SHA-256), with which bounds and error; the
    original provenance follows as "Before calibration". Data files the originals name are
    referred to from ``outdir``. A file none of whose values was fitted (the compounds when
    only the road was fitted, the road when only the adhesive law was) is not written.
    """
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    s = result.spec
    written: dict[str, Path] = {}
    values = result.compound_values()
    kinds = {KINDS[p.name].target for p in s.parameters}
    for i, c in enumerate(s.compounds):
        if "adhesion" not in kinds and s.adhesion_shift == "file":
            break
        src = c.compound.source
        data = _relocate(_load_toml(src), Path(src).parent, out)
        law = result.model.law(i, values[c.name])
        adh = dict(data.get("adhesion", {}))
        adh.update({"model": "eq21", "sigma_f0": law.sigma_f0, "c": law.c,
                    "v_star": law.v_star, "T_ref": law.T_ref})
        if result.model.shift_kind[i] == "arrhenius":
            adh["shift"] = "arrhenius"
            adh["activation_energy"] = law.shift.activation_energy  # type: ignore[union-attr]
        else:
            adh["shift"] = "bulk"
            adh.pop("activation_energy", None)
        data["adhesion"] = adh
        data["provenance"] = (provenance_block(result, c.name) + "\n\nBefore calibration: "
                              + str(data.get("provenance", "")).strip() + "\n")
        path = out / f"{c.name}.toml"
        path.write_text(dumps(data, header=f"{c.name}: calibrated copy of {src}\n"
                              "written by tirefric fit; see provenance"))
        written[c.name] = path
    if "surface" not in kinds:
        return written
    ssrc = s.surface.source
    data = _relocate(_load_toml(ssrc), Path(ssrc).parent, out)
    fs = result.fitted_surface()
    road = result.model.values(result.u)[1]
    if "q1" in road or "xi1" in road:
        data["cutoff"] = ({"rule": "fixed", "q1": fs.cutoff.q1} if fs.cutoff.rule == "fixed"
                          else {"rule": "rms_slope", "xi1": fs.cutoff.xi1})
    if "D" in road:
        data["macroasperity"] = {**data.get("macroasperity", {}), "D": fs.D}
    data["provenance"] = (provenance_block(result, None) + "\n\nBefore calibration: "
                          + str(data.get("provenance", "")).strip() + "\n")
    name = str(data.get("name", Path(ssrc).stem))
    path = out / f"{name}.toml"
    if path.stem in written:
        path = out / f"{name}_surface.toml"
    path.write_text(dumps(data, header=f"{name}: calibrated copy of {ssrc}\n"
                          "written by tirefric fit; see provenance"))
    written["surface"] = path
    return written
