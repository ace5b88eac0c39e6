r"""The paper's cross-section shape optimisation (eq. 8), in CasADi (Opti + IPOPT).

Decision variables: the free subset of x = [a, a_int, b_int, h] (mm), scaled
by the coil's inner radius R so they are of order one; b is fixed by the
assembly. The geometric domain X is explicit:

- outer ellipse inside the coil: a ≤ √(R b) (a simple bound, exact; see
  :func:`softcath.design.section.max_outer_semi_axis`);
- lumen inside the outer ellipse shrunk by the minimum wall t: sampled at
  N = 41 values of s = sin φ on [−1, 1], each
  a_int²(1 − s²)(b − t)² + (h + b_int s)²(a − t)² ≤ (1 − m)(a − t)²(b − t)²,
  where the margin m = Δs²/4 bounds the quadratic's excursion between samples,
  so the sampled constraints imply the exact one;
- lumen semi-axes ≥ 0.01 mm (a lumen must exist);
- tangency to coil and channel holds by construction (b and the tube centre).

Objective (eq. 8): w_ε Σ(ε(x) p_k − ε_k)² + w_κ Σ(κ(x) p_k − κ_k)², where ε(x),
κ(x) are the gains per MPa of eqs. 4 and 7. The model is linear in p, so the
sums reduce to five sufficient statistics (S_pp, S_pε, S_εε, S_pκ, S_κκ),
passed as Opti *parameters*: the cost of a solve does not grow with the
series. Default weights w = 1/Σy² make both terms relative.

Multistart from a grid over X (as the paper does); the result reports how
many starts reached the best objective. All starts are solved in one IPOPT
run: the Opti problem stacks the starts as columns of a decision matrix and
sums their (independent) objectives, so each column converges to its own
local optimum while the solver's set-up cost is paid once (falls back to one
start at a time if the batch fails). With two measured gains and four
free shape numbers the optimum is a 2-D family, not a point: the tie among
optimal starts is broken toward the nominal shape, and the result says
whether x is identifiable (rank of ∂(gains)/∂x). Fix parameters (``free``)
to make it identifiable. If no x in X reaches the data's gains, the result
says so and returns the best constrained fit; it never returns an x outside X.
"""

from __future__ import annotations

import itertools
import logging
from dataclasses import dataclass

import numpy as np

from softcath.analytic.beam import gains_arrays
from softcath.analytic.data_gain import data_gain
from softcath.analytic.section import design_inputs, section_arrays
from softcath.design import TipDesign
from softcath.design.errors import DataError, DesignError
from softcath.design.measurement import Measurement
from softcath.design.section import check_shape, max_outer_semi_axis

__all__ = ["CalibrationResult", "calibrate", "nrmse", "SHAPE_KEYS", "MIN_LUMEN_SEMI_AXIS"]

log = logging.getLogger(__name__)

SHAPE_KEYS = ("a", "a_int", "b_int", "h")
MIN_LUMEN_SEMI_AXIS = 0.01  # mm
N_CONTAINMENT = 41
IPOPT_OPTIONS = {
    # no "expand": the per-start block is already an SX Function, mapped over the starts; expanding
    # the Opti graph to SX costs more to build (70 ms) than it saves in evaluation
    "expand": False,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.tol": 1e-12,
    "ipopt.acceptable_tol": 1e-10,
    "ipopt.max_iter": 300,
    # honour the bounds of X exactly: IPOPT relaxes them by 1e-8 by default
    "ipopt.bound_relax_factor": 0.0,
}


def nrmse(model: np.ndarray, data: np.ndarray) -> float:
    """Root-mean-square error normalised by the data's range (max − min)."""
    data = np.asarray(data, float)
    span = float(np.ptp(data))
    if span == 0:
        raise DataError("nrmse: the data series is constant; its range is zero")
    return float(np.sqrt(np.mean((np.asarray(model, float) - data) ** 2)) / span)


