"""Water on the road in the transient tire and the FMUs (input water_depth).

The tire core reads the wet branch of its grid (lookup.grid.wet) at the step's water depth
and at each element's drainage time (its time in the footprint, 2a / |V_r|), and lets the
water carry Horne's share of the load (tire_brush.hydroplaning; NASA TN D-2056).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from brush_cases import T20, passenger
from fmu_support import FmuDriver, slave_outputs

from fmu_src.make.build import BuildOptions, stage_resources
from fmu_src.make.native_build import WET_TABLE_FILE, build_native_fmu
from fmu_src.runtime.interface import STATUS_BITS
from lookup.grid import load_grid
from lookup.grid.store import resolve_grid_path
from lookup.grid.wet import load_wet
from tire_brush.hydroplaning import horne_speed
from tire_brush.steady import SteadyBrush
from tire_brush.transient import TransientBrushTire
from tire_brush.wet_friction import wet_branch_table

FZ, TEXTURE = 4000.0, 7e-4


@pytest.fixture(scope="module")
def grid():
    return load_grid("r117_wet")


@pytest.fixture(scope="module")
def wet():
    return load_wet(resolve_grid_path("r117_wet"))


def _tire(grid, wet, tire=None, **kw):
    tr = TransientBrushTire(tire or passenger(), grid, **kw)
    tr.set_wet(wet, texture_depth=TEXTURE)
    return tr


def _run(tr, n, vx, kappa, d, Fz=FZ, vy=0.0):
    R = tr.params.R_e
    for _ in range(n):
        out = tr.step(1e-3, vx, vy, vx * (1.0 + kappa) / R, Fz, T20, 1.0, 0.0, d)
    return out


def test_c_core_equals_its_python_reference_on_water(grid, wet):
    """The wet lookup (scratch rows, bounds, hydroplaning) is mirrored bit for bit."""
    u = (20.0, 0.2, 20.0 * 0.93 / 0.31, FZ, T20, 1.0, 0.0, 1e-3)
    a, b = _tire(grid, wet), _tire(grid, wet, backend="reference")
    for _ in range(6):
        assert a.step_array(1e-3, *u) == b.step_array(1e-3, *u)
    assert np.array_equal(a.state_vector(), b.state_vector())


def test_zero_water_is_the_dry_road_bit_for_bit(grid, wet):
    dry = TransientBrushTire(passenger(), grid)
    wet_t = _tire(grid, wet)
    for k in range(40):
        kappa = -0.1 * min(k / 20, 1.0)
        u = (20.0, 0.1, 20.0 * (1 + kappa) / 0.31, FZ, T20, 1.0, 0.0)
        assert dry.step_array(1e-3, *u) == wet_t.step_array(1e-3, *u, 0.0)


def test_transient_on_water_settles_on_the_steady_wet_brush(grid, wet):
    """Braking at 15 m/s on 1 mm of water (no lift: the grooves and texture hold 3.1 mm):
    the transient force settles within 1 % of Fz (the defaults' convergence bound,
    docs/tire-core.md) on the steady brush with the wet branch at the same drainage time,
    and well below the dry road's. The tread rings on the shipped summer compound (stick-slip,
    std 0.9 % of Fz step to step after 0.5 s), so the force is the mean of the last 100 ms of
    0.6 s (measured 0.1 % of Fz from the steady brush; a single step at 0.3 s was 1.3 %)."""
    tire = passenger()
    vx, kappa = 15.0, -0.1
    tr = _tire(grid, wet)
    _run(tr, 500, vx, kappa, 1e-3)
    outs = [_run(tr, 1, vx, kappa, 1e-3) for _ in range(100)]
    Fx = float(np.mean([o.Fx for o in outs]))
    a, _ = tire.patch.size(FZ)
    t_drain = 2.0 * a / abs(vx * (1.0 + kappa))
    table = wet_branch_table(grid, wet, 1e-3, t_drain)
    ss = SteadyBrush(tire, table).solve(kappa, 0.0, vx, FZ, float(outs[-1].T_tread))
    assert Fx / FZ == pytest.approx(float(ss.Fx) / FZ, abs=1e-2)
    out = outs[-1]
    dry = _run(TransientBrushTire(tire, grid), 300, vx, kappa, 0.0)
    assert out.Fx > dry.Fx + 0.05 * FZ, "water lowers the braking force"


def test_hydroplaning_lifts_horne_share_of_the_load(grid, wet):
    """Deep water (10 mm: the excess over the 3.1 mm the grooves and texture hold exceeds
    d_full) at half Horne's speed: the water carries (1/2)^2 = 1/4 of the load, so the forces
    are those of the tire at 3/4 of the load on water it can drain (1 mm, same friction
    tables: the branch's deepest node is 1 mm), to the bit."""
    tire = passenger()
    vx = 0.5 * horne_speed(tire.patch.p_inflation)
    deep = _run(_tire(grid, wet), 60, vx, -0.05, 1e-2, vy=0.3)
    drained = _run(_tire(grid, wet), 60, vx, -0.05, 1e-3, Fz=0.75 * FZ, vy=0.3)
    assert (deep.Fx, deep.Fy, deep.Mz) == (drained.Fx, drained.Fy, drained.Mz)


@pytest.mark.parametrize("p_kpa", [200.0, 250.0, 300.0])
def test_full_hydroplaning_at_horne_speed(grid, wet, p_kpa):
    """At and above V_p = 6.35 sqrt(p / kPa) km/h on deep water the tread loses the road (no
    force), just below it keeps a share (1 - (V/V_p)^2) of the load."""
    tire = passenger()
    # at 200 kPa the softer tire's width law peaks below 10 kN: a lower Fz_max for all
    tire = dataclasses.replace(tire, patch=dataclasses.replace(
        tire.patch, p_inflation=p_kpa * 1e3, Fz_max=8000.0))
    vp = 6.35 * math.sqrt(p_kpa) / 3.6
    assert horne_speed(p_kpa * 1e3) == pytest.approx(vp, rel=1e-15)
    at = _run(_tire(grid, wet, tire), 30, vp * 1.0001, -0.05, 1e-2)
    assert (at.Fx, at.Fy, at.Mz) == (0.0, 0.0, 0.0)
    below = _run(_tire(grid, wet, tire), 30, 0.9 * vp, -0.05, 1e-2)
    assert below.Fx < -0.02 * FZ


def test_bad_water_depth_is_refused(grid, wet):
    from tirefric.errors import InputError

    tr = _tire(grid, wet)
    for d in (-1e-3, math.nan, math.inf):
        with pytest.raises(InputError, match="water_depth"):
            tr.step(1e-3, 10.0, 0.0, 30.0, FZ, T20, 1.0, 0.0, d)


def test_both_fmu_flavours_read_water(grid, wet, tmp_path):
    """The pythonfmu slave and the native FMU built on the wet reference road's grid step
    like the Python model on 1 mm of water, to the bit; a negative depth is clamped to 0
    (input_status bit 256); an FMU whose grid has no wet branch takes water as a dry road
    (bit 512)."""
    from tire_brush.rolling_resistance import rolling_table

    u = [20.0, 0.2, 20.0 * 0.93 / 0.31, FZ, T20, 1.0, 0.0, 1e-3]
    model = _tire(grid, wet)
    model.set_rolling(rolling_table(passenger(), grid)[0])
    want = np.array([model.step(1e-3, *u).as_array() for _ in range(20)])
    opts = BuildOptions(texture_depth=TEXTURE)
    res = tmp_path / "resources"
    build = stage_resources(passenger(), grid, res, opts)
    assert build["wet"]["file"] and build["options"]["texture_depth"] == TEXTURE
    assert np.array_equal(slave_outputs(res, u, 20), want)
    fmu = build_native_fmu(passenger(), grid, tmp_path / "n.fmu", opts,
                           platforms=("linux64",)).path
    d = FmuDriver(fmu)
    assert np.array_equal(np.array([d.step(u) for _ in range(20)]), want)
    d.step([*u[:7], -1e-3])
    assert d.status() == STATUS_BITS["water_clamped"]
    d.close()
    import zipfile

    with zipfile.ZipFile(fmu) as z:
        assert f"resources/{WET_TABLE_FILE}" in z.namelist()
    dry_fmu = stage_resources(passenger(), load_grid("default"), tmp_path / "dry")
    assert dry_fmu["wet"]["file"] is None and "wet branch" in dry_fmu["wet"]["why"]
