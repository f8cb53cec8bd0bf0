"""``tirefric rolling cylinder|sphere|wedge``: a thin shell over :mod:`lookup.rolling`.

Prints the rolling (or lubricated-sliding, for the wedge) friction coefficient mu(v) at one or
more temperatures as a table or JSON, and optionally plots the rolling-friction master curve.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from scipy.optimize import brentq

from tirefric.cli import (
    dump_json,
    parse_float,
    parse_float_list,
    parse_temperature_option,
    print_table,
)
from tirefric.errors import InputError

#: Plot speeds when --v gives fewer than two values [m/s].
PLOT_V_DEFAULT = (1e-9, 1e2)


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric rolling``."""
    p = sub.add_parser("rolling", help="rolling friction of a cylinder, sphere or wedge "
                                       "(review sec. 6-7)",
                       description="Viscoelastic rolling friction from the compound's master "
                                   "curve: hard cylinder (review eqs. 30-31), sphere (eqs. "
                                   "32-33) or lubricated wedge (sec. 7), no adhesion, no "
                                   "heating.")
    kinds = p.add_subparsers(dest="geometry", required=True, metavar="GEOMETRY")
    specs = {"cylinder": ("hard cylinder, load per unit length", "N/m"),
             "sphere": ("hard sphere", "N"),
             "wedge": ("rigid wedge (lubricated sliding), load per unit length", "N/m")}
    for name, (what, unit) in specs.items():
        k = kinds.add_parser(name, help=what)
        k.add_argument("--compound", required=True, help="compound TOML file or shipped name")
        if name == "wedge":
            k.add_argument("--angle-deg", required=True,
                           help="half-opening angle of the wedge [deg], in (0, 90)")
        else:
            k.add_argument("--radius", required=True, help=f"{name} radius [m]")
        k.add_argument("--load", required=True, help=f"normal load [{unit}]")
        k.add_argument("--v", required=True, help="rolling speed(s) [m/s], comma separated")
        k.add_argument("--T", required=True,
                       help="temperature(s), comma separated: a bare number is Celsius, or "
                            "with a unit ('293.15 K')")
        k.add_argument("--strain", default=None,
                       help="strain for the softening factors (default: the compound's own; "
                            "for the wedge 1/(2 tan alpha), review sec. 7)")
        k.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
        k.add_argument("--plot", default=None, metavar="FILE.png",
                       help="plot mu against log10 v at each --T and shifted with a_T")
    p.set_defaults(func=_run)


def _positive(text: str, option: str, what: str) -> float:
    x = parse_float(text, option)
    if not x > 0:
        raise InputError(f"{what} must be > 0", source=option, value=text)
    return x


def _geometry(args: argparse.Namespace):
    """(mu(v, modulus), size(v, modulus), strain, description) for the chosen geometry."""
    from . import rolling as r

    load = _positive(args.load, "--load", "the load")
    if args.geometry == "wedge":
        deg = parse_float(args.angle_deg, "--angle-deg")
        if not 0.0 < deg < 90.0:
            raise InputError("half-opening angle must lie strictly between 0 and 90 deg",
                             source="--angle-deg", value=args.angle_deg)
        alpha = math.radians(deg)
        strain = r.wedge_strain(alpha)

        def size_of_E(E):
            return r.wedge_half_width(load, alpha, E)

        def mu(v, m):
            return r.mu_wedge(load, alpha, v, m)

        desc = {"geometry": "wedge", "angle_deg": deg, "load_N_per_m": load}
        size_name = "a_m"
    else:
        R = _positive(args.radius, "--radius", "the radius")
        strain = None
        if args.geometry == "cylinder":
            def size_of_E(E):
                return r.cylinder_half_width(load, R, E)

            def mu(v, m):
                return r.mu_cylinder(load, R, v, m)

            desc = {"geometry": "cylinder", "radius_m": R, "load_N_per_m": load}
            size_name = "a_m"
        else:
            def size_of_E(E):
                return r.sphere_contact_radius(load, R, E)

            def mu(v, m):
                return r.mu_sphere(load, R, v, m)

            desc = {"geometry": "sphere", "radius_m": R, "load_N": load}
            size_name = "r_c_m"
    if args.strain is not None:
        strain = _positive(args.strain, "--strain", "the strain")
    return mu, size_of_E, strain, desc, size_name


def characteristic_size(size_of_E, v: float, modulus) -> float:
    """Contact size s with s = size(|E_eff(v / s)|): the width the rubber shows to a
    deformation of duration ~ s/v (a diagnostic; mu itself uses |E_eff(q v)| per q)."""
    E_lo, E_hi = modulus.magnitude_range()
    lo, hi = float(size_of_E(E_hi)), float(size_of_E(E_lo))
    if hi <= lo * (1 + 1e-12):
        return hi

    def f(ls: float) -> float:
        s = math.exp(ls)
        return ls - math.log(float(size_of_E(modulus.magnitude(np.array(v / s)))))

    return math.exp(brentq(f, math.log(lo) - 1e-9, math.log(hi) + 1e-9, xtol=1e-12))


def _run(args: argparse.Namespace) -> int:
    from .compound import load_compound
    from .rolling import EffectiveModulus

    v = parse_float_list(args.v, "--v")
    if any(x <= 0 for x in v):
        raise InputError("rolling speeds must be > 0 m/s", source="--v", value=args.v)
    temps = [parse_temperature_option(t, "--T") for t in args.T.split(",")]
    mu, size_of_E, strain, desc, size_name = _geometry(args)
    compound = load_compound(args.compound)
    rows = []
    for T in temps:
        m = EffectiveModulus(compound, T, strain)
        mus = mu(np.asarray(v), m)
        for vi, mi in zip(v, mus, strict=True):
            rows.append({"T_C": T - 273.15, "v": vi, "mu": float(mi),
                         size_name: characteristic_size(size_of_E, vi, m)})
    used_strain = compound.strain if strain is None else strain
    if args.json:
        dump_json({"compound": compound.name, **desc, "strain": used_strain,
                   "contact_size": "mu uses the size at |E_eff(q v)| per wavenumber (review "
                                   "after eqs. 31, 33 and sec. 7); the column is the size at "
                                   "|E_eff(v / size)|", "points": rows})
    else:
        extra = ", ".join(f"{k} = {val:g}" for k, val in desc.items() if k != "geometry")
        print(f"# rolling {desc['geometry']}, compound {compound.name}, {extra}, "
              f"strain = {used_strain:g}")
        print_table(rows, ("T_C", "v", "mu", size_name))
    if args.plot:
        from .plots import plot_rolling

        span = (min(v), max(v)) if len(v) >= 2 and min(v) < max(v) else PLOT_V_DEFAULT
        vv = np.logspace(np.log10(span[0]), np.log10(span[1]), 61)
        out = plot_rolling(compound, [T - 273.15 for T in temps], vv,
                           lambda vs, T: mu(vs, EffectiveModulus(compound, T, strain)),
                           f"{desc['geometry']}, {compound.name}", args.plot)
        print(f"wrote {out}")
    return 0
