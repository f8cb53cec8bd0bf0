"""The FMU's ``axes`` parameter, both flavours: the same physical manoeuvre given in the
adapted SAE, ISO-W and SAE axes gives the same physical forces, and each system's signs are
its own (docs/axes.md):

* ISO-W (y left, z up): a wheel whose contact centre moves to the left (vy > 0) has
  alpha > 0 and is pushed back to the right, Fy < 0, with an aligning moment Mz > 0
  (about z up, turning the wheel towards the motion);
* SAE (y right, z down): the same manoeuvre is vy < 0, alpha < 0, Fy > 0 (pushed to the
  right) and Mz < 0 (the same moment about z down);
* adapted SAE: SAE axes with the slip angle reversed, alpha > 0 and Fy > 0, Mz < 0.

Forces are compared to the last bit: the conversion is a sign change on the way in and out.
"""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
from fmu_support import OUTPUTS, FmuDriver, build_test_fmu, synthetic_grid

VX, FZ, R_E = 20.0, 4000.0, 0.31   # free rolling at 3 deg
IX = {n: i for i, n in enumerate(OUTPUTS)}


@pytest.fixture(scope="module", params=["pythonfmu", "native"])
def fmu(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(f"axes_{request.param}")
    if request.param == "pythonfmu":
        return build_test_fmu(d)
    if shutil.which("cc") is None and shutil.which("gcc") is None:
        pytest.skip("the native FMU needs a C compiler")
    from fmu_src.make.native_build import build_native_fmu

    return build_native_fmu("passenger", synthetic_grid(), d / "BrushTireNative.fmu",
                            platforms=("linux64",)).path


def _run(fmu, axes: int, vy: float, n: int = 60) -> np.ndarray:
    d = FmuDriver(fmu, name=f"axes{axes}", logging=False, start_values={"axes": axes})
    try:
        for _ in range(n):
            out = d.step([VX, vy, VX / R_E, FZ, 293.15, 1.0, 0.0, 0.0])
        return out
    finally:
        d.close()


def test_the_same_manoeuvre_in_three_axis_systems(fmu) -> None:
    left = VX * math.tan(math.radians(3.0))     # contact centre moving to the left
    iso = _run(fmu, 1, +left)
    sae = _run(fmu, 2, -left)                   # SAE y points right
    ada = _run(fmu, 0, -left)                   # adapted SAE: SAE axes
    assert iso[IX["alpha"]] > 0 and iso[IX["Fy"]] < 0 and iso[IX["Mz"]] > 0, "ISO-W signs"
    assert sae[IX["alpha"]] < 0 and sae[IX["Fy"]] > 0 and sae[IX["Mz"]] < 0, "SAE signs"
    assert ada[IX["alpha"]] > 0 and ada[IX["Fy"]] > 0 and ada[IX["Mz"]] < 0, "adapted SAE"
    for name, s_iso, s_sae in (("Fx", 1, 1), ("kappa", 1, 1), ("Fy", -1, 1), ("Mz", -1, 1),
                               ("alpha", 1, -1), ("mu_eff", 1, 1), ("T_tread", 1, 1)):
        assert iso[IX[name]] == s_iso * ada[IX[name]], f"{name}: ISO-W against adapted SAE"
        assert sae[IX[name]] == s_sae * ada[IX[name]], f"{name}: SAE against adapted SAE"


def test_an_unknown_axis_system_is_refused(fmu) -> None:
    """axes = 7: the native FMU refuses to initialise (fmi2Error); the pythonfmu one, whose
    exitInitializationMode cannot fail, logs it and refuses every step."""
    from fmpy.fmi1 import FMICallException

    with pytest.raises(FMICallException):
        d = FmuDriver(fmu, name="axes7", logging=False, start_values={"axes": 7})
        d.step([VX, 0.0, VX / R_E, FZ, 293.15, 1.0, 0.0, 0.0])
