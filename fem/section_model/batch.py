"""Section models of many designs at once: template meshes, one vectorised kernel, factorisations reused.

Designs whose sections share a template mesh (``softcath.fem.section_model.template``)
differ only in node positions and region moduli, so everything that depends on the
connectivity is done once per template (a :class:`_Kernel`): the CCR DOF layout and
reference shape functions, the sparse pattern of the condensed stiffness with the
scatter from element matrices to it, the lumen edges' parent elements, the rigid-body
pins and the symbolic factorisation (QDLDL with AMD ordering; each further design only
refactorises numerically, :func:`qdldl.Solver.update`). The element kernel then runs on
all designs of a template at once, and each design's four right-hand sides (three unit
global strains, the unit lumen pressure) share one factorisation.

The kernel orders a template's triangles straight-sided first. A straight-sided triangle
has a constant Jacobian, so its blocks are reference-element integrals (same quadrature
rule) times inverse-Jacobian products and moduli, one matrix product per block
(:meth:`_Kernel._affine_blocks`); the triangles with a curved edge keep isoparametric
quadrature (:meth:`_Kernel._curved_blocks`). Pressure projection and bubble condensation
use closed-form 2 x 2 inverses (tests/fem/section_model/test_fast_assembly.py: equal to
scikit-fem's quadrature assembly to 1e-10).

The answers are :func:`~softcath.fem.section_model.section_model`'s on the same
(template) mesh, to round-off (tests/fem/section_model/test_batch.py).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse

from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.solve import LOADS
from softcath.interrupts import raise_pending_stop

__all__ = ["BatchItem", "CHUNK", "TIMERS", "section_models"]

log = logging.getLogger(__name__)

#: Wall seconds of this process per stage (a cheap clock: the CPU clock costs ~1 ms a call
#: on a loaded machine): ``laws``, ``template``
#: (reference section and, once per template, its gmsh mesh), ``morph``, ``assembly``,
#: ``factorisation``, ``solve``, ``post``: the benchmark's time split.
TIMERS: dict[str, float] = {}
#: Most designs assembled at once. The kernel's arrays peak at ~10 MB per paper-sized design; 256
#: paper variants of one template took 27, 32 and 44 ms a design in chunks of 32, 64 and 256
#: (0.6, 1.0 and 3.0 GB peak), so larger chunks buy nothing.
CHUNK = 32


def _tick(name: str, t0: float) -> float:
    t = time.perf_counter()
    TIMERS[name] = TIMERS.get(name, 0.0) + t - t0
    return t


@dataclass(frozen=True)
class BatchItem:
    """One design's section model from :func:`section_models`.

    Attributes
    ----------
    result
        The :class:`~softcath.fem.section_model.SectionResult` (no fields).
    strain_range
        Load -> (smallest, largest) principal strain per MPa in the silicone.
    """

    result: object
    strain_range: dict[str, tuple[float, float]] = field(default_factory=dict)


class _Kernel:
    """Everything of a template that does not depend on node positions or moduli."""

    def __init__(self, template) -> None:
        from skfem import CellBasis, ElementTriCCR, ElementVector

        from softcath.fem.section_model.element import _rigid_pins

        m = template.mesh
        mesh = m.skfem_mesh()
        basis = CellBasis(mesh, ElementVector(ElementTriCCR()), intorder=4)
        self.template = template
        dofs = basis.element_dofs  # (nb, nel)
        nb, nel = dofs.shape
        if not np.array_equal(dofs[nb - 2 :], basis.interior_dofs):
            raise RuntimeError("unexpected CCR DOF layout: bubbles are not the last local DOFs")
        self.nb, self.nel, self.N = nb, nel, basis.N
        self.n = basis.N - basis.interior_dofs.size
        X, W = basis.X, basis.W
        self.W = W
        scalar = ElementTriCCR()
        self.dphi = np.stack([scalar.lbasis(X, s)[1] for s in range(nb // 2)])  # (ns, 2, nq)
        r, s = X
        lam0 = 1 - r - s
        # P2 geometry: corners 0, 1, 2, midsides 01, 12, 20.
        self.Ng = np.stack(
            [lam0 * (2 * lam0 - 1), r * (2 * r - 1), s * (2 * s - 1), 4 * lam0 * r, 4 * r * s, 4 * s * lam0]
        )
        dr = np.stack([1 - 4 * lam0, 4 * r - 1, 0 * r, 4 * (lam0 - r), 4 * s, -4 * s])
        ds = np.stack([1 - 4 * lam0, 0 * r, 4 * s - 1, -4 * r, 4 * r, 4 * (lam0 - s)])
        self.dNg = np.stack([dr, ds], axis=1)  # (6, 2, nq)
        self._triangles(m, mesh, dofs)
        self._reference(X, W)
        self.pinned = _rigid_pins(basis, mesh)
        self._pattern()
        self._lumen(m, mesh)
        self.factor = None

    def _triangles(self, m, mesh, dofs) -> None:
        """Per-triangle tables, the triangles reordered: straight-sided first, then curved.

        ``rank[t]`` is where the mesh's triangle ``t`` went; ``n_affine`` triangles are straight.
        """
        nel = self.nel
        tri = np.ascontiguousarray(mesh.t.T)  # scikit-fem's vertex order (sorted), not the mesh's
        nv = np.int64(m.points.shape[0])
        ce = np.sort(m.curved_edges, axis=1) @ np.array([nv, 1])
        order = np.argsort(ce)
        edge_curved = np.full((nel, 3), -1)
        for j, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
            e = np.sort(tri[:, [a, b]], axis=1) @ np.array([nv, 1])
            pos = np.clip(np.searchsorted(ce, e, sorter=order), 0, max(ce.size - 1, 0))
            hit = ce[order[pos]] == e if ce.size else np.zeros(nel, bool)
            edge_curved[hit, j] = order[pos[hit]]
        bent = (edge_curved >= 0).any(axis=1)
        perm = np.concatenate([np.flatnonzero(~bent), np.flatnonzero(bent)])
        self.rank = np.empty(nel, dtype=np.int64)
        self.rank[perm] = np.arange(nel)
        self.n_affine = int((~bent).sum())
        self.tri, self.edge_curved, self.dofs = tri[perm], edge_curved[perm], dofs[:, perm]
        self.labels = m.labels[perm]
        self.silicone = np.isin(self.labels, (TUBE, FILLER))
        self.silicone_elements = np.flatnonzero(self.silicone)

    def _pattern(self) -> None:
        """Sparse pattern of the free-free block and the scatters into it."""
        nb, nel, dofs = self.nb, self.nel, self.dofs
        free = np.setdiff1d(np.arange(self.n), self.pinned)
        self.free = free
        where = np.full(self.n, -1)
        where[free] = np.arange(free.size)
        rd = where[dofs[: nb - 2].T]  # (nel, nr)
        rows = np.broadcast_to(rd[:, :, None], (nel, nb - 2, nb - 2)).ravel()
        cols = np.broadcast_to(rd[:, None, :], (nel, nb - 2, nb - 2)).ravel()
        ok = (rows >= 0) & (cols >= 0)
        key = rows.astype(np.int64) * free.size + cols
        uniq, slot = np.unique(key[ok], return_inverse=True)
        self.indices = (uniq % free.size).astype(np.int32)
        self.indptr = np.searchsorted(uniq // free.size, np.arange(free.size + 1)).astype(np.int32)
        self.nnz = uniq.size
        # The LDL factorisation reads the upper triangle in CSC: for a symmetric matrix, the
        # CSR rows of its lower triangle (column <= row).
        row_of = np.repeat(np.arange(free.size), np.diff(self.indptr))
        self.lower = self.indices <= row_of
        count = np.bincount(row_of[self.lower], minlength=free.size)
        self.indptr_lower = np.concatenate([[0], np.cumsum(count)]).astype(np.int32)
        self.lower_at, self.indices_lower = np.flatnonzero(self.lower), self.indices[self.lower]
        nr = nb - 2
        self.scatter_k = sparse.csr_matrix(
            (np.ones(slot.size), (slot, np.flatnonzero(ok))), shape=(self.nnz, nel * nr * nr)
        )
        rdofs = dofs[: nb - 2].T.ravel()
        self.scatter_g = sparse.csr_matrix(
            (np.ones(rdofs.size), (rdofs, np.arange(rdofs.size))), shape=(self.n, rdofs.size)
        )

    def _lumen(self, m, mesh) -> None:
        t = mesh.t
        nv = int(t.max()) + 1
        le = np.sort(m.lumen_edges, axis=1)
        all_edges = np.sort(np.concatenate([t[[i, j]].T for i, j in ((0, 1), (1, 2), (2, 0))]), axis=1)
        keys = all_edges[:, 0].astype(np.int64) * nv + all_edges[:, 1]
        order = np.argsort(keys)
        want = le[:, 0].astype(np.int64) * nv + le[:, 1]
        hit = order[np.searchsorted(keys[order], want)]
        self.l_elems, self.l_which = self.rank[hit % self.nel], hit // self.nel
        s, ws = np.polynomial.legendre.leggauss(4)
        self.l_s, self.l_ws = 0.5 * (s + 1), 0.5 * ws
        start = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])[self.l_which]
        stop = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])[self.l_which]
        self.l_dir = (stop - start).T  # (2, nf)
        X = start.T[:, :, None] + self.l_dir[:, :, None] * self.l_s[None, None, :]  # (2, nf, nq)
        r, s_ = X
        lam0 = 1 - r - s_
        self.l_N = np.stack(
            [
                lam0 * (2 * lam0 - 1),
                r * (2 * r - 1),
                s_ * (2 * s_ - 1),
                4 * lam0 * r,
                4 * r * s_,
                4 * s_ * lam0,
            ]
        )
        dr = np.stack([1 - 4 * lam0, 4 * r - 1, 0 * r, 4 * (lam0 - r), 4 * s_, -4 * s_])
        ds = np.stack([1 - 4 * lam0, 0 * r, 4 * s_ - 1, -4 * r, 4 * r, 4 * (lam0 - s_)])
        self.l_dN = np.stack([dr, ds], axis=1)  # (6, 2, nf, nq)
        from skfem import ElementTriCCR

        scalar = ElementTriCCR()
        self.l_phi = np.stack([scalar.lbasis(X, k // 2)[0] for k in range(self.nb)])  # (nb, nf, nq)
        ld = self.dofs[:, self.l_elems].T  # (nf, nb)
        self.scatter_l = sparse.csr_matrix(
            (np.ones(ld.size), (ld.ravel(), np.arange(ld.size))), shape=(self.N, ld.size)
        )

    def geometry(self, meshes: Sequence) -> np.ndarray:
        """(m, nel, 6, 2) P2 node positions of each design's triangles."""
        tri = self.tri
        out = []
        for sm in meshes:
            p = sm.points[tri]  # (nel, 3, 2)
            mids = 0.5 * (p + p[:, [1, 2, 0]])
            curved = self.edge_curved >= 0
            mids[curved] = sm.curved_midpoints[self.edge_curved[curved]]
            out.append(np.concatenate([p, mids], axis=1))
        return np.stack(out)

    def _reference(self, X: np.ndarray, W: np.ndarray) -> None:
        """Reference-element integrals of the straight-sided (affine) triangles' blocks.

        On an affine triangle the Jacobian is constant, so every block is a fixed
        combination of these integrals (taken with the curved triangles' quadrature,
        hence the same numbers as quadrature on the mapped triangle, to round-off),
        laid out so that each block is one matrix product with per-element coefficients.
        """
        r, s = X
        psi = np.stack([np.ones_like(r), r, s])  # (3, nq): 1, r, s
        dphi = self.dphi  # (ns, 2, nq)
        i2, i3 = np.eye(2), np.eye(3)
        # R[j, k, s, t] = int dphi_s/dX_j dphi_t/dX_k, spread over the DOF components (c, d):
        # k_loc[(s, c), (t, d)] = sum_jk F[c, d, j, k] R[j, k, s, t].
        grad = np.einsum("sjq,tkq,q->jkst", dphi, dphi, W)
        self.ref_stiff = np.einsum("cC,dD,jkst->cdjksCtD", i2, i2, grad).reshape(16, -1)
        # S[j, s, m] = int dphi_s/dX_j psi_m: kug[(s, c), k] and phi_div[k, (s, c)] are
        # sum_jm P[c, k, j, m] S[j, s, m] with per-element P.
        gpsi = np.einsum("sjq,mq,q->jsm", dphi, psi, W)
        self.ref_kug = np.einsum("cC,kK,jsm->ckjmsCK", i2, i3, gpsi).reshape(36, -1)
        self.ref_div = np.einsum("cC,kK,jsm->ckjmKsC", i2, i3, gpsi).reshape(36, -1)
        self.ref_mass = np.einsum("mq,nq,q->mn", psi, psi, W).reshape(9)  # int psi_m psi_n
        # Strain component p of local DOF (scalar s, component c) is sum_I sel[c, p, I] d phi_s / dx_I.
        sel = np.zeros((2, 4, 2))
        sel[0, 0, 0] = sel[1, 1, 1] = sel[0, 3, 1] = sel[1, 3, 0] = 1.0
        self.sel_zz = sel.transpose(1, 0, 2).reshape(4, 4)  # sigma_zz row of D -> (c, I)
        # E[(c, d, I, J)] = sum_pq sel[c, p, I] sel[d, q, J] D[p, q], as one product with D (16,).
        self.sel2 = np.einsum("cpI,dqJ->pqcdIJ", sel, sel).reshape(16, 16)

    def _affine_blocks(self, x6: np.ndarray, D: np.ndarray):
        """Element blocks of straight-sided triangles from the reference integrals.

        ``x6`` (e, 6, 2) nodes, ``D`` (e, 4, 4). Returns ``k_loc`` (e, nb, nb), ``kug``
        (e, nb, 3), ``phi_phi`` = int phi phi^T (e, 3, 3) with phi = (1, x, y),
        ``phi_div`` = int phi div (e, 3, nb), and the inverse Jacobian (e, 2, 2).
        """
        e = x6.shape[0]
        x0 = x6[:, 0]
        J = (x6[:, 1:3] - x0[:, None]).transpose(0, 2, 1)  # J[I, j] = dx_I / dX_j
        det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
        inv = (
            np.stack([np.stack([J[:, 1, 1], -J[:, 0, 1]], -1), np.stack([-J[:, 1, 0], J[:, 0, 0]], -1)], -2)
            / det[:, None, None]
        )
        adet = np.abs(det)[:, None]
        invT = inv.transpose(0, 2, 1)  # (e, I, j)
        C = (invT[:, :, None, :, None] * invT[:, None, :, None, :]).reshape(e, 4, 4)  # (IJ, jk)
        E = (D.reshape(e, 16) @ self.sel2).reshape(e, 4, 4)  # (e, (c, d), (I, J))
        k_loc = (((E @ C).reshape(e, 16) * adet) @ self.ref_stiff).reshape(e, self.nb, self.nb)
        # phi = A psi with psi = (1, r, s): A = [[1, 0, 0], [x0, J0.], [y0, J1.]].
        A = np.zeros((e, 3, 3))
        A[:, 0, 0] = 1.0
        A[:, 1:, 0] = x0
        A[:, 1:, 1:] = J
        # sigma_zz of DOF (s, c) = sum_I e2[c, I] d phi_s / dx_I; div of (s, c) = d phi_s / dx_c.
        e2inv = (D[:, 2] @ self.sel_zz).reshape(e, 2, 2) @ invT  # (e, c, j)
        G = np.stack([e2inv, inv.transpose(0, 2, 1)], axis=1)  # (e, 2, c, j)
        P = (G[:, :, :, None, :, None] * A[:, None, None, :, None, :]).reshape(e, 2, 36) * adet[:, :, None]
        kug = (P[:, 0] @ self.ref_kug).reshape(e, self.nb, 3)
        phi_div = (P[:, 1] @ self.ref_div).reshape(e, 3, self.nb)
        AA = (A[:, :, None, :, None] * A[:, None, :, None, :]).reshape(e, 9, 9)
        phi_phi = ((AA @ self.ref_mass) * adet).reshape(e, 3, 3)
        return k_loc, kug, phi_phi, phi_div, inv

    def _curved_blocks(self, x6: np.ndarray, D: np.ndarray):
        """:meth:`_affine_blocks` of curved (isoparametric P2) triangles, by quadrature.

        The inverse Jacobian is returned per quadrature point, (e, nq, 2, 2).
        """
        e, nb = x6.shape[0], self.nb
        J = np.einsum("ekI,kjq->eqIj", x6, self.dNg)  # dx_I / dX_j
        det = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
        inv = (
            np.stack(
                [np.stack([J[..., 1, 1], -J[..., 0, 1]], -1), np.stack([-J[..., 1, 0], J[..., 0, 0]], -1)], -2
            )
            / det[..., None, None]
        )
        g = self.dphi.transpose(2, 0, 1)[None] @ inv  # physical gradients (e, nq, ns, 2)
        w = np.abs(det) * self.W  # (e, nq)
        xq = np.einsum("ekI,kq->Ieq", x6, self.Ng)
        nq = w.shape[1]
        B = np.zeros((e, 4, nq, nb))  # strain (xx, yy, zz, xy) of each local DOF at each point
        B[:, 0, :, 0::2] = g[..., 0]
        B[:, 1, :, 1::2] = g[..., 1]
        B[:, 3, :, 0::2] = g[..., 1]
        B[:, 3, :, 1::2] = g[..., 0]
        DB = (D @ B.reshape(e, 4, nq * nb)).reshape(e, 4, nq, nb)
        Bw = B * w[:, None, :, None]
        k_loc = Bw.reshape(e, 4 * nq, nb).transpose(0, 2, 1) @ DB.reshape(e, 4 * nq, nb)
        phi = np.stack([np.ones_like(xq[0]), xq[0], xq[1]])  # (3, e, nq)
        phiw = (phi * w).transpose(1, 2, 0)  # (e, nq, 3)
        kug = DB[:, 2].transpose(0, 2, 1) @ phiw
        phi_phi = phiw.transpose(0, 2, 1) @ phi.transpose(1, 2, 0)
        phi_div = phiw.transpose(0, 2, 1) @ (B[:, 0] + B[:, 1])
        return k_loc, kug, phi_phi, phi_div, inv

    def _element_blocks(self, x6: np.ndarray, D: np.ndarray, lam: np.ndarray):
        """Element blocks of all triangles (M = m nel), the projected volumetric part included.

        Returns ``k_loc`` (M, nb, nb), ``kug`` (M, nb, 3), ``k_gg`` (M, 3, 3), ``phi_phi``
        (M, 3, 3) and the inverse Jacobian at the quadrature points (M, nq, 2, 2).
        """
        m, nel = x6.shape[0], self.nel
        M, nq, na = m * nel, self.W.size, self.n_affine
        parts = []  # the straight triangles are the first n_affine of every design, the curved the rest
        for part, blocks in ((slice(0, na), self._affine_blocks), (slice(na, nel), self._curved_blocks)):
            k = len(range(nel)[part])
            if k:
                got = blocks(x6[:, part].reshape(-1, 6, 2), D[:, part].reshape(-1, 4, 4))
                inv = np.broadcast_to(got[4][:, None], (m * k, nq, 2, 2)) if got[4].ndim == 3 else got[4]
                parts.append([v.reshape((m, k) + v.shape[1:]) for v in (*got[:4], inv)])
        k_loc, kug, phi_phi, phi_div, inv = (
            np.concatenate(vs, axis=1).reshape((M,) + vs[0].shape[2:]) for vs in zip(*parts, strict=True)
        )
        k_gg = D.reshape(M, 4, 4)[:, 2, 2, None, None] * phi_phi
        _add_volumetric(k_loc, kug, k_gg, phi_phi, phi_div, lam.reshape(M))
        return k_loc, kug, k_gg, phi_phi, inv.reshape(M, nq, 2, 2)

    def assemble(self, x6: np.ndarray, D: np.ndarray, lam: np.ndarray, ez: np.ndarray) -> dict:
        """The condensed operators of ``m`` designs (``element.assemble``'s algebra, batched).

        ``x6`` (m, nel, 6, 2) node positions; ``D`` (m, nel, 4, 4), ``lam`` and ``ez`` (m, nel)
        the region laws per triangle. Straight-sided triangles take their blocks from the
        reference integrals (:meth:`_affine_blocks`), curved ones by quadrature.
        """
        m, nel, nb = x6.shape[0], self.nel, self.nb
        k_loc, kug_loc, k_gg, phi_phi, inv = self._element_blocks(x6, D, lam)
        k_rr, k_rg, k_gg, xr, xg = _condense(k_loc, kug_loc, k_gg)
        nr = nb - 2
        data = np.ascontiguousarray((self.scatter_k @ k_rr.reshape(m, -1).T).T)  # (m, nnz)
        k_ug = self.scatter_g @ k_rg.reshape(m, nel * nr, 3).transpose(1, 0, 2).reshape(nel * nr, 3 * m)
        k_ug = k_ug.reshape(self.n, m, 3).transpose(1, 0, 2)  # (m, n, 3)
        f, area, xl, yl = self._lumen_load(x6)
        ez_moments = ez.reshape(m, nel, 1) * phi_phi[:, 0].reshape(m, nel, 3)
        ybar = ez_moments[..., 2].sum(axis=1) / ez_moments[..., 0].sum(axis=1)
        xq = np.einsum("mekI,kq->Imeq", x6, self.Ng)
        return {
            "data": data,
            "K_ug": k_ug,
            "K_gg": k_gg.reshape(m, nel, 3, 3).sum(axis=1),
            "f": f,
            "area": area,
            "centroid": np.stack([xl, yl], axis=1),
            "ybar": ybar,
            "inv": inv.reshape(m, nel, -1, 2, 2).transpose(0, 3, 4, 1, 2),
            "xq": xq,
            "xr": xr.reshape(m, nel, 2, nr),
            "xg": xg.reshape(m, nel, 2, 3),
        }

    def _lumen_load(self, x6: np.ndarray):
        """Unit lumen-pressure loads (m, n) and the lumens' areas and centroids."""
        xe = x6[:, self.l_elems]  # (m, nf, 6, 2)
        xg = np.einsum("mfkI,kfq->Imfq", xe, self.l_N)
        J = np.einsum("mfkI,kjfq->mfqIj", xe, self.l_dN)
        tangent = np.einsum("mfqIj,jf->Imfq", J, self.l_dir)
        length = np.hypot(tangent[0], tangent[1])
        normal = np.stack([tangent[1], -tangent[0]]) / length
        centre = xe[:, :, :3].mean(axis=2)  # (m, nf, 2)
        flip = np.sign(np.einsum("imfq,imf->mf", normal, xg.mean(axis=3) - centre.transpose(2, 0, 1)))
        normal = normal * flip[None, :, :, None]
        wds = length * self.l_ws
        f_loc = -np.einsum("kfq,kmfq,mfq->mfk", self.l_phi, normal[np.arange(self.nb) % 2], wds)
        m = x6.shape[0]
        f = (self.scatter_l @ f_loc.reshape(m, -1).T).T[:, : self.n]
        a_l = -(xg[0] * normal[0] * wds).sum(axis=(1, 2))
        xl = -(0.5 * xg[0] ** 2 * normal[0] * wds).sum(axis=(1, 2)) / a_l
        yl = -(0.5 * xg[1] ** 2 * normal[1] * wds).sum(axis=(1, 2)) / a_l
        return f, a_l, xl, yl

    def factorise(self, data: np.ndarray):
        """Numeric factorisation of one design's free-free block; the symbolic one is reused."""
        import qdldl

        n = self.free.size
        kff = sparse.csr_matrix((data, self.indices, self.indptr), shape=(n, n))
        upper = sparse.csc_matrix(
            (data.take(self.lower_at), self.indices_lower, self.indptr_lower), shape=(n, n)
        )
        if self.factor is None:
            self.factor = qdldl.Solver(upper, upper=True)
        else:
            self.factor.update(upper, upper=True)
        return kff, self.factor


