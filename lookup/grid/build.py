"""Building friction grids: parallel over slip-speed slices, resumable, local or on Dask.

One task computes one *slice*: every (T0, p) node at one slip speed, through the engine's
``grid_slice(v, T0, p) -> {name: (nT, np) array}`` (:meth:`lookup.friction.PerssonFriction.
grid_slice`). Slices are independent, so the build is embarrassingly parallel:

* ``workers == 1``: in this process;
* ``workers > 1``: a local :class:`concurrent.futures.ProcessPoolExecutor` (the model is sent
  to each worker once, at start-up);
* ``scheduler``: an existing Dask distributed cluster (address, or a ``distributed.Client``);
  the model is scattered to every worker once.

Every task computes a slice from the model and its own speed only, so the result does not
depend on how the slices are distributed: serial, process-pool and Dask builds give identical
numbers (tested).

Resuming: finished slices are written, as they arrive, to a checkpoint next to the output
(``<output>.partial.npz``, replaced atomically), together with a fingerprint of the spec and
the model description. A build started again with the same output skips the slices found
there; a checkpoint with a different fingerprint is set aside (renamed ``*.stale.npz``), not
reused. The checkpoint is removed when the grid file has been written.
"""

from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import os
import signal
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from tirefric.errors import GridError, InputError

from .reader import (
    ALL_VARIABLES,
    DIAGNOSTIC_VARIABLES,
    VARIABLES,
    FrictionGrid,
    _json_default,
    round_to_float32,
)
from .spec import GridSpec, load_spec
from .store import package_version, save_grid, utc_now


class SliceModel(Protocol):
    """What the builder needs from a friction model (``lookup.friction.PerssonFriction``)."""

    def grid_slice(self, v: float, T0: np.ndarray, sigma0: np.ndarray
                   ) -> dict[str, np.ndarray]: ...

    def describe(self) -> dict[str, Any]: ...


def make_model(spec: GridSpec) -> SliceModel:
    """The Persson engine for a spec: compound, surface and ``[engine]`` settings."""
    from ..compound import load_compound
    from ..friction import EngineSettings, PerssonFriction
    from ..surface import load_surface

    try:
        settings = EngineSettings(**spec.engine)
    except TypeError as exc:
        raise InputError(f"bad engine settings: {exc}", source=spec.source,
                         field="engine") from None
    return PerssonFriction(load_compound(spec.compound), load_surface(spec.surface),
                           settings=settings)


# -- one slice ---------------------------------------------------------------------------------
def compute_slice(model: SliceModel, v: float, T: np.ndarray, p: np.ndarray
                  ) -> dict[str, np.ndarray]:
    """Run ``model.grid_slice`` at one speed; float64 arrays of shape ``(nT, np)``, checked.

    Raises
    ------
    GridError
        A variable is missing, has the wrong shape or a non-finite value (named with v, T, p).
    """
    out = model.grid_slice(float(v), np.asarray(T, float), np.asarray(p, float))
    missing = [n for n in VARIABLES if n not in out]
    if missing:
        raise GridError(f"the model's grid_slice at v = {v:g} m/s did not return {missing}")
    res = {n: np.asarray(out[n], dtype=float) for n in ALL_VARIABLES if n in out}
    shape = (np.size(T), np.size(p))
    for n, a in res.items():
        if a.shape != shape:
            raise GridError(f"the model's grid_slice at v = {v:g} m/s returned {n} with shape "
                            f"{a.shape}, expected {shape} = (T, p)")
        if not np.isfinite(a).all():
            j, k = (int(x) for x in np.argwhere(~np.isfinite(a))[0])
            raise GridError(f"the model returned a non-finite {n} = {a[j, k]!r} at "
                            f"v = {v:g} m/s, T = {T[j]:g} K, p = {p[k]:g} Pa")
    return res


# -- the task runner (shared by the grid build and the compound screening) -------------------
_WORKER_SHARED: Any = None


def _init_worker(shared: Any) -> None:
    global _WORKER_SHARED
    _WORKER_SHARED = shared
    # Ctrl-C goes to the whole process group: let the parent handle it (checkpoint, then stop
    # the pool) instead of every worker dying with a KeyboardInterrupt of its own
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _pool_call(func: Callable[..., Any], args: tuple[Any, ...]) -> Any:
    if _WORKER_SHARED is None:
        raise RuntimeError("worker process was not initialised with its shared object")
    return func(_WORKER_SHARED, *args)


