"""The design package: preset, as-assembled section, coil homogenisation, TOML, bad input."""

import math

import numpy as np
import pytest

from softcath import design
from softcath.design.section import lumen_containment, max_outer_semi_axis, paper_frame_reading


@pytest.fixture(scope="module")
def paper():
    return design.preset("paper")


def test_paper_section_is_tangent_to_coil_and_channel(paper):
    s = paper.section
    # b = (coil ID - channel OD)/2 = (0.6 - 0.3)/2
    assert s.b == pytest.approx(0.15, abs=1e-15)
    # top of the tube touches the coil ID; bottom touches the channel's top
    assert s.tube_center_y + s.b == pytest.approx(s.coil_inner_radius, abs=1e-15)
    assert s.tube_center_y - s.b == pytest.approx(s.channel_center_y + s.channel_outer_radius, abs=1e-15)
    # the channel touches the coil ID at the bottom
    assert s.channel_center_y - s.channel_outer_radius == pytest.approx(-s.coil_inner_radius, abs=1e-15)


def test_catalogue_tube_does_not_fit_and_the_design_says_so(paper):
    assert not paper.catalogue_fits
    report = paper.fit_report()
    assert report.startswith("note: the catalogue tube is squeezed to fit") and "0.9 mm" in report
    assert "NOT" not in report  # a squeezed tube is a note on a valid design, not a failure


def test_nominal_rule_fills_the_width_and_keeps_the_lumen_ratio(paper):
    s = paper.section
    assert s.a == pytest.approx(math.sqrt(0.3 * 0.15), rel=1e-14)
    assert s.a_int / s.a == pytest.approx(0.5, rel=1e-14)
    assert s.b_int / s.b == pytest.approx(0.5, rel=1e-14)
    assert s.h == 0.0


@pytest.mark.parametrize("radius,b", [(0.3, 0.15), (1.0, 0.2), (0.5, 0.49), (2.0, 1.0)])
def test_inscribed_bound_matches_brute_force(radius, b):
    """a² ≤ R·b is exactly the condition for the ellipse to stay inside the coil circle."""
    a_max = max_outer_semi_axis(coil_inner_radius=radius, b=b)
    phi = np.linspace(0, 2 * np.pi, 200_001)

    def max_radius(a):
        return np.max(np.hypot(a * np.cos(phi), radius - b + b * np.sin(phi)))

    assert max_radius(a_max * (1 - 1e-4)) <= radius * (1 + 1e-12)
    assert max_radius(a_max * (1 + 1e-3)) > radius


def test_paper_optimum_only_fits_when_h_is_read_from_the_catheter_bottom():
    r = paper_frame_reading()
    assert r["h_local"] == pytest.approx(0.0, abs=1e-12)  # concentric lumen
    assert r["a_excess_fraction"] == pytest.approx(0.23 / math.sqrt(0.045) - 1, rel=1e-12)
    assert 0.003 < r["protrusion_mm"] < 0.004  # pokes ~3.4 µm into the coil wire
    # read in the local frame (h from the tube centre) it is rejected with the bound named
    base = design.preset("paper")
    with pytest.raises(design.DesignError, match=r"tube\.h.*\|h\| must be <="):
        base.with_tube_shape(a=0.21, a_int=0.12, b_int=0.12, h=0.55)


def test_lumen_containment_exact_max_matches_sampling():
    rng = np.random.default_rng(1)
    phi = np.linspace(0, 2 * np.pi, 100_001)
    for _ in range(50):
        a, b = rng.uniform(0.1, 0.3, 2)
        a_int, b_int = rng.uniform(0.01, 0.1, 2)
        h, t = rng.uniform(-0.05, 0.05), 0.01
        x, y = a_int * np.cos(phi), h + b_int * np.sin(phi)
        brute = np.max((x / (a - t)) ** 2 + (y / (b - t)) ** 2)
        assert lumen_containment(a, b, a_int, b_int, h, t) == pytest.approx(brute, rel=1e-8)


def test_coil_stiffness_against_spring_formulas(paper):
    c = design.coil_stiffness(paper.coil)
    d, p, mean_d = 0.1, 0.1, 0.7
    g = 193000.0 / (2 * 1.29)
    # spring rate of a 10 mm coil, k = G d⁴ / (8 D³ n), n = L/p, must equal E_t A / L
    length = 10.0
    k = g * d**4 / (8 * mean_d**3 * (length / p))
    area = math.pi * (0.4**2 - 0.3**2)
    assert c.axial_modulus_tension * area / length == pytest.approx(k, rel=1e-12)
    # Wahl: EI = p E I_w / (π R (2 + ν))
    assert c.bending_stiffness == pytest.approx(
        p * 193000.0 * math.pi * d**4 / 64 / (math.pi * 0.35 * 2.29), rel=1e-12
    )
    # close-wound: wire fraction π/4; compression and hoop stiffer than tension by orders of magnitude
    assert c.wire_fraction == pytest.approx(math.pi / 4)
    assert c.axial_modulus_compression / c.axial_modulus_tension > 1e4


