"""Batched section models: the same answers as the section model on the same (template) meshes."""

from __future__ import annotations

import pytest

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.section_model import section_model
from softcath.fem.section_model.batch import BatchItem, section_models
from softcath.fem.section_model.strain import silicone_strain_range
from softcath.studies.sweep.random_designs import random_designs

PER_LOAD = (
    "curvature_per_mm_per_MPa",
    "elongation_per_MPa",
    "lumen_area_change_mm2_per_MPa",
    "fem_formula_ratio",
)
SCALARS = ("EA_N", "EI_N_mm2", "EI_lateral_N_mm2", "coupling_N_mm", "axial_centroid_mm", "lumen_area_mm2")


@pytest.mark.parametrize("coil_bending", ["annulus", "wahl"])
def test_batched_equals_one_by_one_on_the_template_mesh(coil_bending):
    designs = random_designs(5, seed=41) + [design.resolve("paper")]
    items = section_models(designs, coil_bending=coil_bending)
    for d, item in zip(designs, items, strict=True):
        assert isinstance(item, BatchItem)
        ref = section_model(d, coil_bending=coil_bending, keep_fields=True)
        got = item.result
        for name in PER_LOAD:
            for load in ("cap", "lumen"):
                assert getattr(got, name)[load] == pytest.approx(
                    getattr(ref, name)[load], rel=1e-9, abs=1e-14
                )
        for name in SCALARS:
            assert getattr(got, name) == pytest.approx(getattr(ref, name), rel=1e-9)
        assert got.dofs == ref.dofs and got.n_triangles == ref.n_triangles
        assert got.backward_error < 1e-12
        for load in ("cap", "lumen"):
            assert item.strain_range[load] == pytest.approx(silicone_strain_range(ref, load), rel=1e-9)


def test_a_bad_design_is_returned_as_its_error_and_the_others_are_solved():
    good = random_designs(1, seed=43)[0]
    items = section_models([None, good], loads=("lumen",))
    assert isinstance(items[0], Exception)
    assert items[1].result.loads == ("lumen",)
    with pytest.raises(DesignError, match="coil_bending"):
        section_models([good], coil_bending="spring")


def test_as_built_designs_are_solved_as_built_next_to_batched_ones():
    """A non-default assembly is not the bonded kernel's problem: the batch hands it to the
    per-design section model (interfaces split, axial groups), whose answer it returns."""
    from dataclasses import replace

    from softcath.design.assembly import Assembly

    paper = design.resolve("paper")
    sliding = replace(
        paper, assembly=Assembly(tube_coil="sliding", channel_coil="sliding", filler_coil="sliding")
    )
    coat = replace(paper, assembly=Assembly(filler="coat"))
    designs = [sliding, random_designs(1, seed=53)[0], coat]
    items = section_models(designs, loads=("lumen",))
    for d, item in zip(designs, items, strict=True):
        ref = section_model(d, loads=("lumen",), keep_fields=True)
        got = item.result
        assert got.assembly == d.assembly.to_dict()
        assert got.axial_groups == ref.axial_groups
        assert got.curvature_per_mm_per_MPa["lumen"] == pytest.approx(
            ref.curvature_per_mm_per_MPa["lumen"], rel=1e-9
        )
        assert got.EI_N_mm2 == pytest.approx(ref.EI_N_mm2, rel=1e-9)
        assert item.strain_range["lumen"] == pytest.approx(silicone_strain_range(ref, "lumen"), rel=1e-9)
    assert items[0].result.axial_groups == 2
    # the interfaces matter, so the batch did not solve the sliding tip as the bonded one
    bonded = section_models([paper], loads=("lumen",))[0].result
    assert items[0].result.curvature_per_mm_per_MPa["lumen"] != pytest.approx(
        bonded.curvature_per_mm_per_MPa["lumen"], rel=1e-3
    )


def test_chunked_assembly_gives_the_same_answers(monkeypatch):
    """Designs of one template are assembled CHUNK at a time (memory); the answers do not depend on it."""
    from softcath.fem.section_model import batch

    designs = random_designs(4, seed=41) + [design.resolve("paper")] * 3
    whole = section_models(designs, loads=("lumen",))
    monkeypatch.setattr(batch, "CHUNK", 2)
    chunked = section_models(designs, loads=("lumen",))
    for a, b in zip(whole, chunked, strict=True):
        assert b.result.curvature_per_mm_per_MPa == pytest.approx(
            a.result.curvature_per_mm_per_MPa, rel=1e-12
        )
        assert b.strain_range["lumen"] == pytest.approx(a.strain_range["lumen"], rel=1e-12)


def test_a_design_that_fails_in_a_shared_chunk_fails_alone(monkeypatch):
    """Designs of one template are factorised one after the other and condensed together; a
    failure in either step is that design's error, and its chunk-mates get their answers alone."""
    from dataclasses import replace

    import numpy as np

    from softcath.fem.section_model import batch

    paper = design.resolve("paper")
    silicone = paper.tube.material
    designs = [  # one section geometry, so one template and one chunk
        replace(
            paper, name=f"paper {k}", tube=replace(paper.tube, material=replace(silicone, youngs_modulus=k))
        )
        for k in (1.0, 2.0, 3.0, 4.0)
    ]
    alone = [section_models([d])[0] for d in designs]
    spd_factor, condense = batch._Kernel.spd_factor, batch._condense

    class SecondFails:  # the chunk's second factorisation fails
        def __init__(self, factor):
            self.factor, self.calls = factor, 0

        def factorise(self, data):
            self.calls += 1
            if self.calls == 2:
                raise RuntimeError("injected factorisation failure")
            self.factor.factorise(data)

        def solve(self, rhs):
            return self.factor.solve(rhs)

    def fourth_singular(kernel, ops, ok, *args, **kwargs):
        if 3 in ok:
            raise np.linalg.LinAlgError("injected singular section stiffness")
        return condense(kernel, ops, ok, *args, **kwargs)

    failing = {}
    monkeypatch.setattr(
        batch._Kernel, "spd_factor", lambda self: failing.setdefault(id(self), SecondFails(spd_factor(self)))
    )
    monkeypatch.setattr(batch, "_condense", fourth_singular)
    items = section_models(designs)
    assert isinstance(items[1], RuntimeError) and isinstance(items[3], np.linalg.LinAlgError)
    for k in (0, 2):
        got, ref = items[k], alone[k]
        assert got.result.curvature_per_mm_per_MPa == pytest.approx(
            ref.result.curvature_per_mm_per_MPa, rel=1e-12
        )
        for load, extremes in ref.strain_range.items():
            assert got.strain_range[load] == pytest.approx(extremes, rel=1e-12)
