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

``tirefric tire fit-mf --T CELSIUS --vx M_S -o FILE.tir [--tire passenger] [--grid default]
[--loads 0.5,1,1.5] [--fittyp 61|6] [--json] [--points FILE.csv] [--axes iso-w]`` fits Magic
Formula 6.1 / PAC2002 coefficients to the steady brush (:mod:`tire_brush.mf_fit`), writes the
``.tir`` file (ISO-W, as MF readers expect; :mod:`tire_brush.tir`) and prints the fit error per
channel (RMS and largest ``|MF - brush| / Fz``), the load dependence of brush and MF, and the
camber (``PKY6, PKY7``, Pacejka 2012 eqs. (4.E27)-(4.E30)), overturning (``QSX3``, eq. (4.E69))
and rolling-resistance (``QSY1, QSY3, QSY7``, eq. (4.E70); only when the grid's compound and
the tire's ``[rolling_resistance]`` table are there, else why not) results, also in the file's
header; ``--points`` writes the fit points with the brush's and the MF's forces in the
``--axes`` convention.
"""

from __future__ import annotations

import argparse

import numpy as np

from tirefric.cli import (
    dump_json,
    parse_float,
    parse_float_list,
    parse_quantity_option,
    parse_temperature_option,
    print_table,
)
from tirefric.errors import InputError

from .axes import AXES, BRUSH_AXES, SlipInputs, Wrench, convert_inputs, convert_wrench
from .rolling_resistance_cli import add_parser as add_rolling_resistance_parser

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
    c.add_argument("--fidelity", choices=("full", "realtime"), default="full",
                   help="'full' (default): the steady march of the tread elements; "
                        "'realtime': the real-time fidelity held at each point until settled "
                        "(its patch table is built once per tire and grid, about a minute on "
                        "2 cores, then cached; docs/realtime.md)")
    c.add_argument("--n-elements", type=int, default=None,
                   help="cells along the patch (default: the steady model's default)")
    c.add_argument("--axes", choices=AXES, default=BRUSH_AXES,
                   help="sign convention of --alpha-deg and of the printed forces (default "
                        "adapted-sae, the brush model's; iso-v = iso-w at zero steer angle)")
    c.add_argument("--json", action="store_true", help="print JSON with a list 'points'")
    c.add_argument("--plot", metavar="FILE.png", help="write a plot of the curve")
    c.set_defaults(func=_run_curve)
    _register_fit_mf(ts)
    add_rolling_resistance_parser(ts)


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
    # the slip angle is given in --axes; the brush works in its own convention
    alpha_brush = convert_inputs(SlipInputs(kappa, alpha, vx, 0.0), args.axes, BRUSH_AXES).alpha
    if args.fidelity == "realtime":
        from types import SimpleNamespace

        from .realtime_build import realtime_curve

        out = SimpleNamespace(**realtime_curve(tire, friction, kappa, alpha_brush, vx, Fz,
                                               T_C + 273.15))
        out.kappa, out.alpha = kappa, alpha_brush
    else:
        out = SteadyBrush(tire, friction, n_elements=n).solve(kappa, alpha_brush, vx, Fz,
                                                              T_C + 273.15)
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
                   "fidelity": args.fidelity, "points": rows})
    else:
        print(f"# tire {tire.name}, Fz = {Fz:g} N, vx = {vx:g} m/s, T = {T_C:g} C, "
              f"{n} cells, axes {args.axes}, fidelity {args.fidelity}")
        print_table(rows, KEYS)
    return 0


# -- tirefric tire fit-mf ---------------------------------------------------------------------
def _register_fit_mf(ts: argparse._SubParsersAction) -> None:
    f = ts.add_parser("fit-mf", help="fit Magic Formula 6.1 / PAC2002 coefficients to the "
                                     "steady brush and write a .tir file",
                      description="Fit MF 6.1 / PAC2002 coefficients (pure and combined "
                                  "slip, load dependence, camber stiffness, overturning and "
                                  "rolling-resistance moments) to the steady brush model at "
                                  "one temperature and speed and write a TYDEX .tir file "
                                  "(ISO-W).")
    f.add_argument("--tire", default="passenger",
                   help="tire TOML file or shipped name (default passenger)")
    f.add_argument("--grid", default="default",
                   help="grid file, shipped grid name (default), or constant:MU[,MU_HOT]")
    f.add_argument("--T", required=True, help="background temperature [Celsius]")
    f.add_argument("--vx", required=True, help="forward speed of the fit [m/s] (> 0)")
    f.add_argument("-o", "--output", required=True, metavar="FILE.tir",
                   help="the .tir file to write")
    f.add_argument("--loads", default="0.5,1,1.5",
                   help="loads of the fit as multiples of the nominal load (default "
                        "0.5,1,1.5)")
    f.add_argument("--fittyp", type=int, choices=(61, 6), default=61,
                   help="FITTYP written: 61 (MF 6.1, default) or 6 (PAC2002: no camber "
                        "range, My without the load exponent QSY7)")
    f.add_argument("--size", help="size designation, e.g. '205/55 R16' (default: read from "
                                  "the tire file's description)")
    f.add_argument("--pressure", help="inflation pressure written to the file, e.g. "
                                      "'230 kPa' (default: read from the tire file's "
                                      "description; no coefficient depends on it)")
    f.add_argument("--axes", choices=AXES, default="iso-w",
                   help="sign convention of --points (the .tir file is always ISO-W)")
    f.add_argument("--points", metavar="FILE.csv",
                   help="write the fit points: brush and MF forces in --axes")
    f.add_argument("--json", action="store_true", help="print the result as JSON")
    f.set_defaults(func=_run_fit_mf)


def _run_fit_mf(args: argparse.Namespace) -> int:
    from tirefric import __version__

    from .mf_fit import CHANNELS, FitSettings, fit_mf
    from .params import load_tire
    from .steady import N_STEADY, TOL, SteadyBrush
    from .tir import parse_pressure_bar, parse_size, tir_text, write_tir

    T_K = parse_temperature_option(args.T, "--T")
    vx = parse_float(args.vx, "--vx")
    if vx <= 0:
        raise InputError("forward speed must be > 0 m/s", source="--vx", value=args.vx)
    loads = tuple(parse_float_list(args.loads, "--loads"))
    try:
        settings = FitSettings(loads=loads)
    except InputError as exc:
        raise InputError(exc.message, source="--loads", value=args.loads) from None
    tire = load_tire(args.tire)
    size = parse_size(args.size if args.size else tire.description,
                      "--size" if args.size else f"{tire.source} description")
    pressure = (parse_quantity_option(args.pressure, "--pressure", "pressure", "Pa")
                if args.pressure else parse_pressure_bar(tire.description,
                                                         f"{tire.source} description"))
    if not pressure > 0:
        raise InputError("must be > 0", source="--pressure", value=args.pressure)
    if max(loads) * tire.Fz_nom > tire.patch.Fz_max:
        raise InputError(f"the largest load {max(loads) * tire.Fz_nom:g} N is above the "
                         f"tire's patch-law limit Fz_max = {tire.patch.Fz_max:g} N",
                         source="--loads", value=args.loads)
    friction = load_friction(args.grid)
    model = SteadyBrush(tire, friction)
    fit = fit_mf(model, vx, T_K, settings, grid=getattr(friction, "grid", None),
                 fittyp=args.fittyp)
    fdesc = friction.describe()
    grid_meta = fdesc.get("grid", {})
    road = (f"compound {grid_meta.get('compound_name', '?')} on surface "
            f"{grid_meta.get('surface_name', '?')}, grid hash {grid_meta.get('hash', '?')}"
            if fdesc.get("kind") == "grid" else
            f"constant friction mu_cold = {fdesc.get('mu_cold')}, mu_hot = "
            f"{fdesc.get('mu_hot')}")
    T_C = T_K - 273.15
    F = np.asarray(loads) * tire.Fz_nom
    provenance = [
        f"Magic Formula {'6.1' if args.fittyp == 61 else 'PAC2002'} fit of the tirefric "
        f"{__version__} steady brush model",
        f"(tire_brush.steady: {N_STEADY} cells, tolerance {TOL:g}; tire_brush.mf_fit).",
        f"Tire: {tire.name} ({tire.description})",
        f"Road: {road} (--grid {args.grid})",
        f"Background temperature T = {T_C:g} C; speed vx = {vx:g} m/s; loads "
        + ", ".join(f"{x:g}" for x in F) + " N.",
        "Fit error |MF - brush| / Fz (forces [1], Mz [m]), RMS / max:",
        *[f"  {ch}: {fit.errors[ch]['rms']:.4g} / {fit.errors[ch]['max']:.4g}"
          for ch in CHANNELS],
        *_extra_provenance(fit, args.fittyp),
        "No pressure or turn-slip model: those coefficients are 0. Shifts are 0: the brush",
        "is symmetric in alpha.",
        *([f"On a bound of the fit (the MF form cannot follow the brush): "
           f"{', '.join(fit.at_bounds)}."] if fit.at_bounds else []),
    ]
    s = fit.settings
    cam = s.camber_max if args.fittyp == 61 else 0.0
    ranges = {"KPUMIN": -s.kappa_max, "KPUMAX": s.kappa_max,
              "ALPMIN": -np.radians(s.alpha_max_deg), "ALPMAX": np.radians(s.alpha_max_deg),
              "CAMMIN": -cam if cam else 0.0, "CAMMAX": cam,
              "FZMIN": float(F.min()), "FZMAX": float(F.max())}
    text = tir_text(fit.coefficients, fittyp=args.fittyp, size=size, pressure=pressure,
                    vertical_stiffness=tire.patch.C_z, vx=vx, ranges=ranges,
                    provenance=provenance)
    write_tir(args.output, text)
    if args.points:
        _write_points(args.points, fit, args.axes)
    if args.json:
        dump_json({"tire": tire.name, "friction": fdesc, "T_C": T_C, "vx_m_s": vx,
                   "loads_N": F.tolist(), "fittyp": args.fittyp, "output": args.output,
                   "tir_axes": "iso-w", "coefficients": fit.coefficients,
                   "fitted": fit.fitted, "at_bounds": fit.at_bounds, "errors": fit.errors,
                   "load_dependence": fit.load_dependence, "camber": fit.camber,
                   "overturning": fit.overturning, "rolling": fit.rolling,
                   "points_axes": args.axes if args.points else None})
        return 0
    print(f"# wrote {args.output} (FITTYP {args.fittyp}, ISO-W): tire {tire.name}, "
          f"T = {T_C:g} C, vx = {vx:g} m/s")
    print("# fit error |MF - brush| / Fz (forces [1], Mz [m])")
    print_table([{"channel": ch, **{k: fit.errors[ch][k] for k in ("rms", "max", "max_abs",
                                                                    "n")}}
                 for ch in CHANNELS], ("channel", "rms", "max", "max_abs", "n"))
    if fit.at_bounds:
        print(f"# on a bound of the fit (the MF form cannot follow the brush): "
              f"{', '.join(fit.at_bounds)}")
    print("# load dependence, brush against MF: slip stiffness / Fz [1], peak mu [1], "
          "pneumatic trail at small alpha [m]")
    cols = [f"{row['Fz_N']:g} N" for row in fit.load_dependence]
    print_table([{"quantity": key, **{c: row[key] for c, row in
                                     zip(cols, fit.load_dependence, strict=True)}}
                 for key in list(fit.load_dependence[0])[1:]], ("quantity", *cols))
    print("# camber, overturning and rolling-resistance moments")
    for line in _extra_provenance(fit, args.fittyp):
        print(f"# {line.strip()}")
    return 0


def _extra_provenance(fit, fittyp: int) -> list[str]:
    """Lines on the camber, ``Mx`` and ``My`` fits (file header and text output)."""
    cam, ot, rr = fit.camber, fit.overturning, fit.rolling
    c = fit.coefficients
    e = cam["errors"]
    lines = [
        f"Camber (MF 6.1): PKY6 = {c['PKY6']:.5g}, PKY7 = {c['PKY7']:.5g} from the brush's "
        f"camber stiffness (largest error {cam['stiffness_rel_error_max']:.2%});",
        f"  |gamma| <= {cam['gamma_max_rad']:g} rad, kappa = 0: Fy error / Fz RMS / max "
        f"{e['Fy']['rms']:.4g} / {e['Fy']['max']:.4g} (camber part "
        f"{e['Fy_camber_part']['rms']:.4g} / {e['Fy_camber_part']['max']:.4g});",
        f"  the brush's camber aligning moment (not in the file, QDZ8.. = 0): |dMz| / Fz "
        f"RMS / max {e['Mz_camber_part_brush']['rms']:.3g} / "
        f"{e['Mz_camber_part_brush']['max']:.3g} m.",
    ]
    if fittyp != 61:
        lines.append("  PAC2002 readers do not evaluate PKY6, PKY7: CAMMIN = CAMMAX = 0.")
    lines.append(f"Mx: QSX3 = Fz0 / (R0 k_y) = {ot['QSX3']:.6g} (the brush's Mx = Fy Fz / k_y, "
                 f"exact).")
    if rr["fitted"]:
        r = rr["errors"]
        lines.append(
            f"My: {', '.join(f'{n} = {c[n]:.5g}' for n in rr['fitted'])} from "
            f"tire_brush.rolling_resistance (compound {rr['compound']}, T of the fit); "
            f"|dMy| / (R0 Fz) RMS / max {r['rms']:.3g} / {r['max']:.3g} "
            f"({r['rel_max']:.1%} of My at most).")
    else:
        lines.append(f"My: QSY* = 0, no rolling-resistance fit: {rr['why']}.")
    return lines


def _write_points(path: str, fit, axes: str) -> None:
    """The fit points with the brush's and the MF's forces in ``axes`` (CSV)."""
    import csv

    p = fit.points
    inp = convert_inputs(SlipInputs(p.kappa, p.alpha, 1.0, 0.0), "iso-w", axes)
    brush = convert_wrench(Wrench(p.Fx, p.Fy, p.Fz, 0.0, 0.0, p.Mz), "iso-w", axes)
    mfw = convert_wrench(Wrench(fit.mf["Fx"], fit.mf["Fy"], p.Fz, 0.0, 0.0, fit.mf["Mz"]),
                         "iso-w", axes)
    cols = {"kind": p.kind, "kappa": inp.kappa, "alpha_rad": inp.alpha, "Fz_N": brush.Fz,
            "Fx_brush_N": brush.Fx, "Fy_brush_N": brush.Fy, "Mz_brush_Nm": brush.Mz,
            "Fx_mf_N": mfw.Fx, "Fy_mf_N": mfw.Fy, "Mz_mf_Nm": mfw.Mz}
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([f"# axes: {axes}"])
        w.writerow(list(cols))
        for i in range(p.kappa.size):
            w.writerow([cols["kind"][i], *(repr(float(np.asarray(v)[i]))
                                          for k, v in cols.items() if k != "kind")])


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

