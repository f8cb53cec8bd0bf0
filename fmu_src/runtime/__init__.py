"""What runs inside the FMU (numpy and the standard library only; see :mod:`fmu_src`).

Importing this package imports nothing: the FMU's private copy of the modules
(:mod:`fmu_src.make.package`) starts from the slave alone.
"""
