"""The screening spec (TOML): which compounds, which roads, which tire, at which resolution.

Layout (``models/studies/screen_example.toml`` is a worked example)::

    name = "screen_example"
    description = "..."
    provenance = "..."

    [compounds]                  # optional: compound files or shipped names, as they are
    files = ["summer", "my_compound.toml"]

    [sweep]                      # optional: a designed sweep around a base compound
    base = "summer"
    method = "sobol"             # "factorial" | "lhs" | "sobol" (scipy.stats.qmc)
    n = 8                        # points (lhs, sobol: a power of two); factorial: levels
    seed = 1                     # lhs and sobol (scrambled) draw from a seeded generator
    [sweep.parameters]           # name = [low, high] (tire_brush.screening.compounds)
    T_g_shift = ["-6 K", "6 K"]
    E_inf_scale = [0.8, 1.25]

    [roads]
    dry = "default"              # grid spec whose surface, engine settings (and axis
                                 # ranges, coarsened below) the dry grid takes
    wet = "r117_wet"             # grid spec of the wet reference road (with [wet])
    wet_grip = "wet_grip"        # the wet grip test spec (reference tire, test conditions)
    reference_compound = "summer"  # the reference tire's tread (see docs/screening.md)

    [tire]
    file = "passenger"

    [braking]
    study = "abs_default"        # car, ABS, maps and simulation settings of the stops
    v0 = "100 km/h"
    v_stop = "1 m/s"
    temperature = "20 degC"

    [outputs]
    peak_temperatures = ["0 degC", "20 degC", "50 degC"]
    peak_speed = "72 km/h"

    [resolution]                 # optional: the screening grids' speed and pressure axes
    dry_v_per_decade = 4         # (the temperature axes are the ones the outputs read);
    dry_p_nodes = 10             # 0: the grid spec's own axis
    wet_v_per_decade = 0
    wet_p_nodes = 0
    v_min = "1e-6 m/s"
    stop_T_step = "7 K"          # the dry stop's force-map temperature nodes: the case
                                 # temperature and every stop_T_step above it up to the
                                 # tread's heating bound (0: the study's own nodes)
    stop_dt = "5 ms"             # largest step of the quarter car (stops and the wet grip
                                 # test; 0: the study's and the test's own)

Relative paths are taken relative to the spec file. Errors name the file, the field and the
value (:class:`tirefric.errors.InputError`; several at once as
:class:`tirefric.errors.InputErrors`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.config import Table
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file

from .compounds import PARAMETERS

#: Sampling methods of a designed sweep.
METHODS = ("factorial", "lhs", "sobol")

#: Screening resolution of the grids' speed and pressure axes, per road (docs/screening.md:
#: the tolerance against the full-resolution grids is measured there and held by
#: tests/test_screening.py). 0 keeps the grid spec's own axis: the wet grid has two
#: temperature nodes only, so its full speed and pressure axes cost little.
#: ``stop_T_step`` [K] and ``stop_dt`` [s] coarsen the braking study's settings for the
#: stops (:func:`tire_brush.screening.evaluate.screen_study`; 0 keeps the study's own): the
#: force map's temperature nodes from the case temperature up every 7 K to the tread's
#: heating bound (0, 7, 14, 21 K for abs_default; the study: -4, 0, 4 K, then every 2 K to
#: 20 K) and the quarter car's largest step 5 ms, the ABS controller's period (the study:
#: 0.5 ms; the step control still shortens the steps where the wheel needs it,
#: tire_brush.braking.simulation). docs/screening.md measures both.
DEFAULT_RESOLUTION: dict[str, float] = {"dry_v_per_decade": 4, "dry_p_nodes": 10,
                                        "wet_v_per_decade": 0, "wet_p_nodes": 0,
                                        "v_min": 1e-6, "stop_T_step": 7.0,
                                        "stop_dt": 5e-3}


@dataclass(frozen=True)
class Sweep:
    """A designed sweep around ``base``: parameter ranges and how they are sampled."""

    base: str
    method: str
    n: int
    seed: int
    ranges: dict[str, tuple[float, float]]

    def points(self) -> list[dict[str, float]]:
        """The sweep's points: parameter -> value, in a fixed order.

        ``factorial``: every combination of ``n`` equally spaced levels per parameter;
        ``lhs``: a Latin hypercube (McKay, Beckman & Conover, Technometrics 21 (1979) 239) of
        ``n`` points; ``sobol``: the first ``n`` points of a scrambled Sobol sequence (Sobol',
        USSR Comput. Math. Math. Phys. 7 (1967) 86; Owen scrambling), both from
        ``scipy.stats.qmc`` with the seed, scaled to the ranges.
        """
        names = list(self.ranges)
        lo = np.array([self.ranges[k][0] for k in names])
        hi = np.array([self.ranges[k][1] for k in names])
        if self.method == "factorial":
            levels = np.linspace(0.0, 1.0, self.n) if self.n > 1 else np.array([0.5])
            unit = np.array(list(itertools.product(levels, repeat=len(names))))
        else:
            from scipy.stats import qmc

            if self.method == "lhs":
                sampler = qmc.LatinHypercube(d=len(names), seed=self.seed)
                unit = sampler.random(self.n)
            else:
                sampler = qmc.Sobol(d=len(names), scramble=True, seed=self.seed)
                unit = sampler.random_base2(round(math.log2(self.n)))
        x = lo + unit * (hi - lo)
        return [{k: float(row[i]) for i, k in enumerate(names)} for row in x]


@dataclass(frozen=True)
class ScreenSpec:
    """A validated screening spec (module docstring); paths resolved, quantities SI."""

    name: str
    source: str
    files: tuple[str, ...]
    sweep: Sweep | None
    dry_grid: str
    wet_grid: str
    wet_grip: str
    reference_compound: str
    tire: str
    study: str
    v0: float
    v_stop: float
    T_K: float
    peak_T_K: tuple[float, ...]
    peak_speed: float
    resolution: dict[str, float] = field(default_factory=lambda: dict(DEFAULT_RESOLUTION))
    description: str = ""

    def compounds(self) -> list[dict[str, Any]]:
        """The compound descriptions (tire_brush.screening.compounds), files first, then the
        sweep's points, each with a unique name."""
        out: list[dict[str, Any]] = []
        for f in self.files:
            out.append({"name": _stem_name(f), "file": f})
        if self.sweep is not None:
            stem = _stem_name(self.sweep.base)
            width = len(str(max(len(self.sweep.points()) - 1, 0)))
            for i, pt in enumerate(self.sweep.points()):
                out.append({"name": f"{stem}_{i:0{width}d}", "base": self.sweep.base,
                            "params": pt})
        seen: dict[str, int] = {}
        for d in out:
            n = seen.get(d["name"], 0)
            seen[d["name"]] = n + 1
            if n:
                d["name"] = f"{d['name']}_{n + 1}"
        return out

    def reference(self) -> dict[str, Any]:
        """Description of the reference tire's tread compound."""
        return {"name": f"reference_{_stem_name(self.reference_compound)}",
                "file": self.reference_compound}

    def axes(self, template, road: str) -> dict[str, np.ndarray]:
        """Screening speed and pressure axes of ``road`` (``"dry"`` or ``"wet"``) for its
        grid spec (template): the template's ranges at the spec's density
        (:data:`DEFAULT_RESOLUTION`; 0 keeps the template's axis)."""
        r = self.resolution
        out: dict[str, np.ndarray] = {}
        per_decade = int(r[f"{road}_v_per_decade"])
        if per_decade:
            v_lo = max(float(r["v_min"]), float(template.v[0]))
            v_hi = float(template.v[-1])
            nv = max(2, math.ceil(per_decade * math.log10(v_hi / v_lo)) + 1)
            v = np.geomspace(v_lo, v_hi, nv)
            v[0], v[-1] = v_lo, v_hi
            out["v"] = v
        n_p = int(r[f"{road}_p_nodes"])
        if n_p:
            p = np.geomspace(float(template.p[0]), float(template.p[-1]), n_p)
            p[0], p[-1] = float(template.p[0]), float(template.p[-1])
            out["p"] = p
        return out


