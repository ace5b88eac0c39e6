"""Contact between turns of the resolved-wire coil: coil-bound compression, pivoting, initial tension."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

from softcath import design
from softcath.fem.coil import bending_curve, coil_wire, resolved_coil_stiffness
from softcath.fem.coil import closed_forms as cf
from softcath.fem.coil.contact import solve_with_contact
from softcath.fem.errors import SolverError


@pytest.fixture(scope="module")
def paper():
    return design.resolve("paper")


def _solve(k, f):
    return sp.linalg.spsolve(k, f)


def test_active_set_on_two_springs_and_a_gap():
    # Mass on a spring k1 pushed by F toward a stop (gap 0.1) backed by penalty k_c: closes only if F > 0.1
    # k1.
    k = sp.csr_matrix([[1.0]])
    b = sp.csr_matrix([[-1.0]])  # gap = 0.1 - u
    for force, closed in ((0.05, False), (1.0, True)):
        u, active, _ = solve_with_contact(_solve, k, np.array([force]), b, np.array([0.1]), np.array([1e3]))
        expect = (force + 1e3 * 0.1) / (1 + 1e3) if closed else force
        assert bool(active[0]) is closed
        assert u[0] == pytest.approx(expect, rel=1e-12)


def test_active_set_that_cannot_settle_is_an_error():
    k = sp.csr_matrix([[1.0]])
    with pytest.raises(SolverError, match="did not settle"):
        solve_with_contact(
            _solve,
            k,
            np.array([1.0]),
            sp.csr_matrix([[-1.0]]),
            np.array([0.1]),
            np.array([1e3]),
            active=np.array([False]),
            max_iterations=1,
        )


def test_close_wound_coil_is_bilinear_and_pivots(paper):
    coil = paper.coil
    wire, geo = coil_wire(coil), {"radius": coil.mean_radius, "pitch": coil.pitch}
    r = resolved_coil_stiffness(coil)
    k = design.coil_stiffness(coil)
    # Tension: the turns separate at once (no initial tension), the spring (chord error 0.4 % at m = 48).
    assert r.axial_tension == pytest.approx(cf.helix_axial_energy(wire, **geo), rel=6e-3)
    assert r.tension_threshold == pytest.approx(0.0, abs=1e-12)
    # Compression: coil-bound. The contact stiffness is set to E·φ (design.coil_stiffness's bound), so this
    # checks the contact assembly, not the bound; the wire's own compliance is < 0.1 %.
    assert r.axial_compression == pytest.approx(k.axial_modulus_compression * k.area, rel=2e-3)
    assert r.axial_compression / r.axial_tension > 1e5
    # Bending with contact at zero axial force: one pivot line at y = -R, EI = EI_open + EA R².
    assert r.bending == pytest.approx(cf.helix_bending_energy(wire, **geo), rel=1e-3)
    assert r.bending_contact == pytest.approx(cf.pivot_bending(wire, **geo), rel=6e-3)
    assert r.neutral_axis_y == pytest.approx(-coil.mean_radius, rel=1e-3)
    assert r.contact_fraction == pytest.approx(1 / r.elements_per_turn)
    # All turns closed: a ring of contact springs k_c per wire length, one layer per pitch p:
    # EI = k_c p ∫ y² ds = k_c p π R³ (Σ y_k² = m R²/2 exactly for equally spaced pairs; wire compliance < 0.1
    # %).
    k_line = (
        coil.material.youngs_modulus
        * (np.pi * coil.wire_diameter / (4 * coil.pitch))
        * coil.wire_diameter
        / coil.pitch
    )
    assert r.bending_closed == pytest.approx(k_line * coil.pitch * np.pi * coil.mean_radius**3, rel=2e-3)


def test_pivot_stiffness_does_not_depend_on_the_penalty(paper):
    soft = resolved_coil_stiffness(paper.coil, penalty_scale=0.3).bending_contact
    stiff = resolved_coil_stiffness(paper.coil, penalty_scale=100.0).bending_contact
    assert stiff == pytest.approx(soft, rel=1e-3)


def test_end_plate_model_agrees_with_the_periodic_cell_in_contact(paper):
    cell = resolved_coil_stiffness(paper.coil, elements_per_turn=16)
    plates = resolved_coil_stiffness(paper.coil, elements_per_turn=16, turns=16)
    assert plates.axial_tension == pytest.approx(cell.axial_tension, rel=1e-4)
    assert plates.axial_compression == pytest.approx(cell.axial_compression, rel=1e-3)
    # The middle turns of the plate model pivot exactly like the cell (the plates only disturb the end turns).
    assert plates.bending_contact == pytest.approx(cell.bending_contact, rel=1e-6)


def test_initial_tension_is_a_threshold_force(paper):
    f0 = 0.05
    coil = dataclasses.replace(paper.coil, initial_tension=f0)
    r = resolved_coil_stiffness(coil)
    plain = resolved_coil_stiffness(paper.coil)
    assert r.initial_tension == f0
    assert r.tension_threshold == pytest.approx(f0, rel=1e-9)
    assert r.axial_tension == pytest.approx(plain.axial_tension, rel=1e-9)
    # Below the threshold a tension is carried by unloading the contacts: as stiff as in compression.
    kappa, strain = bending_curve(coil, moments=[0.0], axial_force=0.5 * f0)
    assert 0.5 * f0 / strain[0] == pytest.approx(plain.axial_compression, rel=1e-3)


@pytest.mark.parametrize("axial", ["initial_tension", "compression"])
def test_closed_turns_open_at_the_ring_moment(paper, axial):
    # A ring of equal pairs under force P and moment M: the convex pair unloads at M = P R / 2.
    force = 0.04
    coil = paper.coil
    if axial == "initial_tension":
        coil, axial_force = dataclasses.replace(coil, initial_tension=force), 0.0
    else:
        axial_force = -force
    m_open = force * coil.mean_radius / 2
    r = resolved_coil_stiffness(coil)
    kappa, _ = bending_curve(
        coil, moments=[0.9 * m_open, 1.2 * m_open, 1.4 * m_open], axial_force=axial_force
    )
    assert 0.9 * m_open / kappa[0] == pytest.approx(r.bending_closed, rel=1e-6)
    tangent = 0.2 * m_open / (kappa[2] - kappa[1])
    assert tangent < 0.5 * r.bending_closed


def test_axial_tension_preload_gives_the_open_coil(paper):
    # Pulled apart beyond the initial tension (here 0), every turn is open: Wahl's coil, not the pivot.
    kappa, _ = bending_curve(paper.coil, moments=[1e-3], axial_force=0.01)
    r = resolved_coil_stiffness(paper.coil)
    assert 1e-3 / kappa[0] == pytest.approx(r.bending, rel=1e-9)


def test_pivoting_coil_with_initial_tension_has_a_moment_offset(paper):
    # Fully pivoting on the concave edge, the initial tension F₀ acts at arm R about the pivot:
    # κ = (M − F₀ R) / (EI_open + EA R²) — an exact piecewise-linear law once the last convex pair is open.
    f0 = 0.05
    coil = dataclasses.replace(paper.coil, initial_tension=f0)
    r = resolved_coil_stiffness(paper.coil)
    moments = np.array([4.0, 8.0]) * f0 * coil.mean_radius
    kappa, _ = bending_curve(coil, moments=moments)
    tangent = np.diff(moments)[0] / np.diff(kappa)[0]
    assert tangent == pytest.approx(r.bending_contact, rel=1e-6)
    # The pivot pair's penalty spring is compressed by the load: a 0.04 % shift of the offset.
    assert moments[1] - tangent * kappa[1] == pytest.approx(f0 * coil.mean_radius, rel=1e-3)
