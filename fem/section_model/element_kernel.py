"""The section model's element blocks, compiled: one loop over triangles, no temporaries.

The batched section models (:mod:`softcath.fem.section_model.batch`) spend most of
their assembly in NumPy's small-matrix temporaries (a 14 x 14 block per triangle
from strain-displacement products, the volumetric projection, the bubble
condensation): at ~700 triangles per section the work is memory-bound, and
batching designs only makes the arrays bigger. This module does the same algebra
per triangle in registers with Numba (a dependency of CadQuery already), compiled
once and cached on disk.

Per triangle (isoparametric P2 geometry, vector Crouzeix-Raviart P2 + bubble
displacements with the local DOFs ``(s, c)`` interleaved, bubbles last; strains
``(xx, yy, zz, xy)`` with engineering shear; the quadrature rule of the section
model's scikit-fem basis) it forms

- ``k_loc = int B^T D B``, ``kug = int B^T D[:, zz] phi^T`` and
  ``k_gg = D_zz,zz int phi phi^T`` with ``phi = (1, x, y)``;
- the Lamé part ``lam P(tr eps)^2``, ``P`` the L2 projection onto P1 on the
  triangle (added to all three blocks);
- the static condensation of the two bubble DOFs: the retained blocks
  ``k_rr``, ``k_rg``, ``k_gg`` and the bubble maps ``xr``, ``xg``
  (bubbles = -(xr u_r + xg g)).

Tests: tests/fem/section_model/test_fast_assembly.py (equal to scikit-fem's
quadrature assembly to 1e-10).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["element_blocks", "scatter_rows", "strain_extremes"]


@njit(cache=True)
def _quadrature_point(x6, e, q, Ng, dNg):
    """Position, inverse Jacobian (row j, column I: dX_j / dx_I) and |det J| at point ``q``."""
    j00 = j01 = j10 = j11 = 0.0
    px = py = 0.0
    for k in range(6):
        x, y = x6[e, k, 0], x6[e, k, 1]
        j00 += x * dNg[k, 0, q]
        j01 += x * dNg[k, 1, q]
        j10 += y * dNg[k, 0, q]
        j11 += y * dNg[k, 1, q]
        px += x * Ng[k, q]
        py += y * Ng[k, q]
    det = j00 * j11 - j01 * j10
    return px, py, j11 / det, -j01 / det, -j10 / det, j00 / det, abs(det)


@njit(cache=True)
def _integrate(x6, D, e, dphi, W, Ng, dNg, kl, ku, pp, pd, inv_q, xq):
    """``k_loc``, ``kug``, ``int phi phi^T`` and ``int phi div`` of triangle ``e`` by quadrature."""
    ns, nq = dphi.shape[0], W.size
    nb = 2 * ns
    g = np.empty((2, ns))
    db = np.empty((4, nb))
    for q in range(nq):
        px, py, i00, i01, i10, i11, adet = _quadrature_point(x6, e, q, Ng, dNg)
        inv_q[e, q, 0, 0], inv_q[e, q, 0, 1], inv_q[e, q, 1, 0], inv_q[e, q, 1, 1] = i00, i01, i10, i11
        xq[e, q, 0], xq[e, q, 1] = px, py
        w = adet * W[q]
        for s in range(ns):
            g[0, s] = dphi[s, 0, q] * i00 + dphi[s, 1, q] * i10
            g[1, s] = dphi[s, 0, q] * i01 + dphi[s, 1, q] * i11
        # B of DOF (s, 0) is (g0, 0, 0, g1), of DOF (s, 1) is (0, g1, 0, g0): D B by columns.
        for s in range(ns):
            for p in range(4):
                db[p, 2 * s] = D[e, p, 0] * g[0, s] + D[e, p, 3] * g[1, s]
                db[p, 2 * s + 1] = D[e, p, 1] * g[1, s] + D[e, p, 3] * g[0, s]
        phi = (1.0, px, py)
        for a in range(nb):
            s, c = a // 2, a % 2
            ga, gb = g[c, s], g[1 - c, s]  # B_a's entries: ga in row c, gb in row 3
            for b in range(a, nb):  # upper triangle; D is symmetric
                kl[a, b] += w * (ga * db[c, b] + gb * db[3, b])
            for m in range(3):
                ku[a, m] += w * db[2, a] * phi[m]
                pd[m, a] += w * phi[m] * ga
        for m in range(3):
            for n in range(3):
                pp[m, n] += w * phi[m] * phi[n]


@njit(cache=True)
def _add_volumetric(kl, ku, kg, pp, pd, lam) -> None:
    """``lam P(tr eps)^2`` with ``P`` onto P1 on the triangle, in place.

    The P1 basis ``(1, x - xc, y - yc)`` has the block-diagonal Gram matrix
    ``diag(area, C)``, C the centred second moments: one scalar and one 2 x 2 inverse.
    """
    nb = kl.shape[0]
    area = pp[0, 0]
    cx, cy = pp[0, 1] / area, pp[0, 2] / area
    # Rows of [gu | gg] in the centred basis.
    rows = np.empty((3, nb + 3))
    for k in range(nb):
        rows[0, k] = pd[0, k]
        rows[1, k] = pd[1, k] - cx * pd[0, k]
        rows[2, k] = pd[2, k] - cy * pd[0, k]
    for k in range(3):
        rows[0, nb + k] = pp[0, k]
        rows[1, nb + k] = pp[1, k] - cx * pp[0, k]
        rows[2, nb + k] = pp[2, k] - cy * pp[0, k]
    a00, a01, a10, a11 = rows[1, nb + 1], rows[1, nb + 2], rows[2, nb + 1], rows[2, nb + 2]
    det = a00 * a11 - a01 * a10
    i00, i01, i10, i11 = a11 / det, -a01 / det, -a10 / det, a00 / det
    v = np.empty((3, nb + 3))
    for k in range(nb + 3):
        v[0, k] = rows[0, k] * lam / area
        v[1, k] = (i00 * rows[1, k] + i01 * rows[2, k]) * lam
        v[2, k] = (i10 * rows[1, k] + i11 * rows[2, k]) * lam
    for a in range(nb):
        for b in range(nb):
            kl[a, b] += rows[0, a] * v[0, b] + rows[1, a] * v[1, b] + rows[2, a] * v[2, b]
        for m in range(3):
            ku[a, m] += v[0, a] * rows[0, nb + m] + v[1, a] * rows[1, nb + m] + v[2, a] * rows[2, nb + m]
    for m in range(3):
        for n in range(3):
            for r in range(3):
                kg[m, n] += rows[r, nb + m] * v[r, nb + n]


@njit(cache=True)
def _condense(kl, ku, kg, e, k_rr, k_rg, k_gg, xr, xg) -> None:
    """Static condensation of the two bubble DOFs (the last two) of triangle ``e``."""
    nr = kl.shape[0] - 2
    a00, a01, a10, a11 = kl[nr, nr], kl[nr, nr + 1], kl[nr + 1, nr], kl[nr + 1, nr + 1]
    det = a00 * a11 - a01 * a10
    i00, i01, i10, i11 = a11 / det, -a01 / det, -a10 / det, a00 / det
    for k in range(nr):
        xr[e, 0, k] = i00 * kl[nr, k] + i01 * kl[nr + 1, k]
        xr[e, 1, k] = i10 * kl[nr, k] + i11 * kl[nr + 1, k]
    for m in range(3):
        xg[e, 0, m] = i00 * ku[nr, m] + i01 * ku[nr + 1, m]
        xg[e, 1, m] = i10 * ku[nr, m] + i11 * ku[nr + 1, m]
    for a in range(nr):
        for b in range(nr):
            k_rr[e, a, b] = kl[a, b] - (kl[nr, a] * xr[e, 0, b] + kl[nr + 1, a] * xr[e, 1, b])
        for m in range(3):
            k_rg[e, a, m] = ku[a, m] - (kl[nr, a] * xg[e, 0, m] + kl[nr + 1, a] * xg[e, 1, m])
    for m in range(3):
        for n in range(3):
            k_gg[e, m, n] = kg[m, n] - (ku[nr, m] * xg[e, 0, n] + ku[nr + 1, m] * xg[e, 1, n])


@njit(cache=True)
def _blocks(x6, D, lam, dphi, W, Ng, dNg, k_rr, k_rg, k_gg, xr, xg, moments, inv_q, xq) -> None:
    nb = 2 * dphi.shape[0]
    kl = np.empty((nb, nb))
    ku = np.empty((nb, 3))
    kg = np.empty((3, 3))
    pp = np.empty((3, 3))
    pd = np.empty((3, nb))
    for e in range(x6.shape[0]):
        kl[:] = 0.0
        ku[:] = 0.0
        pp[:] = 0.0
        pd[:] = 0.0
        _integrate(x6, D, e, dphi, W, Ng, dNg, kl, ku, pp, pd, inv_q, xq)
        for a in range(nb):
            for b in range(a):
                kl[a, b] = kl[b, a]
        for m in range(3):
            moments[e, m] = pp[0, m]
            for n in range(3):
                kg[m, n] = D[e, 2, 2] * pp[m, n]
        _add_volumetric(kl, ku, kg, pp, pd, lam[e])
        _condense(kl, ku, kg, e, k_rr, k_rg, k_gg, xr, xg)


def element_blocks(x6, D, lam, *, dphi, W, Ng, dNg) -> dict:
    """Condensed element blocks of triangles ``x6`` (M, 6, 2) with laws ``D`` (M, 4, 4), ``lam`` (M,).

    Parameters
    ----------
    x6
        P2 node positions per triangle: corners 0, 1, 2, then midsides 01, 12, 20 [mm].
    D, lam
        Each triangle's 4 x 4 modulus matrix (xx, yy, zz, xy; engineering shear) and the
        Lamé part of its volumetric modulus, projected on P1 [MPa].
    dphi, W, Ng, dNg
        Reference gradients of the scalar element's basis (ns, 2, nq), quadrature weights
        (nq,), and the P2 geometry's shape functions (6, nq) and their gradients (6, 2, nq).

    Returns
    -------
    dict
        ``k_rr`` (M, nr, nr), ``k_rg`` (M, nr, 3), ``k_gg`` (M, 3, 3), ``xr`` (M, 2, nr),
        ``xg`` (M, 2, 3), ``moments`` (M, 3) = int (1, x, y), ``inv`` (M, nq, 2, 2) the
        inverse Jacobians and ``xq`` (M, nq, 2) the quadrature points.
    """
    M, ns, nq = x6.shape[0], dphi.shape[0], W.size
    nr = 2 * ns - 2
    out = {
        "k_rr": np.empty((M, nr, nr)),
        "k_rg": np.empty((M, nr, 3)),
        "k_gg": np.empty((M, 3, 3)),
        "xr": np.empty((M, 2, nr)),
        "xg": np.empty((M, 2, 3)),
        "moments": np.empty((M, 3)),
        "inv": np.empty((M, nq, 2, 2)),
        "xq": np.empty((M, nq, 2)),
    }
    c = np.ascontiguousarray
    _blocks(
        c(x6, dtype=float),
        c(D, dtype=float),
        c(lam, dtype=float),
        c(dphi),
        c(W),
        c(Ng),
        c(dNg),
        *out.values(),
    )
    return out


@njit(cache=True)
def _scatter(values, slot, out) -> None:
    for i in range(slot.size):
        k = slot[i]
        if k >= 0:
            out[k] += values[i]


def scatter_rows(values: np.ndarray, slot: np.ndarray, size: int) -> np.ndarray:
    """``out[slot[i]] += values[i]`` over the entries with ``slot[i] >= 0`` (an assembly scatter)."""
    out = np.zeros(size)
    _scatter(np.ascontiguousarray(values, dtype=float).ravel(), slot, out)
    return out


@njit(cache=True)
def _strain_extremes(u, dofs, elements, xr, xg, g, dphi, inv_q, xq):
    ns, nq = dphi.shape[0], dphi.shape[2]
    nr = 2 * ns - 2
    ue = np.empty(2 * ns)
    low, high = np.inf, -np.inf
    for e in elements:
        for k in range(nr):
            ue[k] = u[dofs[k, e]]
        for i in range(2):
            b = 0.0
            for k in range(nr):
                b += xr[e, i, k] * ue[k]
            for m in range(3):
                b += xg[e, i, m] * g[m]
            ue[nr + i] = -b
        for q in range(nq):
            # reference gradients d u_c / d X_j, then the physical ones through dX_j / dx_I
            r00 = r01 = r10 = r11 = 0.0
            for s in range(ns):
                r00 += ue[2 * s] * dphi[s, 0, q]
                r01 += ue[2 * s] * dphi[s, 1, q]
                r10 += ue[2 * s + 1] * dphi[s, 0, q]
                r11 += ue[2 * s + 1] * dphi[s, 1, q]
            i00, i01, i10, i11 = inv_q[e, q, 0, 0], inv_q[e, q, 0, 1], inv_q[e, q, 1, 0], inv_q[e, q, 1, 1]
            exx = r00 * i00 + r01 * i10
            eyy = r10 * i01 + r11 * i11
            exy = 0.5 * (r00 * i01 + r01 * i11 + r10 * i00 + r11 * i10)
            ezz = g[0] + g[1] * xq[e, q, 0] + g[2] * xq[e, q, 1]
            mean = 0.5 * (exx + eyy)
            radius = np.sqrt((0.5 * (exx - eyy)) ** 2 + exy**2)
            low = min(low, mean - radius, ezz)
            high = max(high, mean + radius, ezz)
    return low, high


def strain_extremes(u, dofs, elements, blocks: dict, g, dphi) -> tuple[float, float]:
    """(smallest, largest) principal strain over the quadrature points of ``elements``.

    Parameters
    ----------
    u
        Retained DOFs of the section (n,); the bubbles are recovered with the blocks'
        ``xr``, ``xg`` and the global strains ``g`` (3,).
    dofs
        Local-to-global DOF table (nb, nel); ``elements`` the triangles to visit.
    blocks
        :func:`element_blocks`' ``xr``, ``xg``, ``inv`` and ``xq`` of the section's triangles.
    dphi
        Reference gradients of the scalar basis (ns, 2, nq).
    """
    if len(elements) == 0:
        return (0.0, 0.0)
    low, high = _strain_extremes(
        u, dofs, elements, blocks["xr"], blocks["xg"], np.asarray(g, float), dphi, blocks["inv"], blocks["xq"]
    )
    return float(low), float(high)
