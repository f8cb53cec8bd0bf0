"""The tire's inputs and outputs, declared once: order, dimension, unit, start value, meaning.

Every user of the tire's signals reads this table instead of writing the list again: the
transient model's ``step`` (:mod:`tire_brush.transient`), the brush outputs
(:class:`tire_brush.slip.BrushOutputs`, whose fields are :data:`OUTPUT_NAMES`), the FMU's
variable table (:mod:`fmu_src.runtime.interface`), its input guard, the hosts and benchmarks
that drive an FMU, and the native FMU's generated C header
(``fmu_src/runtime/native/tfn_interface.h``). The compiled core takes the inputs as the
arguments of ``tf_tire_step`` and returns the outputs in this order (``tirecore.h``); a test
parses the header and compares (tests/test_interface_table.py). Adding an input is one row
here plus the physics that uses it; the tests name every place that has not followed.

Units are not written here: each signal has a dimension of :mod:`tirefric.units`, whose SI
unit (in the FMI spelling) is the signal's unit.

This module imports only the standard library and :mod:`tirefric.units` (stdlib only): it
runs inside the FMU.
"""

from __future__ import annotations

from dataclasses import dataclass

from tirefric.units import si_unit


@dataclass(frozen=True)
class Signal:
    """One input or output of the tire.

    Attributes
    ----------
    name : str
        Name (a Python identifier; the FMU variable's name).
    dimension : str
        Dimension in :data:`tirefric.units.SI_UNITS`; the unit is its SI unit.
    description : str
        What it is, with its unit and sign convention.
    start : float or None
        Start value of an input [SI]; None for an output, and for the load, whose start is
        the tire's nominal load.
    """

    name: str
    dimension: str
    description: str
    start: float | None = None

    @property
    def unit(self) -> str:
        """SI unit in the FMI spelling (:func:`tirefric.units.si_unit`)."""
        return si_unit(self.dimension)


#: Inputs, in the order of ``tf_tire_step``'s arguments and of every input vector.
INPUTS: tuple[Signal, ...] = (
    Signal("vx", "velocity",
           "Wheel-centre velocity in the wheel plane (longitudinal) [m/s]", 0.0),
    Signal("vy", "velocity",
           "Wheel-centre velocity lateral to the wheel plane [m/s] (along y of the axis system "
           "of parameter axes)", 0.0),
    Signal("omega", "angular_frequency",
           "Wheel spin [rad/s]; the rolling speed is omega * tire.R_e", 0.0),
    Signal("Fz", "force", "Vertical load [N]; Fz <= 0 is lift-off (no forces)"),
    Signal("T_surface", "temperature",
           "Background tread/road temperature [K] (friction tables' T0; the tread temperature "
           "relaxes to it)", 293.15),
    Signal("mu_scale", "dimensionless",
           "Road friction scale [1], multiplies both friction branches", 1.0),
    Signal("gamma", "angle",
           "Inclination (camber) angle of the wheel plane [rad]: a rotation about x, top of the "
           "wheel to the right positive, the same sign in every axis system (docs/axes.md)",
           0.0),
    Signal("water_depth", "length",
           "Water film depth on the road [m] (0 = dry), read through the wet branch of the "
           "FMU's grid, with dynamic hydroplaning", 0.0),
)

#: Outputs of a step, in the order of the core's output vector and of
#: :class:`tire_brush.slip.BrushOutputs`.
OUTPUTS: tuple[Signal, ...] = (
    Signal("Fx", "force",
           "Longitudinal force on the tire from the road [N] (braking: Fx < 0)"),
    Signal("Fy", "force",
           "Lateral force on the tire from the road [N] (axis system of parameter axes)"),
    Signal("Mz", "moment",
           "Aligning moment about the vertical axis through the patch centre [N.m] (axis "
           "system of parameter axes)"),
    Signal("kappa", "dimensionless",
           "Longitudinal slip [1] (reported, with the speed floor v_floor)"),
    Signal("alpha", "angle",
           "Slip angle [rad] (reported, with the speed floor v_floor; sign of the axis system "
           "of parameter axes)"),
    Signal("mu_eff", "dimensionless", "Utilised friction |F| / Fz [1] (0 without load)"),
    Signal("mu_slide", "dimensionless",
           "Pressure-weighted mean friction coefficient (eq. 28) of the sliding elements [1]"),
    Signal("sliding_fraction", "dimensionless",
           "Share of the contact patch where the tread slides [1]"),
    Signal("dT_flash_max", "temperature_difference",
           "Largest flash-temperature rise in the contact patch [K]"),
    Signal("T_tread", "temperature",
           "Tread (background) temperature the friction is read at [K]; equals T_surface when "
           "tire.thermal.enabled is false"),
    Signal("Mx", "moment",
           "Overturning moment about the x axis through the contact centre [N.m]: the load "
           "shifted sideways by the belt's lateral deflection (the same sign in every axis "
           "system)"),
    Signal("My", "moment",
           "Rolling resistance moment about the wheel axis [N.m], f_r Fz R_e against the spin "
           "(axis system of parameter axes: ISO-W My < 0 rolling forward); 0 when the FMU was "
           "built without a rolling-resistance table"),
)

#: Input names in order.
INPUT_NAMES: tuple[str, ...] = tuple(s.name for s in INPUTS)
#: Output names in order.
OUTPUT_NAMES: tuple[str, ...] = tuple(s.name for s in OUTPUTS)
#: Output name -> unit.
OUTPUT_UNITS: dict[str, str] = {s.name: s.unit for s in OUTPUTS}
