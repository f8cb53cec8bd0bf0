"""The in-process paths that used to crash the host at exit, run as one process.

``python tests/fmu_exit_paths.py FMU`` (a pythonfmu FMU of the shipped tire) runs, in one
process: the quarter-car example's vehicle loop through
:func:`fmu_src.host.cosim.simulate_braking_fmu` (locked wheel and ABS), four instances
stepping side by side, every FMI misuse of ``tests/test_fmu_cosim.py`` and a corrupt state
blob, and exits leaving two instances for the
interpreter's shutdown to release. The test that runs it requires exit status 0 each time
(pythonfmu turned any Python exception into fmi2Fatal and released the instance, so the next
call or the release at exit freed it twice: fmu_src/runtime/slave.py, module docstring).
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))

from fmu_support import FmuDriver, braking_inputs  # noqa: E402


def main(fmu: Path) -> None:
    ex = runpy.run_path(str(HERE.parent / "examples" / "quarter_car_braking.py"))
    for use_abs in (False, True):
        data = ex["simulate"](fmu, mass=400.0, inertia=1.0, v0=15.0, torque=2500.0,
                              ramp=(0.02, 0.1), T_road=293.15, t_max=0.3, use_abs=use_abs)
        assert np.isfinite(data["v"]).all()
    drivers = [FmuDriver(fmu, None, f"tire{i}") for i in range(4)]
    U = braking_inputs(200)
    for k in range(U.shape[1]):
        for d in drivers:
            d.step(U[:, k])
    d = drivers[0]
    f, n_vars = d.fmu, len(d.md.modelVariables)
    from fmpy.fmi1 import FMICallException

    for call in (lambda: f.setReal([d.vr["Fx"]], [1.0]), lambda: f.getReal([n_vars + 3]),
                 lambda: f.setInteger([d.vr["vx"]], [1]),
                 lambda: f.setString([d.vr["info.tire"]], ["x"])):
        try:
            call()
        except FMICallException as exc:
            assert exc.status != 4, "fmi2Fatal"
    blob = bytearray(f.serializeFMUstate(f.getFMUstate()))
    blob[len(blob) // 3] ^= 1
    try:
        f.setFMUstate(f.deSerializeFMUstate(bytes(blob)))
    except FMICallException as exc:
        assert exc.status != 4, "fmi2Fatal"
    assert np.isfinite(d.step(U[:, 0])).all()
    for d in drivers[:2]:
        d.close()
    print("ok")                                   # drivers[2:] are left to the shutdown


if __name__ == "__main__":
    main(Path(sys.argv[1]))
