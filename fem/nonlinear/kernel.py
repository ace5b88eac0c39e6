r"""The 3-D body's internal forces and tangent, compiled: one P2 tetrahedron at a time.

The same algebra as the batched NumPy kernels of :class:`~softcath.fem.nonlinear.body.HyperelasticBody`
(which stay the reference), written with Numba (compiled once, cached on disk) for the laws the
catheter uses:

- decoupled compressible Yeoh (:class:`~softcath.fem.hyperelastic.laws.Yeoh`), with its
  volumetric energy either at every quadrature point or, mixed u–p, of the element's mean
  dilatation :math:`\bar J` (the condensed P2–P0 pressure; its rank-one block
  :math:`U''(\bar J)/V\, g g^T` with :math:`g_{ai} = \int \mathrm{cof}F_{iJ}\,\partial_J\phi_a`);
- Saint Venant–Kirchhoff with a constant anisotropic :math:`\mathbb{C}`
  (:class:`~softcath.fem.hyperelastic.laws.AnisotropicSVK`).

Per element: F at the quadrature points, P and A = dP/dF per point, the element force
:math:`f_{ai} = \sum_q P_{iJ} w\,\partial_J\phi_a` and stiffness
:math:`K_{ai,bk} = \sum_q w\,\partial_J\phi_a A_{iJkL} \partial_L\phi_b`, summed straight into the
global force vector and the tangent's pattern values (no (e, 30, 30) intermediate array and no
``bincount`` over the pattern, which is where the NumPy path spends most of its time).

Tests: tests/fem/nonlinear/test_body_kernel.py (equal to the NumPy path, and the tangent equal to
a finite difference of the forces).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from softcath.fem.hyperelastic.laws import AnisotropicSVK, Yeoh

__all__ = ["YEOH", "SVK", "law_code", "assemble"]

#: Compiled once and cached on disk. No fastmath: the compiled path is checked against the
#: NumPy reference to round-off, and reassociation would only buy a few per cent here.
_JIT = {"cache": True, "error_model": "numpy"}

#: Law codes understood by :func:`assemble`.
YEOH, SVK = 0, 1


def law_code(law) -> tuple[int, np.ndarray] | None:
    """(code, parameters) of a law the kernel implements, ``None`` for any other law.

    Only the exact classes qualify: a subclass may change the energy, and then the NumPy path
    (which calls the law's own methods) is the right one.
    """
    if type(law) is Yeoh:
        return YEOH, np.array([law.c1, law.c2, law.c3, law.bulk_modulus], float)
    if type(law) is AnisotropicSVK:
        return SVK, np.ascontiguousarray(law.tensor, float).ravel()
    return None


@njit(inline="always", **_JIT)
def _cofactor(f, c) -> float:
    """cof F into ``c`` (3, 3); returns det F."""
    c[0, 0] = f[1, 1] * f[2, 2] - f[1, 2] * f[2, 1]
    c[0, 1] = f[1, 2] * f[2, 0] - f[1, 0] * f[2, 2]
    c[0, 2] = f[1, 0] * f[2, 1] - f[1, 1] * f[2, 0]
    c[1, 0] = f[0, 2] * f[2, 1] - f[0, 1] * f[2, 2]
    c[1, 1] = f[0, 0] * f[2, 2] - f[0, 2] * f[2, 0]
    c[1, 2] = f[0, 1] * f[2, 0] - f[0, 0] * f[2, 1]
    c[2, 0] = f[0, 1] * f[1, 2] - f[0, 2] * f[1, 1]
    c[2, 1] = f[0, 2] * f[1, 0] - f[0, 0] * f[1, 2]
    c[2, 2] = f[0, 0] * f[1, 1] - f[0, 1] * f[1, 0]
    return f[0, 0] * c[0, 0] + f[0, 1] * c[0, 1] + f[0, 2] * c[0, 2]


@njit(inline="always", **_JIT)
def _yeoh(f, cof, j, prm, volumetric, p, a) -> None:
    """Yeoh P and A (``Yeoh.stress_tangent``'s closed form), its U(J) included if ``volumetric``."""
    c1, c2, c3, kappa = prm[0], prm[1], prm[2], prm[3]
    i1 = 0.0
    for i in range(3):
        for jj in range(3):
            i1 += f[i, jj] * f[i, jj]
    jm = j ** (-2.0 / 3.0)
    x = jm * i1 - 3.0
    w1 = c1 + 2.0 * c2 * x + 3.0 * c3 * x * x
    w2 = 2.0 * c2 + 6.0 * c3 * x
    c_hh = (4.0 / 9.0) * w1 * jm * i1
    c_sw = (2.0 / 3.0) * w1 * jm * i1
    c_fh = -(4.0 / 3.0) * w1 * jm
    c_ii = 2.0 * w1 * jm
    u1 = kappa * (j - 1.0)
    if volumetric:
        c_hh += j * j * kappa + j * u1
        c_sw -= j * u1
    h = np.empty((3, 3))
    d = np.empty((3, 3))
    for i in range(3):
        for jj in range(3):
            h[i, jj] = cof[i, jj] / j
            d[i, jj] = jm * (2.0 * f[i, jj] - (2.0 / 3.0) * i1 * h[i, jj])
            p[i, jj] = w1 * d[i, jj] + (u1 * cof[i, jj] if volumetric else 0.0)
    for i in range(3):
        for jj in range(3):
            for k in range(3):
                for ll in range(3):
                    a[i, jj, k, ll] = (
                        c_hh * h[i, jj] * h[k, ll]
                        + c_fh * (f[i, jj] * h[k, ll] + h[i, jj] * f[k, ll])
                        + w2 * d[i, jj] * d[k, ll]
                        + c_sw * h[i, ll] * h[k, jj]
                    )
    for i in range(3):
        for jj in range(3):
            a[i, jj, i, jj] += c_ii


@njit(inline="always", **_JIT)
def _svk(f, prm, p, a) -> None:
    """SVK P = F S and A_iJkL = δ_ik S_JL + F_iM ℂ_MJLQ F_kQ with ℂ flattened in ``prm``."""
    e = np.empty((3, 3))
    for ii in range(3):
        for jj in range(3):
            s = 0.0
            for m in range(3):
                s += f[m, ii] * f[m, jj]
            e[ii, jj] = 0.5 * (s - (1.0 if ii == jj else 0.0))
    s = np.zeros((3, 3))
    for ii in range(3):
        for jj in range(3):
            acc = 0.0
            for k in range(3):
                for ll in range(3):
                    acc += prm[27 * ii + 9 * jj + 3 * k + ll] * e[k, ll]
            s[ii, jj] = acc
    for i in range(3):
        for jj in range(3):
            acc = 0.0
            for m in range(3):
                acc += f[i, m] * s[m, jj]
            p[i, jj] = acc
    # g[M, J, L, k] = Σ_Q ℂ_MJLQ F_kQ, then A_iJkL = Σ_M F_iM g[M, J, L, k]
    g = np.empty((3, 3, 3, 3))
    for m in range(3):
        for jj in range(3):
            for ll in range(3):
                for k in range(3):
                    acc = 0.0
                    for q in range(3):
                        acc += prm[27 * m + 9 * jj + 3 * ll + q] * f[k, q]
                    g[m, jj, ll, k] = acc
    for i in range(3):
        for jj in range(3):
            for k in range(3):
                for ll in range(3):
                    acc = s[jj, ll] if i == k else 0.0
                    for m in range(3):
                        acc += f[i, m] * g[m, jj, ll, k]
                    a[i, jj, k, ll] = acc


@njit(**_JIT)
def assemble(u, dofs, grads, weights, volumes, pattern_pos, code, prm, split, f_out, data_out) -> None:
    """Add the elements' internal forces into ``f_out`` and tangent into ``data_out``.

    Parameters
    ----------
    u
        Displacement (ndofs,) [mm].
    dofs
        (e, 30) global vector DOFs, (node a, component i) order.
    grads, weights
        (e, q, 10, 3) reference shape-function gradients [1/mm] and (e, q) weights [mm³].
    volumes
        (e,) element volumes [mm³] (the sum of the weights).
    pattern_pos
        (e, 900) positions in the tangent's pattern of the element matrix, row-major.
    code, prm
        Law code (:data:`YEOH` or :data:`SVK`) and its parameters (:func:`law_code`).
    split
        Mixed u–p: the Yeoh U(J) of the element's mean dilatation instead of at each point.
    f_out, data_out
        Force vector (ndofs,) [N] and pattern values [N/mm], added to.
    """
    ne, nq = weights.shape
    fmat = np.empty((nq, 3, 3))
    cofs = np.empty((nq, 3, 3))
    dets = np.empty(nq)
    p = np.empty((3, 3))
    a = np.empty((3, 3, 3, 3))
    ue = np.empty((10, 3))
    fe = np.empty((10, 3))
    ke = np.empty((30, 30))
    t = np.empty((3, 3, 30))
    ge = np.empty((10, 3))
    for e in range(ne):
        for n in range(10):
            for i in range(3):
                ue[n, i] = u[dofs[e, 3 * n + i]]
        jbar = 0.0
        for q in range(nq):
            for i in range(3):
                for jj in range(3):
                    acc = 1.0 if i == jj else 0.0
                    for n in range(10):
                        acc += ue[n, i] * grads[e, q, n, jj]
                    fmat[q, i, jj] = acc
            dets[q] = _cofactor(fmat[q], cofs[q])
            jbar += dets[q] * weights[e, q]
        jbar /= volumes[e]
        fe[:] = 0.0
        ke[:] = 0.0
        ge[:] = 0.0
        u1bar = prm[3] * (jbar - 1.0) if split else 0.0
        for q in range(nq):
            fq, cq, w = fmat[q], cofs[q], weights[e, q]
            if code == YEOH:
                _yeoh(fq, cq, dets[q], prm, not split, p, a)
            else:
                _svk(fq, prm, p, a)
            if split:
                # U'(J̄) cof F and U'(J̄) d(cof F)/dF = U'(J̄) (C_iJ C_kL − C_iL C_kJ) / J
                cj = u1bar / dets[q]
                for i in range(3):
                    for jj in range(3):
                        p[i, jj] += u1bar * cq[i, jj]
                        for k in range(3):
                            for ll in range(3):
                                a[i, jj, k, ll] += cj * (cq[i, jj] * cq[k, ll] - cq[i, ll] * cq[k, jj])
            for n in range(10):
                for i in range(3):
                    acc = 0.0
                    acc_g = 0.0
                    for jj in range(3):
                        acc += p[i, jj] * grads[e, q, n, jj]
                        acc_g += cq[i, jj] * grads[e, q, n, jj]
                    fe[n, i] += acc * w
                    ge[n, i] += acc_g * w
            # t[i, J, 3b + k] = Σ_L A_iJkL ∂_L φ_b, then K[3a + i, 3b + k] += w Σ_J ∂_J φ_a t[i, J, 3b + k]:
            # the column (b, k) innermost and contiguous in both, so the row updates vectorise
            for i in range(3):
                for jj in range(3):
                    for b in range(10):
                        for k in range(3):
                            t[i, jj, 3 * b + k] = (
                                a[i, jj, k, 0] * grads[e, q, b, 0]
                                + a[i, jj, k, 1] * grads[e, q, b, 1]
                                + a[i, jj, k, 2] * grads[e, q, b, 2]
                            )
            # A has major symmetry (hyperelastic), so K is symmetric: the node blocks b >= a only
            for n in range(10):
                g0, g1, g2 = grads[e, q, n, 0] * w, grads[e, q, n, 1] * w, grads[e, q, n, 2] * w
                for i in range(3):
                    row = ke[3 * n + i]
                    t0, t1, t2 = t[i, 0], t[i, 1], t[i, 2]
                    for c in range(3 * n, 30):
                        row[c] += g0 * t0[c] + g1 * t1[c] + g2 * t2[c]
        for n in range(10):
            for b in range(n + 1, 10):
                for i in range(3):
                    for k in range(3):
                        ke[3 * b + k, 3 * n + i] = ke[3 * n + i, 3 * b + k]
        if split:
            c = prm[3] / volumes[e]  # U''(J̄) / V
            for n in range(10):
                for i in range(3):
                    for b in range(10):
                        for k in range(3):
                            ke[3 * n + i, 3 * b + k] += c * ge[n, i] * ge[b, k]
        for n in range(10):
            for i in range(3):
                f_out[dofs[e, 3 * n + i]] += fe[n, i]
        for r in range(30):
            for c in range(30):
                data_out[pattern_pos[e, 30 * r + c]] += ke[r, c]
