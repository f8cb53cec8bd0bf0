r"""Surface roughness power spectra from measured topography (review sec. 3; docs/review-notes.md,
Trap 4).

Conventions
-----------
The review's spectrum is the 2D isotropic power spectrum [m^4]

.. math::

    C(q) = \frac{1}{(2\pi)^2} \int d^2x \, \langle h(\mathbf x) h(\mathbf 0) \rangle
           e^{-i \mathbf q \cdot \mathbf x},
    \qquad h_{rms}^2 = 2\pi \int_0^\infty q C(q)\, dq, \qquad
    \xi^2 = 2\pi \int_0^\infty q^3 C(q)\, dq .

This is the review's eq. (9), ``C_2D(q) = (2 pi)^2 |h(q)|^2 / A_0`` with
``h(q) = (2 pi)^-2 int d^2x h(x) e^{iq.x}``. A line scan gives the 1D spectrum [m^3] of eq. (8),
``C_1D = 2 pi |h(q_x)|^2 / L``, i.e.
:math:`C_{1D}(q) = (2\pi)^{-1} \int dx \langle h(x) h(0) \rangle e^{-iqx}`, even in q, with
:math:`h_{rms}^2 = 2 \int_0^\infty C_{1D}(q)\, dq`. For an isotropic surface
:math:`C_{1D}(q_x) = \int dq_y\, C(\sqrt{q_x^2 + q_y^2})` (:func:`psd_1d_from_2d`), inverted by
the Abel transform (:func:`psd_2d_from_1d`; Persson, Tribol. Lett. 54 (2014) 99; Persson et al.,
J. Phys.: Condens. Matter 17 (2005) R1)

.. math::

    C(q) = -\frac{1}{\pi} \int_q^\infty dq' \, \frac{C_{1D}'(q')}{\sqrt{q'^2 - q^2}} .

SurfaceTopography's isotropic PSD is :math:`(2\pi)^2 C(q)` in this notation.

Discrete normalisation (periodic FFT). For an ``ny x nx`` map with pixel sizes dx, dy (area
``A = nx dx ny dy``) and ``H = numpy.fft.fft2(h)``, the periodogram is
``C(q_k) = |H_k|^2 dx dy / ((2 pi)^2 nx ny)`` on the lattice ``q = 2 pi (i/(nx dx), j/(ny dy))``
whose cells have area ``(2 pi)^2 / A``; then ``sum_k C(q_k) (2 pi)^2 / A = mean(h^2)`` exactly
(Parseval). In 1D, ``C1D(q_k) = |Z_k|^2 dx / (2 pi N)`` on ``q_k = 2 pi k / (N dx)``. A window
w is normalised by ``mean(w^2)`` so that the spectrum of a stationary surface is unbiased.
The FFT treats the data as periodic: measured (non-periodic) data should be detrended and
windowed (the defaults); synthetic periodic maps are exact with ``detrend="none", window=None``.

Radial / log binning. Spectra are averaged in logarithmic bins (``bins_per_decade``, edges at
``10^(k / bins_per_decade)``); empty bins are dropped. In 2D only |q| <= pi / max(dx, dy) (the
largest full circle inside the Fourier lattice) is used. The bin value is the arithmetic mean
of the periodogram (unbiased for any height statistics); the bin's wavenumber is the q at which
a power law with the local slope (from the neighbouring bins) equals that mean,
``q_b = <q^-alpha>^(-1/alpha)`` over the bin's modes, so power laws are reproduced without the
few-percent bias of taking the mean q of a wide bin.

File formats
------------
Heights are read by :func:`read_height_map` and :func:`read_line_scan`:

* ``.csv`` / ``.txt`` / ``.dat``: text. Lines starting with ``#`` are free-text comments (put
  the provenance there). Metadata lines have the form ``key = value`` (no ``#``; one word,
  then ``=``) and come before the data. Keys:

  - ``dx``: pixel size along x (columns), ``"<number> <unit>"`` with a length unit
    (``m, cm, mm, um, nm``) or a bare number in metres. Required.
  - ``dy``: pixel size along y (rows), maps only; defaults to ``dx``.
  - ``height_unit``: unit of the height values (a length unit). Required.

  Example header: ``dx = 0.5 um`` / ``dy = 0.5 um`` / ``height_unit = nm``, one per line.
  Unknown keys are errors (a misspelt key is not silently ignored). A height map has one row
  of values per y (first row y = 0), values separated by commas and/or whitespace. A line scan
  has one value per line. A line scan can instead be a two-column CSV table with the header
  ``x [unit], z [unit]`` (units as in :func:`tirefric.config.read_csv_table`); x must be equally
  spaced (to 1e-3 of the step) and then defines dx.
* ``.npz``: arrays ``heights`` [m] (2D map or 1D scan) and ``dx`` [m], optional ``dy`` [m].
* ``.npy``: a heights array [m]; the pixel size is passed as ``dx`` (and ``dy``) [m].

NaN or infinite heights (missing points), non-positive pixel sizes and fewer than
:data:`MIN_POINTS` points per axis are :class:`~tirefric.errors.InputError`\ s naming the file,
the field and the value.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

from tirefric.config import UNITS, parse_quantity, read_csv_table
from tirefric.errors import InputError

from .roughness import PowerSpectrum, SelfAffinePSD

#: Fewest points per axis accepted for a spectrum (fewer give < 8 wavenumbers).
MIN_POINTS = 16

Detrend2D = Literal["plane", "mean", "none"]
Detrend1D = Literal["line", "mean", "none"]
Window = Literal["hann"] | None
Tail = Literal["powerlaw", "none"]

_N_GAUSS = 16
_GL_X, _GL_W = np.polynomial.legendre.leggauss(_N_GAUSS)


# ------------------------------------------------------------------------------------------
# Input checks
# ------------------------------------------------------------------------------------------
def _check_step(value: float, name: str, source: str | Path | None = None) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError("pixel size must be a number [m]", source=source, field=name,
                         value=value) from None
    if not (math.isfinite(v) and v > 0):
        raise InputError("pixel size must be finite and > 0 [m]", source=source, field=name,
                         value=value)
    return v


def _check_heights(h: ArrayLike, ndim: tuple[int, ...], source: str | Path | None = None,
                   name: str = "heights") -> np.ndarray:
    """Return ``h`` as a float array after checking its shape, size and finiteness."""
    try:
        a = np.asarray(h, dtype=float)
    except (TypeError, ValueError):
        raise InputError("heights must be numbers", source=source, field=name) from None
    if a.ndim not in ndim:
        raise InputError(f"heights must be a {' or '.join(f'{d}D' for d in ndim)} array",
                         source=source, field=name, value=a.shape)
    # Maps need MIN_POINTS along both axes; parallel line scans (rows) along each row.
    short = a.shape if ndim == (2,) else a.shape[-1:]
    if a.size == 0 or min(short) < MIN_POINTS:
        raise InputError(f"too few points for a spectrum (need >= {MIN_POINTS} per axis)",
                         source=source, field=name, value=a.shape)
    bad = ~np.isfinite(a)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise InputError(f"{int(bad.sum())} height(s) are NaN or infinite (missing points?), "
                         f"first at index {idx}; fill or crop the data first",
                         source=source, field=name, value=a[idx])
    return a


def _check_spectrum(q: ArrayLike, C: ArrayLike, qname: str = "q",
                    cname: str = "C") -> tuple[np.ndarray, np.ndarray]:
    q = np.asarray(q, dtype=float)
    C = np.asarray(C, dtype=float)
    if q.ndim != 1 or q.shape != C.shape or q.size < 2:
        raise InputError("q and C must be 1D arrays of the same length >= 2", field=cname,
                         value=(q.shape, C.shape))
    if not (np.all(np.isfinite(q)) and np.all(q > 0) and np.all(np.diff(q) > 0)):
        raise InputError("wavenumbers must be finite, > 0 and strictly increasing [1/m]",
                         field=qname)
    if not np.all(np.isfinite(C)):
        raise InputError("spectrum must be finite", field=cname)
    return q, C


# ------------------------------------------------------------------------------------------
# Model spectrum and synthetic surfaces
# ------------------------------------------------------------------------------------------
def _check_n(n: int) -> int:
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < MIN_POINTS or n % 2:
        raise InputError(f"must be an even integer >= {MIN_POINTS}", field="n", value=n)
    return int(n)


def self_affine_C0(h_rms: float, H: float, q0: float, qr: float, q1: float) -> float:
    """Plateau C0 [m^4] of :class:`~lookup.roughness.SelfAffinePSD` cut off at q1 with rms h_rms.

    ``h_rms^2 = 2 pi C0 [(qr^2 - q0^2)/2 + qr^2 (1 - (q1/qr)^(-2H)) / (2H)]``, the closed form
    of ``2 pi int_q0^q1 q C dq`` (review sec. 3 spectrum with roll-off).

    Parameters
    ----------
    h_rms
        rms height [m].
    H
        Hurst exponent (0, 1).
    q0, qr, q1
        Lower cut-off, roll-off and upper cut-off [1/m], 0 < q0 <= qr < q1.
    """
    if not (math.isfinite(h_rms) and h_rms > 0):
        raise InputError("must be finite and > 0 [m]", field="h_rms", value=h_rms)
    if not 0 < H < 1:
        raise InputError("Hurst exponent must be in (0, 1)", field="H", value=H)
    if not (0 < q0 <= qr < q1 and math.isfinite(q1)):
        raise InputError("need 0 < q0 <= qr < q1 [1/m]", field="q0, qr, q1", value=(q0, qr, q1))
    m2 = 0.5 * (qr**2 - q0**2) + qr**2 / (2.0 * H) * (1.0 - (q1 / qr) ** (-2.0 * H))
    return h_rms**2 / (2.0 * math.pi * m2)


def isotropic_prefactor_ratio(H: float) -> float:
    r"""``C(q) q / C1D(q)`` for a self-affine power law: Gamma(1+H) / (sqrt(pi) Gamma(H+1/2)).

    For ``C(q) = C0 q^{-2(H+1)}`` the line-scan spectrum is ``C1D = C0 sqrt(pi)
    Gamma(H+1/2)/Gamma(H+1) q^{-(2H+1)}`` (Persson, Tribol. Lett. 54 (2014) 99): with
    k = q t the Abel integral :math:`\int_1^\infty t^{-2H-1}(t^2-1)^{-1/2}dt
    = \tfrac12 B(H + \tfrac12, \tfrac12)` is a Beta function.
    """
    if not H > -0.5:
        raise InputError("needs H > -1/2", field="H", value=H)
    return math.exp(math.lgamma(1.0 + H) - math.lgamma(H + 0.5)) / math.sqrt(math.pi)


def height_map_from_psd(n: int, L: float, psd: PowerSpectrum, q1: float | None = None, *,
                        rng: np.random.Generator | int,
                        random_amplitudes: bool = True) -> np.ndarray:
    """Periodic n x n height map [m] with the 2D spectrum ``psd.C(q)`` up to q1 (Fourier filtering).

    White Gaussian noise is Fourier transformed, multiplied by ``sqrt((2 pi)^2 C(q)/(dx dy))``
    and transformed back (the inverse of the normalisation in the module docstring), so the
    expected periodogram is C(q) at every lattice wavevector with |q| <= q1, and 0 above. The
    filter depends on |q| only, so Hermitian symmetry and a real map are preserved.

    Parameters
    ----------
    n
        Pixels per side (even, >= MIN_POINTS).
    L
        Side length [m]; dx = L / n.
    psd
        Any :class:`~lookup.roughness.PowerSpectrum` (self-affine or tabulated).
    q1
        Upper cut-off [1/m]; default pi n / L (the Nyquist wavenumber).
    rng
        A ``numpy.random.Generator`` or an integer seed for ``np.random.default_rng``.
    random_amplitudes
        True: Gaussian random surface (periodogram scatters like chi^2 with 2 d.o.f. about
        C). False: amplitudes exactly sqrt(C) with random phases, so the periodogram equals
        C(q) at every mode (for exact tests).

    Returns
    -------
    numpy.ndarray
        Heights [m], shape (n, n), rows along y.
    """
    n = _check_n(n)
    L = _check_step(L, "L")
    q1 = math.pi * n / L if q1 is None else _check_step(q1, "q1")
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    dx = L / n
    k = 2.0 * math.pi * np.fft.fftfreq(n, d=dx)
    qabs = np.hypot(k[None, :], k[:, None])
    W = np.fft.fft2(gen.standard_normal((n, n)))
    if not random_amplitudes:
        W = n * np.exp(1j * np.angle(W))
    C = np.where((qabs > 0) & (qabs <= q1), psd.C(np.where(qabs > 0, qabs, 1.0)), 0.0)
    filt = np.sqrt((2.0 * math.pi) ** 2 * C / (dx * dx))
    return np.fft.ifft2(W * filt).real


def self_affine_height_map(n: int, L: float, H: float, q0: float | None = None,
                           qr: float | None = None, q1: float | None = None, *,
                           C0: float | None = None, h_rms: float | None = None,
                           rng: np.random.Generator | int,
                           random_amplitudes: bool = True) -> np.ndarray:
    """Periodic self-affine height map [m]: :func:`height_map_from_psd` of a
    :class:`~lookup.roughness.SelfAffinePSD` (q0, qr, H, C0) cut off at q1.

    Parameters
    ----------
    n, L
        Pixels per side (even) and side length [m].
    H
        Hurst exponent (0, 1).
    q0, qr, q1
        Lower cut-off, roll-off and upper cut-off [1/m]; defaults 2 pi / L, q0, pi n / L.
    C0, h_rms
        Give exactly one: the plateau C0 [m^4] or the model's rms height [m] over q0..q1
        (:func:`self_affine_C0`; the realisation's rms differs by sampling).
    rng, random_amplitudes
        See :func:`height_map_from_psd`.
    """
    n = _check_n(n)
    L = _check_step(L, "L")
    q0 = 2.0 * math.pi / L if q0 is None else float(q0)
    qr = q0 if qr is None else float(qr)
    q1 = math.pi * n / L if q1 is None else float(q1)
    if (C0 is None) == (h_rms is None):
        raise InputError("give exactly one of C0 [m^4] and h_rms [m]", field="C0, h_rms",
                         value=(C0, h_rms))
    c0 = float(C0) if C0 is not None else self_affine_C0(float(h_rms), H, q0, qr, q1)
    return height_map_from_psd(n, L, SelfAffinePSD(q0, qr, H, c0), q1, rng=rng,
                               random_amplitudes=random_amplitudes)


# ------------------------------------------------------------------------------------------
# Periodograms
# ------------------------------------------------------------------------------------------
def _window_1d(n: int, window: Window) -> np.ndarray:
    if window is None:
        return np.ones(n)
    if window == "hann":
        return np.hanning(n)
    raise InputError("window must be 'hann' or None", field="window", value=window)


def _detrend_2d(h: np.ndarray, detrend: Detrend2D) -> np.ndarray:
    if detrend == "none":
        return h
    if detrend == "mean":
        return h - h.mean()
    if detrend == "plane":
        ny, nx = h.shape
        y, x = np.mgrid[0:ny, 0:nx]
        A = np.column_stack([np.ones(h.size), x.ravel(), y.ravel()])
        coef, *_ = np.linalg.lstsq(A, h.ravel(), rcond=None)
        return h - (A @ coef).reshape(h.shape)
    raise InputError("detrend must be 'plane', 'mean' or 'none'", field="detrend",
                     value=detrend)


def _detrend_rows(z: np.ndarray, detrend: Detrend1D) -> np.ndarray:
    if detrend == "none":
        return z
    if detrend == "mean":
        return z - z.mean(axis=-1, keepdims=True)
    if detrend == "line":
        x = np.arange(z.shape[-1], dtype=float)
        x -= x.mean()
        slope = (z * x).sum(axis=-1, keepdims=True) / (x * x).sum()
        return z - z.mean(axis=-1, keepdims=True) - slope * x
    raise InputError("detrend must be 'line', 'mean' or 'none'", field="detrend",
                     value=detrend)


def periodogram_2d(h: ArrayLike, dx: float, dy: float | None = None, *,
                   detrend: Detrend2D = "plane",
                   window: Window = "hann") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Full 2D periodogram C(qx, qy) [m^4] of a height map (normalisation: module docstring).

    Parameters
    ----------
    h
        Heights [m], shape (ny, nx), rows along y.
    dx, dy
        Pixel sizes [m]; ``dy`` defaults to ``dx``.
    detrend
        Remove the least-squares plane, the mean, or nothing.
    window
        ``"hann"`` (separable, normalised by mean(w^2)) or None (periodic data).

    Returns
    -------
    qx, qy, C
        Wavenumbers [1/m] in ``numpy.fft.fftfreq`` order and C [m^4] of shape (ny, nx). With
        ``window=None``, ``C.sum() * (2 pi)^2 / (nx dx ny dy)`` equals the mean square of the
        detrended heights (Parseval).
    """
    h = _check_heights(h, (2,))
    dx = _check_step(dx, "dx")
    dy = dx if dy is None else _check_step(dy, "dy")
    ny, nx = h.shape
    h = _detrend_2d(h, detrend)
    w = _window_1d(ny, window)[:, None] * _window_1d(nx, window)[None, :]
    H = np.fft.fft2(h * w)
    C = np.abs(H) ** 2 * dx * dy / ((2.0 * math.pi) ** 2 * nx * ny * np.mean(w * w))
    qx = 2.0 * math.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, d=dy)
    return qx, qy, C


