"""The finite-strain section model of the tip as built.

Peers:

* the linear as-built section model on the same split mesh, ties and axial groups: the
  finite-strain model's small-load limit. Two measures: the rest state's tangent (the
  linear gain, no load nonlinearity: equal to round-off, measured <= 5e-12 relative,
  bound 1e-9) and the secant at 1e-3 MPa, which carries the load's own nonlinearity:
  measured 6.6e-4 relative for the bonded default (the existing path) and 5.6e-4 to
  1.4e-3 for the as-built variants (the tip without filler is softest, so its bend per
  pressure is largest), bound 0.5 %, ~3.5x the largest;
* the bonded section's own problem: the as-built machinery given the default assembly
  (every interface tied in full, one axial group) must walk to the same large-bend state,
  to the Newton tolerance (relative residual 1e-6; measured 1e-9 on the unknowns).
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import pytest

from softcath import design, models
from softcath.design.assembly import Assembly
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import section_curve, section_laws
from softcath.fem.section_model.finite_strain.as_built import as_built_problem, split_section
from softcath.fem.section_model.finite_strain.discretisation import discretise
from softcath.fem.section_model.finite_strain.lumen import lumen_wall
from softcath.fem.section_model.finite_strain.newton import Loading, SectionProblem, walk
from softcath.fem.section_model.mesh import catheter_section_mesh

ALL_SLIDING = {k: "sliding" for k in ("tube_coil", "tube_channel", "channel_coil", "filler_coil")}

#: The variants of the brief plus a tube-free tip whose tube is its own axial group and the cap
#: force goes to the coil-channel group it is tied to at the tip (three axial groups in all: two).
VARIANTS = {
    "tube_coil sliding": {"tube_coil": "sliding"},
    "all sliding": ALL_SLIDING,
    "tied-at-tip, tube-free": {
        "tube_coil": "tied-at-tip",
        "tube_channel": "tied-at-tip",
        "proximal": "tube-free",
    },
    "filler none": {"filler": "none"},
    "filler coat": {"filler": "coat"},
    "no filler, tube-free carrier": {
        "filler": "none",
        "tube_coil": "tied-at-tip",
        "tube_channel": "tied-at-tip",
        "channel_coil": "sliding",
        "proximal": "tube-free",
    },
    "all sliding, no filler": {**ALL_SLIDING, "filler": "none"},
}


def _without_yeoh(d):
    """Silicones without a Yeoh fit: the finite-strain laws' linearisation is exactly the linear
    model's (as in the bonded small-load test)."""
    filler = None if d.filler is None else replace(d.filler, yeoh=None)
    tube = replace(d.tube, material=replace(d.tube.material, yeoh=None))
    return replace(d, tube=tube, filler=filler)


def _paper(**assembly):
    return replace(_without_yeoh(design.preset("paper")), assembly=Assembly(**assembly))


@pytest.mark.parametrize("name", list(VARIANTS))
def test_small_load_is_the_linear_as_built_model(name):
    d = _paper(**VARIANTS[name])
    p = 1e-3
    lin = section_model(d, loads=("lumen",))
    c = section_curve(d, [p])  # the linear model's mesher: the same mesh
    kappa, eps = lin.gains("lumen")
    assert c.linear_curvature_per_mm_per_MPa == pytest.approx(kappa, rel=1e-9)
    assert c.curvature_per_mm[0] / p == pytest.approx(kappa, rel=5e-3)
    assert c.elongation[0] / p == pytest.approx(eps, rel=5e-3)
    slip = c.interface_slip_per_element
    assert slip is not None
    assert slip.shape == (1,) and np.isfinite(slip).all() and 0.0 <= slip[0] < 1e-2


