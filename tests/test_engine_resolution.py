"""The default resolution's bias against a converged result, stated honestly.

Glassy single-relaxation solid (review eq. 4: E0 = 3 MPa, E1 = 3 GPa, tau = 10 ms; at
20 C and v = 1e-4 .. 1 m/s the road's frequencies q v reach the glassy plateau), H = 0.8,
q0 = 1e3, q1 = 1e6 1/m, h_rms = 10 um, p = 0.3 MPa, no adhesion. Reference: 384 q-nodes per
decade, 64 phi-nodes, 320 master-curve samples per decade. Measured bias of the default
settings (24, 16, 40): mu_visc +0.15 / -0.12 / -0.17 %, A/A0 -0.007 / -0.22 / -0.004 % at
v = 1e-4 / 1e-2 / 1 m/s. It comes from the q quadrature (the trapezoidal rule for G(q),
second order: 48 nodes per decade give a quarter of it, 96 a sixteenth); n_phi and the
master-curve sampling contribute < 0.02 %. ``--q-per-decade 96`` (CLI) or
``[engine] q_per_decade = 96`` (grid spec) brings it below 0.02 %.
"""

from __future__ import annotations

import numpy as np
from conftest import T20, make_compound, make_surface

from lookup.adhesion import NoAdhesion
from lookup.friction import EngineSettings, PerssonFriction
from lookup.modulus import SingleRelaxation
from lookup.roughness import CutoffRule

V = np.array([1e-4, 1e-2, 1.0])


def run(**kw):
    comp = make_compound(SingleRelaxation(3e6, 3e9, 1e-2), NoAdhesion(), nu=0.5)
    surf = make_surface(H=0.8, q0=1e3, q_r=1e3, h_rms=1e-5, cutoff=CutoffRule("fixed", q1=1e6))
    r = PerssonFriction(comp, surf, EngineSettings(**kw)).cold(V, T20, 3e5)
    return r.mu_visc, r.area


def test_default_resolution_bias_on_a_glassy_solid() -> None:
    ref_mu, ref_a = run(q_per_decade=384, n_phi=64, modulus_per_decade=320)
    bias = {}
    for n in (24, 48, 96):
        mu, a = run(q_per_decade=n)
        bias[n] = (np.abs(mu / ref_mu - 1).max(), np.abs(a / ref_a - 1).max())
        print(f"q_per_decade {n}: mu_visc bias {bias[n][0]:.3%}, A/A0 bias {bias[n][1]:.3%}")
    # the default is good to a few tenths of a percent, not to 0.1 %
    assert 5e-4 < bias[24][0] < 5e-3 and 5e-4 < bias[24][1] < 5e-3
    # second-order convergence in the q spacing: halving it divides the bias by ~4
    assert bias[24][0] / bias[48][0] > 3.5 and bias[48][0] / bias[96][0] > 3.5
    assert bias[96][0] < 2e-4 and bias[96][1] < 2e-4
    # the angular and master-curve resolutions are not what limits the default
    mu, a = run(n_phi=64, modulus_per_decade=160)
    assert np.abs(mu / run()[0] - 1).max() < 2e-4
