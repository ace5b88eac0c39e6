"""``softcath coil``: resolved-wire coil stiffness of a design's coils, JSON keys, picture, bad input."""

from __future__ import annotations

import json

import pytest

from softcath import design
from softcath.cli.main import main
from softcath.fem.coil import closed_forms as cf
from softcath.fem.coil import coil_wire


def test_coil_writes_json_and_png(tmp_path):
    assert main(["coil", "paper", "--out", str(tmp_path), "--elements-per-turn", "32"]) == 0
    doc = json.loads((tmp_path / "coil.json").read_text())
    assert (tmp_path / "coil.png").stat().st_size > 10_000
    paper = design.resolve("paper")
    for name, coil in (("coil", paper.coil), ("channel", paper.channel)):
        e = doc[name]
        k = design.coil_stiffness(coil)
        geo = {"radius": coil.mean_radius, "pitch": coil.pitch}
        # Against closed forms computed here: the helix energy (chord error 9/m² ≈ 0.9 % at m = 32).
        assert e["axial_tension_N"] == pytest.approx(cf.helix_axial_energy(coil_wire(coil), **geo), rel=0.012)
        assert e["bending_N_mm2"] == pytest.approx(cf.helix_bending_energy(coil_wire(coil), **geo), rel=3e-3)
        assert e["bending_contact_N_mm2"] == pytest.approx(
            cf.pivot_bending(coil_wire(coil), **geo), rel=0.012
        )
        assert e["initial_tension_N"] == 0.0
        ratios = e["ratios"]
        assert ratios["axial_tension/spring_rate_EA"] == pytest.approx(
            e["axial_tension_N"] / (k.axial_modulus_tension * k.area)
        )
        assert ratios["bending/wahl"] == pytest.approx(e["bending_N_mm2"] / k.bending_stiffness)
        assert ratios["bending/annulus_tension_EI"] == pytest.approx(
            e["bending_N_mm2"] / (k.axial_modulus_tension * k.second_moment)
        )
        # Coil-bound: the contact stiffness is set to E·φ, the wire adds < 1 % compliance (or stiffness, the
        # ring).
        assert ratios["axial_compression/coil_bound_EA"] == pytest.approx(1.0, abs=0.01)
        assert e["axial_compression_N"] > 1e3 * e["axial_tension_N"]
        assert e["n_elements"] == 32 and e["seconds"] > 0
        assert set(e["homogenised"]) == {
            "annulus_tension",
            "annulus_bending",
            "spring_wahl",
            "bimodular_annulus",
        }


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["coil", "nope"], "softcath coil: error: design = 'nope'"),
        (["coil", "paper", "--elements-per-turn", "4"], "--elements-per-turn = 4: must be an integer >= 6"),
    ],
)
def test_coil_bad_input_is_one_line(tmp_path, capsys, argv, message):
    assert main([*argv, "--out", str(tmp_path), "--no-png"]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
