r"""The sealing effect: the road spectrum that the rubber sees when water is trapped in cavities.

What the papers do. Persson, Tartaglino, Albohr & Tosatti (Nature Materials 3 (2004) 882;
Phys. Rev. B 71 (2005) 035428) explain the 20-30 % lower low-speed friction of rubber on wet
rough roads by *sealing*: where the rubber closes off a water-filled cavity ("pool") of the
road, the trapped water cannot escape on the time scale of the contact and, being nearly
incompressible, keeps the rubber out of it. The water surface is flat, so the road that the
rubber deforms over is smoother than the dry road. They compute a water-smoothed power
spectrum from the measured one, by filling the sealed pools of a surface topography with
water, and run the same friction theory (review eqs. 17-20) on it; adhesion is not involved.
(We had the abstracts and the review's summary, sec. 5.2 and 8, not the full texts; the
construction below is this project's, written from that description.)

What this module does (and where it differs):

1. **Topography.** A periodic height map with the surface's spectrum C(q), q0 <= q <= q1
   (Fourier filtering of white noise, :func:`lookup.topography.height_map_from_psd`; side
   ``L = L_over_lambda0 * 2 pi / q0`` so that the map holds several of the largest cavities;
   ``n_maps`` seeded realisations are averaged), or the surface file's measured height map
   when it gives one (``[psd] model = "height_map"``).
2. **Where sealing happens.** The contact at magnification q percolates while the Persson
   contact fraction P(q) (review eq. 18, corrected) is above the percolation threshold
   p_c = 0.42 of random roughness (Dapp, Luecke, Persson & Muesser, Phys. Rev. Lett. 108
   (2012) 244301: elastic contact of randomly rough surfaces percolates at A/A0 ~ 0.42). P
   falls with q, so the pools are those of the largest magnification that still percolates,
   q_c with P(q_c) = p_c (q_c = q1 when P(q1) >= p_c). The q_c of a friction point is taken
   from the *dry* contact at that point (no iteration with the sealed spectrum, which raises
   P: on the wet-grip road at 20 C, 0.3 MPa one iteration moves q_c from 4.8e3 to 1.5e4 1/m
   and lowers the viscoelastic wet/dry ratio from 0.69 to 0.67, docs/physics.md sec. 7a; the
   dry q_c is the smaller smoothing). If P has fallen below p_c already at the first
   resolved magnification above q0 (the engine's second q node), the contact never
   percolates over resolved roughness: no pool is sealed and the wet spectrum is the dry one.
3. **Which regions are pools.** The rubber at magnification q_c is taken to touch the
   highest fraction p_c of the map low-pass filtered to |q| <= q_c (the map seen at that
   magnification; a truncation model of the contact geometry, where the papers use their
   contact model). The connected non-contact regions are the cavities, and all of them are
   sealed: by the criterion of item 2 the contact percolates at q_c, so every non-contact
   region is enclosed. (In the truncation geometry itself the non-contact region may still
   span the map, because a Gaussian field's level set percolates at area 1/2 rather than
   0.42; that is an artefact of the truncation model, not a drainage channel, and is not
   treated as one. On a measured, non-periodic map the rim of a cavity cut by the map's edge
   is the part inside the map.)
4. **How full.** A sealed pool holds water up to its spill level, the lowest height of its
   rim (the contact pixels around it) as seen at the sealing magnification, i.e. on the
   filtered map: the rubber closes the pool at that level, and the roughness finer than q_c
   on the rim does not drain it within a contact time because the contact at q_c percolates
   around it (leakage through the finer, non-percolating channels is the squeeze-out of
   :mod:`lookup.wet.squeeze`, not modelled here). The fill level is never above the free
   water level on the road: a water film of depth d (volume per unit nominal area,
   so d = 0 is a dry road) fills the road's texture from its lowest points up to the level
   z_w with mean(max(z_w - h, 0)) = d. A point of a sealed pool below its fill level is
   replaced by the water surface at that level; the rest of the road is unchanged.
5. **The spectrum.** The ratio r(q) = C_wet(q) / C(q) is the ratio of the radially binned
   periodograms of the filled and the dry map of the same realisation (the realisation's
   scatter largely cancels), binned on the friction engine's q nodes. Only bins up to half the
   map's Nyquist wavenumber are used: the water surfaces meet the road with a kink, whose
   power above the Nyquist wavenumber aliases into the top bins. Above that r is held at its
   last value (not extrapolated). For q much larger than 1/(pool size) r should approach the
   area fraction not under pool water (fine roughness removed where water lies, kept
   elsewhere); the held value is above that limit (less smoothing) where the shores' kinks
   still add power. C_wet = r C.

The filled surface never rises above the dry one except inside pools, so r < 1 except for
the spectrum estimate's scatter near q0 (few Fourier modes per bin) and the power that the
kinks at the pools' shores add at some wavelengths; the tests bound r by 1 + that scatter.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from tirefric.errors import InputError

from ..roughness import PowerSpectrum
from ..topography import height_map_from_psd

#: Contact-area fraction at which the contact of randomly rough surfaces percolates
#: (Dapp, Luecke, Persson & Muesser, Phys. Rev. Lett. 108 (2012) 244301).
PERCOLATION_THRESHOLD = 0.42


@dataclass(frozen=True)
class SealingSettings:
    """Numerical settings of the sealed-spectrum construction (module docstring).

    Attributes
    ----------
    p_c : float
        Percolation threshold of the contact area (Dapp et al. 2012: 0.42).
    n : int
        Pixels per side of a synthetic map (even).
    L_over_lambda0 : float
        Side of a synthetic map in units of the largest wavelength 2 pi / q0.
    n_maps : int
        Seeded synthetic realisations averaged.
    seed : int
        Seed of the first realisation (``np.random.default_rng(seed + k)``).
    qc_per_decade : int
        Nodes per decade of the table over the sealing wavenumber q_c.
    """

    p_c: float = PERCOLATION_THRESHOLD
    n: int = 512
    L_over_lambda0: float = 4.0
    n_maps: int = 2
    seed: int = 2004
    qc_per_decade: int = 12

    def __post_init__(self) -> None:
        checks = [("p_c", 0.0 < self.p_c < 1.0), ("n", self.n >= 32 and self.n % 2 == 0),
                  ("L_over_lambda0", self.L_over_lambda0 >= 1.0),
                  ("n_maps", self.n_maps >= 1), ("qc_per_decade", self.qc_per_decade >= 2)]
        for name, ok in checks:
            if not ok:
                raise InputError("invalid sealing setting", field=f"wet.sealing.{name}",
                                 value=getattr(self, name))


def _bin_edges(q: np.ndarray) -> np.ndarray:
    """Edges halfway (geometrically) between the nodes q, the ends extended by half a step."""
    lq = np.log(q)
    mid = 0.5 * (lq[1:] + lq[:-1])
    return np.exp(np.concatenate([[lq[0] - (mid[0] - lq[0])], mid,
                                  [lq[-1] + (lq[-1] - mid[-1])]]))


def _periodic_labels(mask: np.ndarray) -> tuple[np.ndarray, int]:
    """Connected components (4-neighbour) of ``mask`` on the torus: labels 1..n, 0 = outside."""
    from scipy import ndimage
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    lab, n = ndimage.label(mask)
    if n == 0:
        return lab, 0
    a = np.concatenate([lab[:, 0], lab[0, :]])
    b = np.concatenate([lab[:, -1], lab[-1, :]])
    keep = (a > 0) & (b > 0)
    g = coo_matrix((np.ones(int(keep.sum())), (a[keep], b[keep])), shape=(n + 1, n + 1))
    _, comp = connected_components(g, directed=False)
    # renumber so that 0 stays the background and components are 1..m
    _, new = np.unique(comp[1:], return_inverse=True)
    mapping = np.concatenate([[0], new + 1])
    out = mapping[lab]
    return out, int(new.max()) + 1


def _rim_minimum(lab: np.ndarray, n_lab: int, h: np.ndarray, periodic: bool) -> np.ndarray:
    """Lowest height of the contact pixels 4-adjacent to each cavity (index 0 unused)."""
    rim = np.full(n_lab + 1, np.inf)
    contact = lab == 0
    for axis in (0, 1):
        for shift in (1, -1):
            if periodic:
                nb = np.roll(lab, shift, axis=axis)
            else:
                nb = np.zeros_like(lab)
                src = [slice(None)] * 2
                dst = [slice(None)] * 2
                src[axis] = slice(None, -1) if shift == 1 else slice(1, None)
                dst[axis] = slice(1, None) if shift == 1 else slice(None, -1)
                nb[tuple(dst)] = lab[tuple(src)]
            sel = contact & (nb > 0)
            np.minimum.at(rim, nb[sel], h[sel])
    return rim


def free_water_level(h: np.ndarray, depth: float) -> float:
    """Level z_w [m] with mean(max(z_w - h, 0)) = depth (module docstring item 4).

    Returns -inf for depth 0 (a dry road). Above the highest point the extra water lies on
    top: z_w = max(h) + (depth - void volume below max(h)).
    """
    if depth <= 0.0:
        return -math.inf
    hs = np.sort(h.ravel())
    n = hs.size
    # water volume per area when the level is at hs[k]: (k+1) hs[k]/n - cumsum(hs)[k]/n
    cum = np.cumsum(hs)
    vol = (np.arange(1, n + 1) * hs - cum) / n
    if depth >= vol[-1]:
        return float(hs[-1] + (depth - vol[-1]))
    k = int(np.searchsorted(vol, depth))
    # between hs[k-1] and hs[k] the volume grows linearly with slope k/n
    return float(hs[k - 1] + (depth - vol[k - 1]) * n / k)


@dataclass
class SealedMap:
    """One height map prepared for sealing: heights, its FFT, binning on the engine's q nodes.

    Parameters
    ----------
    h : numpy.ndarray
        Heights [m], shape (ny, nx).
    dx, dy : float
        Pixel sizes [m].
    q_nodes : numpy.ndarray
        The friction engine's wavenumber nodes [1/m] (bins are centred on them).
    periodic : bool
        Synthetic periodic map (True) or measured map (False: cavities at the edge are open).

    Notes
    -----
    The map is real, so its transform is kept on the half plane (``numpy.fft.rfft2``); the
    binned periodogram counts every mode of the dropped half through its conjugate (weight 2
    for the columns that have one), which is the full-plane sum.
    """

    h: np.ndarray
    dx: float
    dy: float
    q_nodes: np.ndarray
    periodic: bool

    def __post_init__(self) -> None:
        ny, nx = self.h.shape
        if not self.periodic:
            self.h = self.h - self.h.mean()
        kx = 2.0 * math.pi * np.fft.rfftfreq(nx, d=self.dx)
        ky = 2.0 * math.pi * np.fft.fftfreq(ny, d=self.dy)
        self.qabs = np.hypot(kx[None, :], ky[:, None])
        self.q_nyquist = math.pi / max(self.dx, self.dy)
        self.H = np.fft.rfft2(self.h)
        # conjugate pairs: columns 1 .. ceil(nx/2)-1 stand for two modes each
        wcol = np.full(kx.size, 2.0)
        wcol[0] = 1.0
        if nx % 2 == 0:
            wcol[-1] = 1.0
        self.mode_weight = np.broadcast_to(wcol[None, :], self.qabs.shape).ravel()
        edges = _bin_edges(self.q_nodes)
        b = np.searchsorted(edges, self.qabs.ravel(), side="right") - 1
        inside = (b >= 0) & (b < self.q_nodes.size) & (self.qabs.ravel() > 0) & (
            self.qabs.ravel() <= self.q_nyquist)
        self.bin = np.where(inside, b, self.q_nodes.size)
        self.count = np.bincount(self.bin, weights=self.mode_weight,
                                 minlength=self.q_nodes.size + 1)[:-1]
        self.dry = self._binned(self.H)
        self._h_sorted: np.ndarray | None = None
        self._z_w: dict[float, float] = {}

    def _binned(self, F: np.ndarray) -> np.ndarray:
        p = np.abs(F.ravel()) ** 2 * self.mode_weight
        return np.bincount(self.bin, weights=p, minlength=self.q_nodes.size + 1)[:-1]

    def water_level(self, depth: float) -> float:
        """:func:`free_water_level` of this map (cached per depth)."""
        z = self._z_w.get(depth)
        if z is None:
            z = self._z_w[depth] = free_water_level(self.h, depth)
        return z

    def pools(self, q_c: float, p_c: float) -> tuple[np.ndarray, np.ndarray]:
        """Sealed-pool labels (0 = not a sealed pool) and each pool's spill level [m]."""
        h_c = np.fft.irfft2(self.H * (self.qabs <= q_c), s=self.h.shape)
        if np.ptp(h_c) <= 1e-12 * max(np.ptp(self.h), 1e-300):
            return np.zeros(self.h.shape, int), np.zeros(1)
        z = np.quantile(h_c, 1.0 - p_c)
        cav = h_c < z
        if self.periodic:
            lab, n_lab = _periodic_labels(cav)
        else:
            from scipy import ndimage

            lab, n_lab = ndimage.label(cav)
        spill = _rim_minimum(lab, n_lab, h_c, self.periodic)
        return lab, spill

    def ratio(self, lab: np.ndarray, spill: np.ndarray, depth: float
              ) -> tuple[np.ndarray, float]:
        """C_wet/C per bin (NaN for empty bins) and the area fraction under pool water."""
        z_w = self.water_level(depth)
        level = np.minimum(spill, z_w)[lab]
        wet = (lab > 0) & (self.h < level)
        if not wet.any():
            return np.where(self.count > 0, 1.0, np.nan), 0.0
        hw = np.where(wet, level, self.h)
        Cw = self._binned(np.fft.rfft2(hw))
        with np.errstate(invalid="ignore", divide="ignore"):
            r = np.where((self.count > 0) & (self.dry > 0), Cw / self.dry, np.nan)
        return r, float(wet.mean())


