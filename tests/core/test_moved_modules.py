"""Modules moved in the last refactor: the old import paths still work, warning where the names went."""

from __future__ import annotations

import importlib
import re
import types
import warnings

import pytest

from softcath.core.deprecation import moved_names

#: Old module -> (its new place, the names the old module exported).
MOVED = {
    "softcath.fem.nonlinear.laws": (
        "softcath.fem.hyperelastic.laws",
        (
            "Yeoh",
            "AnisotropicSVK",
            "neo_hookean",
            "isotropic_from_young",
            "yeoh_at_modulus",
            "transversely_isotropic",
            "isotropic_tensor",
        ),
    ),
    "softcath.fem.nonlinear.tensors": (
        "softcath.fem.hyperelastic.tensors",
        ("LEVI_CIVITA", "det", "cofactor", "dcofactor"),
    ),
    "softcath.models.response": ("softcath.core.response", ("OBSERVABLES", "ResponseBatch", "TipResponse")),
    "softcath.studies.selection.criteria": (
        "softcath.studies.criteria",
        (
            "Constraint",
            "Objective",
            "at_pressure",
            "parse_constraint",
            "parse_objective",
            "check_columns",
            "rows_at",
            "without_text",
        ),
    ),
    "softcath.studies.selection.expressions": (
        "softcath.studies.criteria.expressions",
        (
            "SelectionError",
            "Expr",
            "COMPARE",
            "MAX_EXPR_CHARS",
            "MAX_EXPR_DEPTH",
            "check_tree",
            "parse_tree",
            "parse_expr",
            "finite_constant",
            "op_name",
            "short",
        ),
    ),
    "softcath.studies.sweep.section_eval": (
        "softcath.models.section_eval",
        ("SECTION_KEYS", "SECTION_OPTIONS", "section_blocks_many", "section_columns"),
    ),
    "softcath.studies.sweep.section_nonlinear_eval": (
        "softcath.models.section_nonlinear_eval",
        ("REST_PROBE_MPA", "SECTION_NONLINEAR_KEYS", "curve_with_rest", "section_nonlinear_columns"),
    ),
}

CASES = [(old, new, name) for old, (new, names) in MOVED.items() for name in names]


@pytest.mark.parametrize("old", sorted(MOVED))
def test_importing_an_old_module_alone_is_silent(old):
    # the API reference and the import checks walk every module: only a use may warn
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        module = importlib.import_module(old)
    assert not any(name in vars(module) for name in MOVED[old][1])  # served, never copied


@pytest.mark.parametrize(("old", "new", "name"), CASES)
def test_an_old_name_warns_with_the_new_place_and_is_the_same_object(old, new, name):
    module = importlib.import_module(old)
    with pytest.warns(DeprecationWarning, match=re.escape(f"moved to {new} (import {name} from there)")):
        value = getattr(module, name)
    assert value is getattr(importlib.import_module(new), name)


def test_from_import_of_an_old_path_warns_at_the_importer():
    with pytest.warns(DeprecationWarning, match=r"softcath\.core\.response") as record:
        from softcath.models.response import TipResponse
    from softcath.core.response import TipResponse as new

    assert TipResponse is new
    assert record[0].filename == __file__  # the import machinery's frames are skipped


def test_moved_names_refuses_unknown_and_missing_names():
    new = types.ModuleType("pkg.new")
    new.Thing = object()  # pyright: ignore[reportAttributeAccessIssue]  # a module made on the spot
    module_getattr = moved_names("pkg.old", new, ("Thing",))
    with pytest.raises(AttributeError, match="module 'pkg.old' has no attribute 'Other'"):
        module_getattr("Other")
    with pytest.raises(ValueError, match=r"names = \['Gone'\]: not in pkg\.new"):
        moved_names("pkg.old", new, ("Thing", "Gone"))


def test_the_old_response_module_leaves_the_models_response_function_alone():
    from softcath import models
    from softcath.models.registry import response

    importlib.import_module("softcath.models.response")
    assert models.response is response  # a submodule of that name must not shadow the function
