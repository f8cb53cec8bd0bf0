"""Reading TOML and CSV model files with errors that name the file, the field and the value.

Quantities in model files are numbers in the SI unit stated by the schema (written in the
files' comments), or strings ``"<number> <unit>"`` in any unit this module knows, e.g.
``E0 = "6 MPa"``, ``T_ref = "20 degC"``, ``v_star = "1 cm/s"``. An unknown unit is an error.
Text tables (CSV and the like) carry their units in the header, ``name [unit]`` or
``name (unit)``; :class:`CsvTable` reads them as users write them (header commented or not,
comma, tab, semicolon or white space, the column aliases of :data:`COLUMN_ALIASES`).
"""

from __future__ import annotations

import csv
import math
import re
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
        """A file path, relative paths taken relative to the TOML file's folder; must exist.

        A missing file is an :class:`InputError` with the absolute path tried and, for a
        relative path, the folder it was taken relative to."""
        value = self.string(key)
        p = Path(value).expanduser()
        relative = not p.is_absolute()
        if relative:
            p = self.source.parent / p
        if not p.is_file():
            what = "is a directory, not a file" if p.is_dir() else "file not found"
            where = (f", relative to the folder of {self.source} ({self.source.parent.resolve()})"
                     if relative else "")
            raise self.error(key, f"{what}: tried {p.resolve()}{where}", value)
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


#: Column names accepted for a canonical column, besides the canonical name itself. Names are
#: compared after :func:`_normalise_name` (case, spaces and underscores do not matter). The
#: table is the whole vocabulary: a column whose name is not here is not recognised (nothing
#: is guessed from the numbers).
COLUMN_ALIASES: dict[str, tuple[str, ...]] = {
    # master curves (lookup.compound: [modulus] model = "tabulated")
    "omega": ("f", "freq", "frequency", "\u03c9"),
    "E_storage": ("E'", "E\u2032", "Eprime", "E_prime", "storage modulus"),
    "E_loss": ("E''", "E\u2033", "Edoubleprime", "E_doubleprime", "loss modulus"),
    "tan_delta": ("tan delta", "tan d", "tand", "tan\u03b4", "tan \u03b4", "loss factor"),
    # shift tables and strain sweeps
    "T": ("temp", "temperature"),
    "aT": ("a_T",),
    "log10_aT": ("log10 a_T", "log10(aT)", "log10(a_T)", "log aT", "log(aT)"),
    "strain": ("eps", "epsilon", "\u03b5", "strain amplitude"),
    "eta_R": ("E'/E'0", "E'/E'_0"),
    "eta_I": ("E''/E''0", "E''/E''_0"),
}

#: What a canonical column holds, for error messages.
COLUMN_MEANINGS: dict[str, str] = {
    "omega": "frequency (cyclic f in Hz or angular omega in rad/s)",
    "E_storage": "storage modulus E'", "E_loss": "loss modulus E''",
    "tan_delta": "loss tangent E''/E'", "T": "temperature", "aT": "shift factor a_T",
    "log10_aT": "decimal logarithm of a_T", "strain": "strain amplitude",
    "eta_R": "E' over its small-strain value", "eta_I": "E'' over its small-strain value",
}


def _normalise_name(name: str) -> str:
    """A column name as compared with :data:`COLUMN_ALIASES`: lower case, runs of spaces and
    underscores as one space."""
    return " ".join(name.replace("_", " ").lower().split())


def column_names_for(canonical: str) -> tuple[str, ...]:
    """The canonical name and its aliases (:data:`COLUMN_ALIASES`)."""
    return (canonical, *COLUMN_ALIASES.get(canonical, ()))


def describe_column(canonical: str, dimension: str) -> str:
    """``"E_loss (also E'', ...) [Pa, kPa, MPa, GPa]"``: a column as an error names it."""
    aliases = COLUMN_ALIASES.get(canonical, ())
    units = [u for u in UNITS.get(dimension, {}) if u]
    text = canonical + (f" (also {', '.join(aliases)})" if aliases else "")
    return text + (f" [{', '.join(units)}]" if units else "")


def _decode_lenient(line: bytes) -> str:
    """A comment line as text: UTF-8 where it is, else Windows-1252/Latin-1 (never fails)."""
    try:
        return line.decode("utf-8")
    except UnicodeDecodeError:
        return line.decode("latin-1")


def _is_utf8(line: bytes) -> bool:
    try:
        line.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


