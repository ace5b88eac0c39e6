"""The layer rule and the Richardson error estimate of the 3-D bend (fast: closed forms, no 3-D solve)."""

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from softcath import design
from softcath.fem.nonlinear.bend import needs_mixed
from softcath.fem.nonlinear.convergence import (
    MAX_LAYERS,
    MIN_LAYERS,
    coarse_layers,
    default_layers,
    extrapolate,
    layers_for_angle,
    observed_order,
    richardson_error,
)
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.reference import estimate_error


def _model(n, f_inf=0.2, c=-1.7, q=2.6):
    """A quantity converging as f_inf + c (1/n)^q: Richardson is exact on it."""
    return f_inf + c * (1.0 / np.asarray(n, float)) ** q


@pytest.mark.parametrize("layers", [(4, 8, 16), (4, 8, 12), (5, 9, 17)])
def test_observed_order_and_extrapolation_are_exact_on_a_power_law(layers):
    f = _model(layers)
    q = observed_order(f, layers)
    assert q == pytest.approx(2.6, rel=1e-8)
    assert extrapolate(f, layers, q) == pytest.approx(0.2, rel=1e-10)


def test_observed_order_of_the_measured_paper_sequence():
    # paper design, 0.6 MPa, lumen load, mixed: 4 -> 8 -> 12 layers gave 0.1686 -> 0.1944 -> 0.1970 1/mm;
    # by hand: (0.0258 / 0.0026) = (4^-q - 8^-q)/(8^-q - 12^-q) at q = 3.0 (ratio 0.1005 vs 0.1008)
    q = observed_order([0.1686, 0.1944, 0.1970], [4, 8, 12])
    assert q == pytest.approx(3.0, abs=0.05)
    assert extrapolate([0.1686, 0.1944, 0.1970], [4, 8, 12], q) == pytest.approx(0.1981, abs=2e-4)


def test_observed_order_is_nan_without_monotone_convergence():
    assert math.isnan(observed_order([0.1, 0.2, 0.15], [4, 8, 16]))
    assert math.isnan(observed_order([0.1, 0.1, 0.1], [4, 8, 16]))
    assert math.isnan(extrapolate([0.1, 0.2, 0.15], [4, 8, 16], float("nan")))
    with pytest.raises(SettingError, match="layers"):
        observed_order([0.1, 0.2, 0.3], [8, 4, 16])


@pytest.mark.parametrize("n, coarse", [(8, 4), (12, 6), (11, 5)])
def test_richardson_error_is_the_true_error_when_the_order_is_right(n, coarse):
    f, c = _model([n]), _model([coarse])
    true = abs(f - 0.2) / abs(f)
    assert richardson_error(f, c, layers=n, coarse_layers=coarse, order=2.6) == pytest.approx(true, rel=1e-10)


def test_richardson_error_refuses_bad_meshes_and_orders():
    with pytest.raises(SettingError, match="coarse_layers"):
        richardson_error([1.0], [1.0], layers=4, coarse_layers=4)
    with pytest.raises(SettingError, match="order"):
        richardson_error([1.0], [1.0], layers=8, coarse_layers=4, order=0.0)
    assert np.isnan(richardson_error([0.0], [0.1], layers=8, coarse_layers=4)).all()


def test_estimate_error_per_pressure_from_two_curves():
    p = np.array([0.3, 0.6])
    fine = SimpleNamespace(layers=12, pressure=p, curvature_mid=_model([12, 12]) * p)
    coarse = SimpleNamespace(layers=6, pressure=p, curvature_mid=_model([6, 6]) * p)
    e = estimate_error(fine, coarse, order=2.6)
    exact = _model(12) - 0.2
    assert e.relative == pytest.approx(np.abs(exact / _model(12)) * np.ones(2), rel=1e-10)
    assert e.extrapolated == pytest.approx(0.2 * p, rel=1e-10)
    doc = e.to_json()
    assert doc["quantity"] == "curvature_mid_per_mm" and doc["coarse_layers"] == 6
    assert "Richardson" in doc["method"] and "assumed" in doc["method"]
    with pytest.raises(SettingError, match="pressure"):
        estimate_error(fine, SimpleNamespace(layers=6, pressure=p[:1], curvature_mid=p[:1]))


@pytest.mark.parametrize(
    "deg, expected",
    [(0.0, MIN_LAYERS), (10.0, MIN_LAYERS), (40.0, 8), (40.1, 9), (59.0, 12), (400.0, MAX_LAYERS)],
)
def test_layer_rule_caps_the_turn_per_layer(deg, expected):
    assert layers_for_angle(math.radians(deg)) == expected


def test_layer_rule_refuses_bad_settings():
    with pytest.raises(SettingError, match="deg_per_layer"):
        layers_for_angle(1.0, deg_per_layer=0.0)
    with pytest.raises(SettingError, match="min_layers"):
        layers_for_angle(1.0, min_layers=20, max_layers=16)
    with pytest.raises(SettingError, match="layers"):
        coarse_layers(5)
    assert coarse_layers(11) == 5


def test_default_layers_of_the_paper_follow_the_section_model():
    # the finite-strain section model turns the paper's design by 59 deg at 0.6 MPa (its doctest)
    c = default_layers(design.resolve("paper"), 0.6)
    assert c.source == "finite-strain section model"
    assert math.degrees(c.predicted_angle_rad) == pytest.approx(59.0, abs=1.0)
    assert c.layers == 12 and c.deg_per_layer <= 5.0
    assert default_layers(design.resolve("paper"), 0.05).layers == MIN_LAYERS


def test_mixed_by_default_only_for_near_incompressible_silicones():
    paper = design.resolve("paper")
    assert needs_mixed(paper)  # nu = 0.49
    soft = dataclasses.replace(paper.tube.material, poisson_ratio=0.3)
    other = dataclasses.replace(paper, tube=dataclasses.replace(paper.tube, material=soft), filler=None)
    assert not needs_mixed(other)
