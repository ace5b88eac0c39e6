"""The section model's as-built options: defaults unchanged, axial groups, the coat geometry."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from softcath import design
from softcath.design.assembly import Assembly
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import CHANNEL, COIL, FILLER, TUBE, VOID
from softcath.fem.section_model import section_model
from softcath.fem.section_model.as_built import axial_plan

LABELS = (COIL, TUBE, CHANNEL, FILLER)


def test_all_bonded_through_the_split_path_is_the_default_to_round_off():
    d = design.preset("paper")
    ref = section_model(d)
    # tube-free with every interface bonded: the as-built path, nothing released.
    r = section_model(replace(d, assembly=Assembly(proximal="tube-free")))
    assert r.axial_groups == 1 and ref.axial_groups == 1
    for ld in ("cap", "lumen"):
        assert r.curvature_per_mm_per_MPa[ld] == pytest.approx(ref.curvature_per_mm_per_MPa[ld], rel=1e-10)
    assert r.EI_N_mm2 == pytest.approx(ref.EI_N_mm2, rel=1e-10)
    assert r.assembly["proximal"] == "tube-free" and ref.assembly == Assembly().to_dict()


@pytest.mark.parametrize(
    ("options", "groups", "carrier"),
    [
        ({}, 1, TUBE),
        ({"filler_coil": "sliding", "tube_coil": "sliding", "channel_coil": "sliding"}, 2, TUBE),
        # tied at the tip and clamped at the base: no average slip, one group
        ({"filler_coil": "tied-at-tip", "tube_coil": "tied-at-tip", "channel_coil": "tied-at-tip"}, 1, TUBE),
        # the tube free at the base: its cap force goes to the coil it is tied to at the tip
        (
            {
                "filler": "none",
                "tube_coil": "tied-at-tip",
                "tube_channel": "sliding",
                "proximal": "tube-free",
            },
            2,
            COIL,
        ),
        # tube-free but tied at the tip to nothing: the tube keeps its own cap force
        (
            {"filler": "none", "tube_coil": "sliding", "tube_channel": "sliding", "proximal": "tube-free"},
            2,
            TUBE,
        ),
    ],
)
def test_axial_groups_and_the_cap_carrier(options, groups, carrier):
    a = Assembly(**options)
    plan = axial_plan(a, LABELS if a.filler != "none" else (COIL, TUBE, CHANNEL))  # the mesh's labels
    assert plan.n_groups == groups
    assert plan.cap_share.sum() == 1.0 and plan.cap_share[plan.group[carrier]] == 1.0


def test_coat_keeps_filler_only_near_the_channel_and_the_default_digest_is_unchanged():
    d = design.preset("paper")
    g_full = geometry_from_design(d)
    g_coat = geometry_from_design(replace(d, assembly=Assembly(filler="coat", filler_coat_thickness=0.03)))
    g_none = geometry_from_design(replace(d, assembly=Assembly(filler="none")))
    assert g_full.filler_coat == 0.0 and g_coat.filler_coat == 0.03 and not g_none.filled
    x = np.linspace(-0.3, 0.3, 241)
    xx, yy = np.meshgrid(x, x)
    lab = g_coat.classify(xx.ravel(), yy.ravel())
    r = np.hypot(xx.ravel(), yy.ravel() - g_coat.channel_y)
    assert (r[lab == FILLER] < g_coat.channel_outer_radius + 0.03 + 1e-12).all()
    assert (g_none.classify(xx.ravel(), yy.ravel()) != FILLER).all()
    assert (lab == VOID).any()
    # the fully filled geometry keeps the digest (and the mesh caches) it had before the option
    assert g_full.digest() != g_coat.digest()
    import hashlib
    import json
    from dataclasses import asdict

    old = {k: v for k, v in asdict(g_full).items() if k != "filler_coat"}
    blob = json.dumps(old, sort_keys=True, separators=(",", ":"))
    assert g_full.digest() == hashlib.sha256(blob.encode()).hexdigest()[:16]
