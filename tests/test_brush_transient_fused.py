"""The fused transient step against the unfused one, bit for bit.

:class:`~tire_brush.transient.TransientBrushTire` advances its elements with the fused
:class:`~tire_brush.element.LatticeStepper` (same operations, fewer numpy calls). Here it is
pinned to the model as it was before the fusion (:mod:`brush_unfused`, stepping through
:func:`~tire_brush.element.element_step`): over seeded random input sequences that visit
rolling, braking, cornering, standstill, a locked wheel, reversing, lift-off, several internal
sub-steps, ``dt = 0``, road-friction scales and numpy/int input types, every output and every
array of the state must agree to the bit (compared as bytes, so even signed zeros). Tolerance:
none; the fusion only reorders where results are stored, never the arithmetic.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from brush_cases import T20, isotropic, passenger, peaked_grid, without_thermal
from brush_unfused import UnfusedTransientTire

from lookup.grid import FrictionGrid, load_grid
from tire_brush.friction import BranchTable, ConstantFriction, GridFriction
from tire_brush.params import TireParams
from tire_brush.transient import TransientBrushTire


def _irregular_grid() -> FrictionGrid:
    """A smooth grid on non-uniform axes (the tables' interpolating index path)."""
    v = np.concatenate([np.logspace(-6, -2, 9), np.logspace(-1.5, np.log10(40.0), 14)])
    T = np.array([250.0, 270.0, 300.0, 340.0, 400.0])
    p = np.array([2e4, 6e4, 3e5, 1e6, 5e6])
    x = np.log10(v / 0.03)[:, None, None] - 0.02 * (T[None, :, None] - T20)
    mu_c = 0.6 + 0.5 * np.exp(-0.3 * x * x) - 0.02 * np.log10(p)[None, None, :]
    mu_h = mu_c * (1.0 - 0.3 * (v * v / (v * v + 0.01))[:, None, None])
    dT = 80.0 * (v / (v + 1.0))[:, None, None] + 0.0 * mu_c
    return FrictionGrid.from_arrays(v, T, p, {"mu_cold": mu_c, "mu_hot": mu_h, "dT_flash": dT},
                                    s0_m=2e-4, D_m=1e-3)


def _grid_table(grid: Callable[[], FrictionGrid], **kw) -> Callable[[], BranchTable]:
    return lambda: BranchTable.from_model(GridFriction(grid(), **kw))


#: (tire, friction, model options): the benchmark's configuration first.
CASES = {
    "default grid": (passenger, _grid_table(lambda: load_grid("default")), {}),
    "peaked, rigid, no thermal": (lambda: without_thermal(passenger()),
                                  _grid_table(peaked_grid), {"rigid_carcass": True}),
    "isotropic massless, two branches": (lambda: isotropic(passenger()),
                                         lambda: ConstantFriction(1.0, 0.8),
                                         {"massless": True}),
    "isotropic, three evaluations": (lambda: isotropic(passenger()), _grid_table(peaked_grid),
                                     {"n_newton": 3}),
    "static/kinetic, two evaluations": (passenger,
                                        lambda: ConstantFriction.static_kinetic(1.0, 0.7),
                                        {"n_newton": 2}),
    "s0 = inf, coarse": (passenger, _grid_table(peaked_grid, s0=math.inf),
                         {"n_elements": 37, "dt_internal": 4e-4}),
    "irregular axes": (passenger, _grid_table(_irregular_grid), {}),
}


def _inputs(tire: TireParams, rng: np.random.Generator, n: int) -> list[tuple]:
    """A random drive: held segments of a few steps in one regime each."""
    out = []
    while len(out) < n:
        vx = float(rng.choice([20.0, 35.0, 3.0, 0.05, -5.0, 0.0]) + rng.normal(0.0, 0.5))
        kappa = float(rng.choice([0.0, -0.03, -0.1, -0.4, 0.08, -1.0]))
        omega = vx * (1.0 + kappa) / tire.R_e
        vy = float(rng.choice([0.0, 0.3, -1.0, 2.5]))
        Fz = float(rng.choice([4000.0, 2500.0, 6500.0, 4000.0, 3000.0, 0.0]))
        Fz = Fz + float(rng.normal(0.0, 150.0)) if Fz else float(rng.choice([0.0, -100.0]))
        T = float(rng.uniform(270.0, 330.0))
        mu_scale = float(rng.choice([1.0, 1.0, 0.6]))
        if rng.random() < 0.15:
            vx = vy = omega = 0.0                          # standstill
        for _ in range(int(rng.integers(1, 12))):
            dt = float(rng.choice([1e-3, 1e-3, 2.5e-3, 4e-4, 0.0]))
            jitter = float(rng.normal(0.0, 0.05)) if vx else 0.0
            step = (dt, vx + jitter, vy, omega, Fz, T, mu_scale)
            if rng.random() < 0.05:                       # numpy scalars and ints are inputs too
                step = (np.float64(dt), np.float32(vx), vy, np.int64(round(omega)), int(Fz),
                        np.float64(T), mu_scale)
            out.append(step)
    return out[:n]


def _bytes(x) -> bytes:
    return np.asarray(x, dtype=float).tobytes()


@pytest.mark.parametrize("case", list(CASES))
def test_fused_step_equals_unfused_bit_for_bit(case: str) -> None:
    """400 random steps per seed: outputs and the whole state (elements, lattice phase, belt,
    force, tread temperature, time) equal the unfused model's bytes after every step; a
    state handed across (get_state of one, set_state of the other) continues identically."""
    tire_of, friction_of, options = CASES[case]
    tire = tire_of()
    for seed in (1, 2):
        rng = np.random.default_rng(seed)
        fused = TransientBrushTire(tire, friction_of(), **options)
        unfused = UnfusedTransientTire(tire, friction_of(), **options)
        for i, step in enumerate(_inputs(tire, rng, 400)):
            a = fused.step(*step)
            b = unfused.step(*step)
            assert _bytes(a.as_array()) == _bytes(b.as_array()), \
                f"{case}, seed {seed}, step {i} {step}: outputs differ"
            sa, sb = fused.get_state(), unfused.get_state()
            for key in sb:
                assert _bytes(sa[key]) == _bytes(sb[key]), \
                    f"{case}, seed {seed}, step {i} {step}: state '{key}' differs"
            if i % 97 == 50:
                fused.set_state(sb)
                unfused.set_state(sa)
        assert np.isfinite(a.as_array()).all(), "the drive stays finite"


def test_sliding_lookup_equals_general_lookup(rng) -> None:
    """BranchTable.at_sliding (the fused step's read) equals at(slope=True) bit for bit at
    speeds from the table's floor to beyond its last node, on uniform and irregular axes."""
    for grid in (load_grid("default"), _irregular_grid()):
        table = BranchTable.from_model(GridFriction(grid))
        n = 300
        v = table.v_floor * 10.0 ** rng.uniform(0.0, 10.0, n)
        v[:3] = table.v_floor, 10.0 ** table.log10_v[5], 10.0 ** table.log10_v[-1] * 3.0
        q = table.prepare(305.0, 10.0 ** rng.uniform(3.0, 7.5, n))
        vals, slopes = table.at(v, q, slope=True)
        got = table.at_sliding(v, q)
        for k, name in enumerate(("mu_cold", "mu_hot", "dT_flash")):
            assert got[k].tobytes() == vals[k].tobytes(), f"{name} differs"
        for k, name in enumerate(("dmu_cold/dln v", "dmu_hot/dln v")):
            assert got[3 + k].tobytes() == slopes[k].tobytes(), f"{name} differs"
