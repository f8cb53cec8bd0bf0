"""Binary table files of the FMU (friction table, rolling-resistance table).

One layout for both: little endian, 16 bytes magic, uint32 version, three axis sizes, the
float64 axes, float64 node values (three per node) and an FNV-1a 64 checksum. The native
wrapper reads it in C (``fmu_src/runtime/native/fmu_wrapper.c``), the pythonfmu slave with
:func:`read_table_bytes`; the build writes it with :func:`table_bytes`.

This module imports only the standard library (numpy inside the functions): it runs inside
the FMU.
"""

from __future__ import annotations

import struct
from typing import Any

#: Magic bytes and version of the table files.
TABLE_MAGIC = b"TIREFRIC-TABLE\0\0"
TABLE_VERSION = 1

_FNV_OFFSET, _FNV_PRIME = 1469598103934665603, 1099511628211


def fnv1a64(data: bytes) -> int:
    """FNV-1a 64-bit hash (the checksum of the table file and of a serialized FMU state)."""
    h = _FNV_OFFSET
    for b in data:
        h = ((h ^ b) * _FNV_PRIME) & 0xFFFFFFFFFFFFFFFF
    return h


def table_bytes(table: Any) -> bytes:
    """A table as the native wrapper reads it (the friction table
    ``resources/tirefric-table.bin``; the rolling-resistance table uses the same layout).

    Little endian: 16 bytes magic ``TIREFRIC-TABLE\\0\\0``, uint32 version (1), uint32 ``nv``,
    ``nT``, ``np``; float64 axes ``log10_v[nv]`` [log10 m/s], ``T[nT]`` [K], ``log10_p[np]``
    [log10 Pa]; float64 ``values[nv][nT][np][3]`` (mu_cold, mu_hot, dT_flash [K]); uint64
    FNV-1a 64 of all preceding bytes. ``s0`` is not in the file: it is the FMU parameter
    ``s0`` (``1/s0`` goes to the core when the model is built).

    Parameters
    ----------
    table
        A :class:`tire_brush.friction.BranchTable` (the one the Python model uses), or any
        object with ``log10_v``, ``T``, ``log10_p`` and ``values`` of shape
        ``(nv, nT, np, 3)`` (:class:`tire_brush.rolling_resistance.RollingTable`).
    """
    import numpy as np

    axes = [np.ascontiguousarray(a, dtype="<f8") for a in (table.log10_v, table.T,
                                                            table.log10_p)]
    values = np.ascontiguousarray(table.values, dtype="<f8")
    head = TABLE_MAGIC + struct.pack("<4I", TABLE_VERSION, *(a.size for a in axes))
    body = head + b"".join(a.tobytes() for a in axes) + values.tobytes()
    return body + struct.pack("<Q", fnv1a64(body))


def read_table_bytes(data: bytes) -> dict[str, Any]:
    """Inverse of :func:`table_bytes`: axes and values as numpy arrays.

    Raises
    ------
    ValueError
        Not a table file, another version, or a checksum or size mismatch (corrupt file).
    """
    import numpy as np

    if data[:16] != TABLE_MAGIC:
        raise ValueError("not a tirefric friction table")
    if len(data) < 40:
        raise ValueError("table file too short")
    version, nv, nT, np_ = struct.unpack("<4I", data[16:32])
    if version != TABLE_VERSION or struct.unpack("<Q", data[-8:])[0] != fnv1a64(data[:-8]):
        raise ValueError("unsupported version or checksum mismatch")
    if len(data) != 40 + 8 * (nv + nT + np_ + 3 * nv * nT * np_):
        raise ValueError("table file size does not match its header")
    a = np.frombuffer(data[32:-8], dtype="<f8")
    return {"log10_v": a[:nv], "T": a[nv:nv + nT], "log10_p": a[nv + nT:nv + nT + np_],
            "values": a[nv + nT + np_:].reshape(nv, nT, np_, 3)}


#: Magic bytes and version of the wet-branch file.
WET_MAGIC = b"TIREFRIC-WET\0\0\0\0"
WET_VERSION = 1


def wet_bytes(wet: Any, d_full: float, drain_scale: float = 1.0) -> bytes:
    """The wet branch of a grid as the FMUs read it (``tirefric-wet.bin``).

    Little endian: 16 bytes magic ``TIREFRIC-WET\\0\\0\\0\\0``, uint32 version (1), uint32
    ``nd``, ``nt``, ``nv``, ``nT``, ``np``; float64 ``d_full`` [m] and ``drain_scale`` [1]
    (:func:`tire_brush.transient.TransientBrushTire.set_wet`); float64 axes ``depth[nd]`` [m]
    and ``log10_t[nt]`` [log10 s]; float64 ``mu[nd][nv][nT][np][4]`` (cold and hot with the
    adhesive term off and on: cold_w0, cold_w1, hot_w0, hot_w1); float64
    ``w_dry[nd][nt][nv][nT][np]``; uint64 FNV-1a 64 of all preceding bytes. The (v, T, p)
    nodes are those of the friction table file.

    Parameters
    ----------
    wet
        A :class:`lookup.grid.wet.WetGrid`.
    """
    import numpy as np

    v = wet.variables
    mu = np.stack([v["mu_wet_cold_w0"], v["mu_wet_cold_w1"], v["mu_wet_hot_w0"],
                   v["mu_wet_hot_w1"]], axis=-1)
    nd, nv, nT, np_, _ = mu.shape
    nt = wet.axes["log10_t_drain"].size
    head = WET_MAGIC + struct.pack("<6I", WET_VERSION, nd, nt, nv, nT, np_)
    parts = [np.array([d_full, drain_scale], "<f8"), wet.axes["water_depth"],
             wet.axes["log10_t_drain"], mu, v["w_dry"]]
    body = head + b"".join(np.ascontiguousarray(a, dtype="<f8").tobytes() for a in parts)
    return body + struct.pack("<Q", fnv1a64(body))


def read_wet_bytes(data: bytes) -> dict[str, Any]:
    """Inverse of :func:`wet_bytes`: ``d_full``, ``drain_scale``, ``depth``, ``log10_t``,
    ``mu`` (nd, nv, nT, np, 4) and ``w_dry`` (nd, nt, nv, nT, np).

    Raises
    ------
    ValueError
        Not a wet-branch file, another version, or a checksum or size mismatch.
    """
    import numpy as np

    if len(data) < 60 or data[:16] != WET_MAGIC:
        raise ValueError("not a tirefric wet-branch file")
    version, nd, nt, nv, nT, np_ = struct.unpack("<6I", data[16:40])
    if version != WET_VERSION or struct.unpack("<Q", data[-8:])[0] != fnv1a64(data[:-8]):
        raise ValueError("unsupported version or checksum mismatch")
    nn = nv * nT * np_
    if len(data) != 48 + 8 * (2 + nd + nt + 4 * nd * nn + nd * nt * nn):
        raise ValueError("wet-branch file size does not match its header")
    a = np.frombuffer(data[40:-8], dtype="<f8")
    o = 2 + nd + nt
    return {"d_full": float(a[0]), "drain_scale": float(a[1]), "depth": a[2:2 + nd],
            "log10_t": a[2 + nd:o], "mu": a[o:o + 4 * nd * nn].reshape(nd, nv, nT, np_, 4),
            "w_dry": a[o + 4 * nd * nn:].reshape(nd, nt, nv, nT, np_)}
