"""The ``paper`` tier: the paper's composite-beam formula (eq. 7), vectorised over designs."""

from __future__ import annotations

import time

import numpy as np

from softcath import analytic
from softcath.analytic.section import section_arrays
from softcath.core.response import tip_curvature
from softcath.models.tier import Tier
from softcath.models.validity import LINEAR_BEND_LIMIT_DEG

__all__ = ["PAPER", "PaperTier"]


class PaperTier(Tier):
    """The formula over all designs at once: one dict of input arrays, every load from the same section.

    The largest silicone strain is the composite beam's axial strain ε + κ (y − ȳ) at the
    tube's top and bottom fibres (Euler–Bernoulli).
    """

    def _solve(self, designs, pressures, loads, options):
        t0 = time.perf_counter()
        inp = {k: v[:, None] for k, v in analytic.design_inputs_many(designs).items()}
        s = section_arrays(inp)
        y_top = s["tube_centre_y"] + s["b"] - s["neutral_axis_y"]
        y_bot = s["tube_centre_y"] - s["b"] - s["neutral_axis_y"]
        out = {}
        for load in loads:
            r = analytic.response_arrays(inp, pressures[None, :], load)
            strain = np.maximum(
                np.abs(r.elongation + r.curvature * y_top), np.abs(r.elongation + r.curvature * y_bot)
            )
            values = {
                "curvature_per_mm": r.curvature,
                "tip_curvature_per_mm": tip_curvature(r.bend_angle, r.elongation, inp["length"]),
                "elongation": r.elongation,
                "bend_angle_rad": r.bend_angle,
                "tip_x_mm": r.tip_x,
                "tip_y_mm": r.tip_y,
                "max_strain": strain,
            }
            out[load] = values
        seconds = np.full(len(designs), (time.perf_counter() - t0) / max(len(designs), 1))
        return {
            load: self._batch(designs, pressures, load, v, seconds=seconds, options=options)
            for load, v in out.items()
        }


#: The paper's formula.
PAPER = PaperTier(
    "paper",
    "the paper's formula",
    "paper's formula (eq. 7)",
    "composite-beam formula of the paper (eq. 7): microseconds a design",
    "analytic",
    default_load="cap",
    valid_to_deg=LINEAR_BEND_LIMIT_DEG,
    load_notes={"lumen": "paper tier, lumen load: the formula's cap gain times (1 - 2 nu)"},
    batched=True,
    seconds_per_design=1e-4,
    closed_form=True,
)
