"""Shared grids of the grid-interpolation tests."""

from __future__ import annotations

import numpy as np
import pytest

from lookup.grid import load_grid
from lookup.grid.reader import FrictionGrid
from lookup.shift import WLF
from tirefric.errors import InputError


def default_grid() -> FrictionGrid:
    """The shipped default grid (the test is skipped where it has not been built)."""
    try:
        return load_grid("default")
    except InputError:
        pytest.skip("the default grid has not been built yet")


def reduced_speed_linear_grid() -> tuple[FrictionGrid, WLF, np.ndarray, np.ndarray]:
    """A grid whose friction is linear in the reduced speed log10(v a_T) and in log10 p,
    ``mu = 1 + 0.05 (log10 v + log10 a_T) + 0.01 log10 p`` (WLF 8 / 120 K at 20 C, the shift
    stored as the grid's compound data); returns the grid, the shift, the log10 v and the T
    axes."""
    lv = np.linspace(-6, 1.6, 77)
    T = np.linspace(253.15, 393.15, 15)
    lp = np.linspace(4.7, 6.3, 5)
    w = WLF(8.0, 120.0, 293.15)
    V, TT, P = np.meshgrid(lv, T, lp, indexing="ij")
    vals = 1.0 + 0.05 * (V + w.log10_aT(TT)) + 0.01 * P
    g = FrictionGrid(lv, T, lp, {"mu_cold": vals, "mu_hot": vals, "dT_flash": 0 * vals},
                     {"s0_m": 2e-4, "D_m": 1e-3, "compound": {"shift": w.describe()}})
    return g, w, lv, T
