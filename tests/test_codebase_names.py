"""One name per concept: no two public classes of the package share a name.

Two classes of one name (two ``BendCurve`` records, an ``Assembly`` of the design and another of a
solver's residual) make a reader, a search and the API reference guess which one is meant.
"""

from __future__ import annotations

from collections import defaultdict

from tests.codebase_scan import public_classes, relative


def test_no_two_public_classes_share_a_name():
    where: dict[str, list[str]] = defaultdict(list)
    for name, _module, path, line in public_classes():
        where[name].append(f"{relative(path)}:{line}")
    assert len(where) > 100  # guards the scan against finding nothing
    shared = {name: places for name, places in sorted(where.items()) if len(places) > 1}
    assert shared == {}, "rename one of each (a name that says what it is):\n" + "\n".join(
        f"{name}: {', '.join(places)}" for name, places in shared.items()
    )


def test_the_result_records_have_one_name_each():
    names = {name for name, *_ in public_classes()}
    assert {"TipResponse", "NonlinearFemCurve", "BilinearCoilCurve", "SectionCurve"} <= names
    assert "BendCurve" not in names  # a deprecated alias only (module __getattr__), never a class
