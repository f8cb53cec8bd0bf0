"""Exact, self-checking byte serialization of the FMU state (numpy arrays included).

pythonfmu serializes an FMU state with ``json.dumps``, which cannot hold numpy arrays and
rounds nothing but loses NaN/inf portability. The brush tire's state is a tree of dicts and
lists with floats, ints, bools, strings, None and float64 arrays (the tread-element states);
:func:`to_bytes` writes it as

``MAGIC | sha256 of the rest (32 bytes) | header length (8 bytes, little endian) |
header (JSON) | array data``

where every float is stored as ``float.hex`` (exact, NaN and inf included) and every array as
its little-endian float64 bytes, named in the header by offset, length and shape.
:func:`from_bytes` checks the magic, the checksum and every size before it builds anything, and
never unpickles (a state blob from a master is data, not code).

This module imports only numpy, the standard library and :mod:`tirefric.errors` (standard library
only): it runs inside the FMU (``docs/design.md``, "Runtime constraints").
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

import numpy as np

from tirefric.errors import TirefricError

MAGIC = b"TIREFRIC-FMU-STATE\x00"
#: Version of the byte layout.
FORMAT_VERSION = 1
_DIGEST = 32


class StateFormatError(TirefricError, ValueError):
    """The bytes are not a state written by :func:`to_bytes` (or were altered)."""


def to_bytes(state: Any) -> bytes:
    """Serialize a state tree exactly (module docstring).

    Raises
    ------
    TypeError
        A value of a type the format does not hold (the message names where it is).
    """
    blobs: list[bytes] = []
    offset = 0

    def enc(x: Any, where: str) -> Any:
        nonlocal offset
        if x is None or isinstance(x, bool | str):
            return x
        if isinstance(x, int | np.integer):
            return {"i": int(x)}
        if isinstance(x, float | np.floating):
            return {"f": float(x).hex()}
        if isinstance(x, np.ndarray):
            a = np.ascontiguousarray(x, dtype="<f8")
            if a.dtype != x.dtype and not np.array_equal(a, x, equal_nan=True):
                raise TypeError(f"state '{where}': array of {x.dtype} is not exact as float64")
            b = a.tobytes()
            blobs.append(b)
            node = {"a": [offset, len(b), list(a.shape)]}
            offset += len(b)
            return node
        if isinstance(x, dict):
            if not all(isinstance(k, str) for k in x):
                raise TypeError(f"state '{where}': dict keys must be strings")
            return {"d": {k: enc(v, f"{where}.{k}") for k, v in x.items()}}
        if isinstance(x, list | tuple):
            return {"l": [enc(v, f"{where}[{i}]") for i, v in enumerate(x)]}
        raise TypeError(f"state '{where}': cannot serialize a {type(x).__name__}")

    tree = enc(state, "state")
    header = json.dumps({"version": FORMAT_VERSION, "tree": tree}, separators=(",", ":"),
                        allow_nan=False).encode()
    body = len(header).to_bytes(8, "little") + header + b"".join(blobs)
    return MAGIC + hashlib.sha256(body).digest() + body


def from_bytes(data: bytes) -> Any:
    """Inverse of :func:`to_bytes`.

    Raises
    ------
    StateFormatError
        Wrong magic or version, checksum mismatch (altered or truncated), a malformed header.
    """
    data = bytes(data)
    n0 = len(MAGIC)
    if data[:n0] != MAGIC:
        raise StateFormatError("not a tirefric FMU state (wrong magic bytes)")
    digest, body = data[n0:n0 + _DIGEST], data[n0 + _DIGEST:]
    if len(digest) != _DIGEST or hashlib.sha256(body).digest() != digest:
        raise StateFormatError("FMU state checksum mismatch: the bytes were truncated or "
                               "altered")
    n = int.from_bytes(body[:8], "little")
    try:
        head = json.loads(body[8:8 + n].decode())
    except (UnicodeDecodeError, ValueError) as exc:
        raise StateFormatError(f"FMU state header is not valid JSON ({exc})") from None
    if not isinstance(head, dict) or head.get("version") != FORMAT_VERSION:
        raise StateFormatError(f"unsupported FMU state version "
                               f"{head.get('version') if isinstance(head, dict) else head!r} "
                               f"(this FMU reads version {FORMAT_VERSION})")
    data_start = 8 + n

    def dec(node: Any) -> Any:
        if node is None or isinstance(node, bool | str):
            return node
        if not (isinstance(node, dict) and len(node) == 1):
            raise StateFormatError(f"malformed FMU state node {node!r}")
        ((kind, val),) = node.items()
        if kind == "i":
            return int(val)
        if kind == "f":
            return float.fromhex(val)
        if kind == "a":
            off, size, shape = val
            start = data_start + int(off)
            if size < 0 or start + size > len(body) or size != 8 * int(np.prod(shape)):
                raise StateFormatError("FMU state array out of bounds")
            return np.frombuffer(body, dtype="<f8", count=size // 8,
                                 offset=start).reshape(shape).astype(float)
        if kind == "d":
            return {k: dec(v) for k, v in val.items()}
        if kind == "l":
            return [dec(v) for v in val]
        raise StateFormatError(f"unknown FMU state node kind {kind!r}")

    try:
        return dec(head["tree"])
    except (KeyError, TypeError, ValueError) as exc:
        if isinstance(exc, StateFormatError):
            raise
        raise StateFormatError(f"malformed FMU state ({exc!r})") from None
