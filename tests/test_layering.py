"""Dependencies between the rooms go one way; real-device code never imports the virtual bench.

Checked on every ``import`` statement in the package's source (module level
and inside functions alike), so a lazy import cannot hide a wrong-way edge.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ROOMS = ("core", "design", "analytic", "fem", "hardware", "virtualbench", "studies", "cli")
# room -> the rooms it may import (besides itself)
ALLOWED = {
    "core": set(),  # the ground floor: errors, atomic outputs, limits, interrupts, plotting
    "design": {"core"},
    "analytic": {"design", "core"},
    "fem": {"design", "analytic", "core"},
    "hardware": {"design", "core"},  # real devices: no models, no virtual bench
    "virtualbench": {"design", "analytic", "hardware", "core"},
    "studies": {"design", "analytic", "fem", "hardware", "virtualbench", "core"},
    "cli": {"design", "analytic", "fem", "hardware", "virtualbench", "studies", "core"},
}


def _imported_rooms(path: Path) -> set[tuple[str, int]]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        else:
            continue
        for name in names:
            parts = name.split(".")
            if parts[0] == "softcath" and len(parts) > 1 and parts[1] in ROOMS:
                found.add((parts[1], node.lineno))
    return found


@pytest.mark.parametrize("room", ROOMS)
def test_room_imports_only_what_lies_below_it(room):
    wrong = [
        f"{path.relative_to(ROOT)}:{line} imports softcath.{other}"
        for path in sorted((ROOT / room).rglob("*.py"))
        for other, line in sorted(_imported_rooms(path))
        if other != room and other not in ALLOWED[room]
    ]
    assert wrong == []


def test_the_layering_has_no_cycle():
    seen: dict[str, int] = {}

    def depth(room: str) -> int:
        if room not in seen:
            seen[room] = -1
            seen[room] = 1 + max((depth(r) for r in ALLOWED[room]), default=0)
        assert seen[room] != -1, f"cycle through {room}"
        return seen[room]

    assert [depth(r) for r in ROOMS] == [1, 2, 3, 4, 3, 4, 5, 6]