def _inv2(a00, a01, a10, a11):
    """Entries of the inverses of batched 2 x 2 matrices given by their entries."""
    det = a00 * a11 - a01 * a10
    return a11 / det, -a01 / det, -a10 / det, a00 / det


def _add_volumetric(k_loc, kug, k_gg, phi_phi, phi_div, lam) -> None:
    """Add lambda * P(tr eps)^2, P onto P1 per element, in place (explicit small-matrix algebra).

    With phi = (1, x, y), the P1 pressures q = (1, x - xc, y - yc) = T phi have the
    block-diagonal Gram matrix diag(A, C), A = int 1, C the centred second moments; so
    ``k_loc += gu^T M^-1 gu`` and its ``kug``/``k_gg`` kin need no batched inverse.
    """
    area = phi_phi[:, 0, 0]
    c = phi_phi[:, 0, 1:] / area[:, None]  # centroid (M, 2)
    gg = phi_phi.copy()
    gg[:, 1:] -= c[:, :, None] * phi_phi[:, :1]  # T phi_phi: rows (q_k, phi_l)
    gu = phi_div.copy()
    gu[:, 1:] -= c[:, :, None] * phi_div[:, :1]
    i00, i01, i10, i11 = _inv2(gg[:, 1, 1], gg[:, 1, 2], gg[:, 2, 1], gg[:, 2, 2])
    # The centred block C = (T phi_phi T^T)[1:, 1:] = gg[1:, 1:] (the shift of the columns adds 0).
    lam_a = lam / area
    # M^-1 applied to the rows of [gu | gg]: row 0 / area, rows 1-2 by the centred block's inverse.
    rows = np.concatenate([gu, gg], axis=2)  # (M, 3, nb + 3)
    v = np.empty_like(rows)
    v[:, 0] = rows[:, 0] * lam_a[:, None]
    v[:, 1] = (i00[:, None] * rows[:, 1] + i01[:, None] * rows[:, 2]) * lam[:, None]
    v[:, 2] = (i10[:, None] * rows[:, 1] + i11[:, None] * rows[:, 2]) * lam[:, None]
    nb = gu.shape[2]
    vu, vg = v[:, :, :nb], v[:, :, nb:]
    k_loc += gu.transpose(0, 2, 1) @ vu
    kug += vu.transpose(0, 2, 1) @ gg
    k_gg += gg.transpose(0, 2, 1) @ vg


