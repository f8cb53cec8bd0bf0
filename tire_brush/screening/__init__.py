"""Compound screening: many tread compounds to label classes, stopping distances and peak
friction (``tirefric screen``, docs/screening.md).

- :mod:`.compounds`: compound files and designed variants of a base compound;
- :mod:`.spec`: the screening spec (TOML), sweep points (full factorial, Latin hypercube,
  Sobol);
- :mod:`.evaluate`: one compound, a pure function of its description and the settings;
- :mod:`.store`: one record per finished compound, keyed by a hash of its inputs (resume);
- :mod:`.run`: the tasks on the grid build's runner (local processes or Dask), the table,
  plots and report;
- :mod:`.cli`: ``tirefric screen``.
"""

from .run import ScreenResult, pareto_front, run_screen, sensitivity
from .spec import ScreenSpec, load_screen_spec

__all__ = ["ScreenResult", "ScreenSpec", "load_screen_spec", "pareto_front", "run_screen",
           "sensitivity"]
