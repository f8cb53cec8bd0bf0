"""The real-time fidelity of the brush tire: a quasi-steady patch on the belt's dynamics.

The full tire (:mod:`tire_brush.transient`, ``tirecore.c``) integrates every tread element
through the patch; a 1 ms step costs 0.1-5 M instructions (docs/tire-core.md, "Cost"). Real-time
physical tire models keep such a model for reference and run a reduced one in the loop (TameTire,
MF-Swift, FTire's real-time mode). This module is that reduced model of the same tire
(docs/realtime.md):

* **The patch is quasi-steady.** Its response, the forces ``Fx, Fy, Mz`` and ``mu_slide``,
  ``sliding_fraction``, ``dT_flash_max`` and the friction power (the heat of the patch), is
  the steady march of the same elements (:meth:`tire_brush.steady.SteadyBrush.patch_response`,
  ``tf_steady`` of the core: eq. (28) blending along the patch, the same friction grid and
  pressure shape), with the belt unyawed, tabulated at build time (:func:`build_patch_table`)
  over the slip velocity the tread sees (polar: the slip share
  ``rho = |V| / (|V| + |V_r|)``, 0 rolling freely, 1 locked, and the direction
  ``theta = atan2(V_y, |V_x|)``), the speed ``|V| + |V_r|``, the load, the tread temperature
  and the inclination. The slip share is read on the scale of the load's own full-sliding slip
  (the similarity of the brush's force curves over the load, Pacejka 2012, ch. 3 and 4): the
  axis is ``rho_n = rho / (rho + q (1 - rho))`` with ``q = 3 Fz / C`` (``C = 2 k_x b a^2`` the
  brush's slip stiffness at the load: ``rho_n = 1/2`` where a brush of friction 1 slides
  entirely), so the force peak sits at the same nodes whatever the load. The forces are
  stored in the slip's own frame (along and across the slip, over ``Fz``), which
  interpolates without the cosine's curvature, less the force at zero slip (the camber's,
  a fixed vector kept apart).
* **Transients come from the belt and the tread's transit.** The belt is the full model's:
  massless, springs ``k_c`` and dampers ``d_c`` to the rim in ``x`` and ``y`` and the yaw
  (twist) spring ``k_psi`` with damper ``d_psi`` (Pacejka 2012, sec. 3.3), loaded by the
  patch's forces and moment; it moves the slip the tread sees by its deflection rate, and the
  yaw turns the lateral slip by ``-V_r psi``. The tread carries deflection through the patch:
  a change of slip reaches the adhering elements only as new ones enter. Its lag is that of
  the adhesion zone: the patch's slip velocity ``V_p`` follows the belt's ``V_b`` with the
  relaxation length ``(2a/3) (1 - sliding_fraction)`` (a sliding element carries
  no memory). The length is the mean delay of the brush's linear response: a step of slip
  reaches an element that has rolled ``x`` into the patch as ``min(x, s)`` after the tire has
  rolled ``s``, so the force rises as ``s/a - s^2/4a^2`` up to ``s = 2a``, whose delay
  ``integral (1 - F/F_inf) ds`` is ``2a/3`` whatever the pressure along the patch; a
  first-order lag of the same delay keeps the sum of delays of tread and carcass in series,
  and so the relaxation length of the whole (measured in docs/realtime.md).
* **Integration.** Fixed sub-steps no longer than ``dt_internal`` of linearly implicit Euler
  on belt, yaw and patch slip together (the patch's forces linearised about the sub-step's
  start with the table's own derivatives): L-stable for the linear relaxation however stiff
  the coupling (the belt's damper time ``d_c / k_c`` is 0.25 ms, the coupled tread mode
  shorter still), and a steady state of the full model's equations is reproduced exactly.
* **The tread temperature, camber, Mx, My, state.** As in the full model: the lumped tread
  temperature heated by ``heat_fraction`` of the friction power, the inclination an axis of
  the table, ``Mx = -delta_y Fz``, the rolling-resistance table.
* **Water.** A table built on a grid with a wet branch has a layer per water depth (depth 0
  the dry road's), each the steady march on the wet friction the full model reads at its
  nodes (:func:`tire_brush.realtime_build.build_patch_table`); the water depth is read
  between the two layers about it by the full model's depth law of the friction
  (:attr:`PatchTable.depth_law`), clamped to the layers' depths.

This file is the readable reference of ``tire_brush/csrc/tirert.c``, operation for operation;
the tests pin the two together. It imports numpy and the standard library only at module level
(it runs inside the FMU).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tirefric.errors import InputError

#: Values stored per node: force along the slip (opposing it, over Fz), force across it (over
#: Fz), Mz / Fz [m], the moment of the tread's stress on the belt over Fz [m] (it yaws the
#: belt), mu_slide, sliding_fraction, dT_flash_max [K], friction power over
#: (Fz (|V| + |V_r|)) [1].
VALUE_NAMES: tuple[str, ...] = ("f_along", "f_across", "mz", "mb", "mu_slide",
                                "sliding_fraction", "dT_flash_max", "power")
N_VALUES = len(VALUE_NAMES)
#: Axes of the table, outermost first (the values are stored C-contiguous in this order with
#: the value index innermost).
AXIS_NAMES: tuple[str, ...] = ("gamma", "T", "Fz", "log10_v", "theta", "rho")

#: Default nodes of the normalised slip share ``rho_n`` (module docstring): every 0.04 over the
#: linear rise (the aligning and belt moments' curvature there sets the relaxation after a
#: step of slip angle), every 0.02 from 0.2 to 0.4 (the force peak, and the aligning moment's
#: collapse as the patch comes to slide whole, both narrower than 0.04 on the full model's
#: march), every 0.025 to 0.5, wider towards locking; the resolution measured in
#: docs/realtime.md.
RHO_NODES: tuple[float, ...] = (0.0, 0.04, 0.08, 0.12, 0.16, 0.2, 0.22, 0.24, 0.26, 0.28, 0.3,
                                0.32, 0.34, 0.36, 0.38, 0.4, 0.425, 0.45, 0.475, 0.5, 0.57,
                                0.65, 0.75, 0.87, 0.93, 1.0)
#: Default direction nodes [rad]: 22.5 degrees from pure lateral slip (-90) to pure lateral (90).
THETA_NODES: tuple[float, ...] = tuple(math.radians(-90.0 + 22.5 * k) for k in range(9))
#: Default speed nodes [m/s] of |V| + |V_r|; the first is also the speed floor of rho. From 4 to
#: 35 m/s about evenly in log v (ratio ~1.7; the sliding friction's speed dependence, which
#: the ratio 2-2.5 left 2.5 % of Fz off between nodes: docs/realtime.md).
SPEED_NODES: tuple[float, ...] = (1.0, 4.0, 7.0, 12.0, 20.0, 35.0, 70.0)
#: Default load nodes [N]: every factor ~4/3 from 2 to 6.5 kN (the aligning moment's collapse
#: moves with the load; the factor 1.5 left 5-6 % of its peak off between nodes:
#: docs/realtime.md).
LOAD_NODES: tuple[float, ...] = (1000.0, 2000.0, 2700.0, 3600.0, 4800.0, 6500.0, 10000.0)
#: Default inclination nodes [rad] (|gamma|; the table is mirrored for gamma < 0).
GAMMA_NODES: tuple[float, ...] = (0.0, 0.1)
#: Default spacing of the temperature nodes [K] over the friction grid's temperature range.
T_STEP = 10.0


def fnv1a64(data: bytes) -> int:
    """64-bit FNV-1a hash as the FMUs' resource files use it (``fnv1a`` of the native FMU's
    tfn_files.c, :func:`fmu_src.runtime.table_file.fnv1a64`: the same offset basis)."""
    h = 1469598103934665603
    for byte in data:
        h = ((h ^ byte) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


@dataclass(frozen=True)
class PatchTable:
    """The steady patch response tabulated for the real-time fidelity.

    Attributes
    ----------
    gamma, T, Fz, log10_v, theta, rho : numpy.ndarray
        Strictly ascending axes: |inclination| [rad] (first node 0), tread temperature [K],
        load [N], log10 of ``|V| + |V_r|`` [m/s] (the first node's speed is the floor of the
        slip share's denominator), slip direction [rad] in [-pi/2, pi/2], normalised slip
        share ``rho_n`` [1] from 0 to 1 (module docstring).
    q : numpy.ndarray
        The slip share of full sliding ``3 Fz / C`` (< 1) at each load node [1]; linear in
        the load between them.
    f0 : numpy.ndarray
        Shape ``(n_gamma, n_T, n_Fz, n_v, 2)``: the force at zero slip (the camber's) over
        Fz, x and y [1]; the values' forces in the slip's frame are those of the force less
        this one (a fixed vector, which the slip's frame would turn with the slip's
        direction where the slip is tiny).
    values : numpy.ndarray
        Shape ``(n_gamma, n_T, n_Fz, n_v, n_theta, n_rho, N_VALUES)``, see
        :data:`VALUE_NAMES` (with a leading axis over ``depth`` when it has more than one
        layer, as ``f0``). Held at single precision, as the file stores them (rounded on
        construction; a relative 6e-8, against the interpolation's ~1e-2 between nodes:
        docs/realtime.md), so that a table read back, the core's copy and the Python mirror
        evaluate the same numbers.
    key : str
        Hash of the tire parameters, friction table and axes it was built from.
    depth : numpy.ndarray
        Water depths [m] of the table's layers, strictly ascending from 0 (the dry road;
        default: that one layer). With more than one layer ``f0`` and ``values`` carry a
        leading axis over them: each layer the patch on the grid's wet branch at that depth
        (:func:`tire_brush.realtime_build.build_patch_table`, docs/realtime.md).
    depth_law : numpy.ndarray or None
        Shape ``(n_depth - 1, n_gamma, n_T, n_Fz, n_v, n_theta, n_rho)``: the curvature
        ``kappa`` in [-1, 1] of the full model's depth law between each two neighbouring
        layers at each node: at the fraction ``f`` of the way from one layer's depth to the
        next the full model's friction has moved the share ``s = f - kappa f (1 - f)`` of
        the way between the two layers' (its wet branch is read as the product of two
        linear interpolations in the depth, so the friction is quadratic in ``f``:
        :mod:`lookup.grid.wet`), and the table reads the layers with the weights ``1 - s``
        and ``s`` (the force follows the friction between two layers of one node far more
        closely than it follows the depth; docs/realtime.md). None: the weights ``1 - f``
        and ``f``.
    """

    gamma: np.ndarray
    T: np.ndarray
    Fz: np.ndarray
    log10_v: np.ndarray
    theta: np.ndarray
    rho: np.ndarray
    q: np.ndarray
    f0: np.ndarray
    values: np.ndarray
    key: str = ""
    meta: dict = field(default_factory=dict, compare=False)
    depth: np.ndarray = field(default_factory=lambda: np.zeros(1))
    depth_law: np.ndarray | None = None

    def __post_init__(self) -> None:
        axes = self.axes()
        d = np.asarray(self.depth, float)
        object.__setattr__(self, "depth", d)
        if d.ndim != 1 or d.size < 1 or d[0] != 0.0 or not np.all(np.isfinite(d)) \
                or not np.all(np.diff(d) > 0):
            raise InputError("must be strictly ascending water depths from 0 [m]",
                             field="patch_table.depth", value=d.tolist())
        lead = (d.size,) if d.size > 1 else ()
        for name, ax in zip(AXIS_NAMES, axes, strict=True):
            if ax.ndim != 1 or ax.size < 2 or not np.all(np.isfinite(ax)) \
                    or not np.all(np.diff(ax) > 0):
                raise InputError("must be a strictly ascending axis of >= 2 finite nodes",
                                 field=f"patch_table.{name}", value=ax.tolist())
        if self.gamma[0] != 0.0 or self.rho[0] != 0.0 or self.rho[-1] != 1.0:
            raise InputError("gamma must start at 0 and rho run from 0 to 1",
                             field="patch_table.axes", value=[self.gamma[0], self.rho[0],
                                                              self.rho[-1]])
        if not (self.theta[0] >= -math.pi / 2 - 1e-12 and self.theta[-1] <= math.pi / 2 + 1e-12):
            raise InputError("must lie in [-pi/2, pi/2]", field="patch_table.theta",
                             value=self.theta.tolist())
        if self.q.shape != self.Fz.shape or not np.all((self.q > 0) & (self.q < 1)):
            raise InputError("must lie in (0, 1), one per load node", field="patch_table.q",
                             value=np.asarray(self.q).tolist())
        shape = (*lead, *(a.size for a in axes), N_VALUES)
        s0 = (*shape[:len(lead) + 4], 2)
        if self.f0.shape != s0 or not np.all(np.isfinite(self.f0)):
            raise InputError(f"must be finite with shape {s0}",
                             field="patch_table.f0", value=self.f0.shape)
        if self.values.shape != shape or not np.all(np.isfinite(self.values)):
            raise InputError(f"must be finite with shape {shape}", field="patch_table.values",
                             value=self.values.shape)
        # single precision, as stored in the file (to_bytes): float32 is round-to-nearest, and
        # every float32 is a double, so C's copy and the Python mirror read these exactly
        object.__setattr__(self, "values",
                           np.asarray(self.values, np.float32).astype(np.float64))
        if self.depth_law is not None:
            k = np.asarray(self.depth_law, float)
            object.__setattr__(self, "depth_law", k)
            sk = (d.size - 1, *shape[len(lead):-1])
            if d.size < 2 or k.shape != sk or not np.all(np.abs(k) <= 1.0):
                raise InputError(f"must lie in [-1, 1] with shape {sk} (a table with water "
                                 f"layers)", field="patch_table.depth_law", value=k.shape)

    def axes(self) -> tuple[np.ndarray, ...]:
        """The axes in :data:`AXIS_NAMES` order."""
        return (self.gamma, self.T, self.Fz, self.log10_v, self.theta, self.rho)

    def to_bytes(self) -> bytes:
        """The table as the FMUs read it (:meth:`from_bytes`; in C ``tf_patch_from_bytes`` of
        tirert.c, which the native FMU calls after checking the trailer).

        Format 3: the magic ``TIREFRIC-PATCH\\0\\3``; the number of depth layers (1: a dry
        table), the six axis lengths and a flag (1 when the depth law follows the values, else
        0), little-endian int32; the depths, the axes, ``q`` and ``f0`` of every layer as
        little-endian doubles; the values of every layer as little-endian single-precision
        floats (:attr:`values`: the file's size halves, the FMU's with it); the depth law
        (:attr:`depth_law`, doubles) when flagged; and the FNV-1a 64 hash of all that
        (little-endian uint64)."""
        law = self.depth_law is not None
        head = b"TIREFRIC-PATCH\0\3" + struct.pack("<8i", self.depth.size,
                                                    *(a.size for a in self.axes()), int(law))
        body = b"".join(np.ascontiguousarray(a, "<f8").tobytes()
                        for a in (self.depth, *self.axes(), self.q, self.f0))
        data = head + body + np.ascontiguousarray(self.values, "<f4").tobytes()
        if law:
            data += np.ascontiguousarray(self.depth_law, "<f8").tobytes()
        return data + struct.pack("<Q", fnv1a64(data))

    @classmethod
    def from_bytes(cls, data: bytes, key: str = "", *, verify: bool = True) -> PatchTable:
        """Read :meth:`to_bytes`' format 3 (``verify=False`` skips the checksum, which takes a
        few seconds in Python: for a file whose sha256 was checked already)."""
        if len(data) < 56 or data[:16] != b"TIREFRIC-PATCH\0\3":
            raise InputError("not a patch table (format 3)", field="patch_table",
                             value=len(data))
        nd, *nl, law = struct.unpack("<8i", data[16:48])
        n = tuple(nl)
        if min(n) < 2 or nd < 1 or law not in (0, 1) or (law and nd < 2):
            raise InputError("axis lengths must be >= 2, layers >= 1 and the depth law's "
                             "flag 0 or 1 (1 only with layers)", field="patch_table",
                             value=(nd, n, law))
        nn = math.prod(n)
        n0 = n[0] * n[1] * n[2] * n[3] * 2
        n_head = nd + sum(n) + n[2] + nd * n0        # doubles ahead of the values
        n_val = nd * nn * N_VALUES                     # floats
        n_law = law * (nd - 1) * nn                    # doubles after them
        if len(data) != 48 + 8 * n_head + 4 * n_val + 8 * n_law + 8 or \
                (verify and struct.unpack("<Q", data[-8:])[0] != fnv1a64(data[:-8])):
            raise InputError("wrong size for its axes or checksum mismatch (corrupt file)",
                             field="patch_table", value=len(data))
        arr = np.frombuffer(data, "<f8", count=n_head, offset=48).astype(float)
        depth = arr[:nd].copy()
        off = nd
        lead: tuple[int, ...] = (nd,) if nd > 1 else ()
        axes = []
        for k in n:
            axes.append(arr[off:off + k].copy())
            off += k
        q = arr[off:off + n[2]].copy()
        off += n[2]
        f0 = arr[off:off + nd * n0].reshape((*lead, *n[:4], 2)).copy()
        start = 48 + 8 * n_head
        vals = np.frombuffer(data, "<f4", count=n_val, offset=start).astype(float)
        vals = vals.reshape((*lead, *n, N_VALUES))
        dl = None
        if law:
            dl = np.frombuffer(data, "<f8", count=n_law, offset=start + 4 * n_val)
            dl = dl.astype(float).reshape((nd - 1, *n))
        return cls(*axes, q=q, f0=f0, values=vals, key=key, depth=depth, depth_law=dl)


# ---------------------------------------------------------------------------- evaluation


def _locate(ax: np.ndarray | list[float], x: float) -> tuple[int, float, float]:
    """Cell ``i`` and weight ``f`` of ``x`` on a strictly ascending axis, clamped to its ends,
    and ``1 / (ax[i+1] - ax[i])`` (0 when clamped: the derivative there is 0)."""
    n = len(ax)
    if not (x > ax[0]):
        return 0, 0.0, 0.0
    if not (x < ax[n - 1]):
        return n - 2, 1.0, 0.0
    i = 0
    while ax[i + 1] <= x:
        i += 1
    inv = 1.0 / (ax[i + 1] - ax[i])
    return i, (x - ax[i]) * inv, inv


class PatchEval:
    """Python mirror of the core's evaluation of a patch table (``patch_eval`` of tirert.c).

    Call with the patch slip velocity ``(Vx, Vy)`` [m/s], the rolling speed ``V_r`` [m/s], the
    load ``Fz`` [N], temperature ``T`` [K], inclination ``gamma`` [rad] and the water depth
    ``d_water`` [m] (default 0, the dry road; between the table's two layers about it by
    their depth law, :attr:`PatchTable.depth_law`, or linearly without one; clamped to their
    depths as the full model clamps the wet branch); returns
    ``(F, J, extra, flags)``: ``F = [Fx, Fy, Mz, M_belt]``, ``J`` their derivatives by ``Vx``
    and ``Vy`` (row-major 4 x 2), ``extra = [mu_slide, sliding_fraction, dT_flash_max, power
    [W]]``, and 2 when ``T`` lies outside the table's temperature axis.
    """

    def __init__(self, table: PatchTable) -> None:
        self.t = table
        self.ax = [a.tolist() for a in table.axes()]
        self.n = [len(a) for a in self.ax]
        self.val = table.values.ravel().tolist()
        self.vmin = math.pow(10.0, float(table.log10_v[0]))
        self.q = table.q.tolist()
        self.f0 = table.f0.ravel().tolist()
        self.depth = table.depth.tolist()
        self.law = None if table.depth_law is None else table.depth_law.ravel().tolist()
        self.lval = int(np.prod(self.n)) * N_VALUES
        self.lf0 = self.n[0] * self.n[1] * self.n[2] * self.n[3] * 2

    def __call__(self, Vx: float, Vy: float, Vr: float, Fz: float, T: float,
                 gamma: float, d_water: float = 0.0
                 ) -> tuple[list[float], list[float], list[float], int]:
        sx = -1.0 if Vx < 0.0 else 1.0
        sg = -1.0 if gamma < 0.0 else 1.0
        sv = -1.0 if Vr < 0.0 else 1.0
        ax_ = abs(Vx)
        vy = Vy * sg
        s = math.sqrt(ax_ * ax_ + vy * vy)
        vr = abs(Vr)
        vref = s + vr
        den = vref if vref > self.vmin else self.vmin
        rho = s / den
        drho = (vr / (den * den)) if vref > self.vmin else 1.0 / den
        theta = math.atan2(vy, ax_) if s > 0.0 else 0.0
        if s > 0.0:
            ux, uy = ax_ / s, vy / s
        else:
            ux, uy = 1.0, 0.0
        iF, fF, _ = _locate(self.ax[2], Fz)
        qs = self.q[iF] + fF * (self.q[iF + 1] - self.q[iF])
        D = rho + qs * (1.0 - rho)
        rn = rho / D
        drho = drho * (qs / (D * D))
        xs = (abs(gamma), T, Fz, math.log10(den), theta, rn)
        loc = [_locate(self.ax[k], xs[k]) for k in range(6)]
        flags = 2 if not (self.ax[1][0] <= T <= self.ax[1][-1]) else 0
        n = self.n
        strides = [0] * 6
        st = N_VALUES
        for k in range(5, -1, -1):
            strides[k] = st
            st *= n[k]
        acc = [0.0] * N_VALUES
        dr = [0.0, 0.0, 0.0, 0.0]
        dth = [0.0, 0.0, 0.0, 0.0]
        base = 0
        for k in range(6):
            base += loc[k][0] * strides[k]
        # the outer (gamma, T, Fz, v) cell's first node in the zero-slip force array
        ob = ((loc[0][0] * n[1] + loc[1][0]) * n[2] + loc[2][0]) * n[3] + loc[3][0]
        g0x = g0y = 0.0
        # the 16 outer corners (gamma, T, Fz, v) with a weight: their weights and offsets from
        # the cell's first node, each corner with its 2 x 2 (theta, rho) cell
        cw: list[float] = []
        co: list[int] = []
        for c in range(16):
            w = 1.0
            off = 0
            for k in range(4):
                bit = (c >> (3 - k)) & 1
                f = loc[k][1]
                w *= f if bit else 1.0 - f
                off += bit * strides[k]
            if w == 0.0:
                continue
            cw.append(w)
            co.append(off)
        ft, fr = loc[4][1], loc[5][1]
        # the water depth: the two layers about it, clamped to the layers' depths (a dry-only
        # table: the one layer)
        il, fl = 0, 0.0
        if len(self.depth) > 1:
            il, fl, _ = _locate(self.depth, d_water)
            if self.law is not None and fl > 0.0 and fl < 1.0:
                # the full model's depth law between the two layers (PatchTable.depth_law):
                # its curvature at the point, multilinear over the node cell as the values
                s4, s5 = strides[4] // N_VALUES, strides[5] // N_VALUES
                kb = il * (self.lval // N_VALUES) + base // N_VALUES
                kap = 0.0
                for i in range(len(cw)):
                    k00 = kb + co[i] // N_VALUES
                    k10 = k00 + s4
                    a00, a01 = self.law[k00], self.law[k00 + s5]
                    a10, a11 = self.law[k10], self.law[k10 + s5]
                    lo = a00 + fr * (a01 - a00)
                    hi = a10 + fr * (a11 - a10)
                    kap += cw[i] * (lo + ft * (hi - lo))
                fl = fl - kap * (fl * (1.0 - fl))
        for lay in range(2):
            wl = fl if lay else 1.0 - fl
            if wl == 0.0:
                continue
            lbase = base + (il + lay) * self.lval
            lob = ob + (il + lay) * (self.lf0 // 2)
            for i in range(len(cw)):
                w = wl * cw[i]
                off = lbase + co[i]
                o0 = 2 * (lob + co[i] // strides[3])
                g0x += w * self.f0[o0]
                g0y += w * self.f0[o0 + 1]
                p00 = off
                p01 = off + strides[5]
                p10 = off + strides[4]
                p11 = p10 + strides[5]
                v = self.val
                for q in range(N_VALUES):
                    a00, a01, a10, a11 = v[p00 + q], v[p01 + q], v[p10 + q], v[p11 + q]
                    lo = a00 + fr * (a01 - a00)
                    hi = a10 + fr * (a11 - a10)
                    acc[q] += w * (lo + ft * (hi - lo))
                    if q < 4:
                        dr[q] += w * ((a01 - a00) + ft * ((a11 - a10) - (a01 - a00)))
                        dth[q] += w * (hi - lo)
        ir, it = loc[5][2], loc[4][2]
        for q in range(4):
            dr[q] *= ir
            dth[q] *= it
        fa, fc, mz, mb = acc[0], acc[1], acc[2], acc[3]
        # the force in the folded frame: -f_along along the slip, f_across across it
        nx, ny = -uy, ux
        Fxf = Fz * (g0x + (-fa * ux + fc * nx))
        Fyf = Fz * (g0y + (-fa * uy + fc * ny))
        # derivatives by the folded velocity (a, c) = (|Vx|, sg Vy)
        r1 = self.ax[5][1]
        s1 = 0.5 * ((r1 * qs) / (1.0 - r1 * (1.0 - qs))) * den
        se = s if s > s1 else s1
        J = [0.0] * 8
        for j in range(2):
            sj = ux if j == 0 else uy
            nj = nx if j == 0 else ny
            dfa = dr[0] * drho * sj + dth[0] * nj / se
            dfc = dr[1] * drho * sj + dth[1] * nj / se
            dmz = dr[2] * drho * sj + dth[2] * nj / se
            dmb = dr[3] * drho * sj + dth[3] * nj / se
            J[j] = Fz * (-dfa * ux + dfc * nx - fa * nx * nj / se - fc * ux * nj / se)
            J[2 + j] = Fz * (-dfa * uy + dfc * ny - fa * ny * nj / se - fc * uy * nj / se)
            J[4 + j] = Fz * dmz
            J[6 + j] = Fz * dmb
        F = [sx * Fxf, sg * Fyf, sg * sv * (Fz * mz), sg * sv * (Fz * mb)]
        # unfold: d/dVx = sx d/da, d/dVy = sg d/dc
        Jo = [J[0], sx * sg * J[1], sg * sx * J[2], J[3], sg * sv * sx * J[4], sv * J[5],
              sg * sv * sx * J[6], sv * J[7]]
        extra = [acc[4], acc[5], acc[6], acc[7] * Fz * vref]
        return F, Jo, extra, flags


def evaluate(table: PatchTable, Vx: Any, Vy: Any, Vr: Any, Fz: Any, T: Any,
             gamma: Any = 0.0, d_water: Any = 0.0) -> dict[str, np.ndarray]:
    """The table's patch response at arrays of points (numpy broadcasting): ``Fx, Fy, Mz``
    [N, N m], ``mu_slide``, ``sliding_fraction``, ``dT_flash_max``, ``power`` [W] (water
    depth ``d_water`` [m])."""
    ev = PatchEval(table)
    arrs = np.broadcast_arrays(*(np.asarray(x, float) for x in (Vx, Vy, Vr, Fz, T, gamma,
                                                                 d_water)))
    res = np.zeros((*arrs[0].shape, 8))
    for idx in np.ndindex(arrs[0].shape):
        F, _, ex, _ = ev(*(float(a[idx]) for a in arrs))
        res[idx] = F + ex
    names = ("Fx", "Fy", "Mz", "M_belt", "mu_slide", "sliding_fraction", "dT_flash_max",
             "power")
    return {k: res[..., i] for i, k in enumerate(names)}


#: Flag of a step that read the friction outside the table's temperature axis (the core's
#: ``TF_FLAG_T_RANGE``).
FLAG_T_RANGE = 2


def rt_advance(p: Any, ev: PatchEval, s: Any, h: float, Vsx: float, Vsy: float, V_r: float,
               Fz: float, a: float, Ts: float, mus: float, gamma: float,
               q_roll: float, d_water: float = 0.0) -> list[float]:
    """One sub-step ``h`` [s] of the real-time fidelity (``rt_advance`` of tirert.c): belt,
    yaw and the patch's slip velocity by linearly implicit Euler, the tread temperature by
    implicit Euler (module docstring).

    Parameters
    ----------
    p
        Core parameters (:class:`tire_brush.ccore.Params` fields).
    ev
        The patch table's evaluator.
    s
        State with attributes ``delta`` (belt deflection, 2) [m], ``Vb`` (the patch's slip
        velocity, 2) [m/s], ``F`` (the patch force, 2) [N], ``M`` (the moment on the belt) [N m],
        ``psi`` (belt yaw) [rad], ``wpsi`` (its rate) [rad/s], ``T_tread`` [K], ``flags``;
        updated in place.
    h, Vsx, Vsy, V_r, Fz, a, Ts, mus, gamma, q_roll, d_water
        Sub-step [s], the rim's slip velocity and the rolling speed [m/s], the road's load
        [N], the patch half-length at it [m], T_surface [K], mu_scale, inclination [rad],
        the tread's share of the rolling loss [W] and the water depth [m] (0 without a wet
        branch).

    Returns
    -------
    list
        ``fin`` as the full model's outer step: ``[contact, -, sliding_fraction, mu_slide,
        dT_flash_max, impulse_x, impulse_y, impulse_Mz]``.
    """
    fin = [0.0] * 8
    rigid = p.rigid != 0
    if not (Fz > 0.0 and a > 0.0) or not (mus > 1e-6):
        # no contact (or no friction): the belt relaxes on its dampers, as the full model's
        if not rigid:
            s.delta[0] *= p.dc_x / (p.kc_x * h + p.dc_x)
            s.delta[1] *= p.dc_y / (p.kc_y * h + p.dc_y)
            s.psi *= p.dc_psi / (p.kc_psi * h + p.dc_psi)
        s.Vb[0] = Vsx
        s.Vb[1] = Vsy - V_r * s.psi
        s.wpsi = 0.0
        s.F[0] = s.F[1] = 0.0
        s.M = 0.0
        if p.thermal:
            s.T_tread = (s.T_tread + h / p.heat_capacity * (p.conductance * Ts)) / \
                (1.0 + h * p.conductance / p.heat_capacity)
        return fin
    T0 = s.T_tread if p.thermal else Ts
    # the patch at the sub-step's start; a friction scale by the similarity method (Pacejka
    # 2012, ch. 4): the patch at mu_scale and slip V responds as mu_scale times the patch at
    # 1 and V / mu_scale (sliding speeds and friction power scale once more)
    ims = 1.0 / mus
    F, J, ex, fl = ev(s.Vb[0] * ims, s.Vb[1] * ims, V_r, Fz, T0, gamma, d_water)
    s.flags |= fl
    F0x, F0y, Mz0, M0 = mus * F[0], mus * F[1], mus * F[2], mus * F[3]
    frac = ex[1]
    if frac > 1.0:
        frac = 1.0
    if not (frac > 0.0):
        frac = 0.0
    vr = abs(V_r)
    if vr < ev.vmin:
        vr = ev.vmin
    # the tread's lag: the transit of the adhesion zone (the mean delay 2a/3 of the brush's
    # linear response to a step of slip, module docstring), and at least the tip's own response
    # time sqrt(m / k) (a sliding patch is still a tread of massive tips on springs in series
    # with the belt: without it a falling friction would close an algebraic loop through the
    # massless belt)
    tau = ((2.0 / 3.0) * a) * (1.0 - frac) / vr
    kmax = p.k_x if p.k_x > p.k_y else p.k_y
    tau_tip = math.sqrt(p.mass / kmax)
    if tau < tau_tip:
        tau = tau_tip
    if not rigid:
        # where the patch's force falls with its slip (J_xx or J_yy > 0: a falling friction),
        # the loop patch -> massless belt -> patch is stable only while J < d_c + k_c tau; the
        # lag is made long enough for twice the slope (the full model stick-slips there, its
        # mean is what the table holds; docs/realtime.md)
        t_x = (2.0 * J[0] - p.dc_x) / p.kc_x
        t_y = (2.0 * J[3] - p.dc_y) / p.kc_y
        if tau < t_x:
            tau = t_x
        if tau < t_y:
            tau = t_y
    t_ = tau + h
    if rigid:
        iAx = iAy = 0.0
        iB = 0.0
        kcx = kcy = kps = 0.0
    else:
        iAx = 1.0 / (p.kc_x + p.dc_x / h)
        iAy = 1.0 / (p.kc_y + p.dc_y / h)
        iB = 1.0 / (p.kc_psi + p.dc_psi / h)
        kcx, kcy, kps = p.kc_x, p.kc_y, p.kc_psi
    hv = h * V_r * iB
    m11 = t_ - J[0] * iAx
    m12 = -J[1] * iAx
    m21 = -J[2] * iAy + hv * J[6]
    m22 = t_ - J[3] * iAy + hv * J[7]
    r1 = h * (Vsx - s.Vb[0]) + (F0x - kcx * s.delta[0]) * iAx
    r2 = h * ((Vsy - V_r * s.psi) - s.Vb[1]) + (F0y - kcy * s.delta[1]) * iAy - \
        hv * (M0 - kps * s.psi)
    det = m11 * m22 - m12 * m21
    if not (det > 0.25 * t_ * t_):
        # the linearisation would not be a contraction here: the patch's force held over
        # the sub-step (explicit in the force, implicit in the belt)
        J = [0.0] * 8
        m11 = m22 = t_
        m12 = m21 = 0.0
        det = t_ * t_
    dVx = (r1 * m22 - m12 * r2) / det
    dVy = (m11 * r2 - m21 * r1) / det
    Fx = F0x + (J[0] * dVx + J[1] * dVy)
    Fy = F0y + (J[2] * dVx + J[3] * dVy)
    Mz = Mz0 + (J[4] * dVx + J[5] * dVy)
    Mb = M0 + (J[6] * dVx + J[7] * dVy)
    ddx = ddy = 0.0
    if not rigid:
        ddx = (Fx - kcx * s.delta[0]) * iAx
        ddy = (Fy - kcy * s.delta[1]) * iAy
        s.delta[0] += ddx
        s.delta[1] += ddy
        dpsi = (Mb - kps * s.psi) * iB
        s.psi += dpsi
        s.wpsi = dpsi / h
    s.Vb[0] += dVx
    s.Vb[1] += dVy
    s.F[0] = Fx
    s.F[1] = Fy
    s.M = Mb
    if p.thermal:
        # the patch's friction heat, at most the work the belt does on the patch (its force
        # on the belt's slip velocity, Vs + d(delta)/dt - V_r psi): while the patch's slip
        # lags the belt's the table's power at it could exceed what the belt delivers
        P = (mus * mus) * ex[3]
        Pb = -(Fx * (Vsx + ddx / h) + Fy * ((Vsy + ddy / h) - V_r * s.psi))
        if not (Pb > 0.0):
            Pb = 0.0
        if P > Pb:
            P = Pb
        Q = P * h
        s.T_tread = (s.T_tread + (p.heat_fraction * Q + h * q_roll +
                                  h * p.conductance * Ts) / p.heat_capacity) / \
            (1.0 + h * p.conductance / p.heat_capacity)
    fin[0] = 1.0
    fin[2] = ex[1]
    fin[3] = mus * ex[0]
    fin[4] = (mus * mus) * ex[2]
    fin[5] = h * Fx
    fin[6] = h * Fy
    fin[7] = h * Mz
    return fin
