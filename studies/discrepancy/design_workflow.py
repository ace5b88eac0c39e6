"""The missing-effect workflow over a design sweep: which physics does the paper's formula lack?

A sweep that holds, per design and load, the paper's formula (the analytic
curvature) and a reference curvature (the 3-D FEM) is explained ingredient by
ingredient. Each candidate is a switch of the section model
(:mod:`softcath.fem.section_model`), so a named ingredient is a physical statement:

``coil_homogenisation``
    The coils bend as their homogenised annuli (the FEM's coils), not with the
    helical-spring (Wahl) EI the formula gives them.
``poisson_mismatch``
    The real Poisson ratios, bonded: silicone (nu ~ 0.49) against steel (0.29)
    stiffens the section axially and in bending (the formula has nu = 0).
``confinement``
    The lumen-wall pressure acting on the near-incompressible silicone that the
    coil's hoop boxes in (lumen-load rows only; it brings the real nu along).
    The one-material (1 - 2 nu) form of this load has the wrong sign inside a
    coil, so the ingredient takes it from the section model.
``end_effects``
    What the 3-D tip has and a section does not (clamp and cap zones): a
    correction (1 + c D/L) with c fitted on the training designs.

Method (as the time-series workflow): split the designs into training and
held-out sets (seeded); at each step fit every remaining candidate on the
training designs, score it on the held-out ones by the gap, the median of
``|reference/model - 1|``; name the best only if it shrinks the held-out gap by
more than the margin, add it, and iterate. Parameter-free physics is weighed first; the fitted
``end_effects`` only for what no physics candidate explains. Candidates within the margin of the
named one are reported as ``ambiguous_with``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath import analytic
from softcath.design.errors import DataError
from softcath.models import LOADS
from softcath.models import responses as tier_responses
from softcath.studies.sweep.results import read_results
from softcath.studies.sweep.variants import build_variant

__all__ = ["INGREDIENTS", "DesignCase", "DesignWorkflowResult", "load_sweep_cases", "run_design_workflow"]

log = logging.getLogger(__name__)

INGREDIENTS = ("coil_homogenisation", "poisson_mismatch", "confinement", "end_effects")
#: The 3-D FEM caps silicone at nu = 0.49 (displacement-only P2); the section model mirrors it.
FEM_POISSON_CAP = 0.49


@dataclass(frozen=True)
class DesignCase:
    """One design under one load: the reference and formula gains (kappa/p, 1/(mm MPa))."""

    design_id: int
    load: str
    design: object = field(repr=False)
    reference_gain: float
    formula_gain: float


#: The tiers a design sweep's formula is compared with -> the sweep column of their curvature.
_REFERENCE_COLUMNS = {"fem": "curvature_fem_per_mm"}


def load_sweep_cases(sweep_dir: str | Path, *, reference: str = "fem") -> list[DesignCase]:
    """The (design, load) cases of a finished sweep with a finite reference curvature.

    Gains are curvature over pressure at every nonzero pressure, medianed per
    design and load (both models are linear in pressure).
    """
    import json

    import pandas as pd

    ref_col = _REFERENCE_COLUMNS.get(reference)
    if ref_col is None:
        raise DataError(f"reference = {reference!r}: a design sweep is compared with the 3-D FEM ('fem')")
    root = Path(sweep_dir)
    df = read_results(root)
    if ref_col not in df or df[ref_col].notna().sum() == 0:
        raise DataError(
            f"{root}: the sweep has no 3-D FEM curvature ({ref_col}); run it with evaluators = "
            '["paper", "fem"]'
        )
    manifest = json.loads((root / "sweep.json").read_text(encoding="utf-8"))
    designs = pd.read_csv(root / "designs.csv")
    params = [c for c in designs.columns if c != "design_id"]
    ok = df[(df["status"] == "ok") & df[ref_col].notna() & (df["pressure_MPa"] != 0)]
    ok = ok.assign(
        ref_gain=ok[ref_col] / ok["pressure_MPa"],
        formula_gain=ok["curvature_analytic_per_mm"] / ok["pressure_MPa"],
    )
    gains = ok.groupby(["design_id", "load"])[["ref_gain", "formula_gain"]].median().reset_index()
    by_id = designs.set_index("design_id")
    built: dict[int, object] = {}
    cases = []
    for row in gains.itertuples(index=False):
        did = int(row.design_id)
        if did not in built:
            over = {p: by_id.loc[did, p] for p in params if pd.notna(by_id.loc[did, p])}
            built[did] = build_variant(manifest["base_table"], over, name=f"design {did}")
        # The paper's formula is the cap-load model for both loads (the sweep's lumen-load
        # analytic column is the one-material (1 - 2 nu) form, which is not the paper's).
        formula = analytic.gains(built[did], "cap")[0]
        cases.append(DesignCase(did, str(row.load), built[did], float(row.ref_gain), float(formula)))
    if len({c.design_id for c in cases}) < 4:
        raise DataError(f"{root}: {len(built)} designs with a FEM result; the workflow needs at least 4")
    return cases


class _Models:
    """Section-model gains per design and switch setting, computed once each."""

    def __init__(self, progress=None) -> None:
        self._cache: dict = {}
        self._progress = progress

    def gain(self, case: DesignCase, active: frozenset, c_end: float) -> float:
        physics = active - {"end_effects"}
        if not physics:
            g = case.formula_gain
        else:
            lumen = case.load == "lumen" and "confinement" in physics
            poisson = "poisson_mismatch" in physics or lumen
            coil = "annulus" if "coil_homogenisation" in physics else "wahl"
            key = (case.design_id, poisson, coil)
            if key not in self._cache:
                options = {"poisson": poisson, "coil_bending": coil, "poisson_cap": FEM_POISSON_CAP}
                # linear in pressure: the response at 1 MPa is the gain
                batches = tier_responses([case.design], [1.0], tier="section", loads=LOADS, options=options)
                self._cache[key] = {ld: float(b[0].curvature_per_mm[0]) for ld, b in batches.items()}
                if self._progress is not None:
                    self._progress.update(1)
            g = self._cache[key]["lumen" if lumen else "cap"]
        if "end_effects" in active:
            g *= 1.0 + c_end * _slenderness(case)
        return g


def _slenderness(case: DesignCase) -> float:
    return case.design.outer_diameter / case.design.tip.bending_length


def _gap(cases: Sequence[DesignCase], models: _Models, active: frozenset, c_end: float) -> float:
    """The reported gap: median ``|reference/model - 1|``."""
    r = [c.reference_gain / models.gain(c, active, c_end) - 1.0 for c in cases]
    return float(np.median(np.abs(r)))


def _score(cases: Sequence[DesignCase], models: _Models, active: frozenset, c_end: float) -> float:
    """The naming score: RMS of log(reference/model). Unlike the median it sees an
    ingredient that fixes only one load's rows (half the cases)."""
    r = [math.log(c.reference_gain / models.gain(c, active, c_end)) for c in cases]
    return float(np.sqrt(np.mean(np.square(r))))


