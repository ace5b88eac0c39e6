"""Shared scans of the package's source for the codebase tests (``tests/test_codebase_*.py``).

The package is ``src/softcath`` with the rooms linked in; every scan walks it as users import it
and reports paths relative to the checkout (the rooms' real locations).
"""

from __future__ import annotations

import ast
import functools
import os
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "softcath"


@functools.cache
def modules() -> tuple[tuple[str, Path], ...]:
    """``(dotted name, real path)`` of every module of the package, ``__init__`` as its package."""
    return tuple(_walk())


@functools.cache
def _module_names() -> frozenset[str]:
    return frozenset(name for name, _ in modules())


@functools.cache
def parsed(path: Path) -> ast.Module:
    """The syntax tree of the module at ``path`` (parsed once per test session)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _walk() -> Iterator[tuple[str, Path]]:
    for folder, dirs, files in sorted(os.walk(PACKAGE, followlinks=True)):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for file in sorted(f for f in files if f.endswith(".py")):
            path = Path(folder) / file
            parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            yield ".".join(parts), path.resolve()


def relative(path: Path) -> str:
    """``path`` relative to the checkout (``fem/api.py``, ``src/softcath/__init__.py``)."""
    return str(path.relative_to(ROOT))


def _absolute(node: ast.ImportFrom, module: str, is_package: bool) -> str:
    """The absolute module a ``from ... import`` names (relative imports resolved)."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def softcath_imports(module: str, path: Path) -> Iterator[tuple[ast.stmt, list[str], bool]]:
    """Each ``softcath`` import of ``module``: the node, the modules it names, and whether it is
    function-local (its nearest enclosing scope is a function).

    ``from a import b`` names ``a.b`` when that is a module, else ``a``. Imports under
    ``if TYPE_CHECKING:`` are not run and are left out.
    """
    known = _module_names()
    is_package = path.name == "__init__.py"
    tree = parsed(path)

    def names(node) -> list[str]:
        if isinstance(node, ast.Import):
            return [a.name for a in node.names if a.name.split(".")[0] == "softcath"]
        target = _absolute(node, module, is_package)
        if target.split(".")[0] != "softcath":
            return []
        out = []
        for a in node.names:
            sub = f"{target}.{a.name}"
            out.append(sub if sub in known else target)
        return sorted(set(out))

    def walk(node, in_function: bool):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                continue
            if isinstance(child, ast.Import | ast.ImportFrom):
                found = names(child)
                if found:
                    yield child, found, in_function
            scope = in_function or isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda)
            yield from walk(child, scope)

    yield from walk(tree, False)


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def public_classes() -> Iterator[tuple[str, str, Path, int]]:
    """``(class name, module, real path, line)`` of every public class: defined at a module's top,
    its name not starting with ``_`` (the command line's included)."""
    for name, path in modules():
        for node in parsed(path).body:
            if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                yield node.name, name, path, node.lineno