def _raw_lines(path: Path) -> list[tuple[int, bytes]]:
    """All lines of a text table as (line number, bytes), a UTF-8 byte-order mark removed."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except FileNotFoundError as exc:
        raise InputError(f"file not found (tried {p.resolve()}"
                         + ("" if p.is_absolute() else f", relative to the working directory "
                            f"{Path.cwd()}") + ")", source=path) from exc
    except IsADirectoryError as exc:
        raise InputError("is a directory, not a CSV file", source=path) from exc
    if raw.startswith(b"\xef\xbb\xbf"):  # UTF-8 byte-order mark (Excel)
        raw = raw[3:]
    return list(enumerate(raw.splitlines(), start=1))


def _decode_data(path: Path, n: int, line: bytes) -> str:
    """A header or data line as UTF-8 text, or an :class:`InputError` naming the line."""
    try:
        return line.decode("utf-8")
    except UnicodeDecodeError as exc:
        bad = line[max(exc.start - 10, 0):exc.end + 10]
        raise InputError(f"line {n} is not UTF-8 text (byte {line[exc.start]:#04x} near "
                         f"{bad!r}); save the file as UTF-8, or mark the line as a "
                         "comment with '#'", source=path, field=f"line {n}") from None


def _csv_lines(path: Path) -> list[tuple[int, str]]:
    """Data and header lines of a CSV file as (line number, text), comments dropped.

    Comment lines (``#`` first) may be in any encoding (provenance notes are often Latin-1 or
    Windows-1252); they are never decoded strictly. The other lines must be UTF-8 (ASCII is
    UTF-8); a line that is not is an :class:`InputError` naming the file and the line.
    """
    return [(n, _decode_data(path, n, line)) for n, line in _raw_lines(path)
            if line.strip() and not line.lstrip().startswith(b"#")]


def _csv_delimiter(line: str) -> str | None:
    """The delimiter of a line: comma, tab or semicolon, whichever it uses most; None (runs of
    white space) when it has none of them."""
    counts = {d: line.count(d) for d in CSV_DELIMITERS}
    best = max(counts, key=lambda d: counts[d])
    return best if counts[best] else None


def _delimiter_name(delim: str | None) -> str:
    return "white-space" if delim is None else CSV_DELIMITERS[delim]


def _split(line: str, delim: str | None) -> list[str]:
    """Cells of a line (``csv`` quoting rules for an explicit delimiter)."""
    if delim is None:
        return line.split()
    return next(csv.reader([line], delimiter=delim))


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


_ALL_ALIASES = {_normalise_name(a) for c, al in COLUMN_ALIASES.items() for a in (c, *al)}
_HEADER_TOKEN = re.compile(r"\[[^\]]*\]|\([^)]*\)|[^\s\[(]+(?:\[[^\]]*\]|\([^)]*\))?")


def _header_cells(line: str, delim: str | None) -> list[str]:
    """The cells of a header line. With a delimiter, its cells; with white space, the words,
    where a bracketed unit written apart (``f [Hz]``) belongs to the word before it and the
    words of a multi-word name of :data:`COLUMN_ALIASES` (``tan delta``) stay together."""
    if delim is not None:
        return [c.strip() for c in _split(line, delim)]
    tokens = _HEADER_TOKEN.findall(line)
    cells: list[str] = []
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok[0] in "[(" and cells:
            cells[-1] += " " + tok
            i += 1
            continue
        # longest multi-word alias starting here (words without an attached unit)
        for k in range(min(3, len(tokens) - i), 1, -1):
            words = tokens[i:i + k]
            if (all(w[0] not in "[(" for w in words)
                    and _normalise_name(" ".join(words)) in _ALL_ALIASES):
                tok, i = " ".join(words), i + k - 1
                break
        cells.append(tok)
        i += 1
    return cells


def _name_and_unit(cell: str) -> tuple[str, str]:
    """``"E' [MPa]"`` or ``"E' (MPa)"`` -> ("E'", "MPa"); a known name as a whole
    (``"log10(aT)"``) keeps its brackets; no bracket -> (cell, "")."""
    cell = cell.strip()
    if _normalise_name(cell) in _ALL_ALIASES:
        return cell, ""
    for open_, close in (("[", "]"), ("(", ")")):
        if open_ in cell and cell.endswith(close):
            name, unit = cell[:-1].split(open_, 1)
            return name.strip(), unit.strip()
    return cell, ""


@dataclass
class CsvTable:
    """A text table as users write it, before any column is converted.

    Layout (docs/engine-inputs.md, "CSV tables"): a header line naming the columns, then rows
    of numbers. The header may be a comment (the last ``#`` line before the first row of
    numbers, e.g. ``# f [Hz]  E' [MPa]  E'' [MPa]``) or a plain line. Cells are separated by a
    comma, a tab or a semicolon (whichever the line uses most) or, when it has none of them,
    by white space. Units follow a name in square brackets or parentheses: ``E' [MPa]``,
    ``E' (MPa)``. Names are the canonical ones or an alias of :data:`COLUMN_ALIASES`.

    Attributes
    ----------
    path : Path
    header_line : int
        Line number of the header (1-based).
    header_commented : bool
        Whether the header is a ``#`` line.
    delimiter : str or None
        Delimiter of the data rows (None: white space).
    cells : list of str
        The header's cells as written.
    names, units : list of str
        Each column's name and unit ("" when none is written).
    rows : list of (int, list of str)
        Data rows with their line numbers.
    header_utf8 : bool
        Whether the header line is UTF-8 text (a commented header in another encoding is
        read as Latin-1, which garbles e.g. a degree sign).
    """

    path: Path
    header_line: int
    header_commented: bool
    delimiter: str | None
    cells: list[str]
    names: list[str]
    units: list[str]
    rows: list[tuple[int, list[str]]]
    header_utf8: bool = True

    @classmethod
    def read(cls, path: str | Path) -> CsvTable:
        """Read and split a table (no column is converted yet)."""
        path = Path(path)
        lines = _raw_lines(path)
        content = [(n, b) for n, b in lines if b.strip()]
        first = next(((k, n, b) for k, (n, b) in enumerate(content)
                      if not b.lstrip().startswith(b"#")), None)
        if first is None:
            raise InputError("empty table (no line of data)", source=path)
        k, n0, b0 = first
        text0 = _decode_data(path, n0, b0)
        delim0 = _csv_delimiter(text0)
        cells0 = [c.strip() for c in _split(text0, delim0) if c.strip()]
        if cells0 and all(_is_number(c) for c in cells0):
            # no plain header: the last comment line before the data names the columns
            if k == 0:
                raise InputError(
                    f"no header line: line {n0} is already numbers. Name the columns in a "
                    "line above the data (a comment is fine), e.g. "
                    "\"# f [Hz]  E' [MPa]  E'' [MPa]\"", source=path, field=f"line {n0}")
            nh, bh = content[k - 1]
            header = _decode_lenient(bh).lstrip()[1:].strip()
            header_utf8 = _is_utf8(bh)
            hdelim = _csv_delimiter(header)
            cells = _header_cells(header, hdelim)
            if len(cells) != len(cells0):
                raise InputError(
                    f"the header is taken from the comment line {nh} just above the data, "
                    f"but it has {len(cells)} column(s) ({cells}) and the first data line "
                    f"{n0} has {len(cells0)} ({_delimiter_name(delim0)}-delimited)",
                    source=path, field=f"line {nh}")
            header_line, commented, delim, data_from = nh, True, delim0, k
        else:
            header_line, commented, delim, data_from = n0, False, delim0, k + 1
            cells = _header_cells(text0, delim0)
            header_utf8 = True
        rows = []
        for n, b in content[data_from:]:
            if b.lstrip().startswith(b"#"):
                continue
            row = [c.strip() for c in _split(_decode_data(path, n, b), delim)]
            if row and any(row):
                rows.append((n, row))
        names, units = zip(*(_name_and_unit(c) for c in cells), strict=True) if cells else ((), ())
        return cls(path, header_line, commented, delim, cells, list(names), list(units), rows,
                   header_utf8)

    # -- columns ----------------------------------------------------------------------------
    def _where(self) -> str:
        kind = "commented header" if self.header_commented else "header"
        return (f"{kind} line {self.header_line}, {_delimiter_name(self.delimiter)}-delimited: "
                f"{self.cells}")

    def find(self, canonical: str) -> int | None:
        """Index of the column holding ``canonical`` (its name or an alias), or None.

        Two columns that both mean it are an :class:`InputError`."""
        wanted = {_normalise_name(a) for a in column_names_for(canonical)}
        hits = [i for i, nm in enumerate(self.names)
                if nm == canonical or _normalise_name(nm) in wanted]
        if len(hits) > 1:
            raise InputError(f"{len(hits)} columns mean '{canonical}': "
                             f"{[self.cells[i] for i in hits]}; keep one ({self._where()})",
                             source=self.path, field=canonical)
        return hits[0] if hits else None

    def has(self, canonical: str) -> bool:
        """Whether a column means ``canonical``."""
        return self.find(canonical) is not None

    def missing(self, canonical: str, expected: str) -> InputError:
        """The error for a missing column: what is expected, what was found."""
        return InputError(f"missing column '{canonical}'; expected columns: {expected}; "
                          f"found ({self._where()})", source=self.path, field=canonical)

    def unit(self, canonical: str) -> str:
        """The unit written for a column ("" if none)."""
        i = self.find(canonical)
        return "" if i is None else self.units[i]

    def column(self, canonical: str, dimension: str, expected: str | None = None, *,
               bare_unit: str | None = None) -> np.ndarray:
        """The column meaning ``canonical`` in SI units of ``dimension``.

        Parameters
        ----------
        expected
            What the caller expects in all (for the missing-column error); default: this
            column alone.
        bare_unit
            Unit taken when the header writes none (default: the dimension's own rule; a
            strain without unit is refused as ambiguous).
        """
        i = self.find(canonical)
        if i is None:
            raise self.missing(canonical, expected or describe_column(canonical, dimension))
        unit = self.units[i]
        if not unit and bare_unit is not None:
            unit = bare_unit
        where = (f"column '{self.cells[i]}'" if self.cells[i] != canonical else None)
        if unit in AMBIGUOUS_UNITS.get(dimension, {}):
            raise InputError(AMBIGUOUS_UNITS[dimension][unit]
                             + (f" ({where})" if where else ""), source=self.path,
                             field=canonical, value=unit)
        if unit not in UNITS[dimension]:
            others = [nm for d, nm in CSV_DELIMITERS.items() if d in unit]
            hint = (f"; the header contains a {others[0]}: is that the delimiter? (read with "
                    f"{_delimiter_name(self.delimiter)} delimiter)" if others else "")
            if not self.header_utf8 and not unit.isascii():
                hint += (f"; the header (line {self.header_line}) is not UTF-8 text, so a "
                         "sign such as the degree sign is garbled: save it as UTF-8 or write "
                         "the unit in ASCII (degC, C, K)")
            raise InputError(f"unknown unit '{unit}' for a {dimension.replace('_', ' ')} "
                             f"(known: {', '.join(u for u in UNITS[dimension] if u)})"
                             + (f" ({where})" if where else "") + hint,
                             source=self.path, field=canonical, value=unit)
        dname = _delimiter_name(self.delimiter)
        vals = []
        for r, row in self.rows:
            try:
                vals.append(float(row[i]))
            except (ValueError, IndexError):
                raise InputError(f"line {r}: not a number ({dname}-delimited, decimal point; "
                                 f"{len(row)} cell(s), the header has {len(self.cells)})",
                                 source=self.path, field=canonical,
                                 value=row[i] if i < len(row) else None) from None
        arr = np.array([to_si(v, unit, dimension) for v in vals])
        validate_array(arr, lambda msg: InputError(msg, source=self.path, field=canonical))
        return arr


def read_csv_table(path: Path, columns: dict[str, str],
                   units_out: dict[str, str] | None = None) -> dict[str, np.ndarray]:
    """Read a text table whose header names columns as ``name [unit]`` (layout:
    :class:`CsvTable`).

    Parameters
    ----------
    path
        The table; lines starting with ``#`` are comments (provenance goes there; they may be
        in any encoding), the last one before the data is the header when no plain header
        line is there. Delimiter: comma, tab, semicolon or white space; numbers use a decimal
        point.
    columns
        Required column names mapped to their dimension (for the unit conversion); a column
        is found by this name or an alias of :data:`COLUMN_ALIASES`.
    units_out
        If given, filled with column name -> the unit the file used (to report it).

    Returns
    -------
    dict
        Column name (as requested) -> values in SI units.

    Raises
    ------
    InputError
        Missing file (with the absolute path tried), a non-UTF-8 data line, a missing column
        (naming the expected columns, their units and aliases, and the header found), an
        unknown or ambiguous unit or a cell that is not a number; the message names the
        file, the column and the value.
    """
    table = CsvTable.read(path)
    expected = "; ".join(describe_column(c, d) for c, d in columns.items())
    out: dict[str, np.ndarray] = {}
    for col, dim in columns.items():
        out[col] = table.column(col, dim, expected)
        if units_out is not None:
            units_out[col] = table.unit(col)
    return out


def csv_column_names(path: Path) -> list[str]:
    """The column names (without their ``[unit]``) of a CSV table read by
    :func:`read_csv_table`, e.g. to offer alternative columns."""
    return CsvTable.read(path).names
