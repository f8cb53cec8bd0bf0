r"""Squeeze-out: the share of the real contact area that is dry when water must drain first.

At low speed water is squeezed out of the asperity contacts and wet friction equals dry
friction; at high speed there is no time and the adhesive (real-contact) term disappears
(review sec. 5.2 and sec. 8, "forced dewetting"). This module computes the dry share w of the
real contact area of a macroasperity contact after the time available, and w weights the
adhesive term: 1 when there is time, 0 when there is none.

Model (after Lorenz & Persson, Eur. Phys. J. E 32 (2010) 281, "Time-dependent fluid
squeeze-out between solids with rough surfaces"):

1. **Geometry and load.** The water drains from a macroasperity contact of diameter D (the
   surface's ``[macroasperity] D``, radius R = D/2) that carries the nominal pressure
   sigma_m = sigma0 / P(q_m), q_m = pi / D (as in :mod:`lookup.flash_temperature`).
2. **Thin-film flow.** The film between the rubber and the road thins by Reynolds' squeeze
   flow between parallel discs (Stefan's law), dh/dt = -2 h^3 p_f / (3 eta R^2), driven by
   the fluid pressure p_f = sigma_m - p_s(h), where p_s is the pressure carried by the
   solids. Lorenz & Persson write the same balance with the interfacial separation from the
   contact mechanics and add a pressure-flow factor for the flow through the roughness
   channels; the flow factor is omitted here (smooth-film Reynolds flow), which drains the
   last stage faster than theirs.
3. **Contact mechanics.** h is identified with the average interfacial separation u_bar, and
   p_s(u_bar) is the inverse of Persson's u_bar(p) (Yang & Persson, J. Phys.: Condens. Matter
   20 (2008) 215214):

   .. math::

       \bar u(p) = \sqrt\pi \int_{q_m}^{q_1} dq\, q^2 C(q) w(q)
                   \int_{p}^{\infty} \frac{dp'}{p'} [\gamma + 3(1-\gamma) P^2(p', q)]
                   e^{-(w(q) p'/E^*)^2},

   with :math:`w(q) = (\pi \int_{q_m}^{q} q'^3 C dq')^{-1/2}` and P(p', q) = erf(w p'/E*)
   (the corrected eq. 18). The rubber's modulus enters through the friction engine's G(q)
   (eq. 19, the modulus at the sliding frequencies): w p'/E* is replaced by
   p' / (2 sigma0 sqrt(G(q) - G(q_m))), which is the same in the elastic limit. With
   t = w p'/E* the inner integral is the tabulated function
   K(a) = int_a^inf (dt/t) [gamma + 3 (1 - gamma) erf(t)^2] exp(-t^2).
4. **Dry share.** Starting from a thick film, the time to reach the state with solid
   pressure p_s is t(p_s) = 3 eta R^2 / (4 sigma_m u_bar(p_lo)^2) + int (3 eta R^2 / 2)
   |du_bar| / (u_bar^3 (sigma_m - p_s)), and the real contact that has formed after the
   available time t_a carries p_s(t_a): its share of the final (dry) contact area is
   w = p_s / sigma_m (the contact area is proportional to the load it carries, review eq. 11
   at small contact). w -> 1 as t_a -> infinity and w -> 0 as t_a -> 0.

The available time is the macroasperity contact time D / v for a sliding block and the tread
element's time in the footprint for a tire (:mod:`lookup.wet.friction`). The viscosity is that
of the lubricant at the background temperature T0 (:mod:`lookup.wet.water`).

**The asperity contacts while sliding** (:func:`asperity_dry_share`). The macro contact's
drainage above builds the solid contact the contact mechanics predicts, but a contact region
at the highest magnification is dry only once the water film on it has been thinned to the
thickness at which it collapses; while the rubber slides, each such region exists only for
its size over the sliding speed (review sec. 8: "at much higher sliding speeds, there is
insufficient time for the water film to be fully squeezed out"). The law:

5. **Contact regions at q1.** Review eq. (17) excites the rubber at scale q with the frequency
   q v cos(phi): a contact region of that scale is deformed for half a period, so it has the
   diameter d = pi / q and lasts d / v. At q1 (the real contact) the radius is
   r = pi / (2 q1).
6. **Stefan squeeze film** of a disc of radius r under the local pressure sigma (Stefan 1874;
   Reynolds, Phil. Trans. R. Soc. 177 (1886) 157; the rigid-disc form
   t = (3 pi eta r^4 / 4F) (1/h^2 - 1/h0^2) with F = pi r^2 sigma): from a thick film
   (h0 >> h) the film reaches h after t = 3 eta r^2 / (4 sigma h^2).
7. **Collapse thickness.** Below h_c = 40 nm the film collapses and the surfaces spring into
   adhesive contact (Roberts & Tabor, Proc. R. Soc. A 325 (1971) 323, as quoted in review
   sec. 8: "When the thickness of the film falls below 40 nm, the surfaces suddenly spring
   together"). A contact region is dry if t(h_c) <= d / v, i.e. if its pressure exceeds
   sigma* = 3 eta r |v| / (8 h_c^2).
8. **Pressure distribution.** The share of the real contact at q1 with pressure above
   sigma* follows from Persson's contact-pressure distribution (Persson, J. Chem. Phys. 115
   (2001) 3840; review eq. (18) is its integral over sigma > 0),
   P(sigma) = [exp(-(sigma - sigma0)^2 / s^2) - exp(-(sigma + sigma0)^2 / s^2)] / (s sqrt(pi)),
   s = 2 sigma0 sqrt(G(q1)):

   .. math::

       w_{asp} = \frac{\mathrm{erfc}((\sigma^* - \sigma_0)/s) - \mathrm{erfc}((\sigma^*
                 + \sigma_0)/s)}{2\,\mathrm{erf}(\sigma_0 / s)},

   1 at v = 0 and falling to 0 as the sliding speed grows. Where the film stays, the adhesive
   term is removed (the film's viscous shear eta v / h is left out: at 28 m/s and h = 0.1 um it
   is ~0.3 MPa on the real contact, against sigma_f of MPa; docs/physics.md sec. 7a).

The two squeeze-outs act in series: the dry share of the real contact is
w = w_macro(t) w_asp(v), the macro contact's drainage within the available time t times the
share of its asperity contacts dried within their own contact time.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.special import erf, erfc

#: Film thickness [m] below which a squeezed water film collapses into adhesive contact
#: (Roberts & Tabor 1971, review sec. 8; module item 7).
H_COLLAPSE = 40e-9

#: Solid-pressure ratios s = p_s / sigma_m at which u_bar and the drainage time are tabulated.
S_NODES = np.concatenate([np.geomspace(1e-6, 0.5, 30), 1.0 - np.geomspace(0.5, 1e-4, 14)[1:]])


@lru_cache(maxsize=4)
def _K_table(gamma: float) -> tuple[np.ndarray, np.ndarray]:
    """ln a and K(a) on a fine grid (Simpson in ln t), K(a) = int_a^inf ... (module item 3)."""
    lt = np.linspace(np.log(1e-12), np.log(8.0), 8001)
    t = np.exp(lt)
    f = (gamma + 3.0 * (1.0 - gamma) * erf(t) ** 2) * np.exp(-t * t)  # (dt/t) = d ln t
    dl = lt[1] - lt[0]
    seg = 0.5 * (f[1:] + f[:-1]) * dl
    K = np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])
    return lt, K


def K_function(a: np.ndarray, gamma: float = 0.5) -> np.ndarray:
    """K(a) = int_a^inf (dt/t) [gamma + 3 (1 - gamma) erf(t)^2] exp(-t^2) (module item 3).

    For a below 1e-12 the small-a asymptote K(1e-12) + gamma ln(1e-12 / a) is used.
    """
    lt, K = _K_table(float(gamma))
    la = np.log(np.maximum(np.asarray(a, float), 1e-300))
    out = np.interp(la, lt, K, right=0.0)
    return np.where(la < lt[0], K[0] + gamma * (lt[0] - la), out)


def mean_separation(s: np.ndarray, q: np.ndarray, F: np.ndarray, G: np.ndarray, i_m: int,
                    sigma0: np.ndarray, P_m: np.ndarray, gamma: float) -> np.ndarray:
    """Average interfacial separation u_bar [m] in the macro contact (module item 3).

    Parameters
    ----------
    s : numpy.ndarray
        Solid-pressure ratios p_s / sigma_m, shape (ns,).
    q : numpy.ndarray
        Wavenumber nodes [1/m], shape (nq,).
    F : numpy.ndarray
        q^4 C(q) [m^0], shape (nq,) or (B, nq).
    G : numpy.ndarray
        The engine's G(q) at the nominal pressure sigma0, shape (B, nq).
    i_m : int
        Index of the first node at or above q_m.
    sigma0, P_m : numpy.ndarray
        Nominal pressure [Pa] and macro-contact fraction P(q_m), shape (B,).

    Returns
    -------
    numpy.ndarray
        u_bar, shape (B, ns).
    """
    lnq = np.log(q)
    Fm = np.broadcast_to(F, G.shape)[:, i_m:]
    qq = q[i_m:]
    # w(q) = (pi int_{q_m}^q q'^3 C dq')^(-1/2), trapezoid in ln q (int q^3 C dq = int F dlnq)
    dl = np.diff(lnq[i_m:])
    cum = np.concatenate([np.zeros((G.shape[0], 1)),
                          np.cumsum(0.5 * (Fm[:, 1:] + Fm[:, :-1]) * dl, axis=1)], axis=1)
    dG = G[:, i_m:] - G[:, i_m:i_m + 1]
    ok = (cum > 0) & (dG > 0)
    w = np.where(ok, 1.0 / np.sqrt(np.pi * np.where(ok, cum, 1.0)), 0.0)
    sigma_m = (sigma0 / P_m)[:, None, None]
    a = s[None, :, None] * sigma_m / (2.0 * sigma0[:, None, None]
                                      * np.sqrt(np.where(ok, dG, 1.0))[:, None, :])
    Kv = np.where(ok[:, None, :], K_function(a, gamma), 0.0)
    # integrand q^2 C w K dq = (F / q) w K d ln q
    f = (Fm / qq)[:, None, :] * w[:, None, :] * Kv
    wts = np.zeros(qq.size)
    wts[:-1] += 0.5 * dl
    wts[1:] += 0.5 * dl
    return np.sqrt(np.pi) * np.einsum("bsq,q->bs", f, wts)


def dry_share(t_avail: np.ndarray, eta: np.ndarray, R: float, sigma0: np.ndarray,
              P_m: np.ndarray, u_bar: np.ndarray, s: np.ndarray = S_NODES) -> np.ndarray:
    """Dry share w of the real contact after time ``t_avail`` [s] (module item 4).

    Parameters
    ----------
    t_avail, eta, sigma0, P_m : numpy.ndarray
        Available time [s], viscosity [Pa s], nominal pressure [Pa] and P(q_m), shape (B,).
    R : float
        Macro-contact radius [m].
    u_bar : numpy.ndarray
        :func:`mean_separation` at the ratios ``s``, shape (B, ns).

    Returns
    -------
    numpy.ndarray
        w in [0, 1], shape (B,).
    """
    sigma_m = sigma0 / P_m
    c = (3.0 * eta * R * R / sigma_m)[:, None]
    u = np.maximum(u_bar, 1e-300)
    t0 = 0.25 * c[:, 0] / u[:, 0] ** 2
    # d t = (3 eta R^2 / 2) |du| / (u^3 sigma_m (1 - s)): trapezoid over the s nodes
    g = 0.5 / (u**3 * (1.0 - s)[None, :])
    du = -np.diff(u, axis=1)
    dt = c * 0.5 * (g[:, 1:] + g[:, :-1]) * np.maximum(du, 0.0)
    t = np.concatenate([t0[:, None], t0[:, None] + np.cumsum(dt, axis=1)], axis=1)
    lt = np.log(np.maximum(t, 1e-300))
    lta = np.log(np.maximum(np.asarray(t_avail, float), 1e-300))
    out = np.empty(lta.size)
    for b in range(lta.size):  # t is increasing in s; interpolate s at t = t_avail
        out[b] = np.interp(lta[b], lt[b], s, left=0.0, right=s[-1])
    return np.where(lta < lt[:, 0], 0.0, out)


def asperity_pressure_threshold(v: np.ndarray, eta: np.ndarray, q1: float,
                                h_c: float = H_COLLAPSE) -> np.ndarray:
    """sigma* = 3 eta r |v| / (8 h_c^2) [Pa] with r = pi / (2 q1) (module items 5-7): the
    least local pressure that thins the film on a contact region of radius r from a thick
    film to h_c within its contact time 2 r / |v| (Stefan's law)."""
    r = 0.5 * np.pi / q1
    return 3.0 * np.asarray(eta, float) * r * np.abs(np.asarray(v, float)) / (8.0 * h_c * h_c)


def asperity_dry_share(v: np.ndarray, eta: np.ndarray, q1: float, sigma0: np.ndarray,
                       G1: np.ndarray, h_c: float = H_COLLAPSE) -> np.ndarray:
    """Share w_asp of the real contact at q1 whose water film collapses within the contact
    regions' lifetime (module items 5-8).

    Parameters
    ----------
    v : numpy.ndarray
        Sliding speed [m/s].
    eta : numpy.ndarray
        Viscosity of the lubricant [Pa s].
    q1 : float
        Largest wavenumber of the roughness [1/m] (the real contact's scale).
    sigma0 : numpy.ndarray
        Nominal pressure [Pa].
    G1 : numpy.ndarray
        The contact mechanics' G(q1) (review eq. 19) of the real contact, > 0.
    h_c : float
        Collapse thickness [m].

    Returns
    -------
    numpy.ndarray
        w_asp in [0, 1] (broadcast shape of the inputs).
    """
    sig = np.asarray(sigma0, float)
    s = 2.0 * sig * np.sqrt(np.asarray(G1, float))
    st = asperity_pressure_threshold(v, eta, q1, h_c)
    with np.errstate(invalid="ignore", divide="ignore"):
        num = 0.5 * (erfc((st - sig) / s) - erfc((st + sig) / s))
        w = num / erf(sig / s)
    return np.clip(np.where(s > 0, w, 1.0), 0.0, 1.0)
