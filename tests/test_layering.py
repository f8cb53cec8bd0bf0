"""Dependency direction (docs/design.md): imports point down the flow only, and never in a circle.

The layers, from the bottom: ``tirefric`` (errors, units, model files, paths, the CLI root: no
physics) <- ``lookup`` (friction engine) <- ``tire_brush`` (tire, braking studies) <-
``fmu_src`` (``runtime`` <- ``make`` <- ``host``). Checked on the sources' import statements:
module level, inside functions and under ``TYPE_CHECKING`` alike, so that a cycle hidden by an
import inside a function cannot come back unnoticed.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The project's packages (import names = folders).
PACKAGES = ("tirefric", "lookup", "tire_brush", "fmu_src")
#: package (or sub-package) -> the packages it must not import
FORBIDDEN = {
    "tirefric": ("lookup", "tire_brush", "fmu_src"),
    "lookup": ("tire_brush", "fmu_src"),
    "tire_brush": ("fmu_src",),
    "fmu_src/runtime": ("fmu_src.make", "fmu_src.host"),
    "fmu_src/make": ("fmu_src.host",),
}
#: Modules of plumbing that live in the base package, not in the physics package ``lookup``.
BASE_MODULES = ("errors", "paths", "config", "units")


def _module_name(path: Path, root: Path = ROOT) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path, root: Path | None = None) -> list[str]:
    """Every module a file imports (absolute names; relative imports resolved when ``root``
    is given), wherever the statement stands."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: list[str] = []
    here = _module_name(path, root).split(".") if root is not None else []
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0 and node.module:
                base = node.module
            elif node.level > 0 and root is not None:
                base = ".".join(package[:len(package) - node.level + 1]
                                + ([node.module] if node.module else []))
            else:
                continue
            names.append(base)
            names += [f"{base}.{a.name}" for a in node.names]
    return names


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """Module -> the project modules it imports (a name ``pkg.mod.attr`` counts as ``pkg.mod``;
    importing a package's attribute that is a module counts as that module)."""
    files = [p for pkg in PACKAGES for p in sorted((root / pkg).rglob("*.py"))]
    modules = {_module_name(p, root): p for p in files}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        deps = set()
        for imp in _imports(path, root):
            parts = imp.split(".")
            while parts and ".".join(parts) not in modules:
                parts.pop()
            if parts and ".".join(parts) != name:
                target = ".".join(parts)
                if not (modules[target].name == "__init__.py" and name.startswith(target + ".")):
                    deps.add(target)
        graph[name] = deps
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_imports_point_down_the_flow(package) -> None:
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        for name in _imports(path, ROOT):
            if any(name == f or name.startswith(f + ".") for f in FORBIDDEN[package]):
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
    assert not bad, "\n".join(bad)


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
    assert _imports(f) == ["fmu_src.host", "fmu_src.host.cosim", "fmu_src.make"]


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