def _stem_name(ref: str) -> str:
    """A file-name friendly name of a compound reference."""
    return re.sub(r"[^A-Za-z0-9_-]+", "_", Path(ref).stem) or "compound"


def _model(t: Table, key: str, kind: str, default: str | None = None) -> str:
    """A model reference: a file relative to the spec, or a shipped name; resolved path."""
    value = t.string(key) if default is None else t.string(key, default)
    p = Path(value)
    if not p.is_absolute():
        p = t.source.parent / p
    if p.is_file():
        return str(p.resolve())
    try:
        return str(resolve_model_file(value, kind))
    except InputError as exc:
        raise t.error(key, exc.message, value) from None


def _compound_file(t: Table, key: str, value: Any) -> str:
    """A compound file or shipped name (no existence check: a missing file is a failed
    compound, reported in the results while the others finish)."""
    if not isinstance(value, str) or not value:
        raise t.error(key, "expected a compound file or shipped name", value)
    p = Path(value)
    if not p.is_absolute():
        p = t.source.parent / p
    if p.is_file() or p.suffix:
        return str(p.resolve())
    try:
        return str(resolve_model_file(value, "compounds"))
    except InputError:
        return str(p.resolve())


def load_screen_spec(path: str | Path) -> ScreenSpec:
    """Read and validate a screening spec (a file or a shipped study name).

    Raises
    ------
    InputError
        A missing or misspelt field, an unknown parameter, method or unit, an empty range,
        a Sobol size that is not a power of two, no compounds at all; naming the file, the
        field and the value.
    """
    path = resolve_model_file(path, "studies")
    root = Table.load(path)
    name = root.string("name", path.stem)
    description = root.string("description", "")
    root.raw("provenance", "")
    files: list[str] = []
    ct = root.table("compounds", required=False)
    if ct is not None:
        raw = ct.raw("files")
        if not isinstance(raw, list):
            raise ct.error("files", "expected a list of compound files or names", raw)
        files = [_compound_file(ct, "files", v) for v in raw]
        ct.check_unknown()
    sweep = None
    sw = root.table("sweep", required=False)
    if sw is not None:
        base = _compound_file(sw, "base", sw.raw("base"))
        method = sw.string("method", "sobol", choices=METHODS)
        n = sw.integer("n", minimum=1)
        seed = sw.integer("seed", 0, minimum=0)
        if method == "sobol" and n & (n - 1):
            raise sw.error("n", "a Sobol sample keeps its balance only at a power of two "
                           "points (scipy.stats.qmc.Sobol)", n)
        pt = sw.table("parameters")
        ranges: dict[str, tuple[float, float]] = {}
        for k in pt.data:
            if k not in PARAMETERS:
                raise pt.error(k, f"unknown design parameter (known: {', '.join(PARAMETERS)})",
                               k)
            lo_hi = pt.array(k, PARAMETERS[k].dimension)
            if lo_hi.shape != (2,) or not lo_hi[1] > lo_hi[0]:
                raise pt.error(k, "expected [low, high] with high > low", pt.raw(k))
            ranges[k] = (float(lo_hi[0]), float(lo_hi[1]))
        pt.check_unknown()
        if not ranges:
            raise sw.error("parameters", "a sweep needs at least one parameter")
        sw.check_unknown(extra_allowed=("parameters",))
        sweep = Sweep(base, method, n, seed, ranges)
    if not files and sweep is None:
        raise root.error("compounds", "no compounds: give [compounds] files or a [sweep]")
    rt = root.table("roads")
    dry = _model(rt, "dry", "grids", "default")
    wet = _model(rt, "wet", "grids", "r117_wet")
    wet_grip = _model(rt, "wet_grip", "studies", "wet_grip")
    ref = _compound_file(rt, "reference_compound", rt.raw("reference_compound", "summer"))
    rt.check_unknown()
    tt = root.table("tire", required=False)
    tire = _model(tt, "file", "tires", "passenger") if tt is not None else \
        str(resolve_model_file("passenger", "tires"))
    if tt is not None:
        tt.check_unknown()
    bt = root.table("braking", required=False)
    b = bt if bt is not None else Table({}, path, "braking")
    study = _model(b, "study", "studies", "abs_default")
    v0 = b.quantity("v0", "velocity", 100 / 3.6, positive=True)
    v_stop = b.quantity("v_stop", "velocity", 1.0, positive=True)
    if not v0 > v_stop:
        raise b.error("v_stop", "must be below braking.v0", v_stop)
    T_K = b.quantity("temperature", "temperature", 293.15, positive=True)
    b.check_unknown()
    ot = root.table("outputs", required=False)
    o = ot if ot is not None else Table({}, path, "outputs")
    peak_T = (o.array("peak_temperatures", "temperature", positive=True, increasing=True)
              if o.has("peak_temperatures") else np.array([273.15, 293.15, 323.15]))
    peak_speed = o.quantity("peak_speed", "velocity", 20.0, positive=True)
    o.check_unknown()
    res = dict(DEFAULT_RESOLUTION)
    rs = root.table("resolution", required=False)
    if rs is not None:
        for road in ("dry", "wet"):
            if rs.has(f"{road}_v_per_decade"):
                res[f"{road}_v_per_decade"] = rs.integer(f"{road}_v_per_decade", minimum=0)
            if rs.has(f"{road}_p_nodes"):
                n_p = rs.integer(f"{road}_p_nodes", minimum=0)
                if n_p == 1:
                    raise rs.error(f"{road}_p_nodes", "an axis needs 2 nodes (or 0: the grid "
                                   "spec's own)", n_p)
                res[f"{road}_p_nodes"] = n_p
        if rs.has("v_min"):
            res["v_min"] = rs.quantity("v_min", "velocity", positive=True)
        if rs.has("stop_T_step"):
            res["stop_T_step"] = rs.quantity("stop_T_step", "temperature_difference",
                                             nonnegative=True)
        if rs.has("stop_dt"):
            res["stop_dt"] = rs.quantity("stop_dt", "time", nonnegative=True, maximum=0.01)
        rs.check_unknown()
    root.check_unknown()
    return ScreenSpec(name, str(path), tuple(files), sweep, dry, wet, wet_grip, ref, tire,
                      study, v0, v_stop, T_K, tuple(float(x) for x in peak_T), peak_speed,
                      res, description)