def _dask_call(func: Callable[..., Any], shared: Any, args: tuple[Any, ...]) -> Any:
    return func(shared, *args)


def pool_size(n_tasks: int, workers: int, scheduler: Any = None) -> int:
    """Where :func:`run_tasks` runs ``n_tasks`` tasks: 0 on a Dask scheduler, 1 in this
    process, else the number of local processes."""
    if scheduler is not None:
        return 0
    return 1 if workers <= 1 or n_tasks <= 1 else min(workers, n_tasks)


def pool_label(size: int) -> str:
    """A :func:`pool_size` in words, for progress bars and reports: ``"dask"``,
    ``"serial"`` or ``"N processes"``."""
    return {0: "dask", 1: "serial"}.get(size, f"{size} processes")


class TaskRun:
    """The results of :func:`run_tasks` as they finish (iterate it), and where they run:
    :attr:`size` (:func:`pool_size`: 0 on a Dask scheduler, 1 in this process, else the
    number of local processes) and :attr:`where` (the same in words)."""

    def __init__(self, size: int, results: Iterator[Any]) -> None:
        self.size = size
        self._results = results

    @property
    def where(self) -> str:
        """:attr:`size` in words (:func:`pool_label`)."""
        return pool_label(self.size)

    def __iter__(self) -> Iterator[Any]:
        return self._results

    def close(self) -> None:
        """Drop the queued tasks and let the running ones end (nothing half-done is
        yielded)."""
        self._results.close()


def run_tasks(func: Callable[..., Any], shared: Any, tasks: list[tuple[Any, ...]], *,
              workers: int = 1, scheduler: Any = None) -> TaskRun:
    """Run ``func(shared, *task)`` for every task; the returned :class:`TaskRun` yields the
    results as they finish and says where they run.

    ``shared`` (the friction model of a grid build, the settings of a screening) is sent to
    each worker once, the tasks carry only their own small arguments. ``func`` must be a
    module-level function (picklable) whose result depends on its arguments only, so that
    where it runs does not change the numbers:

    * ``scheduler`` given: an existing Dask distributed cluster (address, or a
      ``distributed.Client``); ``shared`` is scattered to every worker once;
    * else ``workers == 1`` or a single task: in this process, in the given order;
    * else a local :class:`concurrent.futures.ProcessPoolExecutor` of ``min(workers,
      len(tasks))`` processes (fork where available: the workers inherit the imported
      modules), ``shared`` passed once per worker through the initialiser.

    Nothing runs before the first result is asked for. Closing the run early
    (:meth:`TaskRun.close`, an interruption, an exception in the consumer) drops the queued
    tasks and lets the running ones end; nothing half-done is yielded.
    """
    n = pool_size(len(tasks), workers, scheduler)
    return TaskRun(n, _results(func, shared, tasks, n, scheduler))


def _results(func: Callable[..., Any], shared: Any, tasks: list[tuple[Any, ...]], n: int,
             scheduler: Any) -> Iterator[Any]:
    """The results of :func:`run_tasks` on a pool of :func:`pool_size` ``n``."""
    if n == 0:
        yield from _run_dask(func, shared, tasks, scheduler)
    elif n == 1:
        for args in tasks:
            yield func(shared, *args)
    else:
        yield from _run_pool(func, shared, tasks, n)


def _run_pool(func: Callable[..., Any], shared: Any, tasks: list[tuple[Any, ...]],
              workers: int) -> Iterator[Any]:
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                               initargs=(shared,))
    try:
        pending = {pool.submit(_pool_call, func, args) for args in tasks}
        while pending:
            finished, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in finished:
                yield fut.result()
    finally:
        # on an interruption: drop queued tasks, let running ones end, keep nothing half-done
        pool.shutdown(wait=True, cancel_futures=True)


def _run_dask(func: Callable[..., Any], shared: Any, tasks: list[tuple[Any, ...]],
              scheduler: Any) -> Iterator[Any]:
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        shared_f = client.scatter(shared, broadcast=True)
        futures = [client.submit(_dask_call, func, shared_f, args, pure=False)
                   for args in tasks]
        try:
            for fut in as_completed(futures):
                yield fut.result()
        finally:
            client.cancel(futures)
    finally:
        if own:
            client.close()


