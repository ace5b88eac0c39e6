r"""Sliding interfaces between the bodies of a section: split nodes, tie the normal component.

A frictionless interface keeps the two sides in contact (their normal
displacements agree) and lets them slip tangentially. On a conforming mesh
this is a transformation at the mesh and DOF level, independent of the
element's physics, so the linear section model and a finite-strain one can
share it:

1. :func:`split_interfaces` duplicates every vertex that lies on the boundary
   between two different *bodies* (one copy per body): the split mesh has no
   element connecting the bodies any more.
2. :func:`tie_projection` builds, for a scikit-fem vector basis with nodal and
   facet DOFs (P2, CCR) on the split mesh, the sparse projection
   :math:`T` from the reduced unknowns :math:`\hat u` to the split DOFs,
   :math:`u = T \hat u`, such that at every interface node pair (vertex and
   edge midpoint) with unit normal :math:`n` and tangent :math:`t`

   .. math::

       u_s = (n \cdot u_m)\, n + q_s\, t ,

   i.e. the slave copy ``s`` shares the master copy ``m``'s normal
   displacement and keeps its own tangential displacement :math:`q_s` (a
   new reduced unknown). Vertices where three or more bodies meet are tied
   in full (a point of measure zero). A reduced stiffness is
   :math:`\hat K = T^\mathsf{T} K T`, a reduced load :math:`\hat f = T^\mathsf{T} f`.
3. The tangential slips :math:`s = q_s - t \cdot u_m` are returned as the
   rows of a sparse matrix :math:`S` (``S @ u_hat``) with their quadrature
   weights :math:`w` (interface length per node, Simpson's rule on each P2
   edge): :math:`k_s S^\mathsf{T} \mathrm{diag}(w) S` adds an interface spring
   layer of tangential modulus :math:`k_s` (N/mm³). A tiny :math:`k_s` only
   removes the free spin of a body whose interfaces are all circles; a
   large one bonds the interface back.

Public API: :class:`InterfaceSplit`, :func:`split_interfaces`,
:class:`Ties`, :func:`tie_projection`. Nothing here knows materials or loads.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from softcath.fem.section_model.triangles import SectionMesh

__all__ = ["InterfaceSplit", "Ties", "split_interfaces", "tie_projection"]


@dataclass(frozen=True)
class InterfaceSplit:
    """A section mesh split along the interfaces between bodies.

    Attributes
    ----------
    mesh
        The split :class:`SectionMesh` (same triangles and labels, interface
        vertices duplicated; lumen and curved edges renumbered).
    body
        Body index per triangle.
    edges
        Interface edges (k, 4): split vertex ids ``(m0, m1, s0, s1)`` of the master
        side (lower body index) and the slave side, ``m0 <-> s0``, ``m1 <-> s1``.
    edge_bodies
        (k, 2) master and slave body of each interface edge.
    edge_normals
        (k, 2) unit normal of each edge's chord, out of the master body.
    vertex_copies
        Original vertex -> list of (split vertex, body), master first, for the
        interface vertices only.
    """

    mesh: SectionMesh
    body: np.ndarray
    edges: np.ndarray
    edge_bodies: np.ndarray
    edge_normals: np.ndarray
    vertex_copies: dict


def split_interfaces(section: SectionMesh, body: np.ndarray) -> InterfaceSplit:
    """Duplicate the vertices shared by different bodies.

    Parameters
    ----------
    section
        A conforming labelled mesh.
    body
        Body index per triangle; triangles of one body stay connected, every
        edge between two bodies becomes an interface.
    """
    body = np.asarray(body, dtype=np.int64)
    tri = section.triangles
    npts = section.points.shape[0]
    # One copy of each vertex per body touching it; the lowest body keeps the original id.
    pairs = np.unique(np.column_stack([tri.ravel(), np.repeat(body, 3)]), axis=0)  # sorted (vertex, body)
    first = np.ones(len(pairs), bool)
    first[1:] = pairs[1:, 0] != pairs[:-1, 0]
    new_id = np.where(first, pairs[:, 0], npts + np.cumsum(~first) - 1)
    lookup = {(int(v), int(b)): int(i) for (v, b), i in zip(pairs, new_id, strict=True)}
    new_tri = np.array([[lookup[(int(v), int(b))] for v in t] for t, b in zip(tri, body, strict=True)])
    points = np.vstack([section.points, section.points[pairs[~first, 0]]])
    copies: dict[int, list[tuple[int, int]]] = {}
    for (v, b), i in zip(pairs, new_id, strict=True):
        copies.setdefault(int(v), []).append((int(i), int(b)))
    copies = {v: c for v, c in copies.items() if len(c) > 1}

    # Edges -> owning triangles (original numbering).
    owners: dict[tuple[int, int], list[int]] = {}
    for e, t in enumerate(tri):
        for i, j in ((0, 1), (1, 2), (2, 0)):
            owners.setdefault((min(t[i], t[j]), max(t[i], t[j])), []).append(e)

    def renumber(edges: np.ndarray, extra: np.ndarray | None = None):
        out, out_extra = [], []
        for k, (a, b) in enumerate(edges):
            for e in owners.get((min(a, b), max(a, b)), []):
                out.append((lookup[(int(a), int(body[e]))], lookup[(int(b), int(body[e]))]))
                if extra is not None:
                    out_extra.append(extra[k])
        out = np.array(out, dtype=np.int64).reshape(-1, 2)
        return out if extra is None else (out, np.array(out_extra).reshape(-1, 2))

    ce, cm = renumber(section.curved_edges, section.curved_midpoints)
    lumen = renumber(section.lumen_edges)
    lumen = np.unique(np.sort(lumen, axis=1), axis=0)

    iface, ib, normals = [], [], []
    for (a, b), owner in owners.items():
        if len(owner) != 2 or body[owner[0]] == body[owner[1]]:
            continue
        em, es = sorted(owner, key=lambda e: body[e])
        bm, bs = int(body[em]), int(body[es])
        iface.append((lookup[(a, bm)], lookup[(b, bm)], lookup[(a, bs)], lookup[(b, bs)]))
        ib.append((bm, bs))
        d = section.points[b] - section.points[a]
        n = np.array([d[1], -d[0]]) / np.hypot(*d)
        centre = section.points[tri[em]].mean(axis=0)
        if n @ (0.5 * (section.points[a] + section.points[b]) - centre) < 0:
            n = -n
        normals.append(n)
    mesh = SectionMesh(
        points=points,
        triangles=new_tri,
        labels=section.labels,
        curved_edges=ce,
        curved_midpoints=cm,
        lumen_edges=lumen,
        seconds=section.seconds,
        key=f"{section.key}|split",
    )
    return InterfaceSplit(
        mesh=mesh,
        body=body,
        edges=np.array(iface, dtype=np.int64).reshape(-1, 4),
        edge_bodies=np.array(ib, dtype=np.int64).reshape(-1, 2),
        edge_normals=np.array(normals).reshape(-1, 2),
        vertex_copies=copies,
    )


@dataclass(frozen=True)
class Ties:
    """The normal ties of a split mesh on one basis.

    Attributes
    ----------
    T
        Sparse (n, n_hat) projection, ``u = T @ u_hat`` over the first ``n``
        (nodal and facet) DOFs of the basis.
    slip
        Sparse (k, n_hat): tangential slip of each tied node pair.
    weights
        (k,) interface length (mm) attributed to each slip row.
    retained
        (n_hat,) for every reduced unknown, the split DOF it equals (its own
        DOF, or -1 for a tangential unknown).
    """

    T: sparse.csr_matrix
    slip: sparse.csr_matrix
    weights: np.ndarray
    retained: np.ndarray

    def spring(self, modulus: float) -> sparse.csr_matrix:
        r"""Reduced stiffness :math:`k_s S^\mathsf{T} \mathrm{diag}(w) S` of a tangential spring layer."""
        return (self.slip.T @ sparse.diags(modulus * self.weights) @ self.slip).tocsr()


def tie_projection(split: InterfaceSplit, basis, *, tie: np.ndarray | None = None) -> Ties:
    """Normal-contact ties of ``split`` on a scikit-fem vector ``basis`` built on ``split.mesh``.

    Parameters
    ----------
    split
        From :func:`split_interfaces`.
    basis
        A vector basis whose nodal (``basis.nodal_dofs``) and facet
        (``basis.facet_dofs``) DOFs are numbered before any interior ones.
    tie
        Optional bool per interface edge: ``False`` ties that edge in full (a
        bonded interface kept split), default all ``True`` (normal tie only).
    """
    nd, fd = np.asarray(basis.nodal_dofs), np.asarray(basis.facet_dofs)
    n = int(max(nd.max(), fd.max())) + 1
    tie = np.ones(len(split.edges), bool) if tie is None else np.asarray(tie, bool)
    nodes = _node_pairs(split, basis.mesh, nd, fd, tie)
    return _ties(nodes, n)


def _add_pair(nodes: dict, sdofs, mdofs, normal, full, weight) -> None:
    """Add a slave/master node pair to ``nodes``, or accumulate its normal, full flag and weight."""
    key = int(sdofs[0])
    if key in nodes:
        entry = nodes[key]
        entry[1] = entry[1] + normal
        entry[2] = entry[2] or full
        entry[3] += weight
    else:
        nodes[key] = [
            tuple(int(d) for d in mdofs),
            normal.copy(),
            full,
            weight,
            tuple(int(d) for d in sdofs),
        ]


def _node_pairs(split: InterfaceSplit, mesh, nd, fd, tie) -> dict[int, list]:
    """Master/slave node pairs with their normals (None: full tie) and interface length weights."""
    nodes: dict[int, list] = {}  # slave node dofs key -> [master dofs, normal sum, full, weight]
    facets = np.sort(np.asarray(mesh.facets), axis=0)
    nv = int(mesh.p.shape[1])
    fkey = facets[0].astype(np.int64) * nv + facets[1]
    order = np.argsort(fkey)

    def facet_of(a, b):
        k = min(a, b) * nv + max(a, b)
        i = np.searchsorted(fkey[order], k)
        return int(order[i])

    pts = np.asarray(mesh.p)
    for (m0, m1, s0, s1), nrm, t_ok in zip(split.edges, split.edge_normals, tie, strict=True):
        length = float(np.hypot(*(pts[:, m1] - pts[:, m0])))
        full = not t_ok
        _add_pair(nodes, nd[:, s0], nd[:, m0], nrm, full, length / 6)
        _add_pair(nodes, nd[:, s1], nd[:, m1], nrm, full, length / 6)
        _add_pair(nodes, fd[:, facet_of(s0, s1)], fd[:, facet_of(m0, m1)], nrm, full, 2 * length / 3)
    # Vertices shared by three or more bodies: every copy tied in full to the master.
    for copies in split.vertex_copies.values():
        if len(copies) > 2:
            master = copies[0][0]
            for v, _ in copies[1:]:
                _add_pair(nodes, nd[:, v], nd[:, master], np.zeros(2), True, 0.0)
                nodes[int(nd[0, v])][0] = tuple(int(d) for d in nd[:, master])
    return nodes


def _ties(nodes: dict[int, list], n: int) -> Ties:
    """The projection T and slip rows S of the node pairs on ``n`` split DOFs."""
    slaves = set()
    for entry in nodes.values():
        slaves.update(entry[4])
    kept = np.array([d for d in range(n) if d not in slaves], dtype=np.int64)
    col = {int(d): i for i, d in enumerate(kept)}
    rows, cols, vals = [int(d) for d in kept], list(range(len(kept))), [1.0] * len(kept)
    srow, scol, sval, weights, extra = [], [], [], [], []
    ncol = len(kept)
    for mdofs, nsum, full, weight, sdofs in nodes.values():
        if any(d in slaves for d in mdofs):
            raise RuntimeError("interface tie chain: a master node is itself tied as a slave")
        norm = float(np.hypot(*nsum))
        if full or norm == 0.0:
            for sd, md in zip(sdofs, mdofs, strict=True):
                rows.append(sd), cols.append(col[md]), vals.append(1.0)
            continue
        nvec = nsum / norm
        tvec = np.array([-nvec[1], nvec[0]])
        q = ncol
        ncol += 1
        extra.append(q)
        for i, sd in enumerate(sdofs):
            for j, md in enumerate(mdofs):
                rows.append(sd), cols.append(col[md]), vals.append(nvec[i] * nvec[j])
            rows.append(sd), cols.append(q), vals.append(tvec[i])
        r = len(weights)
        srow += [r, r, r]
        scol += [q, col[mdofs[0]], col[mdofs[1]]]
        sval += [1.0, -tvec[0], -tvec[1]]
        weights.append(weight)
    T = sparse.csr_matrix((vals, (rows, cols)), shape=(n, ncol))
    S = sparse.csr_matrix((sval, (srow, scol)), shape=(len(weights), ncol))
    retained = np.concatenate([kept, -np.ones(ncol - len(kept), dtype=np.int64)])
    return Ties(T=T, slip=S, weights=np.array(weights), retained=retained)
