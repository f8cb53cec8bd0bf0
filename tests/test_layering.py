"""Dependency direction (docs/design.md): imports point down the flow only, and never in a circle.

The layers, from the bottom: ``tirefric`` (errors, units, model files, paths, the CLI root: no
physics) <- ``lookup`` (friction engine) <- ``tire_brush`` (tire, braking studies) <-
``fmu_src`` (``runtime`` <- ``make`` <- ``host``). Checked on the sources' import statements:
module level, inside functions and under ``TYPE_CHECKING`` alike, so that a cycle hidden by an
import inside a function cannot come back unnoticed.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from import_graph import PACKAGES, cycles, import_graph, imports

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "docs" / "design.md"


def layers_from_design(text: str) -> dict[str, tuple[str, ...]]:
    """The layer table of docs/design.md ("Dependency direction"): package (or sub-package
    folder) -> the packages it must not import."""
    rows = re.findall(r"^\| *\d+ *\| *`([\w/]+)` *\|([^|]*)\|\s*$", text, re.M)
    return {pkg: tuple(re.findall(r"`([\w.]+)`", rest)) for pkg, rest in rows}


#: package (or sub-package) -> the packages it must not import, as docs/design.md states it
FORBIDDEN = layers_from_design(DESIGN.read_text(encoding="utf-8"))
#: Modules of plumbing that live in the base package, not in the physics package ``lookup``.
BASE_MODULES = ("errors", "paths", "config", "units")


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_imports_point_down_the_flow(package) -> None:
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        for name in imports(path, ROOT):
            if any(name == f or name.startswith(f + ".") for f in FORBIDDEN[package]):
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
    assert not bad, "\n".join(bad)


def test_the_design_document_states_every_layer() -> None:
    """The table the checks read lists the base, the physics, the tire and the FMU's three
    parts bottom up, each barred from everything above it (so a new layer needs a row)."""
    order = ["tirefric", "lookup", "tire_brush", "fmu_src/runtime", "fmu_src/make",
             "fmu_src/host"]
    assert list(FORBIDDEN) == order, f"docs/design.md layer table: {list(FORBIDDEN)}"
    tops = ["tirefric", "lookup", "tire_brush", "fmu_src"]
    for pkg in ("tirefric", "lookup", "tire_brush"):
        above = tops[tops.index(pkg) + 1:]
        assert set(FORBIDDEN[pkg]) == set(above), f"{pkg} must be barred from {above}"
    packages = {p for p in PACKAGES}
    assert packages == {k.split("/")[0] for k in FORBIDDEN}


def test_no_import_cycles() -> None:
    """No two project modules import each other, directly or round a longer circle."""
    found = cycles(import_graph())
    assert not found, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_the_physics_package_holds_no_plumbing() -> None:
    """Errors, units, model-file reading and paths live in the base package ``tirefric``."""
    stray = [f"lookup/{m}.py" for m in BASE_MODULES if (ROOT / "lookup" / f"{m}.py").exists()]
    assert not stray, f"plumbing inside the physics package: {stray}"
    assert all((ROOT / "tirefric" / f"{m}.py").exists() for m in BASE_MODULES)


def test_the_check_sees_a_forbidden_import(tmp_path) -> None:
    """The checker itself: an import of fmu_src inside a function is found."""
    f = tmp_path / "m.py"
    f.write_text("def g():\n    from fmu_src.host import cosim\n    import fmu_src.make\n")
    assert imports(f) == ["fmu_src.host", "fmu_src.host.cosim", "fmu_src.make"]


def test_the_check_sees_a_cycle_through_a_function_level_import(tmp_path) -> None:
    """The cycle finder itself: a <-> b through a relative import inside a function, and a
    three-module circle, are found; a chain is not."""
    pkg = tmp_path / "tirefric"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import x\n")
    (pkg / "b.py").write_text("def f():\n    from . import a\n")
    (pkg / "c.py").write_text("import tirefric.d\n")
    (pkg / "d.py").write_text("from tirefric.e import y\n")
    (pkg / "e.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                              "    from .c import z\n")
    (pkg / "f.py").write_text("from .a import x\n")
    found = cycles(import_graph(tmp_path))
    assert sorted(found) == [["tirefric.a", "tirefric.b"],
                             ["tirefric.c", "tirefric.d", "tirefric.e"]]


def test_a_study_with_fmu_abs_needs_a_simulator_handed_to_it(tmp_path) -> None:
    """The braking study is handed its FMU simulator (no entry-point lookup): without one, a
    study that asks for the ABS through the FMU is refused with a message naming the field."""
    from dataclasses import replace

    from tire_brush.braking.study import load_study, run_study
    from tirefric.errors import InputError

    spec = load_study("abs_default")
    with pytest.raises(InputError, match=r"study\.fmu_abs"):
        run_study(replace(spec, fmu_abs=True))


def test_the_version_is_defined_once() -> None:
    """docs/design.md: the version is defined once, in tirefric/__init__.py, and the
    packaging metadata reads it there."""
    import tomllib

    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert meta["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "tirefric.__version__"}
    defs = [str(p.relative_to(ROOT)) for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")
            if re.search(r"^__version__\s*=", p.read_text(encoding="utf-8"), re.M)]
    assert defs == ["tirefric/__init__.py"], defs
