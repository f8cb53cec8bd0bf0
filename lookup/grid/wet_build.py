"""Building the wet branch of a grid (:mod:`lookup.grid.wet`), after the dry build.

The spec's ``[wet]`` table (:mod:`lookup.grid.spec`)::

    [wet]
    water_depth = ["0 mm", "1 mm"]   # first node 0 (dry); volume of water per nominal area
    lubricant = "water"              # "water", "soapy_water" or "custom" (with eta, S)
    [wet.t_drain]                    # drainage time axis, log-spaced [s]
    min = "1e-6 s"
    max = "1 s"
    n = 7
    [wet.sealing]                    # optional: lookup.wet.sealing.SealingSettings fields
    n = 512

Slices over the slip speed run in parallel like the dry build (local processes); the wet pass
is not checkpointed (an interrupted build redoes it).
"""

from __future__ import annotations

import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from tirefric.errors import GridError

from .wet import PendingWetGrid, WetGrid

_MODEL: Any = None


def make_wet_model(spec) -> Any:
    """The :class:`~lookup.wet.friction.WetPerssonFriction` of a spec with a ``[wet]`` table."""
    from ..compound import load_compound
    from ..friction import EngineSettings
    from ..surface import load_surface
    from ..wet.friction import WetPerssonFriction
    from ..wet.sealing import SealingSettings
    from ..wet.water import Lubricant

    w = spec.wet
    return WetPerssonFriction(load_compound(spec.compound), load_surface(spec.surface),
                              EngineSettings(**spec.engine), depths=w["water_depth"],
                              lubricant=Lubricant(**w["lubricant"]),
                              sealing=SealingSettings(**w.get("sealing", {})))


def wet_slice(model, v: float, T: np.ndarray, p: np.ndarray, t_drain: np.ndarray,
              dry: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray]:
    """All wet variables at one slip speed: (nd, nT, np) and w_dry (nd, nt, nT, np).

    Depth node 0 is the dry road: both end points are the dry friction and w_dry = 1. Its
    values are ``dry["mu_cold"]``, ``dry["mu_hot"]`` (nT, np) when given (the dry tables of
    the same grid: no second dry solve), NaN when ``dry`` is ``"defer"`` (filled from the grid
    file by :func:`lookup.grid.wet.save_wet`), else computed by the dry engine. The wet
    nodes come from :meth:`lookup.wet.friction.WetPerssonFriction.end_points`.
    """
    TT, PP = np.meshgrid(T, p, indexing="ij")
    nd = model.depths.size
    names = ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0", "mu_wet_hot_w1")
    out = {n: np.zeros((nd, T.size, p.size)) for n in names}
    out["w_dry"] = np.ones((nd, t_drain.size, T.size, p.size))
    if isinstance(dry, str):  # "defer"
        c_mu = h_mu = np.full(TT.shape, np.nan)
    elif dry is not None:
        c_mu, h_mu = dry["mu_cold"], dry["mu_hot"]
    else:
        c, h = model.at(0).cold_and_hot(v, TT, PP)
        c_mu, h_mu = c.mu, h.mu
    for n in names:
        out[n][0] = c_mu if "cold" in n else h_mu
    for i in range(1, nd):
        e = model.at(i).end_points(v, TT, PP, t_drain)
        for n, a in e.items():
            out[n][i] = a
    return out


def _init(model) -> None:
    global _MODEL
    _MODEL = model


def _work(iv: int, v: float, T, p, t, dry) -> tuple[int, dict[str, np.ndarray]]:
    return iv, wet_slice(_MODEL, v, T, p, t, dry)