def periodogram_1d(z: ArrayLike, dx: float, *, detrend: Detrend1D = "line",
                   window: Window = "hann") -> tuple[np.ndarray, np.ndarray]:
    """1D periodogram C1D(q) [m^3] for q > 0 of one scan or the mean over parallel scans.

    Parameters
    ----------
    z
        Heights [m]: shape (N,) for one scan or (n_scans, N) for parallel scans (their
        periodograms are averaged).
    dx
        Point spacing [m].
    detrend, window
        Per scan: remove the least-squares line, the mean or nothing; ``"hann"`` or None.

    Returns
    -------
    q, C1D
        ``q_k = 2 pi k / (N dx)``, k = 1 .. N//2 [1/m], and ``|Z_k|^2 dx / (2 pi N)`` [m^3].
        With ``window=None``: ``mean(z^2) = (2 pi / (N dx)) (C1D(0) + 2 sum_{0<k<N/2} C1D +
        C1D(N/2))`` (Parseval, the Nyquist term once for even N).
    """
    z = _check_heights(z, (1, 2))
    dx = _check_step(dx, "dx")
    z2 = np.atleast_2d(z)
    N = z2.shape[-1]
    z2 = _detrend_rows(z2, detrend)
    w = _window_1d(N, window)
    Z = np.fft.rfft(z2 * w, axis=-1)
    C = (np.abs(Z) ** 2).mean(axis=0) * dx / (2.0 * math.pi * N * np.mean(w * w))
    q = 2.0 * math.pi * np.fft.rfftfreq(N, d=dx)
    return q[1:], C[1:]


