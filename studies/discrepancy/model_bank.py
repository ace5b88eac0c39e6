r"""The finite-strain curves a prototype's hypotheses are built from, each solved once.

A hypothesis's prediction at the measured pressures is made of

- a **finite-strain section curve** (the tier valid past 5 deg) of one model
  variant of the design — tube modulus, filler or none, silicone Poisson ratio —
  solved on one pressure grid from 0 to the largest measured pressure and
  interpolated (linearly; the grid's 24 steps put the interpolation error
  below 1e-4 of the curve's span on the paper design). A tube modulus or an
  outer-coil spring rate between the three grid values of its range (the ends
  and their geometric mean) interpolates the curvature linearly in its log
  (multilinearly when both are free);
- with the coils' **initial tension** F0, the finite-strain model with
  coil-bound coils (``section_curve(coil_bound=True)``: coil-bound in
  compression, closed up to F0 in tension) at five F0 evenly over the sourced
  range. F0 mostly shifts the curve to higher pressure (the threshold at which
  the turns open grows in proportion to F0 in the linear model), so between two
  grid values a and b (weight w on b) the curve is interpolated along that
  shift, in the pressure at equal curvature rise above the rest state:
  :math:`p(\Delta\kappa) = (1-w)\,p_a(\Delta\kappa) + w\,p_b(\Delta\kappa)`, the
  elongation likewise. Past the rise b reaches on the grid, b is a moved right
  by their pressure difference at b's top (b closed throughout: the nearest
  lower pair's difference per newton, else the linear bilinear model's
  threshold per newton, times the F0 step). Measured on the paper design
  (24-step grid to 0.5 MPa), a midpoint F0 against its direct solve: within
  0.84 % of the curve's span at the grid pressures, 1.4 % between them (where
  the opening's kink falls between grid pressures; 1.1 % at a grid F0 itself).
  The linear model's fallback is coarser: with the grid only to 0.15 MPa (every
  F0 > 0 closed throughout) it is 10 % above the finite-strain threshold per
  newton, and a midpoint F0 is within 16 % of its (small) span.

The tube's pre-stretch is a continuous model parameter too (its range from 1 to the
design's catalogue/as-built wall-area ratio, :func:`.ingredients.tube_prestretch_for`), on
a grid of six values dense near 1; a pre-stretched variant's curve starts at its rest
curvature (absolute curvature). The tube's squeeze (:func:`.ingredients.tube_squeeze_for`, a share
in [0, 1]) likewise, on the grid 0, 1/8, 1/4, 1/2, 1 and interpolated linearly in the share (its
range starts at 0; the rest bend grows nearly in proportion to it: -0.108, -0.224, -0.347 mm^-1 at
0.1, 0.2, 0.3 on the paper design; a share between grid values within 1.5 % of the curve's span
of its direct solve, measured at 0.0625 and 0.2); a variant with both the squeeze and the
pre-stretch has no curve (the squeeze carries its own axial stretch), nor one whose rest state is
not reached (the paper design's stalls at 0.56 with the open coil).
"""

from __future__ import annotations

import logging
import multiprocessing
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, replace

import numpy as np

from softcath.design import coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.section_model.bilinear import bend_curve
from softcath.fem.section_model.finite_strain import SectionConvergenceError
from softcath.models.section_nonlinear import SECTION_NONLINEAR
from softcath.studies.discrepancy.ingredients import INGREDIENTS, tube_prestretch_for, tube_squeeze_for

__all__ = ["Variant", "ModelBank", "MODEL_PARAMETERS", "TENSION"]

#: The continuous parameters that change the finite-strain solve (interpolated in their logs, the
#: squeeze, whose range starts at 0, linearly).
MODEL_PARAMETERS = ("tube_modulus", "coil_spring_rate", "tube_prestretch", "tube_squeeze")
#: The parameters interpolated linearly rather than in their logs.
_LINEAR = ("tube_squeeze",)
#: The coils' initial tension: a finite-strain solve with coil-bound coils (interpolated along the shift).
TENSION = "coil_initial_tension"

log = logging.getLogger(__name__)

_GRID_STEPS = 24
#: Inner points of the pre-stretch grid, as shares of its range (1.018, 1.073, 1.146, 1.29 for the paper).
_PRESTRETCH_STEPS = (0.01, 0.04, 0.08, 0.16)
#: Inner points of the squeeze grid, as shares of its range.
_SQUEEZE_STEPS = (0.125, 0.25, 0.5)
#: Initial tensions of the grid (the range's ends included; the module docstring's measured accuracy).
_TENSION_POINTS = 5
#: Share of the lower curve's rise above which a curvature level counts in matching the shift (the
#: closed coil's creep below the opening is ~1e-4 of it).
_LEVEL_SHARE = 0.01


