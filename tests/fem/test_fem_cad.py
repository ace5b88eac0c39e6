"""CadQuery geometry: solids, volumes against the mesh, STEP/STL export."""

from __future__ import annotations

import pytest

from softcath import design
from softcath.design.cad import export_step, export_stl, land_half_widths, solid_volumes
from softcath.fem.adapter import geometry_from_design


def test_land_half_widths_match_the_fem_geometry():
    d = design.preset("paper")
    g = geometry_from_design(d)
    s = d.section
    lands = land_half_widths(
        coil_inner_radius=s.coil_inner_radius,
        channel_outer_radius=s.channel_outer_radius,
        channel_y=s.channel_center_y,
        tube_a=s.a,
        tube_b=s.b,
        tube_y=s.tube_center_y,
    )
    assert lands == g.lands()


@pytest.mark.slow
def test_cad_volumes_step_and_stl(tmp_path):
    import cadquery as cq

    from softcath.fem.mesh import mesh_tip

    d = design.preset("paper")
    cad = solid_volumes(d)
    mesh = mesh_tip(geometry_from_design(d), mesh_size=0.15, cache=tmp_path)
    # Region volumes of the mesh within 1 % of the CAD solids.
    for name, v in cad.items():
        assert mesh.region_volumes[name] == pytest.approx(v, rel=0.01), name
    step = export_step(d, tmp_path / "tip.step")
    text = step.read_text(errors="replace")
    for name in ("coil", "tube", "channel", "filler"):  # one named solid per component
        assert f"'{name}'" in text
    solids = cq.importers.importStep(str(step)).solids().vals()
    # the filler is two pockets (left and right of the tube-channel land): 5 solids
    assert len(solids) == 5
    assert sum(s.Volume() for s in solids) == pytest.approx(sum(cad.values()), rel=1e-6)
    import pyvista as pv

    stl = pv.read(str(export_stl(d, tmp_path / "tip.stl")))
    # closed surfaces: the enclosed volume is the assembly's (2 %: chordal tessellation)
    assert stl.volume == pytest.approx(sum(cad.values()), rel=0.02)


@pytest.mark.slow
def test_helical_coil_option_has_the_wire_volume():
    import math
    from dataclasses import replace

    from softcath.design.cad import build_solids

    d = design.preset("paper")
    d = replace(d, tip=replace(d.tip, bending_length=1.0, cap_thickness=0.3))
    coil = build_solids(d, coil="helix")["coil"].val()
    assert coil.isValid()
    c = d.coil
    # swept circle (0.1 % clearance) along one helix of length L/p turns
    turns = 1.0 / c.pitch
    wire = math.pi * (0.999 * c.wire_diameter / 2) ** 2 * math.hypot(2 * math.pi * c.mean_radius, c.pitch)
    # 0.5 %: the sweep's end faces are cut square to the helix, not to z
    assert coil.Volume() == pytest.approx(wire * turns, rel=0.005)