def _fit_end(cases: Sequence[DesignCase], models: _Models, active: frozenset) -> tuple[float, float]:
    """Least-squares c of reference/model - 1 = c D/L on the training designs, and c / its standard error."""
    if "end_effects" not in active:
        return 0.0, math.inf
    x = np.array([_slenderness(c) for c in cases])
    r = np.array([c.reference_gain / models.gain(c, active, 0.0) - 1.0 for c in cases])
    c = float((x @ r) / (x @ x))
    se = math.sqrt(float(((r - c * x) ** 2).sum()) / max(x.size - 1, 1) / float(x @ x))
    return c, (abs(c) / se if se > 0 else math.inf)


def _passes(scores: dict, names: list, current: float, margin: float) -> bool:
    return any(
        scores[k]["significant"] and scores[k]["score_heldout"] < (1 - margin) * current for k in names
    )


@dataclass(frozen=True)
class DesignWorkflowResult:
    """What the design-space workflow found (``discrepancy.json``)."""

    named: tuple[str, ...]
    steps: tuple[dict, ...]
    ambiguous_with: dict[str, list[str]]
    gap_before: float
    gap_after: float
    nrmse_before: float
    nrmse_after: float
    end_effects_coefficient: float | None
    n_designs: int
    n_train: int
    n_heldout: int
    margin: float
    seed: int
    notes: tuple[str, ...]
    table: list[dict] = field(repr=False)

    def to_json(self) -> dict:
        from dataclasses import asdict

        d = asdict(self)
        d.pop("table")
        d["mode"] = "designs"
        d["reference"] = "fem"
        d["candidates"] = list(INGREDIENTS)
        return d


def _nrmse(cases, models, active, c_end) -> float:
    ref = np.array([c.reference_gain for c in cases])
    mod = np.array([models.gain(c, active, c_end) for c in cases])
    return float(np.sqrt(np.mean((ref - mod) ** 2)) / np.sqrt(np.mean(ref**2)))


def run_design_workflow(
    cases: Sequence[DesignCase],
    *,
    candidates: Iterable[str] = INGREDIENTS,
    margin: float = 0.05,
    heldout_fraction: float = 0.4,
    seed: int = 0,
    max_steps: int = 4,
    progress: bool = False,
) -> DesignWorkflowResult:
    """Name the section-model ingredients that explain reference/formula over the designs.

    Parameters
    ----------
    cases
        From :func:`load_sweep_cases`.
    candidates
        Subset of :data:`INGREDIENTS`.
    margin
        Required relative shrink of the held-out gap to name an ingredient.
    heldout_fraction
        Fraction of designs held out (seeded split by design, so both loads of a
        design fall on the same side).
    """
    cands = _check_options(candidates, margin, heldout_fraction)
    ids, held, train, test = _split(cases, heldout_fraction, seed)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=ids.size * 4, desc="section models", unit="model", leave=False)
    models = _Models(bar)
    gap0 = _gap(test, models, frozenset(), 0.0)
    nrmse0 = _nrmse(test, models, frozenset(), 0.0)
    sel = _select(cands, train, test, models, margin=margin, max_steps=max_steps, gap0=gap0)
    active, c_end = sel.active, sel.c_end
    if bar is not None:
        bar.close()
    notes = []
    if not sel.named:
        notes.append(
            f"nothing beats the paper's formula by the {margin:.0%} margin on held-out designs "
            f"(held-out gap {gap0:.3g})"
        )
    return DesignWorkflowResult(
        named=tuple(sel.named),
        steps=tuple(sel.steps),
        ambiguous_with=sel.ambiguous,
        gap_before=gap0,
        gap_after=sel.gap,
        nrmse_before=nrmse0,
        nrmse_after=_nrmse(test, models, active, c_end),
        end_effects_coefficient=c_end if "end_effects" in active else None,
        n_designs=int(ids.size),
        n_train=len({c.design_id for c in train}),
        n_heldout=len(held),
        margin=margin,
        seed=seed,
        notes=tuple(notes),
        table=_table(cases, held, models, active, c_end),
    )


