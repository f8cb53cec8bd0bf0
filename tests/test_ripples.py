"""Force-slip curves with one maximum: the ripple counter, and the steady brush over the
operating range (docs/tire-core.md, "smoothness").

A measured mu-slip curve rises to one maximum and falls; the criterion here is no reversal
above 0.5 % of Fz besides the peak at 0, 20 and 50 C, 5-30 m/s, 2-6 kN, pure and combined slip.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from tire_brush.curves import ripples, turning_points

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))

#: the criterion: reversals above this share of Fz count as ripples
THRESHOLD = 0.005


def test_counter_on_known_curves() -> None:
    """A curve with one peak (the Magic Formula's shape, Pacejka 2012 eq. (4.49), B = 10,
    C = 1.9, E = 0.97: peak 1 at 0.18, falling to 0.91) has no ripple; 5 periods of an
    oscillation of amplitude 0.02 on its falling side add 10 (a minimum and a maximum per
    period); the same oscillation at 0.002, below half the threshold, adds none (the
    hysteresis of the zig-zag filter)."""
    x = np.linspace(0.0, 1.0, 2001)
    B, C, E = 10.0, 1.9, 0.97
    peak = np.sin(C * np.arctan(B * x - E * (B * x - np.arctan(B * x))))
    assert ripples(peak, THRESHOLD) == 0
    assert turning_points(x, THRESHOLD) == []                      # monotone: none
    assert len(turning_points(peak, THRESHOLD)) == 1
    # 5 full periods over x in [0.5, 1] on the falling side: 10 reversals, all ripples
    wave = np.where(x > 0.5, -0.02 * np.sin(2 * np.pi * 5 * (x - 0.5) / 0.5), 0.0)
    assert ripples(peak + wave, THRESHOLD) == 10
    assert ripples(peak + 0.1 * wave, THRESHOLD) == 0             # amplitude 0.002 < 0.005/2
    # a dip before the peak is a ripple (a minimum) even though the curve has one maximum
    dip = peak - np.where((x > 0.02) & (x < 0.04), 0.02, 0.0)
    assert ripples(dip, THRESHOLD) >= 1


def test_counter_refuses_bad_input() -> None:
    with pytest.raises(ValueError, match="threshold"):
        turning_points([0.0, 1.0], 0.0)
    with pytest.raises(ValueError, match="non-finite"):
        turning_points([0.0, np.nan], 0.1)


def _brush(ageing: bool | None = None):
    """The shipped passenger tire on the default grid (``ageing``: its tread's contact age
    on / off; None: the tire file's, off)."""
    import dataclasses

    from lookup.grid import load_grid
    from tire_brush.friction import GridFriction
    from tire_brush.params import load_tire
    from tire_brush.steady import SteadyBrush

    tire = load_tire("passenger")
    if ageing is not None:
        tire = dataclasses.replace(tire, tread=dataclasses.replace(tire.tread,
                                                                   contact_ageing=ageing))
    return SteadyBrush(tire, GridFriction(load_grid("default")))


@pytest.fixture(scope="module")
def brush():
    return _brush()


#: The shipped tire's single row of identical elements stick-slips in phase on the falling
#: mu(v); with the tread's contact age (off in the shipped tire, docs/tire-core.md "contact
#: age") a re-sticking element no longer holds the table's low-speed peak and these pass.
RIPPLES = pytest.mark.xfail(strict=True, reason="the single-row brush of identical elements "
                            "stick-slips in phase on the falling mu(v): ripples "
                            "(docs/tire-core.md)")


@pytest.mark.parametrize("T_C,v,Fz,ageing", [
    pytest.param(0.0, 10.0, 4000.0, False, marks=RIPPLES),
    pytest.param(20.0, 5.0, 4000.0, False, marks=RIPPLES),
    (0.0, 10.0, 4000.0, True), (20.0, 5.0, 4000.0, True)])
def test_steady_curves_have_one_maximum_sample(T_C, v, Fz, ageing) -> None:
    """Two cases of the range below (the worst at 0 and 20 C on the shipped tire), 201
    points per curve (a ripple of the full range's 401-point sweep spans >= 4 points),
    with the tread's contact age off (the shipped tire) and on."""
    from bench_ripples import curves

    found = {k: ripples(y, THRESHOLD)
             for k, y in curves(_brush(ageing), T_C, v, Fz, 201).items()}
    assert not any(found.values()), found


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="78 of 144 curves ripple on the shipped tire (5 with "
                   "the tread's contact age on: 0 C pure braking at 5 and 10 m/s; "
                   "docs/tire-core.md)")
def test_steady_curves_have_one_maximum_over_the_range(brush) -> None:
    """0/20/50 C, 5/10/20/30 m/s, 2/4/6 kN; pure braking, pure cornering, combined at
    4 deg (benchmarks/bench_ripples.py): no ripple above 0.5 % of Fz in any of 144 curves of
    401 points."""
    from bench_ripples import run

    bad = [r for r in run(401, (THRESHOLD,), brush) if r["counts"][0] > 0]
    assert not bad, f"{len(bad)} curves ripple, e.g. {bad[:3]}"
