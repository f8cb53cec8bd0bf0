"""The EU label's physics against what tires measure (a report, not a timed test).

Prints, for the shipped passenger tire and the wet reference road (docs/label.md, docs/rolling.md,
docs/physics.md sec. 7a):

* rolling resistance at the ISO 28580 conditions: RRC [N/kN] and class, its change per K over
  20-30 C, the load exponent (F_r ~ Fz^alpha, 0.5-1.2 x the load-index load) and the pressure
  exponent (F_r ~ p^beta, 210-250 kPa), and f_r over speed; each for the tire held at 25 C
  (isothermal) and at its thermal equilibrium at 25 C ambient (warm: the tread's temperature
  from its losses and the tire file's conductance, as ISO 28580 measures; the change per K
  then of the ambient), and the deformation index of the tread at the patch's harmonics;
* wet friction against speed: the locked wheel's Fx/Fz at 20, 60 and 100 km/h on the wet
  reference road (and dry), at 5, 20 and 35 C, and the ratio mu(100)/mu(20), next to the
  PIARC speed constant of the road's texture (Sp = 14.2 + 89.7 MPD km/h, ASTM E1960);
* the wet grip test at 5 ... 35 C: BFC of the passenger tire and the reference tire, the
  reference tire's windows, dBFC/dT, G and the classes.

Usage: ``python benchmarks/bench_label.py [--quick] [--rolling]`` (--quick: 5 / 20 / 35 C
only; --rolling: the rolling resistance only).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def _parts(res, i=...) -> dict:
    """The parts of a RollingResistance result [N/kN]: the tread's footprint-pressure loss
    (eq. 29), the tread band's and the belt's bending, the sidewalls' deflection loss."""
    band = res.f_band if res.f_band is not None else 0 * res.f_tread
    belt = res.f_belt if res.f_belt is not None else 0 * res.f_tread
    return {"tread_p": 1e3 * (res.f_tread - band)[i], "band": 1e3 * band[i],
            "belt": 1e3 * belt[i], "sidewall": 1e3 * (res.f_carcass - belt)[i],
            "total": 1e3 * res.f_r[i]}


