"""Benchmark of the calibration (lookup.calibration): the cost of one model evaluation and of
whole fits, with the caches the fit uses against a naive evaluation that builds the engine
anew each time.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_fit.py [--repeat N]

Case: the shipped summer compound on the shipped asphalt, 24 synthetic "measured" points
(8 speeds 1e-4..3 m/s x 10, 20, 40 C at 0.3 MPa) computed with sigma_f0 = 6 MPa and
v* = 3 cm/s. Reported (medians over the repeats, ms or s):

* one evaluation after a change of the adhesive law only (what a Jacobian column of sigma_f0,
  c, v_star or the activation energy costs): cold branch with mu_visc and A/A0 kept per q1
  (review eq. 12), hot branch with the engine (modulus table, heat kernels) kept;
* one evaluation after a change of q1 (the engine and its heat kernels rebuilt);
* the same evaluations done naively (a new PerssonFriction per evaluation), and the ratio;
* whole fits: cold (sigma_f0, c, v_star, q1) and hot (sigma_f0, v_star, D).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace

import numpy as np
from timing import median_time

from lookup.calibration import (
    Branch,
    CalibrationModel,
    CompoundData,
    FitSpec,
    MeasuredTable,
    ParameterSpec,
    fit,
)
from lookup.compound import load_compound
from lookup.friction import PerssonFriction
from lookup.roughness import CutoffRule
from lookup.surface import load_surface


def case(branch: str, params: tuple[ParameterSpec, ...]) -> FitSpec:
    comp, surf = load_compound("summer"), load_surface("asphalt")
    law = replace(comp.adhesion, sigma_f0=6e6, v_star=3e-2)
    eng = PerssonFriction(replace(comp, adhesion=law), surf)
    v, T = (a.ravel() for a in np.meshgrid(np.geomspace(1e-4, 3.0, 8),
                                           np.array([283.15, 293.15, 313.15])))
    mu = getattr(eng, branch)(v, T, 3e5).mu
    tab = MeasuredTable("synthetic", v, T, np.full(v.size, 3e5), mu, np.ones(v.size))
    return FitSpec("bench", surf, (CompoundData("summer", comp, (tab,)),), params,
                   Branch(branch))


ADHESION = (ParameterSpec("sigma_f0", 1e6, 3e7), ParameterSpec("c", 0.02, 1.0),
            ParameterSpec("v_star", 1e-5, 10.0))
Q1 = ParameterSpec("q1", 2e3, 1e7)


def evaluations(branch: str, repeat: int) -> dict[str, float]:
    spec = case(branch, (*ADHESION, Q1))
    m = CalibrationModel(spec)
    m.predict(m.u0)
    k = [0]

    def adhesive() -> None:  # a new sigma_f0 each call, q1 unchanged
        k[0] += 1
        m.predict(m.u0 + np.array([1e-3 * k[0], 0, 0, 0]))

    def new_q1() -> None:  # a new q1 each call
        k[0] += 1
        m.predict(m.u0 + np.array([0, 0, 0, 1e-4 * k[0]]))

    comp, surf = spec.compounds[0].compound, spec.surface
    tab = spec.compounds[0].tables[0]

    def naive() -> None:  # what an evaluation costs without the caches
        k[0] += 1
        law = replace(comp.adhesion, sigma_f0=4e6 * (1 + 1e-3 * k[0]))
        e = PerssonFriction(replace(comp, adhesion=law),
                            replace(surf, cutoff=CutoffRule("fixed", q1=surf.q1)), m.settings)
        getattr(e, branch)(tab.v, tab.T, tab.p)

    out = {"adhesive_change_ms": 1e3 * median_time(adhesive, repeat, 3),
           "q1_change_ms": 1e3 * median_time(new_q1, repeat, 3),
           "naive_ms": 1e3 * median_time(naive, repeat, 3)}
    out["naive_over_adhesive"] = out["naive_ms"] / out["adhesive_change_ms"]
    return out


def fits(repeat: int) -> dict[str, dict]:
    res = {}
    for branch, params in (("cold", (*ADHESION, Q1)),
                           ("hot", (ADHESION[0], ADHESION[2], ParameterSpec("D", 2e-4, 5e-3)))):
        spec = case(branch, params)
        info: dict = {}

        def run(spec=spec, info=info) -> None:
            r = fit(spec)
            info.update(evaluations=r.solver["model_evaluations"], nfev=r.solver["nfev"],
                        rms_log10=r.rms_log10_fit,
                        values={p.label: p.value for p in r.parameters})

        info["seconds"] = median_time(run, repeat)
        res[branch] = info
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    out = {"evaluation": {b: evaluations(b, a.repeat) for b in ("cold", "hot")},
           "fit": fits(max(1, a.repeat // 2))}
    if a.json:
        print(json.dumps(out, indent=2))
        return
    print("one model evaluation, 24 points (median ms):")
    print(f"  {'branch':6s} {'adhesive law':>13s} {'new q1':>9s} {'naive':>9s} {'naive/law':>10s}")
    for b, e in out["evaluation"].items():
        print(f"  {b:6s} {e['adhesive_change_ms']:13.2f} {e['q1_change_ms']:9.2f} "
              f"{e['naive_ms']:9.2f} {e['naive_over_adhesive']:10.1f}")
    print("whole fits (median s):")
    for b, f in out["fit"].items():
        print(f"  {b:6s} {f['seconds']:7.2f} s, {f['evaluations']} evaluations, "
              f"RMS log10 {f['rms_log10']:.2e}, {f['values']}")


if __name__ == "__main__":
    main()
