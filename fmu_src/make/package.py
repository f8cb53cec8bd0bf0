"""The FMU's private copy of the tirefric modules it runs: closure, renaming, import checks.

Inside an FMU the slave runs in the host's Python interpreter, next to whatever else that
interpreter has loaded: other pythonfmu FMUs, or tirefric itself. So the FMU carries its own
copy of exactly the modules the slave needs, under a package name no one else uses:

* **closure** -- starting from the slave (:mod:`fmu_src.runtime.slave`), follow every
  module-level import of a tirefric package (``tirefric``, ``lookup``, ``tire_brush``,
  ``fmu_src``) and collect the modules and the ``__init__`` of every package on the way;
* **renaming** -- copy them below ``tirefric_fmu_runtime_<code hash>`` (the hash of the copied
  sources: two FMUs built from different tirefric versions can run in one process) and point
  absolute imports of tirefric packages there (``from tirefric.errors import X`` ->
  ``from tirefric_fmu_runtime_<h>.tirefric.errors import X``); relative imports stay as they are;
* **checks** -- every module-level import of the copy must be the standard library, numpy,
  pythonfmu (the slave only) or the copy itself. A module that imports scipy, xarray, casadi,
  matplotlib (or anything else) at module level stops the build with a message naming the module and
  the import: what runs inside an FMU needs numpy and the standard library only (``docs/design.md``,
  "Runtime constraints"). Imports inside functions are rewritten too but only reported: they are not
  executed unless that function is called (e.g. ``load_tire`` reading TOML).

This module runs at build time only.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import sys
from dataclasses import dataclass, field
from pathlib import Path

from tirefric.errors import TirefricError

#: Top-level tirefric packages whose modules may be copied into an FMU.
PROJECT_PACKAGES = ("tirefric", "lookup", "tire_brush", "fmu_src")
#: Third-party packages allowed at module level inside the FMU (pythonfmu: the slave only).
ALLOWED_THIRD_PARTY = ("numpy",)
#: The slave module.
SLAVE_MODULE = "fmu_src.runtime.slave"
#: Prefix of the private package name.
RUNTIME_PREFIX = "tirefric_fmu_runtime"
#: Prefix of the slave module's name inside the FMU.
SLAVE_PREFIX = "tirefric_brush_tire"


class PackagingError(TirefricError):
    """The slave's module closure cannot run inside an FMU (the message says why)."""


@dataclass
class RuntimePackage:
    """The sources that go into the FMU's resources folder.

    Attributes
    ----------
    package : str
        Private package name, ``tirefric_fmu_runtime_<code hash>``.
    slave_module : str
        Module name of the slave inside the FMU (``tirefric_brush_tire_<code hash>``).
    files : dict
        Path relative to the resources folder (POSIX) -> rewritten source text; the slave
        module is at the top level, the rest below ``package/``.
    modules : list of str
        The tirefric modules copied (their names in a source checkout).
    deferred_imports : list of str
        Imports inside functions that point outside the copy ("module: import"): they fail
        if those functions are called inside the FMU.
    code_hash : str
        SHA-256 of the original sources (relative paths and bytes) of the copied modules.
    """

    package: str
    slave_module: str
    files: dict[str, str] = field(default_factory=dict)
    modules: list[str] = field(default_factory=list)
    deferred_imports: list[str] = field(default_factory=list)
    code_hash: str = ""


def _source_path(module: str) -> Path:
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        raise PackagingError(f"cannot find the Python source of module '{module}'")
    return Path(spec.origin)


def _is_package(module: str) -> bool:
    spec = importlib.util.find_spec(module)
    return spec is not None and spec.submodule_search_locations is not None


def _resolve(module: str, node: ast.ImportFrom, is_pkg: bool) -> str:
    """Absolute module name of a ``from ... import`` in ``module``."""
    if node.level == 0:
        return node.module or ""
    parts = module.split(".")
    base = parts if is_pkg else parts[:-1]
    if node.level - 1 > len(base) - 1:
        raise PackagingError(f"{module}: relative import beyond the top-level package")
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _top(name: str) -> str:
    return name.partition(".")[0]


@dataclass
class _Import:
    target: str          # absolute module name imported (or package whose names are taken)
    names: list[str]     # names taken by a from-import ([] for a plain import)
    nested: bool         # inside a function or class body
    node: ast.stmt


def _imports(module: str, tree: ast.Module) -> list[_Import]:
    """Every import statement of a module, resolved to absolute names."""
    is_pkg = _is_package(module)
    out: list[_Import] = []

    def visit(node: ast.AST, nested: bool) -> None:
        # module and class bodies run at import time; function bodies only when called
        for child in ast.iter_child_nodes(node):
            inner = nested or isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef |
                                         ast.Lambda)
            if isinstance(child, ast.Import):
                for a in child.names:
                    out.append(_Import(a.name, [], nested, child))
            elif isinstance(child, ast.ImportFrom):
                out.append(_Import(_resolve(module, child, is_pkg),
                                   [a.name for a in child.names], nested, child))
            else:
                visit(child, inner)

    visit(tree, False)
    return out


