"""Ranges files: a design file needs its own, and a malformed one is refused naming the key."""

from __future__ import annotations

import pytest

from softcath.design import presets
from softcath.design.errors import DesignError
from softcath.studies.predict import predict, resolve_ranges


@pytest.fixture
def design_file(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(presets.text("paper"), encoding="utf-8")
    return path


def test_design_file_without_ranges_or_vary_is_refused(design_file):
    with pytest.raises(
        DesignError, match=r"no ranges file for design .*mine\.toml: give ranges to vary or a ranges file"
    ):
        resolve_ranges(design_file)


def test_design_file_with_its_ranges_file(design_file, tmp_path):
    rf = tmp_path / "r.toml"
    rf.write_text(
        '[ranges."materials.medical_silicone_tubing.youngs_modulus"]\nlow = 2.0\nhigh = 3.0\nsource = "test '
        'bounds"\n[ranges."tube.h"]\ndefault = false\nlow = -0.01\nhigh = 0.01\nsource = "off by default"\n',
        encoding="utf-8",
    )
    (r,) = resolve_ranges(design_file, ranges_file=rf)
    assert (r.path, r.low, r.high, r.source) == (
        "materials.medical_silicone_tubing.youngs_modulus",
        2.0,
        3.0,
        "test bounds",
    )
    doc, _ = predict(design_file, model="paper", ranges_file=rf, samples=16)
    assert doc["design"] == "paper" and [x["path"] for x in doc["ranges"]] == [r.path]


@pytest.mark.parametrize(
    ("body", "match"),
    [
        ('[ranges."tube.h"]\nlow = 0\nhigh = 1\nwidth = 2\n', r"ranges\.tube\.h = \['width'\]: unknown keys"),
        ('[ranges."tube.h"]\nlow = 0\nhigh = 1\ndefault = "yes"\n', r"ranges\.tube\.h\.default = 'yes'"),
        (
            '[ranges."tube.h"]\nlow = 0\nhigh = 1\nscale = "log"\n',
            r"ranges\.tube\.h\.scale = 'log': must be one of",
        ),
        ('[ranges."model.coil_modulus"]\nlevels = ["steel"]\n', r"ranges\.model\.coil_modulus\.levels"),
        ("[other]\nx = 1\n", r"needs a non-empty \[ranges\] table"),
        ("[ranges\n", r"is not valid TOML"),
    ],
)
def test_malformed_ranges_file_is_refused(tmp_path, body, match):
    rf = tmp_path / "bad.toml"
    rf.write_text(body, encoding="utf-8")
    with pytest.raises(DesignError, match=match):
        resolve_ranges("paper", ranges_file=rf)
