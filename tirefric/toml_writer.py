"""Writing model files: a TOML serializer for the values the loaders read back.

The standard library reads TOML (``tomllib``) but does not write it. What tirefric writes
(calibrated compound and surface files, :mod:`lookup.calibration`) is plain data: tables,
strings, numbers, booleans and lists of them. This module writes exactly that, so that
``tomllib.loads(dumps(d)) == d`` for such a dict (floats are written with ``repr``, which
round-trips exactly; TOML 1.0, https://toml.io/en/v1.0.0).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

from .errors import InputError

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    if not isinstance(k, str):
        raise InputError("TOML keys must be strings", field=str(k))
    return k if _BARE_KEY.match(k) else _string(k)


def _string(s: str) -> str:
    # A JSON string is a TOML basic string (same escapes: \" \\ \n \t \uXXXX ...); with
    # ensure_ascii=False no surrogate pairs (which TOML refuses) are produced.
    return json.dumps(s, ensure_ascii=False)


def _value(v: Any, where: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(float(v))  # float(): a numpy float's repr names its type
    if isinstance(v, str):
        plain = all((ch >= " " and ch != "\x7f") or ch in "\n\t" for ch in v)
        if "\n" in v and plain and '"""' not in v and "\\" not in v and not v.endswith('"'):
            # a multi-line basic string keeps long provenance texts readable (the newline
            # right after the opening quotes is not part of the value)
            return '"""\n' + v + '"""'
        return _string(v)
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_value(x, where) for x in v) + "]"
    if hasattr(v, "item") and callable(v.item):  # numpy scalar
        return _value(v.item(), where)
    raise InputError(f"cannot write a {type(v).__name__} to TOML", field=where)


def _is_table(v: Any) -> bool:
    return isinstance(v, Mapping)


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list | tuple) and len(v) > 0 and all(_is_table(x) for x in v)


def _emit(data: Mapping[str, Any], path: list[str], out: list[str]) -> None:
    scalars = [(k, v) for k, v in data.items() if not _is_table(v) and not _is_table_array(v)]
    for k, v in scalars:
        out.append(f"{_key(k)} = {_value(v, '.'.join([*path, k]))}")
    for k, v in data.items():
        if _is_table(v):
            out.append("")
            out.append("[" + ".".join(_key(p) for p in [*path, k]) + "]")
            _emit(v, [*path, k], out)
        elif _is_table_array(v):
            for item in v:
                out.append("")
                out.append("[[" + ".".join(_key(p) for p in [*path, k]) + "]]")
                _emit(item, [*path, k], out)


def dumps(data: Mapping[str, Any], header: str = "") -> str:
    """TOML text for ``data``; ``header`` lines are written first as ``#`` comments.

    Scalars of a table come before its sub-tables, as TOML requires; the order of keys is
    otherwise kept.
    """
    out = [f"# {line}".rstrip() for line in header.splitlines()]
    _emit(data, [], out)
    return "\n".join(out).lstrip("\n") + "\n"
