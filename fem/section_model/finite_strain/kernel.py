r"""The finite-strain section's element and lumen-wall blocks, compiled, bubbles condensed.

The same algebra as :func:`~softcath.fem.section_model.finite_strain.residual.internal` and
:func:`~softcath.fem.section_model.finite_strain.lumen.lumen_volume`, written with Numba
(compiled once, cached on disk) one triangle at a time, for the template path of
:mod:`softcath.fem.section_model.finite_strain.fast`:

- per quadrature point the five varying components of F, the law's stress and
  tangent on them (decoupled Yeoh with the projected volumetric split, or Saint
  Venant-Kirchhoff), the strain-displacement rows (each local unknown touches at
  most three of the five components) and the second derivatives of
  :math:`F_{33} = \lambda (1 + k\cdot x)`;
- per triangle the projected volumetric block and the static condensation of the
  two bubble unknowns (interior to the triangle), so that the assembled system has
  the retained (vertex and edge) unknowns and the three globals only; the bubble
  maps are kept to recover the bubbles' step;
- the scatter into the free-free CSR values of the retained block (its pattern is
  the linear section model's), the retained-global coupling and the 3 x 3 global block.

The lumen wall's cubic bubbles vanish on the wall, so its blocks touch the retained
unknowns and the globals only and are added after the condensation.

Tests: tests/fem/section_model/finite_strain/test_finite_strain_fast.py (equal to the
reference assembly's Newton path to its tolerance).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["assemble", "lumen"]

#: Compiled once and cached on disk; reassociation lets the loops vectorise (NaN and infinity
#: keep their meaning: an inverted or diverged state must be seen).
_JIT = {"cache": True, "error_model": "numpy", "fastmath": {"reassoc", "contract", "arcp"}}

#: Local unknowns of a triangle: 12 retained, 2 bubbles, 3 globals.
NR, NB, NL = 12, 14, 17
#: The five varying components of F as (row, column): 11, 12, 21, 22, 33.
_I5 = np.array([0, 0, 1, 1, 2])
_J5 = np.array([0, 1, 0, 1, 2])
#: The two in-plane rows of B's column per local unknown (the globals' values there are 0).
_ROWS_A = np.array([0, 2] * 7 + [0, 0, 0])
_ROWS_B = np.array([1, 3] * 7 + [1, 1, 1])


@njit(inline="always", **_JIT)
def _yeoh(f, c1, c2, c3, p5, a5, tangent, h, d) -> None:
    """Deviatoric Yeoh stress and tangent on the five components (volumetric part split off)."""
    f11, f12, f21, f22, f33 = f[0], f[1], f[2], f[3], f[4]
    det2 = f11 * f22 - f12 * f21
    j = det2 * f33
    # h: F^-T on the five components (cofactor / J); d: dI1bar/dF
    h[0], h[1], h[2], h[3], h[4] = f22 / det2, -f21 / det2, -f12 / det2, f11 / det2, 1.0 / f33
    i1 = f11 * f11 + f12 * f12 + f21 * f21 + f22 * f22 + f33 * f33
    jm = j ** (-2.0 / 3.0)
    x = jm * i1 - 3.0
    w1 = c1 + 2.0 * c2 * x + 3.0 * c3 * x * x
    w2 = 2.0 * c2 + 6.0 * c3 * x
    for a in range(5):
        d[a] = jm * (2.0 * f[a] - (2.0 / 3.0) * i1 * h[a])
        p5[a] = w1 * d[a]
    if not tangent:
        return
    c_hh = (4.0 / 9.0) * w1 * jm * i1
    c_sw = (2.0 / 3.0) * w1 * jm * i1
    c_fh = -(4.0 / 3.0) * w1 * jm
    for a in range(5):
        for b in range(5):
            # H boxtimes H: H[i_a, J_b] H[i_b, J_a] (zero across the in-plane / axial blocks)
            sw = _h_entry(h, _I5[a], _J5[b]) * _h_entry(h, _I5[b], _J5[a])
            a5[a, b] = c_hh * h[a] * h[b] + c_fh * (f[a] * h[b] + h[a] * f[b]) + w2 * d[a] * d[b] + c_sw * sw
        a5[a, a] += 2.0 * w1 * jm


@njit(inline="always", **_JIT)
def _h_entry(h, i, j) -> float:
    """Entry (i, j) of a 3 x 3 tensor stored on the five components (0 elsewhere)."""
    if i == 2 or j == 2:
        return h[4] if (i == 2 and j == 2) else 0.0
    return h[2 * i + j]


@njit(inline="always", **_JIT)
def _svk(f, c, p5, a5, tangent, ff, e, s_) -> None:
    """Saint Venant-Kirchhoff stress P = F S and tangent on the five components (``ff``, ``e``,
    ``s_``: 3 x 3 scratch, ``ff`` zero off the in-plane and axial blocks)."""
    ff[0, 0], ff[0, 1], ff[1, 0], ff[1, 1], ff[2, 2] = f[0], f[1], f[2], f[3], f[4]
    for i in range(3):
        for j in range(3):
            s = 0.0
            for a in range(3):
                s += ff[a, i] * ff[a, j]
            e[i, j] = 0.5 * (s - (1.0 if i == j else 0.0))
    for i in range(3):
        for j in range(3):
            t = 0.0
            for k in range(3):
                for m in range(3):
                    t += c[i, j, k, m] * e[k, m]
            s_[i, j] = t
    for a in range(5):
        i, jj = _I5[a], _J5[a]
        t = 0.0
        for m in range(3):
            t += ff[i, m] * s_[m, jj]
        p5[a] = t
        if not tangent:
            continue
        for b in range(5):
            k, ll = _I5[b], _J5[b]
            v = s_[jj, ll] if i == k else 0.0
            for m in range(3):
                if ff[i, m] != 0.0:
                    for q in range(3):
                        v += ff[i, m] * c[m, jj, ll, q] * ff[k, q]
            a5[a, b] = v


@njit(**_JIT)
def assemble(
    ue, g, w, gs, phi, xq, pq, minv, kind, yeoh, svk, silicone, given, use_given,
    slot_rr, rdof, tangent, data, k_ug, r_raw, r_cond, out_g, xb, kbi, xbr, pe, mg, stats,
):  # fmt: skip
    """Residual and condensed tangent of one state, scattered; per-triangle bubble and pressure data.

    Parameters (nel triangles, nq points, 7 scalar shape functions)
    ----------
    ue (nel, 14), g (3)
        Local in-plane unknowns and the globals (lambda, k_1, k_2).
    w (nel, nq), gs (nel, nq, 7, 2), phi (nq, 7), xq (nel, nq, 2)
        Weights, physical shape-function gradients, values, reference points.
    pq (nel, nq, 3), minv (nel, 3, 3)
        The P1 projection basis and its inverse Gram matrices.
    kind (nel,), yeoh (nel, 4), svk (nel, 3, 3, 3, 3), silicone (nel,)
        Law per triangle (0: Yeoh c1, c2, c3, bulk modulus, volume split; 1: SVK tensor);
        silicone triangles report their largest strain.
    given (nel, 3), use_given
        The mixed iteration's projected pressures (used in the tangent's geometric term).
    slot_rr (nel, 12, 12), rdof (nel, 12)
        Scatter of the retained block into the free-free CSR ``data``; retained unknowns.
    tangent
        Also the tangent (else the residual alone, condensed with the bubble maps ``xb`` and
        ``kbi`` of an earlier tangent: a modified Newton step's right-hand side).

    Outputs (zeroed by the caller): ``data``, ``k_ug`` (n, 3), ``r_raw``/``r_cond`` (n,) the
    retained residual before and after condensation, ``out_g`` (5, 3) the globals' residual
    before and after condensation (rows 0, 1) and their block (rows 2-4); the bubble maps
    ``xb`` (nel, 2, 15), the bubbles' inverse blocks ``kbi`` (nel, 2, 2) (both written with
    ``tangent``, read otherwise) and ``xbr`` (nel, 2) (bubbles' step = -(xbr + xb @ step));
    ``pe`` (nel, 3) the computed projected pressures
    and ``mg`` (nel, 3, 17) their derivative, ``stats`` = (min J, max strain, sum of the
    bubbles' squared residuals).
    """
    nel, nq = w.shape
    lam, k1, k2 = g[0], g[1], g[2]
    fq = np.empty((nq, 5))
    xx = np.empty((nq, 2))
    jq = np.empty(nq)
    st = np.empty(nq)
    p5 = np.empty(5)
    a5 = np.empty((5, 5))
    ra, rb = _ROWS_A, _ROWS_B
    va, vb, v4 = np.zeros(NL), np.zeros(NL), np.zeros(NL)
    ab = np.empty((5, NL))
    sh, sd = np.empty(5), np.empty(5)  # the laws' scratch
    sff, sgreen, sstress = np.zeros((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    ke = np.empty((NL, NL))
    re = np.empty(NL)
    gv = np.empty((3, NL))
    coef = np.empty(3)
    cof = np.empty(5)
    min_j, max_strain, rb2 = np.inf, 0.0, 0.0
    for e in range(nel):
        ke[:] = 0.0
        re[:] = 0.0
        gv[:] = 0.0
        for q in range(nq):
            d0 = d1 = d2 = d3 = 0.0
            x0, x1 = xq[e, q, 0], xq[e, q, 1]
            for s in range(7):
                u0, u1 = ue[e, 2 * s], ue[e, 2 * s + 1]
                d0 += u0 * gs[e, q, s, 0]
                d1 += u0 * gs[e, q, s, 1]
                d2 += u1 * gs[e, q, s, 0]
                d3 += u1 * gs[e, q, s, 1]
                x0 += u0 * phi[q, s]
                x1 += u1 * phi[q, s]
            stretch = 1.0 + k1 * x0 + k2 * x1
            fq[q, 0], fq[q, 1], fq[q, 2], fq[q, 3], fq[q, 4] = 1.0 + d0, d1, d2, 1.0 + d3, lam * stretch
            xx[q, 0], xx[q, 1] = x0, x1
            st[q] = stretch
            jq[q] = ((1.0 + d0) * (1.0 + d3) - d1 * d2) * lam * stretch
            min_j = min(min_j, jq[q], lam * stretch)
        if min_j <= 0.0:
            stats[0] = min_j
            return
        split = kind[e] == 0
        projected = pointwise = 0.0
        if split:
            c1 = yeoh[e, 0]
            projected = max(yeoh[e, 3] - 4.0 * c1 / 3.0, 0.0)
            pointwise = yeoh[e, 3] - projected
            for a in range(3):
                t = 0.0
                for q in range(nq):
                    t += w[e, q] * jq[q] * (minv[e, a, 0] * pq[e, q, 0] + minv[e, a, 1] * pq[e, q, 1]
                                            + minv[e, a, 2] * pq[e, q, 2])  # fmt: skip
                coef[a] = t
            coef[0] -= 1.0
            for a in range(3):
                pe[e, a] = projected * coef[a]
        for q in range(nq):
            f = fq[q]
            if split:
                _yeoh(f, yeoh[e, 0], yeoh[e, 1], yeoh[e, 2], p5, a5, tangent, sh, sd)
            else:
                _svk(f, svk[e], p5, a5, tangent, sff, sgreen, sstress)
            # B's column m: rows ra[m], rb[m] with values va[m], vb[m], and F33's row with v4[m]
            # ((s, 0) -> F11, F12; (s, 1) -> F21, F22; the globals -> F33 only)
            for s_ in range(7):
                g0, g1, ph = gs[e, q, s_, 0], gs[e, q, s_, 1], phi[q, s_]
                va[2 * s_], vb[2 * s_], v4[2 * s_] = g0, g1, lam * k1 * ph
                va[2 * s_ + 1], vb[2 * s_ + 1], v4[2 * s_ + 1] = g0, g1, lam * k2 * ph
            v4[NB], v4[NB + 1], v4[NB + 2] = st[q], lam * xx[q, 0], lam * xx[q, 1]
            wq = w[e, q]
            if split:
                j = jq[q]
                pbar = pointwise * (j - 1.0)
                pgeo = pbar
                for a in range(3):
                    pbar += projected * pq[e, q, a] * coef[a]
                    if use_given:
                        pgeo += pq[e, q, a] * given[e, a]
                if not use_given:
                    pgeo = pbar
                f11, f12, f21, f22, f33 = f[0], f[1], f[2], f[3], f[4]
                det2 = f11 * f22 - f12 * f21
                cof[0], cof[1], cof[2], cof[3], cof[4] = f22 * f33, -f21 * f33, -f12 * f33, f11 * f33, det2
                for a in range(5):
                    p5[a] += pbar * cof[a]
                if tangent:
                    for a in range(5):
                        for b in range(5):
                            swap = _h_entry(cof, _I5[a], _J5[b]) * _h_entry(cof, _I5[b], _J5[a])
                            a5[a, b] += pgeo * (cof[a] * cof[b] - swap) / j + pointwise * cof[a] * cof[b]
                # dJ/d(local) and its projection
                w0, w1_, w2_ = wq * pq[e, q, 0], wq * pq[e, q, 1], wq * pq[e, q, 2]
                for m in range(NL):
                    dj = cof[ra[m]] * va[m] + cof[rb[m]] * vb[m] + cof[4] * v4[m]
                    gv[0, m] += w0 * dj
                    gv[1, m] += w1_ * dj
                    gv[2, m] += w2_ * dj
            for m in range(NL):
                re[m] += wq * (p5[ra[m]] * va[m] + p5[rb[m]] * vb[m] + p5[4] * v4[m])
            if silicone[e]:
                f11, f12, f21, f22 = f[0], f[1], f[2], f[3]
                c11 = f11 * f11 + f21 * f21
                c22 = f12 * f12 + f22 * f22
                c12 = f11 * f12 + f21 * f22
                top = 0.5 * (c11 + c22) + np.sqrt(0.25 * (c11 - c22) ** 2 + c12 * c12)
                max_strain = max(max_strain, np.sqrt(max(top, f[4] * f[4])) - 1.0)
            if not tangent:
                continue
            for m in range(NL):  # A B, weighted
                am, bm, xa, xb_, x4 = ra[m], rb[m], wq * va[m], wq * vb[m], wq * v4[m]
                for a in range(5):
                    ab[a, m] = a5[a, am] * xa + a5[a, bm] * xb_ + a5[a, 4] * x4
            for m in range(NL):
                am, bm, xa, xb_, x4 = ra[m], rb[m], va[m], vb[m], v4[m]
                for n in range(m, NL):
                    ke[m, n] += xa * ab[am, n] + xb_ * ab[bm, n] + x4 * ab[4, n]
            # second derivatives of F33 = lambda (1 + k . x)
            t4 = wq * p5[4]
            for s_ in range(7):
                ph = phi[q, s_]
                ke[2 * s_, NB] += t4 * k1 * ph
                ke[2 * s_ + 1, NB] += t4 * k2 * ph
                ke[2 * s_, NB + 1] += t4 * lam * ph
                ke[2 * s_ + 1, NB + 2] += t4 * lam * ph
            ke[NB, NB + 1] += t4 * xx[q, 0]
            ke[NB, NB + 2] += t4 * xx[q, 1]
        if split:  # the projected pressures' derivative (and block: projected * gv^T Minv gv)
            for a in range(3):
                for m in range(NL):
                    t = 0.0
                    for b in range(3):
                        t += minv[e, a, b] * gv[b, m]
                    mg[e, a, m] = projected * t
        if tangent:
            for m in range(NL):
                for n in range(m):
                    ke[m, n] = ke[n, m]
            if split:
                for m in range(NL):
                    for n in range(NL):
                        t = 0.0
                        for a in range(3):
                            t += gv[a, m] * mg[e, a, n]
                        ke[m, n] += t
            # static condensation of the bubbles (local 12, 13); the element block is symmetric
            b00, b01, b10, b11 = ke[NR, NR], ke[NR, NR + 1], ke[NR + 1, NR], ke[NR + 1, NR + 1]
            det = b00 * b11 - b01 * b10
            kbi[e, 0, 0], kbi[e, 0, 1], kbi[e, 1, 0], kbi[e, 1, 1] = (
                b11 / det,
                -b01 / det,
                -b10 / det,
                b00 / det,
            )
            for m in range(15):
                col = m if m < NR else m + 2
                xb[e, 0, m] = kbi[e, 0, 0] * ke[NR, col] + kbi[e, 0, 1] * ke[NR + 1, col]
                xb[e, 1, m] = kbi[e, 1, 0] * ke[NR, col] + kbi[e, 1, 1] * ke[NR + 1, col]
        rb0, rb1 = re[NR], re[NR + 1]
        rb2 += rb0 * rb0 + rb1 * rb1
        xbr[e, 0] = kbi[e, 0, 0] * rb0 + kbi[e, 0, 1] * rb1
        xbr[e, 1] = kbi[e, 1, 0] * rb0 + kbi[e, 1, 1] * rb1
        for m in range(15):
            lm = m if m < NR else m + 2
            rc = re[lm] - (xb[e, 0, m] * rb0 + xb[e, 1, m] * rb1)
            if m < NR:
                r_raw[rdof[e, m]] += re[lm]
                r_cond[rdof[e, m]] += rc
            else:
                out_g[0, m - NR] += re[lm]
                out_g[1, m - NR] += rc
            if not tangent:
                continue
            kb0, kb1 = ke[lm, NR], ke[lm, NR + 1]
            for n in range(15):
                ln = n if n < NR else n + 2
                kc = ke[lm, ln] - (kb0 * xb[e, 0, n] + kb1 * xb[e, 1, n])
                if m < NR and n < NR:
                    slot = slot_rr[e, m, n]
                    if slot >= 0:
                        data[slot] += kc
                elif m < NR:
                    k_ug[rdof[e, m], n - NR] += kc
                elif n >= NR:
                    out_g[2 + m - NR, n - NR] += kc
    stats[0] = min_j
    stats[1] = max_strain
    stats[2] = rb2


@njit(**_JIT)
def lumen(ue, g, points, tangents, weights, lphi, ldphi, out_v, du, dug, duu) -> None:
    """The lumen's V' = lambda (a + k . s) and its derivatives (module ``lumen``'s formulas).

    ``ue`` (nf, 14) the wall edges' parent unknowns; ``points``, ``tangents`` (nf, nq, 2);
    ``weights`` (nf, nq) signed; ``lphi``, ``ldphi`` (nf, nq, 7) scalar shape functions and
    their derivatives along the edge. Outputs: ``out_v`` = (V', a, s_1, s_2), ``du`` (nf, 14),
    ``dug`` (nf, 14, 3), ``duu`` (nf, 14, 14).
    """
    nf, nq = weights.shape
    lam, k1, k2 = g[0], g[1], g[2]
    area = s1 = s2 = 0.0
    dgv = np.empty(4)
    d1 = np.empty(4)
    d2 = np.empty(4)
    h = np.zeros((4, 4))
    dbase = np.empty(NB)
    ds = np.empty((NB, 2))
    for f in range(nf):
        dbase[:] = 0.0
        ds[:] = 0.0
        for k in range(NB):
            for m in range(NB):
                duu[f, k, m] = 0.0
        for q in range(nq):
            X, Y = points[f, q, 0], points[f, q, 1]
            Xp, Yp = tangents[f, q, 0], tangents[f, q, 1]
            for s in range(7):
                X += lphi[f, q, s] * ue[f, 2 * s]
                Y += lphi[f, q, s] * ue[f, 2 * s + 1]
                Xp += ldphi[f, q, s] * ue[f, 2 * s]
                Yp += ldphi[f, q, s] * ue[f, 2 * s + 1]
            wq = weights[f, q]
            area += wq * 0.5 * (X * Yp - Y * Xp)
            s1 += wq * 0.5 * X * X * Yp
            s2 += wq * (-0.5) * Y * Y * Xp
            d1[0], d1[1], d1[2], d1[3] = X * Yp, 0.0, 0.0, 0.5 * X * X
            d2[0], d2[1], d2[2], d2[3] = 0.0, -Y * Xp, -0.5 * Y * Y, 0.0
            dgv[0] = 0.5 * Yp + k1 * d1[0]
            dgv[1] = -0.5 * Xp + k2 * d2[1]
            dgv[2] = -0.5 * Y + k2 * d2[2]
            dgv[3] = 0.5 * X + k1 * d1[3]
            h[0, 0] = k1 * Yp
            h[0, 3] = h[3, 0] = 0.5 + k1 * X
            h[1, 1] = -k2 * Xp
            h[1, 2] = h[2, 1] = -0.5 - k2 * Y
            for k in range(NB):
                c, s = k % 2, k // 2
                a, b = lphi[f, q, s], ldphi[f, q, s]
                dbase[k] += wq * (a * dgv[c] + b * dgv[2 + c])
                ds[k, 0] += wq * (a * d1[c] + b * d1[2 + c])
                ds[k, 1] += wq * (a * d2[c] + b * d2[2 + c])
                for m in range(NB):
                    cc, sm = m % 2, m // 2
                    a2, b2 = lphi[f, q, sm], ldphi[f, q, sm]
                    duu[f, k, m] += (
                        wq
                        * lam
                        * (
                            a * a2 * h[c, cc]
                            + a * b2 * h[c, 2 + cc]
                            + b * a2 * h[2 + c, cc]
                            + b * b2 * h[2 + c, 2 + cc]
                        )
                    )
        for k in range(NB):
            du[f, k] = lam * dbase[k]
            dug[f, k, 0] = dbase[k]
            dug[f, k, 1] = lam * ds[k, 0]
            dug[f, k, 2] = lam * ds[k, 1]
    base = area + k1 * s1 + k2 * s2
    out_v[0], out_v[1], out_v[2], out_v[3] = lam * base, area, s1, s2
