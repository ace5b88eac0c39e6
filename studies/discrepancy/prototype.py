r"""Which physical ingredients explain a measured prototype curve, point by point.

A measured curvature-vs-pressure curve of a built design (``pressure_MPa,
curvature_per_mm[, elongation]``) is compared, at every measured pressure,
with the predictions of physical hypotheses on the finite-strain section
model, the tier valid past 5 deg (:mod:`.physical`; ingredients and their
sourced ranges in :mod:`.ingredients`). The measured curvature is the
prototype's circle fit over the visible tip, so the model's mid-span
curvature is multiplied by the tip-level factor (end zones included).

The noise of a point comes from the data themselves (:mod:`.noise`), never
from a model's misfit. A hypothesis fits when its chi-square is within the
95 % quantile; the fewest ingredients that fit decide; when several fit at
that size they are reported as equally good with the bench measurement that
would separate them. When nothing fits, the record says so with the best
hypothesis, its residual and what the model would need.
"""

from __future__ import annotations

import csv
import logging
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from softcath.design.errors import DataError, DesignError
from softcath.fem.section_model.end_zones import end_zones
from softcath.fem.section_model.finite_strain.prestretch import PRESTRETCH_MAX
from softcath.studies.discrepancy.ingredients import INGREDIENTS
from softcath.studies.discrepancy.model_bank import ModelBank
from softcath.studies.discrepancy.physical import (
    FIT_QUANTILE,
    Measured,
    decide,
    fit_hypothesis,
    hypotheses,
    score_hypotheses,
)

__all__ = ["INGREDIENTS", "load_prototype_csv", "explain_prototype", "tip_level_factor", "hypotheses_table"]

log = logging.getLogger(__name__)

#: Default candidates: every ingredient.
DEFAULT_MAX_SIZE = 3
TIER = "finite-strain section"


def load_prototype_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read ``pressure_MPa, curvature_per_mm[, elongation]`` (one row per measured point)."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            reader = csv.DictReader(fh)
            rows = list(reader)
            header = reader.fieldnames or []
    except FileNotFoundError:
        raise DataError(f"{path}: does not exist") from None
    except UnicodeDecodeError as exc:
        raise DataError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except csv.Error as exc:
        raise DataError(f"{path}: not a CSV file ({exc})") from None
    for col in ("pressure_MPa", "curvature_per_mm"):
        if col not in header:
            raise DataError(
                f"{path}: column {col} is required (pressure_MPa, curvature_per_mm[, elongation])"
            )
    out = {}
    for col in ("pressure_MPa", "curvature_per_mm", "elongation"):
        if col not in header:
            continue
        values = []
        for line, r in enumerate(rows, start=2):
            cell = r.get(col)
            if cell is None or cell == "":
                raise DataError(f"{path}: line {line}: column {col} is empty (every row needs every column)")
            try:
                values.append(float(cell))
            except ValueError:
                raise DataError(f"{path}: line {line}: column {col} = {cell!r}: not a number") from None
        out[col] = np.array(values)
        if not np.all(np.isfinite(out[col])):
            raise DataError(f"{path}: column {col}: must be finite")
    if out["pressure_MPa"].size < 4:
        raise DataError(f"{path}: needs at least 4 measured points, has {out['pressure_MPa'].size}")
    p = out["pressure_MPa"]
    if np.any(p < 0):
        raise DataError(f"{path}: column pressure_MPa: must be >= 0 MPa (a gauge pressure)")
    if p.max() > 2.0:
        raise DataError(
            f"{path}: column pressure_MPa reaches {p.max():g}: past 2 MPa, far beyond a silicone tube's "
            "burst; is the log in bar (1 bar = 0.1 MPa)?"
        )
    if not np.ptp(p) > 0:
        raise DataError(f"{path}: column pressure_MPa is constant: there is no curve to explain")
    return out


def check_candidates(candidates: Sequence[str] | None) -> list[str]:
    """The candidate ingredients, each known (a bad name is refused, naming the known ones)."""
    if candidates is None:
        return list(INGREDIENTS)
    unknown = [c for c in candidates if c not in INGREDIENTS]
    if unknown:
        raise DesignError("--candidates", ",".join(unknown), f"must be among {', '.join(INGREDIENTS)}")
    if len(set(candidates)) != len(candidates):
        raise DesignError("--candidates", ",".join(candidates), "names an ingredient twice")
    return list(candidates)


