"""Section models of many designs at once: template meshes, a compiled element kernel, analyses reused.

Designs whose sections share a template mesh (``softcath.fem.section_model.template``)
differ only in node positions and region moduli, so everything that depends on the
connectivity is done once per template (a :class:`_Kernel`): the CCR DOF layout and
reference shape functions, the sparse pattern of the condensed stiffness with the
scatter from element blocks to it, the lumen edges' parent elements, the rigid-body
pins and the analysis (ordering, symbolic factorisation) of the free-free block. Per
design, the element blocks come from the compiled kernel
(:mod:`softcath.fem.section_model.element_kernel`, equal to scikit-fem's quadrature
assembly to 1e-10: tests/fem/section_model/test_fast_assembly.py), the block is
factorised numerically only (MKL PARDISO, or QDLDL where MKL is missing) and the four
right-hand sides (three unit global strains, the unit lumen pressure) are solved at once.

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

from softcath.analytic import design_inputs_many, gains_arrays
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import FILLER, TUBE
from softcath.fem.limits import check_section_budget
from softcath.fem.section_model.api import COIL_BENDING, SectionResult, section_model
from softcath.fem.section_model.coil_models import coil_terms
from softcath.fem.section_model.element import _rigid_pins
from softcath.fem.section_model.end_zones import end_zones
from softcath.fem.section_model.laws import section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.solve import LOADS
from softcath.fem.section_model.strain import silicone_strain_range
from softcath.fem.section_model.template import log_fallback, morph, section_template
from softcath.interrupts import raise_pending_stop

__all__ = ["BatchItem", "CHUNK", "TIMERS", "section_models"]

log = logging.getLogger(__name__)

#: Wall seconds of this process per stage (a cheap clock: the CPU clock costs ~1 ms a call
#: on a loaded machine): ``laws``, ``template``
#: (reference section and, once per template, its gmsh mesh), ``morph``, ``assembly``,
#: ``factorisation``, ``solve``, ``post``: the benchmark's time split.
TIMERS: dict[str, float] = {}
#: Most designs assembled at once. The compiled kernel works triangle by triangle, so a chunk
#: only bounds the memory of its outputs (~1.5 MB per paper-sized design).
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
        from softcath.fem.section_model.element_kernel import element_blocks

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
            from softcath.fem.section_model.spd_factor import SpdFactor

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


def _solve_all(kernel: _Kernel, ops: dict) -> tuple[list, np.ndarray]:
    """Factorise and solve every design of an assembled chunk, one after the other.

    Returns per design its solutions (n_free, 4) of the four right-hand sides (three unit
    global strains' loads, the unit lumen pressure) or the exception it raised, and the
    right-hand sides (m, n_free, 4).
    """
    t0 = time.perf_counter()
    free = kernel.free
    rhs = np.concatenate([ops["K_ug"][:, free], ops["f"][:, free, None]], axis=2)
    factor = kernel.spd_factor()
    solved: list = []
    for j in range(rhs.shape[0]):  # back to back: the factor's memory stays warm
        try:
            factor.factorise(ops["data"][j])
            t0 = _tick("factorisation", t0)
            solved.append(factor.solve(rhs[j]))
        except Exception as exc:
            raise_pending_stop()
            solved.append(exc)
        t0 = _tick("solve", t0)
    return solved, rhs


def _condense(kernel: _Kernel, ops: dict, ok: np.ndarray, sol: np.ndarray, rhs: np.ndarray, loads, extra):
    """Section stiffnesses, global strains, lumen area changes and silicone strains of designs ``ok``.

    ``sol`` and ``rhs`` (len(ok), n_free, 4); ``extra`` the coils' bending stiffness added
    to the two bending terms, per design.
    """
    from softcath.fem.section_model.element_kernel import strain_extremes

    t0 = time.perf_counter()
    k_ug = rhs[:, :, :3]
    x_g, x_p = sol[:, :, :3], sol[:, :, 3]
    coupled = np.einsum("mfi,mfj->mij", k_ug, sol)  # K_ugᵀ [x_g x_p]
    k_sec = ops["K_gg"][ok] - coupled[:, :, :3]
    k_sec = 0.5 * (k_sec + k_sec.transpose(0, 2, 1))
    k_sec[:, 1, 1] += extra
    k_sec[:, 2, 2] += extra
    area, centroid = ops["area"][ok], ops["centroid"][ok]
    cap = area[:, None] * np.column_stack([np.ones_like(area), centroid])
    f = ops["f"][ok]
    per_load = {}
    for ld in loads:
        lumen = ld == "lumen"
        f_g = cap - coupled[:, :, 3] if lumen else cap
        g = np.linalg.solve(k_sec, f_g[:, :, None])[:, :, 0]
        u = np.zeros((len(ok), kernel.n))
        u[:, kernel.free] = (x_p if lumen else 0.0) - np.einsum("mfi,mi->mf", x_g, g)
        per_load[ld] = (g, np.einsum("mn,mn->m", f, u), u)
    out = []
    for c, j in enumerate(ok):
        blocks = {key: ops[key][j] for key in ("xr", "xg", "inv", "xq")}
        strains = {
            ld: strain_extremes(u[c], kernel.dofs, kernel.silicone_elements, blocks, g[c], kernel.dphi)
            for ld, (g, _, u) in per_load.items()
        }
        out.append((k_sec[c], {ld: (g[c], float(da[c]), strains[ld]) for ld, (g, da, _) in per_load.items()}))
    _tick("post", t0)
    return out


def _result(
    d, laws, mesh, ops, j, k_sec, out, backward, kernel, mesh_size, segments, opts, seconds, formula_k
):

    ea = float(k_sec[0, 0])
    ybar = float(ops["ybar"][j])
    return SectionResult(
        design_name=d.name,
        end_zones=end_zones(d),
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
    formula_k, _ = gains_arrays(design_inputs_many([m[1] for m in members]), "cap")
    share = (_tick("assembly", t0) - t0) / len(members)
    t1 = time.perf_counter()
    solved, rhs = _solve_all(kernel, ops)
    ok = np.array([j for j, v in enumerate(solved) if not isinstance(v, Exception)], dtype=int)
    for j, v in enumerate(solved):
        if isinstance(v, Exception):
            results[members[j][0]] = v
    if ok.size:
        extra = np.array([members[j][3] for j in ok])
        sol = np.stack([solved[j][0] for j in ok])
        try:
            condensed = _condense(kernel, ops, ok, sol, rhs[ok], loads, extra)
        except Exception:  # one design's failure (a singular section stiffness) is its own
            raise_pending_stop()
            condensed = []
            for c, j in enumerate(ok):
                try:
                    condensed += _condense(
                        kernel, ops, ok[c : c + 1], sol[c : c + 1], rhs[j : j + 1], loads, extra[c : c + 1]
                    )
                except Exception as exc:
                    raise_pending_stop()
                    condensed.append(exc)
        share += (time.perf_counter() - t1) / len(members)
        for done, j in zip(condensed, ok, strict=True):
            i, d, laws, _, mesh, _ = members[j]
            if isinstance(done, Exception):
                results[i] = done
                continue
            k_sec, out = done
            try:
                r = _result(
                    d, laws, mesh, ops, j, k_sec, out, solved[j][1], kernel, mesh_size, segments, opts,
                    share + mesh.seconds, float(formula_k[j]),
                )  # fmt: skip
                results[i] = BatchItem(r, {ld: v[2] for ld, v in out.items()})
            except Exception as exc:
                raise_pending_stop()
                results[i] = exc


def _solve_alone(d, mesher: str, loads, mesh_size, segments, opts):
    """A design solved by the per-design section model (its :class:`BatchItem` or its exception)."""

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
