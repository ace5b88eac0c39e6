"""The morph's precomputed plan and vectorised checks against the straightforward morph.

``_straight_morph`` is the morph as first written (a loop over the curves with
:func:`numpy.interp`, per-point Jacobians): the fast morph must give its node positions
and midpoints to 1e-12 mm and raise its :class:`MorphError` on the same designs.
"""

from __future__ import annotations

import numpy as np
import pytest

from softcath.fem.adapter import geometry_from_design
from softcath.fem.mesh.gmsh_section import _p2_triangles_valid
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.template import (
    _CONIC,
    _ON_CURVE_MM,
    QUALITY_RATIO,
    MorphError,
    _curves,
    _intersect,
    _param,
    _point,
    _quality,
    _residual,
    morph,
    section_template,
)
from softcath.studies.sweep.random_designs import DEFAULT_RANGES, random_designs


def _straight_intersect(c1, c2, t0):
    t = t0.copy()
    for _ in range(30):
        x, y = _point(c1, t)
        kind1, _, _, a1, b1 = c1.T
        dx = np.where(kind1 == _CONIC, -a1 * np.sin(t), 0.0)
        dy = np.where(kind1 == _CONIC, b1 * np.cos(t), 1.0)
        kind2, xc2, yc2, a2, b2 = c2.T
        f = np.where(kind2 == _CONIC, ((x - xc2) / a2) ** 2 + ((y - yc2) / b2) ** 2 - 1.0, x - xc2)
        fx = np.where(kind2 == _CONIC, 2 * (x - xc2) / a2**2, 1.0)
        fy = np.where(kind2 == _CONIC, 2 * (y - yc2) / b2**2, 0.0)
        step = f / np.where(np.abs(fx * dx + fy * dy) > 1e-300, fx * dx + fy * dy, 1e-300)
        t = t - step
        if np.abs(step).max() < 1e-15:
            break
    return _point(c1, t)


def _straight_p2_valid(x6):
    e1, e2 = x6[:, 1] - x6[:, 0], x6[:, 2] - x6[:, 0]
    lin = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    ok = np.ones(len(x6), bool)
    for r, s in [(0, 0), (1, 0), (0, 1), (0.5, 0), (0.5, 0.5), (0, 0.5), (1 / 3, 1 / 3)]:
        lam = 1 - r - s
        dr = np.array([1 - 4 * lam, 4 * r - 1, 0, 4 * (lam - r), 4 * s, -4 * s])
        ds = np.array([1 - 4 * lam, 0, 4 * s - 1, -4 * r, 4 * r, 4 * (lam - s)])
        jr, js = np.einsum("k,mkd->md", dr, x6), np.einsum("k,mkd->md", ds, x6)
        ok &= (jr[:, 0] * js[:, 1] - jr[:, 1] * js[:, 0]) * np.sign(lin) > 0.05 * np.abs(lin)
    return ok


def _straight_curve_nodes(t, new_params):
    params, old = t.params, t.curves
    for c, nodes, corner, free, order in t.curve_plan:
        t_old, ta = params[nodes, c], params[corner, c][order]
        if old[c, 0] == _CONIC:
            if corner.size == 0:
                continue
            shift = np.angle(np.exp(1j * (new_params[corner, c][order] - ta)))
            delta = np.interp(t_old, ta, shift, period=2 * np.pi)
            new_params[nodes[free], c] = t_old[free] + delta[free]
        else:
            if corner.size < 2:
                raise MorphError("template", c, "a land line needs two corners")
            new_params[nodes[free], c] = np.interp(t_old[free], ta, new_params[corner, c][order])


def _straight_check(t, g, xy, mids):
    m = t.mesh
    ratio = _quality(xy, m.triangles) / t.quality
    if not (np.isfinite(ratio).all() and ratio.min() >= QUALITY_RATIO):
        raise MorphError("morph.quality_ratio", float(np.nanmin(ratio)), f"must be >= {QUALITY_RATIO}")
    t3 = m.triangles[t.bent_triangles]
    x6 = np.concatenate([xy[t3], 0.5 * (xy[t3] + xy[t3[:, [1, 2, 0]]])], axis=1)
    which = t.triangle_curved_edge[t.bent_triangles]
    x6[:, 3:][which >= 0] = mids[which[which >= 0]]
    valid = _straight_p2_valid(x6)
    if not valid.all():
        raise MorphError("morph.p2_jacobian", int((~valid).sum()), "curved triangles folded")
    cen = xy[m.triangles].mean(axis=1)
    bad = int((g.classify(cen[:, 0], cen[:, 1], np.zeros(len(cen))) != m.labels).sum())
    if bad:
        raise MorphError("morph.labels", bad, "triangles changed region; must be 0")


def _straight_morph(t, g):
    """(points, midpoints) of the morph as first written, or its MorphError."""
    m, params, new = t.mesh, t.params, _curves(g)
    new_params = params.copy()
    c1, c2, k = t.corner_curves[:, 0], t.corner_curves[:, 1], t.corners
    cx, cy = _straight_intersect(new[c1], new[c2], params[k, c1])
    miss = np.maximum(np.abs(_residual(new[c1], cx, cy)), np.abs(_residual(new[c2], cx, cy)))
    if not (np.isfinite(miss).all() and miss.max() < _ON_CURVE_MM):
        raise MorphError("geometry", g.digest(), "a region corner of the template has no counterpart")
    new_params[k, c1], new_params[k, c2] = _param(new[c1], cx, cy), _param(new[c2], cx, cy)
    _straight_curve_nodes(t, new_params)
    xy, b = m.points.copy(), t.boundary
    first = np.argmax(t.on_curve, axis=1)
    xy[b, 0], xy[b, 1] = _point(new[first[b]], new_params[b, first[b]])
    xy[k, 0], xy[k, 1] = cx, cy
    xy[t.interior] = m.points[t.interior] - t.laplace_ii.solve(t.laplace_ib @ (xy[b] - m.points[b]))
    ce, ec = m.curved_edges, t.edge_curve
    ta, tb = new_params[ce[:, 0], ec], new_params[ce[:, 1], ec]
    span = np.where(new[ec, 0] == _CONIC, np.angle(np.exp(1j * (tb - ta))), tb - ta)
    mids = np.column_stack(_point(new[ec], ta + t.edge_frac * span))
    _straight_check(t, g, xy, mids)
    return xy, mids


