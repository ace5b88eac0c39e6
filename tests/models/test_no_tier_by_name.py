"""No tier is chosen by comparing its name outside the registry: consumers read capabilities.

The library (every room but ``models``, which is the registry, and the tests) is parsed with
:mod:`ast`; a comparison with a string literal that names a tier (``model == "paper"``,
``tier != "fem"``, ``model in ("paper", "section")``, ``"section" in evaluators``) is a tier
chosen by name. The one file in :data:`ALLOWED` compares a string that is not a tier there.
"""

from __future__ import annotations

import ast
from pathlib import Path

from softcath import models

ROOT = Path(__file__).resolve().parents[2]
ROOMS = ("analytic", "cli", "design", "fem", "hardware", "studies", "virtualbench", "src/softcath")
NAMES = frozenset(models.names())

#: Files whose comparisons with a tier's name are not tier choices, by path -> count.
ALLOWED = {
    "hardware/vision/dispatch.py": 1,  # "paper" is a vision method there (the paper's detector), not a tier
}


def _literals(node: ast.AST) -> list[str]:
    """The tier names among the string literals of ``node`` (a constant or a tuple/list/set of them)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value] if node.value in NAMES else []
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [n for e in node.elts for n in _literals(e)]
    return []


def tier_comparisons(source: str) -> list[tuple[int, str]]:
    """(line, tier name) of each comparison of a tier's name in ``source``."""
    hits = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            for side in (node.left, *node.comparators):
                hits += [(node.lineno, n) for n in _literals(side)]
    return hits


def _library_files():
    for room in ROOMS:
        for path in sorted((ROOT / room).rglob("*.py")):
            if path.is_symlink() or any(
                p.is_symlink() for p in path.relative_to(ROOT).parents if p != Path(".")
            ):
                continue
            yield path


def test_the_scan_sees_a_comparison_by_name():
    assert tier_comparisons('if model == "paper":\n    pass\n') == [(1, "paper")]
    assert tier_comparisons('x = m in ("section", "other")') == [(1, "section")]
    assert tier_comparisons('x = "fem" in evaluators') == [(1, "fem")]
    assert tier_comparisons('x = {"paper": 1}["paper"]') == []  # a lookup is data, not a choice


def test_no_tier_is_chosen_by_name_outside_the_registry():
    found = {}
    for path in _library_files():
        rel = path.relative_to(ROOT).as_posix()
        hits = tier_comparisons(path.read_text(encoding="utf-8"))
        if hits:
            found[rel] = hits
    unexpected = {k: v for k, v in found.items() if k not in ALLOWED}
    assert not unexpected, (
        f"tiers chosen by name (read a capability of softcath.models instead): {unexpected}"
    )
    grown = {k: v for k, v in found.items() if len(v) > ALLOWED[k]}
    assert not grown, f"more comparisons by tier name than allowed: {grown}"
    stale = {k: n for k, n in ALLOWED.items() if len(found.get(k, [])) != n}
    assert not stale, f"allowed comparisons no longer there (shrink ALLOWED): {stale}"