def rolling_report() -> dict:
    from dataclasses import replace

    from lookup.compound import load_compound
    from tire_brush.params import load_tire
    from tire_brush.rolling_resistance import iso28580, load_rolling_params, rolling_resistance

    tire = load_tire("passenger")
    rr = load_rolling_params(tire)
    comp = load_compound("summer")
    iso = iso28580(tire, comp, rr=rr, warm_up=False)
    iso_tire = replace(tire, patch=replace(tire.patch, p_inflation=rr.iso_inflation))
    V, T = 80 / 3.6, 298.15
    loads = np.array([0.5, 1.2]) * rr.load_index_load
    rl = rolling_resistance(iso_tire, comp, V, loads, T, rr=rr)
    Fr = rl.F_r
    alpha = math.log(Fr[1] / Fr[0]) / math.log(loads[1] / loads[0])
    ps = np.array([210e3, 250e3])
    rp = [rolling_resistance(replace(tire, patch=replace(tire.patch, p_inflation=p)),
                             comp, V, iso.load_N, T, rr=rr) for p in ps]
    beta = math.log(float(rp[1].F_r) / float(rp[0].F_r)) / math.log(ps[1] / ps[0])
    speeds = np.array([20, 50, 80, 120, 150]) / 3.6
    fv = rolling_resistance(iso_tire, comp, speeds, iso.load_N, T, rr=rr)
    parts = rolling_resistance(iso_tire, comp, V, iso.load_N, T, rr=rr)
    Ts = np.array([293.15, 298.15, 303.15, 328.15, 333.15, 338.15])
    rt = rolling_resistance(iso_tire, comp, V, iso.load_N, Ts, rr=rr)
    pt = [_parts(rt, i) for i in range(Ts.size)]

    def per_K(i0, i1, k):  # the part's change per K over the total, %/K
        return 100 * (pt[i1][k] - pt[i0][k]) / ((Ts[i1] - Ts[i0]) * pt[(i0 + i1) // 2]["total"])

    pl = [_parts(rl, 0), _parts(rl, 1)]
    pp = [_parts(r, ...) for r in rp]
    keys = ("tread_p", "band", "belt", "sidewall")
    return {"rrc": iso.rrc_N_per_kN, "class": iso.label_class, "per_K": 100 * iso.per_K,
            "alpha": alpha, "beta": beta, "f_tread": 1e3 * float(parts.f_tread),
            "f_carcass": 1e3 * float(parts.f_carcass),
            "parts": {k: float(v) for k, v in _parts(parts, ...).items()},
            "per_K_parts": {k: per_K(0, 2, k) for k in keys},
            "rrc_60C": pt[4]["total"], "per_K_60C": per_K(3, 5, "total"),
            "parts_60C": pt[4],
            # force exponents of the parts: F ~ Fz^alpha (f = F/Fz) and F ~ p^beta
            "alpha_parts": {k: 1 + math.log(pl[1][k] / pl[0][k]) / math.log(1.2 / 0.5)
                            for k in keys if pl[0][k] > 0},
            "beta_parts": {k: math.log(float(pp[1][k]) / float(pp[0][k])) / math.log(250 / 210)
                           for k in keys if float(pp[0][k]) > 0},
            "tread_share": float(parts.tread_share), "heat_W": float(parts.heat_rate),
            "f_v": (fv.f_r / fv.f_r[2]).tolist()}


def warm_report() -> dict:
    """The ISO point at thermal equilibrium (25 C ambient): the RRC, the tread temperature, the
    change per K of the ambient, the load and pressure exponents and f_r over speed, each
    point at its own equilibrium temperature; and the deformation index of the tread at the
    patch's first harmonics (q = k pi / a)."""
    from dataclasses import replace

    from lookup.compound import load_compound
    from lookup.rolling import EffectiveModulus
    from tire_brush import rolling_resistance as rrm
    from tire_brush.params import load_tire

    tire = load_tire("passenger")
    rr = rrm.load_rolling_params(tire)
    comp = load_compound("summer")
    iso = rrm.iso28580(tire, comp, rr=rr)

    def at(p, Fz, V=rrm.ISO_SPEED, Ta=rrm.ISO_T_K):
        t = replace(tire, patch=replace(tire.patch, p_inflation=p))
        T = rrm.steady_temperature(t, comp, V, Fz, Ta, rr=rr)
        return rrm.rolling_resistance(t, comp, V, Fz, T, rr=rr), T

    LI = rr.load_index_load
    (r0, _), (r1, _) = at(210e3, 0.5 * LI), at(210e3, 1.2 * LI)
    alpha = math.log(float(r1.F_r / r0.F_r)) / math.log(2.4)
    (p0, _), (p1, _) = at(210e3, iso.load_N), at(250e3, iso.load_N)
    beta = math.log(float(p1.F_r / p0.F_r)) / math.log(250 / 210)
    fv, Tv = zip(*(at(210e3, iso.load_N, V=v / 3.6) for v in (20, 50, 80, 120, 150)),
                 strict=True)
    f_v = [float(r.f_r / fv[2].f_r) for r in fv]
    t210 = replace(tire, patch=replace(tire.patch, p_inflation=210e3))
    a, _ = t210.patch.size(iso.load_N)
    mod = EffectiveModulus(comp, comp.T_ref)
    land = 1.0 - tire.tread.void_ratio
    n_idx = []
    for k in (1, 2, 4):
        q = k * math.pi / a
        w = q * rrm.ISO_SPEED * 10.0 ** float(comp.log10_aT(np.asarray(rrm.ISO_T_K)))
        Er, Ei = mod.storage_loss(np.array([w]))
        c_t = float(rrm._tread_shape(rr, comp.nu, land, q)) / math.hypot(Er[0], Ei[0])
        c_b = float(rrm.belt_compliance(t210, rr, iso.load_N, q))
        n_idx.append((k, c_t, c_b, float(rrm.deformation_index(c_t, c_b))))
    return {"rrc": iso.rrc_N_per_kN, "class": iso.label_class, "T_tire_C": iso.T_tire_K - 273.15,
            "per_K": 100 * iso.per_K, "per_K_iso": 100 * iso.per_K_isothermal,
            "alpha": alpha, "beta": beta, "f_v": f_v, "T_v": [t - 273.15 for t in Tv],
            "tread_share": iso.tread_share, "index": n_idx}


def wet_speed_report(temps, partial_lift: bool = False, dry: bool = True) -> list[dict]:
    from tire_brush.braking.wet_grip_test import _grids, friction_source, load_wet_grip_spec

    spec = load_wet_grip_spec()
    grids = _grids(spec.grid)
    out = []
    for d in (spec.water_depth, 0.0) if dry else (spec.water_depth,):
        src = friction_source(spec, "passenger", d, grids, partial_lift=partial_lift)
        for T in temps:
            mu = [-float(src(np.array([-1.0]), v / 3.6, spec.car.Fz, T + 273.15)[0])
                  for v in (20, 60, 100)]
            out.append({"depth_mm": d * 1e3, "T_C": T, "mu": mu, "ratio": mu[2] / mu[0]})
    return out


def wet_grip_report(temps, partial_lift: bool = False) -> list[dict]:
    from tire_brush.braking.wet_grip_test import load_wet_grip_spec, run_wet_grip

    spec = load_wet_grip_spec()
    rows = []
    for T in temps:
        doc, _ = run_wet_grip(spec, "passenger", T, partial_lift=partial_lift)
        rows.append({"T_C": T, "bfc": doc["candidate"]["bfc_wet"],
                     "bfc_ref": doc["reference"]["bfc_wet"],
                     "peak_ref": doc["reference"]["peak_wet"], "G": doc["G"],
                     "class": doc["label_class"], "in_windows": doc["reference_in_windows"],
                     "notes": len(doc["notes"])})
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rolling", action="store_true", help="the rolling resistance only")
    args = ap.parse_args()
    temps = [5.0, 20.0, 35.0] if args.quick else [5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0]
    t0 = time.perf_counter()
    r = rolling_report()
    print("rolling resistance (ISO 28580: 80 km/h, 4825 N, 210 kPa), the tire held at 25 C")
    print(f"  RRC {r['rrc']:.2f} N/kN (tread {r['f_tread']:.2f}, carcass {r['f_carcass']:.2f}),"
          f" class {r['class']}   [passenger tires 6-12 N/kN]")

    def fmt(d, f):
        return ", ".join(f"{k} {f.format(v)}" for k, v in d.items())

    print(f"  parts [N/kN]: {fmt(r['parts'], '{:.2f}')}; tread share {r['tread_share']:.2f}, "
          f"heat {r['heat_W']:.0f} W")
    print(f"  change per K {r['per_K']:+.2f} %/K   [ISO 28580: -0.8 %/K; accepted -0.5..-1.2]"
          f"; parts {fmt(r['per_K_parts'], '{:+.2f}')}")
    print(f"  whole tire at 60 C: RRC {r['rrc_60C']:.2f} N/kN ({fmt(r['parts_60C'], '{:.2f}')}),"
          f" change per K {r['per_K_60C']:+.2f} %/K")
    print(f"  load exponent {r['alpha']:.3f}   [0.85-1.05]; parts "
          f"{fmt(r['alpha_parts'], '{:.2f}')}")
    print(f"  pressure exponent {r['beta']:.3f}   [-0.25..-0.5]; parts "
          f"{fmt(r['beta_parts'], '{:+.2f}')}")
    print("  f_r(V)/f_r(80 km/h) at 20/50/80/120/150 km/h: "
          + " / ".join(f"{x:.3f}" for x in r["f_v"]))
    w = warm_report()
    print(f"at thermal equilibrium, 25 C ambient: RRC {w['rrc']:.2f} N/kN, class {w['class']}, "
          f"tread {w['T_tire_C']:.1f} C, tread share {w['tread_share']:.2f}")
    print(f"  change per K of the ambient {w['per_K']:+.2f} %/K (isothermal at 25 C "
          f"{w['per_K_iso']:+.2f}); load exponent {w['alpha']:.3f}; pressure exponent "
          f"{w['beta']:.3f}")
    print("  f_r(V)/f_r(80 km/h) at 20/50/80/120/150 km/h: "
          + " / ".join(f"{x:.3f}" for x in w["f_v"]) + " (tread at "
          + " / ".join(f"{t:.1f}" for t in w["T_v"]) + " C)")
    print("  deformation index of the tread at q = k pi/a (ISO point): "
          + "; ".join(f"k={k}: c_t {ct:.2e}, c_b {cb:.2e} m/Pa, n = {n:.2f}"
                      for k, ct, cb, n in w["index"]))
    if args.rolling:
        print(f"({time.perf_counter() - t0:.0f} s)")
        return 0
    mpd = (0.7 - 0.2) / 0.8
    sp = 14.2 + 89.7 * mpd
    print(f"wet locked wheel Fx/Fz at 20 / 60 / 100 km/h (r117_wet, MPD {mpd:.3f} mm: PIARC "
          f"Sp = {sp:.0f} km/h, exp(-80/Sp) = {math.exp(-80 / sp):.2f})")
    for row in wet_speed_report([5.0, 20.0, 35.0]):
        print(f"  {row['depth_mm']:.0f} mm, {row['T_C']:4.0f} C: "
              + " / ".join(f"{m:.3f}" for m in row["mu"])
              + f"   mu(100)/mu(20) = {row['ratio']:.3f}   [wet: at most 0.75]")
    rows = wet_grip_report(temps)
    print("wet grip test (passenger vs SRTT, 1 mm water)")
    for row in rows:
        print(f"  {row['T_C']:4.0f} C: BFC {row['bfc']:.3f}, SRTT BFC {row['bfc_ref']:.3f} "
              f"peak {row['peak_ref']:.3f}, G {row['G']:.3f} ({row['class']}), in windows "
              f"{row['in_windows']}, notes {row['notes']}")
    T = np.array([row["T_C"] for row in rows])
    for key in ("bfc", "bfc_ref"):
        slope = np.polyfit(T, [row[key] for row in rows], 1)[0]
        print(f"  d{key}/dT over {T[0]:g}-{T[-1]:g} C: {slope:+.5f} per K   [-0.006 .. 0]")
    from tire_brush.braking.wet_grip_test import load_wet_grip_spec
    from tire_brush.hydroplaning import gallaway_speed
    from tire_brush.params import load_tire

    spec = load_wet_grip_spec()
    film = spec.water_depth - spec.texture_depth
    vps = {n: 3.6 * gallaway_speed(film, load_tire(n).patch.p_inflation,
                                   spec.tire_entry(n).tread_depth, spec.texture_depth)
           for n in ("passenger", spec.reference_tire)}
    print("study option: partial lift of the entering film, (V/V_p)^2 with Gallaway's V_p "
          f"(film {film * 1e3:.1f} mm above the texture: V_p "
          + ", ".join(f"{n} {v:.0f} km/h" for n, v in vps.items()) + ")")
    for row in wet_speed_report([5.0, 20.0, 35.0], partial_lift=True, dry=False):
        print(f"  locked, {row['T_C']:4.0f} C: " + " / ".join(f"{m:.3f}" for m in row["mu"])
              + f"   mu(100)/mu(20) = {row['ratio']:.3f}")
    for row in wet_grip_report([5.0, 20.0, 35.0], partial_lift=True):
        print(f"  {row['T_C']:4.0f} C: BFC {row['bfc']:.3f}, SRTT BFC {row['bfc_ref']:.3f} "
              f"peak {row['peak_ref']:.3f}, G {row['G']:.3f} ({row['class']}), in windows "
              f"{row['in_windows']}")
    print(f"({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
