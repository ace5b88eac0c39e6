"""No tier is chosen by comparing its name outside the registry: consumers read capabilities.

The library (every room but ``models``, which is the registry, and the tests) is parsed with
:mod:`ast`; a comparison with a string literal that names a tier (``model == "paper"``,
``tier != "fem"``, ``model in ("paper", "section")``, ``"section" in evaluators``) is a tier
chosen by name. The files listed in :data:`ALLOWED` still hold such comparisons and are
owned elsewhere; each is to move onto the registry's capabilities.
"""

from __future__ import annotations

import ast
from pathlib import Path

from softcath import models

ROOT = Path(__file__).resolve().parents[2]
ROOMS = ("analytic", "cli", "design", "fem", "hardware", "studies", "virtualbench", "src/softcath")
NAMES = frozenset(models.names())

#: Files with remaining comparisons, by path -> count (owned by the command line and the app).
ALLOWED = {
    "cli/analytic.py": 4,  # --model section|paper: check_assembly, the section branch, the paper block
    "cli/calibrate.py": 3,  # args.model == "section": the calibration's load and fit
    "cli/discrepancy.py": 1,  # --reference fem needs data
    "cli/optimise.py": 1,  # the default load by model (Tier.default_load)
    "cli/options.py": 2,  # --model fem / --compare fem need the FEM (Tier.slow)
    "cli/predict.py": 1,  # --nonlinear needs --model section
    "cli/section_overlay.py": 2,  # the overlay's curves by tier
    "cli/select.py": 3,  # the tiers a selection's robust pass can run (optimise.MODELS)
    "studies/app/layout.py": 1,  # the FEM panel
    "studies/app/page.py": 1,  # the fast section curve
    "studies/sweep/spec.py": 6,  # the section options table, the FEM's, the paper's formula always on
    "studies/outputs/analytic.py": 4,  # the command's files, moved from cli/analytic.py
    "studies/outputs/discrepancy.py": 1,
    "studies/outputs/overlay.py": 2,
    "studies/outputs/selection.py": 3,
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
