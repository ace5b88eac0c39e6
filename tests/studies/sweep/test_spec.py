"""Sweep specification parsing, variant building and seeded Latin-hypercube sampling."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DesignError
from softcath.studies.sweep import expand, latin_hypercube, load_spec, parse_spec, variant_table
from softcath.studies.sweep.variants import VariantBuilder


def _spec(params: dict, **sweep) -> dict:
    return {"sweep": {"base": "paper", "pressures_MPa": [1.0], **sweep}, "parameters": params}


def test_grid_values_and_factorial_order(small_spec):
    spec = load_spec(small_spec)
    variants = expand(spec)
    assert len(variants) == 12
    # factorial: the first parameter varies slowest
    assert [v["tube.h"] for v in variants[:2]] == [-0.03, -0.03]
    assert [v["tip.bending_length"] for v in variants[:2]] == [4.0, 6.0]
    spec2 = parse_spec(_spec({"tube.h": {"grid": [-0.02, 0.02, 5]}}))
    np.testing.assert_allclose([v["tube.h"] for v in expand(spec2)], np.linspace(-0.02, 0.02, 5), atol=1e-15)


def test_nested_parameter_tables_are_dotted_paths():
    spec = parse_spec(_spec({"tube": {"h": {"values": [0.0]}}, "tip": {"bending_length": {"values": [5.0]}}}))
    assert [p.path for p in spec.parameters] == ["tube.h", "tip.bending_length"]


def test_latin_hypercube_stratified_and_seeded():
    n = 50
    x = latin_hypercube([(0.0, 1.0), (2.0, 4.0)], n, seed=3)
    assert x.shape == (n, 2)
    # exactly one point in each of the n strata of every parameter (the defining LHS property)
    for j, (lo, hi) in enumerate([(0.0, 1.0), (2.0, 4.0)]):
        strata = np.floor((x[:, j] - lo) / (hi - lo) * n).astype(int)
        assert sorted(strata) == list(range(n))
    np.testing.assert_array_equal(x, latin_hypercube([(0.0, 1.0), (2.0, 4.0)], n, seed=3))
    assert not np.allclose(x, latin_hypercube([(0.0, 1.0), (2.0, 4.0)], n, seed=4))


def test_lhs_combined_with_factorial():
    spec = parse_spec(
        {
            **_spec({"tube.h": {"lhs": [-0.02, 0.02]}, "tip.bending_length": {"values": [4.0, 5.0]}}, seed=1),
            "sample": {"n": 7},
        }
    )
    v = expand(spec)
    assert len(v) == 14
    assert [x["tube.h"] for x in v[:7]] == [x["tube.h"] for x in v[7:]]


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (
            {"sweep": {"pressures_MPa": [1.0]}, "parameters": {"tube.zz": {"values": [1]}}},
            r"parameters\.tube\.zz.*not a field",
        ),
        (_spec({"tube.h": {"grid": [0, 1]}}), r"parameters\.tube\.h\.grid.*\[start, stop, count\]"),
        (
            _spec(
                {"tube.h": {"lhs": [0.1, 0.0]}},
            ),
            r"lhs\[1\] = 0: must be > low",
        ),
        (_spec({"tube.h": {"lhs": [0.0, 0.1]}}), r"sample\.n.*required"),
        (
            _spec({"tube.h": {"bogus": [1]}}),
            r"parameters\.tube\.h\.bogus = \[1\]: must be a table with exactly one of grid",
        ),
        (_spec({}, loads=["side"]), r"sweep\.loads"),
        (_spec({}, evaluators=["magic"]), r"sweep\.evaluators"),
        ({"sweep": {"pressures_MPa": []}}, r"sweep\.pressures_MPa"),
        (_spec({}, pressures_MPa=[-1.0]), r"sweep\.pressures_MPa = -1: must be >= 0"),
        (_spec({}, base="nope"), r"sweep\.base = 'nope'"),
        (_spec({}, colour="red"), r"sweep\.colour.*unknown key"),
        ({"sweep": {"pressures_MPa": [1.0]}, "extra": {}}, r"extra.*unknown table"),
    ],
)
def test_bad_spec_names_parameter(data, match):
    with pytest.raises(DesignError, match=match):
        parse_spec(data)


def test_spec_file_errors(tmp_path, spec_writer):
    with pytest.raises(DesignError, match="does not exist"):
        load_spec(tmp_path / "missing.toml")
    bad = spec_writer("[sweep\n")
    with pytest.raises(DesignError, match="not valid TOML"):
        load_spec(bad)


def test_base_path_relative_to_spec(tmp_path, spec_writer):
    design.save(design.preset("paper"), tmp_path / "mine.toml")
    path = spec_writer('[sweep]\nbase = "mine.toml"\npressures_MPa = [1.0]\n')
    assert load_spec(path).base_table["tip"]["bending_length"] == 5.0


def test_dependent_fields_follow_swept_ones():
    spec = parse_spec(_spec({}))
    table = variant_table(spec.base_table, {"coil.outer_diameter": 0.9})
    d = design.from_dict(table)
    # close-wound single layer: wire = (OD - ID)/2, pitch = wire
    assert d.coil.wire_diameter == pytest.approx(0.15) and d.coil.pitch == pytest.approx(0.15)
    # sweeping the wire alone keeps the catheter OD: ID = OD - 2 wire, pitch = wire
    d = design.from_dict(variant_table(spec.base_table, {"coil.wire_diameter": 0.05}))
    assert (d.coil.outer_diameter, d.coil.inner_diameter, d.coil.pitch) == pytest.approx((0.8, 0.7, 0.05))
    d = design.from_dict(
        variant_table(spec.base_table, {"channel.inner_diameter": 0.1, "channel.wire_diameter": 0.1})
    )
    assert d.channel.outer_diameter == pytest.approx(0.3)
    base = design.from_dict(spec.base_table)
    d2 = design.from_dict(variant_table(spec.base_table, {"tube.h": 0.01}))
    assert d2.tube_shape == {**base.tube_shape, "h": 0.01}


def _variants():
    hs = [-0.07, -0.03, 0.0, 0.02, 0.05, 0.06]
    ods = [0.5, 0.8, 0.95]
    e = [2.46, -1.0, 1.0]
    nu = [0.3, 0.49, 0.6]
    for h, od, ee, n in itertools.product(hs, ods, e, nu):
        yield {
            "tube.h": h,
            "coil.outer_diameter": od,
            "materials.medical_silicone_tubing.youngs_modulus": ee,
            "materials.stainless_steel_sus304.poisson_ratio": n,
        }
    yield {"tube.a_int": 0.3}
    yield {"coil.wire_diameter": 0.05}
    yield {"coil.wire_diameter": 0.5}
    yield {"coil.wire_diameter": 0.05, "coil.outer_diameter": 0.9}
    yield {"coil.wire_diameter": 0.05, "coil.inner_diameter": 0.6}
    yield {"coil.wire_diameter": 0.05, "coil.inner_diameter": 0.6, "coil.outer_diameter": 0.8}
    yield {"coil.pitch": 0.2, "coil.outer_diameter": 0.85}
    yield {"channel.wire_diameter": "thick"}
    yield {"channel.outer_diameter": 0.7}
    yield {"tip.cap_thickness": 3.0, "tip.bending_length": 5.0}
    yield {"filler.material": "none", "tube.material": "ecoflex_00_30"}
    yield {"tube.material": "unobtainium"}
    yield {"materials.ecoflex_00_30.poisson_ratio": 0.7, "materials.ecoflex_00_30.youngs_modulus": -2.0}


def test_fast_builder_matches_from_dict():
    """The fast builder is a peer of design.from_dict: same design, or the same error, for every variant."""
    spec = parse_spec(_spec({}))
    builder = VariantBuilder(spec.base_table)
    n_err = 0
    for v in _variants():
        try:
            expected = design.from_dict(variant_table(spec.base_table, v))
        except DesignError as exc:
            n_err += 1
            with pytest.raises(DesignError) as got:
                builder.build(v)
            assert str(got.value) == str(exc)
            continue
        assert builder.build(v) == expected
    assert n_err > 20  # the list exercises many invalid combinations


def test_fem_result_forms_are_read_the_same():
    """The FEM adapter's reader: the same numbers in each accepted result layout give the same rows."""
    from dataclasses import dataclass

    from softcath.studies.sweep.evaluators import fem_records

    @dataclass(frozen=True)
    class Case:  # the layout of one (load, pressure) entry of fem.json
        load: str
        pressure_MPa: float
        curvature_per_mm: float
        elongation: float
        n_elements: int

    cases = [
        Case(ld, p, k * p, 0.01 * p, 99) for ld, k in (("cap", 0.07), ("lumen", 0.03)) for p in (0.5, 1.0)
    ]
    expected = fem_records(cases)
    assert expected[("lumen", 1.0)]["curvature_per_mm"] == pytest.approx(0.03)
    assert expected[("cap", 0.5)]["n_elements"] == 99 and np.isnan(expected[("cap", 0.5)]["max_strain"])
    flat = {
        "load": [c.load for c in cases],
        "pressure_MPa": [c.pressure_MPa for c in cases],
        "curvature_per_mm": [c.curvature_per_mm for c in cases],
        "elongation": [c.elongation for c in cases],
        "n_elements": 99,
    }
    grid = {
        **flat,
        "load": ["cap", "lumen"],
        "pressure_MPa": [0.5, 1.0],
        "curvature_per_mm": np.reshape(flat["curvature_per_mm"], (2, 2)),
    }
    grid["elongation"] = np.reshape(flat["elongation"], (2, 2))
    per_load = {
        "cap": [c for c in cases if c.load == "cap"],
        "lumen": [c for c in cases if c.load == "lumen"],
    }
    for form in (flat, grid, {"cases": cases}, per_load):
        got = fem_records(form)
        assert got.keys() == expected.keys()
        for key, row in expected.items():
            np.testing.assert_equal(got[key], row)
    with pytest.raises(KeyError, match="no curvature_per_mm"):
        fem_records({"something": 1})