def screen_settings(spec: ScreenSpec, keep: str | None = None):
    """The :class:`~tire_brush.screening.evaluate.Settings` of a spec: the grid templates at
    the screening resolution."""
    from lookup.grid.spec import load_spec
    from tirefric import __version__

    from .evaluate import Settings

    dry = load_spec(spec.dry_grid)
    wet = load_spec(spec.wet_grid)
    if not wet.wet:
        raise InputError("the wet road's grid spec has no [wet] table", source=spec.source,
                         field="roads.wet", value=spec.wet_grid)
    dry = dry.with_axes(**spec.axes(dry, "dry"))
    wet = wet.with_axes(**spec.axes(wet, "wet"))
    p_dry, p_wet = read_pressures(spec)
    dry = dry.with_axes(p=pressure_axis_to(dry.p, p_dry))
    wet = wet.with_axes(p=pressure_axis_to(wet.p, p_wet))
    return Settings(tire=spec.tire, dry_spec=dry, wet_spec=wet, wet_grip_spec=spec.wet_grip,
                    study=spec.study, v0=spec.v0, v_stop=spec.v_stop, T_K=spec.T_K,
                    peak_T_K=spec.peak_T_K, peak_speed=spec.peak_speed, keep=keep,
                    version=__version__, stop_T_step=float(spec.resolution["stop_T_step"]),
                    stop_dt=float(spec.resolution["stop_dt"]))


