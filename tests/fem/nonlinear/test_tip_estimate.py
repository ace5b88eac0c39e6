"""The 3-D tip angle's extrapolation in the layers (``estimate_tip``) and its place in fem.json."""

import json
from types import SimpleNamespace

import numpy as np
import pytest

from softcath.fem.nonlinear.convergence import ASSUMED_ORDER
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.reference import DEFICIT_ORDER, estimate_tip


def _curve(layers, rate, deficit, length, p):
    return SimpleNamespace(
        layers=layers, pressure=p, bend_rate_mid=rate, bend_angle=rate * (length - deficit)
    )


def test_recovers_a_tip_whose_rate_and_deficit_converge_at_their_orders():
    """Bend rate r∞ + a/n³ and deficit δ∞ + b/n: two meshes give r∞ (L − δ∞) to round-off."""
    length, p = 5.0, np.array([0.1, 0.6])
    rate_inf, deficit_inf = np.array([0.024, 0.2]), np.array([0.30, 0.28])
    a, b = np.array([-2.0, -40.0]), np.array([0.8, 0.9])

    def mesh(n):
        return _curve(n, rate_inf + a / n**ASSUMED_ORDER, deficit_inf + b / n**DEFICIT_ORDER, length, p)

    t = estimate_tip(mesh(16), mesh(8), length=length)
    exact = rate_inf * (length - deficit_inf)
    np.testing.assert_allclose(t.extrapolated, exact, rtol=1e-12)
    np.testing.assert_allclose(t.deficit, deficit_inf, rtol=1e-12)
    np.testing.assert_allclose(t.relative, np.abs(mesh(16).bend_angle - exact) / exact, rtol=1e-10)
    doc = t.to_json()
    assert doc["layers"] == 16 and doc["coarse_layers"] == 8 and "order 1" in doc["method"]


def test_refuses_curves_it_cannot_compare():
    p = np.array([0.1])
    one = _curve(8, np.array([0.02]), np.array([0.3]), 5.0, p)
    with pytest.raises(SettingError, match="layers"):
        estimate_tip(one, one, length=5.0)
    other = _curve(4, np.array([0.02]), np.array([0.3]), 5.0, np.array([0.2]))
    with pytest.raises(SettingError, match="pressure"):
        estimate_tip(one, other, length=5.0)


@pytest.mark.slow
def test_fem_json_states_the_tip_angle_error(tmp_path):
    from softcath import design
    from softcath.fem.nonlinear import NonlinearSettings, run_check

    s = NonlinearSettings(pressure=0.01, steps=1, layers=6, mesh_size=0.3, curvature_points=8)
    run_check(design.resolve("paper"), s, tmp_path)
    doc = json.loads((tmp_path / "fem.json").read_text())
    tip = doc["tip_angle_discretisation"]
    assert tip["layers"] == 6 and tip["coarse_layers"] == 3
    assert doc["tip_angle_error_estimate"] == pytest.approx(tip["relative"][-1])
    assert tip["bend_angle_rad"][-1] == pytest.approx(doc["bend_angle_rad"])
    # the deficit is the plug (0.3 mm) and the Saint-Venant zones', coarse: between the plug and 0.7 mm
    assert 0.3 < tip["deficit_mm"][-1] < 0.7
    # 6 vs 3 layers at a 0.6 deg bend: measured 1.3 % (deficit 0.39 mm; 16 layers: 0.35, converged ~0.30)
    assert 0.005 < doc["tip_angle_error_estimate"] < 0.03
