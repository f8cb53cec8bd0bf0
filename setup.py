"""Build of the compiled tire core (tire_brush/csrc/tirecore.c, tirert.c,
bspline.c) at install.

The core is a plain C99 library loaded with ctypes (tire_brush/ccore.py); setuptools builds
it as an extension file so that a wheel carries it for its platform. All other metadata is in
pyproject.toml.
"""

import ast
import sys
from pathlib import Path

from setuptools import Extension, setup


def core_cflags() -> list[str]:
    """The core's compiler flags, ``CORE_CFLAGS`` of tire_brush/ccore.py (one place; read
    without importing the package, which needs numpy)."""
    tree = ast.parse((Path(__file__).parent / "tire_brush" / "ccore.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "CORE_CFLAGS"
                                                for t in node.targets):
            return list(ast.literal_eval(node.value))
    raise RuntimeError("tire_brush/ccore.py defines no CORE_CFLAGS")


if sys.platform == "win32":
    cflags = ["/O2", "/fp:precise"]
else:
    cflags = core_cflags()

setup(ext_modules=[Extension("tire_brush._tirecore", ["tire_brush/csrc/tirecore.c",
                                                     "tire_brush/csrc/tirert.c",
                                                     "tire_brush/csrc/bspline.c"],
                             define_macros=[("TF_PYTHON_EXTENSION", "1")],
                             extra_compile_args=cflags,
                             libraries=[] if sys.platform == "win32" else ["m"])])
