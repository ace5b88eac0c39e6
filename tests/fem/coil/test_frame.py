"""The resolved-wire coil's frame element and open-coil stiffness against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from softcath.design.errors import DesignError
from softcath.fem.coil import closed_forms as cf
from softcath.fem.coil.frame import WireSection, frame_stiffness
from softcath.fem.coil.model import build_coil_model

STEEL = WireSection(diameter=0.1, youngs_modulus=193000.0, poisson_ratio=0.29)
OPEN = {"radius": 1.0, "pitch": 0.3}  # spring index 20, helix angle 2.7°: an open coil


def _cantilever(direction, n_elements, load):
    """Tip displacement/rotation of a straight cantilever (length 2, clamped at node 0) along
    ``direction``."""
    direction = np.asarray(direction, float) / np.linalg.norm(direction)
    nodes = np.outer(np.linspace(0, 2.0, n_elements + 1), direction)
    elements = np.column_stack([np.arange(n_elements), np.arange(1, n_elements + 1)])
    k = frame_stiffness(nodes, elements, STEEL).tocsc()[6:, 6:]
    f = np.zeros(k.shape[0])
    f[-6:] = load
    return spsolve(k, f)[-6:]


@pytest.mark.parametrize("n_elements", [1, 5])
def test_cantilever_is_exact_for_a_tip_load_in_any_orientation(n_elements):
    # Timoshenko element with the Φ term is nodally exact for end loads: PL³/3EI + PL/(κGA), PL/EA, TL/GJ.
    direction = np.array([1.0, 2.0, -0.5])
    e1 = direction / np.linalg.norm(direction)
    e2 = np.cross(e1, [0.0, 0.0, 1.0])
    e2 /= np.linalg.norm(e2)
    L, P, T = 2.0, 0.01, 0.003
    s = STEEL
    bend = P * L**3 / (3 * s.youngs_modulus * s.second_moment) + P * L / (
        s.shear_coefficient * s.shear_modulus * s.area
    )
    tip = _cantilever(direction, n_elements, np.concatenate([P * e2 + 0.5 * P * e1, T * e1]))
    np.testing.assert_allclose(tip[:3] @ e2, bend, rtol=1e-9)
    np.testing.assert_allclose(tip[:3] @ e1, 0.5 * P * L / (s.youngs_modulus * s.area), rtol=1e-9)
    np.testing.assert_allclose(tip[3:] @ e1, T * L / (s.shear_modulus * s.polar_moment), rtol=1e-9)


def test_slender_cantilever_tends_to_euler_bernoulli():
    # L/d = 20: the shear term is 0.1 % of PL³/3EI (κGA vs 3EI/L²).
    tip = _cantilever([0, 0, 1], 4, np.array([1e-3, 0, 0, 0, 0, 0]))
    euler = 1e-3 * 2.0**3 / (3 * STEEL.youngs_modulus * STEEL.second_moment)
    assert tip[0] == pytest.approx(euler, rel=2e-3)
    assert tip[0] > euler  # shear adds compliance


def _per_turn_stiffness(m, turns=None, geometry=OPEN):
    model = build_coil_model(section=STEEL, turns=turns, elements_per_turn=m, **geometry)
    p = geometry["pitch"]
    ea = p / model.per_turn(model.solve(np.array([0, 0, 1.0, 0, 0, 0]), mode="free"))[0]
    ei = p / model.per_turn(model.solve(np.array([0, 0, 0, 1.0, 0, 0]), mode="free"))[1][0]
    return ea, ei


def test_open_coil_matches_spring_rate_and_wahl():
    ea, ei = _per_turn_stiffness(64)
    # Same physics, exact energy (helix angle, shear, axial terms): only the chords' 9/m², 1.6/m² error
    # remains.
    assert ea == pytest.approx(cf.helix_axial_energy(STEEL, **OPEN), rel=3e-3)
    assert ei == pytest.approx(cf.helix_bending_energy(STEEL, **OPEN), rel=6e-4)
    # Textbook forms (α → 0, torsion/bending only): they differ from the exact energy by 0.2 % here.
    assert ea == pytest.approx(cf.spring_rate_axial(STEEL, **OPEN), rel=5e-3)
    assert ei == pytest.approx(cf.wahl_bending(STEEL, **OPEN), rel=5e-3)


def test_textbook_forms_are_the_small_angle_limits_of_the_energy_forms():
    flat = {"radius": 1.0, "pitch": 1e-3}
    assert cf.helix_bending_energy(STEEL, **flat) == pytest.approx(cf.wahl_bending(STEEL, **flat), rel=1e-6)
    # The axial one keeps the direct-shear term J/(κ A R²) = d²/(8 κ R²) (0.14 % here).
    shear = STEEL.diameter**2 / (8 * STEEL.shear_coefficient * flat["radius"] ** 2)
    assert cf.spring_rate_axial(STEEL, **flat) / cf.helix_axial_energy(STEEL, **flat) == pytest.approx(
        1 + shear, rel=1e-6
    )


def test_mesh_convergence_is_second_order():
    exact = np.array([cf.helix_axial_energy(STEEL, **OPEN), cf.helix_bending_energy(STEEL, **OPEN)])
    err = {m: np.array(_per_turn_stiffness(m)) / exact - 1 for m in (16, 32, 64)}
    for coarse, fine in ((16, 32), (32, 64)):
        assert np.all((3.6 < err[coarse] / err[fine]) & (err[coarse] / err[fine] < 4.4))
    # Richardson on 32/64 removes the chord error: what is left is the energy forms' own neglect (< 0.02 %).
    extrapolated = (4 * (1 + err[64]) - (1 + err[32])) / 3
    np.testing.assert_allclose(extrapolated, 1.0, atol=2e-4)


def test_periodic_cell_is_the_middle_of_a_long_coil():
    # 16 turns between rigid plates, measured over the middle 8: end effects of an open coil are gone.
    np.testing.assert_allclose(_per_turn_stiffness(24, turns=16), _per_turn_stiffness(24), rtol=1e-4)


def test_bad_model_sizes_are_design_errors():
    with pytest.raises(DesignError, match=r"elements_per_turn = 4: must be an integer >= 6"):
        build_coil_model(section=STEEL, elements_per_turn=4, **OPEN)
    with pytest.raises(DesignError, match=r"turns = 2: must be an integer >= 3"):
        build_coil_model(section=STEEL, turns=2, **OPEN)
    with pytest.raises(DesignError, match=r"poisson_ratio = 0.5: must be in"):
        WireSection(diameter=0.1, youngs_modulus=1.0, poisson_ratio=0.5)