@dataclass(frozen=True, kw_only=True)
class CalibrationResult:
    """Outcome of :func:`calibrate` (mm, MPa).

    Attributes
    ----------
    x_opt, x_nominal
        Shape {a, a_int, b_int, h} after and before.
    free
        The shape parameters that were optimised.
    objective
        Eq. 8 objective at the optimum (weighted, relative).
    nrmse_nominal, nrmse_optimized
        Curvature NRMSE (range-normalised) of the nominal and optimised model.
    ratio
        nrmse_nominal / nrmse_optimized (the paper reports 20.1371).
    nrmse_elongation_nominal, nrmse_elongation_optimized
        The same for elongation, or None without arc-length data.
    gains_data, gains_model
        Least-squares gains of the data and the optimised model's gains:
        ``{"curvature_per_mm_per_MPa", "elongation_per_MPa"}``.
    gain_data_stderr, gain_data_method, gain_data_by_group
        Standard error of the data's curvature gain from the spread of per-run
        (or per-block) gains, how the groups were formed, and each group's gain
        (``softcath.analytic.data_gain``).
    reachable
        False when the model family cannot reach the data's gains inside X.
    identifiable
        True when the data determine the free parameters (locally).
    starts, starts_at_optimum
        Multistart starts tried and how many reached the best objective.
    message
        A plain statement of the outcome.
    design
        The calibrated design (the input design with x_opt as its tube shape).
    """

    x_opt: dict[str, float]
    x_nominal: dict[str, float]
    free: tuple[str, ...]
    objective: float
    nrmse_nominal: float
    nrmse_optimized: float
    ratio: float
    nrmse_elongation_nominal: float | None
    nrmse_elongation_optimized: float | None
    gains_data: dict[str, float | None]
    gains_model: dict[str, float]
    reachable: bool
    identifiable: bool
    starts: int
    starts_at_optimum: int
    message: str
    design: TipDesign
    gain_data_stderr: float | None = None
    gain_data_method: str = ""
    gain_data_by_group: dict[str, float] | None = None

    def to_json(self) -> dict:
        """The JSON document ``softcath calibrate`` writes."""
        return {
            "x_opt": self.x_opt,
            "x_nominal": self.x_nominal,
            "free": list(self.free),
            "nrmse_nominal": self.nrmse_nominal,
            "nrmse_optimized": self.nrmse_optimized,
            "ratio": self.ratio,
            "nrmse_elongation_nominal": self.nrmse_elongation_nominal,
            "nrmse_elongation_optimized": self.nrmse_elongation_optimized,
            "objective": self.objective,
            "starts": self.starts,
            "starts_at_optimum": self.starts_at_optimum,
            "gains_data": self.gains_data,
            "gains_model": self.gains_model,
            "reachable": self.reachable,
            "identifiable": self.identifiable,
            "message": self.message,
            "gain_data_uncertainty": {
                "curvature_per_mm_per_MPa_stderr": self.gain_data_stderr,
                "method": self.gain_data_method,
                "by_group": self.gain_data_by_group,
            },
            "units": {"x_opt": "mm", "gains": "per MPa"},
        }


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


def _sufficient_statistics(p: np.ndarray, y: np.ndarray | None) -> tuple[float, float]:
    if y is None:
        return 0.0, 0.0
    return float(p @ y), float(y @ y)


