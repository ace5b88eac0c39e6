"""The 3-D FEM tier against its independent peer, the section model, on the same variants (slow)."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from softcath.design import presets
from softcath.studies.predict import Range, predict_tier

TABLE = tomllib.loads(presets.text("paper"))


@pytest.mark.slow
def test_fem_tier_agrees_with_the_section_tier_variant_by_variant():
    # Same seed, same single range -> the same two variants in both tiers. The section model reproduces
    # the 3-D FEM's lumen gain of the paper design to 0.3 % (docs/fem.md); 1 % allows
    # for the FEM's default 0.16 mm mesh at other tube moduli. nu stays 0.49, where both tiers agree.
    ranges = [Range("materials.medical_silicone_tubing.youngs_modulus", low=1.648, high=4.43)]
    fem = predict_tier(TABLE, "fem", ranges, load="lumen", samples=2, seed=9)
    sec = predict_tier(TABLE, "section", ranges, load="lumen", samples=2, seed=9)
    np.testing.assert_allclose(fem.gains, sec.gains, rtol=1e-2)
    assert fem.nominal_gain == pytest.approx(sec.nominal_gain, rel=1e-2)
    assert "skipped" in fem.sensitivity  # two FEM runs cannot give indices, and it says so
