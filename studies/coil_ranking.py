"""How much a design ranking depends on the coil model.

Users sweep coil dimensions and pick the design that bends most per MPa. The
coil model is uncertain (docs/coil.md): the 3-D FEM's annulus, the resolved
wire's stiffnesses, or the resolved wire with coil-bound compression. This
module ranks the same designs under each model and reports how far the
rankings agree: Spearman's rank correlation and the overlap of the top k.

>>> from softcath.studies.coil_ranking import random_coil_designs, rank_by_coil_model
>>> designs = random_coil_designs(4, seed=1)
>>> r = rank_by_coil_model(designs, models=("annulus", "resolved"), top=2)
>>> sorted(r.gains)
['annulus', 'resolved']
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.section_model import bend_curve, section_model
from softcath.fem.section_model.coil_models import model_options
from softcath.studies.sweep.variants import VariantBuilder

__all__ = ["CoilRanking", "RANKING_MODELS", "COIL_SWEEP", "random_coil_designs", "rank_by_coil_model", "gain"]

log = logging.getLogger(__name__)

#: Linear section-model coil models (``softcath.fem.section_model.coil_models``) plus ``coil-bound``:
#: the resolved ring with the bilinear law (F0 = 0, so kappa is still linear in p), and
#: ``coil-bound-tensioned``: the same with initial tension F0 on the outer coil, ranked by
#: kappa(p)/p at one pressure (the response has a threshold, so the gain depends on p).
RANKING_MODELS = ("annulus", "annulus-bending", "wahl", "resolved", "coil-bound", "coil-bound-tensioned")

#: Coil dimensions sampled by :func:`random_coil_designs` (dotted path -> (low, high) mm), about the paper's.
COIL_SWEEP = {
    "coil.outer_diameter": (0.7, 1.0),
    "coil.wire_diameter": (0.05, 0.15),
    "channel.outer_diameter": (0.22, 0.4),
    "channel.wire_diameter": (0.04, 0.1),
}


@dataclass(frozen=True)
class CoilRanking:
    """Gains of the same designs under several coil models and how their rankings agree.

    Attributes
    ----------
    designs
        Design names, in input order.
    gains
        Model -> kappa/p [1/(mm MPa)] per design (``load``).
    spearman
        (model a, model b) -> Spearman's rank correlation of the gains.
    top_overlap
        (model a, model b) -> share of model a's top ``top`` designs also in model b's.
    top
        k of the top-k overlap.
    """

    designs: tuple[str, ...]
    load: str
    gains: dict
    spearman: dict
    top_overlap: dict
    top: int

    def order(self, model: str) -> list[str]:
        """Design names from the largest gain down under ``model``."""
        g = self.gains[model]
        return [self.designs[i] for i in np.argsort(-g, kind="stable")]


def random_coil_designs(n: int, *, seed: int = 0, base="paper", ranges=None, max_tries: int = 20) -> list:
    """``n`` valid variants of ``base`` with coil dimensions drawn uniformly from ``ranges``.

    Draws that violate the design's checks (a coil too thin for the tube, a
    channel that does not fit) are redrawn, up to ``max_tries * n`` draws.
    """
    if n < 1:
        raise DesignError("n", n, "must be >= 1")
    ranges = COIL_SWEEP if ranges is None else ranges
    builder = VariantBuilder(design.to_dict(design.resolve(base)))
    rng = np.random.default_rng(seed)
    out, tries = [], 0
    while len(out) < n:
        tries += 1
        if tries > max_tries * n:
            raise DesignError(
                "ranges", dict(ranges), f"gave only {len(out)} valid designs in {tries - 1} draws"
            )
        values = {k: float(rng.uniform(lo, hi)) for k, (lo, hi) in ranges.items()}
        try:
            out.append(builder.build(values, name=f"d{len(out):02d}"))
        except DesignError as exc:
            log.debug("redraw: %s", exc)
    return out


def gain(
    d, model: str, *, load: str = "lumen", initial_tension: float = 0.005, pressure: float = 0.3, **options
) -> float:
    """kappa/p of design ``d`` under coil model ``model`` (:data:`RANKING_MODELS`).

    ``initial_tension`` [N] (outer coil) and ``pressure`` [MPa] apply to ``coil-bound-tensioned`` only.
    """
    if model == "coil-bound":
        return float(bend_curve(d, [1.0], load=load, initial_tension=(0.0, 0.0), **options).gain_pivoting)
    if model == "coil-bound-tensioned":
        c = bend_curve(d, [pressure], load=load, initial_tension=(initial_tension, 0.0), **options)
        return float(c.curvature[0] / pressure)
    if model not in RANKING_MODELS:
        raise DesignError("model", model, f"must be one of {RANKING_MODELS}")
    return float(
        section_model(d, loads=(load,), **model_options(model), **options).curvature_per_mm_per_MPa[load]
    )


def rank_by_coil_model(
    designs: Sequence,
    *,
    models: Sequence[str] = ("annulus", "resolved", "coil-bound"),
    load: str = "lumen",
    top: int = 5,
    **options,
) -> CoilRanking:
    """Rank ``designs`` by kappa/p under each model and compare every pair of rankings.

    ``options`` go to :func:`gain` (``initial_tension``, ``pressure``) and the
    section model (mesh size, Poisson ratio).
    """
    from scipy.stats import spearmanr

    models = tuple(models)
    bad = [m for m in models if m not in RANKING_MODELS]
    if bad or len(models) < 2:
        raise DesignError("models", models, f"must be two or more of {RANKING_MODELS}")
    if not 1 <= top <= len(designs):
        raise DesignError("top", top, f"must be in [1, {len(designs)}] (the number of designs)")
    gains = {m: np.array([gain(d, m, load=load, **options) for d in designs]) for m in models}
    rho, overlap = {}, {}
    for i, a in enumerate(models):
        for b in models[i + 1 :]:
            rho[(a, b)] = float(spearmanr(gains[a], gains[b]).statistic)
            best_a = set(np.argsort(-gains[a], kind="stable")[:top].tolist())
            best_b = set(np.argsort(-gains[b], kind="stable")[:top].tolist())
            overlap[(a, b)] = len(best_a & best_b) / top
    return CoilRanking(tuple(d.name for d in designs), load, gains, rho, overlap, int(top))
