"""A resolved-wire coil, as a periodic one-turn cell or between two rigid end plates.

**Periodic cell** (default for stiffness): far from its ends a uniformly
loaded coil repeats itself every turn up to a rigid-body increment, so one
turn with u(k + m) = u(k) + Δc + Δθ × x_k, θ(k + m) = θ(k) + Δθ (node 0
held to remove rigid motion) is the exact middle of an infinitely long coil.
(Δc, Δθ) are the per-turn stretch and rotation; their work conjugates are the
axial force and moment the coil transmits, so loads act on them directly. A
contact pair (k, k + m) then only sees the increment: its gap is planar in
(x, y) — plane sections of the turns' contact surface stay plane.

**End plates** (``turns`` given; the pictures, and a check of the cell): the first turn is welded to a fixed
plate (all its nodes clamped); the last
turn is welded to a free rigid plate whose centre (on the coil axis, at
z = N·p) carries the load: every node of that turn follows the plate,
u = U + Θ × (x − X), θ = Θ (a multipoint constraint, eliminated by a
transformation u = T q). Stiffnesses are measured per turn in the middle
turns, where the response is periodic and the plates no longer matter:
between node k and node k + m (same angle, one turn up) the axial
displacement and the rotation increase by exactly one turn's share.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from softcath.design.errors import DesignError
from softcath.fem.coil.contact import ContactPairs, solve_with_contact
from softcath.fem.coil.frame import WireSection, element_frames, frame_stiffness
from softcath.fem.coil.helix import HelixMesh, helix_mesh
from softcath.fem.errors import SolverError

__all__ = ["CoilModel", "LoadState", "build_coil_model"]


def _solve(k: sp.spmatrix, f: np.ndarray) -> np.ndarray:
    u = spsolve(k, f)
    residual = np.linalg.norm(k @ u - f) / max(np.linalg.norm(f), 1e-300)
    if not np.all(np.isfinite(u)) or residual > 1e-6:
        raise SolverError(f"coil frame solve: relative residual {residual:.2e} (mechanism or singular)")
    return u


@dataclass(frozen=True, eq=False)
class LoadState:
    """One solved load case (displacements relative to the unloaded, possibly preloaded, coil).

    Attributes
    ----------
    displacement
        (n_nodes, 6) nodal displacements and rotations.
    contact_force
        (n_pairs,) compressive force of each contact pair [N] (0 where open), total, not relative.
    closed
        (n_pairs,) closed-pair mask.
    iterations
        Active-set iterations.
    reduced
        The solved unknowns (for the periodic cell the last six are Δc, Δθ).
    """

    displacement: np.ndarray
    contact_force: np.ndarray
    closed: np.ndarray
    iterations: int
    reduced: np.ndarray


@dataclass(frozen=True, eq=False)
class CoilModel:
    """An assembled resolved-wire coil (build with :func:`build_coil_model`)."""

    mesh: HelixMesh
    section: WireSection
    stiffness: sp.csr_matrix  # reduced
    transform: sp.csr_matrix  # full DOFs = transform @ reduced
    pairs: ContactPairs
    gap_operator: sp.csr_matrix  # reduced

    periodic: bool

    @property
    def n_dofs(self) -> int:
        return self.stiffness.shape[0]

    @property
    def middle(self) -> np.ndarray:
        """Nodes k whose pair (k, k + m) lies in the middle half of the coil, whole turns only."""
        n, m = self.mesh.turns, self.mesh.elements_per_turn
        if self.periodic:
            return np.arange(m)
        skip = max(2, n // 4)
        return np.arange(skip * m, (n - skip - 1) * m)

    def with_initial_tension(self, force: float) -> CoilModel:
        """The same coil pressed together by ``force`` [N] across every cut (f₀ = force / m per pair)."""
        preload = np.full_like(self.pairs.gap0, force / self.mesh.elements_per_turn)
        return replace(self, pairs=replace(self.pairs, preload=preload))

    def solve(self, load: np.ndarray, *, mode: str = "contact", base: LoadState | None = None) -> LoadState:
        """Solve for the plate load (F_x, F_y, F_z, M_x, M_y, M_z) [N, N mm].

        ``mode``: ``"contact"`` (unilateral contact, active set), ``"free"``
        (no contact: the wire alone, an open coil's law) or ``"closed"`` (every
        pair held closed: turns bonded, as under a large axial compression).
        ``base`` is the unloaded state the result is measured from (its
        displacement is subtracted; the active set starts from its pairs).
        """
        if mode not in ("contact", "free", "closed"):
            raise DesignError("mode", mode, "must be contact, free or closed")
        kc, gap0 = self.pairs.stiffness, self.pairs.shifted_gap0
        f = np.zeros(self.n_dofs)
        f[-6:] = load
        if mode != "free":
            f -= self.gap_operator.T @ self.pairs.preload
        if mode == "free":
            q, closed, its = _solve(self.stiffness.tocsc(), f), np.zeros(len(gap0), bool), 1
        elif mode == "closed":
            k = self.stiffness + self.gap_operator.T @ sp.diags(kc) @ self.gap_operator
            q = _solve(k.tocsc(), f - self.gap_operator.T @ (kc * gap0))
            closed, its = np.ones(len(gap0), bool), 1
        else:
            start = None if base is None else base.closed
            q, closed, its = solve_with_contact(
                _solve, self.stiffness, f, self.gap_operator, gap0, kc, active=start
            )
        force = np.where(closed, -kc * (gap0 + self.gap_operator @ q), 0.0)
        u = (self.transform @ q).reshape(-1, 6)
        if base is not None:
            u, q = u - base.displacement, q - base.reduced
        return LoadState(u, force, closed, its, q)

    @property
    def middle_pairs(self) -> np.ndarray:
        """Indices of the contact pairs (k, k + m) for k in :attr:`middle`."""
        return np.searchsorted(self.pairs.first, self.middle)

    def per_turn(self, state: LoadState) -> tuple[float, np.ndarray]:
        """(axial extension, rotation vector) per turn, averaged over the middle turns."""
        if self.periodic:
            return float(state.reduced[-4]), state.reduced[-3:].copy()
        k = self.middle
        m = self.mesh.elements_per_turn
        d = state.displacement[k + m] - state.displacement[k]
        return float(d[:, 2].mean()), d[:, 3:].mean(axis=0)


def _rigid_plate(nodes: np.ndarray, tied: np.ndarray, free: np.ndarray, centre: np.ndarray) -> sp.csr_matrix:
    """T with full DOFs = T q, q = (free nodes' 6 DOFs, plate's 6 DOFs); clamped nodes get zero rows."""
    n_full, n_q = 6 * len(nodes), 6 * len(free) + 6
    rows = list((6 * free[:, None] + np.arange(6)).ravel())
    cols = list(range(6 * len(free)))
    vals = [1.0] * len(cols)
    p = 6 * len(free)  # plate DOFs: U (p..p+2), Θ (p+3..p+5)
    for j in tied:
        rx, ry, rz = nodes[j] - centre
        # u = U + Θ × r ; θ = Θ (fmt: skip keeps one row of the rigid-body map per line)
        entries = [
            (0, 0, 1.0), (0, 4, rz), (0, 5, -ry),
            (1, 1, 1.0), (1, 5, rx), (1, 3, -rz),
            (2, 2, 1.0), (2, 3, ry), (2, 4, -rx),
            (3, 3, 1.0), (4, 4, 1.0), (5, 5, 1.0),
        ]  # fmt: skip
        for a, b, v in entries:
            rows.append(6 * j + a)
            cols.append(p + b)
            vals.append(v)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_full, n_q))


def _contact_stiffness(section: WireSection, pitch: float, wire_length: float, penalty_scale: float) -> float:
    """Penalty stiffness of one pair [N/mm]: E·φ·d/p per unit wire length times the pair's share."""
    d = section.diameter
    wire_fraction = np.pi * d / (4 * pitch)
    return penalty_scale * section.youngs_modulus * wire_fraction * d / pitch * wire_length


