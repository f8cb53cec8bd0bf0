"""ctypes binding of the compiled tire core (``tire_brush/csrc/tirecore.c``).

The core is a C99 library with a plain C API (``tirecore.h``): friction table, transient tire
(create / step / get_state / set_state / free), the steady march, and a tensor
B-spline read at one point (``bspline.h``: a braking study's force map). It is built by the
package's install as the extension file ``tire_brush/_tirecore*.so`` (``*.pyd`` on Windows)
and loaded here with :mod:`ctypes` (it is not a Python module: it needs no Python at all,
which is what lets a native FMU embed it). Where no built library is found (a source
checkout that was not installed, or a platform whose wheel was built without it) the sources
are compiled once with the C compiler on the ``PATH`` (``cc``, or ``$CC``) into a cache folder
(``$TIREFRIC_CACHE``, default ``~/.cache/tirefric``), keyed by the hash of the sources.

Windows and macOS: the install needs a C compiler (MSVC Build Tools on Windows, the Xcode
command-line tools on macOS); the fallback compile uses ``$CC`` (e.g. ``clang``, or ``zig
cc``).

Every floating-point operation of the core is mirrored by the readable reference
:mod:`tire_brush.element`; the tests pin the two together. This module imports only numpy,
the standard library and :mod:`tire_brush.signals`: it runs inside an FMU.
"""

from __future__ import annotations

import ctypes
import hashlib
import importlib.machinery
import os
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np

from tirefric.errors import TirefricError

from .signals import INPUT_NAMES, OUTPUT_NAMES

#: Folder of the C sources.
SOURCE_DIR = Path(__file__).with_name("csrc")
#: C sources of the core, in link order.
SOURCES = ("tirecore.c", "tirert.c", "bspline.c")
#: Headers of the core.
HEADERS = ("tirecore.h", "tirert.h", "bspline.h")
#: Compiler flags of every build of the core (the package's install reads them from here,
#: setup.py; the native FMU adds ``-shared``; benchmarks compiling the core use them too):
#: C99, optimised, no contraction of multiply-adds and no fast-math (the Python reference
#: rounds every product: the two must agree to the last bit).
CORE_CFLAGS = ("-std=c99", "-O2", "-ffp-contract=off", "-fno-fast-math")
#: Flags of the shared library compiled here (:func:`compile_library`).
CFLAGS = (*CORE_CFLAGS, "-fPIC", "-shared")
#: Inputs and outputs of a step (``TF_NIN``, ``TF_NOUT``: the tire's signal table,
#: :mod:`tire_brush.signals`), element columns (``TF_ELEM``), steady columns
#: (``TF_STEADY_IN``, ``TF_STEADY_OUT``). tests/test_interface_table.py parses ``tirecore.h``
#: and compares.
N_IN, N_OUT = len(INPUT_NAMES), len(OUTPUT_NAMES)
N_ELEM, STEADY_IN, STEADY_OUT = 8, 5, 10
#: Work counters of a tire (``TF_NCOUNT``): sub-steps, stage solves, budget fallbacks.
N_COUNT = 3

_lock = threading.Lock()
_lib: ctypes.CDLL | None = None
#: A library chosen by :func:`use_library` (an FMU's own copy), tried first.
_chosen: Path | None = None


class CoreError(TirefricError, RuntimeError):
    """The compiled core could not be built, loaded or refused its input."""


class Params(ctypes.Structure):
    """``tf_params`` of ``tirecore.h`` (SI units; fields as in :mod:`tire_brush.params`)."""

    _fields_ = [(n, ctypes.c_double) for n in (
        "R_e", "Fz_nom", "R0", "width", "C_z", "q_ra1", "q_ra2", "q_rb1", "q_rb2", "Fz_max",
        "p_inflation", "p_nom", "p_fz1", "end_zone",
        "k_x", "k_y", "mass", "d_x", "d_y", "void_ratio", "tread_depth")] + [
        ("rigid", ctypes.c_int)] + [
        (n, ctypes.c_double) for n in ("kc_x", "kc_y", "dc_x", "dc_y", "kc_psi", "dc_psi",
                                       "camber_reduction")] + [
        ("thermal", ctypes.c_int)] + [
        (n, ctypes.c_double) for n in ("heat_capacity", "conductance", "heat_fraction")] + [
        ("n_elements", ctypes.c_int), ("dt_internal", ctypes.c_double),
        ("tol", ctypes.c_double), ("v_floor", ctypes.c_double),
        ("contact_ageing", ctypes.c_int)]