def test_toml_round_trip(paper, tmp_path):
    path = design.save(paper, tmp_path / "p.toml")
    assert design.load(path) == paper
    shaped = paper.with_tube_shape(a=0.2, a_int=0.12, b_int=0.09, h=0.02)
    assert design.loads(design.dumps(shaped)) == shaped
    from dataclasses import replace

    void = replace(paper, filler=None)
    again = design.loads(design.dumps(void))
    assert again == void and again.filler is None


def test_initial_tension_defaults_to_zero_and_round_trips(paper, tmp_path):
    from dataclasses import replace

    assert paper.coil.initial_tension == 0.0 and paper.channel.initial_tension == 0.0
    assert paper.coil.close_wound
    wound = replace(paper, coil=replace(paper.coil, initial_tension=0.02))
    text = design.dumps(wound)
    assert "initial_tension = 0.02" in text
    assert design.loads(text) == wound
    table = design.to_dict(paper)
    del table["coil"]["initial_tension"]  # older design files leave it out
    assert design.from_dict(table).coil.initial_tension == 0.0


def _paper_dict():
    return design.to_dict(design.preset("paper"))


BAD = [
    (
        lambda d: d["coil"].update(inner_diameter=0.9),
        r"coil\.inner_diameter = 0\.9: must be < outer_diameter",
    ),
    (lambda d: d["tube"].update(catalogue_inner_diameter=0.6), r"tube\.catalogue_inner_diameter = 0\.6"),
    (lambda d: d["tip"].update(bending_length=-5.0), r"tip\.bending_length = -5: must be > 0"),
    (lambda d: d["coil"].update(colour="red"), r"coil\.colour = 'red': unknown key"),
    (lambda d: d.update(extra={}), r"extra = \{\}: unknown key"),
    (lambda d: d["coil"].update(outer_diameter=float("nan")), r"coil\.outer_diameter = nan: must be finite"),
    (lambda d: d["tip"].update(cap_thickness=float("inf")), r"tip\.cap_thickness = inf: must be finite"),
    (
        lambda d: d["tip"].update(bending_length=1e300),
        r"tip\.bending_length = 1e\+300: magnitude must be <= 1e\+09",
    ),
    (lambda d: d["coil"].update(pitch=1e-300), r"coil\.pitch = 1e-300: must be >= 1e-09"),
    (
        lambda d: d["materials"]["medical_silicone_tubing"].update(poisson_ratio=0.5),
        r"materials\.medical_silicone_tubing\.poisson_ratio = 0\.5: must be in \(-1, 0\.5\)",
    ),
    (
        lambda d: d["materials"]["medical_silicone_tubing"].update(poisson_ratio=-1.2),
        r"poisson_ratio = -1\.2: must be in \(-1, 0\.5\)",
    ),
    (
        lambda d: d["channel"].update(outer_diameter=0.6, inner_diameter=0.3, wire_diameter=0.15, pitch=0.15),
        r"channel\.outer_diameter = 0\.6: must be < coil\.inner_diameter",
    ),
    (lambda d: d["tube"].update(a=0.3, a_int=0.1, b_int=0.05, h=0.0), r"tube\.a = 0\.3: must be <= sqrt"),
    (
        lambda d: d["tube"].update(a=0.2, a_int=0.19, b_int=0.05, h=0.0),
        r"tube\.a_int = 0\.19: must be <= a - min_wall",
    ),
    (lambda d: d["tube"].update(a=0.2), r"tube\.a_int = None: give all of a, a_int, b_int, h"),
    (lambda d: d["coil"].update(material="unobtainium"), r"coil\.material = 'unobtainium': must name one of"),
    (lambda d: d["coil"].update(pitch=0.05), r"coil\.pitch = 0\.05: must be >= wire_diameter"),
    (lambda d: d["coil"].update(initial_tension=-0.1), r"coil\.initial_tension = -0\.1: must be >= 0"),
    (
        lambda d: d["channel"].update(pitch=0.1, initial_tension=0.01),
        r"channel\.initial_tension = 0\.01: must be 0 for an open coil \(pitch = 0\.1 > wire_diameter",
    ),
    (
        lambda d: d["coil"].update(outer_diameter="wide"),
        r"coil\.outer_diameter = 'wide': must be a real number",
    ),
    (lambda d: d.pop("tip"), r"tip = None: table is required"),
    (lambda d: d["coil"].pop("outer_diameter"), r"coil\.outer_diameter = None: is required"),
]


@pytest.mark.parametrize("mutate,message", BAD)
def test_impossible_designs_name_parameter_value_and_bound(mutate, message):
    data = _paper_dict()
    mutate(data)
    with pytest.raises(design.DesignError, match=message):
        design.from_dict(data)


def test_bad_toml_syntax_is_a_design_error(tmp_path):
    f = tmp_path / "x.toml"
    f.write_text("[coil\nouter = ")
    with pytest.raises(design.DesignError, match="is not valid TOML"):
        design.load(f)


def test_resolve_rejects_unknown_names():
    with pytest.raises(design.DesignError, match="must be a preset"):
        design.resolve("no-such-design")