def _timed_slice(model: SliceModel, iv: int, v: float, T: np.ndarray, p: np.ndarray
                 ) -> tuple[int, dict[str, np.ndarray], float]:
    """One slice of a grid build, with its compute time (a task of :func:`run_tasks`)."""
    t0 = time.perf_counter()
    out = compute_slice(model, v, T, p)
    return iv, out, time.perf_counter() - t0


# -- checkpoint --------------------------------------------------------------------------------
def fingerprint(spec: GridSpec, description: dict[str, Any]) -> str:
    """SHA-256 over the spec's axes and the model description: what a slice depends on."""
    h = hashlib.sha256()
    for a in (spec.v, spec.T, spec.p):
        h.update(np.ascontiguousarray(a, dtype="<f8").tobytes())
    h.update(json.dumps(description, sort_keys=True, default=_json_default).encode())
    return h.hexdigest()


@dataclass
class Checkpoint:
    """Finished slices of an interrupted build (``<output>.partial.npz``)."""

    path: Path
    fingerprint: str
    shape: tuple[int, int, int]

    def __post_init__(self) -> None:
        self.done = np.zeros(self.shape[0], dtype=bool)
        self.data = {n: np.zeros(self.shape) for n in ALL_VARIABLES}
        # which slices returned each diagnostic variable (a grid keeps those all slices have)
        self.diag = np.zeros((self.shape[0], len(DIAGNOSTIC_VARIABLES)), dtype=bool)
        self.seconds = np.zeros(self.shape[0])

    @classmethod
    def for_output(cls, output: Path) -> Path:
        """The checkpoint path belonging to an output file."""
        return output.with_name(output.name + ".partial.npz")

    def load(self) -> bool:
        """Read finished slices; False (and the file set aside) if it belongs to another build."""
        if not self.path.is_file():
            return False
        try:
            with np.load(self.path, allow_pickle=False) as z:
                fp = str(z["fingerprint"])
                done = z["done"]
                data = {n: z[n] for n in ALL_VARIABLES}
                diag = z["diagnostics"]
                seconds = z["seconds"]
        except (OSError, ValueError, KeyError, EOFError) as exc:
            self._set_aside(f"unreadable ({type(exc).__name__})")
            return False
        if fp != self.fingerprint or done.shape != (self.shape[0],) or any(
                a.shape != self.shape for a in data.values()) or diag.shape != self.diag.shape:
            self._set_aside("written by a build with another spec or model")
            return False
        self.done, self.data, self.seconds = done.astype(bool), data, seconds
        self.diag = diag.astype(bool)
        return True

    def _set_aside(self, why: str) -> None:
        stale = self.path.with_name(self.path.name.replace(".partial.npz", ".stale.npz"))
        os.replace(self.path, stale)
        print(f"tirefric grid build: checkpoint {self.path} {why}; moved to {stale}, "
              f"starting afresh", file=sys.stderr)

    def put(self, iv: int, out: dict[str, np.ndarray], seconds: float) -> None:
        """Store a finished slice."""
        for n in ALL_VARIABLES:
            if n in out:
                self.data[n][iv] = out[n]
        self.diag[iv] = [n in out for n in DIAGNOSTIC_VARIABLES]
        self.done[iv] = True
        self.seconds[iv] = seconds

    def variables(self) -> dict[str, np.ndarray]:
        """The grid's variables: :data:`VARIABLES` and the diagnostic ones that every slice
        returned."""
        keep = {n for k, n in enumerate(DIAGNOSTIC_VARIABLES) if self.diag[:, k].all()}
        return {n: a for n, a in self.data.items()
                if n not in DIAGNOSTIC_VARIABLES or n in keep}

    def save(self) -> None:
        """Write atomically (temporary file, then rename)."""
        tmp = self.path.with_name(f".{self.path.name}.tmp-{os.getpid()}")
        with open(tmp, "wb") as fh:
            np.savez(fh, fingerprint=np.array(self.fingerprint), done=self.done,
                     seconds=self.seconds, diagnostics=self.diag, **self.data)
        os.replace(tmp, self.path)

    def remove(self) -> None:
        """Delete the checkpoint (after the grid file is written)."""
        if self.path.exists():
            self.path.unlink()