def _sources_digest() -> str:
    h = hashlib.sha256()
    for name in (*SOURCES, *HEADERS):
        h.update((SOURCE_DIR / name).read_bytes())
    h.update(" ".join(CFLAGS).encode())
    h.update(sys.platform.encode())
    return h.hexdigest()[:16]


def built_library() -> Path | None:
    """The library built by the package's install, if present."""
    here = Path(__file__).parent
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = here / f"_tirecore{suffix}"
        if path.is_file():
            return path
    return None


def compile_library(out_dir: str | Path | None = None, *, cc: str | None = None) -> Path:
    """Compile the core into ``out_dir`` (default: the cache folder) and return the file.

    Raises
    ------
    CoreError
        No compiler, or the compile failed (its output is in the message).
    """
    digest = _sources_digest()
    if out_dir is None:
        out_dir = Path(os.environ.get("TIREFRIC_CACHE", Path.home() / ".cache" / "tirefric"))
    out_dir = Path(out_dir)
    ext = ".dll" if sys.platform == "win32" else ".dylib" if sys.platform == "darwin" else ".so"
    target = out_dir / f"libtirecore-{digest}{ext}"
    if target.is_file():
        return target
    cc = cc or os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc") or \
        shutil.which("clang")
    if not cc:
        raise CoreError("no C compiler found to build the tire core (install gcc or clang, or "
                        "set CC); or reinstall tirefric, whose install builds it")
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out_dir) as tmp:
        tmp_target = Path(tmp) / target.name
        cmd = [*cc.split(), *CFLAGS, "-o", str(tmp_target),
               *(str(SOURCE_DIR / s) for s in SOURCES), "-lm"]
        res = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if res.returncode != 0:
            raise CoreError(f"compiling the tire core failed ({' '.join(cmd)}):\n"
                            f"{res.stdout}{res.stderr}")
        os.replace(tmp_target, target)
    return target


def platform_dir() -> str:
    """FMI 2.0 name of this platform's binaries folder (``linux64``, ``win64``,
    ``darwin64``)."""
    bits = "64" if sys.maxsize > 2**32 else "32"
    if sys.platform == "win32":
        return "win" + bits
    if sys.platform == "darwin":
        return "darwin" + bits
    return "linux" + bits


def library_file_name() -> str:
    """File name of the core library on this platform."""
    return {"win32": "tirecore.dll", "darwin": "libtirecore.dylib"}.get(sys.platform,
                                                                         "libtirecore.so")


def use_library(path: str | Path) -> bool:
    """Load the core from ``path`` (an FMU's own copy) instead of the installed one, if the
    core is not loaded yet in this module; returns whether ``path`` is the one in use."""
    global _chosen
    path = Path(path)
    with _lock:
        if _lib is None:
            _chosen = path
        return _chosen == path


def library_path() -> Path:
    """The core library: one chosen by :func:`use_library`, ``$TIREFRIC_CORE`` if set, the
    installed one, else a cached build."""
    if _chosen is not None and _chosen.is_file():
        return _chosen
    env = os.environ.get("TIREFRIC_CORE")
    if env:
        return Path(env)
    return built_library() or compile_library()


