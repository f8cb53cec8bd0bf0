"""tirefric ``fmu_src``: the transient brush tire as an FMI 2.0 co-simulation FMU (pythonfmu, or
native: the C core with an FMI wrapper), cut by where the code runs.

* :mod:`fmu_src.runtime` -- what runs *inside* the FMU (numpy and the standard library only):
  :mod:`~fmu_src.runtime.interface` (the FMU's variables, units and dependencies as data),
  :mod:`~fmu_src.runtime.slave` (the pythonfmu slave, a thin shell over
  :class:`tire_brush.transient.TransientBrushTire`), :mod:`~fmu_src.runtime.guard` (the input
  envelope), :mod:`~fmu_src.runtime.state` (exact byte serialization of the FMU state) and
  ``runtime/native/`` (the FMI 2.0 wrapper of the C core for the native flavour);
* :mod:`fmu_src.make` -- what *builds* FMUs: :mod:`~fmu_src.make.package` (the FMU's private
  copy of the modules it runs), :mod:`~fmu_src.make.model_description`,
  :mod:`~fmu_src.make.build` (``tire + grid -> BrushTire.fmu``),
  :mod:`~fmu_src.make.native_build` (``-> BrushTireNative.fmu``) and :mod:`~fmu_src.make.cli`
  (``tirefric fmu build [--native]|info``);
* :mod:`fmu_src.host` -- what runs on the *host's* side: :mod:`~fmu_src.host.cosim` (a quarter
  car braked through a built FMU with fmpy, and the FMU simulator handed to the braking
  study), :mod:`~fmu_src.host.abs_cli` (``tirefric abs`` with that simulator) and
  :mod:`~fmu_src.host.demo` (the whole product, ``tirefric demo``).

Dependencies run one way: ``host -> make -> runtime``, and each of them may use ``lookup`` and
``tire_brush``; nothing below imports ``fmu_src`` (the braking study is handed its FMU
simulator). Importing this package imports nothing.
"""
