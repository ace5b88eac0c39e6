"""Design rankings under different coil models."""

from __future__ import annotations

import numpy as np
import pytest

from softcath import design
from softcath.fem.section_model import section_model
from softcath.studies.coil_ranking import COIL_SWEEP, random_coil_designs, rank_by_coil_model


@pytest.fixture(scope="module")
def designs():
    return random_coil_designs(5, seed=3)


@pytest.fixture(scope="module")
def ranking(designs):
    return rank_by_coil_model(designs, models=("annulus", "resolved", "coil-bound"), top=2)


def test_random_designs_are_valid_close_wound_and_seeded(designs):
    again = random_coil_designs(5, seed=3)
    assert [d.coil.outer_diameter for d in again] == [d.coil.outer_diameter for d in designs]
    for d in designs:
        for path, (lo, hi) in COIL_SWEEP.items():
            part, field = path.split(".")
            assert lo <= getattr(getattr(d, part), field) <= hi
        assert d.coil.close_wound and d.channel.close_wound


def test_gains_are_the_section_models(designs, ranking):
    d = designs[1]
    assert ranking.gains["annulus"][1] == pytest.approx(
        section_model(d).curvature_per_mm_per_MPa["lumen"], rel=1e-12
    )
    # Coil-bound concave sides stiffen every design: less curvature than the same linear coils.
    assert np.all(ranking.gains["coil-bound"] < ranking.gains["resolved"])


def test_rank_statistics(ranking):
    # Spearman = Pearson correlation of the ranks (no ties among real gains).
    def ranks(x):
        return np.argsort(np.argsort(x)).astype(float)

    for (a, b), rho in ranking.spearman.items():
        assert rho == pytest.approx(
            np.corrcoef(ranks(ranking.gains[a]), ranks(ranking.gains[b]))[0, 1], rel=1e-12
        )
        top_a, top_b = set(ranking.order(a)[:2]), set(ranking.order(b)[:2])
        assert ranking.top_overlap[(a, b)] == len(top_a & top_b) / 2
    assert set(ranking.spearman) == {
        ("annulus", "resolved"),
        ("annulus", "coil-bound"),
        ("resolved", "coil-bound"),
    }
    g = ranking.gains["annulus"]
    assert ranking.order("annulus")[0] == ranking.designs[int(np.argmax(g))]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"models": ("annulus", "spring")}, "models"),
        ({"models": ("annulus",)}, "models"),
        ({"top": 9}, "top"),
    ],
)
def test_bad_options(designs, kwargs, match):
    with pytest.raises(design.DesignError, match=match):
        rank_by_coil_model(designs[:3], **kwargs)


def test_impossible_ranges_name_the_parameter():
    with pytest.raises(design.DesignError, match="ranges"):
        random_coil_designs(2, ranges={"coil.wire_diameter": (0.5, 0.6)}, max_tries=2)