def _condense(k_loc, kug, k_gg):
    """Static condensation of the two bubble DOFs (the last local DOFs), explicit 2 x 2 algebra.

    Returns the retained blocks ``k_rr``, ``k_rg``, ``k_gg`` and the bubble maps ``xr``
    (M, 2, nr), ``xg`` (M, 2, 3): bubbles = -(xr u_r + xg g).
    """
    nr = k_loc.shape[1] - 2
    i00, i01, i10, i11 = _inv2(
        k_loc[:, nr, nr], k_loc[:, nr, nr + 1], k_loc[:, nr + 1, nr], k_loc[:, nr + 1, nr + 1]
    )
    kbr, kbg = k_loc[:, nr:, :nr], kug[:, nr:]
    xr = np.stack(
        [
            i00[:, None] * kbr[:, 0] + i01[:, None] * kbr[:, 1],
            i10[:, None] * kbr[:, 0] + i11[:, None] * kbr[:, 1],
        ],
        axis=1,
    )
    xg = np.stack(
        [
            i00[:, None] * kbg[:, 0] + i01[:, None] * kbg[:, 1],
            i10[:, None] * kbg[:, 0] + i11[:, None] * kbg[:, 1],
        ],
        axis=1,
    )
    kbr_t = kbr.transpose(0, 2, 1)
    k_rr = k_loc[:, :nr, :nr] - kbr_t @ xr
    k_rg = kug[:, :nr] - kbr_t @ xg
    k_gg = k_gg - kbg.transpose(0, 2, 1) @ xg
    return k_rr, k_rg, k_gg, xr, xg


