"""The host's side of the FMUs: co-simulation, the braking study's FMU simulator and the
demo (see :mod:`fmu_src`). Importing this package imports nothing."""
