"""The rolling-resistance moment My of the transient tire and of both FMU flavours.

The core reads f_r from a table on (log10 |V_r|, T_tread, log10 Fz) made by
:func:`tire_brush.rolling_resistance.core_table` and outputs My = f_r Fz R_e against the spin
(adapted SAE; ISO-W flips it); the tread's share of the loss F_r |V_r| heats the tread.
"""

from __future__ import annotations

import math
import zipfile

import numpy as np
import pytest
from brush_cases import T20, passenger, without_thermal
from fmu_support import OUTPUTS, FmuDriver, slave_outputs

from fmu_src.make.build import BuildOptions, stage_resources
from fmu_src.make.native_build import ROLLING_TABLE_FILE, build_native_fmu
from lookup.compound import load_compound
from lookup.grid import load_grid
from tire_brush.rolling_resistance import RollingTable, rolling_resistance, rolling_table
from tire_brush.transient import TransientBrushTire

FZ, VX = 4000.0, 20.0


@pytest.fixture(scope="module")
def grid():
    return load_grid("default")


@pytest.fixture(scope="module")
def table(grid):
    t, why = rolling_table(passenger(), grid)
    assert t is not None, why
    return t


def _tire(grid, table, **kw):
    tr = TransientBrushTire(passenger(), grid, **kw)
    tr.set_rolling(table)
    return tr


def test_my_at_a_node_is_the_model_and_opposes_the_spin(grid, table):
    """At a table node (V, T, Fz) My = f_r Fz R_e of :func:`rolling_resistance` to rounding
    (thermal off: T_tread = T_surface = the node's T); rolling backwards flips it."""
    tire = without_thermal(passenger())
    V, T, Fz = 10.0 ** table.log10_v[10], float(table.T[7]), 10.0 ** table.log10_Fz[6]
    f_r = float(rolling_resistance(tire, load_compound("summer"), V, Fz, T).f_r)
    for sign in (1.0, -1.0):
        tr = TransientBrushTire(tire, grid)
        tr.set_rolling(table)
        out = tr.step(1e-3, sign * V, 0.0, sign * V / tire.R_e, Fz, T)
        assert out.My == pytest.approx(sign * f_r * Fz * tire.R_e, rel=1e-9)
        assert out.My * sign > 0.0, "adapted SAE: My > 0 opposes rolling forward"


def test_my_vanishes_continuously_at_standstill(grid, table):
    """Below the first speed node My falls linearly with |V_r| to 0 (a viscoelastic solid's
    loss modulus is linear in frequency at low frequency): a parked tire has My = 0 and no
    jump when it starts to roll."""
    tire = without_thermal(passenger())
    v0 = 10.0 ** table.log10_v[0]
    my = []
    for V in (0.0, 0.25 * v0, 0.5 * v0, v0):
        tr = TransientBrushTire(tire, grid)
        tr.set_rolling(table)
        my.append(tr.step(1e-3, V, 0.0, V / tire.R_e, FZ, T20).My)
    assert my[0] == 0.0
    assert my[1] == pytest.approx(0.25 * my[3], rel=1e-12)
    assert my[2] == pytest.approx(0.5 * my[3], rel=1e-12)


def test_rolling_loss_heats_the_tread_by_its_share(grid, table):
    """With friction off (mu_scale = 0: no friction work) the tread temperature follows the
    implicit Euler steps (of dt_internal) of C dT/dt = s f_r Fz |V| - G (T - T_surface) to
    rounding, s the tread share: the rolling loss is the only heat."""
    tire = passenger()
    th = tire.thermal
    tr = _tire(grid, table)
    ref = _tire(grid, table, backend="reference")
    T = T20
    for _ in range(5):
        out = tr.step(1e-3, VX, 0.0, VX / tire.R_e, FZ, T20, 0.0)
        ref.step(1e-3, VX, 0.0, VX / tire.R_e, FZ, T20, 0.0)
        f_r, s = ref._ref._rolling(VX, T, FZ)
        q = s * f_r * FZ * VX                      # held over the step's internal steps
        h = tr.dt_internal
        for _ in range(round(1e-3 / h)):
            T = (T + h * (q + th.conductance * T20) / th.heat_capacity) / (
                1.0 + h * th.conductance / th.heat_capacity)
        assert out.T_tread == pytest.approx(T, rel=1e-14)
    assert out.T_tread > T20 and q > 0.0
    assert np.array_equal(tr.state_vector(), ref.state_vector()), "C and reference agree"


def test_bad_rolling_table_is_refused(grid, table):
    """A table with a negative coefficient or a share outside [0, 1] is refused, naming it."""
    from tirefric.errors import InputError

    tr = TransientBrushTire(passenger(), grid)
    for f_r, share in ((-table.f_r, table.tread_share), (table.f_r, table.tread_share + 1.0)):
        bad = RollingTable(table.log10_v, table.T, table.log10_Fz, f_r, share)
        with pytest.raises(InputError, match="rolling"):
            tr.set_rolling(bad)


