"""``tirefric mu`` and ``tirefric plot``: the friction engine's commands, a thin shell over it.

They register with the root parser (:mod:`tirefric.cli`) through the entry points
``tirefric.commands`` in ``pyproject.toml``.
"""

from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

from tirefric.cli import (
    dump_json,
    parse_float,
    parse_float_list,
    parse_quantity_option,
    parse_temperature_option,
    print_table,
)
from tirefric.errors import ExtrapolationWarning, InputError


def add_engine_options(p: argparse.ArgumentParser) -> None:
    """Options for :class:`lookup.friction.EngineSettings` (resolution, gamma, area law)."""
    g = p.add_argument_group("engine settings (lookup.friction.EngineSettings)")
    g.add_argument("--q-per-decade", type=int, default=None,
                   help="wavenumber nodes per decade (default 24; 96 for a converged check)")
    g.add_argument("--n-phi", type=int, default=None,
                   help="Gauss-Legendre nodes of the angular integrals (default 16)")
    g.add_argument("--modulus-per-decade", type=int, default=None,
                   help="master-curve samples per decade (default 40)")
    g.add_argument("--gamma", default=None, help="gamma of review eq. (20) (default 0.5)")
    g.add_argument("--contact-area", default=None, choices=("persson", "rescaled_kappa"),
                   help="contact-area law: persson (eq. 18, default) or rescaled_kappa "
                        "(small-contact slope --area-kappa, review after eq. 11)")
    g.add_argument("--area-kappa", default=None,
                   help="slope kappa for --contact-area rescaled_kappa (default 2)")


def engine_settings(args: argparse.Namespace):
    """:class:`~lookup.friction.EngineSettings` from the options of :func:`add_engine_options`."""
    from .friction import EngineSettings

    kw: dict = {}
    for name in ("q_per_decade", "n_phi", "modulus_per_decade", "contact_area"):
        if getattr(args, name, None) is not None:
            kw[name] = getattr(args, name)
    for name in ("gamma", "area_kappa"):
        if getattr(args, name, None) is not None:
            kw[name] = parse_float(getattr(args, name), "--" + name.replace("_", "-"))
    try:
        return EngineSettings(**kw)
    except InputError as exc:
        opt = "--" + (exc.field or "").removeprefix("engine.").replace("_", "-")
        raise InputError(exc.message, source=opt, value=exc.value) from None


# -- tirefric mu ------------------------------------------------------------------------------
MU_KEYS = ("v", "mu_cold", "mu_hot", "mu_visc_cold", "mu_cont_cold", "area_cold", "area_hot",
           "dT_flash")