def _log_bin(q: np.ndarray, C: np.ndarray, bins_per_decade: int,
             q_max: float) -> tuple[np.ndarray, np.ndarray]:
    """Average C over modes in log bins; bin q from the local power law (module docstring)."""
    if isinstance(bins_per_decade, bool) or not isinstance(bins_per_decade, int | np.integer) \
            or bins_per_decade < 1:
        raise InputError("must be an integer >= 1", field="bins_per_decade",
                         value=bins_per_decade)
    keep = (q > 0) & (q <= q_max * (1 + 1e-12))
    q, C = q[keep], C[keep]
    k = np.floor(np.log10(q) * bins_per_decade + 1e-9).astype(int)
    k -= k.min()
    nb = int(k.max()) + 1
    count = np.bincount(k, minlength=nb)
    occupied = count > 0
    lnq = np.log(q)
    Cm = np.bincount(k, weights=C, minlength=nb)[occupied] / count[occupied]
    lq = np.bincount(k, weights=lnq, minlength=nb)[occupied] / count[occupied]
    # Local log-log slope -alpha from the neighbouring bins (one-sided at the ends).
    lC = np.log(np.where(Cm > 0, Cm, np.nan))
    if lq.size >= 2:
        slope = np.gradient(lC, lq)
    else:
        slope = np.zeros_like(lq)
    alpha = np.clip(np.nan_to_num(-slope, nan=0.0), -20.0, 20.0)
    # q_b = <q^-alpha>^(-1/alpha) relative to the bin's geometric mean (well conditioned).
    bin_of = np.cumsum(occupied) - 1
    ib = bin_of[k]
    d = lnq - lq[ib]
    a = alpha[ib]
    small = np.abs(alpha) < 1e-8
    mexp = np.bincount(ib, weights=np.exp(-a * d), minlength=lq.size) / count[occupied]
    shift = np.where(small, 0.0, -np.log(mexp) / np.where(small, 1.0, alpha))
    return np.exp(lq + shift), Cm