def closure(entry: str = SLAVE_MODULE) -> list[str]:
    """tirefric modules (and their packages' ``__init__``) reached by module-level imports.

    Raises
    ------
    PackagingError
        A module-level import of a package that is neither the standard library, numpy,
        pythonfmu (slave only) nor tirefric.
    """
    pending = [entry]
    seen: set[str] = set()
    while pending:
        mod = pending.pop()
        if mod in seen:
            continue
        seen.add(mod)
        parts = mod.split(".")
        pending += [".".join(parts[:k]) for k in range(1, len(parts))]  # parent packages
        tree = ast.parse(_source_path(mod).read_text(encoding="utf-8"), filename=mod)
        for imp in _imports(mod, tree):
            if imp.nested:
                continue
            top = _top(imp.target)
            if top in PROJECT_PACKAGES:
                pending.append(imp.target)
                for n in imp.names:  # `from pkg import submodule`
                    sub = f"{imp.target}.{n}"
                    if n != "*" and importlib.util.find_spec(imp.target) is not None and \
                            _is_package(imp.target) and _module_exists(sub):
                        pending.append(sub)
            elif top == "__future__" or top in sys.stdlib_module_names:
                continue
            elif top in ALLOWED_THIRD_PARTY or (top == "pythonfmu" and mod == entry):
                continue
            else:
                raise PackagingError(
                    f"module '{mod}' imports '{imp.target}' at module level; code that runs "
                    f"inside the FMU may import only numpy and the standard library (move the "
                    f"import into the function that needs it)")
    return sorted(seen)


def _module_exists(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def _rewrite(source: str, module: str, package: str, copied: set[str],
             deferred: list[str]) -> str:
    """Point absolute imports of tirefric packages at ``package``; report deferred ones."""
    tree = ast.parse(source, filename=module)
    lines = source.splitlines(keepends=True)
    edits: list[tuple[int, int, str, str]] = []  # (line index, col, old, new)
    for imp in _imports(module, tree):
        node = imp.node
        if isinstance(node, ast.ImportFrom) and node.level:
            if module == SLAVE_MODULE:
                raise PackagingError(f"{module} line {node.lineno}: the slave module sits at "
                                     f"the top of the FMU's resources; use absolute imports")
            continue
        if _top(imp.target) not in PROJECT_PACKAGES:
            continue
        if imp.target not in copied and not any(f"{imp.target}.{n}" in copied
                                                for n in imp.names):
            if not imp.nested:
                raise PackagingError(f"{module}: import of '{imp.target}' is not in the copy")
            deferred.append(f"{module}: {imp.target}")
        if isinstance(node, ast.Import):
            if any(a.asname is None for a in node.names):
                raise PackagingError(f"{module} line {node.lineno}: write 'from "
                                     f"{imp.target} import ...' (or 'import ... as ...') "
                                     f"so that the FMU copy can rename the package")
            keyword = "import"
        else:
            keyword = "from"
        edits.append((node.lineno - 1, node.col_offset, keyword, imp.target))
    for line, col, keyword, target in sorted(set(edits), reverse=True):
        text = lines[line]
        head = f"{keyword} {target}"
        rest = text[col:]
        if not rest.startswith(head):
            raise PackagingError(f"{module} line {line + 1}: cannot rewrite the import "
                                 f"(expected '{head}' on one line)")
        lines[line] = text[:col] + f"{keyword} {package}.{target}" + rest[len(head):]
    return "".join(lines)


def build_runtime(entry: str = SLAVE_MODULE) -> RuntimePackage:
    """Collect, hash, rename and check the modules the slave needs (module docstring)."""
    modules = closure(entry)
    h = hashlib.sha256()
    sources: dict[str, str] = {}
    for mod in modules:
        src = _source_path(mod).read_text(encoding="utf-8")
        sources[mod] = src
        h.update(mod.encode() + b"\0" + src.encode() + b"\0")
    code_hash = h.hexdigest()
    package = f"{RUNTIME_PREFIX}_{code_hash[:12]}"
    slave_module = f"{SLAVE_PREFIX}_{code_hash[:12]}"
    copied = set(modules)
    rt = RuntimePackage(package=package, slave_module=slave_module, modules=modules,
                        code_hash=f"sha256:{code_hash}")
    for mod in modules:
        text = _rewrite(sources[mod], mod, package, copied, rt.deferred_imports)
        if mod == entry:
            rt.files[f"{slave_module}.py"] = text
            continue
        rel = mod.replace(".", "/") + ("/__init__.py" if _is_package(mod) else ".py")
        rt.files[f"{package}/{rel}"] = text
    rt.files[f"{package}/__init__.py"] = (
        f'"""Private copy of the tirefric modules run by the {slave_module} FMU slave '
        f'(generated by fmu_src.make.package; code {rt.code_hash})."""\n')
    _check_copy(rt, entry)
    rt.deferred_imports = sorted(set(rt.deferred_imports))
    return rt


def _check_copy(rt: RuntimePackage, entry: str) -> None:
    """Every module-level import of the rewritten copy resolves inside it or is allowed."""
    present = {rt.slave_module}
    for rel in rt.files:
        if rel.startswith(rt.package + "/"):
            name = rel[:-3].replace("/", ".")
            present.add(name[:-len(".__init__")] if name.endswith(".__init__") else name)
    for rel, text in rt.files.items():
        tree = ast.parse(text, filename=rel)
        for node in tree.body:
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                targets = [node.module or ""]
            else:
                continue
            for t in targets:
                top = _top(t)
                if top in PROJECT_PACKAGES:
                    raise PackagingError(f"{rel}: import of '{t}' was not renamed")
                if top == rt.package and t not in present and not any(
                        f"{t}.{a.name}" in present for a in node.names):
                    raise PackagingError(f"{rel}: '{t}' is missing from the FMU copy")
