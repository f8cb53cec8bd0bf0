"""Shared cases of the brush-tire tests: tire variants and friction grids with known shapes."""

from __future__ import annotations

import dataclasses

import numpy as np

from lookup.grid import FrictionGrid
from tire_brush.params import TireParams, load_tire

T20 = 293.15


def passenger() -> TireParams:
    """The shipped passenger tire."""
    return load_tire("passenger")


def with_contact_age(tire: TireParams, on: bool) -> TireParams:
    """``tire`` with its tread's contact age switched ``on`` / off (docs/tire-core.md,
    "contact age"; off in the shipped tires)."""
    return dataclasses.replace(tire, tread=dataclasses.replace(tire.tread, contact_ageing=on))


def isotropic(tire: TireParams) -> TireParams:
    """``tire`` with the lateral tread stiffness and damping set to the longitudinal ones
    (the closed-form combined slip of Pacejka holds for isotropic stiffness)."""
    tread = dataclasses.replace(tire.tread, k_y=tire.tread.k_x, d_y=tire.tread.d_x)
    return dataclasses.replace(tire, tread=tread)


def pacejka_like(tire: TireParams) -> TireParams:
    """``tire`` with the parabolic pressure along the patch at every load and a rigid carcass
    (no belt yaw): the brush of Pacejka's closed forms (2012, ch. 3)."""
    patch = dataclasses.replace(tire.patch, end_zone=1.0)
    carcass = dataclasses.replace(tire.carcass, rigid=True)
    return dataclasses.replace(tire, patch=patch, carcass=carcass)


def without_thermal(tire: TireParams) -> TireParams:
    """``tire`` with the lumped tread temperature switched off."""
    return dataclasses.replace(tire, thermal=dataclasses.replace(tire.thermal, enabled=False))


def peaked_grid(s0: float = 2e-4, hot_drop: float = 0.35) -> FrictionGrid:
    """A synthetic grid with the qualitative shape of a Persson curve, for numerics tests only.

    ``mu_cold`` rises from 0.5 at 1 um/s to 1.1 near 3 cm/s and falls to 0.7 at 40 m/s
    (half-Gaussians in log10 v, the shape of review eq. 21); ``mu_hot`` equals it below
    ~1e-4 m/s and drops by up to ``hot_drop`` times above (flash heating); ``dT_flash`` grows
    to 120 K. No dependence on T or p. Not physics: a stand-in with a steep falling branch
    (max -dmu/dv ~ 5 s/m) to exercise the velocity-weakening numerics.
    """
    v = np.logspace(-6, np.log10(40.0), 61)
    x = np.log10(v / 0.03)
    mu_c = np.where(x < 0, 0.5 + 0.6 * np.exp(-0.25 * x * x), 0.7 + 0.4 * np.exp(-0.6 * x * x))
    heat = v * v / (v * v + 0.05**2)
    mu_h = mu_c * (1.0 - hot_drop * heat)
    dT = 120.0 * heat
    shape = (v.size, 2, 2)

    def full(a: np.ndarray) -> np.ndarray:
        return np.broadcast_to(a[:, None, None], shape).copy()

    return FrictionGrid.from_arrays(
        v, [250.0, 400.0], [1e4, 1e7],
        {"mu_cold": full(mu_c), "mu_hot": full(mu_h), "dT_flash": full(dT)},
        s0_m=s0, D_m=5.0 * s0 if s0 > 0 else 1e-3, meta={"kind": "test peaked"})
