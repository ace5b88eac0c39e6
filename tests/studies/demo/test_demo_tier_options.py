"""A tier option given to the demo (``--model-option``) changes that tier's numbers in the demo.

The cheapest demo path that shows the section tiers is the large-bends section without the 3-D
FEM (``--no-fem``: the formula, the linear and the finite-strain section models). Each number the
demo reports is checked against the section models solved directly with the option (their own
functions, not the tiers' plumbing), and against the physics the option stands for.
"""

from __future__ import annotations

import json
import math
import re
from typing import cast

import numpy as np
import pytest
from scipy.optimize import brentq

from softcath import design
from softcath.cli.main import main
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import section_curve
from softcath.studies.demo.large_bends import DEMO_SECTION_CURVE_PRESSURES_MPA, four_tiers
from softcath.studies.report.html_blocks import fmt


def _linear_section_p90(d, **options) -> float:
    """The linear section model's pressure for 90 degrees under the lumen load, solved directly."""
    r = section_model(d, loads=("lumen",), **options)
    root = brentq(lambda p: float(r.response(p, "lumen").bend_angle) - math.pi / 2, 0.0, 100.0, xtol=1e-12)
    return cast(float, root)  # full_output=False: the root alone


def _row(html: str, name: str) -> list[str]:
    m = re.search(rf"<tr><td>{re.escape(name)}</td>((?:<td>[^<]*</td>)+)</tr>", html)
    assert m, f"no row {name!r} in the demo's table"
    return re.findall(r"<td>([^<]*)</td>", m.group(1))


def test_a_section_option_changes_the_linear_section_numbers_of_the_demo(tmp_path):
    out = tmp_path / "demo"
    args = ["demo", "paper", "--only", "large_bends", "--no-fem", "--out", str(out)]
    assert main([*args, "--model-option", "section.silicone_poisson=0.45"]) == 0
    html = (out / "index.html").read_text(encoding="utf-8")
    assert json.loads((out / "demo.json").read_text())["model_options"] == {
        "section": {"silicone_poisson": 0.45}
    }
    d = design.preset("paper")
    default, soft = _linear_section_p90(d), _linear_section_p90(d, silicone_poisson=0.45)
    # The lumen load bends the tip through the wall pressure too, because the coil confines nearly
    # incompressible silicone: a more compressible silicone (nu 0.45, not 0.49) loses much of that,
    # so the linear section needs 35 % more pressure for 90 degrees (1.87 against 1.38 MPa).
    assert soft > 1.2 * default
    p90 = _row(html, "linear section model")[0]
    assert p90 == fmt(fmt(soft, 3)) != fmt(fmt(default, 3))  # the tier's batched solve, to 3 digits
    # the finite-strain section model has no option given: its default number stays
    fs = section_curve(d, DEMO_SECTION_CURVE_PRESSURES_MPA, load="lumen", linear_gain=False)
    reached = float(np.degrees(fs.bend_angle_rad[-1]))
    assert _row(html, "finite-strain section model (tip angle)")[2] == fmt(fmt(reached, 3))


def test_a_finite_strain_section_option_reaches_the_four_tiers(tmp_path):
    d = design.preset("paper")
    opts = {"section-nonlinear": {"tube_prestretch": 1.2}}
    rows, extra = four_tiers(d, None, tmp_path / "tiers.png", options=opts)
    name, p90, p_last, angle_last = next(r for r in rows if r[0].startswith("finite-strain"))
    direct = section_curve(
        d, DEMO_SECTION_CURVE_PRESSURES_MPA, load="lumen", linear_gain=False, tube_prestretch=1.2
    )
    default = section_curve(d, DEMO_SECTION_CURVE_PRESSURES_MPA, load="lumen", linear_gain=False)
    assert p_last == DEMO_SECTION_CURVE_PRESSURES_MPA[-1]
    # the same Newton walk as the solver's own call with the option (its rounding only)
    assert angle_last == pytest.approx(np.degrees(direct.bend_angle_rad[-1]), rel=1e-9)
    # a tube pre-stretched by 20 % as built is axially stiffer and pre-tensioned: the tip bends
    # far less (76 against 111 degrees at 1 MPa) and no longer reaches 90 degrees in range
    assert angle_last < 0.8 * np.degrees(default.bend_angle_rad[-1])
    assert p90 is None and extra["p90"][name] is None
    # the other tiers take no option here: the formula's 90-degree pressure is its own
    formula = next(r for r in rows if r[0].startswith("paper"))
    assert formula[1] == four_tiers(d, None, tmp_path / "t0.png")[1]["p90"][formula[0]]
