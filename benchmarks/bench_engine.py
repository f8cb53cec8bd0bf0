"""Benchmark of the Persson engine: median time per (v, T, p) point, cold and hot, one core.

Run:  OMP_NUM_THREADS=1 taskset -c 0 python benchmarks/bench_engine.py [--repeat N]

Reports medians for single-point calls (the CLI / API path) and the per-point cost inside a
grid slice (one speed, all T x p, the grid builder's path), at the default resolution (which
the resolution study shows to be within 0.3 % of a 4x finer run). Targets: cold
<= 5 ms, hot <= 50 ms per point; a public Python implementation of the same equations takes
5-8 s per point, so the ratio against 5 s is printed too.
"""

from __future__ import annotations

import argparse
import json
import statistics

import numpy as np
from timing import median_time

from lookup.compound import load_compound
from lookup.friction import PerssonFriction
from lookup.surface import load_surface

#: Lower end of the 5-8 s per point quoted for public Persson implementations.
PUBLIC_REFERENCE_S = 5.0




def bench_case(comp: str, surf: str, rng: np.random.Generator, repeat: int) -> dict:
    """Time one compound/surface pair at 20 random (v, T, p) points and four grid slices."""
    m = PerssonFriction(load_compound(comp), load_surface(surf))
    v = 10.0 ** rng.uniform(-6, np.log10(40), 20)
    T = rng.uniform(253.15, 393.15, 20)
    p = 10.0 ** rng.uniform(np.log10(5e4), np.log10(2e6), 20)

    def single(branch: str) -> None:
        for i in range(v.size):
            m._kernels.clear()  # a fresh speed each call: include the heat kernel
            getattr(m, branch)(v[i], T[i], p[i])

    cold1 = median_time(lambda: single("cold"), repeat) / v.size
    hot1 = median_time(lambda: single("hot"), repeat) / v.size
    Tg = np.linspace(253.15, 393.15, 15)
    pg = np.geomspace(5e4, 2e6, 6)

    def slice_(vv: float) -> None:
        m._kernels.clear()
        m.grid_slice(vv, Tg, pg)

    sl = [median_time(lambda vv=vv: slice_(vv), max(1, repeat // 2)) / (Tg.size * pg.size)
          for vv in (1e-5, 1e-2, 1.0, 30.0)]
    return {"compound": comp, "surface": surf, "n_q": int(m.q.size),
            "cold_single_ms": cold1 * 1e3, "hot_single_ms": hot1 * 1e3,
            "grid_slice_cold+hot_ms_per_point": statistics.median(sl) * 1e3,
            "speedup_vs_public_hot": PUBLIC_REFERENCE_S / hot1,
            "speedup_vs_public_cold": PUBLIC_REFERENCE_S / cold1}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    rows = [bench_case(c, s_, rng, args.repeat)
            for c, s_ in (("summer", "asphalt"), ("summer", "concrete"), ("racing", "concrete"))]
    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"{'case':22s} {'n_q':>4s} {'cold ms/pt':>11s} {'hot ms/pt':>10s} "
          f"{'slice ms/pt':>12s} {'x public':>9s}")
    for r in rows:
        print(f"{r['compound'] + '/' + r['surface']:22s} {r['n_q']:4d} "
              f"{r['cold_single_ms']:11.3f} {r['hot_single_ms']:10.2f} "
              f"{r['grid_slice_cold+hot_ms_per_point']:12.3f} {r['speedup_vs_public_hot']:9.0f}")
    print("targets: cold <= 5 ms, hot <= 50 ms per point (medians of single-point calls, "
          "one core)")


if __name__ == "__main__":
    main()
