"""Shared fixtures: small hand-built compounds and surfaces with known closed forms.

The pytest header names the copy of the package the tests import: the working tree (an
editable install, or ``PYTHONPATH`` pointing at a checkout) or an installed copy. With
``TIREFRIC_EXPECT_COPY=installed`` (or ``=working-tree``) the run stops at start-up when the
other copy is imported (``.ci/run`` sets it: CI tests the installed package).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import lookup
import tirefric
from lookup.adhesion import GaussianShearLaw, NoAdhesion
from lookup.compound import Compound, RubberThermal
from lookup.modulus import Prony, SingleRelaxation
from lookup.roughness import CutoffRule, SelfAffinePSD
from lookup.shift import WLF
from lookup.softening import NoSoftening
from lookup.surface import RoadThermal, Surface

T20 = 293.15

ROOT = Path(__file__).resolve().parents[1]


def imported_copy() -> tuple[str, Path]:
    """("working-tree" or "installed", the folder ``lookup`` was imported from)."""
    where = Path(lookup.__file__).resolve().parent
    return ("working-tree" if where.is_relative_to(ROOT) else "installed"), where


def pytest_report_header(config: pytest.Config) -> str:
    kind, where = imported_copy()
    label = "working tree" if kind == "working-tree" else "installed copy"
    return f"tirefric: lookup imported from {where} ({label}), version {tirefric.__version__}"


def pytest_configure(config: pytest.Config) -> None:
    want = os.environ.get("TIREFRIC_EXPECT_COPY")
    kind, where = imported_copy()
    if want and want != kind:
        raise pytest.UsageError(f"TIREFRIC_EXPECT_COPY={want}, but the tests import {kind} "
                                f"code from {where}")


def make_compound(modulus=None, adhesion=None, shift=None, nu: float = 0.5) -> Compound:
    """A compound from parts, with the review's thermal data (after eq. 23)."""
    shift = shift or WLF(15.0, 150.0, T20)
    modulus = modulus or Prony.lognormal(10e6, 2e9, 1e-10, 1.8)
    adhesion = adhesion if adhesion is not None else GaussianShearLaw(4e6, 0.17, 1e-2, T20,
                                                                      shift)
    return Compound("test", modulus, T20, shift, NoSoftening(), 0.0, adhesion, nu,
                    RubberThermal(1500.0, 1500.0, 0.3))


def make_surface(H: float = 0.8, q0: float = 1e3, q_r: float = 1e3, h_rms: float = 1e-4,
                 thermal: bool = True, cutoff: CutoffRule | None = None) -> Surface:
    """A self-affine surface (no roll-off by default: q_r = q0)."""
    psd = SelfAffinePSD.from_h_rms(q0, q_r, H, h_rms)
    return Surface("test", psd, cutoff or CutoffRule(), 1e-3,
                   RoadThermal(1.0, 2300.0, 900.0) if thermal else None)


@pytest.fixture
def compound() -> Compound:
    return make_compound()


@pytest.fixture
def surface() -> Surface:
    return make_surface()


@pytest.fixture
def single_relaxation() -> SingleRelaxation:
    return SingleRelaxation(E0=5e6, E1=5e9, tau=1e-4)


@pytest.fixture
def no_adhesion() -> NoAdhesion:
    return NoAdhesion()


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)
