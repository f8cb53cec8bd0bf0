"""Quarter-car straight-line braking with the brush-tire FMU, driven step by step through fmpy.

A small vehicle model plays the vehicle simulator: at every 1 ms communication step it sends
the wheel-centre speed, the wheel spin, the load and the road temperature to the FMU, takes one
``doStep``, reads the tire force and integrates

* the quarter-car body:  ``m dv/dt = Fx``  (no aerodynamic or rolling drag: the tire alone),
* the wheel:             ``J domega/dt = -R_e Fx - T_b``  (``Fx < 0`` braking spins the wheel
  up; the brake torque ``T_b`` acts against the spin and holds a stopped wheel, so a locked
  wheel stays at ``omega = 0``),

with a semi-implicit Euler step. The loop is the library's :mod:`fmu_src.host.cosim`
(:func:`~fmu_src.host.cosim.simulate_braking_fmu`); this script sets up the car and the brake and
plots. The brake torque ramps from zero to ``--torque`` (default 2500 N.m, beyond what the tire
can transmit, so the wheel locks: the tread slides, reaches the hot branch of eq. (28) and the
flash temperature rises). A lower ``--torque`` (e.g. 900 N.m) brakes without locking;
``--abs`` lets the rule-based ABS of :mod:`tire_brush.braking.abs_control` modulate the torque
(up to ``--torque``) instead.

Run (from the repository):

    python examples/quarter_car_braking.py -o braking.png
    python examples/quarter_car_braking.py --grid models/grids/default.nc --torque 900 -o b.png
    python examples/quarter_car_braking.py --abs --torque 3000 -o abs.png

The plot shows speed and wheel speed, slip, Fx (and mu_eff), and the flash-temperature rise
with the tread temperature.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

G = 9.81  # [m/s^2]


def _fmu_radius(fmu: Path) -> float:
    """The FMU's effective rolling radius ``tire.R_e`` [m] (the car's wheel radius)."""
    import fmpy

    md = fmpy.read_model_description(str(fmu))
    return float(next(v.start for v in md.modelVariables if v.name == "tire.R_e"))


def simulate(fmu: Path, *, mass: float, inertia: float, v0: float, torque: float,
             ramp: tuple[float, float], T_road: float, dt: float = 1e-3,
             t_max: float = 6.0, use_abs: bool = False,
             torque_rate: float = 20000.0) -> dict[str, np.ndarray]:
    """Run the manoeuvre through :func:`fmu_src.host.cosim.simulate_braking_fmu`; returns time
    series (SI units) by name (the state at the end of each step, from the start to the
    stop at 0.3 m/s or ``t_max``)."""
    from fmu_src.host.cosim import CosimSettings, simulate_braking_fmu
    from tire_brush.braking.abs_control import ABSParams, RuleBasedABS, TorqueRamp
    from tire_brush.braking.quarter_car import QuarterCar

    R_e = _fmu_radius(fmu)
    ramp_rate = torque / (ramp[1] - ramp[0]) if ramp[1] > ramp[0] else torque / dt
    car = QuarterCar(mass=mass, wheel_inertia=inertia, radius=R_e,
                     brake_torque_max=torque,
                     brake_torque_rate_max=torque_rate if use_abs else ramp_rate, g=G,
                     name="example")
    if use_abs:
        controller = RuleBasedABS(ABSParams(), R_e, car.brake_torque_rate_max)
    else:
        controller = TorqueRamp(torque, *ramp, rate_max=ramp_rate, control_period=dt)
    res = simulate_braking_fmu(fmu, car, controller, v0, T_road, v_stop=0.3,
                               settings=CosimSettings(step=dt, t_max=t_max, thermal="fmu"),
                               instance_name="front_left")
    data = res.histories()
    data["T_brake"] = data["brake_torque"]
    data["distance"] = data["x"]
    return data


def plot(data: dict[str, np.ndarray], output: Path, title: str) -> None:
    """Speed and wheel speed, slip, Fx and mu_eff, flash temperature and tread temperature."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = data["t"]
    fig, ax = plt.subplots(4, 1, figsize=(8, 10), sharex=True)
    ax[0].plot(t, 3.6 * data["v"], label="vehicle speed")
    ax[0].plot(t, 3.6 * data["wheel_speed"], label="wheel speed omega R_e")
    ax[0].set_ylabel("speed [km/h]")
    ax[0].legend()
    ax[1].plot(t, data["kappa"], color="C2")
    ax[1].set_ylabel("slip kappa [1]")
    ax[2].plot(t, data["Fx"] / 1e3, color="C3", label="Fx")
    ax[2].set_ylabel("Fx [kN]")
    mu = ax[2].twinx()
    mu.plot(t, data["mu_eff"], color="C4", lw=0.8, label="mu_eff")
    mu.set_ylabel("mu_eff = |F|/Fz [1]")
    ax[3].plot(t, data["dT_flash_max"], color="C1", label="flash temperature rise (max)")
    ax[3].set_ylabel("dT_flash_max [K]")
    tt = ax[3].twinx()
    tt.plot(t, data["T_tread"] - 273.15, color="C5", lw=0.8, label="tread temperature")
    tt.set_ylabel("T_tread [degC]")
    ax[3].set_xlabel("time [s]")
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Quarter-car braking with the brush-tire FMU")
    ap.add_argument("--fmu", default=None, help="a built BrushTire.fmu (default: build one)")
    ap.add_argument("--tire", default="passenger", help="tire for the build")
    ap.add_argument("--grid", default="default", help="grid for the build")
    ap.add_argument("--mass", type=float, default=400.0, help="quarter-car mass [kg]")
    ap.add_argument("--inertia", type=float, default=1.0, help="wheel inertia [kg m^2]")
    ap.add_argument("--v0", type=float, default=100.0, help="initial speed [km/h]")
    ap.add_argument("--torque", type=float, default=2500.0, help="brake torque [N m]")
    ap.add_argument("--T-road", type=float, default=20.0, help="road temperature [Celsius]")
    ap.add_argument("--abs", action="store_true",
                    help="rule-based ABS (up to --torque) instead of the torque ramp")
    ap.add_argument("-o", "--output", default="quarter_car_braking.png", help="PNG file")
    args = ap.parse_args(argv)

    with tempfile.TemporaryDirectory(prefix="quarter_car_") as tmp:
        fmu = Path(args.fmu) if args.fmu else None
        if fmu is None:
            from fmu_src.make.build import build_fmu

            fmu = build_fmu(args.tire, args.grid, Path(tmp) / "BrushTire.fmu").path
        data = simulate(fmu, mass=args.mass, inertia=args.inertia, v0=args.v0 / 3.6,
                        torque=args.torque, ramp=(0.1, 0.4), T_road=args.T_road + 273.15,
                        use_abs=args.abs)
    stop = data["t"][-1]
    print(f"braking from {args.v0:g} km/h with {args.torque:g} N.m: {data['distance'][-1]:.1f} m "
          f"to {3.6 * data['v'][-1]:.1f} km/h in {stop:.2f} s")
    print(f"peak mu_eff {data['mu_eff'].max():.3f}, mean deceleration "
          f"{(args.v0 / 3.6 - data['v'][-1]) / stop / G:.3f} g, "
          f"max flash-temperature rise {data['dT_flash_max'].max():.1f} K, "
          f"tread {data['T_tread'][0] - 273.15:.1f} -> {data['T_tread'][-1] - 273.15:.2f} C")
    brake = "rule-based ABS, torque up to" if args.abs else "brake torque ramp to"
    title = (f"Quarter car, {args.mass:g} kg, {args.v0:g} km/h, {brake} "
             f"{args.torque:g} N.m (tire {args.tire}, grid {args.grid})")
    plot(data, Path(args.output), title)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
