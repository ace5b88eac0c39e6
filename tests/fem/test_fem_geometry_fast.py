"""The geometry's fast paths give what the straightforward computations give."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from softcath import design
from softcath.design.cad import land_half_widths
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import TipGeometry


def _unchecked(g: TipGeometry, **changes) -> TipGeometry:
    """``g`` with ``changes`` and no validation (to ask an invalid geometry's questions)."""
    out = object.__new__(TipGeometry)
    for f in dataclasses.fields(TipGeometry):
        object.__setattr__(out, f.name, changes.get(f.name, getattr(g, f.name)))
    return out


def _lumens(g: TipGeometry, n: int, seed: int):
    """``n`` lumens around ``g``'s, inside, touching and crossing the tube (semi-axes > 0)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a = g.tube_a * rng.uniform(0.05, 1.2)
        b = g.tube_b * rng.uniform(0.05, 1.2)
        y = g.tube_y + g.tube_b * rng.uniform(-0.6, 0.6)
        yield {"lumen_a": a, "lumen_b": b, "lumen_y": y}


@pytest.fixture(scope="module")
def paper_geometry():
    return geometry_from_design(design.preset("paper"))


def test_lumen_inside_test_implies_a_positive_sampled_wall(paper_geometry):
    proven = 0
    for lumen in _lumens(paper_geometry, 400, seed=3):
        g = _unchecked(paper_geometry, **lumen)
        if g._lumen_clearly_inside():
            proven += 1
            assert g.min_lumen_wall() > 0, lumen
    assert 50 < proven < 400  # both branches are exercised


def test_lumen_inside_test_decides_like_the_sampled_wall(paper_geometry):
    """Construction refuses a lumen exactly when the sampled wall is not positive."""
    refused = 0
    for lumen in _lumens(paper_geometry, 200, seed=4):
        sampled_bad = _unchecked(paper_geometry, **lumen).min_lumen_wall() <= 0
        fields = {f.name: getattr(paper_geometry, f.name) for f in dataclasses.fields(TipGeometry)}
        fields.update(lumen)
        if sampled_bad:
            refused += 1
            with pytest.raises(DesignError, match="lumen"):
                TipGeometry(**fields)
        else:
            TipGeometry(**fields)
    assert 10 < refused < 190


def test_lumen_touching_the_tube_is_not_proven_inside(paper_geometry):
    g = paper_geometry
    top = g.tube_y + g.tube_b  # a lumen whose top touches the tube's top
    touching = _unchecked(g, lumen_b=0.5 * g.tube_b, lumen_y=top - 0.5 * g.tube_b, lumen_a=0.3 * g.tube_a)
    assert not touching._lumen_clearly_inside()


def test_lands_are_the_functions_and_a_copy(paper_geometry):
    g = paper_geometry
    want = land_half_widths(
        coil_inner_radius=g.coil_inner_radius,
        channel_outer_radius=g.channel_outer_radius,
        channel_y=g.channel_y,
        tube_a=g.tube_a,
        tube_b=g.tube_b,
        tube_y=g.tube_y,
        land_gap=g.land_gap,
    )
    got = g.lands()
    assert got == want
    got["tube_coil"] = -1.0
    assert g.lands() == want
    other = dataclasses.replace(g, land_gap=0.02)  # a new geometry computes its own
    assert other.lands() != want


def _land_half_widths_sampled(
    *, coil_inner_radius, channel_outer_radius, channel_y, tube_a, tube_b, tube_y, land_gap
):
    """The land half-widths as first written: every gap on all 6001 samples."""
    x = np.linspace(0.0, coil_inner_radius, 6001)
    r_ci, r_co = coil_inner_radius, channel_outer_radius
    ell = tube_b * np.sqrt(np.clip(1 - (x / tube_a) ** 2, 0, None))
    circ = np.sqrt(np.clip(r_ci**2 - x**2, 0, None))
    chan = np.sqrt(np.clip(r_co**2 - x**2, 0, None))
    in_tube, in_chan = x < tube_a, x < r_co
    gaps = {
        "tube_coil": np.where(in_tube, circ - (tube_y + ell), np.inf),
        "tube_channel": np.where(in_tube & in_chan, (tube_y - ell) - (channel_y + chan), np.inf),
        "channel_coil": np.where(in_chan, (channel_y - chan) + circ, np.inf),
    }
    out = {}
    for name, gap in gaps.items():
        ok = gap >= land_gap
        out[name] = float(x[int(np.argmax(ok))]) if ok.any() else float(x[-1])
    return out


def test_land_half_widths_equal_the_full_sampling(paper_geometry):
    g = paper_geometry
    rng = np.random.default_rng(7)
    for i in range(300):
        ri = g.coil_inner_radius * rng.uniform(0.7, 1.3)
        rco = ri * rng.uniform(0.2, 1.1)  # up to a channel wider than the coil's bore
        a = ri * rng.uniform(0.3, 1.2)  # up to a tube wider than the bore
        b = (ri - rco) * rng.uniform(0.3, 1.2)
        kw = {
            "coil_inner_radius": ri,
            "channel_outer_radius": rco,
            "channel_y": -(ri - rco) + rng.normal(0, 1e-3),
            "tube_a": a,
            "tube_b": b,
            "tube_y": rco + rng.normal(0, 1e-3),
            "land_gap": [0.01, 0.0, 1e-6, 0.05, 10.0, np.inf][i % 6],
        }
        assert land_half_widths(**kw) == _land_half_widths_sampled(**kw), kw