_KERNELS: dict[str, _Kernel] = {}


def _kernel(template) -> _Kernel:
    key = template.mesh.key
    if key not in _KERNELS:
        if len(_KERNELS) >= 256:
            _KERNELS.pop(next(iter(_KERNELS)))
        _KERNELS[key] = _Kernel(template)
    return _KERNELS[key]


def _silicone_range(kernel: _Kernel, ue_r, xr, xg, inv, g, x, y) -> tuple[float, float]:
    """(smallest, largest) principal strain over the silicone triangles' quadrature points.

    ``ue_r`` (e, nb - 2) retained DOFs of the silicone triangles; ``xr``, ``xg`` their bubble
    maps, ``inv`` (2, 2, e, nq) inverse Jacobians, ``x``, ``y`` (e, nq) the points; ``g`` the
    global strains.
    """
    if ue_r.shape[0] == 0:
        return (0.0, 0.0)
    ue = np.concatenate([ue_r, -((xr @ ue_r[:, :, None])[..., 0] + xg @ g)], axis=1)
    ns, nq = kernel.dphi.shape[0], kernel.W.size
    # Reference gradients d u_c / d X_j (c, j, e, q), then the physical ones:
    # d u_c / d x_I = sum_j (d u_c / d X_j) inv[j, I].
    ref = (ue.reshape(-1, ns, 2).transpose(0, 2, 1) @ kernel.dphi.reshape(ns, 2 * nq)).reshape(-1, 2, 2, nq)
    ref = ref.transpose(1, 2, 0, 3)
    exx = ref[0, 0] * inv[0, 0] + ref[0, 1] * inv[1, 0]
    eyy = ref[1, 0] * inv[0, 1] + ref[1, 1] * inv[1, 1]
    exy = 0.5 * (
        ref[0, 0] * inv[0, 1] + ref[0, 1] * inv[1, 1] + ref[1, 0] * inv[0, 0] + ref[1, 1] * inv[1, 0]
    )
    ezz = g[0] + g[1] * x + g[2] * y
    mean, radius = 0.5 * (exx + eyy), np.sqrt((0.5 * (exx - eyy)) ** 2 + exy**2)
    return (float(np.minimum(mean - radius, ezz).min()), float(np.maximum(mean + radius, ezz).max()))


