r"""The pressurised lumen: its volume per unit length and the pressure's potential.

The fluid in the deformed lumen is stretched axially like the solid around it,
so the lumen's volume per unit reference length is

.. math::

    V' = \lambda \int_{\text{lumen}} (1 + k_1 x_1 + k_2 x_2)\, da
       = \lambda\,(a + k_1 s_1 + k_2 s_2),

with the deformed area a and first moments s written as boundary integrals
over the lumen wall (Green's theorem), :math:`a = \tfrac12\oint x\,dy - y\,dx`,
:math:`s_1 = \tfrac12\oint x^2 dy`, :math:`s_2 = -\tfrac12\oint y^2 dx`.
The lumen and the sealed cap close a cavity, so the pressure is conservative:
its potential is :math:`-p V'` per unit length, whose variation is the follower
pressure on the deformed wall (in-plane) and the cap force on the deformed
lumen (the global rows). The ``cap`` load keeps only the latter.

The wall's deformed position along each lumen edge is the P2 edge of the
parent element plus the displacement; 4-point Gauss-Legendre integrates the
degree-5 integrand exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.fem.section_model.element import lumen_edge_elements

__all__ = ["LumenWall", "lumen_wall", "LumenVolume", "lumen_volume"]


@dataclass(frozen=True)
class LumenWall:
    """Quadrature along the lumen edges.

    Attributes
    ----------
    elements
        Parent element of each lumen edge (nf,).
    dofs
        The parent elements' DOFs (nf, nb).
    points, tangents
        Reference wall positions x(t) and dx/dt at the Gauss points (nf, nq, 2).
    value, dvalue
        Shape-function vectors and their t-derivatives (nf, nq, 2, nb).
    weights
        Gauss weights on t in [0, 1] per edge, signed so that each edge runs with the
        lumen on its left (nf, nq).
    """

    elements: np.ndarray
    dofs: np.ndarray
    points: np.ndarray
    tangents: np.ndarray
    value: np.ndarray
    dvalue: np.ndarray
    weights: np.ndarray


def lumen_wall(section, disc) -> LumenWall:
    """The lumen wall of ``section`` on the discretisation ``disc``."""
    mesh, basis = disc.mesh, disc.basis

    t = mesh.t
    elems, which = lumen_edge_elements(section, mesh)
    s, ws = np.polynomial.legendre.leggauss(4)
    s, ws = 0.5 * (s + 1), 0.5 * ws
    start = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])[which]
    step = np.array([[1.0, 0.0], [-1.0, 1.0], [0.0, -1.0]])[which]  # stop - start
    ref = start.T[:, :, None] + step.T[:, :, None] * s[None, None, :]  # (2, nf, nq)
    xg = mesh.mapping().F(ref, tind=elems)
    jac = mesh.mapping().DF(ref, tind=elems)
    tangent = np.einsum("ijfq,jf->ifq", jac, step.T)
    scalar = basis.elem.elem
    nb = basis.Nbfun
    nf, nq = elems.size, s.size
    value = np.zeros((nf, nq, 2, nb))
    dvalue = np.zeros((nf, nq, 2, nb))
    for k in range(nb):
        phi, dphi = scalar.lbasis(ref, k // 2)
        value[:, :, k % 2, k] = phi
        dvalue[:, :, k % 2, k] = np.einsum("ifq,fi->fq", dphi, step)
    points = np.ascontiguousarray(np.transpose(xg, (1, 2, 0)))
    tangents = np.ascontiguousarray(np.transpose(tangent, (1, 2, 0)))
    # Green's theorem needs the lumen on the left of each edge's direction of travel; the
    # solid's element lies on the other side, so the sign comes from the element's centre.
    centre = np.asarray(mesh.p)[:, t[:, elems]].mean(axis=1).T  # (nf, 2)
    mid = points.mean(axis=1) - centre
    left = np.stack([-tangents[..., 1].mean(axis=1), tangents[..., 0].mean(axis=1)], axis=-1)
    sign = np.sign(np.einsum("fa,fa->f", left, mid))
    return LumenWall(
        elements=elems,
        dofs=np.ascontiguousarray(basis.element_dofs[:, elems].T),
        points=points,
        tangents=tangents,
        value=value,
        dvalue=dvalue,
        weights=sign[:, None] * ws[None, :],
    )


@dataclass(frozen=True)
class LumenVolume:
    """V' and its derivatives at one state (local to the lumen edges' parent elements).

    ``du`` (nf, nb), ``dg`` (3,), ``duu`` (nf, nb, nb), ``dug`` (nf, nb, 3), ``dgg`` (3, 3);
    ``area`` and ``moments`` (s_1, s_2) of the deformed lumen.
    """

    volume: float
    area: float
    moments: np.ndarray
    du: np.ndarray
    dg: np.ndarray
    duu: np.ndarray
    dug: np.ndarray
    dgg: np.ndarray


def lumen_volume(wall: LumenWall, u: np.ndarray, g: np.ndarray) -> LumenVolume:
    """V' = lambda (a + k . s) of the deformed lumen and its first and second derivatives."""
    lam, k1, k2 = (float(v) for v in g)
    ue = u[wall.dofs]
    x = wall.points + np.einsum("fqab,fb->fqa", wall.value, ue)
    xp = wall.tangents + np.einsum("fqab,fb->fqa", wall.dvalue, ue)
    X, Y, Xp, Yp = x[..., 0], x[..., 1], xp[..., 0], xp[..., 1]
    w = wall.weights
    # integrands over (x, y, x', y'): area, k_1-moment and k_2-moment parts
    area_i = 0.5 * (X * Yp - Y * Xp)
    s1_i = 0.5 * X**2 * Yp
    s2_i = -0.5 * Y**2 * Xp
    zero = np.zeros_like(X)
    d_area = np.stack([0.5 * Yp, -0.5 * Xp, -0.5 * Y, 0.5 * X], axis=-1)
    d_s1 = np.stack([X * Yp, zero, zero, 0.5 * X**2], axis=-1)
    d_s2 = np.stack([zero, -Y * Xp, -0.5 * Y**2, zero], axis=-1)
    hess = np.zeros(X.shape + (4, 4))
    hess[..., 0, 0] = k1 * Yp
    hess[..., 0, 3] = hess[..., 3, 0] = 0.5 + k1 * X
    hess[..., 1, 1] = -k2 * Xp
    hess[..., 1, 2] = hess[..., 2, 1] = -0.5 - k2 * Y
    d_g = d_area + k1 * d_s1 + k2 * d_s2  # d(a + k.s)/d(x, y, x', y')
    # (x, y, x', y') per local DOF: (nf, nq, nb, 4)
    D = np.concatenate([wall.value, wall.dvalue], axis=2).transpose(0, 1, 3, 2)
    area = float((w * area_i).sum())
    s = np.array([(w * s1_i).sum(), (w * s2_i).sum()])
    base = area + k1 * s[0] + k2 * s[1]
    dbase_du = np.einsum("fq,fqba,fqa->fb", wall.weights, D, d_g)
    ds_du = np.stack(
        [
            np.einsum("fq,fqba,fqa->fb", wall.weights, D, d_s1),
            np.einsum("fq,fqba,fqa->fb", wall.weights, D, d_s2),
        ],
        axis=-1,
    )
    duu = lam * np.einsum("fq,fqba,fqac,fqdc->fbd", wall.weights, D, hess, D)
    dug = np.concatenate([dbase_du[..., None], lam * ds_du], axis=-1)
    dgg = np.zeros((3, 3))
    dgg[0, 1:] = dgg[1:, 0] = s
    return LumenVolume(
        volume=lam * base,
        area=area,
        moments=s,
        du=lam * dbase_du,
        dg=np.array([base, lam * s[0], lam * s[1]]),
        duu=duu,
        dug=dug,
        dgg=dgg,
    )
