"""Grid specifications: which compound, which surface, which axes, which engine settings.

A spec is a small TOML file under ``models/grids/`` (or anywhere)::

    name = "default"
    description = "..."
    provenance = "..."
    compound = "summer"        # shipped name, or a path relative to this file
    surface = "asphalt"        # shipped name, or a path relative to this file

    [axes.v]                   # slip speed, log-spaced (the grid stores log10 v)
    min = "1e-6 m/s"
    max = "40 m/s"
    n = 61

    [axes.T]                   # background temperature, equally spaced
    min = "-20 degC"
    max = "120 degC"
    n = 15

    [axes.p]                   # nominal pressure, log-spaced (the grid stores log10 p)
    min = "0.05 MPa"
    max = "2 MPa"
    n = 6

    [engine]                   # optional: lookup.friction.EngineSettings fields
    q_per_decade = 24

Instead of ``min``/``max``/``n`` an axis may list its nodes: ``values = [...]`` (ascending).
Bare numbers are SI (m/s, K, Pa); strings ``"<number> <unit>"`` convert.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tirefric.config import Table
from tirefric.errors import InputError
from tirefric.paths import resolve_model_file

#: Axis table name -> (dimension for unit conversion, spacing, lower bound on n).
AXIS_SPECS: dict[str, tuple[str, str, int]] = {
    "v": ("velocity", "log", 2),
    "T": ("temperature", "linear", 2),
    "p": ("pressure", "log", 2),
}


@dataclass(frozen=True)
class GridSpec:
    """A validated grid specification.

    Attributes
    ----------
    name : str
        Grid name (the default output file stem).
    compound, surface : str
        Compound and surface: a shipped name or a resolved file path.
    v : numpy.ndarray
        Slip-speed nodes [m/s], ascending, log-spaced unless listed.
    T : numpy.ndarray
        Background-temperature nodes [K], ascending.
    p : numpy.ndarray
        Nominal-pressure nodes [Pa], ascending, log-spaced unless listed.
    engine : dict
        Keyword arguments of :class:`lookup.friction.EngineSettings`.
    wet : dict or None
        The validated ``[wet]`` table (:mod:`lookup.grid.wet_build`): ``water_depth`` [m],
        ``t_drain`` [s], ``lubricant`` (keyword arguments of :class:`lookup.wet.Lubricant`),
        optional ``sealing``; None for a dry-only grid.
    description, provenance : str
        Free text.
    source : str
        The spec file (or ``"<dict>"``).
    """

    name: str
    compound: str
    surface: str
    v: np.ndarray
    T: np.ndarray
    p: np.ndarray
    engine: dict[str, Any] = field(default_factory=dict)
    description: str = ""
    provenance: str = ""
    source: str = "<dict>"
    wet: dict[str, Any] | None = None

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(nv, nT, np)``."""
        return (self.v.size, self.T.size, self.p.size)

    @property
    def n_points(self) -> int:
        """Number of grid nodes."""
        return int(np.prod(self.shape))

    def to_dict(self) -> dict[str, Any]:
        """JSON-able form (stored in the grid's metadata as ``spec``)."""
        d = {"name": self.name, "compound": self.compound, "surface": self.surface,
             "v_m_s": self.v.tolist(), "T_K": self.T.tolist(), "p_Pa": self.p.tolist(),
             "engine": dict(self.engine), "description": self.description,
             "provenance": self.provenance, "source": self.source}
        if self.wet:
            d["wet"] = {k: (np.asarray(v).tolist() if k in ("water_depth", "t_drain") else v)
                        for k, v in self.wet.items()}
        return d

    def with_axes(self, *, v: Any = None, T: Any = None, p: Any = None) -> GridSpec:
        """A copy with some axes replaced (e.g. a reduced grid for a quick check)."""
        return GridSpec(self.name, self.compound, self.surface,
                        self.v if v is None else np.asarray(v, float),
                        self.T if T is None else np.asarray(T, float),
                        self.p if p is None else np.asarray(p, float),
                        dict(self.engine), self.description, self.provenance, self.source,
                        self.wet)


def _model_ref(t: Table, key: str, kind: str) -> str:
    """A compound/surface reference: a path relative to the spec, or a shipped name."""
    value = t.string(key)
    p = Path(value)
    if not p.is_absolute():
        p = t.source.parent / p
    if p.is_file():
        return str(p)
    try:
        resolve_model_file(value, kind)
    except InputError as exc:
        raise t.error(key, exc.message, value) from None
    return value