def _solve_one(kernel: _Kernel, ops: dict, j: int, loads, extra: float):
    """Condensation, loads and silicone strains of design ``j`` of an assembled group."""
    t0 = time.perf_counter()
    kff, factor = kernel.factorise(ops["data"][j])
    t0 = _tick("factorisation", t0)
    free, n = kernel.free, kernel.n
    k_ug = ops["K_ug"][j]
    rhs = np.column_stack([k_ug[free], ops["f"][j][free]])
    sol = np.column_stack([factor.solve(rhs[:, c]) for c in range(rhs.shape[1])])
    resid = kff @ sol - rhs
    row_sum = np.add.reduceat(np.abs(kff.data), kff.indptr[:-1]).max()  # no empty rows (SPD)
    scale = row_sum * np.abs(sol).max(axis=0) + np.abs(rhs).max(axis=0)
    backward = float((np.abs(resid).max(axis=0) / np.where(scale > 0, scale, 1.0)).max())
    x_g, x_p = sol[:, :3], sol[:, 3]
    k_sec = ops["K_gg"][j] - k_ug[free].T @ x_g
    k_sec = 0.5 * (k_sec + k_sec.T)
    k_sec[1, 1] += extra
    k_sec[2, 2] += extra
    xl, yl = ops["centroid"][j]
    cap = ops["area"][j] * np.array([1.0, xl, yl])
    t0 = _tick("solve", t0)
    sil = kernel.silicone_elements
    rdofs = kernel.dofs[: kernel.nb - 2, sil].T
    xr, xg, inv = ops["xr"][j][sil], ops["xg"][j][sil], ops["inv"][j][:, :, sil]
    x, y = ops["xq"][:, j][:, sil]
    out = {}
    for ld in loads:
        f_g = cap.copy()
        u = np.zeros(n)
        if ld == "lumen":
            f_g -= k_ug[free].T @ x_p
            u[free] = x_p
        g = np.linalg.solve(k_sec, f_g)
        u[free] -= x_g @ g
        out[ld] = (g, float(ops["f"][j] @ u), _silicone_range(kernel, u[rdofs], xr, xg, inv, g, x, y))
    _tick("post", t0)
    return k_sec, out, backward


