"""Imports you can see: no import cycle among softcath's modules, few imports hidden in functions.

A module's dependencies are read from its top. An import inside a function hides one (and
often a cycle it would otherwise close); the only good reason left for one is a heavy optional
dependency path that ``import softcath`` and ``softcath --help`` must not pay for.
"""

from __future__ import annotations

import functools
from collections import defaultdict

from tests.codebase_scan import modules, relative, softcath_imports

#: At most 5 % of the package's ``softcath`` imports inside functions, each for a heavy optional
#: dependency path (or a package initialisation order) and saying so.
TARGET_SHARE = 0.05


@functools.cache
def _scan():
    graph: dict[str, set[str]] = defaultdict(set)
    local: list[str] = []
    total = 0
    for name, path in modules():
        for node, targets, in_function in softcath_imports(name, path):
            total += 1
            if in_function:
                local.append(f"{relative(path)}:{node.lineno}")
            else:
                graph[name].update(t for t in targets if t != name)
                graph[name].update(p for t in targets for p in _packages_run(t, name))
    return graph, local, total


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
    graph, _, _ = _scan()
    assert len(graph) > 100  # guards the scan against finding nothing
    cycles = [" -> ".join(c) for c in _cycles(graph)]
    assert cycles == [], "module-level import cycles (move the shared code to a lower floor):\n" + "\n".join(
        cycles
    )


def test_function_local_imports_stay_few():
    _, local, total = _scan()
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