def rubber_pressure_max(tire, Fz: float) -> float:
    """The largest pressure [Pa] at which the tire core reads a grid at load ``Fz`` [N]: the
    patch's peak pressure over the rubber's share of the area, ``p_amp / (1 - void)``, the
    same operations as the core (``tire_brush.element``'s patch size, flat centre and mean
    of the pressure shape: flat centre, parabolic ends; the pressure is at most ``p_amp``).

    Parameters
    ----------
    tire : TireParams
    Fz : float
        Load [N] (a lifted share on a wet road only lowers it).
    """
    from tire_brush import ccore, element

    P = ccore.core_params(tire, n_elements=2, dt_internal=1.0, tol=1e-6, v_floor=0.1,
                          thermal=False, rigid=True, massless=False)
    a, b = element.patch_size(P, Fz)
    cf = element.flat_half_length(P, Fz, a, b)
    mean = (cf + (2.0 / 3.0) * (a - cf)) / a
    return Fz / (2.0 * a * b * mean) / (1.0 - P.void_ratio)


def read_pressures(spec: ScreenSpec) -> tuple[float, float]:
    """The largest grid pressure [Pa] the outputs read on the dry and on the wet road
    (:func:`rubber_pressure_max`): dry, the candidate tire at the stops' and the peak
    friction's load (the study car's); wet, the candidate and the reference tire at the wet
    grip test's car load and each one's trailer load."""
    from tire_brush.braking.study import load_study
    from tire_brush.braking.wet_grip_test import load_wet_grip_spec
    from tire_brush.params import load_tire

    st = load_study(spec.study)
    wg = load_wet_grip_spec(spec.wet_grip)
    dry = rubber_pressure_max(load_tire(spec.tire), st.car.Fz)
    wet = max(rubber_pressure_max(load_tire(t), Fz) for t in (spec.tire, wg.reference_tire)
              for Fz in (wg.car.Fz, wg.trailer_load_share * wg.tire_entry(t).load_capacity))
    return dry, wet


def pressure_axis_to(p: np.ndarray, p_max: float) -> np.ndarray:
    """The pressure axis ``p`` [Pa] up to its first node at or above ``p_max``.

    A grid is read multilinearly in log10 p (the tire core and :mod:`lookup.grid`): a read
    at a pressure up to ``p_max`` uses the two nodes around it, so the nodes above that
    first one are never read, and leaving them out of the grid leaves every value the
    outputs read as it was (to the rounding of the cell's position, the axis' spacing being
    computed from its ends). Each node's friction is computed on its own, so the grid's
    remaining nodes are the same numbers; the screen saves their cost (docs/screening.md).
    An axis that ends below ``p_max`` is returned whole.
    """
    p = np.asarray(p, dtype=float)
    above = np.flatnonzero(p >= p_max)
    if above.size == 0:
        return p
    return p[:max(int(above[0]), 1) + 1].copy()


def full_resolution(settings, dry_spec, wet_spec):
    """The settings with other grid templates (e.g. the shipped full-resolution specs), for
    the resolution check."""
    return dataclasses.replace(settings, dry_spec=dry_spec, wet_spec=wet_spec)
