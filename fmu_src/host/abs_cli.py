"""``tirefric abs`` with the FMU: the braking-study command, handed the FMU simulator.

The study runner (:mod:`tire_brush.braking.study`) knows nothing of FMUs: a study that asks
for the ABS through the FMU (``[study] fmu_abs = true``) needs a simulator factory, and this
top-level command hands it :func:`fmu_src.host.cosim.braking_simulator` (dependencies run
downwards only: docs/design.md).
"""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric abs`` (:func:`tire_brush.braking.cli.register`) with the FMU
    simulator factory."""
    from tire_brush.braking import cli

    from .cosim import braking_simulator

    cli.register(sub, simulator_factory=braking_simulator)
