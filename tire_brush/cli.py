"""``tirefric tire``: steady-state brush-tire curves from the command line (a thin shell).

``tirefric tire curve --tire FILE_OR_NAME --grid GRID --Fz N --vx M_S --T CELSIUS
(--kappa A:B:N | --alpha-deg A:B:N) [--json] [--plot FILE.png]`` sweeps the longitudinal slip
or the slip angle (``A:B:N``: N equally spaced values from A to B) at one load, speed and
background temperature and prints the forces; ``--json`` prints a list ``points`` with keys
``kappa``, ``alpha`` [rad], ``Fx``, ``Fy`` [N], ``Mz`` [N m], ``mu_eff``, ``mu_slide``,
``sliding_fraction`` and ``dT_flash_max`` [K].

``--grid`` takes a grid file or shipped grid name (``default``), or ``constant:MU`` /
``constant:MU_COLD,MU_HOT`` for flat friction (e.g. to compare with Pacejka's brush).
A range starting with a minus sign needs ``=``: ``--kappa=-0.3:0:31`` (argparse would read
``-0.3:0:31`` as an option). ``--axes`` (default ``adapted-sae``, the brush model's own) names
the sign convention of the slip angle given and of the forces printed
(:mod:`tire_brush.axes`; ``iso-v`` is ISO-W at zero steer angle).
"""

from __future__ import annotations

import argparse

import numpy as np

from lookup.cli import dump_json, parse_float, parse_float_list, print_table
from lookup.errors import InputError

from .axes import AXES, BRUSH_AXES, SlipInputs, Wrench, convert_inputs, convert_wrench

KEYS = ("kappa", "alpha", "Fx", "Fy", "Mz", "mu_eff", "mu_slide", "sliding_fraction",
        "dT_flash_max")


def parse_range(text: str, option: str) -> np.ndarray:
    """Parse ``A:B:N`` into N equally spaced values from A to B (N >= 1)."""
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError("expected A:B:N (N values from A to B)", source=option, value=text)
    lo = parse_float(parts[0], option)
    hi = parse_float(parts[1], option)
    try:
        n = int(parts[2])
    except ValueError:
        raise InputError("N must be an integer", source=option, value=text) from None
    if not 1 <= n <= 100000:
        raise InputError("N must lie in 1..100000", source=option, value=text)
    return np.linspace(lo, hi, n)


def load_friction(spec: str):
    """A friction provider for ``--grid``: ``constant:MU[,MU_HOT]``, or a grid name/file."""
    from .friction import ConstantFriction, GridFriction

    if spec.startswith("constant:"):
        vals = parse_float_list(spec.split(":", 1)[1], "--grid")
        if not 1 <= len(vals) <= 2 or min(vals) < 0:
            raise InputError("expected constant:MU or constant:MU_COLD,MU_HOT with mu >= 0",
                             source="--grid", value=spec)
        return ConstantFriction(*vals)
    from lookup.grid import load_grid

    return GridFriction(load_grid(spec))


def register(sub: argparse._SubParsersAction) -> None:
    """Register ``tirefric tire`` and its sub-commands."""
    t = sub.add_parser("tire", help="brush tire on a friction grid (steady-state curves)",
                       description="Brush tire model with cold/hot friction blending "
                                   "(review eq. 28) on a friction grid.")
    ts = t.add_subparsers(dest="tire_command", required=True, metavar="TIRE_COMMAND")
    c = ts.add_parser("curve", help="steady-state force curve over slip or slip angle",
                      description="Steady-state Fx, Fy, Mz, friction and sliding fraction "
                                  "over a sweep of longitudinal slip or slip angle.")
    c.add_argument("--tire", required=True, help="tire TOML file or shipped name (passenger)")
    c.add_argument("--grid", required=True,
                   help="grid file, shipped grid name (default), or constant:MU[,MU_HOT]")
    c.add_argument("--Fz", required=True, help="vertical load [N]")
    c.add_argument("--vx", required=True, help="forward speed [m/s] (> 0)")
    c.add_argument("--T", required=True, help="background temperature [Celsius]")
    sweep = c.add_mutually_exclusive_group(required=True)
    sweep.add_argument("--kappa", help="longitudinal slip sweep A:B:N (slip angle 0); "
                                       "negative start: --kappa=-0.3:0:31")
    sweep.add_argument("--alpha-deg", help="slip-angle sweep A:B:N [deg] (slip 0); "
                                           "negative start: --alpha-deg=-10:10:21")
    c.add_argument("--n-elements", type=int, default=None,
                   help="cells along the patch (default: the steady model's default)")
    c.add_argument("--axes", choices=AXES, default=BRUSH_AXES,
                   help="sign convention of --alpha-deg and of the printed forces (default "
                        "adapted-sae, the brush model's; iso-v = iso-w at zero steer angle)")
    c.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
    c.add_argument("--plot", metavar="FILE.png", help="write a plot of the curve")
    c.set_defaults(func=_run_curve)


