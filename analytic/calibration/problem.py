"""The eq. 8 problem: the shape domain X, the data's sufficient statistics, one start as a CasADi block.

Decision variables are the free subset of x = [a, a_int, b_int, h] (mm), scaled by
the coil's inner radius R (order one). The block of one start gives the weighted
objective and the containment residuals (c <= 0) of the sampled lumen-in-wall
constraint (see :mod:`softcath.analytic.calibration`).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np

from softcath.analytic.section import design_inputs, section_arrays
from softcath.core.errors import DataError, DesignError
from softcath.design import TipDesign
from softcath.design.measurement import Measurement
from softcath.design.section import check_shape, max_outer_semi_axis

__all__ = [
    "SHAPE_KEYS",
    "MIN_LUMEN_SEMI_AXIS",
    "N_CONTAINMENT",
    "FitData",
    "ShapeProblem",
    "fit_data",
    "build_problem",
    "multistart",
]

SHAPE_KEYS = ("a", "a_int", "b_int", "h")
MIN_LUMEN_SEMI_AXIS = 0.01  # mm
N_CONTAINMENT = 41


@dataclass(frozen=True)
class FitData:
    """The measured series reduced to what eq. 8 needs: sums over samples, and the weights.

    ``eps`` is None when elongation is not fitted (no arc length, or not asked for).
    """

    p: np.ndarray
    kap: np.ndarray
    eps: np.ndarray | None
    s_pp: float
    s_pe: float
    s_ee: float
    s_pk: float
    s_kk: float
    w_e: float
    w_k: float

    @property
    def stats(self) -> list[float]:
        """The Opti parameter ``stats``: S_pp, S_pe, S_ee, S_pk, S_kk."""
        return [self.s_pp, self.s_pe, self.s_ee, self.s_pk, self.s_kk]

    @property
    def weights(self) -> list[float]:
        """The Opti parameter ``w``: w_e, w_k."""
        return [self.w_e, self.w_k]


def fit_data(
    measurement: Measurement,
    design: TipDesign,
    *,
    weights: tuple[float, float] | None,
    use_elongation: bool,
) -> FitData:
    """Sufficient statistics and weights of a measurement (see :func:`calibrate` for the parameters)."""
    p = np.asarray(measurement.pressure_MPa, float)
    kap = np.asarray(measurement.curvature_per_mm, float)
    eps = measurement.elongation(design.tip.bending_length) if use_elongation else None
    if eps is not None and not np.all(np.isfinite(eps)):
        raise DataError(
            f"{measurement.source}: column arc_length_mm has missing values; cannot fit elongation"
        )
    s_pp = float(p @ p)
    if s_pp == 0:
        raise DataError(f"{measurement.source}: column pressure_MPa is zero everywhere; nothing to calibrate")
    s_pk, s_kk = _sufficient_statistics(p, kap)
    s_pe, s_ee = _sufficient_statistics(p, eps)
    if weights is None:
        w_k = 1.0 / s_kk if s_kk > 0 else 0.0
        w_e = 1.0 / s_ee if eps is not None and s_ee > 0 else 0.0
    else:
        w_e, w_k = (float(w) for w in weights)
        if eps is None:
            w_e = 0.0
    if w_k == 0 and w_e == 0:
        raise DataError(f"{measurement.source}: curvature and elongation are zero everywhere; nothing to fit")
    return FitData(
        p=p, kap=kap, eps=eps, s_pp=s_pp, s_pe=s_pe, s_ee=s_ee, s_pk=s_pk, s_kk=s_kk, w_e=w_e, w_k=w_k
    )


def _sufficient_statistics(p: np.ndarray, y: np.ndarray | None) -> tuple[float, float]:
    if y is None:
        return 0.0, 0.0
    return float(p @ y), float(y @ y)


@dataclass(frozen=True)
class ShapeProblem:
    """One start of eq. 8 as CasADi functions of the scaled free shape z = x / R.

    Attributes
    ----------
    free
        The free shape keys (order of z).
    r_in
        The scale R, mm (the coil's inner radius).
    lo_z, hi_z
        Bounds of z (the box of X).
    block
        ``(z, stats, w, fixed, scale) -> (objective, containment residuals)``.
    gain_fn
        ``(z, fixed, scale) -> (curvature gain, elongation gain)`` per MPa.
    jac_fn
        ``(z, fixed, scale) -> d(gains)/dz`` (2 x len(free)).
    """

    free: tuple[str, ...]
    r_in: float
    lo_z: np.ndarray
    hi_z: np.ndarray
    block: Any
    gain_fn: Any
    jac_fn: Any


def build_problem(ca, design: TipDesign, free: tuple[str, ...], load: str) -> ShapeProblem:
    """The CasADi block of one start: objective and containment residuals (c <= 0)."""
    bounds = _bounds(design)
    const = _constants(design, load)
    r_in = const["r_in"]
    b, t = design.vertical_semi_axis, design.tube.min_wall
    zc = ca.SX.sym("z", len(free))  # x / R: order one
    stats = ca.SX.sym("stats", 5)  # S_pp, S_pe, S_ee, S_pk, S_kk
    w = ca.SX.sym("w", 2)  # w_e, w_k
    fixed = ca.SX.sym("fixed", 4)  # shape values used for non-free entries
    fs = ca.SX.sym("scale", 2)  # f_kappa, f_eps: the model's gains over the formula's
    x_sym = {k: (zc[free.index(k)] * r_in if k in free else fixed[i]) for i, k in enumerate(SHAPE_KEYS)}
    g_k0, g_e0 = _symbolic_gains(ca, x_sym, const)
    g_k, g_e = fs[0] * g_k0, fs[1] * g_e0
    obj = w[0] * (g_e**2 * stats[0] - 2 * g_e * stats[1] + stats[2]) + w[1] * (
        g_k**2 * stats[0] - 2 * g_k * stats[3] + stats[4]
    )
    s_grid = np.linspace(-1.0, 1.0, N_CONTAINMENT)
    margin = (s_grid[1] - s_grid[0]) ** 2 / 4
    am, bm = x_sym["a"] - t, b - t
    s_col = ca.DM(s_grid)
    lhs = x_sym["a_int"] ** 2 * (1 - s_col**2) * bm**2 + (x_sym["h"] + x_sym["b_int"] * s_col) ** 2 * am**2
    residual = (lhs - (1 - margin) * am**2 * bm**2) / r_in**4
    return ShapeProblem(
        free=free,
        r_in=r_in,
        lo_z=np.array([bounds[k][0] for k in free]) / r_in,
        hi_z=np.array([bounds[k][1] for k in free]) / r_in,
        block=ca.Function("calibration_block", [zc, stats, w, fixed, fs], [obj, residual]),
        gain_fn=ca.Function("shape_gains", [zc, fixed, fs], [g_k, g_e]),
        jac_fn=ca.Function("J", [zc, fixed, fs], [ca.jacobian(ca.vertcat(g_k, g_e), zc)]),
    )


def multistart(design: TipDesign, free: tuple[str, ...], grid: int, r_in: float) -> list[np.ndarray]:
    """Scaled starts: a grid over X (feasible interior points only) and the nominal shape."""
    x_nom = dict(design.tube_shape)
    bounds = _bounds(design)
    axes = []
    for k in free:
        lo, hi = bounds[k]
        axes.append(lo + (hi - lo) * (np.arange(grid) + 0.5) / grid)
    starts = []
    for combo in itertools.product(*axes):
        shape = dict(x_nom)
        shape.update(dict(zip(free, combo, strict=True)))
        if _inside(design, shape, margin=1e-9):
            starts.append(np.array(combo) / r_in)
    if _inside(design, x_nom, margin=1e-9):
        starts.append(np.array([x_nom[k] for k in free]) / r_in)
    if not starts:
        raise DesignError("free", free, "no feasible multistart point: the fixed shape values leave X empty")
    return starts


def _symbolic_gains(ca, x: dict, const: dict):
    """κ/p and ε/p as CasADi expressions of the tube shape (same algebra as analytic.section)."""
    a, a_int, b_int, h = x["a"], x["a_int"], x["b_int"], x["h"]
    pi = np.pi
    b, y_t, r_in, r_c, y_c = const["b"], const["y_t"], const["r_in"], const["r_c"], const["y_c"]
    e_t, e_f = const["tube_E"], const["filler_E"]
    y_l = y_t + h
    # tube: ellipse(a, b, y_t) − ellipse(a_int, b_int, y_l); moments about y = 0
    A_t = pi * (a * b - a_int * b_int)
    Q_t = pi * (a * b * y_t - a_int * b_int * y_l)
    I_t = pi * (a * b**3 / 4 + a * b * y_t**2) - pi * (a_int * b_int**3 / 4 + a_int * b_int * y_l**2)
    # filler: disc(r_in) − ellipse(a, b, y_t) − disc(r_c, y_c)
    A_f = pi * r_in**2 - pi * a * b - pi * r_c**2
    Q_f = -pi * a * b * y_t - pi * r_c**2 * y_c
    I_f = pi * r_in**4 / 4 - pi * (a * b**3 / 4 + a * b * y_t**2) - pi * (r_c**4 / 4 + r_c**2 * y_c**2)
    s_ea = const["EA_coils"] + e_t * A_t + e_f * A_f
    s_eq = const["EQ_coils"] + e_t * Q_t + e_f * Q_f
    s_ei0 = const["EI0_coils"] + e_t * I_t + e_f * I_f
    ybar = s_eq / s_ea
    ei = s_ei0 - 2 * ybar * s_eq + ybar**2 * s_ea
    ap = pi * a_int * b_int
    factor = const["load_factor"]
    return factor * ap * (y_l - ybar) / ei, factor * ap / s_ea


def _constants(design: TipDesign, load: str) -> dict[str, float]:
    inp = design_inputs(design)
    s = section_arrays(inp)
    r_in = design.coil.inner_diameter / 2
    r_c = design.channel.outer_diameter / 2
    ybar = float(s["neutral_axis_y"])
    coils_ea = float(s["EA_coil"] + s["EA_channel"])
    y_c = -(r_in - r_c)
    coils_eq = float(s["EA_channel"]) * y_c
    # EI of the coils about y = 0: recover from their EI about ȳ (parallel axis back-shift)
    coils_ei0 = float(s["EI_coil"] + s["EI_channel"]) + 2 * ybar * coils_eq - ybar**2 * coils_ea
    return {
        "b": float(s["b"]),
        "y_t": float(s["tube_centre_y"]),
        "r_in": r_in,
        "r_c": r_c,
        "y_c": y_c,
        "tube_E": inp["tube_E"],
        "filler_E": inp["filler_E"],
        "EA_coils": coils_ea,
        "EQ_coils": coils_eq,
        "EI0_coils": coils_ei0,
        "load_factor": 1.0 if load == "cap" else 1.0 - 2.0 * inp["tube_nu"],
    }


def _bounds(design: TipDesign) -> dict[str, tuple[float, float]]:
    r_in = design.coil.inner_diameter / 2
    b = design.vertical_semi_axis
    t = design.tube.min_wall
    lo = MIN_LUMEN_SEMI_AXIS
    a_max = max_outer_semi_axis(coil_inner_radius=r_in, b=b)
    if a_max - t < lo or b - t < lo:
        raise DesignError("tube.min_wall", t, "leaves no room for a lumen of semi-axis >= 0.01 mm")
    h_max = b - t - lo
    return {
        "a": (t + lo, a_max),
        "a_int": (lo, a_max - t),
        "b_int": (lo, b - t),
        "h": (-h_max, h_max),
    }


def _inside(design: TipDesign, shape: dict[str, float], margin: float = 0.0) -> bool:
    """Whether ``shape`` lies in X (exact containment test of design.section)."""
    b, t = design.vertical_semi_axis, design.tube.min_wall
    lo = MIN_LUMEN_SEMI_AXIS
    if shape["a_int"] < lo - 1e-15 or shape["b_int"] < lo - 1e-15:
        return False
    try:
        check_shape(coil_inner_radius=design.coil.inner_diameter / 2, b=b, shape=shape, min_wall=t + margin)
    except DesignError:
        return False
    return True
