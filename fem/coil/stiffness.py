"""``resolved_coil_stiffness``: a coil's axial and bending stiffness from its resolved wire.

Load cases on the periodic one-turn cell (the middle of a long coil) or on
the free end plate of an N-turn coil, measured per turn (``softcath.fem.coil.model``):

- tension: EA_t = ΔF·p/Δδ between two forces above the initial tension (the
  slope once the turns have separated); the threshold force is where that
  line meets the unloaded state;
- compression: EA_c = F·p/δ with turns in contact (coil-bound);
- bending, wire only (no contact: the open-coil law Wahl's formula describes),
  with contact (zero axial load; the concave side's turns press on each other)
  and with every pair held closed (a coil under enough axial compression).

Initial tension F₀: the unloaded coil is a state of self-stress in which the
contact force across any cut is F₀ and the wire carries F₀ in tension
(``softcath.fem.coil.contact``); the coil then needs F₀ before its turns separate.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from softcath.design.components import Coil
from softcath.design.errors import DesignError
from softcath.fem.coil.frame import WireSection
from softcath.fem.coil.model import CoilModel, LoadState, build_coil_model

__all__ = [
    "CoilStiffnessResult",
    "BentCoil",
    "resolved_coil_stiffness",
    "bending_curve",
    "coil_wire",
    "assemble_coil",
]

# Straight chords of a curved wire: error ≈ 9/m² in EA, 1.6/m² in EI (tests), 0.4 % at m = 48.
DEFAULT_ELEMENTS_PER_TURN = 48
# Reference curvature for the bending-with-contact case [1/mm] (the paper's tip bends to ~0.2 /mm).
REFERENCE_CURVATURE = 0.1


@dataclass(frozen=True, eq=False)
class BentCoil:
    """The coil bent with contact, for pictures: model, state and the unloaded (preloaded) state."""

    model: CoilModel
    state: LoadState


@dataclass(frozen=True, kw_only=True)
class CoilStiffnessResult:
    """A coil's stiffness per unit length from the resolved wire.

    Attributes
    ----------
    axial_tension
        EA in tension once the turns separate [N].
    axial_compression
        EA in compression with contact between turns [N] (wire only if ``contact=False``).
    bending
        EI of the wire alone, no contact (an open coil; Wahl's formula) [N mm²].
    bending_contact
        EI with contact at zero axial load, secant at ``moment`` [N mm²].
    bending_closed
        EI with every pair held closed (axial compressive preload) [N mm²].
    initial_tension
        Initial tension modelled [N].
    tension_threshold
        Axial force at which the turns separate, measured [N].
    moment
        Moment of the bending-with-contact case [N mm].
    contact_fraction
        Share of the middle pairs closed in the bending-with-contact case.
    neutral_axis_y
        Where the per-turn axial strain is zero in the bending-with-contact
        case, from the coil axis toward the convex (+y) side [mm] (−R: the
        concave edge).
    turns
        Turns between end plates, or 0 for the periodic cell.
    elements_per_turn, n_elements, n_dofs
        Model size.
    contact_iterations
        Active-set iterations of the bending-with-contact case.
    seconds
        Wall time of the whole computation.
    """

    axial_tension: float
    axial_compression: float
    bending: float
    bending_contact: float
    bending_closed: float
    initial_tension: float
    tension_threshold: float
    moment: float
    contact_fraction: float
    neutral_axis_y: float
    turns: int
    elements_per_turn: int
    n_elements: int
    n_dofs: int
    contact_iterations: int
    seconds: float
    bent: BentCoil | None = field(default=None, repr=False, compare=False)


def coil_wire(coil: Coil) -> WireSection:
    """The round wire of ``coil``."""
    return WireSection(
        diameter=coil.wire_diameter,
        youngs_modulus=coil.material.youngs_modulus,
        poisson_ratio=coil.material.poisson_ratio,
    )


def assemble_coil(
    coil: Coil,
    *,
    turns: int | None = None,
    elements_per_turn: int = DEFAULT_ELEMENTS_PER_TURN,
    penalty_scale: float = 1.0,
    contact: bool = True,
) -> tuple[CoilModel, LoadState, str]:
    """The assembled coil, its unloaded (possibly preloaded) state and the solve mode to use."""
    model = build_coil_model(
        radius=coil.mean_radius,
        pitch=coil.pitch,
        section=coil_wire(coil),
        turns=turns,
        elements_per_turn=elements_per_turn,
        penalty_scale=penalty_scale,
    )
    mode = "contact" if contact else "free"
    if contact and coil.initial_tension > 0:
        model = model.with_initial_tension(coil.initial_tension)
    return model, model.solve(np.zeros(6), mode=mode), mode


def bending_curve(
    coil: Coil,
    *,
    moments,
    axial_force: float = 0.0,
    elements_per_turn: int = DEFAULT_ELEMENTS_PER_TURN,
    penalty_scale: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Curvature [1/mm] and axial strain [-] of the periodic cell, with contact, under each moment.

    ``axial_force`` [N] acts together with every moment (negative: compression).
    With initial tension or an axial compression the turns stay closed up to a
    moment that opens the convex side, then pivot toward the concave edge: the
    curve is piecewise linear, stiff first.
    """
    model, base, mode = assemble_coil(coil, elements_per_turn=elements_per_turn, penalty_scale=penalty_scale)
    curvature, strain = [], []
    for m_x in np.atleast_1d(np.asarray(moments, dtype=float)):
        state = model.solve(np.array([0, 0, axial_force, m_x, 0, 0]), mode=mode, base=base)
        dc, dtheta = model.per_turn(state)
        curvature.append(dtheta[0] / coil.pitch)
        strain.append(dc / coil.pitch)
    return np.array(curvature), np.array(strain)


def _turn_strain(model: CoilModel, state: LoadState) -> tuple[float, float]:
    """Least-squares (ε₀, κ) of the per-turn axial strain ε(y) = ε₀ + κ y over the middle pairs."""
    k = model.middle
    m = model.mesh.elements_per_turn
    du = (state.displacement[k + m, 2] - state.displacement[k, 2]) / model.mesh.pitch
    y = model.mesh.nodes[k, 1]
    a = np.column_stack([np.ones_like(y), y])
    (e0, kappa), *_ = np.linalg.lstsq(a, du, rcond=None)
    return float(e0), float(kappa)


def resolved_coil_stiffness(
    coil: Coil,
    *,
    turns: int | None = None,
    contact: bool = True,
    elements_per_turn: int = DEFAULT_ELEMENTS_PER_TURN,
    moment: float | None = None,
    penalty_scale: float = 1.0,
) -> CoilStiffnessResult:
    """Stiffness of ``coil`` from a resolved-wire frame model (see module docstring).

    Parameters
    ----------
    coil
        The coil (wire diameter, pitch, mean radius, wire material, initial tension).
    turns
        ``None`` (default): the periodic one-turn cell, the exact middle of a
        long coil. N ≥ 3: N turns between rigid end plates, measured over the
        middle turns (a check of the cell; slower, 20 s for 50 turns).
    contact
        ``False``: no contact between turns (every case is the wire alone).
    elements_per_turn
        Frame elements per turn.
    moment
        Moment of the bending-with-contact case [N mm]; default: the moment
        that bends the open coil (Wahl) to curvature 0.1 /mm.
    penalty_scale
        Multiplies the contact stiffness (default: a closed coil's axial modulus is E·φ).
    """
    t0 = time.perf_counter()
    p = coil.pitch
    model, base, mode = assemble_coil(
        coil, turns=turns, elements_per_turn=elements_per_turn, penalty_scale=penalty_scale, contact=contact
    )
    f0 = coil.initial_tension if contact else 0.0
    ea_t, ea_c, threshold = _axial_stiffness(model, base, mode, p, f0)

    def bending_stiffness(state: LoadState, m_x: float) -> float:
        return m_x * p / model.per_turn(state)[1][0]

    ei_free = bending_stiffness(model.solve(np.array([0, 0, 0, 1.0, 0, 0]), mode="free"), 1.0)
    ei_closed = bending_stiffness(model.solve(np.array([0, 0, 0, 1.0, 0, 0]), mode="closed"), 1.0)
    m_ref = ei_free * REFERENCE_CURVATURE if moment is None else moment
    if not m_ref > 0:
        raise DesignError("moment", m_ref, "must be > 0 N mm")
    bent = model.solve(np.array([0, 0, 0, m_ref, 0, 0]), mode=mode, base=base)
    ei_contact = bending_stiffness(bent, m_ref)
    neutral_y = _neutral_axis_y(model, bent)
    return CoilStiffnessResult(
        axial_tension=float(ea_t),
        axial_compression=float(ea_c),
        bending=float(ei_free),
        bending_contact=float(ei_contact),
        bending_closed=float(ei_closed) if contact else float(ei_free),
        initial_tension=float(f0),
        tension_threshold=float(threshold),
        moment=float(m_ref),
        contact_fraction=float(bent.closed[model.middle_pairs].mean()),
        neutral_axis_y=float(neutral_y),
        turns=0 if turns is None else int(turns),
        elements_per_turn=int(elements_per_turn),
        n_elements=len(model.mesh.elements),
        n_dofs=model.n_dofs,
        contact_iterations=bent.iterations,
        seconds=time.perf_counter() - t0,
        bent=BentCoil(model, bent),
    )


def _axial_stiffness(model: CoilModel, base: LoadState, mode: str, p, f0: float):
    """Axial stiffness in tension and in compression [N] and the tension threshold [N]."""
    free = model.solve(np.array([0, 0, 1.0, 0, 0, 0]), mode="free")
    ea_free = p / model.per_turn(free)[0]  # wire alone, per unit force
    f_ref = 1e-3 * ea_free  # 0.1 % strain of the separated coil: well inside linear theory
    stretch = [
        model.per_turn(model.solve(np.array([0, 0, f0 + s * f_ref, 0, 0, 0]), mode=mode, base=base))[0]
        for s in (1, 2)
    ]
    ea_t = f_ref * p / (stretch[1] - stretch[0])
    threshold = f0 + f_ref - ea_t * stretch[0] / p
    squeeze = model.per_turn(model.solve(np.array([0, 0, -f_ref, 0, 0, 0]), mode=mode, base=base))[0]
    ea_c = -f_ref * p / squeeze
    return ea_t, ea_c, threshold


def _neutral_axis_y(model: CoilModel, bent: LoadState) -> float:
    """y of the neutral axis of the bent coil [mm]."""
    if model.periodic:
        # Per-turn axial strain ε(x, y) = (Δc_z + Δθ_x y − Δθ_y x)/p; zero on the neutral axis.
        dc, dtheta = model.per_turn(bent)
        return -dc / dtheta[0]
    e0, kappa = _turn_strain(model, bent)
    return -e0 / kappa
