r"""The finite-strain section of the tip as built: sliding interfaces, axial groups, the free tube.

The linear model of the tip as built (:mod:`softcath.fem.section_model.as_built`, whose
module docstring states the rules) carries over to finite strain with the same mesh
transformation and the same axial bookkeeping:

* the section mesh is split at every region boundary and each interface tied by
  :func:`~softcath.fem.section_model.as_built.bodies_and_ties` and
  :func:`~softcath.fem.section_model.interfaces.tie_projection`: bonded edges in full,
  sliding and tied-at-tip edges by their normal component only. The in-plane
  unknowns are the reduced ones, :math:`U = T \hat U`;
* each axial group :math:`g` of :func:`~softcath.fem.section_model.as_built.axial_plan`
  has its own stretch :math:`\lambda_g`, so an element of that group has
  :math:`F_{33} = \lambda_g (1 + k\cdot x)`; the curvature :math:`k` is shared, so the
  moments sum, and each :math:`\lambda_g` has its own axial-force equation;
* the lumen's volume per unit length is stretched by the cap carrier's
  :math:`\lambda` (the group the cap force goes to), so the cap force
  :math:`p\,a` lands on that group's axial equation, as in the linear model.

Unknowns: :math:`(\hat U, \lambda_0 \dots \lambda_{G-1}, k_1, k_2)`. The tangent is
assembled on the split mesh with each element's own group stretch and projected,
:math:`\hat K = P^\mathsf{T} K P`, with :math:`P = \mathrm{diag}(T, I)`; a
tangential spring layer of tiny modulus (the linear model's ``slip_modulus``) removes
the free spin of bodies whose interfaces are all circles.

**The model's limit: small sliding.** The normal tie is imposed in the reference
configuration (the node pairs and normals of the undeformed mesh), which is exact only
while the in-plane tangential slip is small against the element size: a slip of a whole
element pairs nodes that no longer face each other. :attr:`AsBuiltProblem.slip_ratio`
measures the largest tangential slip of a state divided by the median interface edge
length; a curve reports it at every pressure (``interface_slip_per_element``) so a user
can see where the limit is passed. The axial slip between groups,
:math:`(\lambda_a - \lambda_b) Z`, is the model's kinematics and not limited.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import cast

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

from softcath.fem.geometry import COIL
from softcath.fem.section_model.as_built import AxialPlan, _pins, axial_plan, bodies_and_ties
from softcath.fem.section_model.finite_strain.discretisation import N_GLOBAL, Discretisation
from softcath.fem.section_model.finite_strain.lumen import LumenWall
from softcath.fem.section_model.finite_strain.residual import Tangent, internal
from softcath.fem.section_model.interfaces import Ties, tie_projection

__all__ = ["AsBuiltProblem", "as_built_problem", "split_section"]

#: Tangential spring modulus of the interfaces per softest axial modulus [1/mm] (the linear model's).
SLIP_MODULUS = 1e-9


def split_section(section, assembly):
    """``(split, tie, plan)``: the section split at its region boundaries, the edges tied by the
    normal only, and the axial groups (the linear as-built model's, unchanged)."""
    split, tie = bodies_and_ties(section, assembly)
    return split, tie, axial_plan(assembly, np.unique(section.labels))


def _shape(m: sparse.spmatrix) -> tuple[int, int]:
    """A sparse matrix's (rows, columns) (scipy leaves ``shape`` unannotated: the checker sees None)."""
    return cast(tuple[int, int], m.shape)


@dataclass(frozen=True)
class AsBuiltProblem:
    """A discretised split section with its normal ties and axial groups.

    It offers what :func:`softcath.fem.section_model.finite_strain.newton.walk` asks of a
    problem (``free``, ``size``, ``initial_state`` and the assembly methods the Newton
    functions delegate to) on the reduced unknowns :math:`(\\hat U, \\lambda_g, k_1, k_2)`.

    Attributes
    ----------
    disc
        Discretisation of the split mesh.
    wall
        Its lumen wall (or None).
    ties
        Normal ties on ``disc.basis`` (nodal and facet DOFs; the bubbles are kept as they are).
    plan
        Axial groups and cap shares.
    silicone
        Region labels whose largest strain is reported.
    slip_modulus
        Tangential spring modulus of the interfaces [N/mm^3].
    interface_size
        Median interface edge length [mm], the yardstick of :attr:`slip_ratio`.
    """

    disc: Discretisation
    wall: LumenWall | None
    ties: Ties
    plan: AxialPlan
    silicone: tuple[int, ...]
    slip_modulus: float
    interface_size: float

    @property
    def n_groups(self) -> int:
        """G, the number of axial stretches."""
        return self.plan.n_groups

    @cached_property
    def n_hat(self) -> int:
        """Reduced in-plane unknowns."""
        return int(_shape(self.projection)[1]) - self.n_groups - 2

    @property
    def ndofs(self) -> int:
        """Reduced unknowns: in-plane, one stretch per group, two curvatures."""
        return int(_shape(self.projection)[1])

    @cached_property
    def carrier(self) -> int:
        """Index of the group that carries the cap force."""
        return int(np.argmax(self.plan.cap_share))

    @cached_property
    def projection(self) -> sparse.csr_matrix:
        """P: reduced unknowns -> the split mesh's full unknowns (u, lambda_g, k_1, k_2)."""
        t = self.ties.T
        n_u = self.disc.n_u
        bubbles = n_u - _shape(t)[0]
        if bubbles < 0:
            raise RuntimeError("the tie projection covers more DOFs than the basis has")
        blocks = [t, sparse.identity(bubbles), sparse.identity(self.n_groups + 2)]
        return cast(sparse.csr_matrix, sparse.block_diag(blocks, format="csr"))

    @cached_property
    def free(self) -> np.ndarray:
        """The reduced unknowns solved for (all but three in-plane pins)."""
        op = _Basis(self.disc.basis, self.disc.mesh)
        return np.setdiff1d(np.arange(self.ndofs), _pins(op, self.ties))

    @cached_property
    def size(self) -> float:
        """Largest distance of a node from the origin [mm]."""
        return float(np.abs(np.asarray(self.disc.mesh.p)).max())

    @cached_property
    def element_globals(self) -> np.ndarray:
        """(nel, 3) full-vector indices of each element's (lambda of its group, k_1, k_2)."""
        disc, G = self.disc, self.n_groups
        out = np.empty((disc.dofs.shape[0], N_GLOBAL), dtype=np.int64)
        out[:, 1:] = (disc.n_u + G, disc.n_u + G + 1)
        for label, cells in disc.cells.items():
            out[cells, 0] = disc.n_u + self.plan.group[int(label)]
        return out

    @cached_property
    def element_table(self) -> np.ndarray:
        """(nel, nb + 3) full-vector indices of each element's local unknowns."""
        return np.concatenate([self.disc.dofs, self.element_globals], axis=1)

    @cached_property
    def carrier_globals(self) -> np.ndarray:
        """Full-vector indices of (the carrier's lambda, k_1, k_2)."""
        n_u, G = self.disc.n_u, self.n_groups
        return np.array([n_u + self.carrier, n_u + G, n_u + G + 1])

    @cached_property
    def load_tables(self) -> list[np.ndarray]:
        """Full-vector indices of the lumen wall's and the global load blocks (the cap carrier's)."""
        tables = []
        if self.wall is not None:
            g = np.broadcast_to(self.carrier_globals, (self.wall.dofs.shape[0], N_GLOBAL))
            tables.append(np.concatenate([self.wall.dofs, g], axis=1))
        return [*tables, self.carrier_globals[None, :]]

    @cached_property
    def group_discs(self) -> list[Discretisation]:
        """One view of ``disc`` per group holding that group's regions only."""
        groups = []
        for g in range(self.n_groups):
            cells = {k: v for k, v in self.disc.cells.items() if self.plan.group[int(k)] == g}
            groups.append(replace(self.disc, cells=cells))
        return groups

    @cached_property
    def spring(self) -> sparse.csr_matrix:
        """Reduced stiffness of the interfaces' tangential spring layer."""
        k = self.ties.spring(self.slip_modulus)
        n = self.ndofs
        m = n - _shape(k)[0]
        return cast(sparse.csr_matrix, sparse.block_diag([k, sparse.csr_matrix((m, m))], format="csr"))

    def initial_state(self) -> np.ndarray:
        """The unloaded tip: no displacement, every stretch 1, no curvature."""
        q = np.zeros(self.ndofs)
        q[self.n_hat : self.n_hat + self.n_groups] = 1.0
        return q

    def full(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(u, (lambda_g..., k_1, k_2))`` on the split mesh of the reduced ``q``."""
        x = self.projection @ q
        return x[: self.disc.n_u], x[self.disc.n_u :]

    def section_state(self, state):
        """``state`` with ``q = (u, lambda of the outer coil's group, k_1, k_2)``: the layout of
        the bonded section's states (the curve's rows read the coil group's stretch, as the
        linear model's elongation does)."""
        u, g = self.full(state.q)
        coil = self.plan.group.get(COIL, 0)
        return replace(state, q=np.concatenate([u, [g[coil], g[-2], g[-1]]]))

    def slip_ratio(self, q: np.ndarray) -> float:
        """Largest tangential interface slip of ``q`` over the median interface edge length."""
        s = self.ties.slip @ q[: _shape(self.ties.slip)[1]]
        return float(np.abs(s).max() / self.interface_size) if s.size else 0.0

    def _assemble(self, q, loading, factor, pressure, load_blocks):
        """Full residual, full sparse tangent, force norm and the merged element data."""
        disc = self.disc
        u, gl = self.full(q)
        lam, k1, k2 = gl[: self.n_groups], gl[-2], gl[-1]
        res = np.zeros((disc.dofs.shape[0], disc.dofs.shape[1] + N_GLOBAL))
        stiff = np.zeros(res.shape + (res.shape[1],))
        min_j, max_strain, volumetric = np.inf, 0.0, {}
        for g, dg in enumerate(self.group_discs):
            if not dg.cells:
                continue
            tan = internal(dg, u, np.array([lam[g], k1, k2]), silicone=self.silicone, pressure=pressure)
            min_j = min(min_j, tan.min_jacobian)
            if tan.min_jacobian <= 0:
                return None, None, 0.0, Tangent(res, stiff, min_j, np.nan, volumetric)
            max_strain = max(max_strain, tan.max_strain)
            volumetric.update(tan.volumetric)
            res += tan.residual  # each group's rows only: its own cells are nonzero
            stiff += tan.stiffness
        tan = Tangent(res, stiff, float(min_j), max_strain, volumetric)
        g3 = np.array([lam[self.carrier], k1, k2])
        blocks, ext = load_blocks(self, u, g3, loading, factor)
        tables = [self.element_table, *self.load_tables]
        r_blocks = [res, *(r for r, _ in blocks)]
        k_blocks = [stiff, *(k for _, k in blocks)]
        n = disc.n_u + self.n_groups + 2
        r = np.bincount(
            np.concatenate([t.ravel() for t in tables]),
            weights=np.concatenate([x.ravel() for x in r_blocks]),
            minlength=n,
        )
        rows = np.concatenate([np.repeat(t, t.shape[1], axis=1).ravel() for t in tables])
        cols = np.concatenate([np.tile(t, (1, t.shape[1])).ravel() for t in tables])
        k = sparse.csr_matrix((np.concatenate([x.ravel() for x in k_blocks]), (rows, cols)), shape=(n, n))
        return r, k, ext, tan

    def residual_tangent(self, q, loading, factor, pressure, load_blocks):
        """Reduced residual (all unknowns), free-free tangent, force norm and element data."""
        r, k, ext, tan = self._assemble(q, loading, factor, pressure, load_blocks)
        if r is None:
            return None, None, 0.0, tan
        P = self.projection
        r_hat = P.T @ r + self.spring @ q
        k_hat = (P.T @ k @ P + self.spring).tocsr()
        f = self.free
        return r_hat, k_hat[f][:, f].tocsc(), ext, tan

    def load_vector(self, q, loading, load_blocks) -> np.ndarray:
        """Reduced external forces of the unit load factor at ``q``."""
        u, gl = self.full(q)
        g3 = np.array([gl[self.carrier], gl[-2], gl[-1]])
        blocks, _ = load_blocks(self, u, g3, loading, 1.0)
        tables = self.load_tables
        n = self.disc.n_u + self.n_groups + 2
        r = np.bincount(
            np.concatenate([t.ravel() for t in tables]),
            weights=np.concatenate([b.ravel() for b, _ in blocks]),
            minlength=n,
        )
        return -(self.projection.T @ r)

    def factorise(self, k):
        """Sparse LU of a free-free tangent (``RuntimeError`` when singular)."""
        return splu(k, permc_spec="COLAMD")

    def pressures_after(self, tan, step: np.ndarray) -> dict:
        """The projected pressures linearised along the reduced ``step``."""
        local = (self.projection @ step)[self.element_table]
        return {label: v.pressure_after(local[v.cells]) for label, v in tan.volumetric.items()}


@dataclass(frozen=True)
class _Basis:
    """The two attributes :func:`~softcath.fem.section_model.as_built._pins` reads."""

    basis: object
    mesh: object


def as_built_problem(split, tie, plan, disc, wall, *, silicone) -> AsBuiltProblem:
    """The :class:`AsBuiltProblem` of a split section discretised as ``disc``.

    The slip layer's modulus is 1e-9 of the softest element's small-strain axial modulus
    per mm, as in the linear model.
    """
    ties = tie_projection(split, disc.basis, tie=tie)
    e_min = float(disc.axial_modulus.min())
    pts = np.asarray(split.mesh.points)
    edges = split.edges
    lengths = np.hypot(*(pts[edges[:, 1]] - pts[edges[:, 0]]).T) if len(edges) else np.ones(1)
    return AsBuiltProblem(
        disc=disc,
        wall=wall,
        ties=ties,
        plan=plan,
        silicone=tuple(silicone),
        slip_modulus=SLIP_MODULUS * e_min,
        interface_size=float(np.median(lengths)),
    )
