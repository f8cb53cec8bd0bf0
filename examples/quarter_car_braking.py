"""Quarter-car straight-line braking with the brush-tire FMU, driven step by step through fmpy.

A small vehicle model written here in Python plays the vehicle simulator: at every 1 ms
communication step it sends the wheel-centre speed, the wheel spin, the load and the road
temperature to the FMU, takes one ``doStep``, reads the tire force and integrates

* the quarter-car body:  ``m dv/dt = Fx``  (no aerodynamic or rolling drag: the tire alone),
* the wheel:             ``J domega/dt = -R_e Fx - T_b``  (``Fx < 0`` braking spins the wheel
  up; the brake torque ``T_b`` acts against the spin and holds a stopped wheel, so a locked
  wheel stays at ``omega = 0``),

with a semi-implicit Euler step. The brake torque ramps from zero to ``--torque`` (default
2500 N.m, beyond what the tire can transmit, so the wheel locks: the tread slides, reaches the
hot branch of eq. (28) and the flash temperature rises). A lower ``--torque`` (e.g. 900 N.m)
brakes without locking.

Run (from the repository):

    python examples/quarter_car_braking.py -o braking.png
    python examples/quarter_car_braking.py --grid models/grids/default.nc --torque 900 -o b.png

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


def simulate(fmu: Path, *, mass: float, inertia: float, v0: float, torque: float,
             ramp: tuple[float, float], T_road: float, dt: float = 1e-3,
             t_max: float = 6.0) -> dict[str, np.ndarray]:
    """Run the manoeuvre; returns time series (SI units) by name."""
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    R_e = float(next(v.start for v in md.modelVariables if v.name == "tire.R_e"))
    unzipdir = fmpy.extract(str(fmu))
    tire = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName="front_left")
    tire.instantiate()
    tire.setupExperiment(startTime=0.0)
    tire.enterInitializationMode()
    vin = [vr[n] for n in ("vx", "vy", "omega", "Fz", "T_surface", "mu_scale")]
    names = ("Fx", "kappa", "mu_eff", "sliding_fraction", "dT_flash_max", "T_tread")
    vout = [vr[n] for n in names]
    Fz = mass * G
    v, omega, t = v0, v0 / R_e, 0.0
    tire.setReal(vin, [v, 0.0, omega, Fz, T_road, 1.0])
    tire.exitInitializationMode()
    rows = []
    while t < t_max and v > 0.3:
        T_b = torque * min(max((t - ramp[0]) / (ramp[1] - ramp[0]), 0.0), 1.0)
        tire.setReal(vin, [v, 0.0, omega, Fz, T_road, 1.0])
        tire.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
        y = dict(zip(names, tire.getReal(vout), strict=True))
        t += dt
        v += dt * y["Fx"] / mass
        spun = omega - dt * R_e * y["Fx"] / inertia     # tire torque first
        braked = dt * T_b / inertia                      # the brake can at most stop it
        omega = spun - braked if spun > braked else 0.0
        rows.append((t, v, omega * R_e, T_b, *y.values()))
    tire.terminate()
    tire.freeInstance()
    cols = ("t", "v", "wheel_speed", "T_brake", *names)
    data = {c: np.array([r[i] for r in rows]) for i, c in enumerate(cols)}
    data["distance"] = np.cumsum(data["v"]) * dt
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
    ap.add_argument("-o", "--output", default="quarter_car_braking.png", help="PNG file")
    args = ap.parse_args(argv)

    with tempfile.TemporaryDirectory(prefix="quarter_car_") as tmp:
        fmu = Path(args.fmu) if args.fmu else None
        if fmu is None:
            from fmu_src.build import build_fmu

            fmu = build_fmu(args.tire, args.grid, Path(tmp) / "BrushTire.fmu").path
        data = simulate(fmu, mass=args.mass, inertia=args.inertia, v0=args.v0 / 3.6,
                        torque=args.torque, ramp=(0.1, 0.4), T_road=args.T_road + 273.15)
    stop = data["t"][-1]
    print(f"braking from {args.v0:g} km/h with {args.torque:g} N.m: {data['distance'][-1]:.1f} m "
          f"to {3.6 * data['v'][-1]:.1f} km/h in {stop:.2f} s")
    print(f"peak mu_eff {data['mu_eff'].max():.3f}, mean deceleration "
          f"{(args.v0 / 3.6 - data['v'][-1]) / stop / G:.3f} g, "
          f"max flash-temperature rise {data['dT_flash_max'].max():.1f} K, "
          f"tread {data['T_tread'][0] - 273.15:.1f} -> {data['T_tread'][-1] - 273.15:.2f} C")
    title = (f"Quarter car, {args.mass:g} kg, {args.v0:g} km/h, brake torque ramp to "
             f"{args.torque:g} N.m (tire {args.tire}, grid {args.grid})")
    plot(data, Path(args.output), title)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
