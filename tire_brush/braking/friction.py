"""Friction sources of the braking studies: where ``Fx/Fz(kappa, vx, Fz, T)`` comes from.

A study case (road, compound, temperature) is turned into a friction callable
``fx_over_fz(kappa, vx, Fz, T_K)`` by a *factory* registered under a source name:

``analytic``
    A closed-form curve of :mod:`.reference` (Burckhardt or Magic Formula) for the case's road;
    compounds and temperature do not enter. Needs no grid: the validation source.
``brush``
    The steady state of the brush tire (:mod:`tire_brush.steady`) on a friction grid of the
    lookup package, for the case's compound, road and temperature
    (``SteadyBrush.fx_over_fz``). The adapter :func:`brush_fx_over_fz` turns any other
    ``steady_state(params, friction, kappa, alpha, vx, Fz, T_K)`` into ``fx_over_fz``.

Further sources plug in with :func:`register_friction_source`. A factory receives the study's
``[friction]`` settings (a plain dict, so that cases can be shipped to Dask workers), the case
and the folder of the study file (for relative paths), and returns a :class:`FrictionSource`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.errors import InputError

from .force_map import FxOverFz
from .reference import (
    BURCKHARDT_ROADS,
    MAGIC_FORMULA_ROADS,
    Burckhardt,
    burckhardt_road,
    magic_formula_road,
)


@dataclass(frozen=True)
class Case:
    """One study case.

    Attributes
    ----------
    road : str
        Road (surface) name.
    compound : str
        Tread compound name ("" where the source has none, e.g. analytic curves).
    T_K : float
        Background (road/tread) temperature [K].
    """

    road: str
    compound: str
    T_K: float

    @property
    def T_C(self) -> float:
        """Temperature [Celsius]."""
        return self.T_K - 273.15

    @property
    def label(self) -> str:
        """File-name friendly label ``road[_compound]_<T>C``."""
        parts = [self.road] + ([self.compound] if self.compound else [])
        return "_".join(parts) + f"_{self.T_C:g}C"


@dataclass(frozen=True)
class FrictionSource:
    """A friction callable with its provenance.

    Attributes
    ----------
    fx_over_fz : callable
        ``Fx/Fz(kappa, vx, Fz, T_K)``, numpy broadcasting.
    label : str
        One-line description (written into the slip-map CSV and the results).
    provenance : dict
        Parameters behind it (JSON-serialisable), written into the results.
    temperature_dependent : bool
        Whether the friction depends on the temperature argument (if not, the study's force
        map needs no temperature nodes beyond the case temperature).
    """

    fx_over_fz: FxOverFz
    label: str
    provenance: dict = field(default_factory=dict)
    temperature_dependent: bool = True


FrictionFactory = Callable[[Mapping[str, Any], Case, Path], FrictionSource]

FRICTION_SOURCES: dict[str, FrictionFactory] = {}

#: ``[friction]`` keys each source reads (the study loader refuses others).
FRICTION_KEYS: dict[str, tuple[str, ...]] = {}


def register_friction_source(name: str, factory: FrictionFactory,
                             keys: tuple[str, ...] = ()) -> None:
    """Make ``factory`` available as ``[friction] source = name`` reading ``keys``."""
    FRICTION_SOURCES[name] = factory
    FRICTION_KEYS[name] = tuple(keys)


def make_friction_source(settings: Mapping[str, Any], case: Case,
                         base_dir: Path = Path(".")) -> FrictionSource:
    """Build the friction source of ``case`` as ``settings["source"]`` says."""
    kind = settings.get("source", "analytic")
    if kind not in FRICTION_SOURCES:
        raise InputError(f"unknown friction source (known: {', '.join(FRICTION_SOURCES)})",
                         field="friction.source", value=kind)
    return FRICTION_SOURCES[kind](settings, case, base_dir)


# -- analytic -------------------------------------------------------------------------------------
def analytic_source(settings: Mapping[str, Any], case: Case, base_dir: Path) -> FrictionSource:
    """Closed-form curve for ``case.road``: ``model`` is ``burckhardt`` or ``magic_formula``.

    ``c4`` [s/m] (Burckhardt only) adds the velocity term; ``mu_scale`` [1] scales the curve
    (a road friction scale, as the FMU's ``mu_scale``).
    """
    model = settings.get("model", "burckhardt")
    scale = _number(settings, "mu_scale", 1.0)
    if not scale > 0:
        raise InputError("must be > 0", field="friction.mu_scale", value=scale)
    if model == "burckhardt":
        base = burckhardt_road(case.road, _number(settings, "c4", 0.0))
        curve = Burckhardt(base.c1 * scale, base.c2, base.c3 * scale, base.c4, name=case.road)
        prov = {"model": "burckhardt", "road": case.road, "c1": curve.c1, "c2": curve.c2,
                "c3": curve.c3, "c4_s_per_m": curve.c4,
                "source": "Burckhardt 1993, parameters as in Kiencke & Nielsen 2005"}
    elif model == "magic_formula":
        if "c4" in settings:
            raise InputError("c4 belongs to the Burckhardt model", field="friction.c4",
                             value=settings["c4"])
        base = magic_formula_road(case.road)
        curve = type(base)(base.B, base.C, base.D * scale, base.E, name=case.road)
        prov = {"model": "magic_formula", "road": case.road, "B": curve.B, "C": curve.C,
                "D": curve.D, "E": curve.E, "source": "Pacejka 2012 sec. 4.3"}
    else:
        raise InputError("must be 'burckhardt' or 'magic_formula'", field="friction.model",
                         value=model)
    if case.compound:
        raise InputError("analytic friction has no compounds: leave cases.compounds empty",
                         field="cases.compounds", value=case.compound)
    return FrictionSource(curve, f"analytic {model}, road {case.road}", prov,
                          temperature_dependent=False)


def _number(settings: Mapping[str, Any], key: str, default: float) -> float:
    value = settings.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise InputError("expected a finite number (SI units)", field=f"friction.{key}",
                         value=value)
    return float(value)


def analytic_roads(model: str) -> tuple[str, ...]:
    """Road names the analytic ``model`` knows."""
    return tuple(BURCKHARDT_ROADS if model == "burckhardt" else MAGIC_FORMULA_ROADS)


register_friction_source("analytic", analytic_source, ("model", "c4", "mu_scale"))


# -- brush tire on a grid -------------------------------------------------------------------------
def brush_fx_over_fz(steady_state: Callable, params: Any, friction: Any, *,
                     vectorized: bool = True) -> FxOverFz:
    """Adapter: the brush tire's steady state as a friction source ``Fx/Fz``.

    Parameters
    ----------
    steady_state
        ``steady_state(params, friction, kappa, alpha, vx, Fz, T_K)`` returning the forces as
        a mapping or an object with ``Fx`` [N] (pure longitudinal slip: ``alpha = 0``).
    params, friction
        Tire parameters and friction grid, passed through.
    vectorized
        True if ``steady_state`` broadcasts over array inputs; False evaluates point by point.
    """

    def fx_of(res) -> np.ndarray:
        return np.asarray(res["Fx"] if isinstance(res, Mapping) else res.Fx, dtype=float)

    def fx_over_fz(kappa, vx, Fz, T_K) -> np.ndarray:
        k, v, f, t = np.broadcast_arrays(*(np.asarray(a, dtype=float)
                                           for a in (kappa, vx, Fz, T_K)))
        if (f <= 0).any():
            raise InputError("the brush force map needs loads > 0 N", field="Fz")
        if vectorized:
            Fx = fx_of(steady_state(params, friction, k, np.zeros_like(k), v, f, t))
            Fx = np.broadcast_to(Fx, k.shape)
        else:
            Fx = np.empty(k.shape)
            for idx in np.ndindex(k.shape):
                Fx[idx] = float(fx_of(steady_state(params, friction, float(k[idx]), 0.0,
                                                   float(v[idx]), float(f[idx]),
                                                   float(t[idx]))))
        return Fx / f

    return fx_over_fz



def steady_cells(params: Any, s0: float) -> int:
    """Cells along the patch of the steady brush for the braking maps.

    The steady model integrates each element with its own error-controlled steps, eq. (28)
    along the slip path included, and reports the patch integral of the friction, so the
    cell count only places its diagnostics: on the default grid (passenger tire, 20 C,
    4 m/s, kappa = -0.2, 4.4 kN) ``-Fx/Fz`` is 1.2859, 1.2858, 1.2856, 1.2854 at 64, 256,
    1024, 2048 cells (the blending length ``s0`` no longer sets the cell size). Returns the
    steady model's default; ``params`` and ``s0`` are kept for the callers.
    """
    from tire_brush.steady import N_STEADY

    del params, s0
    return N_STEADY


def brush_inputs(settings: Mapping[str, Any], case: Case, base_dir: Path) -> tuple[str, str]:
    """Tire and grid names (or files, relative to the study) of ``case`` for the brush source.

    ``{compound}`` and ``{road}`` in the ``grid`` setting are replaced by the case's.
    """

    def local(name: str) -> str:
        p = Path(name)
        return str(base_dir / p) if not p.is_absolute() and (base_dir / p).is_file() else name

    tire_name = local(str(settings.get("tire", "passenger")))
    grid_name = local(str(settings.get("grid", "default")).format(compound=case.compound,
                                                                  road=case.road))
    return tire_name, grid_name


def brush_source(settings: Mapping[str, Any], case: Case, base_dir: Path) -> FrictionSource:
    """The steady brush tire (:mod:`tire_brush.steady`) on the grid of ``case.compound`` on
    ``case.road``.

    Settings: ``tire`` (TOML file or shipped name, default ``passenger``) and ``grid`` (file
    or shipped grid name, default ``default``) in which ``{compound}`` and ``{road}`` are
    replaced by the case's (:func:`brush_inputs`). Relative paths are taken relative to the
    study file. ``n_elements``: cells along the patch of the steady model, default
    :func:`steady_cells` (resolves the blending length ``s0`` of the grid). The grid's
    metadata names its compound and surface (``compound_name``, ``surface_name``); a case
    whose compound or road differs is refused, so a label can never stand for physics that was
    not computed. Uses ``tire_brush.params.load_tire``, ``lookup.grid.load_grid`` and
    ``tire_brush.steady.SteadyBrush(params, grid).fx_over_fz``.
    """
    from lookup.grid import load_grid
    from tire_brush.params import load_tire
    from tire_brush.steady import SteadyBrush

    tire_name, grid_name = brush_inputs(settings, case, base_dir)
    params = load_tire(tire_name)
    grid = load_grid(grid_name)
    meta = getattr(grid, "meta", {})
    for what, key, want in (("compound", "compound_name", case.compound),
                            ("road", "surface_name", case.road)):
        have = meta.get(key)
        if have is not None and want and have != want:
            raise InputError(f"grid '{grid_name}' was built for {what} '{have}', not "
                             f"'{want}' (use '{{{what}}}' in friction.grid to pick a grid "
                             "per case)", field=f"cases.{what}s", value=want)
    if "n_elements" in settings:
        n = settings["n_elements"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 2:
            raise InputError("must be an integer >= 2", field="friction.n_elements", value=n)
    else:
        n = steady_cells(params, float(grid.s0_m))
    prov = {"model": "brush", "tire": tire_name, "grid": grid_name,
            "compound": case.compound, "road": case.road,
            "grid_hash": str(meta.get("hash", "")), "n_elements": n,
            "tire_params": getattr(params, "describe", dict)()}
    return FrictionSource(SteadyBrush(params, grid, n_elements=n).fx_over_fz,
                          f"brush tire {tire_name} on grid {grid_name} ({n} cells)", prov)


register_friction_source("brush", brush_source, ("tire", "grid", "n_elements"))


def brush_rolling_resistance(provenance: Mapping[str, Any], V: float, Fz: float,
                             T_K: float) -> tuple[float, str]:
    """Rolling resistance coefficient f_r [1] of a brush friction source's tire (its
    ``provenance``: tire and grid) at speed ``V`` [m/s], load ``Fz`` [N] and tread temperature
    ``T_K`` (:mod:`tire_brush.rolling_resistance`, on the grid's own compound), or 0 and why
    (another source, a tire file without a ``[rolling_resistance]`` table, a grid without a
    compound)."""
    if provenance.get("model") != "brush":
        return 0.0, "the friction source is not the brush tire"
    from lookup.grid import load_grid
    from tire_brush.params import load_tire
    from tire_brush.rolling_resistance import (
        grid_compound,
        load_rolling_params,
        rolling_resistance,
    )

    params = load_tire(provenance["tire"])
    compound, why = grid_compound(load_grid(provenance["grid"]))
    if compound is None:
        return 0.0, why
    try:
        load_rolling_params(params)
    except InputError as exc:
        return 0.0, exc.message
    return float(rolling_resistance(params, compound, V, Fz, T_K).f_r), ""
