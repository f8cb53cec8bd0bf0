"""Domain exceptions of tirefric.

A small hierarchy in the manner of SurfaceTopography's ``Exceptions.py``: every error that comes
from user input names the file, the field and the offending value, so that a user can fix the
input without reading code.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path


class TirefricError(Exception):
    """Base class of all errors raised by tirefric."""


class InputError(TirefricError, ValueError):
    """Bad user input (a data file, a command-line value, an API argument).

    Parameters
    ----------
    message
        What is wrong and, where it helps, what is expected.
    source
        The file (or other origin, e.g. ``"--v"``) the value came from.
    field
        Dotted name of the field inside the source, e.g. ``"modulus.E0_Pa"``.
    value
        The offending value (shown with ``repr``).
    """

    def __init__(
        self,
        message: str,
        *,
        source: str | Path | None = None,
        field: str | None = None,
        value: object = ...,
    ) -> None:
        self.message = message
        self.source = None if source is None else str(source)
        self.field = field
        self.value = value
        parts = []
        if self.source is not None:
            parts.append(self.source)
        if field is not None:
            parts.append(f"field '{field}'")
        if value is not ...:
            parts.append(f"value {value!r}")
        prefix = ": ".join([", ".join(parts)]) if parts else ""
        super().__init__(f"{prefix}: {message}" if prefix else message)


class InputErrors(InputError):
    """Several input problems found at once (validators report all of them, as FMPy does)."""

    def __init__(self, errors: Sequence[InputError]) -> None:
        self.errors = list(errors)
        text = "\n".join(f"  - {e}" for e in self.errors)
        TirefricError.__init__(self, f"{len(self.errors)} problem(s) in the input:\n{text}")
        self.message = text
        self.source = self.errors[0].source if self.errors else None
        self.field = self.errors[0].field if self.errors else None
        self.value = self.errors[0].value if self.errors else ...


class ConvergenceError(TirefricError, RuntimeError):
    """An iterative solve (e.g. the self-consistent flash temperature) did not converge."""


class GridError(TirefricError, ValueError):
    """A grid file is corrupt, truncated, inconsistent or does not match its content hash."""


class TirefricWarning(UserWarning):
    """Base class of the warnings tirefric issues (filter them with ``warnings``)."""


class ExtrapolationWarning(TirefricWarning):
    """A result took a notable share of its integrand from outside the measured data (a
    master curve's frequency band): docs/engine-inputs.md, "What a result took from outside
    the data"."""