def _run_curve(args: argparse.Namespace) -> int:
    from .params import load_tire
    from .steady import N_STEADY, SteadyBrush

    Fz = parse_float(args.Fz, "--Fz")
    vx = parse_float(args.vx, "--vx")
    T_C = parse_float(args.T, "--T")
    if Fz < 0:
        raise InputError("vertical load must be >= 0 N", source="--Fz", value=args.Fz)
    if vx <= 0:
        raise InputError("forward speed must be > 0 m/s", source="--vx", value=args.vx)
    if T_C <= -273.15:
        raise InputError("temperature below absolute zero", source="--T", value=args.T)
    if args.kappa is not None:
        kappa = parse_range(args.kappa, "--kappa")
        if (kappa <= -1).any():
            raise InputError("slip must be > -1 (kappa = -1 is a locked wheel; use "
                             "-0.999...)", source="--kappa", value=args.kappa)
        alpha = np.zeros_like(kappa)
    else:
        alpha_deg = parse_range(args.alpha_deg, "--alpha-deg")
        if (np.abs(alpha_deg) >= 90).any():
            raise InputError("slip angle must lie in (-90, 90) deg", source="--alpha-deg",
                             value=args.alpha_deg)
        alpha = np.radians(alpha_deg)
        kappa = np.zeros_like(alpha)
    n = N_STEADY if args.n_elements is None else args.n_elements
    tire = load_tire(args.tire)
    friction = load_friction(args.grid)
    model = SteadyBrush(tire, friction, n_elements=n)
    # the slip angle is given in --axes; the brush works in its own convention
    alpha_brush = convert_inputs(SlipInputs(kappa, alpha, vx, 0.0), args.axes, BRUSH_AXES).alpha
    out = model.solve(kappa, alpha_brush, vx, Fz, T_C + 273.15)
    w = convert_wrench(Wrench(out.Fx, out.Fy, Fz, 0.0, 0.0, out.Mz), BRUSH_AXES, args.axes)
    values = {k: np.asarray(getattr(out, k)) for k in KEYS}
    values.update(alpha=np.broadcast_to(alpha, kappa.shape), Fx=np.asarray(w.Fx),
                  Fy=np.asarray(w.Fy), Mz=np.asarray(w.Mz))
    rows = [{k: float(values[k][i]) for k in KEYS} for i in range(kappa.size)]
    if args.plot:
        _plot(args.plot, rows, "kappa" if args.kappa is not None else "alpha", tire.name,
              Fz, vx, T_C)
    if args.json:
        dump_json({"tire": tire.name, "friction": friction.describe(), "Fz_N": Fz,
                   "vx_m_s": vx, "T_C": T_C, "n_elements": n, "axes": args.axes,
                   "points": rows})
    else:
        print(f"# tire {tire.name}, Fz = {Fz:g} N, vx = {vx:g} m/s, T = {T_C:g} C, "
              f"{n} cells, axes {args.axes}")
        print_table(rows, KEYS)
    return 0


def _plot(path: str, rows: list[dict], sweep: str, tire: str, Fz: float, vx: float,
          T_C: float) -> None:
    """Forces and friction over the sweep (matplotlib, imported here)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.array([r[sweep] for r in rows])
    if sweep == "alpha":
        x = np.degrees(x)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    for key in (("Fx", "Fy") if sweep == "kappa" else ("Fy", "Fx")):
        ax1.plot(x, [r[key] for r in rows], label=f"{key} [N]")
    if sweep == "alpha":
        ax1b = ax1.twinx()
        ax1b.plot(x, [r["Mz"] for r in rows], "k--", label="Mz [N m]")
        ax1b.set_ylabel("Mz [N m]")
        ax1b.legend(loc="lower right")
    ax1.set_ylabel("force [N]")
    ax1.legend(loc="upper left")
    ax1.grid(True, alpha=0.3)
    ax1.set_title(f"{tire}: Fz = {Fz:g} N, vx = {vx:g} m/s, T = {T_C:g} C")
    ax2.plot(x, [r["mu_eff"] for r in rows], label="mu_eff = |F|/Fz [1]")
    ax2.plot(x, [r["mu_slide"] for r in rows], label="mu of sliding elements [1]")
    ax2.plot(x, [r["sliding_fraction"] for r in rows], label="sliding fraction [1]")
    ax2.set_xlabel("slip kappa [1]" if sweep == "kappa" else "slip angle alpha [deg]")
    ax2.set_ylabel("[1]")
    ax2.legend()
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)

