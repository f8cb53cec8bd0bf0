"""One error hierarchy: every exception class the packages define derives from
:class:`tirefric.errors.TirefricError`, so a caller can catch the product's errors in one place
(``docs/design.md``, "Conventions")."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import fmu_src
import lookup
import tire_brush
from fmu_src.runtime.state import StateFormatError, from_bytes, to_bytes
from tirefric.errors import TirefricError


def _exception_classes() -> list[type]:
    found = []
    for pkg in (lookup, tire_brush, fmu_src):
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
            if info.name.endswith("._tirecore"):   # the compiled core: a C library, no module
                continue
            mod = importlib.import_module(info.name)
            for _, cls in inspect.getmembers(mod, inspect.isclass):
                if issubclass(cls, BaseException) and cls.__module__ == info.name:
                    found.append(cls)
    return found


def test_every_exception_is_a_tirefric_error() -> None:
    classes = _exception_classes()
    assert StateFormatError in classes and len(classes) >= 5, "the scan finds the classes"
    outside = [f"{c.__module__}.{c.__name__}" for c in classes
               if c is not TirefricError and not issubclass(c, TirefricError)]
    assert outside == [], f"exceptions outside the TirefricError hierarchy: {outside}"


def test_corrupt_state_raises_a_tirefric_error() -> None:
    """A state blob with one flipped byte fails its checksum as a TirefricError (and, for
    callers that expect it, a ValueError)."""
    blob = bytearray(to_bytes({"x": 1.5}))
    blob[-1] ^= 0xFF
    with pytest.raises(TirefricError, match="checksum"):
        from_bytes(bytes(blob))
    with pytest.raises(ValueError):
        from_bytes(bytes(blob))
