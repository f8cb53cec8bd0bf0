"""tirefric ``fmu_src``: the transient brush tire as an FMI 2.0 co-simulation FMU (pythonfmu, or
native: the C core with an FMI wrapper).

One concern per module (as FMPy does it):

* :mod:`fmu_src.interface` -- the FMU's variables, units and dependencies as data;
* :mod:`fmu_src.slave` -- the pythonfmu slave, a thin shell over
  :class:`tire_brush.transient.TransientBrushTire`;
* :mod:`fmu_src.guard` -- the input envelope (NaN, negative load, absurd speeds);
* :mod:`fmu_src.state` -- exact byte serialization of the FMU state;
* :mod:`fmu_src.package` -- the FMU's private copy of the modules it runs;
* :mod:`fmu_src.model_description` -- post-processing of pythonfmu's modelDescription.xml;
* :mod:`fmu_src.build` -- ``tire + grid -> BrushTire.fmu``; :mod:`fmu_src.cli` --
  ``tirefric fmu build [--native]|info``;
* :mod:`fmu_src.native_build` -- ``tire + grid -> BrushTireNative.fmu``: the C core with the
  FMI 2.0 wrapper ``fmu_src/native/fmu_wrapper.c`` (same interface, no Python on the host);
* :mod:`fmu_src.cosim` -- the host's side: a quarter car braked through a built FMU with fmpy,
  step by step (torque ramp, locked wheel or rule-based ABS), and the braking-study plug-in.

The first four run inside the FMU (numpy and the standard library only); importing this
package imports nothing.
"""
