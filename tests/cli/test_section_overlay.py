"""``softcath section A B ...``: several designs' bend curves in one table and one picture, each value the
single-design run's (same model, same options, same formatting), each curve labelled with its design,
tier and load."""

from __future__ import annotations

import csv
import json
import math
import re

import pytest

from softcath import design


def _variant(tmp_path):
    """A valid edit of the paper design (an offset tube), as a design file."""
    d = design.preset("paper")
    v = d.with_tube_shape(**{**d.tube_shape, "h": 0.02})
    path = tmp_path / "offset.toml"
    path.write_text(design.dumps(v.__class__(**{**v.__dict__, "name": "offset tube"})))
    return path


def _rows(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


@pytest.mark.parametrize("nonlinear", [False, True], ids=["section", "section-nonlinear"])
def test_the_overlay_is_the_single_design_runs(cli, tmp_path, nonlinear):
    other = _variant(tmp_path)
    extra = ["--nonlinear"] if nonlinear else []
    pressures = "0.3,0.1:0.2:2" if not nonlinear else "0.1,0.3"
    r = cli("section", "paper", other, "--pressure", pressures, *extra, "--out", tmp_path / "o")
    assert r.status == 0
    tier = "section-nonlinear" if nonlinear else "section"
    rows = _rows(tmp_path / "o" / "overlay.csv")
    assert {(x["design"], x["tier"], x["load"]) for x in rows} == {
        ("paper", tier, "lumen"),
        ("offset tube", tier, "lumen"),
    }
    for name, src in (("paper", "paper"), ("offset tube", other)):
        single = tmp_path / f"single-{name}"
        assert cli("section", src, "--pressure", pressures, *extra, "--no-png", "--out", single).status == 0
        mine = [x for x in rows if x["design"] == name]
        ref = _rows(single / "section.csv")
        assert len(mine) == len(ref) == (3 if not nonlinear else 2)
        for a, b in zip(mine, ref, strict=True):
            for col in ("pressure_MPa", "curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm"):
                assert a[col] == b[col], (name, col)
            assert float(a["bend_angle_deg"]) == pytest.approx(math.degrees(float(b["bend_angle_rad"])))
        assert f"{name} [{tier}, lumen load]" in r.out
    doc = json.loads((tmp_path / "o" / "overlay.json").read_text())
    assert [x["label"] for x in doc["designs"]] == ["paper", "offset tube"]
    assert doc["tier"] == tier and doc["load"] == "lumen"
    assert (tmp_path / "o" / "overlay.png").read_bytes()[:4] == b"\x89PNG"


def test_the_overlay_takes_the_load_and_labels_a_shared_name_by_its_file(cli, tmp_path):
    copy = tmp_path / "paper_copy.toml"
    copy.write_text(design.dumps(design.preset("paper")))
    r = cli(
        "section", "paper", copy, "--load", "cap", "--pressure", "0.2", "--no-png", "--out", tmp_path / "o"
    )
    assert r.status == 0
    rows = _rows(tmp_path / "o" / "overlay.csv")
    assert [x["design"] for x in rows] == ["paper (paper)", f"paper ({copy})"]
    assert {x["load"] for x in rows} == {"cap"} and rows[0]["curvature_per_mm"] == rows[1]["curvature_per_mm"]
    assert "cap load" in r.out and not (tmp_path / "o" / "overlay.png").exists()


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (("--coil-bound",), r"--coil-bound = True: is taken with one design only"),
        (("--pressure", "0:x:3"), "--pressure = '?0:x:3'?"),
        ((), "DESIGN = 'paper': is given twice"),
    ],
)
def test_the_overlay_refuses_by_name(cli, tmp_path, extra, message):
    second = "paper" if not extra else _variant(tmp_path)
    r = cli("section", "paper", second, *extra, "--out", tmp_path / "o")
    assert r.status == 2
    assert r.error_line().startswith("softcath section: error: ")
    assert re.search(message, r.error_line()), r.error_line()
