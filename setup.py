"""Build of the compiled tire core (tire_brush/csrc/tirecore.c) at install.

The core is a plain C99 library loaded with ctypes (tire_brush/ccore.py); setuptools builds
it as an extension file so that a wheel carries it for its platform. All other metadata is in
pyproject.toml.
"""

import sys

from setuptools import Extension, setup

if sys.platform == "win32":
    cflags = ["/O2", "/fp:precise"]
else:
    cflags = ["-std=c99", "-O2", "-ffp-contract=off", "-fno-fast-math"]

setup(ext_modules=[Extension("tire_brush._tirecore", ["tire_brush/csrc/tirecore.c"],
                             define_macros=[("TF_PYTHON_EXTENSION", "1")],
                             extra_compile_args=cflags,
                             libraries=[] if sys.platform == "win32" else ["m"])])