def _result(d, laws, mesh, ops, j, k_sec, out, backward, kernel, mesh_size, segments, opts, seconds):
    from softcath.analytic import gains
    from softcath.fem.section_model.api import SectionResult

    formula_k, _ = gains(d, "cap")
    ea = float(k_sec[0, 0])
    ybar = float(ops["ybar"][j])
    return SectionResult(
        design_name=d.name,
        loads=tuple(out),
        curvature_per_mm_per_MPa={ld: float(v[0][2]) for ld, v in out.items()},
        elongation_per_MPa={ld: float(v[0][0] + v[0][2] * ybar) for ld, v in out.items()},
        lumen_area_change_mm2_per_MPa={ld: v[1] for ld, v in out.items()},
        fem_formula_ratio={
            ld: float(v[0][2] / formula_k) if formula_k else float("nan") for ld, v in out.items()
        },
        EA_N=ea,
        EI_N_mm2=float(k_sec[2, 2] - k_sec[0, 2] ** 2 / ea),
        EI_lateral_N_mm2=float(k_sec[1, 1] - k_sec[0, 1] ** 2 / ea),
        coupling_N_mm=float(k_sec[0, 2]),
        neutral_axis_mm=float(k_sec[0, 2] / ea),
        axial_centroid_mm=ybar,
        lumen_area_mm2=float(ops["area"][j]),
        lumen_centroid_y_mm=float(ops["centroid"][j][1]),
        stiffness=tuple(tuple(float(v) for v in row) for row in k_sec),
        poisson_ratio_silicone=laws[TUBE].poisson_ratio,
        coil_modulus=opts["coil_modulus"],
        coil_bending=opts["coil_bending"],
        length_mm=float(d.tip.bending_length),
        mesh_size_mm=float(mesh_size),
        segments=int(segments),
        dofs=kernel.n + 3,
        n_triangles=kernel.nel,
        mesh_seconds=float(mesh.seconds),
        seconds=float(seconds),
        backward_error=backward,
        assembly=d.assembly.to_dict(),
    )


