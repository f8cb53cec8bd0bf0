"""Reading TOML and CSV model files with errors that name the file, the field and the value.

Quantities in model files are numbers in the SI unit stated by the schema (written in the
files' comments), or strings ``"<number> <unit>"`` in any unit this module knows, e.g.
``E0 = "6 MPa"``, ``T_ref = "20 degC"``, ``v_star = "1 cm/s"``. An unknown unit is an error.
CSV tables carry their units in the header, ``name [unit]``.
"""

from __future__ import annotations

import csv
import math
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError, InputErrors
from .units import AMBIGUOUS_UNITS, UNITS, parse_quantity, to_si

#: Delimiters a CSV table may use (detected from its header line), with their names.
CSV_DELIMITERS: dict[str, str] = {",": "comma", "\t": "tab", ";": "semicolon"}


@dataclass
class Table:
    """A TOML table with the file it came from and its dotted position inside it.

    Getters validate as they read and raise :class:`InputError` naming file, field and value.
    """

    data: dict[str, Any]
    source: Path
    prefix: str = ""
    _used: set[str] = field(default_factory=set)

    @classmethod
    def load(cls, path: str | Path) -> Table:
        """Parse a TOML file."""
        path = Path(path)
        try:
            with open(path, "rb") as fh:
                data = tomllib.load(fh)
        except FileNotFoundError as exc:
            raise InputError("file not found", source=path) from exc
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML: {exc}", source=path) from exc
        return cls(data, path)

    # -- helpers ------------------------------------------------------------------------------
    def name(self, key: str) -> str:
        """Dotted field name of ``key``."""
        return f"{self.prefix}.{key}" if self.prefix else key

    def error(self, key: str, message: str, value: object = ...) -> InputError:
        """An :class:`InputError` about ``key`` of this table."""
        return InputError(message, source=self.source, field=self.name(key), value=value)

    def has(self, key: str) -> bool:
        """Whether ``key`` is present."""
        return key in self.data

    def raw(self, key: str, default: Any = ...) -> Any:
        """The value of ``key`` as parsed, or ``default``; missing and no default is an error."""
        self._used.add(key)
        if key not in self.data:
            if default is ...:
                raise self.error(key, "required field is missing")
            return default
        return self.data[key]

    def check_unknown(self, extra_allowed: Iterable[str] = ()) -> None:
        """Refuse keys that no getter read (a misspelt key would otherwise be ignored)."""
        unknown = sorted(set(self.data) - self._used - set(extra_allowed))
        if unknown:
            raise InputErrors(
                [self.error(k, "unknown field (misspelt?)", self.data[k]) for k in unknown]
            )

    # -- typed getters ------------------------------------------------------------------------
    def table(self, key: str, required: bool = True) -> Table | None:
        """A sub-table."""
        value = self.raw(key, ... if required else None)
        if value is None:
            return None
        if not isinstance(value, dict):
            raise self.error(key, "expected a table", value)
        return Table(value, self.source, self.name(key))

    def string(self, key: str, default: Any = ..., choices: Iterable[str] | None = None) -> str:
        """A string, optionally one of ``choices``."""
        value = self.raw(key, default)
        if not isinstance(value, str):
            raise self.error(key, "expected a string", value)
        if choices is not None and value not in set(choices):
            raise self.error(key, f"must be one of {sorted(set(choices))}", value)
        return value

    def boolean(self, key: str, default: Any = ...) -> bool:
        """A boolean."""
        value = self.raw(key, default)
        if not isinstance(value, bool):
            raise self.error(key, "expected true or false", value)
        return value

    def integer(self, key: str, default: Any = ..., minimum: int | None = None) -> int:
        """An integer, optionally bounded below."""
        value = self.raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, "expected an integer", value)
        if minimum is not None and value < minimum:
            raise self.error(key, f"must be >= {minimum}", value)
        return value

    def quantity(
        self,
        key: str,
        dimension: str,
        default: Any = ...,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        minimum: float | None = None,
        maximum: float | None = None,
    ) -> float:
        """A finite number in SI units (a bare number is taken as SI; ``"6 MPa"`` converts)."""
        value = self.raw(key, default)
        si = parse_quantity(value, dimension, lambda msg: self.error(key, msg, value))
        check_number(si, lambda msg: self.error(key, msg, value), positive=positive,
                     nonnegative=nonnegative, minimum=minimum, maximum=maximum)
        return si

    def path(self, key: str) -> Path:
        """A file path, relative paths taken relative to the TOML file's folder; must exist."""
        value = self.string(key)
        p = Path(value)
        if not p.is_absolute():
            p = self.source.parent / p
        if not p.is_file():
            raise self.error(key, "file not found", value)
        return p

    def array(self, key: str, dimension: str = "dimensionless", *, positive: bool = False,
              increasing: bool = False, min_length: int = 1) -> np.ndarray:
        """An array of finite numbers (SI) given as a TOML list."""
        value = self.raw(key)
        if not isinstance(value, list) or len(value) < min_length:
            raise self.error(key, f"expected a list of at least {min_length} numbers", value)
        out = np.array([parse_quantity(v, dimension, lambda msg, v=v: self.error(key, msg, v))
                        for v in value], dtype=float)
        validate_array(out, lambda msg: self.error(key, msg, value), positive=positive,
                       increasing=increasing)
        return out