@dataclass(frozen=True)
class Variant:
    """One finite-strain model of the design: tube modulus [MPa], filler removed, silicone nu,
    the outer coil's axial spring rate [N/m] (None: the design's own), the tube's pre-stretch, the
    outer coil's initial tension [N] (None: coils without coil-bound law, the default model) and
    the tube's squeeze (0: none)."""

    tube_modulus: float
    filler_none: bool = False
    silicone_poisson: float | None = None
    coil_spring_rate: float | None = None
    tube_prestretch: float = 1.0
    coil_initial_tension: float | None = None
    tube_squeeze: float = 0.0


@dataclass(frozen=True)
class _Curve:
    pressure: np.ndarray
    curvature: np.ndarray
    elongation: np.ndarray
    reached: float  # the highest pressure solved (the curve stops there if Newton failed)


class ModelBank:
    """Finite-strain curves of one design's variants, solved on demand.

    Parameters
    ----------
    design
        The built design.
    p_max
        Largest pressure a prediction needs [MPa].
    load
        The model load (``"lumen"``: the real one).
    ranges
        Parameter ranges other than the ingredients' sourced ones (to ask what the data would need).
    """

    def __init__(
        self,
        design,
        *,
        p_max: float,
        load: str = "lumen",
        ranges: dict[str, tuple[float, float]] | None = None,
    ) -> None:
        self.design = design
        prestretch = tube_prestretch_for(design)
        squeeze = tube_squeeze_for(design)
        self.ranges = {
            "tube_prestretch": (prestretch.low, prestretch.high),
            "tube_squeeze": (squeeze.low, squeeze.high),
            **(ranges or {}),
        }
        self.load = load
        self.grid = np.linspace(0.0, float(p_max), _GRID_STEPS + 1)
        self._curves: dict[Variant, _Curve] = {}
        self._shifts: dict[tuple[Variant, Variant], float | None] = {}
        self.notes: list[str] = []

    @property
    def nominal_modulus(self) -> float:
        return float(self.design.tube.material.youngs_modulus)

    def variant_design(self, v: Variant):
        """The design of variant ``v``."""
        return variant_design(self.design, v)

    @property
    def nominal_spring_rate(self) -> float:
        """The outer coil's axial spring rate in the homogenised model [N/m]: E_t A / L."""
        return nominal_spring_rate(self.design)

    def curve(self, v: Variant) -> _Curve:
        """The finite-strain curve of ``v`` on the grid (solved once)."""
        if v not in self._curves:
            self._store(v, *solve_variant(self.design, self.grid, self.load, v))
        return self._curves[v]

    def _store(self, v: Variant, curve: _Curve, note: str | None) -> None:
        self._curves[v] = curve
        if note:
            self.notes.append(note)

    def solve(self, variants, *, workers: int = 1, progress: bool = False) -> None:
        """Solve the curves of ``variants`` not solved yet, in ``workers`` processes."""
        from tqdm import tqdm

        todo = [v for v in dict.fromkeys(variants) if v not in self._curves]
        bar = tqdm(total=len(todo), desc="finite-strain variants", unit="curve", disable=not progress)
        with bar:
            if workers <= 1 or len(todo) < 2:
                for v in todo:
                    self.curve(v)
                    bar.update(1)
                return
            ctx = multiprocessing.get_context("spawn")  # a fresh interpreter: no inherited BLAS threads
            with ProcessPoolExecutor(max_workers=min(workers, len(todo)), mp_context=ctx) as pool:
                futures = {pool.submit(solve_variant, self.design, self.grid, self.load, v): v for v in todo}
                for fut in as_completed(futures):
                    self._store(futures[fut], *fut.result())
                    bar.update(1)

    def variants_for(self, ingredients) -> list[Variant]:
        """The grid variants a hypothesis with ``ingredients`` interpolates between."""
        filler_none = "filler_none" in ingredients
        nu = 0.4999 if "nu_0.4999" in ingredients else None
        corners: list[dict[str, float]] = [{}]
        for n in (*MODEL_PARAMETERS, TENSION):
            if n in ingredients:
                corners = [{**c, n: g} for c in corners for g in self.grid_of(n)]
        return [self._variant(c, filler_none, nu) for c in corners]

    def _variant(self, corner: dict[str, float], filler_none: bool, nu) -> Variant:
        """The variant at a grid ``corner`` of the continuous model parameters (absent: the design's)."""
        return Variant(
            tube_modulus=corner.get("tube_modulus", self.nominal_modulus),
            filler_none=filler_none,
            silicone_poisson=nu,
            coil_spring_rate=corner.get("coil_spring_rate"),
            tube_prestretch=corner.get("tube_prestretch", 1.0),
            coil_initial_tension=corner.get(TENSION),
            tube_squeeze=corner.get("tube_squeeze", 0.0),
        )

    def at(self, v: Variant, pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(curvature, elongation) of ``v`` at ``pressure`` (0 below 0, NaN past the solved curve)."""
        c = self.curve(v)
        q = np.clip(pressure, 0.0, None)
        k = np.interp(q, c.pressure, c.curvature)
        e = np.interp(q, c.pressure, c.elongation)
        beyond = q > c.reached + 1e-12
        k[beyond] = np.nan
        e[beyond] = np.nan
        return k, e

    def ingredient(self, name: str):
        """The ingredient ``name`` as this design has it (its range and source)."""
        own = {"tube_prestretch": tube_prestretch_for, "tube_squeeze": tube_squeeze_for}
        return own[name](self.design) if name in own else INGREDIENTS[name]

    def range_of(self, parameter: str) -> tuple[float, float]:
        """The range a hypothesis may choose ``parameter`` in (the sourced one unless overridden)."""
        ing = INGREDIENTS[parameter]
        return self.ranges.get(parameter, (ing.low, ing.high))

    def grid_of(self, parameter: str) -> tuple[float, ...]:
        """The values of a continuous model parameter a hypothesis interpolates between: its range
        ends and their geometric mean; the tube's pre-stretch on a grid dense near 1 (its rest bend
        grows fast and not in proportion to log lambda: a 3-point grid put 40 % into it at 1.08)."""
        lo, hi = self.range_of(parameter)
        if parameter == "tube_prestretch":
            return (lo, *(float(lo + (hi - lo) * s) for s in _PRESTRETCH_STEPS), hi)
        if parameter == "tube_squeeze":
            return (lo, *(float(lo + (hi - lo) * s) for s in _SQUEEZE_STEPS), hi)
        if parameter == TENSION:  # from 0: evenly, not in the log
            return tuple(float(v) for v in np.linspace(lo, hi, _TENSION_POINTS))
        return (lo, float(np.sqrt(lo * hi)), hi)

    def at_values(self, values: dict[str, float], filler_none: bool, nu, pressure):
        """(curvature, elongation) with continuous model parameters ``values`` (``tube_modulus``,
        ``coil_spring_rate``, ``tube_prestretch``, ``tube_squeeze``; absent ones at the design's own),
        multilinear in their logs (the squeeze in itself); with ``coil_initial_tension`` the
        coil-bound model's curves, interpolated along their pressure shift (module docstring)."""
        names = [n for n in MODEL_PARAMETERS if n in values]
        corners: list[tuple[float, dict[str, float]]] = [(1.0, {})]
        for n in names:
            grid = self.grid_of(n)
            axis = np.asarray(grid, float) if n in _LINEAR else np.log(grid)
            x = float(np.clip(values[n] if n in _LINEAR else np.log(values[n]), axis[0], axis[-1]))
            i = min(int(np.searchsorted(axis, x, side="right")) - 1, len(grid) - 2)
            w = (x - axis[i]) / (axis[i + 1] - axis[i])
            corners = [
                (cw * ww, {**cv, n: g})
                for cw, cv in corners
                for ww, g in ((1 - w, grid[i]), (w, grid[i + 1]))
            ]
        k = np.zeros(np.shape(pressure))
        e = np.zeros(np.shape(pressure))
        for weight, corner in corners:
            if weight == 0.0:
                continue
            v = self._variant(corner, filler_none, nu)
            if TENSION in values:
                kc, ec = self._at_tension(v, float(values[TENSION]), pressure)
            else:
                kc, ec = self.at(v, pressure)
            k = k + weight * kc
            e = e + weight * ec
        return k, e

    def _at_tension(self, v: Variant, force: float, pressure) -> tuple[np.ndarray, np.ndarray]:
        """(curvature, elongation) of ``v`` with coil-bound coils at initial tension ``force`` [N]."""
        grid = self.grid_of(TENSION)
        x = float(np.clip(force, grid[0], grid[-1]))
        i = min(int(np.searchsorted(grid, x, side="right")) - 1, len(grid) - 2)
        w = (x - grid[i]) / (grid[i + 1] - grid[i])
        va, vb = (replace(v, coil_initial_tension=grid[j]) for j in (i, i + 1))
        if w == 0.0:
            return self.at(va, pressure)
        return _blend(self.curve(va), self.curve(vb), w, self.shift(v, i), np.asarray(pressure, float))

    def shift(self, v: Variant, i: int) -> float:
        """Pressure [MPa] by which the curve at the ``i + 1``-th grid F0 lies right of the ``i``-th's
        at the higher curve's largest rise (where it stays closed: the fallback of the shift).

        Where the higher curve stays closed over the whole grid, the nearest lower pair's shift
        per newton times this F0 step (the threshold's growth with F0 slows at finite strain), and
        with no such pair the linear bilinear model's threshold per newton.
        """
        grid = self.grid_of(TENSION)
        for j in range(i, -1, -1):
            matched = self._matched_shift(*(replace(v, coil_initial_tension=grid[n]) for n in (j, j + 1)))
            if matched is not None:
                return matched * (grid[i + 1] - grid[i]) / (grid[j + 1] - grid[j])
        return (grid[i + 1] - grid[i]) * self.threshold_per_newton(v)

    def _matched_shift(self, va: Variant, vb: Variant) -> float | None:
        """The shift of ``vb``'s curve right of ``va``'s at ``vb``'s largest rise (None: it stays closed)."""
        key = (va, vb)
        if key not in self._shifts:
            a, b = _Levels(self.curve(va)), _Levels(self.curve(vb))
            self._shifts[key] = None
            if b.top > _LEVEL_SHARE * a.top and a.top > 0:
                level = min(b.top, a.top)
                self._shifts[key] = float(b.pressure_at(level) - a.pressure_at(level))
        return self._shifts[key]

    def threshold_per_newton(self, v: Variant) -> float:
        """The linear bilinear model's threshold pressure per newton of initial tension [MPa/N]."""
        force = 0.01  # any: the threshold is proportional to F0
        b = bend_curve(
            self.variant_design(v),
            [0.1],
            load=self.load,
            coil_model="annulus",
            initial_tension=(force, self.design.channel.initial_tension),
            silicone_poisson=v.silicone_poisson,
        )
        return float(b.threshold_pressure / force)


class _Levels:
    """A solved curve as pressure against its curvature rise (above the rest state)."""

    def __init__(self, c: _Curve) -> None:
        self.curve = c
        self.rise = np.maximum.accumulate(c.curvature - c.curvature[0])  # monotone for the inverse
        self.top = float(self.rise[-1])

    def pressure_at(self, level):
        return np.interp(level, self.rise, self.curve.pressure)

    def elongation_at(self, level):
        return np.interp(self.pressure_at(level), self.curve.pressure, self.curve.elongation)


def _blend(a: _Curve, b: _Curve, w: float, shift: float, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Curvature and elongation at pressures ``q`` between curves ``a`` (weight 1 - w) and ``b``,
    interpolated along the pressure at equal curvature rise; past ``b``'s largest rise, ``b`` is
    ``a`` moved right by ``shift`` [MPa] (the rise beyond ``a``'s: NaN, past the solved curves)."""
    la, lb = _Levels(a), _Levels(b)
    if not la.top > 0:  # no rise to match (a curve that does not bend up): linear in F0
        ka, kb = (np.interp(q, c.pressure, c.curvature, right=np.nan) for c in (a, b))
        ea, eb = (np.interp(q, c.pressure, c.elongation, right=np.nan) for c in (a, b))
        return (1 - w) * ka + w * kb, (1 - w) * ea + w * eb
    # b's own levels up to its top rise, unless it stays closed (its creep only): then all shifted
    cut = lb.top if lb.top > _LEVEL_SHARE * la.top else 0.0
    levels = np.unique(np.concatenate([la.rise, lb.rise[lb.rise <= min(cut, la.top)]]))
    p_a, e_a = la.pressure_at(levels), la.elongation_at(levels)
    beyond = levels > cut
    p_b = np.where(beyond, p_a + shift, lb.pressure_at(levels))
    # b's elongation past its top: a's, offset to meet b there
    e_b = np.where(beyond, e_a + (lb.elongation_at(cut) - la.elongation_at(cut)), lb.elongation_at(levels))
    p_f = np.maximum.accumulate((1 - w) * p_a + w * p_b)  # np.interp needs it ordered
    rest = (1 - w) * a.curvature[0] + w * b.curvature[0]
    qc = np.clip(q, 0.0, None)
    k = rest + np.interp(qc, p_f, levels, right=np.nan)
    e = np.interp(qc, p_f, (1 - w) * e_a + w * e_b, right=np.nan)
    return k, e


def variant_design(design, v: Variant):
    """The design of variant ``v`` of ``design`` (its tube modulus, without filler if asked, its
    outer coil's initial tension)."""
    mat = replace(design.tube.material, youngs_modulus=v.tube_modulus)
    d = replace(design, tube=replace(design.tube, material=mat))
    if v.coil_initial_tension is not None:
        try:  # the coil's own bounds (close-wound, wound-in stress) stand for the variant
            d = replace(d, coil=replace(d.coil, initial_tension=float(v.coil_initial_tension)))
        except DesignError as exc:
            raise DesignError("coil_initial_tension", v.coil_initial_tension, exc.bound) from None
    return replace(d, filler=None) if v.filler_none else d


def nominal_spring_rate(design) -> float:
    """The outer coil's axial spring rate in the homogenised model [N/m]: E_t A / L."""
    k = coil_stiffness(design.coil)
    return float(k.axial_modulus_tension * k.area / design.tip.bending_length * 1e3)


def solve_variant(design, grid: np.ndarray, load: str, v: Variant) -> tuple[_Curve, str | None]:
    """The finite-strain curve of variant ``v`` on ``grid`` and a note if Newton stopped short.

    Solved by the ``section-nonlinear`` tier (its mesher and mesh size the defaults, those of
    :func:`~softcath.fem.section_model.finite_strain.section_curve`); the outer coil's spring
    rate is its ``coil_axial_scale`` relative to the design's :func:`nominal_spring_rate`; an
    initial tension solves with the tier's ``coil_bound`` option and F0 in the variant's design.
    """
    d = variant_design(design, v)
    nan = np.full(1, np.nan)
    if v.tube_prestretch != 1.0 and not d.assembly.is_default:  # the model's pre-stretch: bonded tips
        return _Curve(np.zeros(1), nan, nan, reached=-1.0), f"{v}: no pre-stretch for a tip as built"
    if v.tube_squeeze != 0.0 and not d.assembly.is_default:  # likewise the squeeze
        return _Curve(np.zeros(1), nan, nan, reached=-1.0), f"{v}: no squeeze for a tip as built"
    if v.tube_squeeze != 0.0 and v.tube_prestretch != 1.0:  # the squeeze carries its own axial stretch
        return _Curve(np.zeros(1), nan, nan, reached=-1.0), f"{v}: no squeeze with a pre-stretch"
    options = {
        "silicone_poisson": v.silicone_poisson,
        "coil_axial_scale": None
        if v.coil_spring_rate is None
        else float(v.coil_spring_rate) / nominal_spring_rate(design),
        "tube_prestretch": v.tube_prestretch,
        "tube_squeeze": v.tube_squeeze,
        "coil_bound": v.coil_initial_tension is not None,  # F0: the variant design's own
    }
    batch = SECTION_NONLINEAR.responses([d], grid, loads=(load,), options=options)[load]
    exc = batch.errors.get(0)
    note = None
    if exc is not None:
        if not isinstance(exc, SectionConvergenceError):
            raise exc
        if 0 not in batch.partial:  # the pre-stretched rest state itself was not reached: no prediction
            return _Curve(np.zeros(1), nan, nan, reached=-1.0), f"{v}: no rest state ({exc})"
    r = batch.partial_response(0)
    solved = np.isfinite(r.curvature_per_mm)  # the grid's first part: the pressures the walk reached
    pressure = np.asarray(r.pressures)[solved]
    if exc is not None:
        note = f"{v}: the finite-strain model stops at {pressure[-1]:.3g} MPa ({exc})"
    curve = _Curve(
        pressure=pressure,
        curvature=np.asarray(r.curvature_per_mm)[solved],
        elongation=np.asarray(r.elongation)[solved],
        reached=float(pressure[-1]) if pressure.size else 0.0,
    )
    return curve, note
