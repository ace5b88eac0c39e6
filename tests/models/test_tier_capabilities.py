"""The capabilities consumers read instead of a tier's name: each one true of the tiers it names.

``closed_form`` (the paper's formula: no solve, defined for its default load), ``section_mesh``
(the tiers on the 2-D section mesh) and ``finite_strain_tier`` (a linear tier's finite-strain
counterpart). Each is checked against an independent property of the tiers: the formula's
cost and its response, the section tiers' cost per degree of freedom, the counterpart's range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcath import analytic, design, models


def test_the_closed_form_tier_is_the_formula_and_answers_it_under_its_own_load():
    formula = [t for t in models.tiers() if t.closed_form]
    assert [t.name for t in formula] == ["paper"]
    (t,) = formula
    # no mesh and no solve: no cost per degree of freedom, far below a slow tier's time
    assert t.dof_seconds == 0.0 and not t.section_mesh and not t.slow and t.linear
    assert t.default_load == "cap"  # the formula is defined for the end-cap force
    d = design.preset("paper")
    p = np.array([0.1, 0.3])
    r = t.response(d, p)  # its default load
    direct = analytic.response(d, p, load="cap")
    np.testing.assert_allclose(r.curvature_per_mm, direct.curvature, rtol=1e-12)


def test_the_section_mesh_tiers_are_the_ones_priced_by_section_dofs():
    on_mesh = {t.name for t in models.tiers() if t.section_mesh}
    assert on_mesh == {"section", "section-nonlinear"}
    # the same split read off another capability: a cost per section degree of freedom
    assert on_mesh == {t.name for t in models.tiers() if t.dof_seconds > 0}
    assert all(not models.get(n).slow for n in on_mesh)  # a search can run them


def test_a_finite_strain_counterpart_is_a_registered_tier_without_the_small_rotation_limit():
    pairs = {t.name: t.finite_strain_tier for t in models.tiers() if t.finite_strain_tier}
    assert pairs == {"section": "section-nonlinear", "fem": "fem-nonlinear"}
    for linear, finite in pairs.items():
        lin, fs = models.get(linear), models.get(finite)
        assert lin.linear and not fs.linear and math.isinf(fs.valid_to_deg)
        assert lin.section_mesh == fs.section_mesh  # the same model, on the same mesh
        assert fs.finite_strain_tier is None
    assert models.get("paper").finite_strain_tier is None  # the formula has none


@pytest.mark.parametrize("field", ["closed_form", "section_mesh", "finite_strain_tier"])
def test_a_new_tier_gets_the_capabilities_off_by_default(field):
    t = models.Tier("toy", "a toy", "toy", "a toy tier", "toy")
    assert not getattr(t, field)
