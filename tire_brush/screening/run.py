"""Running a screen: the tasks, the store, the results table, the plots and the report.

One task per compound (:func:`tire_brush.screening.evaluate.run_task`) and one for the
reference tire, run by the grid build's task runner (:func:`lookup.grid.build.run_tasks`: this
process, local processes, or a Dask scheduler). A task receives the compound's description (a
few hundred bytes) and returns its record (a few kB); the settings go to each worker once.
Records are stored as they arrive (:mod:`.store`), so an interruption loses only the
compounds in flight.
"""

from __future__ import annotations

import csv
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .evaluate import OUTPUTS, run_task
from .spec import ScreenSpec, load_screen_spec, screen_settings
from .store import ResultStore, compound_key

#: Outputs the sensitivity analysis and the plots use, with their labels.
LABELS: dict[str, str] = {
    "G": "wet grip index G", "rrc_N_per_kN": "rolling resistance [N/kN]",
    "stop_dry_abs_m": "dry stop, ABS [m]", "stop_wet_abs_m": "wet stop, ABS [m]",
    "stop_dry_locked_m": "dry stop, locked [m]", "stop_wet_locked_m": "wet stop, locked [m]",
}


@dataclass
class ScreenResult:
    """What a screen did and found."""

    spec: ScreenSpec
    out: Path
    records: list[dict[str, Any]]
    reference: dict[str, Any]
    computed: list[str]
    reused: list[str]
    wall_s: float
    workers: int
    """Where the computed tasks ran (:func:`lookup.grid.build.pool_size`): 0 on a Dask
    scheduler, 1 in this process, else the number of local processes."""
    files: dict[str, str] = field(default_factory=dict)

    @property
    def where(self) -> str:
        """:attr:`workers` in words (:func:`lookup.grid.build.pool_label`)."""
        from lookup.grid.build import pool_label

        return pool_label(self.workers)

    @property
    def failed(self) -> list[dict[str, Any]]:
        """Records of the compounds that failed."""
        return [r for r in self.records if r["status"] != "ok"]

    def rows(self) -> list[dict[str, Any]]:
        """The results table (:func:`result_rows`)."""
        return result_rows(self.spec, self.records, self.reference)


def run_screen(spec: ScreenSpec | str | Path, out: str | Path, *, workers: int = 1,
               scheduler: Any = None, progress: bool = True,
               on_record: Callable[[dict[str, Any]], None] | None = None,
               keep_grids: bool = False, write: bool = True) -> ScreenResult:
    """Screen the spec's compounds into ``out`` (module docstring).

    Parameters
    ----------
    spec
        A :class:`ScreenSpec` or its file / shipped name.
    out
        Output folder (created): ``compounds/`` (one record per compound), ``results.csv``,
        ``results.json``, ``results.nc`` (with xarray), ``pareto.png``,
        ``sensitivity.png``, ``report.md``.
    workers
        Local worker processes (1: this process). Ignored with ``scheduler``.
    scheduler
        Address of a Dask distributed scheduler, or a ``distributed.Client``.
    progress
        A progress bar (tqdm, stderr) with the cost per compound.
    on_record
        Called with each record computed in this run, after it is stored (tests, monitors).
    keep_grids
        Keep each compound's file and grids under ``out/work`` (default: removed).
    write
        Write the tables, plots and report.
    """
    from tqdm.auto import tqdm

    from lookup.grid.build import run_tasks

    if not isinstance(spec, ScreenSpec):
        spec = load_screen_spec(spec)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if workers < 1:
        from tirefric.errors import InputError

        raise InputError("must be >= 1", source="--workers", value=workers)
    settings = screen_settings(spec, keep=str(out / "work") if keep_grids else None)
    sdesc = settings.describe()
    store = ResultStore(out)
    # the reference first (every wet grip index needs it), then the compounds in order
    ref_desc = spec.reference()
    ref_key = compound_key(ref_desc, sdesc, "reference")
    jobs = [("reference", ref_desc, ref_key)]
    jobs += [("compound", d, compound_key(d, sdesc)) for d in spec.compounds()]
    done = {key: r for _, _, key in jobs if (r := store.get(key)) is not None}
    pending = [(kind, d, key) for kind, d, key in jobs if key not in done]
    t0 = time.perf_counter()
    # the runner says where it puts the tasks (recorded, and named on the bar)
    runner = run_tasks(run_task, settings, pending, workers=workers, scheduler=scheduler)
    bar = tqdm(total=len(jobs), initial=len(done), unit="compound", disable=not progress,
               desc=f"screen {spec.name} ({runner.where})", dynamic_ncols=True)
    computed: list[str] = []
    cost: list[float] = []
    try:
        for rec in runner:
            store.put(rec)
            done[rec["key"]] = rec
            computed.append(rec["key"])
            cost.append(float(rec["seconds"]["total_s"]))
            bar.update(1)
            bar.set_postfix(s_per_compound=f"{np.median(cost):.1f}",
                            failed=sum(r["status"] != "ok" for r in done.values()),
                            refresh=False)
            if on_record is not None:
                on_record(rec)
    finally:
        bar.close()
        runner.close()
    wall = time.perf_counter() - t0
    records = [done[k] for kind, _, k in jobs if kind == "compound"]
    reference = done[ref_key]
    result = ScreenResult(spec, out, records, reference, computed,
                          [k for _, _, k in jobs if k not in computed], wall,
                          runner.size)
    if write:
        result.files = write_outputs(result)
    return result