class SealedSpectrum:
    """The table r(q; q_c, d) = C_wet(q)/C(q) on the engine's q nodes (module docstring).

    The rows of the table (one per sealing wavenumber node q_c) are computed when first
    needed and kept (:meth:`ratio` asks for the two nodes around each q_c it is given; the
    attributes :attr:`r` and :attr:`water_fraction` complete the table). A friction point
    seals at one q_c, and over a grid the q_c met span a few nodes, so most rows are never
    computed; the values of a row do not depend on which others exist.

    Parameters
    ----------
    psd : PowerSpectrum
        The road's spectrum.
    q_nodes : numpy.ndarray
        The friction engine's q nodes, q0 .. q1 [1/m].
    depths : sequence of float
        Water film depths [m] (>= 0) of the table.
    settings : SealingSettings, optional
    height_map : tuple (heights [m], dx [m], dy [m]) or None
        A measured map to use instead of synthetic ones.
    """

    def __init__(self, psd: PowerSpectrum, q_nodes: np.ndarray, depths,
                 settings: SealingSettings | None = None,
                 height_map: tuple[np.ndarray, float, float] | None = None) -> None:
        from .water import check_water_depth

        self.settings = s = settings or SealingSettings()
        self.q = np.asarray(q_nodes, float)
        self.depths = check_water_depth(depths)
        q0, q1 = float(self.q[0]), float(self.q[-1])
        n_qc = max(math.ceil(math.log10(q1 / self.q[1]) * s.qc_per_decade), 1) + 1
        self.q_c = np.geomspace(self.q[1], q1, n_qc)
        maps: list[SealedMap] = []
        if height_map is not None:
            hm, dx, dy = height_map
            maps.append(SealedMap(np.asarray(hm, float), dx, dy, self.q, periodic=False))
            self.source = "measured height map"
        else:
            L = s.L_over_lambda0 * 2.0 * math.pi / q0
            for k in range(s.n_maps):
                h = height_map_from_psd(s.n, L, psd, q1, rng=np.random.default_rng(s.seed + k))
                maps.append(SealedMap(h, L / s.n, L / s.n, self.q, periodic=True))
            self.source = "synthetic"
        self.maps = maps
        self.q_map = 0.5 * min(m.q_nyquist for m in maps)
        self.maps_used = len(maps)
        # r[i_d, i_qc, i_q] and the pool-water area fraction f[i_d, i_qc], filled per q_c row
        nd, nc, nq = self.depths.size, self.q_c.size, self.q.size
        self._r = np.full((nd, nc, nq), np.nan)
        self._f = np.zeros((nd, nc))
        self._done = np.zeros(nc, bool)

    def _fill(self, rows: np.ndarray) -> None:
        """Compute the table rows ``rows`` (indices into :attr:`q_c`) not computed yet."""
        for j in np.unique(np.asarray(rows, int)):
            if self._done[j]:
                continue
            nd, nq = self.depths.size, self.q.size
            num = np.zeros((nd, nq))
            den = np.zeros((nd, nq))
            f = np.zeros(nd)
            for m in self.maps:
                lab, spill = m.pools(float(self.q_c[j]), self.settings.p_c)
                for i, d in enumerate(self.depths):
                    r, fw = m.ratio(lab, spill, float(d))
                    ok = np.isfinite(r)
                    num[i, ok] += r[ok] * m.dry[ok]
                    den[i, ok] += m.dry[ok]
                    f[i] += fw / len(self.maps)
            with np.errstate(invalid="ignore", divide="ignore"):
                r = num / den
            # bins above the trusted band and empty bins (too few modes): the neighbouring
            # value (held, not extrapolated)
            r[:, self.q > self.q_map] = np.nan
            for i in range(nd):
                row = r[i]
                bad = ~np.isfinite(row)
                if bad.any():
                    good = np.flatnonzero(~bad)
                    row[bad] = np.interp(np.flatnonzero(bad), good, row[good])
            self._r[:, j] = r
            self._f[:, j] = f
            self._done[j] = True

    @property
    def r(self) -> np.ndarray:
        """The whole table r[i_depth, i_qc, i_q] (every row computed)."""
        self._fill(np.arange(self.q_c.size))
        return self._r

    @property
    def water_fraction(self) -> np.ndarray:
        """Area fraction under pool water f[i_depth, i_qc] (every row computed)."""
        self._fill(np.arange(self.q_c.size))
        return self._f

    def ratio(self, q_c: np.ndarray, i_depth: int) -> np.ndarray:
        """r(q) for sealing wavenumbers ``q_c`` (B,) at depth node ``i_depth``: (B, nq).

        Linear in ln q_c between table nodes; q_c below the first table node (the contact
        does not percolate over resolved roughness) gives r = 1.
        """
        q_c = np.asarray(q_c, float)
        x = np.log(np.clip(q_c, self.q_c[0], self.q_c[-1]))
        lq = np.log(self.q_c)
        sealed = q_c >= self.q_c[0]
        if lq.size == 1:
            self._fill(np.zeros(1, int))
            out = np.broadcast_to(self._r[i_depth, 0], (q_c.size, self.q.size)).copy()
        else:
            u = np.clip(np.searchsorted(lq, x) - 1, 0, lq.size - 2)
            t = ((x - lq[u]) / (lq[u + 1] - lq[u]))[:, None]
            if sealed.any():
                self._fill(np.concatenate([u[sealed], u[sealed] + 1]))
            # rows never needed (unsealed points) stay NaN; the where() below discards them
            with np.errstate(invalid="ignore"):
                out = (1 - t) * self._r[i_depth, u] + t * self._r[i_depth, u + 1]
        return np.where(sealed[:, None], out, 1.0)

    def describe(self) -> dict:
        return {"settings": asdict(self.settings), "source": self.source,
                "maps": self.maps_used, "q_map_per_m": self.q_map,
                "q_c_nodes_per_m": [float(self.q_c[0]), float(self.q_c[-1]), int(self.q_c.size)],
                "depths_m": self.depths.tolist(),
                "percolation_threshold_source":
                    "Dapp, Luecke, Persson & Muesser, Phys. Rev. Lett. 108 (2012) 244301",
                "method": "lookup.wet.sealing (Persson, Tartaglino, Albohr & Tosatti, Nat. "
                          "Mater. 3 (2004) 882; Phys. Rev. B 71 (2005) 035428; construction "
                          "documented in the module)"}


