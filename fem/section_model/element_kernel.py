"""The section model's element blocks, compiled: blocks of triangles side by side, no temporaries.

The batched section models (:mod:`softcath.fem.section_model.batch`) would spend most of
their assembly in NumPy's small-matrix temporaries (a 14 x 14 block per triangle
from strain-displacement products, the volumetric projection, the bubble
condensation): at ~700 triangles per section that work is memory-bound, and
batching designs only makes the arrays bigger. This module does the same algebra
with Numba (a dependency of CadQuery already), compiled once and cached on disk,
on :data:`BLOCK` triangles at a time with the triangle innermost, so that every
loop is a vector loop over the block's triangles.

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
  (bubbles = -(xr u_r + xg g)); ``k_rr`` and ``k_rg`` are added straight into the
  assembled matrices, never stored per triangle.

Tests: tests/fem/section_model/test_fast_assembly.py (equal to scikit-fem's
quadrature assembly to 1e-10).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["BLOCK", "element_blocks", "strain_extremes"]

#: Triangles integrated side by side: the innermost loops run over a block of triangles, so
#: the compiler vectorises them (measured, 2026-11-26, 700-triangle sections: 1.4 us a
#: triangle with 48, 1.6 with 32, 2.5 one triangle at a time; 8 and 16 were not vectorised).
BLOCK = 48
#: Compiled once and cached on disk; fast math is safe here (finite inputs, nonzero Jacobians).
_JIT = {"cache": True, "fastmath": True, "error_model": "numpy"}


@njit(inline="always", **_JIT)
def _integrate(x6t, Dt, e0, dphi, W, Ng, dNg, M, s, inv_q, xq) -> None:
    """``k_loc``, ``kug``, ``int phi phi^T`` and ``int phi div`` of the block at ``e0``, by quadrature."""
    T = BLOCK
    ns, nq = dphi.shape[0], W.size
    nb = 2 * ns
    kl, ku, kg, pp, pd, g, db, rows, v, j, inv, w, ph, sc = s
    for q in range(nq):
        j[:] = 0.0
        ph[1] = 0.0
        ph[2] = 0.0
        for k in range(6):
            a0, a1, n0 = dNg[k, 0, q], dNg[k, 1, q], Ng[k, q]
            for t in range(T):
                x, y = x6t[k, 0, e0 + t], x6t[k, 1, e0 + t]
                j[0, t] += x * a0
                j[1, t] += x * a1
                j[2, t] += y * a0
                j[3, t] += y * a1
                ph[1, t] += x * n0
                ph[2, t] += y * n0
        for t in range(T):  # inverse Jacobian: row j, column I holds dX_j / dx_I
            det = j[0, t] * j[3, t] - j[1, t] * j[2, t]
            inv[0, t] = j[3, t] / det
            inv[1, t] = -j[1, t] / det
            inv[2, t] = -j[2, t] / det
            inv[3, t] = j[0, t] / det
            w[t] = abs(det) * W[q]
            ph[0, t] = 1.0
        for t in range(min(T, M - e0)):
            e = e0 + t
            inv_q[e, q, 0, 0], inv_q[e, q, 0, 1] = inv[0, t], inv[1, t]
            inv_q[e, q, 1, 0], inv_q[e, q, 1, 1] = inv[2, t], inv[3, t]
            xq[e, q, 0], xq[e, q, 1] = ph[1, t], ph[2, t]
        for sf in range(ns):
            d0, d1 = dphi[sf, 0, q], dphi[sf, 1, q]
            for t in range(T):
                g[0, sf, t] = d0 * inv[0, t] + d1 * inv[2, t]
                g[1, sf, t] = d0 * inv[1, t] + d1 * inv[3, t]
        # B of DOF (s, 0) is (g0, 0, 0, g1), of DOF (s, 1) is (0, g1, 0, g0): D B by columns.
        for sf in range(ns):
            for p in range(4):
                for t in range(T):
                    db[p, 2 * sf, t] = Dt[p, 0, e0 + t] * g[0, sf, t] + Dt[p, 3, e0 + t] * g[1, sf, t]
                    db[p, 2 * sf + 1, t] = Dt[p, 1, e0 + t] * g[1, sf, t] + Dt[p, 3, e0 + t] * g[0, sf, t]
        for a in range(nb):
            sf, c = a // 2, a % 2  # B_a's entries: g[c] in row c, g[1 - c] in row 3
            for b in range(a, nb):  # upper triangle; D is symmetric
                for t in range(T):
                    kl[a, b, t] += w[t] * (g[c, sf, t] * db[c, b, t] + g[1 - c, sf, t] * db[3, b, t])
            for m in range(3):
                for t in range(T):
                    wp = w[t] * ph[m, t]
                    ku[a, m, t] += wp * db[2, a, t]
                    pd[m, a, t] += wp * g[c, sf, t]
        for m in range(3):
            for n in range(3):
                for t in range(T):
                    pp[m, n, t] += w[t] * ph[m, t] * ph[n, t]


@njit(inline="always", **_JIT)
def _add_volumetric(lamt, e0, s) -> None:
    """``lam P(tr eps)^2`` with ``P`` onto P1 on each triangle, in place.

    The P1 basis ``(1, x - xc, y - yc)`` has the block-diagonal Gram matrix
    ``diag(area, C)``, C the centred second moments: one scalar and one 2 x 2 inverse.
    """
    T = BLOCK
    kl, ku, kg, pp, pd, g, db, rows, v, j, inv, w, ph, sc = s
    nb = kl.shape[0]
    for t in range(T):
        sc[0, t] = pp[0, 0, t]  # area
        sc[1, t] = pp[0, 1, t] / pp[0, 0, t]  # centroid
        sc[2, t] = pp[0, 2, t] / pp[0, 0, t]
    # Rows of [gu | gg] in the centred basis.
    for k in range(nb):
        for t in range(T):
            rows[0, k, t] = pd[0, k, t]
            rows[1, k, t] = pd[1, k, t] - sc[1, t] * pd[0, k, t]
            rows[2, k, t] = pd[2, k, t] - sc[2, t] * pd[0, k, t]
    for k in range(3):
        for t in range(T):
            rows[0, nb + k, t] = pp[0, k, t]
            rows[1, nb + k, t] = pp[1, k, t] - sc[1, t] * pp[0, k, t]
            rows[2, nb + k, t] = pp[2, k, t] - sc[2, t] * pp[0, k, t]
    for t in range(T):
        a00, a01 = rows[1, nb + 1, t], rows[1, nb + 2, t]
        a10, a11 = rows[2, nb + 1, t], rows[2, nb + 2, t]
        lam_det = lamt[e0 + t] / (a00 * a11 - a01 * a10)
        sc[3, t], sc[4, t], sc[5, t], sc[6, t] = a11 * lam_det, -a01 * lam_det, -a10 * lam_det, a00 * lam_det
        sc[7, t] = lamt[e0 + t] / sc[0, t]
    for k in range(nb + 3):
        for t in range(T):
            v[0, k, t] = rows[0, k, t] * sc[7, t]
            v[1, k, t] = sc[3, t] * rows[1, k, t] + sc[4, t] * rows[2, k, t]
            v[2, k, t] = sc[5, t] * rows[1, k, t] + sc[6, t] * rows[2, k, t]
    for a in range(nb):
        for b in range(nb):
            for t in range(T):
                kl[a, b, t] += (
                    rows[0, a, t] * v[0, b, t] + rows[1, a, t] * v[1, b, t] + rows[2, a, t] * v[2, b, t]
                )
        for m in range(3):
            for t in range(T):
                ku[a, m, t] += (
                    v[0, a, t] * rows[0, nb + m, t]
                    + v[1, a, t] * rows[1, nb + m, t]
                    + v[2, a, t] * rows[2, nb + m, t]
                )
    for m in range(3):
        for n in range(3):
            for t in range(T):
                kg[m, n, t] += (
                    rows[0, nb + m, t] * v[0, nb + n, t]
                    + rows[1, nb + m, t] * v[1, nb + n, t]
                    + rows[2, nb + m, t] * v[2, nb + n, t]
                )


@njit(inline="always", **_JIT)
def _condense(e0, M, s, slot_rr, slot_rg, data, k_ug, k_gg, xr, xg, moments) -> None:
    """Static condensation of the two bubble DOFs (the last two); the retained blocks scattered."""
    T = BLOCK
    kl, ku, kg, pp, pd, g, db, rows, v, j, inv, w, ph, sc = s
    nb = kl.shape[0]
    nr = nb - 2
    for t in range(T):
        a00, a01 = kl[nr, nr, t], kl[nr, nr + 1, t]
        a10, a11 = kl[nr + 1, nr, t], kl[nr + 1, nr + 1, t]
        det = a00 * a11 - a01 * a10
        sc[0, t], sc[1, t], sc[2, t], sc[3, t] = a11 / det, -a01 / det, -a10 / det, a00 / det
    # The bubble maps xr (v[:2, :nr]) and xg (v[:2, nb:]).
    for k in range(nr):
        for t in range(T):
            v[0, k, t] = sc[0, t] * kl[nr, k, t] + sc[1, t] * kl[nr + 1, k, t]
            v[1, k, t] = sc[2, t] * kl[nr, k, t] + sc[3, t] * kl[nr + 1, k, t]
    for m in range(3):
        for t in range(T):
            v[0, nb + m, t] = sc[0, t] * ku[nr, m, t] + sc[1, t] * ku[nr + 1, m, t]
            v[1, nb + m, t] = sc[2, t] * ku[nr, m, t] + sc[3, t] * ku[nr + 1, m, t]
    nel = slot_rr.shape[0]
    for t in range(min(T, M - e0)):
        e = e0 + t
        design, el = e // nel, e % nel
        for k in range(nr):
            xr[e, 0, k], xr[e, 1, k] = v[0, k, t], v[1, k, t]
        for m in range(3):
            xg[e, 0, m], xg[e, 1, m] = v[0, nb + m, t], v[1, nb + m, t]
            moments[e, m] = pp[0, m, t]
            for n in range(3):
                k_gg[e, m, n] = kg[m, n, t] - (
                    ku[nr, m, t] * v[0, nb + n, t] + ku[nr + 1, m, t] * v[1, nb + n, t]
                )
        for a in range(nr):
            ka0, ka1 = kl[nr, a, t], kl[nr + 1, a, t]
            for b in range(nr):
                slot = slot_rr[el, a, b]
                if slot >= 0:  # -1: a pinned row or column
                    data[design, slot] += kl[a, b, t] - (ka0 * v[0, b, t] + ka1 * v[1, b, t])
            for m in range(3):
                k_ug[design, slot_rg[el, a, m]] += ku[a, m, t] - (
                    ka0 * v[0, nb + m, t] + ka1 * v[1, nb + m, t]
                )


@njit(**_JIT)
def _blocks(
    x6t, Dt, lamt, dphi, W, Ng, dNg, M, slot_rr, slot_rg, data, k_ug, k_gg, xr, xg, moments, inv_q, xq
):
    T = BLOCK
    ns = dphi.shape[0]
    nb = 2 * ns
    # Scratch of one block (triangles last): see _integrate, _add_volumetric, _condense.
    s = (
        np.empty((nb, nb, T)),  # kl: the local stiffness
        np.empty((nb, 3, T)),  # ku: its coupling with the global strains
        np.empty((3, 3, T)),  # kg: the global strains' block
        np.empty((3, 3, T)),  # pp: int phi phi^T
        np.empty((3, nb, T)),  # pd: int phi div
        np.empty((2, ns, T)),  # g: physical gradients of the scalar basis
        np.empty((4, nb, T)),  # db: D B
        np.empty((3, nb + 3, T)),  # rows: [pd | pp] in the centred P1 basis
        np.empty((3, nb + 3, T)),  # v: lam Gram^-1 rows; then the bubble maps
        np.empty((4, T)),  # j: Jacobian
        np.empty((4, T)),  # inv: its inverse
        np.empty(T),  # w: quadrature weight x |det J|
        np.empty((3, T)),  # ph: phi = (1, x, y) at the point
        np.empty((8, T)),  # sc: per-triangle scalars
    )
    kl, ku, kg, pp, pd = s[0], s[1], s[2], s[3], s[4]
    for e0 in range(0, x6t.shape[2], T):
        kl[:] = 0.0
        ku[:] = 0.0
        pp[:] = 0.0
        pd[:] = 0.0
        _integrate(x6t, Dt, e0, dphi, W, Ng, dNg, M, s, inv_q, xq)
        for a in range(nb):
            for b in range(a):
                for t in range(T):
                    kl[a, b, t] = kl[b, a, t]
        for m in range(3):
            for n in range(3):
                for t in range(T):
                    kg[m, n, t] = Dt[2, 2, e0 + t] * pp[m, n, t]
        _add_volumetric(lamt, e0, s)
        _condense(e0, M, s, slot_rr, slot_rg, data, k_ug, k_gg, xr, xg, moments)


def element_blocks(x6, D, lam, *, dphi, W, Ng, dNg, slot_rr, slot_rg, nnz, n_ug) -> dict:
    """Element blocks of triangles ``x6`` (M, 6, 2), laws ``D`` (M, 4, 4) and ``lam`` (M,), assembled.

    The M triangles are ``m`` designs' ``nel`` triangles each (design-major), all on one mesh
    whose scatters are ``slot_rr`` and ``slot_rg``.

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
    slot_rr, slot_rg
        Where each triangle's retained block goes: ``slot_rr`` (nel, nr, nr) its entry of the
        assembled sparse matrix's data (-1: dropped), ``slot_rg`` (nel, nr, 3) its entry of
        the flattened coupling with the global strains.
    nnz, n_ug
        Sizes of the assembled data and of the flattened coupling.

    Returns
    -------
    dict
        ``data`` (m, nnz) and ``K_ug`` (m, n_ug) assembled per design; per triangle
        ``k_gg`` (M, 3, 3), ``xr`` (M, 2, nr),
        ``xg`` (M, 2, 3), ``moments`` (M, 3) = int (1, x, y), ``inv`` (M, nq, 2, 2) the
        inverse Jacobians and ``xq`` (M, nq, 2) the quadrature points.
    """
    M, ns, nq = x6.shape[0], dphi.shape[0], W.size
    nr = 2 * ns - 2
    nel = slot_rr.shape[0]
    # the compiled scatter trusts these shapes: a mismatch would write out of bounds
    if M == 0 or M % nel or slot_rg.shape[0] != nel:
        raise ValueError(f"x6: {M} triangles, must be a positive multiple of the mesh's {nel} (slot_rr)")
    for name, arr, shape in (("D", D, (M, 4, 4)), ("lam", lam, (M,))):
        if arr.shape != shape:
            raise ValueError(f"{name}: shape {arr.shape}, must be {shape}")
    m = M // nel
    out = {
        "data": np.zeros((m, nnz)),
        "K_ug": np.zeros((m, n_ug)),
        "k_gg": np.empty((M, 3, 3)),
        "xr": np.empty((M, 2, nr)),
        "xg": np.empty((M, 2, 3)),
        "moments": np.empty((M, 3)),
        "inv": np.empty((M, nq, 2, 2)),
        "xq": np.empty((M, nq, 2)),
    }
    pad = -M % BLOCK
    # lanes past the last triangle repeat it (finite values, never written out)
    idx = np.concatenate([np.arange(M), np.full(pad, M - 1)]) if pad else slice(None)
    x6t = np.ascontiguousarray(np.asarray(x6, float)[idx].transpose(1, 2, 0))
    Dt = np.ascontiguousarray(np.asarray(D, float)[idx].transpose(1, 2, 0))
    lamt = np.ascontiguousarray(np.asarray(lam, float)[idx])
    c = np.ascontiguousarray
    _blocks(x6t, Dt, lamt, c(dphi), c(W), c(Ng), c(dNg), M, c(slot_rr), c(slot_rg), *out.values())
    return out


@njit(**_JIT)
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
