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
- the **coil-bound transfer** of the coils' initial tension F0: the linear
  section model with bilinear coils (coil-bound in compression, closed up to
  F0 in tension; ``softcath.fem.section_model.bilinear``) gives
  :math:`\varphi(p/F_0) = \kappa_\text{bilinear}(p; F_0) / (g_\text{linear}\,p)`,
  the share of the homogenised response the closed coil lets through. That law
  is positively homogeneous in (p, F0) jointly, so one table per variant
  serves every F0; the finite-strain curve is multiplied by it (exact in the
  small-strain limit).

The tube's pre-stretch is a continuous model parameter too (its range from 1 to the
design's catalogue/as-built wall-area ratio, :func:`.ingredients.tube_prestretch_for`), on
a grid of six values dense near 1; a pre-stretched variant's curve starts at its rest
curvature (absolute curvature).
"""

from __future__ import annotations

import logging
import multiprocessing
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, replace

import numpy as np

from softcath.design import coil_stiffness
from softcath.fem.section_model.bilinear import bend_curve
from softcath.fem.section_model.finite_strain import SectionConvergenceError
from softcath.models.section_nonlinear import SECTION_NONLINEAR
from softcath.studies.discrepancy.ingredients import INGREDIENTS, tube_prestretch_for

__all__ = ["Variant", "ModelBank", "TRANSFER_FORCE", "MODEL_PARAMETERS"]

#: The continuous parameters that change the finite-strain solve (interpolated on a grid).
MODEL_PARAMETERS = ("tube_modulus", "coil_spring_rate", "tube_prestretch")

log = logging.getLogger(__name__)

#: Initial tension [N] of the transfer table (any F0 follows by homogeneity).
TRANSFER_FORCE = 0.05
_GRID_STEPS = 24
#: Inner points of the pre-stretch grid, as shares of its range (1.018, 1.073, 1.146, 1.29 for the paper).
_PRESTRETCH_STEPS = (0.01, 0.04, 0.08, 0.16)
#: Points of the transfer table (log-spaced, 4.6 % apart: the opening's kink is resolved to ~1 %).
_TRANSFER_POINTS = 241


@dataclass(frozen=True)
class Variant:
    """One finite-strain model of the design: tube modulus [MPa], filler removed, silicone nu,
    the outer coil's axial spring rate [N/m] (None: the design's own) and the tube's pre-stretch."""

    tube_modulus: float
    filler_none: bool = False
    silicone_poisson: float | None = None
    coil_spring_rate: float | None = None
    tube_prestretch: float = 1.0


@dataclass(frozen=True)
class _Curve:
    pressure: np.ndarray
    curvature: np.ndarray
    elongation: np.ndarray
    reached: float  # the highest pressure solved (the curve stops there if Newton failed)


class ModelBank:
    """Finite-strain curves and coil-bound transfers of one design's variants, solved on demand.

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
        self.ranges = {"tube_prestretch": (prestretch.low, prestretch.high), **(ranges or {})}
        self.load = load
        self.grid = np.linspace(0.0, float(p_max), _GRID_STEPS + 1)
        self._curves: dict[Variant, _Curve] = {}
        self._transfers: dict[Variant, tuple[np.ndarray, np.ndarray, float]] = {}
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
        for n in MODEL_PARAMETERS:
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
        return tube_prestretch_for(self.design) if name == "tube_prestretch" else INGREDIENTS[name]

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
        return (lo, float(np.sqrt(lo * hi)), hi)

    def at_values(self, values: dict[str, float], filler_none: bool, nu, pressure):
        """(curvature, elongation) with continuous model parameters ``values`` (``tube_modulus``,
        ``coil_spring_rate``, ``tube_prestretch``; absent ones at the design's own), multilinear in
        their logs."""
        names = [n for n in MODEL_PARAMETERS if n in values]
        corners: list[tuple[float, dict[str, float]]] = [(1.0, {})]
        for n in names:
            grid = self.grid_of(n)
            x = float(np.clip(np.log(values[n]), np.log(grid[0]), np.log(grid[-1])))
            i = min(int(np.searchsorted(np.log(grid), x, side="right")) - 1, len(grid) - 2)
            w = (x - np.log(grid[i])) / (np.log(grid[i + 1]) - np.log(grid[i]))
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
            kc, ec = self.at(self._variant(corner, filler_none, nu), pressure)
            k = k + weight * kc
            e = e + weight * ec
        return k, e

    def transfer(self, v: Variant) -> tuple[np.ndarray, np.ndarray, float]:
        """(pressures at F0 = :data:`TRANSFER_FORCE`, phi there, phi's large-pressure limit) of ``v``."""
        if v not in self._transfers:
            p = np.geomspace(1e-3, 50.0, _TRANSFER_POINTS)
            b = bend_curve(
                self.variant_design(v),
                p,
                load=self.load,
                coil_model="annulus",
                initial_tension=(TRANSFER_FORCE, 0.0),
                silicone_poisson=v.silicone_poisson,
            )
            phi = np.asarray(b.curvature) / (b.gain_linear * p)
            self._transfers[v] = (p, phi, float(b.gain_pivoting / b.gain_linear))
        return self._transfers[v]

    def coil_bound_share(self, v: Variant, pressure: np.ndarray, initial_tension: float) -> np.ndarray:
        """phi: the share of the homogenised curvature a coil with ``initial_tension`` lets through."""
        p_tab, phi, limit = self.transfer(v)
        q = np.clip(np.asarray(pressure, float), 0.0, None)
        if initial_tension <= 0:
            return np.full(q.shape, limit)
        s = q * TRANSFER_FORCE / initial_tension  # the same state at the table's F0
        # interpolate the curvature (phi s: zero, then nearly linear), not the ratio, across the kink
        ks = np.interp(s, p_tab, phi * p_tab, right=np.nan)
        out = np.where(s > p_tab[-1], limit, ks / np.clip(s, p_tab[0], None))
        return np.where(s < p_tab[0], 0.0, out)


def variant_design(design, v: Variant):
    """The design of variant ``v`` of ``design`` (its tube modulus, without filler if asked)."""
    mat = replace(design.tube.material, youngs_modulus=v.tube_modulus)
    d = replace(design, tube=replace(design.tube, material=mat))
    return replace(d, filler=None) if v.filler_none else d


def nominal_spring_rate(design) -> float:
    """The outer coil's axial spring rate in the homogenised model [N/m]: E_t A / L."""
    k = coil_stiffness(design.coil)
    return float(k.axial_modulus_tension * k.area / design.tip.bending_length * 1e3)


def solve_variant(design, grid: np.ndarray, load: str, v: Variant) -> tuple[_Curve, str | None]:
    """The finite-strain curve of variant ``v`` on ``grid`` and a note if Newton stopped short.

    Solved by the ``section-nonlinear`` tier (its mesher and mesh size the defaults, those of
    :func:`~softcath.fem.section_model.finite_strain.section_curve`); the outer coil's spring
    rate is its ``coil_axial_scale`` relative to the design's :func:`nominal_spring_rate`.
    """
    d = variant_design(design, v)
    nan = np.full(1, np.nan)
    if v.tube_prestretch != 1.0 and not d.assembly.is_default:  # the model's pre-stretch: bonded tips
        return _Curve(np.zeros(1), nan, nan, reached=-1.0), f"{v}: no pre-stretch for a tip as built"
    options = {
        "silicone_poisson": v.silicone_poisson,
        "coil_axial_scale": None
        if v.coil_spring_rate is None
        else float(v.coil_spring_rate) / nominal_spring_rate(design),
        "tube_prestretch": v.tube_prestretch,
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