def _solve_chunk(members: list, results: list, loads, mesh_size, segments, opts) -> None:
    """Assemble a chunk of designs sharing a template at once and solve each; results in place."""
    t0 = time.perf_counter()
    kernel = _kernel(members[0][5])
    labels = kernel.labels
    keys = sorted({int(k) for k in np.unique(labels)})
    table = np.searchsorted(keys, labels)
    D = np.stack([np.stack([m[2][k].D for k in keys])[table] for m in members])
    lam = np.stack([np.array([m[2][k].lam for k in keys])[table] for m in members])
    ez = np.stack([np.array([m[2][k].axial_modulus for k in keys])[table] for m in members])
    ops = kernel.assemble(kernel.geometry([m[4] for m in members]), D, lam, ez)
    share = (_tick("assembly", t0) - t0) / len(members)
    for j, (i, d, laws, extra, mesh, _) in enumerate(members):
        t1 = time.perf_counter()
        try:
            k_sec, out, backward = _solve_one(kernel, ops, j, loads, extra)
            r = _result(
                d,
                laws,
                mesh,
                ops,
                j,
                k_sec,
                out,
                backward,
                kernel,
                mesh_size,
                segments,
                opts,
                share + mesh.seconds + time.perf_counter() - t1,
            )
            results[i] = BatchItem(r, {ld: v[2] for ld, v in out.items()})
        except Exception as exc:
            raise_pending_stop()
            results[i] = exc


