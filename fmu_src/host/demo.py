"""``tirefric demo``: the whole product on the shipped defaults, with a report.

Steps (each printed with its time, so progress is visible):

1. the default friction grid (summer compound on asphalt): the shipped file is loaded and
   validated (hash), or built from ``models/grids/default.toml`` if missing, corrupt, or
   ``--rebuild-grid`` is given;
2. plots of the friction branches (cold and hot mu(v), flash temperature, contact area, the
   grid's hot/cold map) and of the brush tire's mu-slip curves with the eq. (28) limits;
3. the brush-tire FMU in both flavours, built and validated with fmpy: pythonfmu
   (``BrushTire.fmu``, needs Python with numpy on the host) and native
   (``BrushTireNative.fmu``, the C core with an FMI wrapper; needs a C compiler to build);
4. a quarter-car braking manoeuvre driven through the FMU by fmpy, step by step;
5. a small ABS study (``models/studies/abs_default.toml``: CasADi optimal control, rule-based
   ABS, locked wheel);
6. ``report.md`` with the figures and the key numbers.

This module orchestrates library calls and holds no physics.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import GridError, TirefricError

DEMO_T_C = (0.0, 20.0, 50.0, 80.0)
CURVE_T_C = (20.0, 50.0)


@dataclass
class DemoLog:
    """Progress lines with timings, and the numbers the report quotes."""

    echo: Callable[[str], None] = print
    numbers: dict[str, Any] = field(default_factory=dict)
    t0: float = field(default_factory=time.perf_counter)

    def step(self, k: int, n: int, text: str) -> None:
        self.echo(f"[{k}/{n}] {text}  (t = {time.perf_counter() - self.t0:5.1f} s)")


def _grid(out: Path, rebuild: bool, log: DemoLog):
    from lookup.grid import load_grid
    from lookup.grid.build import build_grid
    from lookup.grid.spec import load_spec
    from tirefric.paths import models_dir

    if not rebuild:
        try:
            grid = load_grid("default")
            log.numbers["grid_source"] = "shipped models/grids/default.nc (hash verified)"
            return grid, Path(grid.source)
        except GridError as exc:
            log.echo(f"      shipped grid unusable ({exc}); building it")
    path = out / "default.nc"
    grid, _ = build_grid(load_spec(models_dir() / "grids" / "default.toml"), path, workers=2)
    log.numbers["grid_source"] = f"built into {path}"
    return grid, path


def _friction_plots(grid, out: Path, log: DemoLog) -> list[Path]:
    from lookup.compound import load_compound
    from lookup.friction import PerssonFriction
    from lookup.grid.plots import plot_grid
    from lookup.plots import plot_compound, plot_friction, plot_surface
    from lookup.surface import load_surface

    compound = load_compound(grid.meta.get("compound_name", "summer"))
    surface = load_surface(grid.meta.get("surface_name", "asphalt"))
    model = PerssonFriction(compound, surface)
    figs = [plot_friction(model, DEMO_T_C, 3e5, out / "friction_branches.png"),
            plot_grid(grid, out / "friction_grid.png"),
            plot_compound(compound, out / "compound.png", (0.0, 20.0, 50.0)),
            plot_surface(surface, out / "surface.png")]
    v = np.logspace(-6, np.log10(40.0), 241)
    rows = []
    for T in DEMO_T_C:
        c = model.cold(v, T + 273.15, 3e5)
        h = model.hot(np.array([1.0, 10.0]), T + 273.15, 3e5)
        i = int(np.argmax(c.mu))
        rows.append({"T_C": T, "mu_cold_peak": float(c.mu[i]), "v_peak_m_s": float(v[i]),
                     "mu_cold_1": float(np.interp(0.0, np.log10(v), c.mu)),
                     "mu_hot_1": float(h.mu[0]),
                     "mu_cold_10": float(np.interp(1.0, np.log10(v), c.mu)),
                     "mu_hot_10": float(h.mu[1]), "dT_flash_10": float(h.dT_flash[1])})
    log.numbers["friction"] = rows
    log.numbers["q1"] = model.q1
    log.numbers["compound"] = compound.name
    log.numbers["surface"] = surface.name
    return figs


def _tire_curves(grid, out: Path, log: DemoLog) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from tire_brush.friction import GridFriction
    from tire_brush.params import load_tire
    from tire_brush.steady import SteadyBrush

    tire = load_tire("passenger")
    kappa = -np.geomspace(2e-3, 1.0, 40)
    Fz, vx = 4000.0, 20.0
    fig, axes = plt.subplots(1, len(CURVE_T_C), figsize=(6 * len(CURVE_T_C), 4.5))
    rows = []
    for ax, T in zip(np.atleast_1d(axes), CURVE_T_C, strict=True):
        for label, s0, style in (("eq. (28), s0 = 0.2 D", None, "-k"),
                                 ("hot only (s0 = 0)", 0.0, "--r"),
                                 ("cold only (s0 = inf)", math.inf, "--b")):
            out_ = SteadyBrush(tire, GridFriction(grid, s0=s0)).solve(kappa, 0.0, vx, Fz,
                                                                       T + 273.15)
            mu = -out_.Fx / Fz
            ax.semilogx(-kappa, mu, style, label=label)
            if s0 is None:
                i = int(np.argmax(mu))
                rows.append({"T_C": T, "mu_peak": float(mu[i]), "kappa_peak": float(kappa[i]),
                             "mu_locked": float(mu[-1])})
        ax.set(xlabel="longitudinal slip -kappa [1]", ylabel="Fx / Fz [1]",
               title=f"passenger tire, {vx:g} m/s, Fz = {Fz:g} N, T0 = {T:g} C")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    path = out / "tire_mu_slip.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    log.numbers["tire"] = rows
    return path


def _fmu(grid_path: Path, out: Path, log: DemoLog) -> Path:
    from fmpy.validation import validate_fmu

    from fmu_src.make.build import build_fmu

    report = build_fmu("passenger", grid_path if grid_path.is_file() else "default",
                       out / "BrushTire.fmu")
    problems = validate_fmu(str(report.path))
    if problems:
        raise TirefricError("the built FMU does not validate: " + "; ".join(problems))
    log.numbers["fmu"] = {"path": str(report.path), "guid": report.guid,
                          "size_MB": report.size_bytes / 1e6, "grid_hash": report.grid_hash,
                          "validation_problems": len(problems), "build_s": report.seconds}
    try:
        native = build_fmu("passenger", grid_path if grid_path.is_file() else "default",
                           out / "BrushTireNative.fmu", native=True)
    except TirefricError as exc:   # no C compiler: the pythonfmu flavour is enough here
        log.numbers["fmu_native"] = {"error": str(exc)}
        log.echo(f"      native FMU not built: {exc}")
    else:
        log.numbers["fmu_native"] = {
            "path": str(native.path), "guid": native.guid, "size_MB": native.size_bytes / 1e6,
            "platforms": native.runtime_package.strip("()").removeprefix("native: "),
            "validation_problems": len(validate_fmu(str(native.path))),
            "build_s": native.seconds}
    return report.path


def _study(out: Path, log: DemoLog) -> list[Path]:
    from tire_brush.braking.study import load_study, run_study, write_results
    from tirefric.paths import models_dir

    spec = load_study(models_dir() / "studies" / "abs_default.toml")
    from .cosim import braking_simulator

    results = run_study(spec, progress=lambda s: log.echo(f"      {s}"),
                        simulator_factory=braking_simulator)
    doc = write_results(spec, results, out / "abs_study")
    log.numbers["study"] = doc.get("cases", [])
    for f in doc.get("failed", []):
        log.echo(f"      case {f['case']} FAILED: {f['error']}")
    plots = out / "abs_study" / "plots"
    return [p for p in (plots / "distances.png", *sorted(plots.glob("*20C*.png")))
            if p.is_file()]


def _fmt(x: Any, nd: int = 3) -> str:
    return f"{x:.{nd}g}" if isinstance(x, float) else str(x)


def write_report(out: Path, log: DemoLog, figures: dict[str, list[Path]]) -> Path:
    """Markdown report with the figures (relative links) and the key numbers."""
    n = log.numbers
    lines = ["# tirefric demo report", "",
             f"Compound `{n.get('compound')}` on surface `{n.get('surface')}` "
             f"(q1 = {n.get('q1', float('nan')):.3g} 1/m), tire `passenger`. "
             f"Grid: {n.get('grid_source')}.", ""]
    lines += ["## 1. Friction from physics (Persson theory)", "",
              "Cold branch: no flash heating; hot branch: flash temperature fully developed and "
              "self-consistent. Nominal pressure 0.3 MPa.", "",
              "| T0 [C] | cold peak mu | at v [m/s] | mu cold / hot at 1 m/s | "
              "mu cold / hot at 10 m/s | dT_flash at 10 m/s [K] |", "|---|---|---|---|---|---|"]
    for r in n.get("friction", []):
        lines.append(f"| {r['T_C']:g} | {r['mu_cold_peak']:.2f} | {r['v_peak_m_s']:.2g} | "
                     f"{r['mu_cold_1']:.2f} / {r['mu_hot_1']:.2f} | "
                     f"{r['mu_cold_10']:.2f} / {r['mu_hot_10']:.2f} | "
                     f"{r['dT_flash_10']:.0f} |")
    lines.append("")
    lines += [f"![{p.stem}]({p.name})" for p in figures.get("friction", [])] + [""]
    lines += ["## 2. Brush tire on the grid (eq. 28)", "",
              "| T0 [C] | peak Fx/Fz | at slip | locked-wheel Fx/Fz |", "|---|---|---|---|"]
    for r in n.get("tire", []):
        lines.append(f"| {r['T_C']:g} | {r['mu_peak']:.2f} | {r['kappa_peak']:.3f} | "
                     f"{r['mu_locked']:.2f} |")
    lines += [""] + [f"![{p.stem}]({p.name})" for p in figures.get("tire", [])] + [""]
    f = n.get("fmu", {})
    lines += ["## 3. FMU", "",
              f"`{Path(f.get('path', '')).name}`: FMI 2.0 co-simulation, GUID `{f.get('guid')}`, "
              f"{f.get('size_MB', 0):.1f} MB, grid `{f.get('grid_hash')}`; fmpy validation: "
              f"{f.get('validation_problems')} problems.", ""]
    nf = n.get("fmu_native", {})
    if "path" in nf:
        lines += [f"`{Path(nf['path']).name}`: the same model as a native FMU (C core and FMI "
                  f"wrapper, no Python on the host; binaries {nf.get('platforms')}), GUID "
                  f"`{nf.get('guid')}`, {nf.get('size_MB', 0):.2f} MB; fmpy validation: "
                  f"{nf.get('validation_problems')} problems.", ""]
    elif nf:
        lines += [f"Native FMU not built: {nf.get('error')}", ""]
    q = n.get("quarter_car", {})
    if q:
        lines += ["## 4. Quarter-car braking through the FMU", "",
                  f"A quarter car (Python) drives the FMU through fmpy at "
                  f"{_fmt(q.get('step_s'))} s communication steps from "
                  f"{_fmt(q.get('v0_m_per_s'))} m/s at {_fmt(q.get('T_ambient_K'))} K; FMU "
                  f"parameters {q.get('fmu_parameters')}.", "",
                  "| brake control | stopping distance [m] | stop time [s] | mean slip | "
                  "max flash dT [K] | tread rise [K] |", "|---|---|---|---|---|---|"]
        for name in ("abs", "locked"):
            r = q.get(name)
            if isinstance(r, dict):
                lines.append(f"| {name} | {_fmt(r.get('stopping_distance_m'))} | "
                             f"{_fmt(r.get('stop_time_s'))} | {_fmt(r.get('mean_slip'))} | "
                             f"{_fmt(r.get('dT_flash_max_K'))} | "
                             f"{_fmt(r.get('T_tread_rise_K'))} |")
        lines += [""] + [f"![{p.stem}]({p.name})" for p in figures.get("quarter_car", [])]
        lines.append("")
    lines += ["## 5. ABS study (CasADi optimal control, rule-based ABS, locked wheel)", ""]
    study = n.get("study", [])
    if study:
        keys = [k for k in ("case", "T_C", "stopping_distance_ocp", "stopping_distance_abs",
                            "stopping_distance_abs_fmu", "stopping_distance_locked",
                            "optimal_slip") if k in study[0]]
        lines += ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
        lines += ["| " + " | ".join(_fmt(r.get(k)) for k in keys) + " |" for r in study]
    lines += [""] + [f"![{p.stem}]({p.relative_to(out).as_posix()})"
                     for p in figures.get("study", [])]
    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")
    (out / "report.json").write_text(json.dumps(n, indent=2, default=str))
    return path


def run_demo(out_dir: str | Path, *, rebuild_grid: bool = False,
             echo: Callable[[str], None] = print) -> Path:
    """Run the demo into ``out_dir``; returns the report's path."""
    from . import cosim

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    log = DemoLog(echo)
    n = 6
    figures: dict[str, list[Path]] = {}
    log.step(1, n, "default friction grid")
    grid, grid_path = _grid(out, rebuild_grid, log)
    log.step(2, n, "friction branches and tire mu-slip curves")
    figures["friction"] = _friction_plots(grid, out, log)
    figures["tire"] = [_tire_curves(grid, out, log)]
    log.step(3, n, "brush-tire FMUs (pythonfmu and native): build and validate")
    fmu = _fmu(grid_path, out, log)
    log.step(4, n, "quarter-car braking through the FMU (fmpy)")
    figures["quarter_car"], log.numbers["quarter_car"] = cosim.demo_manoeuvre(fmu, out)
    log.step(5, n, "ABS study")
    figures["study"] = _study(out, log)
    log.step(6, n, "report")
    report = write_report(out, log, figures)
    echo(f"done: {report}")
    return report


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric demo``."""
    p = sub.add_parser("demo", help="run the whole product on the shipped defaults",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("-o", "--output", default="demo_out", help="output folder [demo_out]")
    p.add_argument("--rebuild-grid", action="store_true",
                   help="build the default grid instead of using the shipped one")
    p.set_defaults(func=lambda a: (run_demo(a.output, rebuild_grid=a.rebuild_grid), 0)[1])