def _outcome(fn, t, g):
    try:
        got = fn(t, g)
    except MorphError as exc:
        return exc.args[0].split(" = ")[0]  # the parameter the error names
    return got if isinstance(got, tuple) else (got.points, got.curved_midpoints)


def _pairs():
    """(template geometry, geometry): own templates, and other designs' (many refused)."""
    wide = dict(DEFAULT_RANGES)
    wide.update({"tube.a_int": (0.03, 0.2), "tube.b_int": (0.02, 0.12), "coil.outer_diameter": (0.6, 1.2)})
    designs = random_designs(30, seed=8) + random_designs(50, seed=5, ranges=wide)
    gs = [geometry_from_design(d) for d in designs]
    rng = np.random.default_rng(3)
    return [(g, g) for g in gs] + [(gs[int(rng.integers(len(gs)))], g) for g in gs]


@pytest.mark.parametrize("which", ["own", "other"])
def test_fast_morph_equals_the_straightforward_morph(which):
    pairs = _pairs()
    pairs = pairs[: len(pairs) // 2] if which == "own" else pairs[len(pairs) // 2 :]
    outcomes = []
    for tg, g in pairs:
        t = section_template(tg, mesh_size=MESH_SIZE, segments=SEGMENTS)
        fast, straight = _outcome(morph, t, g), _outcome(_straight_morph, t, g)
        outcomes.append(straight if isinstance(straight, str) else "ok")
        if isinstance(straight, str):
            assert fast == straight
        else:
            assert not isinstance(fast, str), fast
            np.testing.assert_allclose(fast[0], straight[0], rtol=0, atol=1e-12)
            np.testing.assert_allclose(fast[1], straight[1], rtol=0, atol=1e-12)
    # Every outcome is exercised: own templates refuse 2 wide designs by their labels; other
    # designs' templates refuse 50 of 80, by quality and (2) by folded curved triangles.
    assert outcomes.count("ok") > 10
    if which == "own":
        assert outcomes.count("morph.labels") >= 1
    else:
        assert outcomes.count("morph.quality_ratio") > 5 and outcomes.count("morph.p2_jacobian") >= 1


def test_p2_validity_equals_the_pointwise_check():
    rng = np.random.default_rng(2)
    x6 = rng.normal(size=(4000, 6, 2))
    x6[:2000, :3] = [[0, 0], [1, 0], [0, 1]]  # straight corners, midsides anywhere: both answers occur
    x6[:2000, 3:] = 0.5 * (x6[:2000, :3] + x6[:2000, [1, 2, 0]]) + 0.2 * rng.normal(size=(2000, 3, 2))
    got, want = _p2_triangles_valid(x6), _straight_p2_valid(x6)
    np.testing.assert_array_equal(got, want)
    assert 100 < got.sum() < 3900
    assert _p2_triangles_valid(np.zeros((0, 6, 2))).shape == (0,)


def test_intersections_equal_newton_and_a_miss_is_nan():
    rng = np.random.default_rng(4)
    rows1, rows2, t0 = [], [], []
    for _ in range(200):  # a land line or a circle, on an ellipse, from near the root's side
        a, b, yc = rng.uniform(0.1, 0.5), rng.uniform(0.1, 0.5), rng.uniform(-0.2, 0.2)
        x = a * rng.uniform(-0.9, 0.9)
        side = rng.choice([-1.0, 1.0])
        y = yc + side * b * np.sqrt(1 - (x / a) ** 2)
        rows2.append((_CONIC, 0.0, yc, a, b))
        if rng.random() < 0.5:
            rows1.append((1, x, 0.0, 1.0, 1.0))  # the land line x = const, parameter y
            t0.append(y + rng.normal(0, 0.02))
        else:  # a circle through (x, y) centred off the ellipse's centre, parameter its angle
            r = rng.uniform(0.2, 0.6)
            ang = rng.uniform(-np.pi, np.pi)
            rows1.append((_CONIC, x - r * np.cos(ang), y - r * np.sin(ang), r, r))
            t0.append(ang + rng.normal(0, 0.02))
    c1, c2, t0 = np.array(rows1), np.array(rows2), np.array(t0)
    got, want = np.column_stack(_intersect(c1, c2, t0)), np.column_stack(_straight_intersect(c1, c2, t0))
    ok = np.abs(_residual(c2, *want.T)) < 1e-12  # where the straightforward Newton converged
    assert ok.sum() > 150
    np.testing.assert_allclose(got[ok], want[ok], rtol=0, atol=1e-12)
    miss = np.array([[1, 2.0, 0.0, 1.0, 1.0]]), np.array([[_CONIC, 0.0, 0.0, 0.5, 0.5]])
    assert np.isnan(_intersect(*miss, np.array([0.1]))[1]).all()