def explain_prototype(
    design,
    measured: dict[str, np.ndarray],
    *,
    load: str = "lumen",
    tip_factor: float = 1.0,
    candidates: Sequence[str] | None = None,
    max_size: int = DEFAULT_MAX_SIZE,
    bank: ModelBank | None = None,
    workers: int = 1,
    progress: bool = False,
) -> dict:
    """Fit every hypothesis to the measured points; the ``discrepancy.json`` record.

    Parameters
    ----------
    design
        The built design (a :class:`design.TipDesign`).
    measured
        From :func:`load_prototype_csv`.
    load
        Model load (``"lumen"``: the real one).
    tip_factor
        Tip-level over mid-span curvature (1: mid-span).
    candidates
        Ingredients to try (default: all of :data:`INGREDIENTS`).
    max_size
        Largest number of ingredients in one hypothesis.
    bank
        The design's solved curves to reuse (default: a new one up to the largest measured pressure).
    workers
        Processes for the finite-strain solves (each model variant is solved once).
    progress
        Show a progress bar over the finite-strain solves.
    """
    cands = check_candidates(candidates)
    if not (isinstance(max_size, int) and 0 <= max_size <= len(INGREDIENTS)):
        raise DesignError("max_size", max_size, f"must be an integer in [0, {len(INGREDIENTS)}]")
    m = Measured.from_columns(measured)
    if not (isinstance(workers, int) and 1 <= workers <= 256):
        raise DesignError("--workers", workers, "must be an integer in [1, 256]")
    if bank is None:
        bank = ModelBank(design, p_max=float(m.pressure.max()), load=load)
    needed = [v for h in hypotheses(cands, max_size) for v in bank.variants_for(h)]
    bank.solve(needed, workers=workers, progress=progress)
    hyps = score_hypotheses(bank, m, cands, max_size=max_size, tip_factor=tip_factor)
    choice = decide(hyps)
    base = hyps[0]
    best = min(hyps, key=lambda h: h["chi_square"])
    notes = list(bank.notes)
    chosen = next(
        (h for h in hyps if choice["equally_good"] and h["ingredients"] == choice["equally_good"][0]), None
    )
    outside = None
    if chosen is None:
        notes.append(_unexplained(m, best, min(max_size, len(cands))))
        outside = beyond_ranges(
            design, m, best, load=load, tip_factor=tip_factor, workers=workers, progress=progress
        )
        if outside is not None:
            notes.append(outside["text"])
    elif choice["also_fit"] or len(choice["equally_good"]) > 1:
        notes.append(_ambiguity(choice))
    p = m.pressure
    return {
        "reference": "prototype",
        "tier": TIER,
        "named": choice["named"],
        "steps": [],
        "nrmse_before": base["nrmse"],
        "nrmse_after": chosen["nrmse"] if chosen else base["nrmse"],
        "best_nrmse": best["nrmse"],
        "best": best["ingredients"],
        "explained": chosen is not None,
        "ambiguous_with": choice["equally_good"] if len(choice["equally_good"]) > 1 else [],
        "noise_floor_nrmse": float(m.noise.sigma / (np.ptp(m.curvature) or 1.0)),
        "noise": m.noise.to_json(),
        "notes": notes,
        "decision_rule": {
            "fit_quantile": FIT_QUANTILE,
            "text": "a hypothesis fits when the chi-square of its best prediction inside the sourced "
            f"ranges, per degree of freedom, is below the {FIT_QUANTILE:.0%} quantile of the F "
            "distribution (the noise is estimated from the data, with its own degrees of freedom); "
            "the fewest ingredients that fit decide; "
            "ingredients are named only if every equally good hypothesis has them",
        },
        "measured_gain_per_mm_MPa": float(p @ m.curvature / (p @ p)),
        "noise_sigma_per_mm": m.noise.sigma,
        "load": load,
        "tip_factor": tip_factor,
        "equally_good": choice["equally_good"],
        "also_fit": choice["also_fit"],
        "beyond_ranges": outside,
        "separating_measurement": choice["separating_measurement"],
        "hypotheses": hyps,
    }


def _unexplained(m: Measured, best: dict, max_size: int) -> str:
    """Why nothing fits: the best hypothesis, its residual and where the model falls short."""
    k = np.asarray([np.nan if v is None else v for v in best["predicted"]["curvature_per_mm"]])
    r = m.curvature - k
    worst = int(np.nanargmax(np.abs(r)))
    name = " + ".join(best["ingredients"]) or "the baseline"
    slope_meas = float(np.max(np.gradient(m.curvature, m.pressure)))
    slope_model = float(np.nanmax(np.gradient(k, m.pressure)))
    ends = [n for n, v in best["parameters"].items() if v["at_range_end"]]
    return (
        f"no hypothesis of up to {max_size} ingredients inside the sourced ranges fits the measurement: "
        f"the best, {name}, leaves NRMSE {best['nrmse']:.3f} against a noise floor of "
        f"{m.noise.sigma / (np.ptp(m.curvature) or 1.0):.3f}; its largest miss is "
        f"{r[worst]:+.3g} 1/mm at {m.pressure[worst]:.3g} MPa; the measured curve rises at up to "
        f"{slope_meas:.3g} 1/(mm MPa), the best model at {slope_model:.3g}"
        + (f"; {', '.join(ends)} sit at the end of their ranges (the data ask for more)" if ends else "")
    )


