"""Grid builds (:mod:`lookup.grid.build`): serial, process pool and Dask give identical grids;
interrupted builds resume without recomputing finished slices.

The build machinery is tested with :class:`AnalyticSliceModel`, a test double with the engine's
``grid_slice`` / ``describe`` API (cheap and exactly reproducible); one test builds a tiny grid
with the real Persson engine.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field

import numpy as np
import pytest

from lookup.grid import load_grid
from lookup.grid.build import Checkpoint, build_grid, fingerprint
from lookup.grid.reader import VARIABLES, round_to_float32
from lookup.grid.spec import GridSpec, load_spec
from tirefric.errors import GridError, InputError


@dataclass
class AnalyticSliceModel:
    """Test double of ``lookup.friction.PerssonFriction``: closed-form, picklable."""

    scale: float = 1.0
    calls: list = field(default_factory=list)

    def grid_slice(self, v, T0, sigma0):
        self.calls.append(float(v))
        lv = np.log10(v)
        T = np.asarray(T0, float)[:, None]
        lp = np.log10(np.asarray(sigma0, float))[None, :]
        base = self.scale * (1.0 + 0.1 * np.sin(lv + 0.01 * T) * (lp - 4.0))
        out = {n: base * (k + 1) for k, n in enumerate(VARIABLES)}
        out["residual_hot"] = 0.0 * base
        return out

    def describe(self):
        return {"compound": {"name": "analytic"}, "surface": {"name": "none"},
                "settings": {"scale": self.scale}, "q1_per_m": 1e5,
                "q1_rule": {"rule": "fixed"}, "D_m": 1e-3, "s0_m": 2e-4}


def small_spec(nv: int = 9) -> GridSpec:
    return GridSpec("test", "analytic", "none", np.geomspace(1e-6, 40.0, nv),
                    np.linspace(253.15, 393.15, 4), np.geomspace(5e4, 2e6, 3))


def expected(spec: GridSpec, scale: float = 1.0) -> dict:
    """Direct slice evaluation, rounded to float32 as builds round by default."""
    m = AnalyticSliceModel(scale)
    return {n: round_to_float32(np.stack([m.grid_slice(v, spec.T, spec.p)[n] for v in spec.v]))
            for n in VARIABLES}


def check_equal(grid, ref, what):
    for n in VARIABLES:
        np.testing.assert_array_equal(grid[n], ref[n], err_msg=f"{what}: {n}")


def test_serial_build(tmp_path):
    spec = small_spec()
    grid, report = build_grid(spec, tmp_path / "g.nc", workers=1,
                              model=AnalyticSliceModel(), progress=False)
    check_equal(grid, expected(spec), "serial build equals direct slice evaluation")
    assert report.n_computed == spec.v.size and report.n_reused == 0
    loaded = load_grid(tmp_path / "g.nc")
    assert loaded.hash == grid.hash, "the written file holds the built grid"
    assert loaded.meta["compound_name"] == "analytic" and loaded.D_m == 1e-3
    assert loaded.meta["spec"]["T_K"] == spec.T.tolist(), "the spec is part of the metadata"
    assert not Checkpoint.for_output(tmp_path / "g.nc").exists(), "checkpoint removed at end"


def test_process_pool_identical_to_serial(tmp_path):
    spec = small_spec()
    serial, _ = build_grid(spec, tmp_path / "s.nc", workers=1, model=AnalyticSliceModel(),
                           progress=False)
    pooled, report = build_grid(spec, tmp_path / "p.nc", workers=2,
                                model=AnalyticSliceModel(), progress=False)
    assert report.workers == 2
    assert pooled.hash == serial.hash, "2-process build is bit-identical to the serial build"


def test_double_precision_build(tmp_path):
    spec = small_spec(3)
    grid, _ = build_grid(spec, tmp_path / "g.nc", workers=1, model=AnalyticSliceModel(),
                         progress=False, single_precision=False)
    m = AnalyticSliceModel()
    direct = np.stack([m.grid_slice(v, spec.T, spec.p)["mu_hot"] for v in spec.v])
    np.testing.assert_array_equal(grid["mu_hot"], direct, err_msg="float64 kept on request")
    assert load_grid(tmp_path / "g.nc").hash == grid.hash, "float64 storage round trip"


def test_npz_output(tmp_path):
    spec = small_spec(3)
    grid, _ = build_grid(spec, tmp_path / "g.npz", workers=1, model=AnalyticSliceModel(),
                         progress=False)
    assert load_grid(tmp_path / "g.npz").hash == grid.hash


class Interrupt(Exception):
    pass


def test_resume_after_interruption(tmp_path):
    spec = small_spec(9)
    out = tmp_path / "g.nc"
    done: list[int] = []

    def stop_after_four(iv):
        done.append(iv)
        if len(done) == 4:
            raise Interrupt

    with pytest.raises(Interrupt):
        build_grid(spec, out, workers=1, model=AnalyticSliceModel(), progress=False,
                   on_slice=stop_after_four)
    ck = Checkpoint.for_output(out)
    assert ck.exists() and not out.exists(), "an interrupted build leaves only its checkpoint"
    model = AnalyticSliceModel()
    grid, report = build_grid(spec, out, workers=1, model=model, progress=False)
    assert report.n_reused == 4 and report.n_computed == 5, "finished slices are reused"
    assert sorted(model.calls) == sorted(float(spec.v[i]) for i in range(9) if i not in done), \
        "only the missing slices are computed again"
    check_equal(grid, expected(spec), "resumed build equals a fresh build")
    assert not ck.exists()


def test_stale_checkpoint_not_reused(tmp_path):
    spec = small_spec(5)
    out = tmp_path / "g.nc"

    def stop(iv):
        raise Interrupt

    with pytest.raises(Interrupt):
        build_grid(spec, out, workers=1, model=AnalyticSliceModel(), progress=False,
                   on_slice=stop)
    # same output, different model: the checkpoint must not be mixed in
    grid, report = build_grid(spec, out, workers=1, model=AnalyticSliceModel(scale=2.0),
                              progress=False)
    assert report.n_reused == 0, "a checkpoint of another model is set aside"
    check_equal(grid, expected(spec, 2.0), "no slice of the other model is used")
    assert (tmp_path / "g.nc.stale.npz").exists()


def test_fingerprint_depends_on_axes_and_model():
    spec = small_spec(5)
    d = AnalyticSliceModel().describe()
    f0 = fingerprint(spec, d)
    assert fingerprint(spec.with_axes(T=spec.T + 1), d) != f0
    assert fingerprint(spec, AnalyticSliceModel(2.0).describe()) != f0
    assert fingerprint(small_spec(5), d) == f0


class BadModel(AnalyticSliceModel):
    def grid_slice(self, v, T0, sigma0):
        out = super().grid_slice(v, T0, sigma0)
        if v > 1.0:
            out["mu_hot"] = out["mu_hot"] * np.nan
        return out


def test_nonfinite_slice_refused(tmp_path):
    with pytest.raises(GridError, match="non-finite mu_hot"):
        build_grid(small_spec(5), tmp_path / "g.nc", workers=1, model=BadModel(),
                   progress=False)
    assert not (tmp_path / "g.nc").exists(), "no grid file from a failed build"


def test_bad_output_and_workers(tmp_path):
    with pytest.raises(InputError, match=r"\.nc"):
        build_grid(small_spec(3), tmp_path / "g.txt", model=AnalyticSliceModel())
    with pytest.raises(InputError, match=">= 1"):
        build_grid(small_spec(3), tmp_path / "g.nc", workers=0, model=AnalyticSliceModel())


def test_dask_local_cluster_identical_to_serial(tmp_path):
    distributed = pytest.importorskip("distributed")
    import cloudpickle

    # the double lives in this test module, which dask worker processes cannot import:
    # ship it by value
    cloudpickle.register_pickle_by_value(sys.modules[AnalyticSliceModel.__module__])
    spec = small_spec(9)
    serial, _ = build_grid(spec, tmp_path / "s.nc", workers=1, model=AnalyticSliceModel(),
                           progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        grid, _ = build_grid(spec, tmp_path / "d.nc", scheduler=cluster.scheduler_address,
                             model=AnalyticSliceModel(), progress=False)
    assert grid.hash == serial.hash, "Dask build is bit-identical to the serial build"


def test_spec_files(tmp_path):
    spec = load_spec("default")
    assert spec.shape[0] >= 61 and spec.shape[1] >= 15 and spec.shape[2] >= 6
    assert spec.v[0] == pytest.approx(1e-6) and spec.v[-1] == pytest.approx(40.0)
    assert spec.T[0] == pytest.approx(253.15) and spec.T[-1] == pytest.approx(393.15)
    assert spec.p[0] == pytest.approx(5e4) and spec.p[-1] == pytest.approx(2e6)
    bad = tmp_path / "bad.toml"
    bad.write_text('compound = "summer"\nsurface = "asphalt"\n[axes.v]\nmin = 1e-6\nmax = 40\n'
                   'n = 5\n[axes.T]\nmin = "20 degC"\nmax = "10 degC"\nn = 3\n[axes.p]\n'
                   'values = [1e5, 2e5]\n')
    with pytest.raises(InputError, match=r"axes\.T\.max"):
        load_spec(bad)
    bad.write_text('compound = "summer"\nsurface = "asphalt"\n[axes.v]\nmin = 1e-6\nmax = 40\n'
                   'n = 5\n[axes.T]\nmin = 280\nmax = 300\nn = 3\n[axes.p]\n'
                   'values = [1e5, 2e5]\n[engine]\nq_per_dec = 3\n')
    with pytest.raises(InputError, match="unknown engine setting"):
        load_spec(bad)
    bad.write_text('compound = "nosuch"\nsurface = "asphalt"\n')
    with pytest.raises(InputError, match="compound"):
        load_spec(bad)


def test_real_engine_tiny_build(tmp_path):
    pytest.importorskip("lookup.friction")
    from lookup.grid.build import make_model

    spec = load_spec("default").with_axes(v=[1e-4, 1e-2, 1.0], T=[273.15, 313.15],
                                          p=[1e5, 1e6])
    model = make_model(spec)
    grid, _ = build_grid(spec, tmp_path / "tiny.nc", workers=1, model=model, progress=False)
    direct = model.grid_slice(1e-2, spec.T, spec.p)
    for n in VARIABLES:
        np.testing.assert_array_equal(grid[n][1], round_to_float32(direct[n]),
                                      err_msg=f"grid node equals the engine's slice (rounded "
                                              f"to float32 as documented): {n}")
    assert grid.meta["q1_per_m"] == pytest.approx(model.q1)
    assert grid.meta["compound"]["name"] == "summer", "full compound parameters stored"


def test_real_engine_dask_and_pool_identical_to_serial(tmp_path):
    pytest.importorskip("lookup.friction")
    distributed = pytest.importorskip("distributed")
    from lookup.grid.build import make_model

    spec = load_spec("default").with_axes(v=[1e-5, 1e-3, 0.1, 3.0, 40.0], T=[273.15, 323.15],
                                          p=[1e5, 1e6])
    serial, _ = build_grid(spec, tmp_path / "s.nc", workers=1, model=make_model(spec),
                           progress=False)
    pooled, _ = build_grid(spec, tmp_path / "p.nc", workers=2, progress=False)
    assert pooled.hash == serial.hash, "process-pool build of the real engine == serial"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        dask_grid, _ = build_grid(spec, tmp_path / "d.nc", scheduler=cluster.scheduler_address,
                                  progress=False)
    assert dask_grid.hash == serial.hash, "Dask LocalCluster build of the real engine == serial"
