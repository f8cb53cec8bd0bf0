"""The project's import graph, read from the sources (module level, inside functions and
under ``TYPE_CHECKING`` alike): used by the layering test (direction, cycles) and by the
mutation check (which tests are nearest a mutated file)."""

from __future__ import annotations

import ast
from collections import deque
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The project's packages (import names = folders).
PACKAGES = ("tirefric", "lookup", "tire_brush", "fmu_src")


def module_name(path: Path, root: Path = ROOT) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports(path: Path, root: Path | None = None) -> list[str]:
    """Every module a file imports (absolute names; relative imports resolved when ``root``
    is given), wherever the statement stands."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: list[str] = []
    here = module_name(path, root).split(".") if root is not None else []
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
    modules = {module_name(p, root): p for p in files}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        deps = set()
        for imp in imports(path, root):
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




def distances_to(target: str, graph: dict[str, set[str]]) -> dict[str, int]:
    """How many import steps each module is from ``target`` (0 for itself, 1 for the modules
    that import it, ...); modules that do not depend on it are left out."""
    users: dict[str, set[str]] = {}
    for m, deps in graph.items():
        for d in deps:
            users.setdefault(d, set()).add(m)
    dist = {target: 0}
    todo = deque([target])
    while todo:
        m = todo.popleft()
        for u in users.get(m, ()):
            if u not in dist:
                dist[u] = dist[m] + 1
                todo.append(u)
    return dist
