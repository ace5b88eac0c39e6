"""The section model as built against the 3-D linear FEM with the same options.

The 3-D FEM (``softcath.fem.interfaces3d``) splits its regions and ties the normal
component like the section model, but it has the ends: every body clamped at the base,
the sealed cap, and reads the mid-span curvature. For interfaces that slide along the
whole tip the middle is a Saint-Venant zone (measured curvature variation along it
< 0.5 %), so the two agree to their discretisation and end-zone errors: measured
0.1-0.9 % on these designs; 3 % as asked of the as-built models.

Not asserted, and documented in docs/as-built.md: a sliding tube-channel interface and
``tied-at-tip`` without filler. There the 3-D curvature varies by 2-9 % along the middle
of the 5 mm tip (end zones reach mid-span) and the section model's uniform state is
4-25 % off; the thin coat with a sliding tube on random designs is 3.6-4.9 % off (cap).
"""

from __future__ import annotations

from dataclasses import replace

import pytest

from softcath import design
from softcath.design.assembly import Assembly
from softcath.fem.interfaces3d import run_tip_as_built
from softcath.fem.section_model import section_model

pytestmark = pytest.mark.slow

SLIDING = Assembly(tube_coil="sliding", channel_coil="sliding", filler_coil="sliding")


def _designs():
    from softcath.studies.sweep.random_designs import random_designs

    return [design.preset("paper"), *random_designs(3, seed=5)]


def test_sliding_coil_paper_and_random_designs_within_3_percent():
    for d0 in _designs():
        d = replace(d0, assembly=SLIDING)
        ref = run_tip_as_built(d)
        s = section_model(d)
        for ld in ("cap", "lumen"):
            assert s.curvature_per_mm_per_MPa[ld] == pytest.approx(ref[ld][0], rel=0.03), (d.name, ld)


def test_coat_paper_design_within_3_percent():
    d = replace(design.preset("paper"), assembly=Assembly(filler="coat"))
    ref = run_tip_as_built(d)
    s = section_model(d)
    for ld in ("cap", "lumen"):
        assert s.curvature_per_mm_per_MPa[ld] == pytest.approx(ref[ld][0], rel=0.03), ld
