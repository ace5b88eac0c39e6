r"""Internal forces and tangent of the finite-strain section, and the pressure's share.

Each element contributes over its in-plane DOFs and the three globals
g = (lambda, k_1, k_2). Only five components of F vary,
(F_11, F_12, F_21, F_22, F_33), so the law's first Piola-Kirchhoff stress
and tangent are read on those; F_33 = lambda (1 + k . x) is bilinear in the
unknowns, so its second derivatives add

.. math::

    S_{33} \left( \frac{\partial^2 F_{33}}{\partial\lambda\,\partial U} = k\cdot N,\;
    \frac{\partial^2 F_{33}}{\partial k_a\,\partial U_a} = \lambda N,\;
    \frac{\partial^2 F_{33}}{\partial\lambda\,\partial k_a} = x_a \right)

to the tangent. Laws that split off a volumetric energy (silicones) use the
projected Jacobian (module ``discretisation``) in its Lame part: with
:math:`\bar p = \lambda (\Pi J - 1) + \tfrac23\mu (J - 1)` the stress gains
:math:`\bar p\,\mathrm{cof} F` and the tangent
:math:`\bar p\, \partial\,\mathrm{cof} F/\partial F + \tfrac23\mu\,\mathrm{cof}F\otimes\mathrm{cof}F`
plus the condensed :math:`\lambda\, G^T M^{-1} G`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcath.fem.hyperelastic.tensors import cofactor, det
from softcath.fem.section_model.finite_strain.discretisation import N_GLOBAL, Discretisation

__all__ = ["Tangent", "Volumetric", "internal", "with_globals", "FIVE"]

#: The varying components of F as (row, column) pairs.
FIVE = ((0, 0), (0, 1), (1, 0), (1, 1), (2, 2))
_I5 = np.array([i for i, _ in FIVE])
_J5 = np.array([j for _, j in FIVE])


@dataclass(frozen=True)
class Tangent:
    """Element residuals and tangents over (element DOFs, globals), and the state's health."""

    residual: np.ndarray  # (nel, nl)
    stiffness: np.ndarray  # (nel, nl, nl)
    min_jacobian: float
    max_strain: float
    volumetric: dict = field(default_factory=dict)  # label -> Volumetric


@dataclass(frozen=True)
class Volumetric:
    """A split region's projected volumetric data at one state.

    ``excess`` are the P1 coefficients of Pi J - 1 (c, 3); ``gradient`` the element
    matrices int q dJ/d(local DOFs) (c, 3, nl); ``inverse_mass`` (c, 3, 3); ``modulus`` the
    projected (Lame) modulus. The projected pressure is ``modulus * excess``; its
    linearised change under a step dq_e is ``modulus * inverse_mass @ gradient @ dq_e``.
    """

    cells: np.ndarray
    excess: np.ndarray
    gradient: np.ndarray
    inverse_mass: np.ndarray
    modulus: float

    def pressure_after(self, step: np.ndarray) -> np.ndarray:
        """Projected pressure coefficients (c, 3) linearised along the local ``step`` (c, nl)."""
        return self.modulus * (
            self.excess + np.einsum("cab,cbl,cl->ca", self.inverse_mass, self.gradient, step)
        )