def _declare(lib: ctypes.CDLL) -> None:
    dp = ctypes.POINTER(ctypes.c_double)
    ip = ctypes.POINTER(ctypes.c_int)
    vp = ctypes.c_void_p
    pp = ctypes.POINTER(Params)
    sig = {
        "tf_table_new": (vp, [ctypes.c_int] * 3 + [dp] * 4 + [ctypes.c_double]),
        "tf_table_free": (None, [vp]),
        "tf_tire_new": (vp, [pp, vp]),
        "tf_tire_free": (None, [vp]),
        "tf_tire_reset": (None, [vp, ctypes.c_double]),
        "tf_tire_step": (ctypes.c_int, [vp, ctypes.c_double, dp, dp]),
        "tf_tire_lattice": (ctypes.c_int, [vp]),
        "tf_tire_state_size": (ctypes.c_int, [vp]),
        "tf_tire_get_state": (None, [vp, dp]),
        "tf_tire_set_state": (ctypes.c_int, [vp, dp]),
        "tf_tire_work": (ctypes.c_double, [vp]),
        "tf_tire_flags": (ctypes.c_int, [vp]),
        "tf_tire_counters": (None, [vp, dp]),
        "tf_tire_set_rolling": (ctypes.c_int, [vp, vp]),
        "tf_wet_new": (vp, [ctypes.c_int] * 5 + [dp] * 4 + [ctypes.c_double] * 2),
        "tf_wet_free": (None, [vp]),
        "tf_tire_set_wet": (ctypes.c_int, [vp, vp, ctypes.c_double]),
        "tf_steady": (ctypes.c_int, [pp, vp, ctypes.c_int, ctypes.c_int, dp, ctypes.c_double,
                                     ctypes.c_double, dp]),
        "tf_patch_new": (vp, [ctypes.POINTER(ctypes.c_int), dp, dp, dp, dp]),
        "tf_patch_free": (None, [vp]),
        "tf_patch_set_depth_law": (ctypes.c_int, [vp, dp]),
        "tf_patch_eval": (ctypes.c_int, [vp] + [ctypes.c_double] * 6 + [dp]),
        "tf_patch_new_wet": (vp, [ctypes.POINTER(ctypes.c_int), ctypes.c_int] + [dp] * 5),
        "tf_patch_eval_wet": (ctypes.c_int, [vp] + [ctypes.c_double] * 7 + [dp]),
        "tf_patch_layers": (ctypes.c_int, [vp]),
        "tf_tire_set_patch": (ctypes.c_int, [vp, vp]),
        "tf_bspline_new": (vp, [ctypes.c_int] + [ip] * 4 + [dp] * 4),
        "tf_bspline_free": (None, [vp]),
        "tf_bspline_eval": (ctypes.c_double, [vp] + [ctypes.c_double] * 4),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args


def load() -> ctypes.CDLL:
    """The loaded core (loaded once per process)."""
    global _lib
    with _lock:
        if _lib is None:
            path = library_path()
            try:
                lib = ctypes.CDLL(str(path))
            except OSError as exc:
                raise CoreError(f"cannot load the tire core {path}: {exc}") from None
            _declare(lib)
            _lib = lib
        return _lib


def _ptr(a: np.ndarray) -> ctypes._Pointer:
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


class CoreTable:
    """A friction table in the core (``tf_table``), owned by this object.

    Parameters
    ----------
    log10_v, T, log10_p
        Strictly ascending axes (>= 2 nodes).
    values
        Node values, shape ``(nv, nT, np, 3)``: mu_cold, mu_hot [1], dT_flash [K].
    inv_s0
        ``1 / s0`` of eq. (28) [1/m] (0: cold only).
    """

    def __init__(self, log10_v: np.ndarray, T: np.ndarray, log10_p: np.ndarray,
                 values: np.ndarray, inv_s0: float) -> None:
        self._lib = load()
        axes = [np.ascontiguousarray(a, dtype=float) for a in (log10_v, T, log10_p)]
        vals = np.ascontiguousarray(values, dtype=float)
        self._keep = (axes, vals)
        handle = self._lib.tf_table_new(axes[0].size, axes[1].size, axes[2].size,
                                        *(_ptr(a) for a in axes), _ptr(vals), float(inv_s0))
        if not handle:
            raise CoreError("the tire core refused the friction table (axes must be strictly "
                            "ascending with >= 2 nodes, values finite, 1/s0 >= 0)")
        self.handle = handle

    def __del__(self) -> None:
        handle = getattr(self, "handle", None)
        if handle:
            self._lib.tf_table_free(handle)
            self.handle = None


class CoreWet:
    """A wet branch in the core (``tf_wet``), owned by this object (freed with it)."""

    def __init__(self, handle: int, lib: ctypes.CDLL) -> None:
        self.handle = handle
        self._lib = lib

    def __del__(self) -> None:
        handle = getattr(self, "handle", None)
        if handle:
            self._lib.tf_wet_free(handle)
            self.handle = None


def core_params(params, *, n_elements: int, dt_internal: float, tol: float, v_floor: float,
                thermal: bool, rigid: bool, massless: bool = False) -> Params:
    """``tf_params`` of a :class:`~tire_brush.params.TireParams` and the model options.

    ``massless`` drops the tip mass and the damping (Pacejka's brush of ch. 3).
    """
    P = Params()
    P.R_e, P.Fz_nom = params.R_e, params.Fz_nom
    pl = params.patch
    for f in ("R0", "width", "C_z", "q_ra1", "q_ra2", "q_rb1", "q_rb2", "Fz_max",
              "p_inflation", "p_nom", "p_fz1", "end_zone"):
        setattr(P, f, getattr(pl, f))
    tr = params.tread
    P.k_x, P.k_y, P.void_ratio, P.tread_depth = tr.k_x, tr.k_y, tr.void_ratio, tr.depth
    P.mass, P.d_x, P.d_y = (0.0, 0.0, 0.0) if massless else (tr.mass, tr.d_x, tr.d_y)
    c = params.carcass
    P.rigid = int(bool(rigid))
    P.kc_x, P.kc_y, P.dc_x, P.dc_y = c.k_x, c.k_y, c.d_x, c.d_y
    P.kc_psi, P.dc_psi = c.k_psi, c.d_psi
    P.camber_reduction = c.camber_reduction
    th = params.thermal
    P.thermal = int(bool(thermal))
    P.heat_capacity, P.conductance, P.heat_fraction = (th.heat_capacity, th.conductance,
                                                       th.heat_fraction)
    P.n_elements = int(n_elements)
    P.dt_internal, P.tol, P.v_floor = float(dt_internal), float(tol), float(v_floor)
    P.contact_ageing = int(bool(tr.contact_ageing))
    return P


_TABLES: dict = {}


def core_table(table) -> CoreTable:
    """The core's copy of a :class:`~tire_brush.friction.BranchTable` (built once per table
    object and shared: tables are immutable)."""
    import weakref

    key = id(table)
    hit = _TABLES.get(key)
    if hit is not None and hit[0]() is table:
        return hit[1]
    ct = CoreTable(table.log10_v, table.T, table.log10_p, table.values, table.inv_s0)
    _TABLES[key] = (weakref.ref(table, lambda _r, k=key: _TABLES.pop(k, None)), ct)
    return ct


#: Results of ``tf_patch_eval`` (``TF_PATCH_NOUT`` of tirert.h).
PATCH_NOUT = 16


class CorePatch:
    """A patch table of the real-time fidelity in the core (``tf_patch``), owned by this
    object (:class:`tire_brush.realtime.PatchTable`)."""

    def __init__(self, table) -> None:
        self._lib = load()
        n = (ctypes.c_int * 6)(*(a.size for a in table.axes()))
        axes = np.ascontiguousarray(np.concatenate(table.axes()), dtype=float)
        vals = np.ascontiguousarray(table.values, dtype=float)
        q = np.ascontiguousarray(table.q, dtype=float)
        f0 = np.ascontiguousarray(table.f0, dtype=float)
        depth = np.ascontiguousarray(table.depth, dtype=float)
        self._keep = depth
        self.handle = self._lib.tf_patch_new_wet(n, depth.size, _ptr(depth), _ptr(axes), _ptr(q),
                                                 _ptr(f0), _ptr(vals))
        if not self.handle:
            raise CoreError("the tire core refused the patch table")
        if table.depth_law is not None:
            law = np.ascontiguousarray(table.depth_law, dtype=float)
            if self._lib.tf_patch_set_depth_law(self.handle, _ptr(law)) != 0:
                self._lib.tf_patch_free(self.handle)
                self.handle = None
                raise CoreError("the tire core refused the patch table's depth law")
        self._out = np.zeros(PATCH_NOUT)

    def eval(self, Vx: float, Vy: float, Vr: float, Fz: float, T: float,
             gamma: float, d_water: float = 0.0) -> tuple[np.ndarray, int]:
        """``tf_patch_eval_wet``: the :data:`PATCH_NOUT` results and the flags (water depth
        ``d_water`` [m], 0: the dry road)."""
        fl = self._lib.tf_patch_eval_wet(self.handle, Vx, Vy, Vr, Fz, T, gamma, d_water,
                                         _ptr(self._out))
        return self._out.copy(), int(fl)

    def __del__(self) -> None:
        h = getattr(self, "handle", None)
        if h:
            self._lib.tf_patch_free(h)
            self.handle = None


def core_patch(table) -> CorePatch:
    """The core's copy of a :class:`tire_brush.realtime.PatchTable`."""
    return CorePatch(table)