# -- the build ---------------------------------------------------------------------------------
@dataclass
class BuildReport:
    """What a build did: slices computed and reused, wall and CPU time, throughput."""

    output: Path
    n_slices: int
    n_computed: int
    n_reused: int
    wall_s: float
    slice_cpu_s: float
    workers: int
    points_per_slice: int

    @property
    def points_per_s_per_core(self) -> float:
        """Grid nodes (cold and hot) per second of one core, from the slice compute times."""
        if self.slice_cpu_s <= 0:
            return math.nan
        return self.n_computed * self.points_per_slice / self.slice_cpu_s

    def as_dict(self) -> dict[str, Any]:
        """JSON-able form."""
        return {"output": str(self.output), "n_slices": self.n_slices,
                "n_computed": self.n_computed, "n_reused": self.n_reused,
                "wall_s": self.wall_s, "slice_cpu_s": self.slice_cpu_s,
                "workers": self.workers, "points_per_s_per_core": self.points_per_s_per_core}


def _progress(total: int, initial: int, enabled: bool, desc: str):
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, unit="slice", desc=desc, disable=not enabled,
                dynamic_ncols=True, smoothing=0.1)


def build_grid(
    spec: GridSpec | str | Path,
    output: str | Path,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    model: SliceModel | None = None,
    progress: bool = True,
    resume: bool = True,
    checkpoint_every_s: float = 2.0,
    on_slice: Callable[[int], None] | None = None,
    single_precision: bool = True,
) -> tuple[FrictionGrid, BuildReport]:
    """Build a friction grid and write it to ``output`` (``.nc``, or ``.npz`` for numpy only).

    Parameters
    ----------
    spec
        A :class:`GridSpec`, or a spec file / shipped spec name.
    output
        The grid file to write.
    workers
        Local worker processes (default: the CPU count); 1 computes in this process. Ignored
        with ``scheduler``.
    scheduler
        Address of a Dask distributed scheduler, or a ``distributed.Client``.
    model
        The friction model (default: :func:`make_model` of the spec). Anything with
        ``grid_slice`` and ``describe`` (:class:`SliceModel`) and picklable.
    progress
        Show a progress bar with ETA (tqdm, on stderr).
    resume
        Reuse finished slices of an interrupted build of the same spec (see module docstring).
    checkpoint_every_s
        Minimum time between checkpoint writes [s] (the last slice is always written).
    on_slice
        Called with each finished slice index (after it is checkpointed); for tests and
        monitoring.
    single_precision
        Round the results to float32 precision (relative 6e-8, far below the interpolation
        error) so that the file stores them as float32, half the size; the grid in memory is
        float64 either way.

    Returns
    -------
    (FrictionGrid, BuildReport)
    """
    if not isinstance(spec, GridSpec):
        spec = load_spec(spec)
    output = Path(output)
    if output.suffix not in (".nc", ".npz"):
        raise InputError("grid output must end in .nc (NetCDF-4) or .npz (numpy)",
                         source=str(output))
    if spec.wet and output.suffix != ".nc":
        raise InputError("a grid with a [wet] branch is written as NetCDF-4 (.nc)",
                         source=str(output))
    if not output.parent.is_dir():
        raise InputError("output folder does not exist", source=str(output.parent))
    if workers is not None and workers < 1:
        raise InputError("must be >= 1", source="--workers", value=workers)
    model = make_model(spec) if model is None else model
    description = model.describe()
    nv, nT, np_ = spec.shape
    ckpt = Checkpoint(Checkpoint.for_output(output), fingerprint(spec, description),
                      spec.shape)
    if resume:
        ckpt.load()
    elif ckpt.path.exists():
        ckpt.remove()
    n_reused = int(ckpt.done.sum())
    # slowest slices (high speed: long hot solves) first, for a balanced finish
    remaining = [int(i) for i in np.argsort(-spec.v, kind="stable") if not ckpt.done[i]]
    n_workers = 1 if scheduler is None and workers == 1 else (
        workers or os.cpu_count() or 1)
    tasks = [(iv, float(spec.v[iv]), spec.T, spec.p) for iv in remaining]
    runner = run_tasks(_timed_slice, model, tasks, workers=n_workers, scheduler=scheduler)
    where = runner.where
    t_start = time.perf_counter()
    last_save = t_start
    cpu = 0.0
    bar = _progress(nv, n_reused, progress, f"grid {spec.name} ({where})")
    try:
        for iv, out, seconds in runner:
            ckpt.put(iv, out, seconds)
            cpu += seconds
            bar.update(1)
            bar.set_postfix(pts_per_s_core=f"{(bar.n - n_reused) * nT * np_ / max(cpu, 1e-9):.0f}",
                            refresh=False)
            now = time.perf_counter()
            if now - last_save >= checkpoint_every_s or ckpt.done.all():
                ckpt.save()
                last_save = now
            if on_slice is not None:
                on_slice(iv)
    except BaseException:
        if ckpt.done.any():
            ckpt.save()
        raise
    finally:
        bar.close()
        runner.close()
    wall = time.perf_counter() - t_start
    if not ckpt.done.all():
        raise GridError(f"build of {output} incomplete: {int((~ckpt.done).sum())} slices "
                        f"missing")
    meta = grid_metadata(spec, description)
    meta["build"] = {"wall_s": wall, "slice_cpu_s": float(ckpt.seconds.sum()),
                     "runner": where, "resumed_slices": n_reused}
    variables = ckpt.variables()
    data = ({n: round_to_float32(a) for n, a in variables.items()} if single_precision
            else variables)
    meta["precision"] = "float32" if single_precision else "float64"
    meta["outside_band"] = outside_summary(spec, description, variables)
    grid = FrictionGrid(np.log10(spec.v), spec.T, np.log10(spec.p), data, meta,
                        source=str(output))
    if output.suffix == ".npz":
        grid.save_npz(output)
    else:
        save_grid(grid, output)
        if spec.wet:  # the wet branch, appended to the same file (lookup.grid.wet)
            from .wet import save_wet
            from .wet_build import build_wet

            wet, wet_s = build_wet(spec, workers=1 if where == "serial" else n_workers)
            wet.meta["build"] = {"wall_s": wet_s}
            save_wet(output, wet)
    ckpt.remove()
    report = BuildReport(output, nv, nv - n_reused, n_reused, wall, cpu,
                         1 if where == "serial" else n_workers, nT * np_)
    return grid, report