def build_wet(spec, workers: int = 1, model: Any = None, dry: Any = "defer"
              ) -> tuple[WetGrid | PendingWetGrid, float]:
    """Compute the wet branch of ``spec`` (which has a ``[wet]`` table); (grid, wall s).

    Parameters
    ----------
    spec : GridSpec
    workers : int
        Local processes over the slip-speed slices.
    model : WetPerssonFriction, optional
        The engine (default: :func:`make_wet_model`).
    dry : FrictionGrid, "defer" or "compute"
        Where the depth-0 (dry road) tables come from. A :class:`~lookup.grid.FrictionGrid`
        of the same spec: its ``mu_cold`` and ``mu_hot``, and a complete :class:`WetGrid` is
        returned. ``"defer"`` (what the grid build uses: the dry tables are already in the
        file the branch is appended to): a :class:`~lookup.grid.wet.PendingWetGrid` that
        :func:`~lookup.grid.wet.save_wet` completes from that file. ``"compute"``: solved
        again by the dry engine (a second dry build; for a standalone wet branch).
        The depth-0 values are the dry tables either way (the wet engine at depth 0 is the
        dry engine, bit for bit); reusing them saves one of the three hot solves per node.
    """
    if not spec.wet:
        raise GridError(f"{spec.source}: the spec has no [wet] table")
    if isinstance(dry, str) and dry not in ("defer", "compute"):
        raise GridError(f"dry must be a FrictionGrid, 'defer' or 'compute', not {dry!r}")
    t0 = time.perf_counter()
    model = make_wet_model(spec) if model is None else model
    t_drain = np.asarray(spec.wet["t_drain"], float)
    nv = spec.v.size
    nd = model.depths.size
    if not isinstance(dry, str):
        for name, a in (("log10_v", np.log10(spec.v)), ("T", spec.T),
                        ("log10_p", np.log10(spec.p))):
            b = np.asarray(dry.axes[name], float)
            if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-9):
                raise GridError(f"{spec.source}: the dry grid has other '{name}' nodes than "
                                f"the spec")
    data = {n: np.zeros((nd, nv, spec.T.size, spec.p.size)) for n in
            ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0", "mu_wet_hot_w1")}
    data["w_dry"] = np.zeros((nd, t_drain.size, nv, spec.T.size, spec.p.size))

    def dry_slice(iv: int) -> Any:
        if dry == "defer":
            return "defer"
        if dry == "compute":
            return None
        return {n: np.asarray(dry.variables[n][iv], float) for n in ("mu_cold", "mu_hot")}

    def put(iv: int, out: dict[str, np.ndarray]) -> None:
        for n, a in out.items():
            if n == "w_dry":
                data[n][:, :, iv] = a
            else:
                data[n][:, iv] = a

    if workers <= 1 or nv <= 1:
        for iv in range(nv):
            put(iv, wet_slice(model, float(spec.v[iv]), spec.T, spec.p, t_drain,
                              dry_slice(iv)))
    else:
        methods = multiprocessing.get_all_start_methods()
        ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
        with ProcessPoolExecutor(max_workers=min(workers, nv), mp_context=ctx,
                                 initializer=_init, initargs=(model,)) as pool:
            futs = [pool.submit(_work, iv, float(spec.v[iv]), spec.T, spec.p, t_drain,
                                dry_slice(iv))
                    for iv in np.argsort(-spec.v)]
            for f in futs:
                put(*f.result())
    desc = model.describe()
    meta = {"wet": desc["wet"], "spec_wet": {k: (list(map(float, v)) if k in (
        "water_depth", "t_drain") else v) for k, v in spec.wet.items()},
            "D_m": model.D, "reduction_hot": "mu_wet_hot linear in w between w = 0 and 1 "
                                               "(lookup.grid.wet)",
            "depth_0": "the dry tables mu_cold, mu_hot of the same grid"}
    args = ({"log10_v": np.log10(spec.v), "T": spec.T, "log10_p": np.log10(spec.p)},
            {"water_depth": model.depths, "log10_t_drain": np.log10(t_drain)}, data, meta)
    cls = PendingWetGrid if dry == "defer" else WetGrid
    grid = cls(*args, source=str(spec.source))
    return grid, time.perf_counter() - t0