def test_the_variants_are_different_tips():
    """The as-built options change the answer (the comparison above is not of one tip seven times)."""
    gains = {n: section_model(_paper(**a), loads=("lumen",)).gains("lumen")[0] for n, a in VARIANTS.items()}
    base = section_model(_paper(), loads=("lumen",)).gains("lumen")[0]
    assert all(abs(g / base - 1) > 1e-3 for g in gains.values())
    assert section_model(_paper(**VARIANTS["all sliding, no filler"]), loads=("lumen",)).axial_groups == 3


def test_the_bonded_tip_through_the_as_built_machinery_is_the_bonded_section():
    d = _paper()
    section = catheter_section_mesh(geometry_from_design(d))
    laws = section_laws(d)
    silicone = (TUBE, FILLER)
    disc = discretise(section, laws)
    bonded = SectionProblem(disc, lumen_wall(section, disc), disc.pinned, silicone)
    split, tie, plan = split_section(section, Assembly(tube_coil="sliding"))
    split, tie = split, np.zeros_like(tie)  # every interface tied in full: the bonded tip, split
    sdisc = discretise(split.mesh, laws)
    tied = as_built_problem(split, tie, plan, sdisc, lumen_wall(split.mesh, sdisc), silicone=silicone)
    assert tied.n_groups == 1
    loading = Loading(pressure=0.6, load="lumen")
    a = walk(bonded, loading, [0.5, 1.0])[-1]
    b = walk(tied, loading, [0.5, 1.0])[-1]
    ga, gb = a.q[disc.n_u :], b.q[tied.n_hat :]
    assert gb == pytest.approx(ga, rel=1e-6, abs=1e-9)
    assert ga[2] > 0.05  # a large bend [1/mm], far from the linear range
    assert tied.slip_ratio(b.q) == 0.0


def test_a_sliding_tip_at_0_6_MPa_reports_its_slip():
    d = _paper(tube_coil="sliding")
    c = section_curve(d, [0.0, 0.2, 0.4, 0.6], mesher="gmsh")
    bonded = section_curve(_paper(), [0.6], mesher="gmsh", linear_gain=False)
    slip = c.interface_slip_per_element
    assert slip is not None
    assert slip.shape == (4,) and slip[0] == 0.0
    assert np.all(np.diff(slip) > 0)  # grows with the bend
    assert slip[-1] < 0.5  # inside the small-sliding limit on the paper tip
    assert c.bend_angle_rad[-1] > 0.5 and abs(c.curvature_per_mm[-1] / bonded.curvature_per_mm[0] - 1) > 1e-3
    assert c.to_json()["interface_slip_per_element"] == pytest.approx(slip.tolist())
    assert bonded.interface_slip_per_element is None


def test_an_as_built_tip_on_the_template_path_is_solved_on_the_reference_path(caplog):
    d = _paper(filler="coat")
    with caplog.at_level(logging.INFO, logger="softcath.fem.section_model.finite_strain.curve"):
        c = section_curve(d, [0.1], linear_gain=False)
    routed = [r for r in caplog.records if "reference path" in r.getMessage()]
    assert len(routed) == 1 and "coat" in routed[0].getMessage()
    assert c.interface_slip_per_element is not None and c.curvature_per_mm[0] > 0


def test_the_section_nonlinear_tier_answers_a_tip_as_built():
    """The tier sweeps, predict and the model bank ask: an as-built design is its own tip there."""
    d = _paper(tube_coil="sliding")
    tier = models.get("section-nonlinear")
    assert tier.as_built
    tier.check_assembly(d.assembly)  # modelled: no refusal
    r = models.response(d, [0.0, 0.3], tier="section-nonlinear", load="lumen")
    c = section_curve(d, [0.0, 0.3], linear_gain=False)
    bonded = models.response(_paper(), [0.3], tier="section-nonlinear", load="lumen")
    assert r.curvature_per_mm == pytest.approx(c.curvature_per_mm, rel=1e-12)
    assert abs(r.curvature_per_mm[-1] / bonded.curvature_per_mm[0] - 1) > 1e-3
