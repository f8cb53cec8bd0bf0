"""The ``tirefric`` command line: a thin shell over the library.

Sub-commands register themselves through the entry-point group ``tirefric.commands``
(``pyproject.toml``); each entry is a function ``register(subparsers)`` that adds one
sub-parser and sets its ``func(args) -> int``. This keeps ``lookup`` (upstream) free of imports
from ``tire_brush`` and ``fmu_src`` (downstream).

Errors from bad input (:class:`~lookup.errors.InputError`, :class:`~lookup.errors.GridError`)
are printed as one clear message and the command exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from importlib.metadata import entry_points

from .errors import InputError, TirefricError


def parse_float_list(text: str, option: str) -> list[float]:
    """Parse ``"1e-3,0.01,1"`` into floats; NaN/inf and junk are input errors naming the option."""
    out = []
    for part in text.split(","):
        try:
            x = float(part)
        except ValueError:
            raise InputError("not a number", source=option, value=part) from None
        if not math.isfinite(x):
            raise InputError("must be a finite number", source=option, value=part)
        out.append(x)
    return out


def parse_float(text: str, option: str) -> float:
    """Parse one finite float for ``option``."""
    vals = parse_float_list(text, option)
    if len(vals) != 1:
        raise InputError("expected one number", source=option, value=text)
    return vals[0]


def print_table(rows: list[dict], keys: Sequence[str]) -> None:
    """Print rows as an aligned text table with the given column keys."""
    print("  ".join(f"{k:>13s}" for k in keys))
    for r in rows:
        print("  ".join(f"{r[k]:13.6g}" if isinstance(r[k], float | int) else f"{r[k]!s:>13s}"
                        for k in keys))


def dump_json(obj: object) -> None:
    """Print ``obj`` as indented JSON on stdout."""
    json.dump(obj, sys.stdout, indent=2)
    sys.stdout.write("\n")


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
    p.add_argument("--T", required=True, help="background temperature [Celsius]")
    p.add_argument("--p", required=True, help="nominal contact pressure [Pa]")
    p.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
    p.set_defaults(func=_run_mu)


def _run_mu(args: argparse.Namespace) -> int:
    from .compound import load_compound
    from .friction import PerssonFriction
    from .surface import load_surface

    v = parse_float_list(args.v, "--v")
    T_C = parse_float(args.T, "--T")
    p = parse_float(args.p, "--p")
    if any(x <= 0 for x in v):
        raise InputError("slip speeds must be > 0 m/s", source="--v", value=args.v)
    if p <= 0:
        raise InputError("nominal pressure must be > 0 Pa", source="--p", value=args.p)
    if T_C <= -273.15:
        raise InputError("temperature below absolute zero", source="--T", value=args.T)
    model = PerssonFriction(load_compound(args.compound), load_surface(args.surface))
    columns = model.mu_table(v, T_C + 273.15, p)
    rows = [{k: float(c[i]) for k, c in zip(MU_KEYS, columns, strict=True)}
            for i in range(len(v))]
    if args.json:
        dump_json({"compound": model.compound.name, "surface": model.surface.name,
                   "T_C": T_C, "p_Pa": p, "q1_per_m": model.q1, "points": rows,
                   "hot_residual_K": model.last_hot_residual})
    else:
        print(f"# compound {model.compound.name}, surface {model.surface.name}, T = {T_C:g} C, "
              f"p = {p:g} Pa, q1 = {model.q1:.4g} 1/m")
        print_table(rows, MU_KEYS)
    return 0


# -- tirefric plot ------------------------------------------------------------------------------
def register_plot(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric plot friction|compound|surface``."""
    p = sub.add_parser("plot", help="plots of friction, compounds and surfaces")
    kinds = p.add_subparsers(dest="what", required=True, metavar="WHAT")
    f = kinds.add_parser("friction", help="mu(v) cold and hot, flash temperature, A/A0 vs v")
    f.add_argument("--compound", required=True, help="compound TOML file or shipped name")
    f.add_argument("--surface", required=True, help="surface TOML file or shipped name")
    f.add_argument("--T", default="0,20,50,80", help="temperatures [Celsius], comma separated")
    f.add_argument("--p", default="3e5", help="nominal contact pressure [Pa]")
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
        p = parse_float(args.p, "--p")
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


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every registered sub-command."""
    parser = argparse.ArgumentParser(
        prog="tirefric",
        description="Physics-based tire friction (Persson theory) -> grids -> brush tire -> FMU.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for ep in sorted(entry_points(group="tirefric.commands"), key=lambda e: e.name):
        try:
            register = ep.load()
        except ModuleNotFoundError as exc:
            # A sub-command whose module is not part of this installation is left out; any
            # other import failure inside an existing module is a bug and propagates.
            if exc.name and ep.module.startswith(exc.name):
                continue
            raise
        register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``tirefric``; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except TirefricError as exc:
        print(f"tirefric {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