def register_mu(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric mu``."""
    p = sub.add_parser("mu", help="steady-sliding friction, cold and hot branch (Persson)",
                       description="Persson steady-sliding friction mu(v) at one temperature "
                                   "and nominal pressure: cold branch (no flash heating) and "
                                   "hot branch (self-consistent flash temperature).")
    p.add_argument("--compound", required=True, help="compound TOML file or shipped name")
    p.add_argument("--surface", required=True, help="surface TOML file or shipped name")
    p.add_argument("--v", required=True, help="slip speed(s) [m/s], comma separated")
    p.add_argument("--T", required=True,
                   help="background temperature: a bare number is Celsius, or with a unit "
                        "('293.15 K', '20 degC')")
    p.add_argument("--p", required=True,
                   help="nominal contact pressure: a bare number is Pa, or with a unit "
                        "('0.3 MPa', '300 kPa')")
    p.add_argument("--branch", choices=("both", "cold", "hot"), default="both",
                   help="which branch to solve (default both; 'cold' needs no [thermal] "
                        "or [macroasperity] data and skips the flash-temperature solve)")
    p.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
    w = p.add_argument_group("wet road (lookup.wet): dry and wet side by side")
    w.add_argument("--water", default=None,
                   help="water film depth: a bare number is m, or with a unit ('1 mm'); "
                        "0 = dry. Adds mu_wet_cold, mu_wet_hot (sliding block: the "
                        "squeeze-out time is D/v)")
    w.add_argument("--lubricant", default="water",
                   help="water (default), soapy_water, or custom (with --eta)")
    w.add_argument("--eta", default=None, help="viscosity of a custom lubricant [Pa s]")
    add_engine_options(p)
    p.set_defaults(func=_run_mu)


def _run_mu(args: argparse.Namespace) -> int:
    from .compound import load_compound
    from .friction import OUTSIDE_WARNING_SHARE, PerssonFriction
    from .surface import load_surface

    v = parse_float_list(args.v, "--v")
    T = parse_temperature_option(args.T, "--T")
    T_C = T - 273.15
    p = parse_quantity_option(args.p, "--p", "pressure", "Pa")
    if any(x <= 0 for x in v):
        raise InputError("slip speeds must be > 0 m/s", source="--v", value=args.v)
    if p <= 0:
        raise InputError("nominal pressure must be > 0 Pa", source="--p", value=args.p)
    model = PerssonFriction(load_compound(args.compound), load_surface(args.surface),
                            engine_settings(args))
    va = np.asarray(v, float)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ExtrapolationWarning)
        if args.branch == "both":
            c, h = model.cold_and_hot(va, T, p)
            columns = (va, c.mu, h.mu, c.mu_visc, c.mu_cont, c.area, h.area, h.dT_flash)
            keys = MU_KEYS
            shares = {"outside_cold": c.outside, "outside_hot": h.outside}
        else:
            r = (model.cold if args.branch == "cold" else model.hot)(va, T, p)
            b = args.branch
            columns = (va, r.mu, r.mu_visc, r.mu_cont, r.area) + (
                (r.dT_flash,) if b == "hot" else ())
            keys = ("v", f"mu_{b}", f"mu_visc_{b}", f"mu_cont_{b}", f"area_{b}") + (
                ("dT_flash",) if b == "hot" else ())
            shares = {f"outside_{b}": r.outside}
    notes = [str(w.message) for w in caught if issubclass(w.category, ExtrapolationWarning)]
    for w in caught:  # anything else goes on as it came
        if not issubclass(w.category, ExtrapolationWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    rows = [{k: float(c[i]) for k, c in zip(keys, columns, strict=True)}
            for i in range(len(v))]
    band = model.band
    if args.json or band is not None:  # a tabulated curve: the shares are columns too
        for i, row in enumerate(rows):
            row.update({k: float(a[i]) for k, a in shares.items()})
        if band is not None:
            keys = tuple(keys) + tuple(shares)
    wet_desc = None
    if args.water is not None or args.eta is not None or args.lubricant != "water":
        wet_desc, wet_cols = _wet_columns(args, model, v, T, p)
        for i, row in enumerate(rows):
            row.update({k: float(c[i]) for k, c in wet_cols.items()})
        keys = tuple(keys) + tuple(wet_cols)
    freq = model.compound.modulus.describe().get("frequency_column")
    if args.json:
        out = {"compound": model.compound.name, "surface": model.surface.name,
               "T_C": T_C, "p_Pa": p, "q1_per_m": model.q1, "branch": args.branch,
               "settings": {k: getattr(model.settings, k) for k in
                            ("q_per_decade", "n_phi", "modulus_per_decade", "gamma",
                             "contact_area", "area_kappa")},
               "points": rows}
        if args.branch != "cold":
            out["hot_residual_K"] = model.last_hot_residual
        if freq:
            out["master_curve_frequency_column"] = freq
        out["measured_band_rad_s"] = (None if band is None
                                      else [10.0 ** band[0], 10.0 ** band[1]])
        out["outside_warning_share"] = OUTSIDE_WARNING_SHARE
        out["warnings"] = notes
        if wet_desc is not None:
            out["wet"] = wet_desc
        dump_json(out)
        for note in notes:
            print(f"tirefric mu: warning: {note}", file=sys.stderr)
    else:
        print(f"# compound {model.compound.name}, surface {model.surface.name}, T = {T_C:g} C, "
              f"p = {p:g} Pa, q1 = {model.q1:.4g} 1/m")
        if freq:
            print(f"# master curve frequency column: {freq}")
        if band is not None:
            print(f"# measured master curve: {10.0 ** band[0]:.4g}..{10.0 ** band[1]:.4g} "
                  "rad/s at T_ref; outside_*: share of each result's integrand from outside "
                  "it (docs/engine-inputs.md)")
        for note in notes:
            print(f"# warning: {note}")
        if wet_desc is not None:
            print(f"# wet: water film {wet_desc['water_depth_m']:g} m, lubricant "
                  f"{wet_desc['lubricant']['name']}, squeeze-out time D/v (sliding block)")
        print_table(rows, keys)
    return 0


def _wet_columns(args: argparse.Namespace, model, v: list[float], T: float, p: float
                 ) -> tuple[dict, dict[str, np.ndarray]]:
    """mu_wet_cold, mu_wet_hot (and the dry share) for ``tirefric mu --water``."""
    from .wet.friction import WetPerssonFriction
    from .wet.water import Lubricant

    if args.water is None:
        raise InputError("--lubricant/--eta need the water film depth --water", source="--water")
    import re

    text = re.sub(r"^\s*([-+0-9.eE]+?)\s*([a-zA-Z]+)\s*$", r"\1 \2", args.water)  # 1mm
    depth = parse_quantity_option(text, "--water", "length", "m")
    if depth < 0:
        raise InputError("water film depth must be >= 0 (0 = dry)", source="--water",
                         field="water_depth", value=args.water)
    eta = None if args.eta is None else parse_float(args.eta, "--eta")
    try:
        lub = Lubricant(args.lubricant, eta=eta)
    except InputError as exc:
        raise InputError(exc.message, source="--lubricant" if exc.field == "wet.lubricant"
                         else "--eta", field=exc.field, value=exc.value) from None
    wet = WetPerssonFriction(model.compound, model.surface, model.settings, depths=(depth,),
                             lubricant=lub)
    va = np.asarray(v, float)
    cols: dict[str, np.ndarray] = {}
    b = args.branch
    if b in ("both", "cold"):
        c = wet.cold(va, T, p)
        cols.update(mu_wet_cold=c.mu, mu_visc_wet_cold=c.mu_visc, w_dry=wet.last_w.copy())
    if b in ("both", "hot"):
        cols["mu_wet_hot"] = wet.hot(va, T, p).mu
    return {"water_depth_m": depth, "lubricant": lub.describe(),
            "sealing": wet.sealed.describe()}, cols


# -- tirefric plot ------------------------------------------------------------------------------
def register_plot(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric plot friction|compound|surface``."""
    p = sub.add_parser("plot", help="plots of friction, compounds and surfaces")
    kinds = p.add_subparsers(dest="what", required=True, metavar="WHAT")
    f = kinds.add_parser("friction", help="mu(v) cold and hot, flash temperature, A/A0 vs v")
    f.add_argument("--compound", required=True, help="compound TOML file or shipped name")
    f.add_argument("--surface", required=True, help="surface TOML file or shipped name")
    f.add_argument("--T", default="0,20,50,80", help="temperatures [Celsius], comma separated")
    f.add_argument("--p", default="3e5",
                   help="nominal contact pressure: a bare number is Pa, or '0.3 MPa'")
    f.add_argument("-o", "--output", required=True, help="PNG file")
    c = kinds.add_parser("compound", help="E', E'' and tan delta of a compound")
    c.add_argument("compound", help="compound TOML file or shipped name")
    c.add_argument("--T", default="20", help="temperatures [Celsius], comma separated")
    c.add_argument("-o", "--output", required=True, help="PNG file")
    s = kinds.add_parser("surface", help="C(q) and rms slope of a surface")
    s.add_argument("surface", help="surface TOML file or shipped name")
    s.add_argument("-o", "--output", required=True, help="PNG file")
    p.set_defaults(func=_run_plot)


def _run_plot(args: argparse.Namespace) -> int:
    from . import plots
    from .compound import load_compound
    from .friction import PerssonFriction
    from .surface import load_surface

    if args.what == "friction":
        p = parse_quantity_option(args.p, "--p", "pressure", "Pa")
        if p <= 0:
            raise InputError("nominal pressure must be > 0 Pa", source="--p", value=args.p)
        model = PerssonFriction(load_compound(args.compound), load_surface(args.surface))
        out = plots.plot_friction(model, parse_float_list(args.T, "--T"), p, args.output)
    elif args.what == "compound":
        out = plots.plot_compound(load_compound(args.compound), args.output,
                                  parse_float_list(args.T, "--T"))
    else:
        out = plots.plot_surface(load_surface(args.surface), args.output)
    print(f"wrote {out}")
    return 0