@pytest.mark.parametrize("part", ["coil", "channel"])
def test_coil_dimensions_pitch_and_initial_tension_are_sweepable(part):
    """Wire diameter, pitch, initial tension, OD and ID of both coils are sweep paths."""
    base = getattr(design.resolve("paper"), part)
    od, idia, wire, pitch = base.outer_diameter, base.inner_diameter, base.wire_diameter, base.pitch
    cases = [
        ({"wire_diameter": [0.8 * wire]}, {"wire_diameter": 0.8 * wire, "inner_diameter": od - 1.6 * wire}),
        ({"inner_diameter": [idia + 0.01]}, {"wire_diameter": (od - idia - 0.01) / 2}),
        ({"outer_diameter": [od + 0.01]}, {"wire_diameter": (od + 0.01 - idia) / 2}),
        ({"pitch": [1.5 * pitch]}, {"pitch": 1.5 * pitch, "initial_tension": 0.0}),
        ({"initial_tension": [0.0, 0.02]}, {"pitch": pitch}),
    ]
    for params, expected in cases:
        spec = parse_spec(_spec({f"{part}.{k}": {"values": v} for k, v in params.items()}))
        builder = VariantBuilder(spec.base_table)
        for overrides in expand(spec):
            for built in (
                builder.build(overrides),
                design.from_dict(variant_table(spec.base_table, overrides)),
            ):
                coil = getattr(built, part)
                for path, value in overrides.items():
                    assert getattr(coil, path.split(".")[1]) == pytest.approx(value)
                for key, value in expected.items():
                    assert getattr(coil, key) == pytest.approx(value)
                if "wire_diameter" in params or "inner_diameter" in params or "outer_diameter" in params:
                    assert coil.pitch == pytest.approx(coil.wire_diameter)  # stays close-wound
    # An initial tension on an open coil is refused with the path named.
    spec = parse_spec(
        _spec({f"{part}.pitch": {"values": [1.5 * pitch]}, f"{part}.initial_tension": {"values": [0.01]}})
    )
    with pytest.raises(DesignError, match=rf"{part}\.initial_tension = 0\.01: must be 0 for an open coil"):
        VariantBuilder(spec.base_table).build(expand(spec)[0])
