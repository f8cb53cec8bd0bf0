"""The ``tirefric`` command line: the root parser and the option parsers every command shares.

Sub-commands register themselves through the entry-point group ``tirefric.commands``
(``pyproject.toml``); each entry is a function ``register(subparsers)`` that adds one
sub-parser and sets its ``func(args) -> int``. The root therefore imports none of the
packages that provide commands (``lookup``, ``tire_brush``, ``fmu_src``): they sit above it
(docs/design.md, "Dependency direction").

Errors from bad input (:class:`~tirefric.errors.InputError`, :class:`~tirefric.errors.GridError`)
are printed as one clear message and the command exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from importlib.metadata import entry_points

from .errors import InputError, TirefricError
from .units import UNITS, parse_quantity


def parse_float_list(text: str, option: str) -> list[float]:
    """Parse ``"1e-3,0.01,1"`` into floats; NaN/inf and junk are input errors naming the option."""
    out = []
    for part in text.split(","):
        try:
            x = float(part)
        except ValueError:
            raise InputError("not a number", source=option, value=part) from None
        if not math.isfinite(x):
            raise InputError("must be a finite number", source=option, value=part)
        out.append(x)
    return out


def parse_float(text: str, option: str) -> float:
    """Parse one finite float for ``option``."""
    vals = parse_float_list(text, option)
    if len(vals) != 1:
        raise InputError("expected one number", source=option, value=text)
    return vals[0]


def parse_quantity_option(text: str, option: str, dimension: str, default_unit: str) -> float:
    """One value for ``option``: a bare number in ``default_unit`` or ``"<number> <unit>"``
    in any unit :mod:`tirefric.units` knows (e.g. ``--p "0.3 MPa"``); returns SI."""
    t = text.strip()
    try:
        x = float(t)
    except ValueError:
        def err(msg: str) -> InputError:
            return InputError(msg, source=option, value=text)

        x = parse_quantity(t, dimension, err)
        if not math.isfinite(x):
            raise InputError("must be a finite number", source=option, value=text) from None
        return x
    if not math.isfinite(x):
        raise InputError("must be a finite number", source=option, value=text)
    factor, offset = UNITS[dimension][default_unit]
    return x * factor + offset


#: A bare --T above this [Celsius] is almost surely a temperature in kelvin.
T_KELVIN_SUSPECT_C = 150.0


def parse_temperature_option(text: str, option: str = "--T") -> float:
    """Background temperature [K] from ``--T``: a bare number is Celsius (as documented),
    ``"293.15 K"`` or ``"20 degC"`` convert. A bare number above 150 (C) is refused as a
    probable kelvin value unless written with its unit (``"200 degC"``): tread temperatures
    above 150 C are outside any tire use, and 293.15 read as Celsius gives a meaningless mu."""
    T = parse_quantity_option(text, option, "temperature", "degC")
    bare = _is_bare_number(text)
    if bare and T - 273.15 > T_KELVIN_SUSPECT_C:
        raise InputError(f"read as {T - 273.15:g} degC, far above any tread temperature: a "
                         f"bare --T is in Celsius; for kelvin write '{text.strip()} K' (or "
                         f"'{text.strip()} degC' if Celsius was meant)", source=option,
                         value=text)
    if not T > 0:
        raise InputError("temperature below absolute zero", source=option, value=text)
    return T


def _is_bare_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def print_table(rows: list[dict], keys: Sequence[str]) -> None:
    """Print rows as an aligned text table with the given column keys."""
    print("  ".join(f"{k:>13s}" for k in keys))
    for r in rows:
        print("  ".join(f"{r[k]:13.6g}" if isinstance(r[k], float | int) else f"{r[k]!s:>13s}"
                        for k in keys))


def dump_json(obj: object) -> None:
    """Print ``obj`` as indented JSON on stdout."""
    json.dump(obj, sys.stdout, indent=2)
    sys.stdout.write("\n")


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every registered sub-command."""
    parser = argparse.ArgumentParser(
        prog="tirefric",
        description="Physics-based tire friction (Persson theory) -> grids -> brush tire -> FMU.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for ep in sorted(entry_points(group="tirefric.commands"), key=lambda e: e.name):
        try:
            register = ep.load()
        except ModuleNotFoundError as exc:
            # A sub-command whose module is not part of this installation is left out; any
            # other import failure inside an existing module is a bug and propagates.
            if exc.name and ep.module.startswith(exc.name):
                continue
            raise
        register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``tirefric``; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except TirefricError as exc:
        print(f"tirefric {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