# -- the table ---------------------------------------------------------------------------------
def result_rows(spec: ScreenSpec, records: list[dict[str, Any]],
                reference: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per compound: name, status, design parameters, outputs, the wet grip index and
    classes (against the reference tire's record), the Pareto flag, the cost."""
    from tire_brush.rolling_resistance import eu_label_class
    from tire_brush.wet_grip import label_class, wet_grip_index

    params = list(spec.sweep.ranges) if spec.sweep is not None else []
    ref_ok = reference.get("status") == "ok"
    rows = []
    for r in records:
        row: dict[str, Any] = {"name": r["name"], "status": r["status"],
                               "error": r.get("error") or ""}
        p = r["description"].get("params", {})
        for k in params:
            row[k] = float(p.get(k, math.nan))
        o = r.get("outputs") or {}
        for k in OUTPUTS:
            row[k] = float(o.get(k, math.nan))
        for T in spec.peak_T_K:
            k = f"mu_peak_{T - 273.15:g}C"
            row[k] = float(o.get(k, math.nan))
        ok = r["status"] == "ok" and ref_ok
        T_C = reference["outputs"]["T_C"] if ref_ok else math.nan
        G = wet_grip_index(row["bfc_wet"], reference["outputs"]["bfc_wet"], T_C, T_C) \
            if ok else math.nan
        Gt = wet_grip_index(row["peak_wet_trailer"], reference["outputs"]["peak_wet_trailer"],
                            T_C, T_C) if ok else math.nan
        row["G"] = float(G)
        row["wet_class"] = label_class(G) if ok else ""
        row["G_trailer"] = float(Gt)
        row["rr_class"] = eu_label_class(row["rrc_N_per_kN"]) if r["status"] == "ok" else ""
        row["seconds"] = float(r.get("seconds", {}).get("total_s", math.nan))
        rows.append(row)
    flags = pareto_front([row["G"] for row in rows], [row["rrc_N_per_kN"] for row in rows])
    for row, f in zip(rows, flags, strict=True):
        row["pareto"] = bool(f)
    return rows


def pareto_front(grip: list[float], rr: list[float]) -> list[bool]:
    """Pareto-optimal points of (wet grip up, rolling resistance down): no other point has at
    least the grip and at most the resistance, one of them strictly. NaN is never optimal."""
    g = np.asarray(grip, float)
    r = np.asarray(rr, float)
    ok = np.isfinite(g) & np.isfinite(r)
    out = []
    for i in range(g.size):
        if not ok[i]:
            out.append(False)
            continue
        dom = ok & (g >= g[i]) & (r <= r[i]) & ((g > g[i]) | (r < r[i]))
        out.append(not dom.any())
    return out


def sensitivity(rows: list[dict[str, Any]], params: list[str], outputs: list[str]
                ) -> dict[str, dict[str, dict[str, float]]]:
    """Sensitivity of each output to each design parameter over the sweep.

    Two global measures over the sample (Saltelli et al., *Global Sensitivity Analysis. The
    Primer*, Wiley 2008, sec. 1.2.5-1.2.6):

    * ``spearman``: Spearman's rank correlation coefficient of output and parameter (robust to
      a monotone non-linear response; on a Latin hypercube or Sobol sample the parameters are
      nearly uncorrelated, so each coefficient is the parameter's own effect);
    * ``src``: standardised regression coefficients beta_j = b_j s_j / s_y of the least-squares
      fit y = b_0 + sum b_j x_j, with ``r2`` the fit's coefficient of determination (their
      squares add up to R^2 for uncorrelated parameters: the share of the output's variance
      each explains); only when there are more successful points than parameters + 1.

    Returns ``{output: {"spearman": {param: rho}, "src": {param: beta}, "r2": R^2}}``.
    """
    from scipy.stats import spearmanr

    ok = [r for r in rows if r["status"] == "ok"]
    res: dict[str, dict[str, Any]] = {}
    if not params or len(ok) < 3:
        return res
    X = np.array([[r[p] for p in params] for r in ok], float)
    for o in outputs:
        y = np.array([r[o] for r in ok], float)
        good = np.isfinite(y) & np.isfinite(X).all(axis=1)
        entry: dict[str, Any] = {"spearman": {}, "src": {}, "r2": math.nan}
        if good.sum() >= 3:
            for j, p in enumerate(params):
                if np.ptp(X[good, j]) > 0 and np.ptp(y[good]) > 0:
                    entry["spearman"][p] = float(spearmanr(X[good, j], y[good]).statistic)
                else:
                    entry["spearman"][p] = math.nan
        if good.sum() > len(params) + 1 and np.ptp(y[good]) > 0:
            Xg, yg = X[good], y[good]
            A = np.column_stack([np.ones(len(yg)), Xg])
            b, *_ = np.linalg.lstsq(A, yg, rcond=None)
            fit = A @ b
            ss = float(((yg - yg.mean()) ** 2).sum())
            entry["r2"] = 1.0 - float(((yg - fit) ** 2).sum()) / ss
            sx = Xg.std(axis=0, ddof=1)
            sy = yg.std(ddof=1)
            entry["src"] = {p: float(b[j + 1] * sx[j] / sy) for j, p in enumerate(params)}
        res[o] = entry
    return res


# -- writing -----------------------------------------------------------------------------------
def _json_number(x: Any) -> Any:
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def write_outputs(result: ScreenResult) -> dict[str, str]:
    """``results.csv``, ``results.json``, ``results.nc`` (xarray and h5netcdf installed),
    ``pareto.png``, ``sensitivity.png`` and ``report.md`` in the output folder."""
    out = result.out
    rows = result.rows()
    spec = result.spec
    params = list(spec.sweep.ranges) if spec.sweep is not None else []
    keys = list(rows[0]) if rows else ["name"]
    files: dict[str, str] = {}
    with open(out / "results.csv", "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    files["csv"] = str(out / "results.csv")
    outs = [o for o in LABELS if any(math.isfinite(r.get(o, math.nan)) for r in rows)]
    sens = sensitivity(rows, params, outs)
    doc = {"screen": spec.name, "spec": spec.source, "compounds": [
        {k: _json_number(v) for k, v in r.items()} for r in rows],
        "reference": {"compound": spec.reference_compound,
                      **{k: _json_number(v) for k, v in
                         (result.reference.get("outputs") or {}).items()},
                      "status": result.reference["status"],
                      "error": result.reference.get("error")},
        "sensitivity": json.loads(json.dumps(sens, default=_json_number).replace("NaN",
                                                                                  "null")),
        "run": {"wall_s": result.wall_s, "workers": result.workers,
                "computed": len(result.computed), "reused": len(result.reused),
                "cost_per_compound_s_median": cost_per_compound(result)},
        "resolution": spec.resolution}
    (out / "results.json").write_text(json.dumps(doc, indent=1, allow_nan=False),
                                      encoding="utf-8")
    files["json"] = str(out / "results.json")
    nc = write_netcdf(rows, params, out / "results.nc", spec)
    if nc:
        files["netcdf"] = nc
    files["pareto"] = plot_pareto(rows, out / "pareto.png", spec.name)
    if sens:
        files["sensitivity"] = plot_sensitivity(sens, params, out / "sensitivity.png")
    files["report"] = write_report(result, rows, sens, out / "report.md")
    return files


def cost_per_compound(result: ScreenResult) -> float:
    """Median wall time of one compound's task [s] over the records (NaN if none)."""
    s = [r["seconds"]["total_s"] for r in result.records if r.get("seconds")]
    return float(np.median(s)) if s else math.nan


def write_netcdf(rows: list[dict[str, Any]], params: list[str], path: Path,
                 spec: ScreenSpec) -> str | None:
    """The results as an xarray Dataset along ``compound`` with the design parameters as
    coordinates, written with h5netcdf; None when xarray is not installed."""
    try:
        import xarray as xr
    except ImportError:
        return None
    names = [r["name"] for r in rows]
    coords: dict[str, Any] = {"compound": names}
    for p in params:
        coords[p] = ("compound", np.array([r[p] for r in rows], float))
    data = {}
    for k in rows[0] if rows else []:
        if k in ("name", *params):
            continue
        vals = [r[k] for r in rows]
        if all(isinstance(v, float) for v in vals):
            data[k] = ("compound", np.array(vals, float))
        elif all(isinstance(v, bool) for v in vals):
            data[k] = ("compound", np.array(vals, np.int8))
        else:
            data[k] = ("compound", np.array([str(v) for v in vals], dtype=object))
    ds = xr.Dataset(data, coords=coords, attrs={"screen": spec.name, "spec": spec.source,
                                                "reference_compound": spec.reference_compound})
    ds.to_netcdf(path, engine="h5netcdf")
    return str(path)


def plot_pareto(rows: list[dict[str, Any]], path: Path, title: str) -> str:
    """Wet grip index against rolling resistance, coloured by the dry ABS stop, the Pareto
    front marked and joined."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r["status"] == "ok" and math.isfinite(r["G"])]
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    if ok:
        x = np.array([r["rrc_N_per_kN"] for r in ok])
        y = np.array([r["G"] for r in ok])
        c = np.array([r["stop_dry_abs_m"] for r in ok])
        sc = ax.scatter(x, y, c=c, cmap="viridis_r", s=40, zorder=3)
        fig.colorbar(sc, ax=ax, label="dry stop 100 km/h -> 1 m/s, ABS [m]")
        par = sorted((r for r in ok if r["pareto"]), key=lambda r: r["rrc_N_per_kN"])
        ax.plot([r["rrc_N_per_kN"] for r in par], [r["G"] for r in par], "r-", lw=1,
                zorder=2, label="Pareto front")
        ax.scatter([r["rrc_N_per_kN"] for r in par], [r["G"] for r in par], s=120,
                   facecolors="none", edgecolors="r", zorder=4)
        for r in ok:
            ax.annotate(r["name"], (r["rrc_N_per_kN"], r["G"]), fontsize=6,
                        xytext=(3, 3), textcoords="offset points")
        ax.legend(fontsize=8, loc="best")
    ax.set_xlabel("rolling resistance coefficient [N/kN] (ISO 28580)")
    ax.set_ylabel("wet grip index G (UN R117, vehicle method)")
    ax.set_title(f"{title}: wet grip vs rolling resistance")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return str(path)


def plot_sensitivity(sens: dict[str, Any], params: list[str], path: Path) -> str:
    """Spearman rank correlation of each output with each design parameter (heat map)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    outs = list(sens)
    M = np.array([[sens[o]["spearman"].get(p, math.nan) for p in params] for o in outs])
    fig, ax = plt.subplots(figsize=(1.3 * len(params) + 3, 0.5 * len(outs) + 1.8))
    im = ax.imshow(M, cmap="RdBu_r", vmin=-1, vmax=1, aspect="auto")
    ax.set_xticks(range(len(params)), params, rotation=30, ha="right", fontsize=8)
    ax.set_yticks(range(len(outs)), [LABELS.get(o, o) for o in outs], fontsize=8)
    for i in range(M.shape[0]):
        for j in range(M.shape[1]):
            if math.isfinite(M[i, j]):
                ax.text(j, i, f"{M[i, j]:+.2f}", ha="center", va="center", fontsize=7)
    fig.colorbar(im, ax=ax, label="Spearman rank correlation")
    ax.set_title("sensitivity over the sweep")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return str(path)


def _fmt(x: Any, nd: int = 3) -> str:
    if isinstance(x, float):
        return "-" if not math.isfinite(x) else f"{x:.{nd}f}"
    return str(x)


def write_report(result: ScreenResult, rows: list[dict[str, Any]], sens: dict[str, Any],
                 path: Path) -> str:
    """A short markdown report: the ranking, the Pareto set, the failures, the cost."""
    spec = result.spec
    ref = result.reference
    lines = [f"# Compound screen `{spec.name}`", "",
             f"Spec: `{spec.source}`. {len(rows)} compounds, "
             f"{sum(r['status'] == 'ok' for r in rows)} evaluated, "
             f"{sum(r['status'] != 'ok' for r in rows)} failed. Tire `{Path(spec.tire).stem}`; "
             f"stops {spec.v0 * 3.6:g} km/h -> {spec.v_stop:g} m/s at "
             f"{spec.T_K - 273.15:g} C; dry road grid `{Path(spec.dry_grid).stem}`, wet "
             f"`{Path(spec.wet_grid).stem}`. Screening resolution: {spec.resolution} "
             "(docs/screening.md gives its tolerance).", "",
             "The wet grip index is formed against the reference tire of the wet grip test on "
             f"the reference compound `{Path(spec.reference_compound).stem}` "
             + (f"(BFC {ref['outputs']['bfc_wet']:.4f})." if ref["status"] == "ok" else
                f"(failed: {ref.get('error')})."), "",
             "| compound | G | class | RRC [N/kN] | class | dry ABS [m] | wet ABS [m] | "
             + " | ".join(k.replace("mu_peak_", "peak ") for k in rows[0]
                          if k.startswith("mu_peak_")) + " | Pareto |",
             "|---" * (8 + sum(k.startswith("mu_peak_") for k in rows[0])) + "|"]
    for r in sorted(rows, key=lambda r: -r["G"] if math.isfinite(r["G"]) else math.inf):
        if r["status"] != "ok":
            continue
        peaks = " | ".join(_fmt(r[k]) for k in r if k.startswith("mu_peak_"))
        lines.append(f"| {r['name']} | {r['G']:.3f} | {r['wet_class']} | "
                     f"{r['rrc_N_per_kN']:.2f} | {r['rr_class']} | {r['stop_dry_abs_m']:.2f} | "
                     f"{r['stop_wet_abs_m']:.2f} | {peaks} | {'yes' if r['pareto'] else ''} |")
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        lines += ["", "## Failed compounds", ""]
        lines += [f"- `{r['name']}`: {r['error']}" for r in failed]
    if sens:
        params = list(spec.sweep.ranges) if spec.sweep else []
        lines += ["", "## Sensitivity (Spearman rank correlation over the sweep; "
                      "standardised regression coefficients and R^2 in results.json)", "",
                  "| output | " + " | ".join(params) + " |", "|---" * (len(params) + 1) + "|"]
        for o, e in sens.items():
            lines.append(f"| {LABELS.get(o, o)} | "
                         + " | ".join(_fmt(e["spearman"].get(p, math.nan), 2) for p in params)
                         + " |")
    lines += ["", "## Cost", "",
              f"{len(result.computed)} tasks computed, {len(result.reused)} reused from "
              f"earlier runs; wall {result.wall_s:.1f} s ({result.where}); "
              f"median {cost_per_compound(result):.1f} s per compound.", ""]
    path.write_text("\n".join(lines), encoding="utf-8")
    return str(path)