def test_both_fmu_flavours_carry_the_table_and_give_my(grid, table, tmp_path):
    """The native FMU (ISO-W axes) and the pythonfmu slave (adapted SAE) built on the default
    grid carry the table and step like the Python model with it: the native FMU's My is the
    model's, flipped into ISO-W (My < 0 rolling forward), the slave's equal to the bit."""
    u = [VX, 0.3, VX * 0.97 / 0.31, FZ, T20, 1.0, 0.02, 0.0]
    model = _tire(grid, table)
    want = np.array([model.step(1e-3, *u).as_array() for _ in range(30)])
    # pythonfmu flavour, in process
    res = tmp_path / "resources"
    build = stage_resources(passenger(), grid, res)
    assert build["rolling"]["file"] and build["rolling"]["compound"] == "summer"
    assert np.array_equal(slave_outputs(res, u, 30), want)
    # native flavour, ISO-W
    fmu = build_native_fmu(passenger(), grid, tmp_path / "n.fmu", BuildOptions(axes=1),
                           platforms=("linux64",)).path
    with zipfile.ZipFile(fmu) as z:
        assert f"resources/{ROLLING_TABLE_FILE}" in z.namelist()
    d = FmuDriver(fmu)
    u_iso = [VX, -0.3, *u[2:]]
    got = np.array([d.step(u_iso) for _ in range(30)])
    d.close()
    iso = {"Fy": -1, "Mz": -1, "My": -1}
    for k, name in enumerate(OUTPUTS):
        assert np.array_equal(got[:, k], iso.get(name, 1) * want[:, k]), name
    assert (got[:, OUTPUTS.index("My")] < 0).all() and math.isfinite(got.sum())


def test_fmu_without_a_compound_has_no_table_and_says_why(tmp_path):
    """A grid that records no compound (the synthetic test grid) gives no table: My = 0 and
    build.json says why."""
    from fmu_support import synthetic_grid

    build = stage_resources(passenger(), synthetic_grid(), tmp_path)
    assert build["rolling"]["file"] is None and "compound" in build["rolling"]["why"]


def test_coast_down_through_the_fmu_decelerates_by_rolling_resistance(tmp_path):
    """The quarter car coasting (no brake) through the native FMU: the only moment on the
    wheel is My, so after the slip has settled the car decelerates at
    f_r Fz / (m + J / R^2) (the wheel's inertia rides along), f_r the FMU's table at 20 m/s
    and 20 C; measured over 0.3-0.8 s to 1 % (the speed falls by 0.1 m/s and the tread warms
    by 0.04 K: f_r changes by well under 1 %; measured 0.2 %). The table's trilinear value
    is within 8 % of the model's (measured 1.7 % at 20 C and 4.4 kN; up to 32 % elsewhere in
    the operating range, below 0 C: the tread's parts, 39 % of f_r at the ISO point, curve
    with temperature and the table's 10 K temperature nodes interpolate them linearly;
    docs/tire-core.md)."""
    from fmu_src.host.cosim import CosimSettings, simulate_braking_fmu
    from tire_brush.braking.abs_control import TorqueRamp
    from tire_brush.braking.quarter_car import load_quarter_car
    from tirefric.paths import models_dir

    car = load_quarter_car(models_dir() / "studies" / "vehicles" / "passenger.toml")
    fmu = build_native_fmu(passenger(), load_grid("default"), tmp_path / "n.fmu",
                           platforms=("linux64",)).path
    res = simulate_braking_fmu(fmu, car, TorqueRamp(0.0), 20.0, T20,
                               settings=CosimSettings(t_max=0.8))
    assert not res.stopped
    sel = res.t >= 0.3
    decel = -np.polyfit(res.t[sel], res.v[sel], 1)[0]
    table, _ = rolling_table(passenger(), load_grid("default"))
    ref = TransientBrushTire(passenger(), load_grid("default"), backend="reference")
    ref.set_rolling(table)
    f_r, _ = ref._ref._rolling(20.0, T20, car.Fz)
    expect = f_r * car.Fz / (car.mass + car.wheel_inertia / car.radius ** 2)
    assert decel == pytest.approx(expect, rel=0.01)
    model = float(rolling_resistance(passenger(), load_compound("summer"), 20.0, car.Fz,
                                     T20).f_r)
    assert f_r == pytest.approx(model, rel=0.08)


def test_quarter_car_wheel_carries_the_rolling_resistance_moment():
    """Map-based studies: J omega' gains -f_r Fz R (the tire's My against the spin), the car's
    m v' does not change (only Fx brakes the car, as in MF-Tyre's convention), and the brush
    study takes f_r from the tire's model on its grid's compound."""
    import dataclasses

    from tire_brush.braking.friction import brush_rolling_resistance
    from tire_brush.braking.quarter_car import load_quarter_car, rhs
    from tirefric.paths import models_dir

    car = load_quarter_car(models_dir() / "studies" / "vehicles" / "passenger.toml")
    rolling = dataclasses.replace(car, rolling_resistance=0.02)
    a = rhs(car, -0.8, 20.0, 60.0, 900.0, 0.0, T20, T20)
    b = rhs(rolling, -0.8, 20.0, 60.0, 900.0, 0.0, T20, T20)
    assert b[1] == a[1]
    Vr = 60.0 * car.radius
    creep = Vr / (Vr**2 + 0.1**2) ** 0.5
    assert b[2] - a[2] == pytest.approx(
        -0.02 * car.Fz * car.radius * creep / car.wheel_inertia, rel=1e-12)
    locked = rhs(rolling, -0.8, 20.0, 0.0, 900.0, 0.0, T20, T20)
    assert locked[2] == rhs(car, -0.8, 20.0, 0.0, 900.0, 0.0, T20, T20)[2], \
        "a locked wheel has no rolling resistance"
    prov = {"model": "brush", "tire": "passenger", "grid": "default"}
    f_r, why = brush_rolling_resistance(prov, 10.0, car.Fz, T20)
    want = float(rolling_resistance(passenger(), load_compound("summer"), 10.0, car.Fz,
                                    T20).f_r)
    assert why == "" and f_r == want
    assert brush_rolling_resistance({"model": "analytic"}, 10.0, car.Fz, T20)[0] == 0.0
