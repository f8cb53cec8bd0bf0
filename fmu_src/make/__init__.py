"""What builds the FMUs (see :mod:`fmu_src`). Importing this package imports nothing."""
