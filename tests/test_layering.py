"""Dependency direction (docs/design.md): imports point down the flow only.

``lookup`` imports neither ``tire_brush`` nor ``fmu_src``; ``tire_brush`` does not import
``fmu_src``; inside ``fmu_src`` imports run ``host -> make -> runtime``. Checked on the
sources' import statements (module level and inside functions), so that a run-time cycle
cannot come back unnoticed.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: package (or sub-package) -> the packages it must not import
FORBIDDEN = {
    "lookup": ("tire_brush", "fmu_src"),
    "tire_brush": ("fmu_src",),
    "fmu_src/runtime": ("fmu_src.make", "fmu_src.host"),
    "fmu_src/make": ("fmu_src.host",),
}


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.append(node.module)
            names += [f"{node.module}.{a.name}" for a in node.names]
    return names


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_imports_point_down_the_flow(package) -> None:
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        for name in _imports(path):
            if any(name == f or name.startswith(f + ".") for f in FORBIDDEN[package]):
                bad.append(f"{path.relative_to(ROOT)} imports {name}")
    assert not bad, "\n".join(bad)


def test_the_check_sees_a_forbidden_import(tmp_path) -> None:
    """The checker itself: an import of fmu_src inside a function is found."""
    f = tmp_path / "m.py"
    f.write_text("def g():\n    from fmu_src.host import cosim\n    import fmu_src.make\n")
    assert _imports(f) == ["fmu_src.host", "fmu_src.host.cosim", "fmu_src.make"]


def test_a_study_with_fmu_abs_needs_a_simulator_handed_to_it(tmp_path) -> None:
    """The braking study is handed its FMU simulator (no entry-point lookup): without one, a
    study that asks for the ABS through the FMU is refused with a message naming the field."""
    from dataclasses import replace

    from lookup.errors import InputError
    from tire_brush.braking.study import load_study, run_study

    spec = load_study("abs_default")
    with pytest.raises(InputError, match=r"study\.fmu_abs"):
        run_study(replace(spec, fmu_abs=True))
