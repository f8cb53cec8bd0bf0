"""Shape checks of force-slip curves: the turning points of a curve above a threshold.

A measured mu-slip curve rises to one maximum and falls (or keeps rising); a curve whose force
reverses more than once by more than a small share of the load has ripples that no measured
tire shows (docs/tire-core.md, "smoothness"). :func:`turning_points` finds the reversals of a
sampled curve with a hysteresis threshold (a zig-zag filter: a reversal counts once the curve
has moved back from its last extreme by more than the threshold, so noise below it is not
counted), and :func:`ripples` counts those that are not the curve's global maximum.

This module imports only numpy.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["ripples", "turning_points"]


def turning_points(y: Any, threshold: float) -> list[int]:
    """Indices of the turning points of the sampled curve ``y`` whose reversal exceeds
    ``threshold`` (same unit as ``y``).

    Walking along ``y`` from its first sample, the direction is set by the first move of more
    than ``threshold`` away from the start; a local extreme is a turning point once the curve
    has come back from it by more than ``threshold``. A monotone curve has none, a curve with
    one maximum one (at the first sample of that maximum).

    Parameters
    ----------
    y
        Samples, in the order of the swept variable.
    threshold
        Smallest reversal counted (> 0).
    """
    y = np.asarray(y, float).ravel()
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValueError(f"threshold must be a finite number > 0, got {threshold!r}")
    if not np.isfinite(y).all():
        raise ValueError("the curve has non-finite samples")
    turns: list[int] = []
    direction = 0
    ext = 0
    for i in range(1, y.size):
        if direction == 0:
            if y[i] - y[0] > threshold:
                direction, ext = 1, i
            elif y[0] - y[i] > threshold:
                direction, ext = -1, i
        elif direction > 0:
            if y[i] > y[ext]:
                ext = i
            elif y[ext] - y[i] > threshold:
                turns.append(ext)
                direction, ext = -1, i
        else:
            if y[i] < y[ext]:
                ext = i
            elif y[i] - y[ext] > threshold:
                turns.append(ext)
                direction, ext = 1, i
    return turns


def ripples(y: Any, threshold: float) -> int:
    """Number of turning points of ``y`` (:func:`turning_points`) other than its global
    maximum: 0 for a curve that rises to one peak and falls, or is monotone."""
    y = np.asarray(y, float).ravel()
    top = int(np.argmax(y)) if y.size else -1
    return sum(1 for i in turning_points(y, threshold) if i != top)
