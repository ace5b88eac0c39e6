"""One spelling a keyword: pressure arrays are ``pressures`` [MPa], never ``pressures_MPa``.

The unit is the package's (MPa) and is said in docstrings; the old spelling lives on only in
the deprecation shim (``softcath.core.deprecation``, applied by decorator) and in file formats
(the sweep TOML key, JSON keys, CSV columns), which are strings, not Python names.
"""

from __future__ import annotations

import ast

from tests.codebase_scan import modules, parsed, relative

RETIRED = {"pressures_MPa": "pressures"}
#: The shim maps the old spelling; it names it only as a string.
SHIM = "core/deprecation.py"


def _names(tree: ast.AST) -> list[tuple[int, str]]:
    """``(line, name)`` of every function parameter and class field (annotated class attribute)."""
    names: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            a = node.args
            every = a.posonlyargs + a.args + a.kwonlyargs + [v for v in (a.vararg, a.kwarg) if v]
            names += [(arg.lineno, arg.arg) for arg in every]
        elif isinstance(node, ast.ClassDef):  # dataclass (and NamedTuple, TypedDict) fields
            names += [
                (s.lineno, s.target.id)
                for s in node.body
                if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)
            ]
    return names


def test_no_parameter_or_field_uses_a_retired_keyword():
    found, scanned = [], 0
    for _, path in modules():
        if relative(path) == SHIM:
            continue
        names = _names(parsed(path))
        scanned += len(names)
        found += [f"{relative(path)}:{line}: {n}" for line, n in names if n in RETIRED]
    assert scanned > 5000  # guards the scan against finding nothing
    assert found == [], f"rename to {RETIRED} (old callers go through softcath.core.deprecation)"


def test_the_scan_finds_a_retired_parameter_and_field():
    tree = ast.parse(
        "def f(p, *, pressures_MPa=None): ...\n"
        "class C:\n    pressures: tuple\n    pressures_MPa: tuple\n"
        "g = lambda pressures_MPa: 0\n"
    )
    assert [(line, n) for line, n in _names(tree) if n in RETIRED] == [
        (1, "pressures_MPa"),
        (4, "pressures_MPa"),
        (5, "pressures_MPa"),
    ]