def outside_summary(spec: GridSpec, description: dict[str, Any],
                    variables: dict[str, np.ndarray]) -> dict[str, Any]:
    """What the grid took from outside its master curve's measured band (metadata).

    The per-node shares are the grid variables ``outside_cold`` and ``outside_hot`` (present
    for a tabulated master curve); this is their summary: the band, the largest share of
    each branch and where it is, and how many nodes exceed the engine's warning share
    (lookup.friction module docstring, docs/engine-inputs.md)."""
    from ..friction import OUTSIDE_WARNING_SHARE

    band = description.get("measured_band_rad_s")
    out: dict[str, Any] = {
        "definition": "share of each node's friction integrand (review eqs. 17 and 19) at "
                      "reduced frequencies outside the master curve's measured band; per "
                      "node in the variables outside_cold, outside_hot (lookup.friction, "
                      "docs/engine-inputs.md)",
        "measured_band_rad_s": band, "warning_share": OUTSIDE_WARNING_SHARE}
    if band is None:
        out.update(max_cold=0.0, max_hot=0.0, nodes_above_warning=0,
                   note="analytic master curve: defined at every frequency, nothing "
                        "extrapolated")
        return out
    for b in ("cold", "hot"):
        a = variables.get(f"outside_{b}")
        if a is None:
            out[f"max_{b}"] = None
            continue
        i, j, k = np.unravel_index(int(np.argmax(a)), a.shape)
        out[f"max_{b}"] = float(a[i, j, k])
        out[f"worst_{b}"] = {"v_m_s": float(spec.v[i]), "T_K": float(spec.T[j]),
                             "p_Pa": float(spec.p[k])}
        out[f"nodes_above_warning_{b}"] = int((a > OUTSIDE_WARNING_SHARE).sum())
    return out


def grid_metadata(spec: GridSpec, description: dict[str, Any]) -> dict[str, Any]:
    """Provenance of a grid built from ``spec`` by a model with ``description``."""
    d = json.loads(json.dumps(description, default=_json_default))
    compound = d.get("compound", {})
    surface = d.get("surface", {})
    return {
        "s0_m": float(d["s0_m"]), "D_m": float(d["D_m"]),
        "q1_per_m": d.get("q1_per_m"), "q1_rule": d.get("q1_rule"),
        "compound_name": compound.get("name") if isinstance(compound, dict) else str(compound),
        "surface_name": surface.get("name") if isinstance(surface, dict) else str(surface),
        "compound": compound, "surface": surface,
        "engine_settings": d.get("settings", {}),
        "engine": {k: v for k, v in d.items()
                   if k not in ("compound", "surface", "settings")},
        "spec": spec.to_dict(), "package_version": package_version(), "created": utc_now(),
        "history": "tirefric grid build " + (spec.source if spec.source else spec.name),
    }