def _deformation(du: np.ndarray, x: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    lam, k1, k2 = g
    stretch = 1.0 + k1 * x[..., 0] + k2 * x[..., 1]
    f = np.zeros(du.shape[:-1] + (3, 3))
    f[..., 0, 0] = 1.0 + du[..., 0]
    f[..., 0, 1] = du[..., 1]
    f[..., 1, 0] = du[..., 2]
    f[..., 1, 1] = 1.0 + du[..., 3]
    f[..., 2, 2] = lam * stretch
    return f, stretch


def internal(
    disc: Discretisation,
    u: np.ndarray,
    g: np.ndarray,
    *,
    silicone: tuple[int, ...] = (),
    pressure: dict | None = None,
) -> Tangent:
    """Element residuals and tangents of the stored energy at (u, g).

    ``silicone`` lists the region labels whose largest principal strain is reported.
    ``pressure`` (label -> P1 coefficients (c, 3)) is the mixed formulation's independent
    projected pressure, used in the tangent's geometric term in place of the one
    computed from u (the residual always uses the latter). Newton's method on the
    u-p pair: the computed pressure after a full step is off by the modulus times the
    step squared, which for nu -> 1/2 would wreck the tangent.
    """
    nel, nb = disc.dofs.shape
    nl = nb + N_GLOBAL
    res = np.zeros((nel, nl))
    stiff = np.zeros((nel, nl, nl))
    min_j, max_strain = np.inf, 0.0
    volumetric = {}
    lam, k1, k2 = (float(v) for v in g)
    for label, cells in disc.cells.items():
        law = disc.laws[label]
        du, x = disc.element_fields(u, cells)
        f, stretch = _deformation(du, x, (lam, k1, k2))
        jac = det(f)
        min_j = min(min_j, float(jac.min()), float(f[..., 2, 2].min()))
        if min_j <= 0:
            return Tangent(res, stiff, min_j, np.nan, volumetric)
        split = bool(getattr(law, "splits_volume", False))
        p, a = law.stress_tangent(f, volumetric=not split)
        p5 = p[..., _I5, _J5]
        a5 = a[..., _I5[:, None], _J5[:, None], _I5[None, :], _J5[None, :]]
        nv = disc.value[cells]
        b = np.zeros(p5.shape[:2] + (5, nl))
        b[:, :, :4, :nb] = disc.grad[cells]
        b[:, :, 4, :nb] = lam * (k1 * nv[:, :, 0, :] + k2 * nv[:, :, 1, :])
        b[:, :, 4, nb] = stretch
        b[:, :, 4, nb + 1] = lam * x[..., 0]
        b[:, :, 4, nb + 2] = lam * x[..., 1]
        w = disc.weights[cells]
        if split:
            given = None if pressure is None else pressure.get(label)
            p5, a5, k_vol, volumetric[label] = _volumetric(
                disc, cells, law, f, jac, b, w=w, p5=p5, a5=a5, given=given
            )
            stiff[cells] += k_vol
        res[cells] += np.einsum("cq,cqa,cqal->cl", w, p5, b)
        bw = b * w[:, :, None, None]
        ab = a5 @ b
        c = cells.size
        stiff[cells] += bw.reshape(c, -1, nl).transpose(0, 2, 1) @ ab.reshape(c, -1, nl)
        # second derivatives of F_33 = lambda (1 + k . x)
        t = w * p5[..., 4]
        lam_u = np.einsum("cq,cqb->cb", t, k1 * nv[:, :, 0, :] + k2 * nv[:, :, 1, :])
        k_u = lam * np.einsum("cq,cqab->cba", t, nv)  # (c, nb, 2)
        lam_k = np.einsum("cq,cqa->ca", t, x)
        blk = stiff[cells]
        blk[:, :nb, nb] += lam_u
        blk[:, nb, :nb] += lam_u
        blk[:, :nb, nb + 1 :] += k_u
        blk[:, nb + 1 :, :nb] += k_u.transpose(0, 2, 1)
        blk[:, nb, nb + 1 :] += lam_k
        blk[:, nb + 1 :, nb] += lam_k
        stiff[cells] = blk
        if label in silicone:
            cc = np.einsum("...aI,...aJ->...IJ", f, f)
            max_strain = max(max_strain, float(np.sqrt(np.linalg.eigvalsh(cc)[..., -1]).max() - 1.0))
    return Tangent(res, stiff, float(min_j), max_strain, volumetric)


def _volumetric(disc, cells, law, f, jac, b, *, w, p5, a5, given):
    """The volumetric energy kappa/2 (J - 1)^2 split as the linear section model splits it.

    lambda/2 (Pi J - 1)^2 is projected (lambda = kappa - 2 mu/3, the Lame modulus that
    grows without bound as nu -> 1/2) and mu/3 (J - 1)^2 stays pointwise: the same
    law, whose linearisation is the linear section model's P2+/P1disc form exactly.
    Returns the stress, the tangent, the condensed projected block and the
    :class:`Volumetric` data; ``given`` replaces the projected pressure in the
    tangent's geometric term (module ``newton``: the mixed u-p iteration).
    """
    projected = max(law.bulk_modulus - 2.0 * law.shear_modulus / 3.0, 0.0)
    pointwise = law.bulk_modulus - projected
    q, minv = disc.projector
    q, minv = q[cells], minv[cells]
    coef = np.einsum("cab,cqb,cq,cq->ca", minv, q, w, jac)
    coef[:, 0] -= 1.0  # Pi J - 1
    pbar = projected * np.einsum("cqa,ca->cq", q, coef) + pointwise * (jac - 1.0)
    p_geo = pbar if given is None else np.einsum("cqa,ca->cq", q, given) + pointwise * (jac - 1.0)
    cof = cofactor(f)
    cof5 = cof[..., _I5, _J5]
    dcof5 = (
        cof5[..., :, None] * cof5[..., None, :]
        - cof[..., _I5[:, None], _J5[None, :]] * cof[..., _I5[None, :], _J5[:, None]]
    ) / jac[..., None, None]
    p5 = p5 + pbar[..., None] * cof5
    a5 = a5 + p_geo[..., None, None] * dcof5 + pointwise * cof5[..., :, None] * cof5[..., None, :]
    dj = np.einsum("cqa,cqal->cql", cof5, b)
    gv = np.einsum("cq,cqa,cql->cal", w, q, dj)
    k_vol = projected * gv.transpose(0, 2, 1) @ (minv @ gv)
    return p5, a5, k_vol, Volumetric(cells, coef, gv, minv, projected)


def with_globals(disc: Discretisation, dofs: np.ndarray) -> np.ndarray:
    """Local DOF table with the three global unknowns appended to each row."""
    g = np.broadcast_to(np.arange(disc.n_u, disc.n_u + N_GLOBAL), (dofs.shape[0], N_GLOBAL))
    return np.concatenate([dofs, g], axis=1)
