r"""The 3-D linear FEM of the tip as built: regions split at their interfaces, normals tied.

The same mechanism as the section model's (:mod:`softcath.fem.section_model.interfaces`),
on the extruded P2 tetrahedral mesh: every vertex shared by two regions is
duplicated (one copy per region), and every pair of coincident P2 nodes on an
interface is tied by the projection :math:`u = T\hat u`:

* ``bonded``: the slave copy equals the master (:math:`u_s = u_m`);
* ``sliding``: :math:`u_s = (n\cdot u_m)\,n + a\,t_1 + b\,t_2` (normal shared,
  both tangential components, in-plane and axial, free);
* ``tied-at-tip``: sliding, and tied in full over the sealed end
  (``cap_thickness`` from the tip: the plug glued into the tube and taped to
  the coil; a tie on the end face alone is a line constraint, mesh-dependent).

Duplicated nodes with a normal tie rather than contact: the interfaces of a
pressurised tip stay closed (the lumen pressure pushes the tube onto the coil
and channel; the squeeze of assembly preloads them), so the contact set is
known and the problem stays linear; a gap opening would need contact and is
flagged by the sign of the normal interface force, which is left to a later
model. At the clamped base (z = 0) every copy is clamped, which ties the
bodies there; with ``proximal = "tube-free"`` the tube's base keeps its
in-plane clamp and is free axially.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy import sparse

from softcath.design.errors import DesignError
from softcath.fem.adapter import fem_laws_from_design, geometry_from_design
from softcath.fem.elasticity import ElasticProblem, Solution
from softcath.fem.geometry import TUBE, interface_kind
from softcath.fem.lumen_load import pressure_facets
from softcath.fem.mesh import mesh_tip
from softcath.fem.neutral_axis import neutral_axis_y
from softcath.fem.post import bending_fit
from softcath.fem.solver import Factorized
from softcath.fem.tags import tag_facets

__all__ = ["run_tip_as_built"]


def _split(mesh):
    """Tip mesh with each vertex duplicated per region touching it."""
    tets, labels = mesh.tets, np.asarray(mesh.labels).astype(np.int64)
    npts = mesh.points.shape[0]
    pairs = np.unique(np.column_stack([tets.ravel(), np.repeat(labels, tets.shape[1])]), axis=0)
    first = np.ones(len(pairs), bool)
    first[1:] = pairs[1:, 0] != pairs[:-1, 0]
    new_id = np.where(first, pairs[:, 0], npts + np.cumsum(~first) - 1)
    # Dense lookup over (vertex, label): labels are small integers.
    nl = int(labels.max()) + 1
    table = np.full((npts, nl), -1, dtype=np.int64)
    table[pairs[:, 0], pairs[:, 1]] = new_id
    new_tets = table[tets, labels[:, None]]
    points = np.vstack([mesh.points, mesh.points[pairs[~first, 0]]])
    ce, cm = [], []
    for lab in range(nl):
        a, b = table[mesh.curved_edges[:, 0], lab], table[mesh.curved_edges[:, 1], lab]
        ok = (a >= 0) & (b >= 0)
        ce.append(np.column_stack([a[ok], b[ok]]))
        cm.append(mesh.curved_midpoints[ok])
    return replace(
        mesh,
        points=points,
        tets=new_tets,
        curved_edges=np.vstack(ce),
        curved_midpoints=np.vstack(cm),
        key=f"{mesh.key}|split",
    )


def _projection(sk, basis, labels, assembly, length: float, cap: float):
    """T (3N x n_hat) and the interface pairs; base nodes (z = 0) are left untied."""
    N = basis.N
    node_label = np.zeros(N, dtype=np.int64)
    node_label[basis.element_dofs.ravel()] = np.repeat(
        labels[None, :], basis.element_dofs.shape[0], 0
    ).ravel()
    x = np.asarray(basis.doflocs)
    key = np.round(x.T / 1e-9).astype(np.int64)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    shared = counts[inv] > 1
    nsum = _node_normals(sk, basis)
    groups: dict[int, list[int]] = {}
    for node in np.flatnonzero(shared):
        groups.setdefault(int(inv[node]), []).append(int(node))
    z = x[2]
    ztol = 1e-6 * length
    tied = [sorted(nodes, key=lambda n: node_label[n]) for nodes in groups.values() if z[nodes[0]] >= ztol]
    slave = np.zeros(N, bool)
    for nodes in tied:
        slave[nodes[1:]] = True
    kept = np.flatnonzero(~np.repeat(slave, 3))
    col = np.full(3 * N, -1, dtype=np.int64)
    col[kept] = np.arange(kept.size)
    rows, cols, vals = list(kept), list(range(kept.size)), [1.0] * kept.size
    ncol = kept.size

    def kind(a, b):
        k = interface_kind(assembly, int(node_label[a]), int(node_label[b]))
        return "bonded" if k == "tied-at-tip" and z[a] > length - cap - ztol else k

    for nodes in tied:
        m = nodes[0]
        if len(nodes) > 2:
            # A line where three regions meet: in-plane tied in full (as the section model's
            # points), axially each copy with the earlier copies it is bonded to, else free.
            zcol = {m: col[3 * m + 2]}
            for s_ in nodes[1:]:
                for c in range(2):
                    rows.append(3 * s_ + c), cols.append(col[3 * m + c]), vals.append(1.0)
                q = next((q for q in nodes[: nodes.index(s_)] if kind(q, s_) == "bonded"), None)
                if q is None:
                    zcol[s_], ncol = ncol, ncol + 1
                else:
                    zcol[s_] = zcol[q]
                rows.append(3 * s_ + 2), cols.append(zcol[s_]), vals.append(1.0)
            continue
        s_ = nodes[1]
        n = nsum[m].copy()
        n[2] = 0.0  # the interfaces are cylinders along z
        norm = float(np.linalg.norm(n))
        if kind(m, s_) == "bonded" or norm == 0:
            for c in range(3):
                rows.append(3 * s_ + c), cols.append(col[3 * m + c]), vals.append(1.0)
            continue
        n /= norm
        t1 = np.array([-n[1], n[0], 0.0])
        t2 = np.array([0.0, 0.0, 1.0])
        for i in range(3):
            for j in range(3):
                rows.append(3 * s_ + i), cols.append(col[3 * m + j]), vals.append(n[i] * n[j])
            rows += [3 * s_ + i, 3 * s_ + i]
            cols += [ncol, ncol + 1]
            vals += [t1[i], t2[i]]
        ncol += 2
    if min(cols) < 0:
        raise RuntimeError("interface tie chain: a master node is itself a slave")
    return sparse.csr_matrix((vals, (rows, cols)), shape=(3 * N, ncol)), col


def _node_normals(sk, basis) -> np.ndarray:
    """(N, 3) sums of the area-weighted outward normals of the boundary facets at their P2 nodes."""
    # Area-weighted outward normals of boundary facets, onto their P2 nodes.
    bf = sk.boundary_facets()
    p = np.asarray(sk.p)
    f = sk.facets[:, bf]
    nrm = 0.5 * np.cross((p[:, f[1]] - p[:, f[0]]).T, (p[:, f[2]] - p[:, f[0]]).T)
    cen = p[:, sk.t[:, sk.f2t[0, bf]]].mean(axis=1).T
    flip = np.sign(np.einsum("ij,ij->i", nrm, p[:, f].mean(axis=1).T - cen))
    nrm *= flip[:, None]
    fnodes = np.vstack([basis.nodal_dofs[0, f], basis.edge_dofs[0, sk.f2e[:, bf]]])  # (6, nbf)
    nsum = np.zeros((basis.N, 3))
    np.add.at(nsum, fnodes.ravel(), np.repeat(nrm[None], 6, axis=0).reshape(-1, 3))
    return nsum


def run_tip_as_built(
    design, *, loads=("cap", "lumen"), mesh_size: float = 0.16, coil_modulus: str = "tension"
):
    """Curvature and elongation per MPa of ``design`` as built, from the 3-D linear FEM.

    Returns ``{load: (curvature_per_mm_per_MPa, elongation_per_MPa)}`` read as
    the linear check reads them (mid-span fit, ``softcath.fem.post.bending_fit``).
    """
    g = geometry_from_design(design)
    laws = fem_laws_from_design(design, coil_modulus=coil_modulus)
    mesh = _split(mesh_tip(g, mesh_size=mesh_size))
    sk = mesh.skfem_mesh()
    tags = tag_facets(sk, g)
    if tags["cap"].size == 0 or tags["base"].size == 0:
        raise DesignError("mesh", mesh.key, "no cap or base facets found in the split mesh")
    labels = np.asarray(mesh.labels).astype(np.int64)
    base = tags["base"]
    tube_base = labels[sk.f2t[0, base]] == TUBE
    free_tube = design.assembly.proximal == "tube-free"
    fixed = [(base[~tube_base], (0, 1, 2)), (base[tube_base], (0, 1) if free_tube else (0, 1, 2))]
    present = {k: v for k, v in laws.items() if (labels == k).any()}
    problem = ElasticProblem(sk, labels, present, [fx for fx in fixed if fx[0].size])
    T, col = _projection(sk, problem.basis, labels, design.assembly, g.length, g.cap_thickness)
    K = (T.T @ problem.stiffness @ T).tocsr()
    clamped = col[np.flatnonzero(problem.fixed_mask)]
    free = np.setdiff1d(np.arange(K.shape[0]), clamped)
    fac = Factorized(K[free][:, free].tocsc())
    ybar = neutral_axis_y(mesh, laws)
    out = {}
    for ld in loads:
        f = T.T @ problem.pressure_load(pressure_facets(tags, ld))
        u_hat = np.zeros(K.shape[0])
        u_hat[free], _ = fac.solve(f[free])
        u = (T @ u_hat).reshape(-1, 3)
        fit = bending_fit(
            problem.nodes,
            u,
            length=g.length,
            margin=2 * g.coil_outer_radius,
            end_z=g.length,
            neutral_axis_y=ybar,
        )
        out[ld] = (fit.curvature_per_mm, fit.elongation, fit.curvature_variation)
    return out


def split_mesh(mesh):
    """The tip mesh with every region's vertices its own (interfaces duplicated)."""
    return _split(mesh)


