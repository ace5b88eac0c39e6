"""Total-Lagrangian P2 assembly: internal forces, tangent, follower pressure.

A :class:`HyperelasticBody` takes a plain scikit-fem ``MeshTet``, one region
label per tetrahedron and a law per label, so any mesher that produces those
plugs in. scikit-fem supplies the quadratic (P2) basis — gradients, weights,
DOF numbering — and the element kernels are batched NumPy contractions
(``einsum`` over elements × quadrature points) rather than scikit-fem's
form loop, which is what makes Newton affordable here. For the laws it knows
(Yeoh, anisotropic SVK) a compiled element loop
(:mod:`softcath.fem.nonlinear.kernel`) does the same sums 4–6× faster; the
NumPy kernels stay as its reference (``compiled=False``).

Displacement DOFs are node-interleaved: DOF ``3 n + c`` is component ``c`` of
scalar P2 node ``n`` (``body.nodes[n]``), the same numbering as the linear FEM.

Mixed u–p: with ``mixed=True`` every law that splits off its volumetric energy
U(J) (the silicones) uses, per element, U of the element's mean dilatation
J̄ = (1/V) ∫ J dV instead of U(J) at each point. That is exactly the P2–P0
mixed u–p formulation with the element pressure p = U'(J̄) condensed out
(Simo, Taylor & Pister 1985, mean-dilatation), which removes volumetric
locking for ν → 0.5 without adding global unknowns.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from softcath.fem.hyperelastic.tensors import cofactor, dcofactor, det
from softcath.fem.nonlinear.errors import NonlinearError

__all__ = ["HyperelasticBody", "FollowerPressure", "SparsePattern"]

log = logging.getLogger(__name__)

# Elements per batch in the kernels: bounds memory (the tangent A is 81 doubles per point).
_CHUNK = 4000


def _vector_dofs(element_dofs: np.ndarray) -> np.ndarray:
    """(n, 30) global vector DOFs ordered (node a, component i) from scalar (10, n) DOFs."""
    ed = np.asarray(element_dofs).T
    return (3 * ed[:, :, None] + np.arange(3)).reshape(ed.shape[0], -1)


def _deformation_gradient(u: np.ndarray, dofs: np.ndarray, grads: np.ndarray) -> np.ndarray:
    """F = I + Σ_a u_a ⊗ ∇φ_a at the quadrature points; ``dofs`` (e, 30), ``grads`` (e, q, 10, 3)."""
    ue = u[dofs].reshape(dofs.shape[0], 10, 3)
    return np.eye(3) + np.einsum("eai,eqaJ->eqiJ", ue, grads, optimize=True)


@dataclass(frozen=True)
class _Chunk:
    """Element data of a block of cells sharing one law."""

    law: object
    cells: np.ndarray
    dofs: np.ndarray
    grads: np.ndarray
    weighted_grads: np.ndarray
    weights: np.ndarray
    pattern_pos: np.ndarray
    volumes: np.ndarray
    #: (code, parameters) for the compiled kernel, ``None`` where the NumPy kernel runs
    compiled: tuple | None


class SparsePattern:
    """The fixed sparsity of the tangent; element matrices are summed into it by index.

    Built once from the volume elements (every pressure facet belongs to a volume
    element, so its entries are in the pattern too).
    """

    def __init__(self, gdofs: np.ndarray, ndofs: int) -> None:
        self.ndofs = ndofs
        rows = np.repeat(gdofs, gdofs.shape[1], axis=1).ravel()
        cols = np.tile(gdofs, (1, gdofs.shape[1])).ravel()
        keys = rows.astype(np.int64) * ndofs + cols
        self.keys, self.volume_index = np.unique(keys, return_inverse=True)
        self.rows = (self.keys // ndofs).astype(np.int64)
        self.cols = (self.keys % ndofs).astype(np.int64)

    def index_of(self, gdofs: np.ndarray) -> np.ndarray:
        """Positions in the pattern of the (n, k, k) element blocks of ``gdofs`` (n, k)."""
        rows = np.repeat(gdofs, gdofs.shape[1], axis=1).ravel()
        cols = np.tile(gdofs, (1, gdofs.shape[1])).ravel()
        keys = rows.astype(np.int64) * self.ndofs + cols
        pos = np.searchsorted(self.keys, keys)
        if np.any(pos >= self.keys.size) or np.any(self.keys[np.minimum(pos, self.keys.size - 1)] != keys):
            raise NonlinearError("facet DOFs outside the volume pattern: facets must be mesh boundary facets")
        return pos

    def restrict(self, free: np.ndarray) -> tuple[np.ndarray, sp.csr_matrix]:
        """(mask over pattern entries, CSR template) of the free-free block."""
        renum = np.full(self.ndofs, -1, np.int64)
        renum[free] = np.arange(free.size)
        r, c = renum[self.rows], renum[self.cols]
        mask = (r >= 0) & (c >= 0)
        r, c = r[mask], c[mask]
        # keys sorted by (row, col) and renum monotone: CSR order is preserved.
        indptr = np.zeros(free.size + 1, np.int64)
        np.add.at(indptr, r + 1, 1)
        indptr = np.cumsum(indptr)
        tmpl = sp.csr_matrix((np.zeros(r.size), c, indptr), shape=(free.size, free.size))
        return mask, tmpl


class HyperelasticBody:
    """A hyperelastic solid on P2 tetrahedra (total Lagrangian).

    Parameters
    ----------
    mesh
        ``skfem.MeshTet`` (coordinates in mm).
    labels
        Region label per tetrahedron, shape (n_tets,).
    laws
        Map label -> law (``softcath.fem.hyperelastic.laws``).
    mixed
        Use the condensed P2–P0 mixed u–p (mean-dilatation) formulation for the
        laws that split off their volumetric part (module docstring).
    intorder
        Quadrature order; 2 (4 points) is the usual choice for P2 tetrahedra.
    compiled
        Assemble with the compiled element loop (:mod:`softcath.fem.nonlinear.kernel`) for
        the laws it implements (Yeoh, anisotropic SVK); ``False`` runs the batched NumPy
        kernels everywhere (the reference the compiled one is tested against).
    """

    def __init__(
        self,
        mesh,
        labels: np.ndarray,
        laws: Mapping[int, object],
        *,
        mixed: bool = False,
        intorder: int = 2,
        compiled: bool = True,
    ) -> None:
        from skfem import CellBasis, ElementTetP2

        labels = np.asarray(labels).ravel()
        if labels.shape[0] != mesh.t.shape[1]:
            raise NonlinearError(f"labels: {labels.shape[0]} given, mesh has {mesh.t.shape[1]} tetrahedra")
        missing = sorted(set(np.unique(labels).tolist()) - set(laws))
        if missing:
            raise NonlinearError(f"region labels {missing}: have no material law")
        self.mesh = mesh
        self.labels = labels
        self.laws = dict(laws)
        self.mixed = bool(mixed)
        self.element = ElementTetP2()
        self.basis = CellBasis(mesh, self.element, intorder=intorder)
        self.n_nodes = self.basis.N
        self.ndofs = 3 * self.n_nodes
        self.gdofs = _vector_dofs(self.basis.element_dofs)
        # (e, q, 10, 3) reference gradients and (e, q) weights.
        self.grads = np.stack([self.basis.basis[a][0].grad for a in range(10)]).transpose(2, 3, 0, 1).copy()
        self.weights = np.asarray(self.basis.dx)
        if np.any(self.weights <= 0):
            raise NonlinearError("mesh has inverted or degenerate tetrahedra (non-positive volume)")
        self.volumes = self.weights.sum(axis=1)
        self.pattern = SparsePattern(self.gdofs, self.ndofs)
        self.groups = {lab: np.flatnonzero(labels == lab) for lab in self.laws}
        kernel = _compiled_kernel() if compiled else None
        law_code = None if kernel is None else kernel.law_code
        self._assemble = None if kernel is None else kernel.assemble
        # per (law, chunk of cells): the gathered element data, made once instead of at every residual
        self._chunks = []
        for lab, law in self.laws.items():
            cells_all = self.groups[lab]
            for start in range(0, cells_all.size, _CHUNK):
                cells = cells_all[start : start + _CHUNK]
                g, w = self.grads[cells], self.weights[cells]
                self._chunks.append(
                    _Chunk(
                        law=law,
                        cells=cells,
                        dofs=self.gdofs[cells],
                        grads=g,
                        weighted_grads=g * w[:, :, None, None],
                        weights=w,
                        pattern_pos=self.pattern.volume_index.reshape(-1, 900)[cells].ravel(),
                        volumes=self.volumes[cells],
                        compiled=None if law_code is None else law_code(law),
                    )
                )

    @property
    def nodes(self) -> np.ndarray:
        """Reference coordinates of the P2 nodes (n_nodes, 3) [mm]."""
        return self.basis.doflocs.T

    def deformation_gradient(self, u: np.ndarray, cells: np.ndarray) -> np.ndarray:
        """F at the quadrature points of ``cells``, shape (n, q, 3, 3)."""
        return _deformation_gradient(u, self.gdofs[cells], self.grads[cells])

    def min_jacobian(self, u: np.ndarray) -> float:
        """Smallest det F over all quadrature points."""
        cells = np.arange(self.gdofs.shape[0])
        return float(det(self.deformation_gradient(u, cells)).min())

    def internal(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Internal force vector [N] (ndofs,) and tangent data aligned with ``pattern``."""
        f = np.zeros(self.ndofs)
        data = np.zeros(self.pattern.keys.size)
        u = np.ascontiguousarray(u, dtype=float)
        for ch in self._chunks:
            split = self.mixed and ch.law.splits_volume
            if ch.compiled is not None and self._assemble is not None:  # (compiled: the kernel loaded)
                code, prm = ch.compiled
                pos = ch.pattern_pos.reshape(-1, 900)
                self._assemble(u, ch.dofs, ch.grads, ch.weights, ch.volumes, pos, code, prm, split, f, data)
                continue
            fe, ke = self._kernel(u, ch, split)
            f += np.bincount(ch.dofs.ravel(), weights=fe.ravel(), minlength=self.ndofs)
            data += np.bincount(ch.pattern_pos, weights=ke.ravel(), minlength=data.size)
        return f, data

    def _kernel(self, u, ch: _Chunk, split: bool):
        F = _deformation_gradient(u, ch.dofs, ch.grads)
        w, g, gw, law = ch.weights, ch.grads, ch.weighted_grads, ch.law
        p, a = law.stress_tangent(F, volumetric=not split)
        if split:
            cof = cofactor(F)
            vol = self.volumes[ch.cells]
            jbar = np.einsum("eq,eq->e", det(F), w) / vol
            _, u1, u2 = law.volumetric(jbar)
            p = p + u1[:, None, None, None] * cof
            a = a + u1[:, None, None, None, None, None] * dcofactor(F, cof)
        fe = np.einsum("eqiJ,eqaJ->eai", p, gw, optimize=True)
        ke = _stiffness(gw, a, g)
        if split:
            ge = np.einsum("eqiJ,eqaJ->eai", cof, gw, optimize=True).reshape(-1, 30)
            ke += (u2 / vol)[:, None, None] * ge[:, :, None] * ge[:, None, :]
        return fe, ke

    def element_stress(self, u: np.ndarray) -> np.ndarray:
        """Cell-mean Cauchy von Mises stress [MPa] per tetrahedron (for pictures)."""
        out = np.zeros(self.gdofs.shape[0])
        for lab, law in self.laws.items():
            cells = self.groups[lab]
            if cells.size == 0:
                continue
            F = self.deformation_gradient(u, cells)
            p, _ = law.stress_tangent(F)
            sig = p @ np.swapaxes(F, -1, -2) / det(F)[..., None, None]
            dev = sig - np.trace(sig, axis1=-2, axis2=-1)[..., None, None] * np.eye(3) / 3
            vm = np.sqrt(1.5 * np.einsum("...ij,...ij->...", dev, dev))
            out[cells] = np.einsum("eq,eq->e", vm, self.weights[cells]) / self.volumes[cells]
        return out


