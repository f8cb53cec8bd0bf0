r"""Rolling friction from the master curve: review sec. 6 (eqs. 29-33) and sec. 7 (wedge).

A normal stress field that moves at speed v over a viscoelastic half space,
:math:`\sigma_z(\mathbf x, t) = \sigma_z(\mathbf x - \mathbf v t)`, dissipates energy in the bulk
and so opposes the motion with the force of review eq. (29),

.. math::

    F_f = \frac{2 (2\pi)^2}{v} \int d^2q\, \frac{\omega}{q}\,
          \mathrm{Im}\frac{1}{E_{\rm eff}(\omega)}\, |\sigma_z(\mathbf q)|^2,
    \qquad \omega = \mathbf q\cdot\mathbf v,

with :math:`\sigma_z(\mathbf q) = (2\pi)^{-2}\int d^2x\, \sigma_z(\mathbf x)
e^{-i\mathbf q\cdot\mathbf x}` and :math:`E_{\rm eff} = E/(1-\nu^2)`. With the time dependence
:math:`e^{-i\omega t}` of review eqs. (1)-(4), :math:`\mathrm{Im}(1/E) = E_I/|E|^2 > 0` for
:math:`\omega > 0` (docs/review-notes.md, Trap 1), so no sign has to be flipped here.

For a stress uniform along y on a strip of length L_y (a cylinder, a wedge, a tire footprint)
the q_y integral collapses and eq. (29) becomes, with
:math:`P(q) = \int dx\, p(x) e^{-iqx}` and the load per unit length :math:`f_N = P(0)`,

.. math::

    \mu = \frac{F_f}{f_N L_y} = \frac{2}{\pi f_N} \int_0^\infty dq\,
          \mathrm{Im}\frac{1}{E_{\rm eff}(q v)}\, |P(q)|^2 .

This is the form behind eq. (30) (Hertz line contact, :math:`P = 2 f_N J_1(qa)/(qa)`) and the
wedge of sec. 7 (:math:`p = p_0\,\mathrm{arccosh}(a/|x|)`,
:math:`P = f_N\, k^{-1}\int_0^k J_0(s)\,ds`, k = qa). Eq. (32) is the same for the Hertz
sphere (:math:`2\pi`-periodic angular integral over :math:`\omega = q v\cos\phi`).

The modulus is evaluated as the sliding engine evaluates it (:mod:`lookup.friction`): the
compound's master curve tabulated with the strain-softening factors of review eq. (6)
(:meth:`lookup.compound.Compound.modulus_table`, or the same table at another strain), at the
reduced frequency :math:`\omega a_T(T)` (:meth:`lookup.compound.Compound.log10_aT`), divided by
:math:`1-\nu^2`. See :class:`EffectiveModulus`.

Contact size. Eqs. (31), (33) and the half-width of sec. 7 contain a modulus; the review takes
it to be :math:`|E_{\rm eff}(\omega)|` at the frequency :math:`\omega = \mathbf q\cdot\mathbf v`
of the Fourier component being integrated. That is what is done here by default: the contact
size is a function a(q) (or r_c(q, phi)) inside the integrals; no further iteration is involved
and none is made. Passing ``E_contact`` instead fixes the modulus of the contact size (e.g. a
measured static modulus); this also gives the fixed-size Hertz fields the tests compare with
the general eq. (29).

Assumptions (review sec. 6): no adhesion and no interfacial shear (lubricated sliding or pure
rolling), the Hertz (or wedge) pressure field of the elastic problem, linear response apart
from the secant strain softening of eq. (6) at one strain, no frictional heating, v much below
the sound speed. docs/rolling.md compares eq. (30) with the exact steady rolling solution.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy.special import itj0y0, j1, y1

from tirefric.errors import InputError

from .compound import Compound
from .modulus import ModulusTable
from .softening import factors_at

# -- numerical settings of the q integrals (resolution checked in tests/test_rolling.py) -------
#: q-nodes per decade where the contact shape oscillates (k = q a > 1) and below it.
_FINE_PER_DECADE = 400
_COARSE_PER_DECADE = 100
#: Dimensionless wavenumbers k = q a covered: [K_LO, K_HI].
_K_LO, _K_HI = 1e-8, 1e6
#: Above k ~ 15-45 the oscillating shape factor is replaced, with a smooth cos^2 taper, by its
#: non-oscillating mean (exact amplitude-phase forms below); the oscillation integrates to zero
#: against the slowly varying Im(1/E) and cannot be followed on a log grid up to k = 1e6.
_TAPER = (15.0, 45.0)


def _check_positive(value: float, name: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError("not a number", field=name, value=value) from None
    if not (np.isfinite(x) and x > 0):
        raise InputError("must be a finite number > 0", field=name, value=value)
    return x


def _check_speeds(v: float | Sequence[float] | np.ndarray) -> np.ndarray:
    va = np.atleast_1d(np.asarray(v, dtype=float))
    if va.ndim != 1 or va.size == 0:
        raise InputError("rolling speeds must be a number or a 1D list", field="v", value=v)
    bad = ~(np.isfinite(va) & (va > 0))
    if bad.any():
        raise InputError("rolling speeds must be finite and > 0 m/s", field="v",
                         value=float(va[np.flatnonzero(bad)[0]]))
    return va


@dataclass(frozen=True)
class EffectiveModulus:
    r"""E_eff(omega) = E(omega a_T(T)) / (1 - nu^2) of a compound, with strain softening.

    The same evaluation as the sliding engine (:class:`lookup.friction.PerssonFriction`):
    the master curve at T_ref tabulated with the softening factors of review eq. (6)
    (:class:`lookup.modulus.ModulusTable`), read at log10(omega) + log10 a_T(T).

    Attributes
    ----------
    compound : Compound
    T : float
        Temperature [K].
    strain : float or None
        Strain [1] at which the softening factors eta_R, eta_I are applied; None = the
        compound's own ``strain`` (as the sliding engine).
    points_per_decade : int
        Master-curve samples per decade (the engine's default 40).
    """

    compound: Compound
    T: float
    strain: float | None = None
    points_per_decade: int = 40
    table: ModulusTable = field(init=False, repr=False)
    log10_aT: float = field(init=False)
    inv_1mnu2: float = field(init=False)

    def __post_init__(self) -> None:
        _check_positive(self.T, "T")
        if self.strain is None:
            table = self.compound.modulus_table(self.points_per_decade, T=self.T)
        else:  # softening factors at this strain (and at T, for strain sweeps at several T)
            eps = _check_positive(self.strain, "strain")
            eta_R, eta_I = (float(x) for x in factors_at(self.compound.softening, eps, self.T))
            table = ModulusTable.from_modulus(self.compound.modulus, eta_R, eta_I,
                                              points_per_decade=self.points_per_decade)
        object.__setattr__(self, "table", table)
        object.__setattr__(self, "log10_aT", float(self.compound.log10_aT(np.asarray(self.T))))
        object.__setattr__(self, "inv_1mnu2", 1.0 / (1.0 - self.compound.nu**2))

    def storage_loss(self, omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(Re E_eff, E_I,eff) [Pa] at omega [rad/s]; E_I = -Im E, odd in omega (Trap 1)."""
        w = np.asarray(omega, dtype=float)
        aw = np.abs(w)
        with np.errstate(divide="ignore"):
            lw = np.where(aw > 0, np.log10(np.where(aw > 0, aw, 1.0)), -np.inf)
        if self.table.outside == "error" and self.table.outside_band(
                (lw + self.log10_aT)[aw > 0]).any():
            lo, hi = (10.0 ** b for b in self.table.log10_band)
            raise InputError(f"frequency outside the master curve's data ({lo:.3g}..{hi:.3g} "
                             "rad/s) and policy is 'error'", source=self.table.source or None,
                             field="modulus.outside", value="error")
        ER, EI = self.table(lw + self.log10_aT)
        EI = np.where(aw > 0, np.sign(w) * EI, 0.0)
        return ER * self.inv_1mnu2, EI * self.inv_1mnu2

    def im_compliance(self, omega: np.ndarray) -> np.ndarray:
        """Im(1/E_eff(omega)) = E_I / |E|^2 [1/Pa]: > 0 for omega > 0 with review eq. (4)."""
        ER, EI = self.storage_loss(omega)
        return EI / (ER * ER + EI * EI)

    def magnitude(self, omega: np.ndarray) -> np.ndarray:
        """|E_eff(omega)| [Pa]."""
        ER, EI = self.storage_loss(omega)
        return np.hypot(ER, EI)

    def magnitude_range(self) -> tuple[float, float]:
        """(min, max) of |E_eff| over the tabulated band [Pa] (bounds of the contact size)."""
        ER = 10.0**self.table.log10_ER
        EI = 10.0**self.table.log10_EI
        m = np.hypot(ER, EI) * self.inv_1mnu2
        return float(m.min()), float(m.max())


# -- contact sizes ----------------------------------------------------------------------------
def cylinder_half_width(f_N: float, R: float, E_eff: np.ndarray | float) -> np.ndarray:
    """Hertz half-width of a cylinder-flat line contact, review eq. (31) [m].

    a = (4 f_N R / (pi E_eff))^(1/2); f_N [N/m] load per unit length, R [m], E_eff [Pa].
    """
    return np.sqrt(4.0 * f_N * R / (np.pi * np.asarray(E_eff, float)))


def sphere_contact_radius(F_N: float, R: float, E_eff: np.ndarray | float) -> np.ndarray:
    """Hertz contact radius of a sphere on a flat, review eq. (33) [m].

    r_c = (3 F_N R / (4 E_eff))^(1/3); F_N [N], R [m], E_eff [Pa].
    """
    return np.cbrt(3.0 * F_N * R / (4.0 * np.asarray(E_eff, float)))


def wedge_half_width(f_N: float, alpha: float, E_eff: np.ndarray | float) -> np.ndarray:
    """Half-width of a rigid wedge (half-opening angle alpha [rad]) on a flat, review sec. 7.

    a = f_N / (E* cot alpha) [m], f_N [N/m] (Johnson, *Contact Mechanics*, sec. 5.8).
    """
    return f_N / (np.asarray(E_eff, float) / np.tan(alpha))


def wedge_strain(alpha: float) -> float:
    """Typical strain under a wedge, epsilon ~ 1/(2 tan alpha) (review sec. 7) [1]."""
    return 1.0 / (2.0 * np.tan(alpha))


def _check_angle(alpha: float) -> float:
    try:
        a = float(alpha)
    except (TypeError, ValueError):
        raise InputError("not a number", field="alpha", value=alpha) from None
    if not (np.isfinite(a) and 0.0 < a < 0.5 * np.pi):
        raise InputError("half-opening angle must lie strictly between 0 and 90 deg "
                         "(0 and pi/2 rad)", field="alpha", value=alpha)
    return a


# -- shape factors |P(q)|^2 / f_N^2 of the 1D fields and their non-oscillating means ----------
def _shape_cylinder(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(J1(k)/k)^2 [Hertz line contact, P = 2 f_N J1(k)/k] and its mean (J1^2 + Y1^2)/(2 k^2)."""
    ks = np.maximum(k, 1e-300)
    exact = np.where(k < 1e-4, 0.25 * (1.0 - k * k / 4.0), (j1(ks) / ks) ** 2)
    with np.errstate(over="ignore", invalid="ignore"):
        mean = (j1(ks) ** 2 + y1(ks) ** 2) / (2.0 * ks * ks)
    return 4.0 * exact, 4.0 * np.where(k > 1.0, mean, 0.0)


def _shape_wedge(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k^-1 int_0^k J0)^2 [wedge, P = f_N k^-1 int_0^k J0] and its mean (1 + 1/(pi k))/k^2."""
    ks = np.maximum(k, 1e-300)
    ij0 = itj0y0(ks)[0]
    exact = np.where(k < 1e-4, 1.0 - k * k / 6.0, (ij0 / ks) ** 2)
    mean = (1.0 + 1.0 / (np.pi * ks)) / (ks * ks)
    return exact, np.where(k > 1.0, mean, 0.0)


def _shape_sphere(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((sin k - k cos k)/k^3)^2 [Hertz sphere] and its mean (1 + k^2)/(2 k^6)."""
    ks = np.maximum(k, 1e-300)
    exact = np.where(k < 1e-3, (1.0 / 3.0 - k * k / 30.0) ** 2,
                     ((np.sin(ks) - ks * np.cos(ks)) / ks**3) ** 2)
    mean = (1.0 + ks * ks) / (2.0 * ks**6)
    return exact, np.where(k > 1.0, mean, 0.0)


def _taper(k: np.ndarray) -> np.ndarray:
    """1 below _TAPER[0], 0 above _TAPER[1], cos^2 in log k between."""
    lo, hi = np.log(_TAPER[0]), np.log(_TAPER[1])
    s = np.clip((np.log(np.maximum(k, 1e-300)) - lo) / (hi - lo), 0.0, 1.0)
    return np.cos(0.5 * np.pi * s) ** 2


def _blended(shape, k: np.ndarray) -> np.ndarray:
    exact, mean = shape(k)
    w = _taper(k)
    return mean + w * (exact - mean)


def _q_grid(size_max: float, size_min: float) -> np.ndarray:
    """ln-q nodes: K_LO/size_max .. K_HI/size_min, fine where q size_max > 1."""
    q_lo, q_mid, q_hi = _K_LO / size_max, 1.0 / size_max, _K_HI / size_min
    n1 = max(int(np.ceil(np.log10(q_mid / q_lo) * _COARSE_PER_DECADE)), 2)
    n2 = max(int(np.ceil(np.log10(q_hi / q_mid) * _FINE_PER_DECADE)), 2)
    return np.concatenate([np.geomspace(q_lo, q_mid, n1, endpoint=False),
                           np.geomspace(q_mid, q_hi, n2)])


def _trapz_lnq(y: np.ndarray, q: np.ndarray) -> np.ndarray:
    """int dq y = int dln q (q y), trapezoidal in ln q, over the last axis."""
    f = y * q
    d = np.diff(np.log(q))
    return np.sum(0.5 * (f[..., 1:] + f[..., :-1]) * d, axis=-1)


def _contact_moduli(modulus: EffectiveModulus, E_contact: float | None
                    ) -> tuple[float, float]:
    if E_contact is not None:
        E = _check_positive(E_contact, "E_contact")
        return E, E
    return modulus.magnitude_range()


def _mu_line(shape, size_of_E, v: np.ndarray, modulus: EffectiveModulus,
             E_contact: float | None, f_N: float) -> np.ndarray:
    """(2 / (pi f_N)) int dq Im(1/E(qv)) |P(q)|^2 with |P|^2 = f_N^2 shape(q a(q))."""
    E_lo, E_hi = _contact_moduli(modulus, E_contact)
    q = _q_grid(float(size_of_E(E_lo)), float(size_of_E(E_hi)))
    w = v[:, None] * q[None, :]
    a = size_of_E(E_contact if E_contact is not None else modulus.magnitude(w))
    y = modulus.im_compliance(w) * _blended(shape, q[None, :] * a)
    return 2.0 * f_N / np.pi * _trapz_lnq(y, q)


def mu_cylinder(f_N: float, R: float, v: float | Sequence[float] | np.ndarray,
                modulus: EffectiveModulus, E_contact: float | None = None) -> np.ndarray:
    r"""Rolling friction coefficient of a hard cylinder on a viscoelastic solid, review eq. (30).

    .. math:: \mu = \frac{8 f_N}{\pi}\int_0^\infty dq\,\mathrm{Im}\frac{1}{E_{\rm eff}(qv)}
              \frac{J_1^2(qa)}{(qa)^2}

    with the Hertz half-width a of eq. (31) evaluated at :math:`|E_{\rm eff}(qv)|` (review
    after eq. 31), or at ``E_contact`` when given.

    Parameters
    ----------
    f_N : float
        Normal load per unit cylinder length [N/m], > 0.
    R : float
        Cylinder radius [m], > 0.
    v : float or array
        Rolling speed(s) [m/s], > 0.
    modulus : EffectiveModulus
        The rubber's E_eff(omega) at the temperature of interest.
    E_contact : float, optional
        Fixed modulus [Pa] for the contact size instead of |E_eff(q v)|.

    Returns
    -------
    numpy.ndarray
        mu [1], one per speed.
    """
    f_N = _check_positive(f_N, "f_N")
    R = _check_positive(R, "R")
    va = _check_speeds(v)
    return _mu_line(_shape_cylinder, lambda E: cylinder_half_width(f_N, R, E), va, modulus,
                    E_contact, f_N)


def mu_wedge(f_N: float, alpha: float, v: float | Sequence[float] | np.ndarray,
             modulus: EffectiveModulus, E_contact: float | None = None) -> np.ndarray:
    r"""Viscoelastic friction of a rigid wedge sliding (lubricated) on rubber, review sec. 7.

    Pressure :math:`p(x) = p_0\,\mathrm{arccosh}(a/|x|)`, :math:`p_0 = f_N/(\pi a)`,
    half-width :math:`a = f_N/(E^*\cot\alpha)` with :math:`E^* \to |E_{\rm eff}(q v)|` (sec. 7),
    inserted in eq. (29); its transform is :math:`P(q) = f_N k^{-1}\int_0^k J_0(s)\,ds`,
    k = q a (integrating by parts with :math:`\int_0^1 \cos(kt)(1-t^2)^{-1/2} dt =
    (\pi/2) J_0(k)`). The strain for the softening, of order :math:`1/(2\tan\alpha)`
    (:func:`wedge_strain`), is the caller's choice when building ``modulus``.

    Parameters
    ----------
    f_N : float
        Normal load per unit length [N/m], > 0.
    alpha : float
        Half-opening angle [rad], 0 < alpha < pi/2.
    v : float or array
        Sliding speed(s) [m/s], > 0.
    modulus : EffectiveModulus
    E_contact : float, optional
        Fixed modulus [Pa] for the half-width instead of |E_eff(q v)|.

    Returns
    -------
    numpy.ndarray
        mu [1], one per speed.
    """
    f_N = _check_positive(f_N, "f_N")
    alpha = _check_angle(alpha)
    va = _check_speeds(v)
    return _mu_line(_shape_wedge, lambda E: wedge_half_width(f_N, alpha, E), va, modulus,
                    E_contact, f_N)


def mu_sphere(F_N: float, R: float, v: float | Sequence[float] | np.ndarray,
              modulus: EffectiveModulus, E_contact: float | None = None,
              n_phi: int = 24) -> np.ndarray:
    r"""Rolling friction coefficient of a hard sphere on a viscoelastic solid, review eq. (32).

    .. math:: \mu = \frac{9 F_N}{2\pi^2}\int_0^\infty dq\, q\int_0^{2\pi} d\phi\,\cos\phi\,
              \mathrm{Im}\frac{1}{E_{\rm eff}(qv\cos\phi)}
              \frac{[\sin(qr_c) - qr_c\cos(qr_c)]^2}{(qr_c)^6}

    with r_c of eq. (33) at :math:`|E_{\rm eff}(qv\cos\phi)|` (or ``E_contact``). The
    integrand is even under phi -> pi - phi and phi -> -phi, so the angle runs over
    [0, pi/2] with ``n_phi`` Gauss-Legendre nodes, times 4 (as Trap 3).

    Parameters
    ----------
    F_N : float
        Normal load [N], > 0.
    R : float
        Sphere radius [m], > 0.
    v : float or array
        Rolling speed(s) [m/s], > 0.
    modulus : EffectiveModulus
    E_contact : float, optional
        Fixed modulus [Pa] for the contact radius instead of |E_eff(q v cos phi)|.
    n_phi : int
        Gauss-Legendre nodes on [0, pi/2].

    Returns
    -------
    numpy.ndarray
        mu [1], one per speed.
    """
    F_N = _check_positive(F_N, "F_N")
    R = _check_positive(R, "R")
    va = _check_speeds(v)
    E_lo, E_hi = _contact_moduli(modulus, E_contact)
    q = _q_grid(float(sphere_contact_radius(F_N, R, E_lo)),
                float(sphere_contact_radius(F_N, R, E_hi)))
    x, wx = np.polynomial.legendre.leggauss(n_phi)
    phi = 0.25 * np.pi * (x + 1.0)
    w_phi = 0.25 * np.pi * wx
    cphi = np.cos(phi)
    out = np.empty(va.size)
    for i, vi in enumerate(va):  # (nq, nphi) per speed keeps memory small
        w = vi * q[:, None] * cphi[None, :]
        E = E_contact if E_contact is not None else modulus.magnitude(w)
        rc = sphere_contact_radius(F_N, R, E)
        g = modulus.im_compliance(w) * _blended(_shape_sphere, q[:, None] * rc)
        ang = 4.0 * (g * (w_phi * cphi)[None, :]).sum(axis=1)
        out[i] = 9.0 * F_N / (2.0 * np.pi**2) * _trapz_lnq(q * ang, q)
    return out


# -- eq. (29) for given fields ----------------------------------------------------------------
def mu_stress_field(sigma: np.ndarray, dx: float, dy: float, v: float,
                    modulus: EffectiveModulus) -> float:
    r"""Review eq. (29) for a normal stress field sampled on a grid, moving along +x.

    ``sigma[iy, ix]`` [Pa] is the interfacial pressure on a periodic grid of spacing dx, dy
    [m]; the field must be surrounded by enough zero padding that its periodic images do not
    interact (the transform of the sampled field stands for the continuous one). With the
    discrete Fourier transform S of sigma, eq. (29) reads

    .. math:: F_f = \frac{2\,dx\,dy}{v N_x N_y}\sum_{\mathbf q}
              \frac{q_x v}{q}\,\mathrm{Im}\frac{1}{E_{\rm eff}(q_x v)}\,|S(\mathbf q)|^2,

    and mu = F_f / F_N with F_N = sum(sigma) dx dy.

    Returns
    -------
    float
        Rolling (or lubricated sliding) friction coefficient [1].
    """
    s = np.asarray(sigma, dtype=float)
    if s.ndim != 2 or not np.isfinite(s).all() or (s < 0).any():
        raise InputError("stress field must be a finite, non-negative 2D array [Pa]",
                         field="sigma")
    dx, dy = _check_positive(dx, "dx"), _check_positive(dy, "dy")
    v = float(_check_speeds(v)[0])
    F_N = s.sum() * dx * dy
    if not F_N > 0:
        raise InputError("stress field carries no load", field="sigma")
    ny, nx = s.shape
    S2 = np.abs(np.fft.rfft2(s)) ** 2
    qx = 2.0 * np.pi * np.fft.rfftfreq(nx, dx)
    qy = 2.0 * np.pi * np.fft.fftfreq(ny, dy)
    QX, QY = np.meshgrid(qx, qy)
    Q = np.hypot(QX, QY)
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.where(Q > 0, QX * v / Q * modulus.im_compliance(QX * v), 0.0) * S2
    # rfft keeps q_x >= 0; the q_x < 0 half is the mirror (the summand is even in q_x)
    mult = np.full(qx.size, 2.0)
    mult[0] = 1.0
    if nx % 2 == 0:
        mult[-1] = 1.0
    F = 2.0 * dx * dy / (v * nx * ny) * float((g * mult[None, :]).sum())
    return F / F_N


def _profile_transform(x: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Exact P(q) = int p(x) e^{-iqx} dx of the piecewise-linear interpolant of (x, p),
    zero outside [x_0, x_-1]; segment by segment with Taylor forms for small q L."""
    L = np.diff(x)
    s = np.diff(p) / L
    th = q[:, None] * L[None, :]
    small = np.abs(th) < 1e-2
    ths = np.where(small, 1.0, th)
    e = np.exp(-1j * ths)
    phi0 = np.where(small, 1 - 0.5j * th - th**2 / 6 + 1j * th**3 / 24, (1 - e) / (1j * ths))
    phi1 = np.where(small, 0.5 - 1j * th / 3 - th**2 / 8 + 1j * th**3 / 30,
                    1j * e / ths - (1 - e) / ths**2)
    seg = np.exp(-1j * q[:, None] * x[None, :-1]) * (p[None, :-1] * L * phi0
                                                     + s * L * L * phi1)
    return seg.sum(axis=1)


def _check_profile(x: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    x = np.asarray(x, dtype=float)
    p = np.asarray(p, dtype=float)
    if x.ndim != 1 or x.shape != p.shape or x.size < 2:
        raise InputError("pressure profile needs equally long 1D arrays x [m], p [Pa] with "
                         "at least two points", field="p")
    if not (np.isfinite(x).all() and np.isfinite(p).all()):
        raise InputError("pressure profile must be finite (NaN or inf found)", field="p")
    if not (np.diff(x) > 0).all():
        raise InputError("x must be strictly increasing", field="x")
    if (p < 0).any():
        raise InputError("pressure must be >= 0", field="p", value=float(p.min()))
    f_N = float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(x)))
    if not f_N > 0:
        raise InputError("pressure profile carries no load", field="p")
    return x, p, f_N


def _profile_integral(x: np.ndarray, p: np.ndarray, f_N: float, v: np.ndarray,
                      weight) -> np.ndarray:
    """(1/(pi f_N)) int_0^inf dq q Im C(q, qv) |P(q)|^2 for a strip (see mu_profile)."""
    length = float(x[-1] - x[0])
    # log nodes up to q L = 4 (where Im(1/E) may vary over decades), then uniform in q at
    # 0.1/L (resolving the oscillation of |P|^2 of period ~ 2 pi / L) up to q L = 400
    q_lo, q_mid, q_hi = _K_LO / length, 4.0 / length, 400.0 / length
    ql = np.geomspace(q_lo, q_mid, int(np.log10(q_mid / q_lo) * _COARSE_PER_DECADE),
                      endpoint=False)
    qu = np.arange(q_mid, q_hi, 0.1 / length)
    q = np.concatenate([ql, qu])
    P2 = np.concatenate([np.abs(_profile_transform(x, p, q[i:i + 256])) ** 2
                         for i in range(0, q.size, 256)])  # bounded memory
    y = weight(q[None, :], v[:, None] * q[None, :]) * P2[None, :]
    dq = np.diff(q)
    body = np.sum(0.5 * (y[:, 1:] + y[:, :-1]) * dq, axis=1)
    # tail beyond q_hi: |P|^2 ~ <q^2 |P|^2> / q^2 (a jump at an edge; an upper bound where
    # the profile is continuous and |P|^2 decays faster),
    # the mean taken over the last 10 % of the uniform nodes
    tail_amp = float(np.mean((q**2 * P2)[-max(len(qu) // 10, 2):]))
    qt = np.geomspace(q_hi, q_hi * 1e6, 6 * _COARSE_PER_DECADE)
    yt = weight(qt[None, :], v[:, None] * qt[None, :]) * tail_amp / qt[None, :] ** 2
    tail = _trapz_lnq(yt, qt)
    return (body + tail) / (np.pi * f_N)


def mu_profile(x: np.ndarray, p: np.ndarray, v: float | Sequence[float] | np.ndarray,
               modulus: EffectiveModulus) -> np.ndarray:
    r"""Review eq. (29) for a line load: pressure p(x) uniform along y, moving along +x.

    .. math:: \mu = \frac{2}{\pi f_N}\int_0^\infty dq\,\mathrm{Im}\frac{1}{E_{\rm eff}(qv)}
              |P(q)|^2,\qquad f_N = \int p\,dx,

    with P the exact transform of the piecewise-linear interpolant of the samples (zero
    outside them).

    Parameters
    ----------
    x : array
        Positions along the rolling direction [m], strictly increasing.
    p : array
        Pressure [Pa] at x, >= 0.
    v : float or array
        Speed(s) [m/s], > 0.
    modulus : EffectiveModulus

    Returns
    -------
    numpy.ndarray
        mu [1], one per speed.
    """
    x, p, f_N = _check_profile(x, p)
    va = _check_speeds(v)
    return _profile_integral(x, p, f_N, va,
                             lambda q, w: 2.0 * modulus.im_compliance(w))


# -- a tread layer (for the tire model) -------------------------------------------------------
def bonded_layer_factor(qh: np.ndarray, nu: float) -> np.ndarray:
    r"""Layered-solid factor K(qh) of review sec. 5.1 for a layer bonded to a rigid base.

    The review's K (:func:`lookup.reference.layered_K`) with mu_0/mu_1 -> 0 has
    m = -1/kappa, n = -kappa, m n = 1 (kappa = 3 - 4 nu); multiplying numerator and
    denominator by kappa e^{2qh} gives the form used here, free of the cancellation of the
    general expression at small qh:

    .. math:: K = \frac{2\kappa\sinh 2x - 4x}{2\kappa\cosh 2x + 1 + \kappa^2 + 4x^2},
              \quad x = qh.

    K -> 1 for qh -> infinity; for an incompressible layer K ~ (2/3)(qh)^3 as qh -> 0 (the
    squeeze-film stiffness of a thin bonded layer).
    """
    x = np.asarray(qh, dtype=float)
    kap = 3.0 - 4.0 * nu
    y = 2.0 * x
    # sinh(y) - y without cancellation
    sh_m_y = np.where(y < 0.1, y**3 / 6 + y**5 / 120 + y**7 / 5040, np.sinh(np.minimum(y, 700))
                      - y)
    num = 2.0 * kap * sh_m_y + 4.0 * x * (kap - 1.0)
    with np.errstate(over="ignore"):
        ch = np.cosh(np.minimum(y, 700.0))
    K = num / (2.0 * kap * ch + 1.0 + kap * kap + 4.0 * x * x)
    return np.where(y > 600.0, 1.0, K)


TreadSupport = Literal["bonded", "winkler"]


def layer_weight(mod: EffectiveModulus, h: float, nu: float, support: str):
    """The weight ``w(q, omega)`` of eq. (29)'s integrand for a tread layer of thickness
    ``h`` (:func:`tread_rolling_resistance`): ``2 K(qh) Im(1/E_eff)`` on a rigid base
    (``"bonded"``), ``q h Im(1/E) / (1 - nu^2)`` for free columns (``"winkler"``)."""
    if support == "bonded":
        def weight(q, w):
            return 2.0 * bonded_layer_factor(q * h, nu) * mod.im_compliance(w)
    else:
        c = 1.0 - nu**2

        def weight(q, w):
            return q * h * mod.im_compliance(w) / c
    return weight


def tread_rolling_resistance(x: np.ndarray, p: np.ndarray, h: float, V: float,
                             compound: Compound, T: float, strain: float | None = None,
                             support: TreadSupport = "bonded") -> float:
    r"""Rolling-resistance coefficient of a tread layer rolling through a footprint.

    The footprint pressure p(x) (uniform across the width) passes through the tread at the
    rolling speed V; the energy the tread dissipates per unit rolling distance, divided by the
    load, is the coefficient. It is eq. (29) for a line load with the half-space compliance
    :math:`2/(q E_{\rm eff})` replaced by the surface compliance C(q, omega) of a layer of
    thickness h:

    .. math:: C_{rr} = \frac{1}{\pi f_N}\int_0^\infty dq\, q\, \mathrm{Im}\,C(q, qV)\,|P(q)|^2.

    ``support="bonded"`` (default): a continuous layer bonded to a rigid base (the steel belt,
    orders of magnitude stiffer than the tread), :math:`C = 2K(qh)/(q E_{\rm eff}(\omega))`
    with the layered-solid factor K of review sec. 5.1 in its rigid-base limit
    (:func:`bonded_layer_factor`); K is real for a rigid base, so Im C = 2K Im(1/E_eff)/q.
    This is exact linear elasticity for an unbroken layer and, for nu = 1/2, very stiff in
    compression (no bulging: K ~ (2/3)(qh)^3).

    ``support="winkler"``: independent columns (a tread cut into blocks by grooves, free to
    bulge), each compressed uniaxially, :math:`C = h/E(\omega)` with the Young's modulus
    E = (1 - nu^2) E_eff (Winkler foundation; Johnson, *Contact Mechanics*, sec. 4.3 on the
    elastic foundation, for thin layers). It ignores the lateral constraint of the block
    shape factor and so gives an upper bound of the compliance of a free-bulging block.

    Both ignore the carcass, the sidewall and the tread's shear, and use the modulus at one
    strain (review eq. 6) and one temperature: no heating within the revolution.

    Parameters
    ----------
    x, p : array
        Footprint pressure profile along the rolling direction: positions [m] (increasing),
        pressure [Pa] (>= 0, piecewise linear between the samples, zero outside).
    h : float
        Tread thickness [m], > 0.
    V : float
        Rolling speed [m/s], > 0.
    compound : Compound
    T : float
        Tread temperature [K].
    strain : float, optional
        Strain for the softening factors; None = the compound's own.
    support : {"bonded", "winkler"}

    Returns
    -------
    float
        Rolling-resistance coefficient [1] (resistance force / load).
    """
    x, p, f_N = _check_profile(x, p)
    h = _check_positive(h, "h")
    va = _check_speeds(V)
    if support not in ("bonded", "winkler"):
        raise InputError("support must be 'bonded' or 'winkler'", field="support",
                         value=support)
    weight = layer_weight(EffectiveModulus(compound, T, strain), h, compound.nu, support)
    return float(_profile_integral(x, p, f_N, va, weight)[0])