#: Sealed spectra kept per process by :func:`shared_sealed_spectrum` (the least recently
#: used is dropped beyond this many: a few MB each, the height maps and their transforms).
SHARED_MAX = 4
_SHARED: dict[str, SealedSpectrum] = {}


def shared_sealed_spectrum(psd: PowerSpectrum, q_nodes: np.ndarray, depths,
                           settings: SealingSettings | None = None,
                           height_map: tuple[np.ndarray, float, float] | None = None
                           ) -> SealedSpectrum:
    """The :class:`SealedSpectrum` of these arguments, one per process.

    The table depends on the road (its spectrum or height map), the engine's q nodes, the
    depths and the sealing settings, not on the compound, and a row's values do not depend
    on which other rows exist (:class:`SealedSpectrum`): a process that builds the wet
    branch of several compounds on one road (the compound screen, tire_brush.screening)
    computes each row once, with the same numbers bit for bit as a fresh table. The key is
    a SHA-256 of the pickled arguments (equal content, equal key)."""
    import hashlib
    import pickle

    q = np.asarray(q_nodes, float)
    d = np.asarray(depths, float)
    s = settings or SealingSettings()
    key = hashlib.sha256(pickle.dumps((type(psd).__qualname__, psd, q, d, s, height_map),
                                      protocol=4)).hexdigest()
    table = _SHARED.pop(key, None)
    if table is None:
        table = SealedSpectrum(psd, q, d, s, height_map)
    _SHARED[key] = table                   # most recently used last
    while len(_SHARED) > SHARED_MAX:
        _SHARED.pop(next(iter(_SHARED)))
    return table