def build_coil_model(
    *,
    radius: float,
    pitch: float,
    section: WireSection,
    turns: int | None = None,
    elements_per_turn: int = 16,
    penalty_scale: float = 1.0,
) -> CoilModel:
    """Assemble the resolved-wire coil.

    Parameters
    ----------
    radius, pitch
        Helix radius R and pitch p [mm].
    section
        The wire.
    turns
        ``None``: the periodic one-turn cell. Else N ≥ 3 turns between end
        plates (the first and last turns welded to them).
    elements_per_turn
        m elements per turn.
    penalty_scale
        Multiplies the contact stiffness. At 1 a closed coil's axial modulus
        over the annulus is E·φ, φ = π d /(4 p) the wire fraction — the
        coil-bound bound that ``design.coil_stiffness`` uses — i.e. a contact
        stiffness per wire length E·φ·d/p [MPa].
    """
    if not penalty_scale > 0:
        raise DesignError("penalty_scale", penalty_scale, "must be > 0")
    if turns is not None and (
        isinstance(turns, bool) or not isinstance(turns, (int, np.integer)) or turns < 3
    ):
        raise DesignError("turns", turns, "must be an integer >= 3 (two end turns and one free) or None")
    periodic = turns is None
    mesh = helix_mesh(
        radius=radius, pitch=pitch, turns=1 if periodic else turns, elements_per_turn=elements_per_turn
    )
    m, n_nodes = mesh.elements_per_turn, len(mesh.nodes)
    full = frame_stiffness(mesh.nodes, mesh.elements, section)
    length, _ = element_frames(mesh.nodes, mesh.elements)
    if periodic:
        # Node m is node 0's image: u_m = Δc + Δθ × x_0 (node 0 held), i.e. a "plate" at x_m − x_0.
        transform = _rigid_plate(mesh.nodes, np.array([m]), np.arange(1, m), mesh.nodes[m] - mesh.nodes[0])
        first = np.arange(m)
        normal = np.tile([0.0, 0.0, 1.0], (m, 1))  # x_{k+m} − x_k = (0, 0, p)
    else:
        tied = mesh.turn_nodes(turns - 1)
        transform = _rigid_plate(
            mesh.nodes, tied, np.arange(m + 1, tied[0]), np.array([0.0, 0.0, mesh.length])
        )
        # Pairs inside one end turn would join two nodes of the same rigid plate: left out.
        first = np.arange(1, n_nodes - m - 1)
        normal = mesh.nodes[first + m] - mesh.nodes[first]
        normal /= np.linalg.norm(normal, axis=1)[:, None]
    stiffness = (transform.T @ full @ transform).tocsr()
    pairs = ContactPairs(
        first=first,
        second=first + m,
        normal=normal,
        gap0=np.full(len(first), pitch - section.diameter),
        stiffness=np.full(len(first), _contact_stiffness(section, pitch, length[0], penalty_scale)),
        preload=np.zeros(len(first)),
    )
    if periodic:
        # Gap change of pair k: n·Δc + Δθ·(x_k × n); only the increment enters.
        rows = np.zeros((m, transform.shape[1]))
        rows[:, -6:-3] = normal
        rows[:, -3:] = np.cross(mesh.nodes[first], normal)
        gap_operator = sp.csr_matrix(rows)
    else:
        gap_operator = (pairs.operator(6 * n_nodes) @ transform).tocsr()
    return CoilModel(mesh, section, stiffness, transform, pairs, gap_operator, periodic)
