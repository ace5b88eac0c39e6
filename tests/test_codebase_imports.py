"""Imports you can see: no import cycle among softcath's modules, few imports hidden in functions.

A module's dependencies are read from its top. An import inside a function hides one (and
often a cycle it would otherwise close); the only good reason left for one is a heavy optional
dependency path that ``import softcath`` and ``softcath --help`` must not pay for. Each such
import is listed in :data:`ALLOWED_LAZY` with its reason, and it still counts as an edge of the
import graph: a lazy import may defer a load, never hide a cycle.
"""

from __future__ import annotations

import functools
from collections import defaultdict

from tests.codebase_scan import modules, relative, softcath_imports

#: At most 5 % of the package's ``softcath`` imports inside functions, each for a heavy optional
#: dependency path (or a package initialisation order) and saying so.
TARGET_SHARE = 0.05

_NUMBA = "numba compiles its kernels on import: loaded on the first batched solve"
_HELP = "the library loads when a command runs, not for softcath --help"
#: The function-local ``softcath`` imports allowed: (importing module, imported module) -> why it waits.
ALLOWED_LAZY = {
    ("softcath.cli.options", "softcath.design"): _HELP,
    ("softcath.cli.options", "softcath.models"): _HELP,
    ("softcath.cli.options", "softcath.studies.tiers"): _HELP,
    ("softcath.fem.section_model.batch", "softcath.fem.section_model.element_kernel"): _NUMBA,
    ("softcath.fem.section_model.template_kernel", "softcath.fem.section_model.element_kernel"): _NUMBA,
    ("softcath.fem.section_model.template_kernel", "softcath.fem.section_model.spd_factor"): _NUMBA,
    ("softcath.fem.section_model.finite_strain.fast", "softcath.fem.section_model.spd_factor"): _NUMBA,
    ("softcath.fem.nonlinear.body", "softcath.fem.nonlinear.kernel"): _NUMBA,
    (
        "softcath.fem.section_model.finite_strain.fast_curve",
        "softcath.fem.section_model.finite_strain.kernel",
    ): _NUMBA,
    (
        "softcath.fem.section_model.finite_strain.fast_walk",
        "softcath.fem.section_model.finite_strain.kernel",
    ): _NUMBA,
}


@functools.cache
def _scan():
    """The import graph (module-level and function-local imports alike), the function-local
    imports' locations, the total count, and the function-local edges with their locations."""
    graph: dict[str, set[str]] = defaultdict(set)
    local: list[str] = []
    lazy: dict[tuple[str, str], list[str]] = defaultdict(list)
    total = 0
    for name, path in modules():
        for node, targets, in_function in softcath_imports(name, path):
            total += 1
            graph[name].update(t for t in targets if t != name)
            graph[name].update(p for t in targets for p in _packages_run(t, name))
            if in_function:
                local.append(f"{relative(path)}:{node.lineno}")
                for t in targets:
                    lazy[(name, t)].append(f"{relative(path)}:{node.lineno}")
    return graph, local, total, lazy


def _packages_run(target: str, importer: str) -> list[str]:
    """The packages whose ``__init__`` importing ``target`` runs (its parents below ``softcath``),
    but not the importer's own: those are already being initialised."""
    parts = target.split(".")
    parents = [".".join(parts[:i]) for i in range(2, len(parts))]
    return [p for p in parents if not importer.startswith(p + ".") and importer != p]


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle (as a path ``a -> b -> ... -> a``) per strongly connected component of the graph."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def visit(root: str) -> None:  # Tarjan's algorithm, iterative (deep graphs)
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        components.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return [_a_cycle(graph, set(c)) for c in components]


def _a_cycle(graph: dict[str, set[str]], component: set[str]) -> list[str]:
    """A shortest cycle through the component's first module (breadth-first)."""
    start = min(component)
    parent: dict[str, str] = {}
    queue = [start]
    while queue:
        v = queue.pop(0)
        for w in sorted(graph.get(v, ())):
            if w == start:
                path = [v]
                while path[-1] in parent:
                    path.append(parent[path[-1]])
                return [*reversed(path), start]
            if w in component and w != start and w not in parent:
                parent[w] = v
                queue.append(w)
    raise AssertionError(f"no cycle through {start}")  # a component of one has no cycle


def test_the_cycle_finder_names_a_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set()}
    assert _cycles(graph) == [["a", "b", "c", "a"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle_among_softcath_modules():
    graph, _, _, _ = _scan()
    assert len(graph) > 100  # guards the scan against finding nothing
    cycles = [" -> ".join(c) for c in _cycles(graph)]
    assert cycles == [], "import cycles (move the shared code to a lower floor):\n" + "\n".join(cycles)


def test_function_local_imports_are_edges_of_the_graph():
    graph, _, _, lazy = _scan()
    # a known lazy import (numba) is an edge: a cycle through a function-local import is found
    assert ("softcath.fem.section_model.batch", "softcath.fem.section_model.element_kernel") in lazy
    assert "softcath.fem.section_model.element_kernel" in graph["softcath.fem.section_model.batch"]


def test_function_local_imports_are_the_allowed_ones():
    _, _, _, lazy = _scan()
    unlisted = sorted(
        f"{', '.join(where)} imports {t}" for (m, t), where in lazy.items() if (m, t) not in ALLOWED_LAZY
    )
    assert unlisted == [], (
        "import at the module's top (or list a heavy optional dependency in ALLOWED_LAZY):\n"
        + ("\n".join(unlisted))
    )
    stale = sorted(f"{m} -> {t}" for m, t in ALLOWED_LAZY if (m, t) not in lazy)
    assert stale == [], "no longer imported inside a function: drop from ALLOWED_LAZY"
    assert all(reason.strip() for reason in ALLOWED_LAZY.values())


def test_function_local_imports_stay_few():
    _, local, total, _ = _scan()
    assert total > 500  # guards the scan against finding nothing
    assert len(local) <= TARGET_SHARE * total, (
        f"{len(local)} of {total} softcath imports are inside functions (target {TARGET_SHARE:.0%}); "
        "import at the module's top: " + ", ".join(local[:20])
    )


def test_the_ground_floor_imports_no_room():
    wrong = [
        f"{relative(path)}:{node.lineno} imports {target}"
        for name, path in modules()
        if name.startswith("softcath.core")
        for node, targets, _ in softcath_imports(name, path)
        for target in targets
        if not target.startswith("softcath.core")
    ]
    assert wrong == []
