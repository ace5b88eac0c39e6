r"""The section model's element and its assembly: generalised plane strain with three beam strains.

The Saint-Venant solution of a long prismatic tip under an axial force,
bending moments and a lumen pressure uniform along z is

.. math::

    u_x = U_x(x, y) - k_1 z^2/2, \quad u_y = U_y(x, y) - k_2 z^2/2, \quad
    u_z = z\,(\varepsilon_0 + k_1 x + k_2 y),

so the out-of-plane shears vanish and
:math:`\varepsilon_{zz} = \varepsilon_0 + k_1 x + k_2 y` — for materials with
z as an axis of symmetry (isotropic, transversely isotropic about z), which
is all the catheter has. The unknowns are the in-plane field U and the three
global strains g = (eps_0, k_1, k_2); k_2 is the project's curvature
(positive toward -y, the channel, as ``softcath.fem.post``). The virtual work of the
section forces (N, M_1, M_2) = (int s_zz, int s_zz x, int s_zz y) on g closes
the system.

Element pair: U in the conforming Crouzeix-Raviart space (P2 plus a cubic
bubble, ``ElementTriCCR``); the volumetric part lambda (tr eps)^2 of isotropic
regions is projected element by element onto discontinuous P1 pressures. That
is the mixed P2+/P1disc element with the pressure condensed out exactly
(inf-sup stable, second order in energy, uniform in lambda), so silicone up to
nu = 0.49999 does not lock. tr eps includes eps_zz, which is linear and so is
reproduced exactly by the projection.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy import sparse

from softcath.design.errors import DesignError
from softcath.fem.section_model.laws import SectionLaw
from softcath.fem.section_model.triangles import SectionMesh

__all__ = ["SectionOperator", "assemble"]


@dataclass(frozen=True)
class SectionOperator:
    """The assembled section problem (unit loads, before any solve).

    Attributes
    ----------
    K_uu
        In-plane stiffness (sparse, n x n), N/mm per mm of length, with the
        element bubbles condensed out (``full_field`` restores them).
    K_ug
        Coupling with the global strains (n x 3).
    K_gg
        Global block (3 x 3): (N, M_1, M_2) per (eps_0, k_1, k_2).
    f_lumen
        In-plane load of a unit lumen pressure (n,); also the lumen-area
        functional: dA_lumen = f_lumen . U.
    lumen_area, lumen_centroid
        Area (mm^2) and centroid (x, y) of the meshed lumen.
    axial_centroid_y
        E_z-weighted centroid y of the solid (mm), the 3-D FEM's neutral axis.
    pinned
        The three DOFs fixed against in-plane rigid motion.
    axial_groups
        Per-triangle axial group (``None``: one group). With G groups the global
        strains are (eps_0 of each group, k_1, k_2): parts free to slip axially
        against each other stretch separately and share the curvatures
        (``softcath.fem.section_model.as_built``).
    """

    mesh: object
    basis: object
    K_uu: sparse.csr_matrix
    K_ug: np.ndarray
    K_gg: np.ndarray
    f_lumen: np.ndarray
    lumen_area: float
    lumen_centroid: tuple[float, float]
    axial_centroid_y: float
    pinned: np.ndarray
    D: np.ndarray
    lam: np.ndarray
    bubble_from_retained: np.ndarray
    bubble_from_strains: np.ndarray
    strain_matrix: np.ndarray
    quadrature_xy: np.ndarray
    axial_groups: np.ndarray | None = None

    @property
    def ndofs(self) -> int:
        """Unknowns of the condensed system (P2 in-plane DOFs + the global strains)."""
        return int(self.K_uu.shape[0]) + int(self.K_ug.shape[1])

    def strain_field(self, u_full: np.ndarray, strains: np.ndarray) -> np.ndarray:
        """Strains (eps_xx, eps_yy, eps_zz, gamma_xy) at the quadrature points, shape (4, nel, nq).

        ``u_full`` is a field on the whole CCR basis (``full_field``); ``strains`` the
        global (eps_0, k_1, k_2).
        """
        ue = u_full[self.basis.element_dofs].T  # (nel, nb)
        out = np.einsum("eqcb,eb->ceq", self.strain_matrix, ue)
        x, y = self.quadrature_xy
        e0 = strains[0] if self.axial_groups is None else np.asarray(strains)[self.axial_groups][:, None]
        out[2] = e0 + strains[-2] * x + strains[-1] * y
        return out

    def full_field(self, u: np.ndarray, strains: np.ndarray) -> np.ndarray:
        """The in-plane field on the whole CCR basis: ``u`` (retained DOFs) plus the bubbles."""
        dofs = self.basis.element_dofs
        nb = dofs.shape[0]
        full = np.zeros(self.basis.N)
        full[: u.size] = u
        ue = u[dofs[: nb - 2]].T  # (nel, nb - 2)
        bub = -(np.einsum("ebr,er->eb", self.bubble_from_retained, ue) + self.bubble_from_strains @ strains)
        full[dofs[nb - 2 :].T] = bub
        return full


def _strains(basis) -> np.ndarray:
    """(nb, 4, nel, nq): strain (xx, yy, zz, xy) of every local in-plane DOF."""
    nb = basis.Nbfun
    g = np.stack([basis.basis[i][0].grad for i in range(nb)])  # (nb, 2, 2, nel, nq)
    out = np.zeros((nb, 4) + g.shape[3:])
    out[:, 0] = g[:, 0, 0]
    out[:, 1] = g[:, 1, 1]
    out[:, 3] = g[:, 0, 1] + g[:, 1, 0]
    return out


def assemble(
    section: SectionMesh, laws: Mapping[int, SectionLaw], *, axial_groups: np.ndarray | None = None
) -> SectionOperator:
    """Assemble the generalised-plane-strain section operator.

    Parameters
    ----------
    section
        The labelled mesh.
    laws
        Region label -> :class:`SectionLaw`; every label in the mesh needs one.
    axial_groups
        Optional per-triangle group index 0..G-1: each group gets its own axial
        strain eps_0 (then ``eps_zz = eps_0[group] + k_1 x + k_2 y``).
    """
    from skfem import CellBasis, ElementTriCCR, ElementVector

    missing = sorted(set(np.unique(section.labels).tolist()) - set(laws))
    if missing:
        raise DesignError("laws", missing, "every region label of the section needs a law")
    mesh = section.skfem_mesh()
    basis = CellBasis(mesh, ElementVector(ElementTriCCR()), intorder=4)
    nel = mesh.t.shape[1]
    table = {k: i for i, k in enumerate(sorted(laws))}
    which = np.array([table[int(k)] for k in section.labels])
    D = np.stack([laws[k].D for k in sorted(laws)])[which]  # (nel, 4, 4)
    lam = np.array([laws[k].lam for k in sorted(laws)])[which]
    ez = np.array([laws[k].axial_modulus for k in sorted(laws)])[which]

    w = basis.dx  # (nel, nq)
    xq, yq = np.asarray(basis.global_coordinates())  # (nel, nq)
    phi = _axial_strain_basis(xq, yq, axial_groups)
    ng = phi.shape[0]
    eps = _strains(basis)
    nb, nq = eps.shape[0], w.shape[1]
    # Batched products over (element, quadrature point): B is (nel, nq, 4, nb).
    B = eps.transpose(2, 3, 1, 0)
    DB = D[:, None] @ B
    Bw = B * w[:, :, None, None]
    k_loc = Bw.reshape(nel, nq * 4, nb).transpose(0, 2, 1) @ DB.reshape(nel, nq * 4, nb)
    phiw = (phi * w).transpose(1, 2, 0)  # (nel, nq, 3)
    kug_loc = DB[:, :, 2, :].transpose(0, 2, 1) @ phiw  # sigma_zz(U_i) * phi_k: (nel, nb, 3)
    k_gg = np.einsum("e,eqk,leq->kl", D[:, 2, 2], phiw, phi)
    # Projected volumetric part: lambda * P(tr eps)^2 with P onto P1 per element.
    k_gg = _add_projected_volumetric(k_loc, kug_loc, k_gg, eps, phi, w, xq=xq, yq=yq, lam=lam)
    # Static condensation of the element bubbles (interior DOFs, the last two local
    # rows, numbered last globally): the global system keeps only the P2 DOFs.
    k_uu, k_ug, k_gg, xr, xg, n = _condense_bubbles(basis, k_loc, kug_loc, k_gg, nb, ng)

    # Lumen pressure (unit): traction -n on the solid's lumen boundary (n out of the solid).
    f_full, a_l, xl, yl = _lumen_load(section, mesh, basis)
    f_lumen = f_full[:n]  # bubbles vanish on edges: no load on them
    wz = (ez[:, None] * w).sum()
    ybar = float((ez[:, None] * w * yq).sum() / wz)
    return SectionOperator(
        mesh=mesh,
        basis=basis,
        K_uu=k_uu,
        K_ug=k_ug,
        K_gg=k_gg,
        f_lumen=f_lumen,
        lumen_area=a_l,
        lumen_centroid=(xl, yl),
        axial_centroid_y=ybar,
        pinned=_rigid_pins(basis, mesh),
        D=D,
        lam=lam,
        bubble_from_retained=xr,
        bubble_from_strains=xg,
        strain_matrix=B,
        quadrature_xy=np.stack([xq, yq]),
        axial_groups=None if axial_groups is None else np.asarray(axial_groups, dtype=np.int64),
    )


def _axial_strain_basis(xq, yq, axial_groups) -> np.ndarray:
    """(G + 2, nel, nq): d eps_zz / d g at the quadrature points."""
    if axial_groups is None:
        return np.stack([np.ones_like(xq), xq, yq])  # (3, nel, nq): d eps_zz / d g
    groups = np.asarray(axial_groups, dtype=np.int64)
    onehot = (groups[None, :] == np.arange(groups.max() + 1)[:, None]).astype(float)
    return np.concatenate([np.broadcast_to(onehot[:, :, None], (onehot.shape[0],) + xq.shape), [xq, yq]])


def _add_projected_volumetric(k_loc, kug_loc, k_gg, eps, phi, w, *, xq, yq, lam) -> np.ndarray:
    """Add lambda * P(tr eps)^2 (P onto P1 per element) in place; returns the updated ``k_gg``."""
    mixed = lam > 0
    if mixed.any():
        area = w.sum(axis=1)
        xc = (w * xq).sum(axis=1) / area
        yc = (w * yq).sum(axis=1) / area
        q = np.stack([np.ones_like(xq), xq - xc[:, None], yq - yc[:, None]], axis=-1)[mixed]  # (e, nq, 3)
        qw = q * w[mixed][:, :, None]
        m = qw.transpose(0, 2, 1) @ q
        div = (eps[:, 0] + eps[:, 1]).transpose(1, 2, 0)[mixed]  # (e, nq, nb)
        gu = qw.transpose(0, 2, 1) @ div  # (e, 3, nb)
        gg = qw.transpose(0, 2, 1) @ phi.transpose(1, 2, 0)[mixed]  # (e, 3, 3)
        minv = np.linalg.inv(m) * lam[mixed, None, None]
        mgu = minv @ gu
        k_loc[mixed] += gu.transpose(0, 2, 1) @ mgu
        kug_loc[mixed] += mgu.transpose(0, 2, 1) @ gg
        k_gg += np.einsum("eak,eal->kl", gg, minv @ gg)
    return k_gg


def _condense_bubbles(basis, k_loc, kug_loc, k_gg, nb, ng):
    """Condense the element bubbles out; returns (K_uu, K_ug, K_gg, bubble maps xr, xg, retained DOFs)."""
    dofs = basis.element_dofs  # (nb, nel)
    ri, bi = np.arange(nb - 2), np.arange(nb - 2, nb)
    if not np.array_equal(dofs[bi], basis.interior_dofs):
        raise RuntimeError("unexpected CCR DOF layout: bubbles are not the last local DOFs")
    kbb_inv = np.linalg.inv(k_loc[:, bi][:, :, bi])
    kbr = k_loc[:, bi][:, :, ri]
    kbg = kug_loc[:, bi, :]
    xr, xg = kbb_inv @ kbr, kbb_inv @ kbg  # bubble values per unit retained DOF / global strain
    k_rr = k_loc[:, ri][:, :, ri] - kbr.transpose(0, 2, 1) @ xr
    k_rg = kug_loc[:, ri, :] - kbr.transpose(0, 2, 1) @ xg
    k_gg = k_gg - np.einsum("ebk,ebl->kl", kbg, xg)
    n = basis.N - basis.interior_dofs.size
    rdofs = dofs[ri]
    rows = np.broadcast_to(rdofs.T[:, :, None], k_rr.shape).ravel()
    cols = np.broadcast_to(rdofs.T[:, None, :], k_rr.shape).ravel()
    k_uu = sparse.coo_matrix((k_rr.ravel(), (rows, cols)), shape=(n, n)).tocsr()
    k_ug = np.zeros((n, ng))
    for k in range(ng):
        k_ug[:, k] = np.bincount(rdofs.T.ravel(), weights=k_rg[:, :, k].ravel(), minlength=n)
    return k_uu, k_ug, k_gg, xr, xg, n


def _rigid_pins(basis, mesh) -> np.ndarray:
    """Three DOFs that remove in-plane rigid motion (loads are self-equilibrated).

    Both components at the vertex nearest the centroid and the x component at
    the vertex farthest from it in y: no stress arises from these supports.
    """
    nd = basis.nodal_dofs
    p = np.asarray(mesh.doflocs)[:, : nd.shape[1]]
    c = p.mean(axis=1)
    a = int(np.argmin(np.hypot(p[0] - c[0], p[1] - c[1])))
    b = int(np.argmax(np.abs(p[1] - p[1, a])))
    return np.array([nd[0, a], nd[1, a], nd[0, b]])


def lumen_edge_elements(section: SectionMesh, mesh) -> tuple[np.ndarray, np.ndarray]:
    """(parent triangle, local edge 0-2) of every lumen edge of ``section`` in ``mesh``.

    Local edges are (0,1), (1,2), (2,0) of ``mesh.t`` (counter-clockwise triangles).
    """
    le = np.sort(section.lumen_edges, axis=1)
    t = mesh.t
    nv = int(t.max()) + 1
    local = ((0, 1), (1, 2), (2, 0))
    all_edges = np.sort(np.concatenate([t[[i, j]].T for i, j in local]), axis=1)  # (3 nel, 2)
    keys = all_edges[:, 0].astype(np.int64) * nv + all_edges[:, 1]
    order = np.argsort(keys)
    want = le[:, 0].astype(np.int64) * nv + le[:, 1]
    pos = np.clip(np.searchsorted(keys[order], want), 0, keys.size - 1)
    if not np.array_equal(keys[order][pos], want):
        raise DesignError("section.lumen", len(le), "a lumen edge belongs to no triangle")
    hit = order[pos]
    nel = t.shape[1]
    return hit % nel, hit // nel


def _lumen_load(section: SectionMesh, mesh, basis):
    """Unit lumen-pressure load vector, and the lumen's area and centroid.

    Integrated directly on each lumen edge's parent element: the edge's
    reference points are known, so no inverse isoparametric map is needed
    (scikit-fem's ``FacetBasis`` solves one by Newton's method, a third of the
    assembly time here). Gauss-Legendre with 4 points is exact for the
    P2-mapped edge geometry times the cubic shape functions up to the
    curved Jacobian's smooth factor.
    """
    t = mesh.t
    elems, which = lumen_edge_elements(section, mesh)
    s, ws = np.polynomial.legendre.leggauss(4)
    s, ws = 0.5 * (s + 1), 0.5 * ws
    # Reference points along each local edge, traversed from its first to its second vertex.
    start = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])[which]  # (nf, 2)
    stop = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])[which]
    X = start.T[:, :, None] + (stop - start).T[:, :, None] * s[None, None, :]  # (2, nf, nq)
    xg = mesh.mapping().F(X, tind=elems)  # (2, nf, nq)
    J = mesh.mapping().DF(X, tind=elems)  # (2, 2, nf, nq)
    tangent = np.einsum("ijfq,jf->ifq", J, (stop - start).T)
    length = np.hypot(tangent[0], tangent[1])
    normal = np.stack([tangent[1], -tangent[0]]) / length  # outward for a counter-clockwise cell
    centre = np.asarray(mesh.p)[:, t[:, elems]].mean(axis=1)  # (2, nf)
    flip = np.sign(np.einsum("ifq,if->f", normal, xg.mean(axis=2) - centre))
    normal = normal * flip[None, :, None]
    wds = length * ws[None, :]
    # H1 shape functions do not depend on the mapping: evaluate the scalar CCR basis on the
    # reference points (no inverse isoparametric map); the vector element interleaves
    # components, local DOF k = (scalar DOF k // 2, component k % 2).
    scalar = basis.elem.elem
    f_loc = np.empty((len(elems), basis.Nbfun))
    for k in range(basis.Nbfun):
        phi = scalar.lbasis(X, k // 2)[0]  # (nf, nq)
        f_loc[:, k] = -np.einsum("fq,fq,fq->f", phi, normal[k % 2], wds)
    f = np.bincount(basis.element_dofs[:, elems].T.ravel(), weights=f_loc.ravel(), minlength=basis.N)
    # Lumen area and centroid by the divergence theorem (lumen normal = -n).
    a_l = -float((xg[0] * normal[0] * wds).sum())
    xl = -float((0.5 * xg[0] ** 2 * normal[0] * wds).sum()) / a_l
    yl = -float((0.5 * xg[1] ** 2 * normal[1] * wds).sum()) / a_l
    return f, a_l, xl, yl