def tied_problem(sk, labels, laws, tags, assembly, geometry, *, method=None):
    """An :class:`~softcath.fem.elasticity.ElasticProblem` on a split mesh, solved under the ties.

    Same interface as the plain problem (``nodes``, ``pressure_load``, ``solve``,
    ``basis``), so the linear check's post-processing runs unchanged.
    """
    labels = np.asarray(labels).astype(np.int64)
    base = tags["base"]
    tube_base = labels[sk.f2t[0, base]] == TUBE
    comps = (0, 1) if assembly.proximal == "tube-free" else (0, 1, 2)
    fixed = [(base[~tube_base], (0, 1, 2)), (base[tube_base], comps)]

    class _Tied(ElasticProblem):
        def factorize(self):
            if self._factor is None:
                self.T, col = _projection(
                    sk, self.basis, labels, assembly, geometry.length, geometry.cap_thickness
                )
                self.K_hat = (self.T.T @ self.stiffness @ self.T).tocsr()
                clamped = col[np.flatnonzero(self.fixed_mask)]
                self.free_hat = np.setdiff1d(np.arange(self.K_hat.shape[0]), clamped)
                kff = self.K_hat[self.free_hat][:, self.free_hat].tocsc()
                self._factor = Factorized(kff, method=self._method, tol=self._tol)
            return self._factor

        def solve(self, load, prescribed=None):
            if prescribed is not None:
                raise DesignError("prescribed", "given", "is not supported with as-built interfaces")
            fac = self.factorize()
            f = self.T.T @ load
            u_hat = np.zeros(self.K_hat.shape[0])
            u_hat[self.free_hat], res = fac.solve(f[self.free_hat])
            return Solution(u=(self.T @ u_hat).reshape(-1, 3), residual=res)

    present = {k: v for k, v in laws.items() if (labels == k).any()}
    return _Tied(sk, labels, present, [fx for fx in fixed if fx[0].size], method=method)