def _compiled_kernel():
    """The compiled kernel module, or ``None`` (NumPy path) where Numba cannot load."""
    try:
        from softcath.fem.nonlinear import kernel
    except ImportError as exc:  # numba is a dependency; a broken install still solves, slower
        log.warning("compiled assembly unavailable (%s): using the NumPy kernels", exc)
        return None
    return kernel


def _stiffness(gw: np.ndarray, a: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Element matrices K[(a,i),(b,k)] = Σ_q gw_aJ A_iJkL g_bL as batched matmuls, (e, 30, 30)."""
    ne, nq = g.shape[:2]
    # T[e, q, (i J k), b] = A[e, q, iJk, L] @ g[e, q, L, b]
    t = np.matmul(a.reshape(ne, nq, 27, 3), np.swapaxes(g, -1, -2)).reshape(ne, nq, 3, 3, 3, 10)
    # to (e, (q J), (i k b)) and contract with gw (e, a, (q J))
    t = t.transpose(0, 1, 3, 2, 4, 5).reshape(ne, nq * 3, 90)
    ke = np.matmul(gw.transpose(0, 2, 1, 3).reshape(ne, 10, nq * 3), t)  # (e, a, (i k b))
    return ke.reshape(ne, 10, 3, 3, 10).transpose(0, 1, 2, 4, 3).reshape(ne, 30, 30)


class FollowerPressure:
    """Pressure on boundary facets that follows the deformed surface (Nanson).

    The fluid pushes into the solid: traction −p n da = −p cof(F) N dA₀, with N
    the outward reference normal. The residual carries +p ∫ φ cof(F)N dA₀ and
    the tangent its load stiffness p ∫ φ_a (∂cof F/∂F : N ⊗ ∇φ_b) dA₀, which is
    what keeps Newton quadratic under large rotations of the loaded surface.

    Parameters
    ----------
    body
        The body whose boundary carries the load.
    facets
        Indices of boundary facets of ``body.mesh``.
    profile
        Optional callable of the reference facet quadrature points ``x (3, n, q)``
        returning a factor ``(n, q)`` that multiplies the pressure (e.g. a linear
        profile makes a follower end moment). Default: uniform.
    intorder
        Facet quadrature order (4 integrates the P2 load exactly at the start).
    """

    def __init__(
        self,
        body: HyperelasticBody,
        facets: np.ndarray,
        *,
        profile: Callable | None = None,
        intorder: int = 4,
    ) -> None:
        from skfem import FacetBasis

        facets = np.asarray(facets, dtype=np.int64).ravel()
        if facets.size == 0:
            raise NonlinearError("pressure facets: none selected")
        boundary = set(body.mesh.boundary_facets().tolist())
        if not set(facets.tolist()) <= boundary:
            raise NonlinearError("pressure facets: must all be boundary facets of the mesh")
        fb = FacetBasis(body.mesh, body.element, facets=facets, intorder=intorder)
        self.body = body
        self.facets = facets
        self.gdofs = _vector_dofs(fb.element_dofs)
        self.values = np.stack([np.asarray(fb.basis[a][0]) for a in range(10)]).transpose(1, 2, 0).copy()
        self.grads = np.stack([fb.basis[a][0].grad for a in range(10)]).transpose(2, 3, 0, 1).copy()
        self.normals = np.asarray(fb.normals).transpose(1, 2, 0).copy()  # (n, q, 3)
        factor = (
            np.ones(fb.dx.shape)
            if profile is None
            else np.asarray(profile(np.asarray(fb.global_coordinates())))
        )
        self.weights = np.asarray(fb.dx) * factor
        # compact scatter targets: the loaded faces touch a small part of the pattern, so the
        # sums run over their own entries instead of pattern-sized arrays (9 ms -> 2 ms per call)
        self.pattern_entries, self._entry_of = np.unique(
            body.pattern.index_of(self.gdofs), return_inverse=True
        )
        self.dof_entries, self._dof_of = np.unique(self.gdofs.ravel(), return_inverse=True)

    def deformed_force(self, u: np.ndarray, pressure: float) -> np.ndarray:
        """Total force of the pressure on the deformed surface [N] (3,)."""
        fe, _ = self._kernel(u, pressure, with_tangent=False)
        return -fe.sum(axis=(0, 1))

    def _kernel(self, u: np.ndarray, pressure: float, *, with_tangent: bool = True):
        ue = u[self.gdofs].reshape(-1, 10, 3)
        F = np.eye(3) + np.einsum("eai,eqaJ->eqiJ", ue, self.grads, optimize=True)
        cn = np.einsum("eqiJ,eqJ->eqi", cofactor(F), self.normals)
        vw = self.values * self.weights[:, :, None] * pressure
        fe = np.einsum("eqa,eqi->eai", vw, cn, optimize=True)
        if not with_tangent:
            return fe, None
        dcn = np.einsum("eqiJkL,eqJ->eqikL", dcofactor(F), self.normals, optimize=True)
        # (e, q, i k, b) = dcn · ∇φ_b, then sum over q against φ_a
        t = np.matmul(dcn.reshape(*dcn.shape[:2], 9, 3), np.swapaxes(self.grads, -1, -2))
        ke = np.matmul(np.swapaxes(vw, 1, 2), t.reshape(t.shape[0], t.shape[1], -1))  # (e, a, (i k b))
        ke = ke.reshape(-1, 10, 3, 3, 10).transpose(0, 1, 2, 4, 3).reshape(-1, 30, 30)
        return fe, ke

    def add_to(self, u: np.ndarray, pressure: float, f: np.ndarray, data: np.ndarray) -> None:
        """Add the load's residual (+) and load stiffness into ``f`` and tangent ``data``."""
        if pressure == 0.0:
            return
        fe, ke = self._kernel(u, pressure)
        f[self.dof_entries] += np.bincount(self._dof_of, weights=fe.ravel(), minlength=self.dof_entries.size)
        data[self.pattern_entries] += np.bincount(
            self._entry_of, weights=ke.ravel(), minlength=self.pattern_entries.size
        )