def check_number(x: float, err, *, positive: bool = False, nonnegative: bool = False,
                 minimum: float | None = None, maximum: float | None = None) -> None:
    """Raise ``err(message)`` if ``x`` is not finite or violates a bound."""
    if not math.isfinite(x):
        raise err("must be a finite number")
    if positive and not x > 0:
        raise err("must be > 0")
    if nonnegative and not x >= 0:
        raise err("must be >= 0")
    if minimum is not None and x < minimum:
        raise err(f"must be >= {minimum:g}")
    if maximum is not None and x > maximum:
        raise err(f"must be <= {maximum:g}")


def validate_array(a: np.ndarray, err, *, positive: bool = False, increasing: bool = False) -> None:
    """Raise ``err(message)`` for NaN/inf entries, non-positive ones or a non-monotonic axis."""
    bad = ~np.isfinite(a)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise err(f"entry {i} is not a finite number ({a[i]!r})")
    if positive and (a <= 0).any():
        i = int(np.flatnonzero(a <= 0)[0])
        raise err(f"entry {i} must be > 0 (is {a[i]!r})")
    if increasing and a.size > 1 and not (np.diff(a) > 0).all():
        i = int(np.flatnonzero(np.diff(a) <= 0)[0])
        raise err(f"must be strictly increasing (entry {i + 1} = {a[i + 1]!r} follows "
                  f"{a[i]!r})")


def _csv_lines(path: Path) -> list[tuple[int, str]]:
    """Data and header lines of a CSV file as (line number, text), comments dropped.

    Comment lines (``#`` first) may be in any encoding (provenance notes are often Latin-1 or
    Windows-1252); they are never decoded strictly. The other lines must be UTF-8 (ASCII is
    UTF-8); a line that is not is an :class:`InputError` naming the file and the line.
    """
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError as exc:
        raise InputError("file not found", source=path) from exc
    except IsADirectoryError as exc:
        raise InputError("is a directory, not a CSV file", source=path) from exc
    if raw.startswith(b"\xef\xbb\xbf"):  # UTF-8 byte-order mark (Excel)
        raw = raw[3:]
    out = []
    for n, line in enumerate(raw.splitlines(), start=1):
        if line.lstrip().startswith(b"#") or not line.strip():
            continue
        try:
            out.append((n, line.decode("utf-8")))
        except UnicodeDecodeError as exc:
            bad = line[max(exc.start - 10, 0):exc.end + 10]
            raise InputError(f"line {n} is not UTF-8 text (byte {line[exc.start]:#04x} near "
                             f"{bad!r}); save the file as UTF-8, or mark the line as a "
                             "comment with '#'", source=path, field=f"line {n}") from None
    return out


