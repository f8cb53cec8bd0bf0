r"""Flash temperature in the macroasperity contacts: the heat kernel of the hot branch.

Model (review sec. 5.1, eqs. 23-27, and the multiscale picture of its ref. [VG]; made concrete
as in docs/review-notes.md, "one defensible hot-branch model"). Assumptions, in order:

1. **Where the heat is made.** All frictional heat is produced inside the macroasperity
   contacts of diameter ``D`` (a surface property), which cover the fraction
   ``P_m = P(q_m)``, ``q_m = pi / D``, of the nominal area; it is spread laterally over them
   (the review's simplification). Per unit macro-contact area the power is the nominal value
   divided by ``P_m``.
2. **How long.** A rubber surface element stays in one macro contact for ``t_c = D / v``; it
   enters at the background temperature ``T0`` (steady sliding over a fresh road track, the
   "fully developed" flash temperature of review eq. 28's hot branch).
3. **At which depth.** Adhesive heat ``sigma_f v A/A0`` is a surface flux (deposited within
   ~1 nm, review after eq. 23). The viscoelastic heat of roughness scale ``q`` (the
   q-integrand of eq. 17 times ``sigma0 v``) is deposited with the depth profile
   ``2 q exp(-2 q z)``: a deformation of wavevector q decays as exp(-q z), its dissipation as
   exp(-2 q z).
4. **Diffusion.** 1D heat diffusion into the rubber (diffusivity ``D_th``) during the contact.
   The road is a second half-space in perfect thermal contact at the background temperature:
   Green's function with an image of strength
   ``R = (e_rubber - e_road) / (e_rubber + e_road)``, ``e = sqrt(kappa rho c)`` (Carslaw &
   Jaeger, *Conduction of Heat in Solids*, 2nd ed., sec. 2.15 for composite media). A surface
   flux then sends the fraction ``e_road / (e_rubber + e_road)`` into the road. With no road
   thermal data, ``R = 1`` (insulated interface: all heat enters the rubber).
5. **Which temperature counts.** Scale ``q`` feels the contact-time average of the temperature
   at its dissipation depth ``z_q = 1 / (2 q)``; the adhesive law feels the contact-time
   average at the surface, which is reported as the flash temperature ``dT_flash``.
6. **Lateral spreading.** When the diffusion length ``sqrt(D_th t_c)`` is not small against
   ``D`` heat escapes sideways. The 1D result is multiplied by
   ``f_lat = (1 + (16 / (9 pi)) / J_d)^(-1/2)``, ``J_d = v D / D_th``. This is Greenwood's
   interpolation (review eq. 26, J_h term absent because depth is resolved explicitly) with the
   constant fixed so that a surface source gives exactly the stationary-source limit of review
   eq. (25), ``dT = q_flux D / kappa``, as ``J_d -> 0``, and the pure 1D result for
   ``J_d >> 1``. The same factor is applied at every depth (approximation).

With constant sources over the contact the time-averaged rise is linear in the sources,
``dT_i = f_lat sum_j K_ij W_j``; the kernel ``K`` depends on the speed only (through t_c) and is
computed here once per speed. The self-consistent fixed point (friction -> heat -> temperature
-> modulus -> friction) is solved in :mod:`lookup.friction`.

Kernel (per unit power per area of a source with profile ``a exp(-a z')``, ``a = 2 q``)::

    K(z) = (1/(rho c)) int_0^t_c (1 - tau/t_c) h(z, tau) dtau,
    h(z, tau) = int_0^inf dz' a e^{-a z'} [N(z - z'; 2 D tau) + R N(z + z'; 2 D tau)],

with N the normal density; the z' integral is closed-form (erfcx), the tau integral is
Gauss-Legendre on log tau plus the analytic small-tau remainder.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import erfc, erfcx

#: Greenwood-type lateral spreading constant (see module docstring, item 6).
LATERAL_CONSTANT = 16.0 / (9.0 * np.pi)


def lateral_factor(J_d: np.ndarray) -> np.ndarray:
    """f_lat(J_d) = (1 + (16/(9 pi))/J_d)^(-1/2) (module docstring item 6; review eq. 26)."""
    J_d = np.asarray(J_d, float)
    return 1.0 / np.sqrt(1.0 + LATERAL_CONSTANT / np.maximum(J_d, 1e-300))


def _exp_gauss(a: np.ndarray, z: np.ndarray, s: np.ndarray, sign: float) -> np.ndarray:
    """int_0^inf a e^{-a z'} N(z - sign*(-z'); s^2) dz' in a stable closed form.

    ``sign=+1``: N(z - z') (direct term); ``sign=-1``: N(z + z') (image term).
    Equals (a/2) exp(-sign a z + a^2 s^2/2) erfc((a s^2 - sign z)/(s sqrt 2)).
    """
    u = (a * s * s - sign * z) / (s * np.sqrt(2.0))
    up = np.maximum(u, 0.0)
    via_erfcx = 0.5 * a * np.exp(-(z * z) / (2.0 * s * s)) * erfcx(up)
    expo = np.minimum(-sign * a * z + 0.5 * (a * s) ** 2, 0.0)
    via_erfc = 0.5 * a * np.exp(expo) * erfc(np.minimum(u, 0.0))
    return np.where(u >= 0.0, via_erfcx, via_erfc)


def _gauss(z: np.ndarray, s: np.ndarray) -> np.ndarray:
    return np.exp(-(z * z) / (2.0 * s * s)) / (s * np.sqrt(2.0 * np.pi))


@dataclass(frozen=True)
class HeatKernelSettings:
    """Quadrature of the kernel's time integral.

    Attributes
    ----------
    nodes_per_decade : int
        Gauss-Legendre nodes per decade of tau.
    decades_below : float
        How far below the shortest diffusion time (1/(4 q_max^2 D_th)) the tau quadrature
        starts; the rest is the analytic small-tau remainder.
    """

    nodes_per_decade: int = 3
    decades_below: float = 3.0


def heat_kernel(
    z: np.ndarray,
    a: np.ndarray,
    t_c: float,
    diffusivity: float,
    rho_c: float,
    R: float,
    settings: HeatKernelSettings | None = None,
) -> np.ndarray:
    """Contact-time-averaged temperature rise per unit source power (1D, no lateral factor).

    Parameters
    ----------
    z : numpy.ndarray
        Evaluation depths [m], shape (nz,), ``>= 0``.
    a : numpy.ndarray
        Source profile constants [1/m], shape (ns,); profile ``a exp(-a z)``; ``np.inf`` means
        a surface flux.
    t_c : float
        Contact time [s].
    diffusivity : float
        Rubber thermal diffusivity D_th [m^2/s].
    rho_c : float
        Volumetric heat capacity rho c_v [J/(m^3 K)].
    R : float
        Image strength (1: insulated surface; see module docstring item 4).
    settings : HeatKernelSettings, optional

    Returns
    -------
    numpy.ndarray
        K, shape (nz, ns) [K m^2 / W]: ``<dT>(z_i) = sum_j K_ij W_j`` for source powers W_j
        [W/m^2] switched on at t = 0 and held for t_c.
    """
    s = settings or HeatKernelSettings()
    z = np.asarray(z, float)[:, None]
    a = np.asarray(a, float)[None, :]
    finite_a = np.isfinite(a)
    a_max = float(np.max(a[finite_a])) if finite_a.any() else 1.0 / max(float(z.max()), 1e-9)
    z_pos = z[z > 0]
    scale = max(a_max, 1.0 / float(z_pos.min()) if z_pos.size else a_max)
    tau_lo = min(t_c, 1.0 / (4.0 * scale**2 * diffusivity)) * 10.0 ** (-s.decades_below)
    decades = np.log10(t_c / tau_lo)
    n = max(int(np.ceil(decades * s.nodes_per_decade)), 4)
    x, w = np.polynomial.legendre.leggauss(n)
    lt = 0.5 * (np.log(t_c) - np.log(tau_lo)) * x + 0.5 * (np.log(t_c) + np.log(tau_lo))
    tau = np.exp(lt)
    wt = w * 0.5 * (np.log(t_c) - np.log(tau_lo)) * tau * (1.0 - tau / t_c)  # dtau weights
    K = np.zeros((z.shape[0], a.shape[1]))
    a_fin = np.where(finite_a, a, 1.0)
    for tk, wk in zip(tau, wt, strict=True):
        sd = np.sqrt(2.0 * diffusivity * tk)
        direct = _exp_gauss(a_fin, z, sd, +1.0)
        image = _exp_gauss(a_fin, z, sd, -1.0)
        vol = direct + R * image
        surf = (1.0 + R) * _gauss(z, sd)
        K += wk * np.where(finite_a, vol, surf)
    # tau in (0, tau_lo): the source has not moved yet; h -> a exp(-a z) (surface: a delta at
    # z = 0, which contributes nothing at z > 0 and is absorbed at z = 0 by the first nodes).
    K += tau_lo * np.where(finite_a, a_fin * np.exp(-a_fin * z), 0.0)
    return K / rho_c


def eq27_flash_temperature(v: np.ndarray, mu_cont: float, sigma: float, kappa: float,
                           diffusivity: float, d: float) -> np.ndarray:
    """Review eq. (27): dT ~ 1.6 mu_cont sigma sqrt(v D d) / kappa_th (adhesive, J_d >> 1)."""
    v = np.asarray(v, float)
    return 1.6 * mu_cont * sigma * np.sqrt(v * diffusivity * d) / kappa


def eq26_flash_temperature(v: np.ndarray, q_flux: np.ndarray, kappa: float, diffusivity: float,
                           d: float, h: float = 0.0) -> np.ndarray:
    """Review eq. (26): Greenwood's interpolation with the J_h term."""
    v = np.asarray(v, float)
    J_d = v * d / diffusivity
    J_h = v * h / diffusivity
    return q_flux * d / kappa / np.sqrt(1.0 + 0.39 * J_d + J_h**2)