def _check_options(candidates, margin, heldout_fraction) -> tuple[str, ...]:
    """Check the candidates, the margin and the held-out fraction; returns the candidates."""
    cands = tuple(candidates)
    bad = [c for c in cands if c not in INGREDIENTS]
    if bad:
        raise DataError(f"candidates {bad}: must be among {INGREDIENTS}")
    if not (0 < margin < 1) or not (0.1 <= heldout_fraction <= 0.9):
        raise DataError(
            f"margin = {margin}, heldout_fraction = {heldout_fraction}: need (0, 1) and [0.1, 0.9]"
        )
    return cands


def _split(cases, heldout_fraction, seed):
    """Seeded split by design; returns (design ids, held-out ids, training cases, held-out cases)."""
    ids = np.array(sorted({c.design_id for c in cases}))
    rng = np.random.default_rng(seed)
    held = set(rng.permutation(ids)[: max(2, int(round(heldout_fraction * ids.size)))].tolist())
    train = [c for c in cases if c.design_id not in held]
    test = [c for c in cases if c.design_id in held]
    if not train or not test:
        raise DataError(f"{ids.size} designs cannot be split into training and held-out sets")
    return ids, held, train, test


@dataclass(frozen=True)
class _Selection:
    """Where the forward selection stopped."""

    steps: list
    named: list
    ambiguous: dict
    active: frozenset
    c_end: float
    gap: float


def _select(cands, train, test, models, *, margin, max_steps, gap0) -> _Selection:
    """Forward selection: add the best candidate while it shrinks the held-out gap by the margin."""
    active: frozenset = frozenset()
    c_end = 0.0
    steps, named, ambiguous = [], [], {}
    current = gap0
    current_score = _score(test, models, active, c_end)
    for _ in range(max_steps):
        remaining = [c for c in cands if c not in active]
        if not remaining:
            break
        scores = _score_candidates(remaining, active, train, test, models)
        # Parameter-free physics first: a fitted correction is only weighed for what physics leaves.
        physics = [k for k in scores if k != "end_effects"]
        pool = physics if physics and _passes(scores, physics, current_score, margin) else list(scores)
        best = min(pool, key=lambda k: scores[k]["score_heldout"])
        s = scores[best]
        passed = s["score_heldout"] < (1 - margin) * current_score and s["significant"]
        step = {
            "step": len(steps) + 1,
            "gap_heldout_before": current,
            "score_heldout_before": current_score,
            "candidates": scores,
            "best": best,
            "named": best if passed else None,
        }
        steps.append(step)
        if not passed:
            break
        rivals = [
            k
            for k, v in scores.items()
            if k != best
            and v["gap_heldout"] < (1 - margin) * current
            and v["gap_heldout"] <= s["gap_heldout"] * (1 + margin) + 1e-12
        ]
        if rivals:
            ambiguous[best] = rivals
        active = active | {best}
        c_end = s["end_effects_coefficient"]
        named.append(best)
        current = s["gap_heldout"]
        current_score = s["score_heldout"]
        step["gap_heldout_after"] = current
    return _Selection(steps=steps, named=named, ambiguous=ambiguous, active=active, c_end=c_end, gap=current)


def _score_candidates(remaining, active, train, test, models) -> dict:
    """Fit and score each remaining candidate added to ``active``."""
    scores = {}
    for cand in remaining:
        trial = active | {cand}
        c_fit, t_stat = _fit_end(train, models, trial)
        scores[cand] = {
            "gap_train": _gap(train, models, trial, c_fit),
            "gap_heldout": _gap(test, models, trial, c_fit),
            "score_heldout": _score(test, models, trial, c_fit),
            "end_effects_coefficient": c_fit,
            # a fitted correction must be resolved on the training designs (|c| > 3 standard errors)
            "significant": bool(cand != "end_effects" or t_stat > 3.0),
        }
    return scores


def _table(cases, held, models, active, c_end) -> list[dict]:
    """Per case: reference, formula and model gains, and whether it was held out."""
    return [
        {
            "design_id": c.design_id,
            "load": c.load,
            "heldout": c.design_id in held,
            "reference_gain": c.reference_gain,
            "formula_gain": c.formula_gain,
            "model_gain": models.gain(c, active, c_end),
        }
        for c in cases
    ]
