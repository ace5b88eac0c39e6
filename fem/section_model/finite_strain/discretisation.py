r"""The finite-strain section's element pair and the data every Newton step reuses.

Kinematics. A reference point :math:`(X_1, X_2, Z)` of the tip maps, in the
frame that turns with the section, to the deformed in-plane position
:math:`x = X + U(X)` and the axial stretch :math:`\lambda (1 + k_1 x_1 + k_2 x_2)`;
the section at Z is turned by :math:`\lambda |k| Z` about an axis in its plane.
The deformation gradient is then the same at every Z,

.. math::

    F = \begin{pmatrix} 1 + U_{1,1} & U_{1,2} & 0 \\ U_{2,1} & 1 + U_{2,2} & 0 \\
        0 & 0 & \lambda (1 + k \cdot x) \end{pmatrix},

and the energy per unit reference length is an integral over the section. The
curvature acts on the *deformed* positions x, which is what carries the
in-plane pull of the axial stress toward the centre of curvature. k_2 > 0
bends toward -y (the channel), the project's sign convention.

Element pair. U is the conforming Crouzeix-Raviart field (P2 plus a cubic
bubble); for laws with a volumetric part (silicones) the Jacobian J is
projected element by element onto discontinuous P1, and the volumetric energy
U(Pi J) replaces U(J): the finite-strain form of the linear section model's
P2+/P1disc pair (uniform in the bulk modulus; the same pair, so the small-load
limit is the linear section model).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.section_model.element import _rigid_pins

if TYPE_CHECKING:  # scikit-fem loads with the first discretisation; named here for the checker
    from skfem import CellBasis, Mesh

__all__ = ["Discretisation", "discretise", "N_GLOBAL"]

#: Global unknowns appended after the in-plane DOFs: (lambda, k_1, k_2).
N_GLOBAL = 3


@dataclass(frozen=True)
class Discretisation:
    """Quadrature data of one section mesh with its laws (shared by every Newton step).

    Attributes
    ----------
    dofs
        Element DOFs (nel, nb) of the vector CCR basis.
    weights
        Quadrature weights times the reference Jacobian (nel, nq) [mm^2].
    points
        Reference quadrature points (nel, nq, 2) [mm].
    grad
        d(F_11, F_12, F_21, F_22)/d(local DOF) at the quadrature points (nel, nq, 4, nb).
    value
        In-plane shape-function vectors (nel, nq, 2, nb).
    cells
        Region label -> its element indices.
    laws
        Region label -> finite-strain law (``softcath.fem.hyperelastic.laws``).
    projector
        P1 functions (1, X - Xc, Y - Yc) per element (nel, nq, 3) and their inverse
        mass matrices (nel, 3, 3), for the projected volumetric energy.
    axial_modulus
        Small-strain axial modulus per element [MPa] (stiffness-weighted centroid).
    n_u
        In-plane unknowns; the globals follow at ``n_u, n_u + 1, n_u + 2``.
    pinned
        Three in-plane DOFs that remove the section's rigid in-plane motion.
    """

    mesh: Mesh
    basis: CellBasis
    dofs: np.ndarray
    weights: np.ndarray
    points: np.ndarray
    grad: np.ndarray
    value: np.ndarray
    labels: np.ndarray
    cells: dict
    laws: dict
    projector: tuple[np.ndarray, np.ndarray]
    axial_modulus: np.ndarray
    n_u: int
    pinned: np.ndarray

    @property
    def ndofs(self) -> int:
        """Unknowns: in-plane DOFs plus the three globals."""
        return self.n_u + N_GLOBAL

    def element_fields(self, u: np.ndarray, cells: np.ndarray | slice = slice(None)):
        """Displacement gradients (c, nq, 4) and deformed positions (c, nq, 2) of ``cells``."""
        ue = u[self.dofs[cells]]
        du = np.einsum("cqab,cb->cqa", self.grad[cells], ue)
        x = self.points[cells] + np.einsum("cqab,cb->cqa", self.value[cells], ue)
        return du, x


def discretise(section, laws: Mapping[int, object]) -> Discretisation:
    """Quadrature data of ``section`` (a :class:`~softcath.fem.section_model.mesh.SectionMesh`).

    Parameters
    ----------
    section
        The labelled section mesh.
    laws
        Region label -> finite-strain law with ``stress_tangent`` and
        ``small_strain_tensor`` (``Yeoh``, ``AnisotropicSVK``).
    """
    from skfem import CellBasis, ElementTriCCR, ElementVector

    labels = np.asarray(section.labels)
    missing = sorted(set(np.unique(labels).tolist()) - set(laws))
    if missing:
        raise DesignError("laws", missing, "every region label of the section needs a law")
    mesh = section.skfem_mesh()
    basis = CellBasis(mesh, ElementVector(ElementTriCCR()), intorder=4)
    nb = basis.Nbfun
    grads = np.stack([basis.basis[i][0].grad for i in range(nb)])  # (nb, 2, 2, nel, nq)
    values = np.stack([np.asarray(basis.basis[i][0]) for i in range(nb)])  # (nb, 2, nel, nq)
    grad = np.stack([grads[:, 0, 0], grads[:, 0, 1], grads[:, 1, 0], grads[:, 1, 1]])  # (4, nb, nel, nq)
    grad = np.ascontiguousarray(grad.transpose(2, 3, 0, 1))
    value = np.ascontiguousarray(values.transpose(2, 3, 1, 0))
    w = np.asarray(basis.dx)
    xq, yq = np.asarray(basis.global_coordinates())
    points = np.stack([xq, yq], axis=-1)
    area = w.sum(axis=1)
    xc = (w * xq).sum(axis=1) / area
    yc = (w * yq).sum(axis=1) / area
    q = np.stack([np.ones_like(xq), xq - xc[:, None], yq - yc[:, None]], axis=-1)
    minv = np.linalg.inv(np.einsum("cq,cqa,cqb->cab", w, q, q))
    cells = {int(k): np.flatnonzero(labels == k) for k in np.unique(labels)}
    ez = np.zeros(labels.size)
    for k, idx in cells.items():
        ez[idx] = _axial_modulus(laws[k])
    return Discretisation(
        mesh=mesh,
        basis=basis,
        dofs=np.ascontiguousarray(basis.element_dofs.T),
        weights=w,
        points=points,
        grad=grad,
        value=value,
        labels=labels,
        cells=cells,
        laws=dict(laws),
        projector=(q, minv),
        axial_modulus=ez,
        n_u=int(basis.N),
        pinned=_rigid_pins(basis, mesh),
    )


def _axial_modulus(law) -> float:
    """Small-strain E_z of a law: 1 / S_zzzz of its linearised stiffness."""
    c = law.small_strain_tensor()
    idx = [(0, 0), (1, 1), (2, 2)]
    c3 = np.array([[c[i, i, k, k] for (k, _) in idx] for (i, _) in idx])
    return float(1.0 / np.linalg.inv(c3)[2, 2])
