"""``docs/design-file.md`` is generated from the design dataclasses and lists the bounds they enforce."""

from __future__ import annotations

import copy
from dataclasses import fields
from pathlib import Path

import pytest

from softcath import design
from softcath.design.reference import FIELD_DOCS, TABLES, design_file_reference

ROOT = Path(__file__).parents[2]
PAGE = ROOT / "docs" / "design-file.md"


def test_the_committed_page_is_the_generated_one():
    assert PAGE.read_text(encoding="utf-8") == design_file_reference(), (
        "docs/design-file.md is out of date: run python -m softcath.design.reference docs/design-file.md"
    )


def test_every_field_of_every_table_is_documented_and_nothing_else():
    for cls, docs in FIELD_DOCS.items():
        assert set(docs) == {f.name for f in fields(cls)}, cls.__name__
        for name, doc in docs.items():
            assert doc.unit in {"mm", "MPa", "N", "-"} and doc.bound and doc.meaning, (cls.__name__, name)
    assert {cls for _, cls, _ in TABLES if cls is not None} == set(FIELD_DOCS)
    page = design_file_reference()
    for header, cls, _ in TABLES:
        assert f"## `{header}`" in page
        for f in fields(cls) if cls is not None else ():
            assert f"| `{f.name}` |" in page


def test_the_page_is_in_the_docs_toctree():
    assert "\ndesign-file\n" in (ROOT / "docs" / "index.md").read_text(encoding="utf-8")


def _paper_table() -> dict:
    table = design.to_dict(design.preset("paper"))
    table["tube"].update(design.preset("paper").tube_shape)  # the explicit shape, to probe a, a_int, ...
    return table


def _positive_fields():
    """(table path, field) of every number documented as "> 0" in the paper design's tables."""
    table = _paper_table()
    parts = {"coil": design.Coil, "channel": design.Coil, "tube": design.Tube, "tip": design.Tip}
    out = [(part, name) for part, cls in parts.items() for name, doc in FIELD_DOCS[cls].items()]
    out += [(f"materials.{m}", name) for m in table["materials"] for name in FIELD_DOCS[design.Material]]
    return [(p, n) for p, n in out if _doc(p, n).bound.startswith("> 0") or ", > 0" in _doc(p, n).bound]


def _doc(path: str, name: str):
    cls = {"coil": design.Coil, "channel": design.Coil, "tube": design.Tube, "tip": design.Tip}.get(
        path, design.Material
    )
    return FIELD_DOCS[cls][name]


@pytest.mark.parametrize(("path", "name"), _positive_fields())
def test_a_documented_positive_bound_is_enforced_naming_the_field(path, name):
    table = copy.deepcopy(_paper_table())
    node = table
    for key in path.split("."):
        node = node[key]
    node[name] = 0.0
    with pytest.raises(design.DesignError) as info:
        design.from_dict(table)
    assert info.value.parameter == f"{path}.{name}" and "> 0" in info.value.bound


@pytest.mark.parametrize(
    ("path", "value", "bound", "documented"),
    [
        ("coil.outer_diameter", 12.5, "<= 12", "<= 12 (36 Fr)"),
        ("tip.bending_length", 201.0, "<= 200", "<= 200 |"),
        ("materials.ecoflex_00_30.poisson_ratio", 0.5, "(-1, 0.5)", "in (-1, 0.5)"),
        ("assembly.filler", "glued", "one of full, coat, none", "one of `full`, `coat`, `none`"),
    ],
)
def test_documented_limits_are_the_validators(path, value, bound, documented):
    table = copy.deepcopy(_paper_table())
    *heads, last = path.split(".")
    node = table
    for key in heads:
        node = node.setdefault(key, {})
    node[last] = value
    with pytest.raises(design.DesignError) as info:
        design.from_dict(table)
    assert info.value.parameter == path and bound in info.value.bound
    assert documented in design_file_reference()
