"""The finite-strain section on its template mesh: what one template shares, what one design adds.

A design meshed by its section topology's template (``softcath.fem.section_model.template``)
differs from the other designs of that template in node positions and laws only, so
everything that depends on the connectivity is made once per template
(:class:`FastTemplate`): the CCR DOF layout, the reference shape functions, the
free-free pattern of the retained unknowns (the linear section model's, from its
batched kernel) with its PARDISO analysis, the lumen wall's parent triangles and
reference data. Per design (:func:`fast_problem`) the quadrature data come from the
P2 node positions in a few array operations, and every Newton step is one compiled
pass (:mod:`~softcath.fem.section_model.finite_strain.kernel`) that assembles the
residual and the tangent with the bubbles condensed; the tangent's retained block
is refactorised numerically only (Cholesky; a tangent that is not positive definite
is factorised by SuperLU instead) and the three globals are eliminated through
their 3 x 3 Schur complement. The Newton walk is
:mod:`~softcath.fem.section_model.finite_strain.fast_walk`'s.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from softcath.fem.hyperelastic.laws import AnisotropicSVK, Yeoh
from softcath.fem.section_model.finite_strain.discretisation import N_GLOBAL, _axial_modulus
from softcath.fem.section_model.template_kernel import _kernel

__all__ = ["FastTemplate", "FastProblem", "Unsupported", "fast_problem", "fast_template"]


class Unsupported(Exception):
    """The template path does not take this case: the caller uses the reference path with ``mesher``."""

    def __init__(self, why: str, *, mesher: str = "template") -> None:
        super().__init__(why)
        self.mesher = mesher


class FastTemplate:
    """Everything of a template mesh that the finite-strain section needs and no design changes."""

    def __init__(self, template) -> None:
        from skfem import CellBasis, ElementTriCCR, ElementVector

        k = _kernel(template)  # the linear section model's per-template data (pattern, scatters)
        self.k = k
        basis = CellBasis(template.mesh.skfem_mesh(), ElementVector(ElementTriCCR()), intorder=4)
        scalar = ElementTriCCR()
        self.phi = np.ascontiguousarray(np.stack([scalar.lbasis(basis.X, s)[0] for s in range(7)], axis=1))
        self.rdof = np.ascontiguousarray(k.dofs[:12].T, dtype=np.int64)  # (nel, 12) retained
        self.bdof = np.ascontiguousarray(k.dofs[12:].T, dtype=np.int64)  # (nel, 2) bubbles
        self.N, self.n = int(k.N), int(k.n)
        self.free = k.free
        self.free_of = np.full(self.n, -1, dtype=np.int64)
        self.free_of[k.free] = np.arange(k.free.size)
        g = np.arange(self.N, self.N + N_GLOBAL)
        self.local = np.ascontiguousarray(
            np.concatenate([k.dofs.T, np.broadcast_to(g, (k.nel, N_GLOBAL))], axis=1), dtype=np.int64
        )  # (nel, 17): in-plane unknowns then the globals
        # lumen wall: scalar shape functions and their derivative along each edge (bubbles vanish there)
        xl = (
            np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])[k.l_which].T[:, :, None]
            + k.l_dir[:, :, None] * k.l_s
        )
        self.lphi = np.ascontiguousarray(np.stack([scalar.lbasis(xl, s)[0] for s in range(7)], axis=-1))
        self.ldphi = np.ascontiguousarray(
            np.stack([np.einsum("ifq,if->fq", scalar.lbasis(xl, s)[1], k.l_dir) for s in range(7)], axis=-1)
        )
        self.l_local = self.local[k.l_elems]  # (nf, 17)
        self.l_slot = k.slot_rr[k.l_elems]  # (nf, 12, 12)
        self.l_rdof = self.rdof[k.l_elems]
        self.lock = threading.Lock()  # one walk at a time on the template's factor
        self.factorisations = 0  # numbers the factors the handle holds
        self._spd = None

    def spd(self):
        """The retained block's repeated Cholesky (analysis kept, one MKL thread: a 3k-unknown
        block gains little from more, and its answer is then the same in every process)."""
        if self._spd is None:
            from softcath.fem.section_model.spd_factor import SpdFactor  # numba: heavy, first use

            self._spd = SpdFactor(self.k.indptr, self.k.indices, threads=1)  # same bits in every process
        return self._spd


_TEMPLATES: dict[str, FastTemplate] = {}


def fast_template(template) -> FastTemplate:
    """The :class:`FastTemplate` of ``template`` (made once per process)."""
    key = template.mesh.key
    if key not in _TEMPLATES:
        if len(_TEMPLATES) >= 256:
            _TEMPLATES.pop(next(iter(_TEMPLATES)))
        _TEMPLATES[key] = FastTemplate(template)
    return _TEMPLATES[key]


@dataclass(frozen=True)
class FastProblem:
    """One design on its template: quadrature data, laws per triangle and the lumen wall."""

    tpl: FastTemplate
    w: np.ndarray
    gs: np.ndarray
    xq: np.ndarray
    pq: np.ndarray
    minv: np.ndarray
    kind: np.ndarray
    yeoh: np.ndarray
    svk: np.ndarray
    silicone: np.ndarray
    axial_modulus: np.ndarray
    l_points: np.ndarray
    l_tangents: np.ndarray
    l_weights: np.ndarray
    size: float

    @property
    def ndofs(self) -> int:
        """Unknowns: in-plane DOFs plus the three globals."""
        return self.tpl.N + N_GLOBAL

    @property
    def n_u(self) -> int:
        """In-plane unknowns (the globals follow)."""
        return self.tpl.N

    def centroid(self, u: np.ndarray) -> np.ndarray:
        """Axial-stiffness-weighted centroid of the deformed section (as ``curve._centroid``)."""
        ue = u[self.tpl.local[:, :14]].reshape(-1, 7, 2)
        x = self.xq + np.einsum("qs,esc->eqc", self.tpl.phi, ue)
        wt = self.w * self.axial_modulus[:, None]
        return np.einsum("cq,cqa->a", wt, x) / wt.sum()


def _laws(labels: np.ndarray, law_map: dict, silicone_labels):
    """Per-triangle law arrays for the kernel; :class:`Unsupported` for a law it does not know."""

    nel = labels.size
    kind = np.zeros(nel, np.int64)
    yeoh = np.zeros((nel, 4))
    svk = np.zeros((nel, 3, 3, 3, 3))
    ez = np.zeros(nel)
    for label in np.unique(labels):
        law = law_map.get(int(label))
        idx = labels == label
        if type(law) is Yeoh and law.splits_volume:
            yeoh[idx] = (law.c1, law.c2, law.c3, law.bulk_modulus)
        elif type(law) is AnisotropicSVK:
            kind[idx] = 1
            svk[idx] = law.tensor
        else:
            raise Unsupported(f"law {type(law).__name__} of region {int(label)}")
        ez[idx] = _axial_modulus(law)
    silicone = np.isin(labels, list(silicone_labels))
    return kind, yeoh, svk, silicone, ez


def fast_problem(tpl: FastTemplate, mesh, law_map: dict, silicone_labels) -> FastProblem:
    """The design's quadrature data on the morphed template ``mesh`` (a ``SectionMesh``)."""
    k = tpl.k
    x6 = k.geometry([mesh])[0]  # (nel, 6, 2) P2 nodes in scikit-fem's vertex order
    jac = np.einsum("ekI,kjq->eqIj", x6, k.dNg)  # dx_I / dX_j
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    inv = np.empty_like(jac)  # dX_j / dx_I as [j, I]
    inv[..., 0, 0], inv[..., 0, 1] = jac[..., 1, 1] / det, -jac[..., 0, 1] / det
    inv[..., 1, 0], inv[..., 1, 1] = -jac[..., 1, 0] / det, jac[..., 0, 0] / det
    w = np.abs(det) * k.W
    gs = np.ascontiguousarray(np.einsum("sjq,eqjI->eqsI", k.dphi, inv))
    xq = np.ascontiguousarray(np.einsum("ekI,kq->eqI", x6, k.Ng))
    area = w.sum(axis=1)
    xc = np.einsum("eq,eqI->eI", w, xq) / area[:, None]
    pq = np.concatenate([np.ones(w.shape + (1,)), xq - xc[:, None, :]], axis=2)
    minv = np.linalg.inv(np.einsum("eq,eqa,eqb->eab", w, pq, pq))
    kind, yeoh, svk, silicone, ez = _laws(np.asarray(k.labels), law_map, silicone_labels)
    # lumen wall: positions and tangents along each edge, signed so the lumen is on the left
    xe = x6[k.l_elems]  # (nf, 6, 2)
    points = np.einsum("fkI,kfq->fqI", xe, k.l_N)
    tangents = np.einsum("fkI,kjfq,jf->fqI", xe, k.l_dN, k.l_dir)
    centre = xe[:, :3].mean(axis=1)
    mid = points.mean(axis=1) - centre
    left = np.stack([-tangents[..., 1].mean(axis=1), tangents[..., 0].mean(axis=1)], axis=-1)
    sign = np.sign(np.einsum("fa,fa->f", left, mid))
    return FastProblem(
        tpl=tpl,
        w=np.ascontiguousarray(w),
        gs=gs,
        xq=xq,
        pq=np.ascontiguousarray(pq),
        minv=np.ascontiguousarray(minv),
        kind=kind,
        yeoh=yeoh,
        svk=svk,
        silicone=silicone,
        axial_modulus=ez,
        l_points=np.ascontiguousarray(points),
        l_tangents=np.ascontiguousarray(tangents),
        l_weights=np.ascontiguousarray(sign[:, None] * k.l_ws[None, :]),
        size=float(np.abs(mesh.points).max()),
    )
