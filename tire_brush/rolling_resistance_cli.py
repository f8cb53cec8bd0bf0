"""``tirefric tire rolling-resistance``: ISO 28580 numbers and a speed/load/temperature table.

The model is :mod:`tire_brush.rolling_resistance` (review eq. 29 through the tread layer plus the
carcass deflection-energy term; docs/rolling.md). Registered under ``tirefric tire`` by
:func:`add_parser`; :func:`main` runs it.
"""

from __future__ import annotations

import argparse

import numpy as np

from tirefric.cli import dump_json, parse_float_list, print_table

KEYS = ("V_kmh", "Fz_N", "T_C", "rrc_N_per_kN", "F_r_N", "My_Nm", "heat_W", "tread_share")


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Add ``rolling-resistance`` to the sub-commands of ``tirefric tire``."""
    p = subparsers.add_parser(
        "rolling-resistance", help="rolling resistance: ISO 28580 coefficient, EU label "
                                   "class, speed/load/temperature table",
        description="Rolling resistance of the brush tire from the tread compound's loss "
                    "(review eq. 29 through the tread layer) and a carcass deflection-energy "
                    "term (docs/rolling.md): the coefficient at the ISO 28580 conditions "
                    "(80 km/h, 25 C, 80 % of the load-index load, ISO inflation), its EU "
                    "label class and change per K, and a table over speed, load and "
                    "temperature at the tire file's inflation pressure.")
    p.add_argument("--tire", default="passenger",
                   help="tire TOML file or shipped name (default passenger); needs a "
                        "[rolling_resistance] table")
    p.add_argument("--compound", default="summer",
                   help="tread compound TOML file or shipped name (default summer)")
    p.add_argument("--speeds-kmh", default="20,50,80,120,150",
                   help="rolling speeds of the table [km/h] (default 20,50,80,120,150)")
    p.add_argument("--loads", default="0.5,0.8,1.0,1.2",
                   help="loads of the table as multiples of the load-index load (default "
                        "0.5,0.8,1.0,1.2)")
    p.add_argument("--T", default="0,25,50,80",
                   help="tread temperatures of the table [Celsius] (default 0,25,50,80)")
    p.add_argument("--json", action="store_true",
                   help="print JSON: 'iso' and a list 'points'")
    p.set_defaults(func=main)
    return p


def main(args: argparse.Namespace) -> int:
    """Run ``tirefric tire rolling-resistance``; returns the exit code."""
    from lookup.compound import load_compound
    from tirefric.errors import InputError

    from .params import load_tire
    from .rolling_resistance import iso28580, load_rolling_params, rolling_resistance

    tire = load_tire(args.tire)
    compound = load_compound(args.compound)
    rr = load_rolling_params(tire)
    speeds = np.array(parse_float_list(args.speeds_kmh, "--speeds-kmh"))
    shares = np.array(parse_float_list(args.loads, "--loads"))
    temps = np.array(parse_float_list(args.T, "--T"))
    if (speeds < 0).any() or (shares < 0).any():
        raise InputError("speeds and loads must be >= 0", source="--speeds-kmh/--loads")
    if not rr.load_index_load > 0:
        raise InputError("the tire file gives no load_index_load", source=tire.source,
                         field="rolling_resistance.load_index_load")
    iso = iso28580(tire, compound, rr=rr)
    V, F, T = np.meshgrid(speeds / 3.6, shares * rr.load_index_load, temps + 273.15,
                          indexing="ij")
    res = rolling_resistance(tire, compound, V, F, T, rr=rr)
    rows = [{"V_kmh": float(v * 3.6), "Fz_N": float(f), "T_C": float(t - 273.15),
             "rrc_N_per_kN": float(1000 * fr), "F_r_N": float(Fr), "My_Nm": float(my),
             "heat_W": float(q), "tread_share": float(s)}
            for v, f, t, fr, Fr, my, q, s in zip(V.ravel(), F.ravel(), T.ravel(),
                                                  res.f_r.ravel(), res.F_r.ravel(),
                                                  res.My.ravel(), res.heat_rate.ravel(),
                                                  res.tread_share.ravel(), strict=True)]
    iso_d = iso.as_dict()
    iso_d.update(size=rr.size, load_index=rr.load_index, load_index_load_N=rr.load_index_load,
                 per_K_iso28580=-0.008)
    if args.json:
        dump_json({"tire": tire.name, "compound": compound.name, "iso": iso_d,
                   "table_inflation_Pa": tire.patch.p_inflation, "points": rows})
        return 0
    print(f"tire {tire.name} ({rr.size}), compound {compound.name}")
    print(f"ISO 28580: {iso.speed_m_s * 3.6:.0f} km/h, {iso.T_K - 273.15:.0f} C ambient, "
          f"Fz = {iso.load_N:.0f} N (80 % of {rr.load_index_load:.0f} N, LI "
          f"{rr.load_index}), {iso.inflation_Pa / 1e3:.0f} kPa")
    print(f"  RRC = {iso.rrc_N_per_kN:.2f} N/kN, EU label class {iso.label_class}, "
          f"tread share {iso.tread_share:.3f}, at the thermal equilibrium: tread "
          f"{iso.T_tire_K - 273.15:.1f} C")
    print(f"  change per K of the ambient (20-30 C): {100 * iso.per_K:+.2f} %/K; isothermal "
          f"at {iso.T_K - 273.15:.0f} C: {100 * iso.per_K_isothermal:+.2f} %/K "
          f"(ISO 28580 temperature correction: -0.80 %/K)")
    print(f"table at {tire.patch.p_inflation / 1e3:.0f} kPa (My in ISO-W, forward rolling):")
    print_table(rows, KEYS)
    return 0