def _solve_alone(d, mesher: str, loads, mesh_size, segments, opts):
    """A design solved by the per-design section model (its :class:`BatchItem` or its exception)."""
    from softcath.fem.section_model.api import section_model
    from softcath.fem.section_model.strain import silicone_strain_range

    try:
        r = section_model(
            d, loads=loads, mesh_size=mesh_size, segments=segments, mesher=mesher, keep_fields=True, **opts
        )
        strains = {ld: silicone_strain_range(r, ld) for ld in loads}
        return BatchItem(dataclasses.replace(r, fields=None), strains)
    except Exception as exc:
        raise_pending_stop()
        return exc


def section_models(
    designs: Sequence,
    *,
    loads: Sequence[str] = LOADS,
    mesh_size: float = MESH_SIZE,
    segments: int = SEGMENTS,
    coil_modulus: str = "tension",
    coil_bending: str = "annulus",
) -> list:
    """The section model of every design (template meshes, batched per template).

    Parameters
    ----------
    designs
        :class:`design.TipDesign` objects.
    loads, mesh_size, segments, coil_modulus, coil_bending
        As in :func:`~softcath.fem.section_model.section_model`.

    Returns
    -------
    list
        Per design, a :class:`BatchItem` or the exception that design raised (a
        design the template cannot morph to is solved on a fresh gmsh mesh; a design
        whose ``assembly`` is not the default bonded tip is solved alone by
        :func:`~softcath.fem.section_model.section_model`, which splits its interfaces).
    """
    from softcath.design.errors import DesignError
    from softcath.fem.adapter import geometry_from_design
    from softcath.fem.limits import check_section_budget
    from softcath.fem.section_model.api import COIL_BENDING
    from softcath.fem.section_model.coil_models import coil_terms
    from softcath.fem.section_model.laws import section_laws_from_design
    from softcath.fem.section_model.template import log_fallback, morph, section_template

    loads = tuple(ld for ld in LOADS if ld in tuple(loads))
    if coil_bending not in COIL_BENDING:
        raise DesignError("coil_bending", coil_bending, f"must be one of {COIL_BENDING}")
    opts = {"coil_modulus": coil_modulus, "coil_bending": coil_bending}
    results: list = [None] * len(designs)
    groups: dict[str, list] = {}
    alone: dict[int, str] = {}  # designs solved one by one below, with the mesher to use
    for i, d in enumerate(designs):
        t0 = time.perf_counter()
        try:
            if not d.assembly.is_default:  # interfaces split, axial groups: the per-design path
                alone[i] = "template"
                continue
            g = geometry_from_design(d)
            check_section_budget(coil_outer_radius=g.coil_outer_radius, mesh_size=mesh_size)
            laws = section_laws_from_design(d, coil_modulus=coil_modulus)
            laws, extra = coil_terms(d, coil_bending, laws)
        except Exception as exc:  # reported per design by the caller
            raise_pending_stop()
            results[i] = exc
            continue
        t0 = _tick("laws", t0)
        try:
            template = section_template(g, mesh_size=mesh_size, segments=segments)
            t0 = _tick("template", t0)
            mesh = morph(template, g)
            _tick("morph", t0)
        except Exception as exc:  # refused or failed: solved below on a fresh gmsh mesh
            raise_pending_stop()
            _tick("morph", t0)
            log_fallback(g, exc)
            alone[i] = "gmsh"
            continue
        groups.setdefault(template.mesh.key, []).append((i, d, laws, sum(extra.values()), mesh, template))
    # A group is assembled in chunks of CHUNK designs: a robust optimisation's task of 10⁴ variants
    # sharing a template would otherwise need ~100 GB at once.
    chunks = [m[k : k + CHUNK] for m in groups.values() for k in range(0, len(m), CHUNK)]
    for members in chunks:
        _solve_chunk(members, results, loads, mesh_size, segments, opts)
    for i, mesher in alone.items():
        results[i] = _solve_alone(designs[i], mesher, loads, mesh_size, segments, opts)
    return results