#: How far past a sourced range end the data may take a parameter when nothing fits inside.
_BEYOND = {"low": 0.5, "high": 2.0}
_HARD_LIMITS = {
    "vision_bias": (0.0, 1.0),
    "pressure_offset": (0.0, 2.0),
    "rest_curvature": (0.0, 1.0),
    "tube_prestretch": (1.0, PRESTRETCH_MAX),
    "tube_squeeze": (0.0, 1.0),
}


def beyond_ranges(
    design, m: Measured, best: dict, *, load: str, tip_factor: float, workers: int, progress: bool = False
) -> dict | None:
    """What the data would need: the best hypothesis refitted with the range ends it sits at moved
    out (halved or doubled; a vision factor at most 1), or None if none sits at an end."""
    ranges: dict[str, tuple[float, float]] = {}
    for n, v in best["parameters"].items():
        lo, hi = v["range"]
        if not v["at_range_end"]:
            continue
        cap_lo, cap_hi = _HARD_LIMITS.get(n, (0.0, np.inf))
        if np.isclose(v["value"], lo):
            lo = max(lo * _BEYOND["low"] if lo > 0 else lo, cap_lo)
        else:
            hi = min(hi * _BEYOND["high"], cap_hi)
        ranges[n] = (lo, hi)
    if not ranges:
        return None
    ingredients = tuple(best["ingredients"])
    bank = ModelBank(design, p_max=float(m.pressure.max()), load=load, ranges=ranges)
    bank.solve(bank.variants_for(ingredients), workers=workers, progress=progress)
    h = fit_hypothesis(bank, m, ingredients, tip_factor)
    chosen = ", ".join(
        f"{n} = {v['value']:.3g} {v['unit']}".rstrip()
        + f" (sourced {INGREDIENTS[n].low:g}-{INGREDIENTS[n].high:g})"
        for n, v in h["parameters"].items()
        if n in ranges
    )
    verdict = "would fit" if h["fits"] else "still would not fit"
    name = " + ".join(ingredients)
    h["text"] = f"beyond the sourced ranges, {name} {verdict}: NRMSE {h['nrmse']:.3f} with {chosen}"
    return h


def _ambiguity(choice: dict) -> str:
    good = [" + ".join(h) or "baseline" for h in choice["equally_good"]]
    text = f"equally good: {'; '.join(good)}"
    if choice["also_fit"]:
        more = [" + ".join(h) for h in choice["also_fit"]]
        text += f"; these fit as well but add ingredients the data do not need: {'; '.join(more)}"
    if choice["separating_measurement"]:
        text += f"; to separate them: {choice['separating_measurement']}"
    return text


def tip_level_factor(design) -> float:
    """Tip-level over mid-span curvature of ``design``: its end zones' factor.

    What a circle fit over the whole tip sees is the end section's rotation over the
    length, end zones included: (L - deficit) / L, from
    :func:`~softcath.fem.section_model.end_zones.end_zones` (fitted on converged 3-D
    finite-strain solves; the same under either load).
    """
    return float(end_zones(design).factor)


def hypotheses_table(record: dict) -> list[str]:
    """Plain-text lines: each hypothesis's fit, best first."""
    lines = [
        f"tier: {record.get('tier', TIER)}, {record['load']} load; tip factor {record['tip_factor']:.3g}; "
        f"noise {record['noise_sigma_per_mm']:.3g} 1/mm ({record['noise']['method']})"
    ]
    for h in sorted(record["hypotheses"], key=lambda h: h["chi_square"])[:12]:
        name = " + ".join(h["ingredients"]) or "baseline (nominal design)"
        verdict = "fits" if h["fits"] else "cannot"
        pars = ", ".join(f"{n} {v['value']:.3g} {v['unit']}".rstrip() for n, v in h["parameters"].items())
        lines.append(f"  {name}: NRMSE {h['nrmse']:.3f} -> {verdict}" + (f" ({pars})" if pars else ""))
    return lines