def psd_from_height_map(h: ArrayLike, dx: float, dy: float | None = None, *,
                        detrend: Detrend2D = "plane", window: Window = "hann",
                        bins_per_decade: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Radially averaged 2D spectrum C(q) [m^4] of a height map (review's convention).

    Parameters
    ----------
    h
        Heights [m], shape (ny, nx), rows along y, at least MIN_POINTS per axis.
    dx, dy
        Pixel sizes [m] (``dy`` defaults to ``dx``).
    detrend, window
        See :func:`periodogram_2d`. Defaults suit measured, non-periodic maps.
    bins_per_decade
        Logarithmic bins per decade of q.

    Returns
    -------
    q, C
        Bin wavenumbers [1/m] (2 pi / L .. pi / max(dx, dy)) and C(q) [m^4], with
        ``h_rms^2 ~ 2 pi int q C dq`` (:func:`hrms_from_psd`).
    """
    qx, qy, C2 = periodogram_2d(h, dx, dy, detrend=detrend, window=window)
    dxv = _check_step(dx, "dx")
    dyv = dxv if dy is None else _check_step(dy, "dy")
    qabs = np.hypot(qx[None, :], qy[:, None]).ravel()
    return _log_bin(qabs, C2.ravel(), bins_per_decade, math.pi / max(dxv, dyv))


def psd_from_line_scan(z: ArrayLike, dx: float, *, detrend: Detrend1D = "line",
                       window: Window = "hann",
                       bins_per_decade: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Log-binned 1D spectrum C1D(q) [m^3] of a line scan, ``h_rms^2 = 2 int_0^inf C1D dq``.

    Parameters
    ----------
    z
        Heights [m]: one scan (N,) or parallel scans (n_scans, N), averaged.
    dx
        Point spacing [m].
    detrend, window
        See :func:`periodogram_1d`.
    bins_per_decade
        Logarithmic bins per decade of q.

    Returns
    -------
    q, C1D
        Bin wavenumbers [1/m] (2 pi / (N dx) .. pi / dx) and C1D [m^3]. Use
        :func:`psd_2d_from_1d` for the review's 2D C(q) of an isotropic surface.
    """
    q, C = periodogram_1d(z, dx, detrend=detrend, window=window)
    return _log_bin(q, C, bins_per_decade, math.pi / _check_step(dx, "dx"))


# ------------------------------------------------------------------------------------------
# Isotropic 1D <-> 2D transforms (Abel pair), on log-spaced data
# ------------------------------------------------------------------------------------------
def _powerlaw_pieces(q: np.ndarray, C: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Segment exponents s_i with C = C_i (q/q_i)^-s_i between the points (log-log linear)."""
    if np.any(C <= 0):
        i = int(np.flatnonzero(C <= 0)[0])
        raise InputError(f"entry {i} must be > 0 (log-log interpolation)", field=name,
                         value=float(C[i]))
    lq, lC = np.log(q), np.log(C)
    return lq, -np.diff(lC) / np.diff(lq)


def _tail_slope(q: np.ndarray, C: np.ndarray, n_tail: int) -> float:
    if isinstance(n_tail, bool) or not isinstance(n_tail, int | np.integer) or \
            not 2 <= n_tail <= q.size:
        raise InputError(f"must be an integer in [2, {q.size}]", field="n_tail", value=n_tail)
    return float(-np.polyfit(np.log(q[-n_tail:]), np.log(C[-n_tail:]), 1)[0])


def _q_out(q: np.ndarray, q_out: ArrayLike | None) -> np.ndarray:
    if q_out is None:
        return q.copy()
    qo = np.atleast_1d(np.asarray(q_out, dtype=float))
    if not np.all(np.isfinite(qo)) or np.any(qo < q[0] * (1 - 1e-12)) or \
            np.any(qo > q[-1] * (1 + 1e-12)):
        raise InputError(f"must lie inside the data range [{q[0]:.6g}, {q[-1]:.6g}] 1/m",
                         field="q_out", value=q_out)
    return np.clip(qo, q[0], q[-1])


def _theta_quadrature(q: np.ndarray, qo: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes in theta, q' = q_out cosh(theta), per (output, segment).

    The substitution removes the 1/sqrt(q'^2 - q^2) singularity:
    ``dq' / sqrt(q'^2 - q^2) = dtheta``. Returns q' nodes, weights (0 for segments below
    q_out) and the segment index, each of shape (n_out, n_seg, N_GAUSS).
    """
    lo = np.maximum(q[None, :-1], qo[:, None]) / qo[:, None]
    hi = np.maximum(q[None, 1:], qo[:, None]) / qo[:, None]
    ta, tb = np.arccosh(lo), np.arccosh(hi)
    half = 0.5 * (tb - ta)
    theta = (0.5 * (ta + tb))[..., None] + half[..., None] * _GL_X
    qp = qo[:, None, None] * np.cosh(theta)
    w = half[..., None] * _GL_W
    seg = np.broadcast_to(np.arange(q.size - 1)[None, :, None], qp.shape)
    return qp, w, seg


def _incomplete_beta(a: float, b: float, x: np.ndarray) -> np.ndarray:
    """Unregularised incomplete Beta function B(x; a, b)."""
    return special.betainc(a, b, x) * special.beta(a, b)


def psd_2d_from_1d(q: ArrayLike, C1D: ArrayLike, q_out: ArrayLike | None = None, *,
                   tail: Tail = "powerlaw", n_tail: int = 3) -> np.ndarray:
    r"""Isotropic 2D spectrum C(q) [m^4] from a line-scan spectrum C1D(q) [m^3].

    ``C(q) = -(1/pi) int_q^inf C1D'(q') / sqrt(q'^2 - q^2) dq'`` (Persson, Tribol. Lett. 54
    (2014) 99), the inverse Abel transform of :func:`psd_1d_from_2d`.

    C1D is interpolated as a piecewise power law between the given points (linear in log-log,
    exact for self-affine data), so C1D' = -s_i C1D / q' on each segment, and with
    ``q' = q cosh(theta)`` each segment is a smooth integral done by 16-point Gauss-Legendre
    (relative error < 1e-10 for segments up to a decade wide). Beyond the last point C1D is
    continued as a power law fitted to the last ``n_tail`` points, integrated in closed form
    (incomplete Beta function), or (``tail="none"``) held constant, which biases C low within
    about a factor 2 in q of the last point. Noise in C1D is amplified by the derivative: bin
    measured spectra first (:func:`psd_from_line_scan`).

    Parameters
    ----------
    q
        Wavenumbers [1/m], strictly increasing, > 0 (log spacing is natural).
    C1D
        Line-scan spectrum [m^3] at ``q``, > 0.
    q_out
        Where to evaluate C [1/m] (inside [q[0], q[-1]]); default ``q``.
    tail
        ``"powerlaw"`` (needs a decaying tail, fitted exponent > 0) or ``"none"``.
    n_tail
        Points used for the tail exponent.

    Returns
    -------
    numpy.ndarray
        C(q_out) [m^4].
    """
    q, C1 = _check_spectrum(q, C1D, cname="C1D")
    lq, s = _powerlaw_pieces(q, C1, "C1D")
    qo = _q_out(q, q_out)
    qp, w, seg = _theta_quadrature(q, qo)
    # integrand of (1/pi) int dtheta s C1D(q') / q'
    f = s[seg] * C1[seg] * np.exp(-s[seg] * (np.log(qp) - lq[seg])) / qp
    out = (f * w).sum(axis=(1, 2)) / math.pi
    if tail == "powerlaw":
        st = _tail_slope(q, C1, n_tail)
        if not st > 0:
            raise InputError(f"fitted tail exponent {st:.3g} is not > 0 (C1D must decay); use "
                             "tail='none' or more points", field="C1D")
        u = (qo / q[-1]) ** 2
        out += (st * C1[-1] / qo * (q[-1] / qo) ** st * 0.5
                * _incomplete_beta(0.5 * (st + 1.0), 0.5, u) / math.pi)
    elif tail != "none":
        raise InputError("tail must be 'powerlaw' or 'none'", field="tail", value=tail)
    return out


def psd_1d_from_2d(q: ArrayLike, C: ArrayLike, q_out: ArrayLike | None = None, *,
                   tail: Tail = "powerlaw", n_tail: int = 3) -> np.ndarray:
    r"""Line-scan spectrum C1D(q) [m^3] of an isotropic surface with 2D spectrum C(q) [m^4].

    ``C1D(q) = int dq_y C(sqrt(q^2 + q_y^2)) = 2 int_q^inf C(k) k / sqrt(k^2 - q^2) dk``
    (Persson, Tribol. Lett. 54 (2014) 99), evaluated like :func:`psd_2d_from_1d`:
    piecewise power law in log-log, ``k = q cosh(theta)``, Gauss-Legendre per segment, and a
    power-law tail (fitted exponent > 1) in closed form, or no tail (``tail="none"``: C = 0
    beyond the last point, as for a surface cut off there).

    Parameters
    ----------
    q, C
        Wavenumbers [1/m] (strictly increasing) and the 2D spectrum [m^4], > 0.
    q_out
        Where to evaluate [1/m] (inside [q[0], q[-1]]); default ``q``.
    tail, n_tail
        Continuation beyond q[-1], see above.

    Returns
    -------
    numpy.ndarray
        C1D(q_out) [m^3].
    """
    q, C2 = _check_spectrum(q, C)
    lq, s = _powerlaw_pieces(q, C2, "C")
    qo = _q_out(q, q_out)
    qp, w, seg = _theta_quadrature(q, qo)
    f = 2.0 * C2[seg] * np.exp(-s[seg] * (np.log(qp) - lq[seg])) * qp
    out = (f * w).sum(axis=(1, 2))
    if tail == "powerlaw":
        st = _tail_slope(q, C2, n_tail)
        if not st > 1:
            raise InputError(f"fitted tail exponent {st:.3g} is not > 1; use tail='none'",
                             field="C")
        u = (qo / q[-1]) ** 2
        out += (2.0 * C2[-1] * qo * (q[-1] / qo) ** st * 0.5
                * _incomplete_beta(0.5 * (st - 1.0), 0.5, u))
    elif tail != "none":
        raise InputError("tail must be 'powerlaw' or 'none'", field="tail", value=tail)
    return out


# ------------------------------------------------------------------------------------------
# Moments of a spectrum
# ------------------------------------------------------------------------------------------
def _powerlaw_cumulative(q: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Cumulative ``int_{q[0]}^{q} f dq``, exact where f is a power law between points.

    With g = q f, ``int f dq = int g dln q`` and g exponential in ln q on a segment, the
    segment integral is the logarithmic mean ``(g_b - g_a) / ln(g_b / g_a) * dln q``
    (trapezoid where g is not positive on both ends).
    """
    g = q * f
    dl = np.diff(np.log(q))
    ga, gb = g[:-1], g[1:]
    pos = (ga > 0) & (gb > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.log(np.where(pos, gb, 1.0) / np.where(pos, ga, 1.0))
        logmean = np.where(np.abs(r) > 1e-12, (gb - ga) / np.where(r == 0, 1.0, r),
                           0.5 * (ga + gb))
    seg = np.where(pos, logmean, 0.5 * (ga + gb)) * dl
    return np.concatenate([[0.0], np.cumsum(seg)])


def hrms_from_psd(q: ArrayLike, C: ArrayLike) -> float:
    """rms height [m] from a 2D spectrum: ``h_rms^2 = 2 pi int q C dq`` over the given q range.

    The integral is exact for piecewise power laws (log-log linear between the points); no
    contribution below q[0] or above q[-1] is added.
    """
    q, C = _check_spectrum(q, C)
    return math.sqrt(2.0 * math.pi * _powerlaw_cumulative(q, q * C)[-1])


def rms_slope_from_psd(q: ArrayLike, C: ArrayLike) -> float:
    """rms slope xi [-] from a 2D spectrum: ``xi^2 = 2 pi int q^3 C dq`` over the given range."""
    return float(cumulative_rms_slope(q, C)[-1])


def cumulative_rms_slope(q: ArrayLike, C: ArrayLike) -> np.ndarray:
    """``xi(q) = (2 pi int_{q[0]}^{q} q'^3 C dq')^{1/2}`` [-] at every q (docs/review-notes.md,
    Trap 6: the review's q1 is where xi reaches about 1)."""
    q, C = _check_spectrum(q, C)
    return np.sqrt(2.0 * math.pi * _powerlaw_cumulative(q, q**3 * C))


def hrms_from_psd_1d(q: ArrayLike, C1D: ArrayLike) -> float:
    """rms height [m] from a line-scan spectrum: ``h_rms^2 = 2 int C1D dq`` (given range)."""
    q, C1 = _check_spectrum(q, C1D, cname="C1D")
    return math.sqrt(2.0 * _powerlaw_cumulative(q, C1)[-1])


def write_psd_table(path: str | Path, q: ArrayLike, C: ArrayLike, provenance: str) -> Path:
    """Write C(q) as the CSV table a surface TOML reads (``model = "tabulated"``).

    Columns ``q [1/m], C [m^4]`` (read by :func:`tirefric.config.read_csv_table` and
    :class:`lookup.roughness.TabulatedPSD`), preceded by ``#`` lines with ``provenance``
    (where the topography came from, instrument, processing: detrend, window, bins).

    Parameters
    ----------
    path
        Output CSV file.
    q, C
        Wavenumbers [1/m] (strictly increasing) and the 2D spectrum [m^4], all > 0.
    provenance
        Free text, required (reference data carry their provenance).

    Returns
    -------
    pathlib.Path
        The written file.
    """
    q, C = _check_spectrum(q, C)
    if np.any(C <= 0):
        i = int(np.flatnonzero(C <= 0)[0])
        raise InputError("C(q) must be > 0 for a tabulated spectrum (drop or re-bin the "
                         "noisy points)", field="C", value=float(C[i]))
    if not provenance.strip():
        raise InputError("a provenance note is required", field="provenance")
    lines = [f"# {line}".rstrip() for line in provenance.strip().splitlines()]
    lines.append("q [1/m], C [m^4]")
    lines += [f"{a!r}, {b!r}" for a, b in zip(q.tolist(), C.tolist(), strict=True)]
    path = Path(path)
    path.write_text("\n".join(lines) + "\n")
    return path


# ------------------------------------------------------------------------------------------
# Reading measured data
# ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class HeightMap:
    """A measured or synthetic height map.

    Attributes
    ----------
    heights : numpy.ndarray
        Heights [m], shape (ny, nx), rows along y.
    dx, dy : float
        Pixel sizes along x (columns) and y (rows) [m].
    source : str
        Where the data came from (file path), for messages and provenance.
    """

    heights: np.ndarray
    dx: float
    dy: float
    source: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        object.__setattr__(self, "heights", _check_heights(self.heights, (2,), src))
        object.__setattr__(self, "dx", _check_step(self.dx, "dx", src))
        object.__setattr__(self, "dy", _check_step(self.dy, "dy", src))

    def psd(self, **kwargs) -> tuple[np.ndarray, np.ndarray]:
        """:func:`psd_from_height_map` of this map (keyword arguments passed on)."""
        return psd_from_height_map(self.heights, self.dx, self.dy, **kwargs)


@dataclass(frozen=True)
class LineScan:
    """A measured or synthetic line scan (profile).

    Attributes
    ----------
    heights : numpy.ndarray
        Heights [m], shape (N,).
    dx : float
        Point spacing [m].
    source : str
        Where the data came from (file path).
    """

    heights: np.ndarray
    dx: float
    source: str = ""

    def __post_init__(self) -> None:
        src = self.source or None
        object.__setattr__(self, "heights", _check_heights(self.heights, (1,), src))
        object.__setattr__(self, "dx", _check_step(self.dx, "dx", src))

    def psd(self, **kwargs) -> tuple[np.ndarray, np.ndarray]:
        """:func:`psd_from_line_scan` of this scan (keyword arguments passed on)."""
        return psd_from_line_scan(self.heights, self.dx, **kwargs)


_KEY_LINE = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*?)$")
_SPLIT = re.compile(r"[,\s]+")
_TEXT_SUFFIXES = {".csv", ".txt", ".dat"}


def _read_text(path: Path, allowed: set[str]) -> tuple[dict[str, str], list[list[str]]]:
    """Header keys and data rows (as tokens, with their line numbers) of a text file."""
    try:
        lines = path.read_text().splitlines()
    except FileNotFoundError as exc:
        raise InputError("file not found", source=path) from exc
    except UnicodeDecodeError as exc:
        raise InputError("not a text file", source=path) from exc
    keys: dict[str, str] = {}
    rows: list[list[str]] = []
    for no, line in enumerate(lines, start=1):
        text = line.strip()
        if not text:
            continue
        if text.startswith("#"):
            continue
        m = _KEY_LINE.match(text)
        if m:
            key, value = m.group(1), m.group(2)
            if rows:
                raise InputError(f"line {no}: header line after the data", source=path,
                                 field=key, value=value)
            if key not in allowed:
                raise InputError(f"line {no}: unknown header key (known: "
                                 f"{', '.join(sorted(allowed))})", source=path, field=key,
                                 value=value)
            if key in keys:
                raise InputError(f"line {no}: key given twice", source=path, field=key,
                                 value=value)
            keys[key] = value
            continue
        rows.append([str(no)] + [t for t in _SPLIT.split(text) if t])
    return keys, rows


def _length_key(path: Path, keys: dict[str, str], key: str) -> float:
    text = keys[key]
    value: float | str
    try:
        value = float(text)
    except ValueError:
        value = text
    si = parse_quantity(value, "length",
                        lambda msg: InputError(msg, source=path, field=key, value=text))
    return _check_step(si, key, path)


def _height_unit(path: Path, keys: dict[str, str]) -> float:
    if "height_unit" not in keys:
        raise InputError("required header key missing ('height_unit = um', any length unit)",
                         source=path, field="height_unit")
    unit = keys["height_unit"]
    if unit not in UNITS["length"]:
        raise InputError(f"unknown length unit (known: {', '.join(UNITS['length'])})",
                         source=path, field="height_unit", value=unit)
    return UNITS["length"][unit][0]


def _to_floats(path: Path, rows: list[list[str]]) -> list[list[float]]:
    out = []
    for row in rows:
        vals = []
        for tok in row[1:]:
            try:
                vals.append(float(tok))
            except ValueError:
                raise InputError(f"line {row[0]}: not a number", source=path,
                                 field="heights", value=tok) from None
        out.append(vals)
    return out


def _require_dx(path: Path, keys: dict[str, str]) -> float:
    if "dx" not in keys:
        raise InputError("required header key missing ('dx = 1 um': pixel size)",
                         source=path, field="dx")
    return _length_key(path, keys, "dx")


def _load_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except FileNotFoundError as exc:
        raise InputError("file not found", source=path) from exc
    except (OSError, ValueError) as exc:
        raise InputError(f"not a readable .npz file: {exc}", source=path) from exc


def _load_npy(path: Path) -> np.ndarray:
    try:
        return np.load(path, allow_pickle=False)
    except FileNotFoundError as exc:
        raise InputError("file not found", source=path) from exc
    except (OSError, ValueError) as exc:
        raise InputError(f"not a readable .npy file: {exc}", source=path) from exc


def _npz_step(path: Path, data: dict[str, np.ndarray], key: str) -> float:
    arr = data[key]
    if arr.size != 1:
        raise InputError("must be a single number [m]", source=path, field=key, value=arr.shape)
    return _check_step(arr.reshape(()).item(), key, path)


def _no_dx_argument(path: Path, dx: float | None, dy: float | None) -> None:
    if dx is not None or dy is not None:
        raise InputError("the file defines the pixel size; do not pass dx/dy", source=path,
                         field="dx", value=(dx, dy))


def read_height_map(path: str | Path, dx: float | None = None,
                    dy: float | None = None) -> HeightMap:
    """Read a height map (formats in the module docstring).

    Parameters
    ----------
    path
        ``.csv``/``.txt``/``.dat`` with a ``dx = ...`` header line, ``.npz`` or ``.npy``.
    dx, dy
        Pixel sizes [m], only for ``.npy`` (which stores none); ``dy`` defaults to ``dx``.

    Returns
    -------
    HeightMap
        Heights in metres.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in _TEXT_SUFFIXES:
        _no_dx_argument(path, dx, dy)
        keys, rows = _read_text(path, {"dx", "dy", "height_unit"})
        step_x = _require_dx(path, keys)
        step_y = _length_key(path, keys, "dy") if "dy" in keys else step_x
        scale = _height_unit(path, keys)
        vals = _to_floats(path, rows)
        if not vals:
            raise InputError("no height values", source=path, field="heights")
        for row, v in zip(rows, vals, strict=True):
            if len(v) != len(vals[0]):
                raise InputError(f"line {row[0]}: {len(v)} values, the first data row has "
                                 f"{len(vals[0])} (rows must have equal length)", source=path,
                                 field="heights")
        return HeightMap(np.array(vals) * scale, step_x, step_y, str(path))
    if suffix == ".npz":
        _no_dx_argument(path, dx, dy)
        data = _load_npz(path)
        for key in ("heights", "dx"):
            if key not in data:
                raise InputError(f"missing array (has: {sorted(data)})", source=path, field=key)
        step_x = _npz_step(path, data, "dx")
        step_y = _npz_step(path, data, "dy") if "dy" in data else step_x
        return HeightMap(data["heights"], step_x, step_y, str(path))
    if suffix == ".npy":
        if dx is None:
            raise InputError("a .npy file holds no pixel size: pass dx [m]", source=path,
                             field="dx")
        step_x = _check_step(dx, "dx", path)
        step_y = step_x if dy is None else _check_step(dy, "dy", path)
        return HeightMap(_load_npy(path), step_x, step_y, str(path))
    raise InputError("unknown file type (use .csv, .txt, .dat, .npz or .npy)", source=path,
                     value=suffix)


def read_line_scan(path: str | Path, dx: float | None = None) -> LineScan:
    """Read a line scan (formats in the module docstring).

    Parameters
    ----------
    path
        ``.csv``/``.txt``/``.dat`` (``dx``/``height_unit`` header lines and one height per line,
        or an ``x [unit], z [unit]`` table), ``.npz`` or ``.npy``.
    dx
        Point spacing [m], only for ``.npy``.

    Returns
    -------
    LineScan
        Heights in metres.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in _TEXT_SUFFIXES:
        _no_dx_argument(path, dx, None)
        keys, rows = _read_text(path, {"dx", "height_unit"})
        if rows and "[" in "".join(rows[0][1:]):
            if keys:
                raise InputError("an 'x [unit], z [unit]' table takes its units and spacing "
                                 "from the columns; remove the 'key = value' lines",
                                 source=path, field=next(iter(keys)))
            table = read_csv_table(path, {"x": "length", "z": "length"})
            x, z = table["x"], table["z"]
            if x.size < MIN_POINTS:
                raise InputError(f"too few points for a spectrum (need >= {MIN_POINTS})",
                                 source=path, field="z", value=x.size)
            steps = np.diff(x)
            step = float(np.mean(steps))
            if not step > 0 or np.max(np.abs(steps - step)) > 1e-3 * abs(step):
                i = int(np.argmax(np.abs(steps - step)))
                raise InputError(f"x must be equally spaced and increasing (step {i + 1} is "
                                 f"{steps[i]!r} m, mean {step!r} m); resample first",
                                 source=path, field="x", value=float(x[i + 1]))
            return LineScan(z, step, str(path))
        step_x = _require_dx(path, keys)
        scale = _height_unit(path, keys)
        vals = _to_floats(path, rows)
        if len(vals) > 1 and any(len(v) != 1 for v in vals):
            bad = next(r for r, v in zip(rows, vals, strict=True) if len(v) != 1)
            raise InputError(f"line {bad[0]}: expected one height per line (or an "
                             "'x [unit], z [unit]' table)", source=path, field="heights")
        flat = [x for v in vals for x in v]
        if not flat:
            raise InputError("no height values", source=path, field="heights")
        return LineScan(np.array(flat) * scale, step_x, str(path))
    if suffix == ".npz":
        _no_dx_argument(path, dx, None)
        data = _load_npz(path)
        for key in ("heights", "dx"):
            if key not in data:
                raise InputError(f"missing array (has: {sorted(data)})", source=path, field=key)
        return LineScan(data["heights"], _npz_step(path, data, "dx"), str(path))
    if suffix == ".npy":
        if dx is None:
            raise InputError("a .npy file holds no point spacing: pass dx [m]", source=path,
                             field="dx")
        return LineScan(_load_npy(path), _check_step(dx, "dx", path), str(path))
    raise InputError("unknown file type (use .csv, .txt, .dat, .npz or .npy)", source=path,
                     value=suffix)