def _csv_delimiter(header: str) -> str:
    """The delimiter of a CSV table, from its header line: comma, tab or semicolon."""
    counts = {d: header.count(d) for d in CSV_DELIMITERS}
    best = max(counts, key=lambda d: counts[d])
    return best if counts[best] else ","


def read_csv_table(path: Path, columns: dict[str, str],
                   units_out: dict[str, str] | None = None) -> dict[str, np.ndarray]:
    """Read a CSV table whose header names columns as ``name [unit]``.

    Parameters
    ----------
    path
        CSV file; lines starting with ``#`` are comments (provenance goes there; they may be
        in any encoding). The delimiter is a comma, a tab or a semicolon, whichever the
        header line uses most (:data:`CSV_DELIMITERS`); numbers use a decimal point.
    columns
        Required column names mapped to their dimension (for the unit conversion).
    units_out
        If given, filled with column name -> the unit the file used (to report it).

    Returns
    -------
    dict
        Column name -> values in SI units.

    Raises
    ------
    InputError
        Missing file, a non-UTF-8 data line, a missing column, an unknown or ambiguous unit
        or a cell that is not a number; the message names the file, the column and the value.
    """
    lines = _csv_lines(path)
    if not lines:
        raise InputError("empty table", source=path)
    delim = _csv_delimiter(lines[0][1])
    dname = CSV_DELIMITERS[delim]
    rows = [(n, r) for n, r in zip((n for n, _ in lines),
                                   csv.reader((t for _, t in lines), delimiter=delim),
                                   strict=True) if r and any(c.strip() for c in r)]
    header = [h.strip() for h in rows[0][1]]
    names: dict[str, tuple[int, str]] = {}
    for i, h in enumerate(header):
        if "[" in h and h.endswith("]"):
            nm, unit = h[:-1].split("[", 1)
            names[nm.strip()] = (i, unit.strip())
        else:
            names[h] = (i, "")
    out: dict[str, np.ndarray] = {}
    for col, dim in columns.items():
        if col not in names:
            raise InputError(f"missing column (header read with {dname} delimiter: "
                             f"{header})", source=path, field=col)
        i, unit = names[col]
        if unit in AMBIGUOUS_UNITS.get(dim, {}):
            raise InputError(AMBIGUOUS_UNITS[dim][unit], source=path, field=col, value=unit)
        if unit not in UNITS[dim]:
            others = [nm for d, nm in CSV_DELIMITERS.items() if d in unit]
            hint = (f"; the header contains a {others[0]}: is that the delimiter? (read with "
                    f"{dname} delimiter)" if others else "")
            raise InputError(f"unknown unit '{unit}' for a {dim.replace('_', ' ')} "
                             f"(known: {', '.join(u for u in UNITS[dim] if u)}){hint}",
                             source=path, field=col, value=unit)
        if units_out is not None:
            units_out[col] = unit
        vals = []
        for r, row in rows[1:]:
            try:
                vals.append(float(row[i]))
            except (ValueError, IndexError):
                raise InputError(f"line {r}: not a number ({dname}-delimited, decimal point)",
                                 source=path, field=col,
                                 value=row[i] if i < len(row) else None) from None
        arr = np.array([to_si(v, unit, dim) for v in vals])
        validate_array(arr, lambda msg, col=col: InputError(msg, source=path, field=col))
        out[col] = arr
    return out


def csv_column_names(path: Path) -> list[str]:
    """The column names (without their ``[unit]``) of a CSV table read by
    :func:`read_csv_table`, e.g. to offer alternative columns."""
    lines = _csv_lines(path)
    if not lines:
        raise InputError("empty table", source=path)
    header = next(csv.reader([lines[0][1]], delimiter=_csv_delimiter(lines[0][1])))
    return [h.split("[", 1)[0].strip() for h in header]