def calibrate(
    measurement: Measurement,
    design: TipDesign,
    *,
    free: tuple[str, ...] = SHAPE_KEYS,
    load: str = "cap",
    weights: tuple[float, float] | None = None,
    grid: int = 3,
    use_elongation: bool = True,
    gain_scale: tuple[float, float] = (1.0, 1.0),
) -> CalibrationResult:
    """Fit the tube shape x to a measured series (paper eq. 8).

    Parameters
    ----------
    measurement
        Pressure, curvature and (optionally) arc length over time; elongation is
        arc_length / L0 − 1 with L0 the design's bending length.
    design
        The design whose tube shape is calibrated; its current shape is the nominal one.
    free
        Which of ``("a", "a_int", "b_int", "h")`` to optimise; the others stay at the design's value.
    load
        ``"cap"`` (the paper's model) or ``"lumen"``.
    weights
        (w_ε, w_κ); default (1/Σε², 1/Σκ²), i.e. relative errors.
    grid
        Grid points per free parameter for the multistart (interior points of X).
    use_elongation
        Fit elongation too when the measurement has arc length.
    gain_scale
        (f_κ, f_ε): the model's gains are the formula's times these factors
        (Opti parameters, so a new scale costs no rebuild of the problem's
        expressions). A model whose gains differ from the formula's by
        slowly varying factors (the section model) is fitted by iterating
        on them (:func:`softcath.fem.section_model.calibration.calibrate_section`).
        All reported gains and NRMSEs include the scale.
    """
    import casadi as ca

    free = tuple(free)
    bad = [k for k in free if k not in SHAPE_KEYS]
    if bad or not free or len(set(free)) != len(free):
        raise DesignError("free", free, f"must be distinct names from {SHAPE_KEYS}")
    if not isinstance(grid, int) or not 1 <= grid <= 9:
        raise DesignError("grid", grid, "must be an integer in [1, 9]")
    if load not in ("cap", "lumen"):
        raise DesignError("load", load, "must be cap or lumen")
    factors = tuple(float(f) for f in gain_scale)
    if len(factors) != 2 or not all(np.isfinite(f) and f > 0 for f in factors):
        raise DesignError("gain_scale", gain_scale, "must be two finite factors > 0 (curvature, elongation)")

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

    x_nom = dict(design.tube_shape)
    bounds = _bounds(design)
    const = _constants(design, load)
    r_in = const["r_in"]
    b, t = design.vertical_semi_axis, design.tube.min_wall

    # --- one start as a CasADi block: objective and containment residuals (c <= 0) ---------
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
    block = ca.Function("calibration_block", [zc, stats, w, fixed, fs], [obj, residual])
    gain_fn = ca.Function("shape_gains", [zc, fixed, fs], [g_k, g_e])
    lo_z = np.array([bounds[k][0] for k in free]) / r_in
    hi_z = np.array([bounds[k][1] for k in free]) / r_in

    p_stats = [s_pp, s_pe, s_ee, s_pk, s_kk]
    p_w = [w_e, w_k]
    p_fixed = [x_nom[k] for k in SHAPE_KEYS]

    # --- multistart grid over X (feasible interior points only) -------------------
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

    def opti_solver(n: int):
        """Opti over n independent starts at once: the objective is a sum of separate blocks, so
        its KKT points are each block's own; one IPOPT run pays the solver overhead once."""
        opti = ca.Opti()
        z = opti.variable(len(free), n)
        st, wp, fx, sc = opti.parameter(5), opti.parameter(2), opti.parameter(4), opti.parameter(2)
        objs, res = block.map(n)(z, st, wp, fx, sc)
        opti.minimize(ca.sum2(objs))
        opti.subject_to(opti.bounded(ca.repmat(ca.DM(lo_z), 1, n), z, ca.repmat(ca.DM(hi_z), 1, n)))
        opti.subject_to(ca.vec(res) <= 0)
        opti.solver("ipopt", IPOPT_OPTIONS)
        return opti.to_function("calibrate_shape", [z, st, wp, fx, sc], [z])

    def solve_all(z0s: list[np.ndarray]) -> list[np.ndarray | None]:
        try:
            z_opt = np.asarray(
                opti_solver(len(z0s))(np.column_stack(z0s), p_stats, p_w, p_fixed, factors), float
            )
            return [z_opt[:, j] for j in range(len(z0s))]
        except RuntimeError as exc:  # the batch failed: solve the starts one by one
            if len(z0s) == 1:
                log.info("calibration start %s failed: %s", z0s[0], exc)
                return [None]
            single = opti_solver(1)
            out = []
            for z0 in z0s:
                try:
                    out.append(np.asarray(single(z0, p_stats, p_w, p_fixed, factors), float).ravel())
                except RuntimeError as exc1:
                    log.info("calibration start %s failed: %s", z0, exc1)
                    out.append(None)
            return out

    results = []
    for z_opt in solve_all(starts):
        if z_opt is None:
            continue
        shape = dict(x_nom)
        shape.update({k: float(v * r_in) for k, v in zip(free, z_opt, strict=True)})
        if not _inside(design, shape):
            continue  # never return an x outside X
        f_opt = float(block(z_opt, p_stats, p_w, p_fixed, factors)[0])
        results.append((f_opt, shape, z_opt))
    if not results:
        raise DesignError("free", free, "every multistart solve failed; the data may be degenerate")

    best_f = min(r[0] for r in results)
    tol = 1e-7 * max(1.0, abs(best_f)) + 1e-12
    optimal = [r for r in results if r[0] <= best_f + tol]
    scale = np.array([max(abs(x_nom[k]), 0.01) for k in free])
    z_nom = np.array([x_nom[k] for k in free]) / r_in

    def distance(r):
        return float(np.sum(((r[2] - z_nom) * r_in / scale) ** 2))

    f_opt, x_opt, z_best = min(optimal, key=distance)

    # --- diagnostics -----------------------------------------------------------------
    g_k_opt, g_e_opt = (float(v) for v in gain_fn(z_best, p_fixed, factors))
    g_k_nom, g_e_nom = (
        float(v) * f for v, f in zip(gains_arrays(design_inputs(design), load), factors, strict=True)
    )
    n_obs = int(w_k > 0) + int(w_e > 0)
    jac = ca.Function("J", [zc, fixed, fs], [ca.jacobian(ca.vertcat(g_k, g_e), zc)])
    jac = np.asarray(jac(z_best, p_fixed, factors))
    rows = [0] if w_e == 0 else ([1] if w_k == 0 else [0, 1])
    rank = int(np.linalg.matrix_rank(jac[rows, :] / np.maximum(np.abs(jac[rows, :]).max(), 1e-300), tol=1e-8))
    identifiable = rank == len(free) and len(free) <= n_obs
    data_gk = s_pk / s_pp
    data_ge = s_pe / s_pp if eps is not None else None
    miss_k = abs(g_k_opt - data_gk) / max(abs(data_gk), 1e-300) if w_k > 0 else 0.0
    miss_e = abs(g_e_opt - data_ge) / max(abs(data_ge), 1e-300) if w_e > 0 and data_ge else 0.0
    reachable = max(miss_k, miss_e) <= 1e-3
    nr_nom = nrmse(g_k_nom * p, kap)
    nr_opt = nrmse(g_k_opt * p, kap)
    nre_nom = nre_opt = None
    if eps is not None and np.ptp(eps) > 0:
        nre_nom, nre_opt = nrmse(g_e_nom * p, eps), nrmse(g_e_opt * p, eps)
    if reachable:
        msg = (
            f"fit reaches the data's gains (curvature {g_k_opt:.5g} vs {data_gk:.5g} 1/(mm MPa)); "
            f"{len(optimal)} of {len(results)} starts reached the best objective"
        )
    else:
        msg = (
            f"the shape family cannot reach the data's gains inside X: curvature gain "
            f"{g_k_opt:.5g} vs data {data_gk:.5g} 1/(mm MPa) ({100 * miss_k:.2g} % short)"
            + (f", elongation {g_e_opt:.5g} vs {data_ge:.5g} 1/MPa ({100 * miss_e:.2g} %)" if w_e > 0 else "")
            + "; this is the best constrained fit"
        )
    dg = data_gain(measurement)
    msg += "; " + dg.describe()
    if not identifiable:
        msg += (
            f"; x is not identifiable from {n_obs} gain(s) with {len(free)} free parameter(s): "
            "the optimum is a family, reported at the point closest to the nominal shape"
        )
    return CalibrationResult(
        x_opt=x_opt,
        x_nominal=x_nom,
        free=free,
        objective=f_opt,
        nrmse_nominal=nr_nom,
        nrmse_optimized=nr_opt,
        ratio=nr_nom / nr_opt if nr_opt > 0 else float("inf"),
        nrmse_elongation_nominal=nre_nom,
        nrmse_elongation_optimized=nre_opt,
        gains_data={"curvature_per_mm_per_MPa": data_gk, "elongation_per_MPa": data_ge},
        gains_model={"curvature_per_mm_per_MPa": g_k_opt, "elongation_per_MPa": g_e_opt},
        reachable=reachable,
        identifiable=identifiable,
        starts=len(starts),
        starts_at_optimum=len(optimal),
        message=msg,
        design=design.with_tube_shape(**x_opt),
        gain_data_stderr=dg.stderr,
        gain_data_method=dg.method,
        gain_data_by_group=dg.by_group,
    )


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