def _axis(t: Table, key: str) -> np.ndarray:
    dim, spacing, n_min = AXIS_SPECS[key]
    a = t.table(key)
    if a.has("values"):
        values = a.array("values", dim, positive=spacing == "log", increasing=True,
                         min_length=n_min)
        a.check_unknown()
        return values
    lo = a.quantity("min", dim, positive=True)
    hi = a.quantity("max", dim, positive=True)
    n = a.integer("n", minimum=n_min)
    a.check_unknown()
    if not hi > lo:
        raise a.error("max", f"must exceed min ({lo:g} SI)", hi)
    if spacing == "log":
        values = np.geomspace(lo, hi, n)
    else:
        values = np.linspace(lo, hi, n)
    values[0], values[-1] = lo, hi
    return values


def load_spec(path: str | Path) -> GridSpec:
    """Read and validate a grid spec TOML (a path, or a shipped spec name such as ``default``).

    Raises
    ------
    InputError
        Missing or misspelt fields, unknown units, non-positive or non-ascending axes, an
        unknown compound or surface; the message names the file, the field and the value.
    """
    path = resolve_model_file(path, "grids")
    t = Table.load(path)
    name = t.string("name", default=path.stem)
    description = t.string("description", default="")
    provenance = t.string("provenance", default="")
    compound = _model_ref(t, "compound", "compounds")
    surface = _model_ref(t, "surface", "surfaces")
    axes = t.table("axes")
    v, T, p = (_axis(axes, k) for k in ("v", "T", "p"))
    axes.check_unknown()
    engine_t = t.table("engine", required=False)
    engine = dict(engine_t.data) if engine_t is not None else {}
    wet = _wet_table(t)
    t.check_unknown(extra_allowed=("engine",))
    spec = GridSpec(name, compound, surface, v, T, p, engine, description, provenance,
                    str(path), wet)
    _check_engine(spec)
    return spec


def _wet_table(t: Table) -> dict[str, Any] | None:
    """The optional ``[wet]`` table (:mod:`lookup.grid.wet_build`), validated."""
    w = t.table("wet", required=False)
    if w is None:
        return None
    depth = w.array("water_depth", "length", increasing=True, min_length=2)
    if depth[0] != 0.0:
        raise w.error("water_depth", "the first node must be 0 (the dry road)", w.raw(
            "water_depth"))
    if (depth < 0).any():
        raise w.error("water_depth", "water film depth must be >= 0", w.raw("water_depth"))
    name = w.string("lubricant", default="water")
    lub: dict[str, Any] = {"name": name}
    if w.has("eta"):
        lub["eta"] = w.quantity("eta", "dimensionless")
    if w.has("S"):
        lub["S"] = w.quantity("S", "dimensionless")
    try:
        from ..wet.water import Lubricant

        Lubricant(**lub)
    except InputError as exc:
        raise InputError(exc.message, source=t.source, field=exc.field, value=exc.value
                         ) from None
    ta = w.table("t_drain")
    if ta.has("values"):
        t_drain = ta.array("values", "time", positive=True, increasing=True, min_length=2)
    else:
        lo = ta.quantity("min", "time", positive=True)
        hi = ta.quantity("max", "time", positive=True)
        n = ta.integer("n", minimum=2)
        if not hi > lo:
            raise ta.error("max", f"must exceed min ({lo:g} s)", hi)
        t_drain = np.geomspace(lo, hi, n)
    ta.check_unknown()
    out: dict[str, Any] = {"water_depth": depth, "t_drain": t_drain, "lubricant": lub}
    st = w.table("sealing", required=False)
    if st is not None:
        out["sealing"] = dict(st.data)
        try:
            from ..wet.sealing import SealingSettings

            SealingSettings(**out["sealing"])
        except TypeError as exc:
            raise InputError(f"unknown sealing setting ({exc})", source=t.source,
                             field="wet.sealing") from None
    w.check_unknown(extra_allowed=("sealing",))
    return out


def _check_engine(spec: GridSpec) -> None:
    """Refuse unknown ``[engine]`` keys early (before any worker starts)."""
    from dataclasses import fields

    try:
        from ..friction import EngineSettings
    except ImportError:  # engine not installed in this environment: checked at build time
        return
    known = {f.name for f in fields(EngineSettings)}
    unknown = sorted(set(spec.engine) - known)
    if unknown:
        raise InputError(f"unknown engine setting(s) {unknown} (known: {', '.join(sorted(known))})",
                         source=spec.source, field="engine")
    try:
        EngineSettings(**spec.engine)
    except InputError as exc:  # name the spec file as well as the field and value
        raise InputError(exc.message, source=spec.source, field=exc.field,
                         value=exc.value) from None
    except TypeError as exc:
        raise InputError(f"wrong type ({exc})", source=spec.source, field="engine") from None
