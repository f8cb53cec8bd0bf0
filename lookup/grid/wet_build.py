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

from ..errors import GridError
from .wet import WetGrid

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


def wet_slice(model, v: float, T: np.ndarray, p: np.ndarray, t_drain: np.ndarray
              ) -> dict[str, np.ndarray]:
    """All wet variables at one slip speed: (nd, nT, np) and w_dry (nd, nt, nT, np)."""
    TT, PP = np.meshgrid(T, p, indexing="ij")
    nd = model.depths.size
    out = {n: np.zeros((nd, T.size, p.size)) for n in
           ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0", "mu_wet_hot_w1")}
    out["w_dry"] = np.ones((nd, t_drain.size, T.size, p.size))
    for i in range(nd):
        for wgt in (0.0, 1.0):
            model.at(i, adhesive_weight=None if i == 0 else wgt)
            c, h = model.cold_and_hot(v, TT, PP)
            key = "w1" if wgt else "w0"
            out[f"mu_wet_cold_{key}"][i] = c.mu
            out[f"mu_wet_hot_{key}"][i] = h.mu
            if i == 0:  # dry: both end points are the dry friction
                out["mu_wet_cold_w0"][i] = c.mu
                out["mu_wet_hot_w0"][i] = h.mu
                out["mu_wet_cold_w1"][i] = c.mu
                out["mu_wet_hot_w1"][i] = h.mu
                break
        if i == 0:
            continue
        # one cold evaluation; the other drainage times reuse its separation law
        model.at(i, t_contact=float(t_drain[0]))
        model.cold(v, TT, PP)
        if model.lubricant.adhesion:
            w = model.dry_shares(t_drain)
        else:  # soapy water: no adhesive term at any time
            w = np.zeros((t_drain.size, TT.size))
        out["w_dry"][i] = w.reshape(t_drain.size, *TT.shape)
    return out


def _init(model) -> None:
    global _MODEL
    _MODEL = model


def _work(iv: int, v: float, T, p, t) -> tuple[int, dict[str, np.ndarray]]:
    return iv, wet_slice(_MODEL, v, T, p, t)


def build_wet(spec, workers: int = 1, model: Any = None) -> tuple[WetGrid, float]:
    """Compute the wet branch of ``spec`` (which has a ``[wet]`` table); (WetGrid, wall s)."""
    if not spec.wet:
        raise GridError(f"{spec.source}: the spec has no [wet] table")
    t0 = time.perf_counter()
    model = make_wet_model(spec) if model is None else model
    t_drain = np.asarray(spec.wet["t_drain"], float)
    nv = spec.v.size
    nd = model.depths.size
    data = {n: np.zeros((nd, nv, spec.T.size, spec.p.size)) for n in
            ("mu_wet_cold_w0", "mu_wet_cold_w1", "mu_wet_hot_w0", "mu_wet_hot_w1")}
    data["w_dry"] = np.zeros((nd, t_drain.size, nv, spec.T.size, spec.p.size))

    def put(iv: int, out: dict[str, np.ndarray]) -> None:
        for n, a in out.items():
            if n == "w_dry":
                data[n][:, :, iv] = a
            else:
                data[n][:, iv] = a

    if workers <= 1 or nv <= 1:
        for iv in range(nv):
            put(iv, wet_slice(model, float(spec.v[iv]), spec.T, spec.p, t_drain))
    else:
        methods = multiprocessing.get_all_start_methods()
        ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
        with ProcessPoolExecutor(max_workers=min(workers, nv), mp_context=ctx,
                                 initializer=_init, initargs=(model,)) as pool:
            futs = [pool.submit(_work, iv, float(spec.v[iv]), spec.T, spec.p, t_drain)
                    for iv in np.argsort(-spec.v)]
            for f in futs:
                put(*f.result())
    desc = model.describe()
    meta = {"wet": desc["wet"], "spec_wet": {k: (list(map(float, v)) if k in (
        "water_depth", "t_drain") else v) for k, v in spec.wet.items()},
            "D_m": model.D, "reduction_hot": "mu_wet_hot linear in w between w = 0 and 1 "
                                               "(lookup.grid.wet)"}
    grid = WetGrid({"log10_v": np.log10(spec.v), "T": spec.T, "log10_p": np.log10(spec.p)},
                   {"water_depth": model.depths, "log10_t_drain": np.log10(t_drain)}, data,
                   meta, source=str(spec.source))
    return grid, time.perf_counter() - t0
