"""A template mesh's assembly kernel: everything of a section template that does not depend on
node positions or moduli, built once per template and cached.

The CCR DOF layout and reference shape functions, the sparse pattern of the condensed
stiffness with the scatter from element blocks to it, the lumen edges' parent elements, the
rigid-body pins and the analysis of the free-free block (used by
:mod:`softcath.fem.section_model.batch` and the finite-strain template path).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy import sparse

from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.section_model.element import _rigid_pins

__all__: list[str] = []


class _Kernel:
    """Everything of a template that does not depend on node positions or moduli."""

    def __init__(self, template) -> None:
        from skfem import CellBasis, ElementTriCCR, ElementVector

        m = template.mesh
        mesh = m.skfem_mesh()
        basis = CellBasis(mesh, ElementVector(ElementTriCCR()), intorder=4)
        self.template = template
        dofs = basis.element_dofs  # (nb, nel)
        nb, nel = dofs.shape
        interior = basis.interior_dofs
        if interior is None:
            raise RuntimeError("unexpected CCR DOF layout: the basis has no bubbles")
        if not np.array_equal(dofs[nb - 2 :], interior):
            raise RuntimeError("unexpected CCR DOF layout: bubbles are not the last local DOFs")
        self.nb, self.nel, self.N = nb, nel, basis.N
        self.n = basis.N - interior.size
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
        self.pinned = _rigid_pins(basis, mesh)
        self._pattern()
        self._lumen(m, mesh)
        self.factor = None

    def _triangles(self, m, mesh, dofs) -> None:
        """Per-triangle tables: vertices, which local edges are curved, DOFs, labels."""
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
        self.tri, self.edge_curved, self.dofs = tri, edge_curved, dofs
        self.labels = m.labels
        self.silicone_elements = np.flatnonzero(np.isin(self.labels, (TUBE, FILLER)))

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
        # Where each entry of the triangles' retained blocks goes: its slot in the free-free
        # pattern (-1: a pinned row or column), and its row x column in K_ug (n, 3).
        self.slot_rr = np.full(rows.size, -1, dtype=np.int64)
        self.slot_rr[ok] = slot
        self.slot_rr = self.slot_rr.reshape(nel, nb - 2, nb - 2)
        rdofs = dofs[: nb - 2].T
        self.slot_rg = (rdofs[:, :, None] * 3 + np.arange(3)).astype(np.int64)  # (nel, nr, 3)

    def _lumen(self, m, mesh) -> None:
        t = mesh.t
        nv = int(t.max()) + 1
        le = np.sort(m.lumen_edges, axis=1)
        all_edges = np.sort(np.concatenate([t[[i, j]].T for i, j in ((0, 1), (1, 2), (2, 0))]), axis=1)
        keys = all_edges[:, 0].astype(np.int64) * nv + all_edges[:, 1]
        order = np.argsort(keys)
        want = le[:, 0].astype(np.int64) * nv + le[:, 1]
        hit = order[np.searchsorted(keys[order], want)]
        self.l_elems, self.l_which = hit % self.nel, hit // self.nel
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
        points = np.stack([sm.points for sm in meshes])  # one template: one node count
        p = points[:, self.tri]  # (m, nel, 3, 2)
        mids = 0.5 * (p + p[:, :, [1, 2, 0]])
        curved = self.edge_curved >= 0
        mids[:, curved] = np.stack([sm.curved_midpoints for sm in meshes])[:, self.edge_curved[curved]]
        return np.concatenate([p, mids], axis=2)

    def assemble(self, x6: np.ndarray, D: np.ndarray, lam: np.ndarray, ez: np.ndarray) -> dict:
        """The condensed operators of ``m`` designs (``element.assemble``'s algebra, compiled).

        ``x6`` (m, nel, 6, 2) node positions; ``D`` (m, nel, 4, 4), ``lam`` and ``ez`` (m, nel)
        the region laws per triangle (:func:`~softcath.fem.section_model.element_kernel.element_blocks`).
        """
        from softcath.fem.section_model.element_kernel import element_blocks  # numba: heavy, first use

        m, nel, nr, nq = x6.shape[0], self.nel, self.nb - 2, self.W.size
        M = m * nel
        blocks = element_blocks(
            x6.reshape(M, 6, 2),
            D.reshape(M, 4, 4),
            lam.reshape(M),
            dphi=self.dphi,
            W=self.W,
            Ng=self.Ng,
            dNg=self.dNg,
            slot_rr=self.slot_rr,
            slot_rg=self.slot_rg,
            nnz=self.nnz,
            n_ug=3 * self.n,
        )
        f, area, xl, yl = self._lumen_load(x6)
        ez_moments = ez.reshape(m, nel, 1) * blocks["moments"].reshape(m, nel, 3)
        ybar = ez_moments[..., 2].sum(axis=1) / ez_moments[..., 0].sum(axis=1)
        return {
            "data": blocks["data"],
            "K_ug": blocks["K_ug"].reshape(m, self.n, 3),
            "K_gg": blocks["k_gg"].reshape(m, nel, 3, 3).sum(axis=1),
            "f": f,
            "area": area,
            "centroid": np.stack([xl, yl], axis=1),
            "ybar": ybar,
            "inv": blocks["inv"].reshape(m, nel, nq, 2, 2),
            "xq": blocks["xq"].reshape(m, nel, nq, 2),
            "xr": blocks["xr"].reshape(m, nel, 2, nr),
            "xg": blocks["xg"].reshape(m, nel, 2, 3),
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

    def spd_factor(self):
        """The free-free block's :class:`~softcath.fem.section_model.spd_factor.SpdFactor` (analysis kept)."""
        if self.factor is None:
            from softcath.fem.section_model.spd_factor import SpdFactor  # numba: heavy, first use

            self.factor = SpdFactor(self.indptr, self.indices)
        return self.factor


_KERNELS: dict[str, _Kernel] = {}


def _kernel(template) -> _Kernel:
    key = template.mesh.key
    if key not in _KERNELS:
        if len(_KERNELS) >= 256:
            _KERNELS.pop(next(iter(_KERNELS)))
        _KERNELS[key] = _Kernel(template)
    return _KERNELS[key]
