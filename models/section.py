"""The ``section`` tier: the linear 2-D generalised-plane-strain section model, batched over designs.

With the template mesher (the default) the designs go through the batched section models
(one kernel per template, factorisations reused: the sweep's path,
:func:`softcath.models.section_eval.section_blocks_many`); with ``mesher = "gmsh"``
each design is solved alone. The response is linear in pressure; the tip's angle and pose
take off its end zones (:mod:`softcath.fem.section_model.end_zones`).
"""

from __future__ import annotations

import numpy as np

from softcath.core.interrupts import raise_pending_stop
from softcath.fem.section_model.laws import NU_MAX
from softcath.models.section_eval import SECTION_KEYS, section_blocks_many, section_columns, section_result
from softcath.models.tier import LOADS, OptionBound, Tier
from softcath.models.validity import LINEAR_BEND_LIMIT_DEG

__all__ = ["SECTION", "SectionTier", "SECTION_FIELDS"]

#: Sweep column of the section evaluator -> response field.
SECTION_FIELDS = {
    "curvature_section_per_mm": "curvature_per_mm",
    "elongation_section": "elongation",
    "bend_angle_section_rad": "bend_angle_rad",
    "tip_x_section_mm": "tip_x_mm",
    "tip_y_section_mm": "tip_y_mm",
    "max_strain_section": "max_strain",
}


#: The options the batched section models take (the others go design by design).
_BATCHED_OPTIONS = frozenset({"mesh_size", "mesher", "segments", "coil_modulus", "coil_bending"})


def _one_by_one(designs, pressures, loads, options) -> tuple[dict, dict]:
    """The sweep's section columns of each design alone (``softcath.fem.section_model.section_model``)."""
    cols = {ld: {k: np.full((len(designs), pressures.size), np.nan) for k in SECTION_KEYS} for ld in loads}
    errors: dict[int, Exception] = {}
    for j, d in enumerate(designs):
        try:
            values = section_columns(d, pressures, loads, options)
        except Exception as exc:  # this design's error, never the batch's
            raise_pending_stop()
            errors[j] = exc
            continue
        for ld in loads:
            for k, v in values[ld].items():
                cols[ld][k][j] = v
    return cols, errors


class SectionTier(Tier):
    """The linear section model; extras ``section_formula_ratio`` (its curvature over eq. 7's, cap load)."""

    def record(self, design, *, loads=LOADS, options=None, keep_fields: bool = False):
        """The section model's own record of one design (DOFs, gains, fields for pictures), solved
        with this tier's ``options`` as its responses are
        (:func:`~softcath.models.section_eval.section_result`).

        Raises
        ------
        DesignError
            An option the tier does not take; the section model's own errors propagate.
        """
        return section_result(design, tuple(loads), self.check_options(options), keep_fields=keep_fields)

    def _solve(self, designs, pressures, loads, options):
        if set(options) <= _BATCHED_OPTIONS:
            cols, errors = section_blocks_many(designs, pressures, loads, options)
        else:  # an option only the single-design model takes (e.g. poisson_cap): one design at a time
            cols, errors = _one_by_one(designs, pressures, loads, options)
        out = {}
        for load in loads:
            block = cols[load]
            values = {field: block[col] for col, field in SECTION_FIELDS.items()}
            out[load] = self._batch(
                designs,
                pressures,
                load,
                values,
                seconds=np.asarray(block["section_seconds"], float)[:, 0]
                if pressures.size
                else np.full(len(designs), np.nan),
                options=options,
                extras={"section_formula_ratio": block["section_formula_ratio"]},
                errors=errors,
            )
        return out


#: The linear section model.
SECTION = SectionTier(
    "section",
    "the section model",
    "section model (2-D GPS)",
    "linear 2-D generalised-plane-strain section model: 3-D-FEM-grade curvature, ~0.2 s a design",
    "section",
    options={
        "mesh_size": 0.08,
        "segments": 20,
        "mesher": "template",
        "coil_modulus": "tension",
        "coil_bending": "annulus",
        "poisson_cap": None,
        "silicone_poisson": None,
        "poisson": True,
    },
    option_bounds={"poisson_cap": OptionBound(0.0, NU_MAX), "silicone_poisson": OptionBound(0.0, NU_MAX)},
    valid_to_deg=LINEAR_BEND_LIMIT_DEG,
    as_built=True,
    # 29.5 ms of worker CPU on the sweep's batched path for the paper section (docs/section.md),
    # whose estimated DOFs are 2.8k
    dof_seconds=1.05e-5,
    batched=True,
    seconds_per_design=0.2,
    section_mesh=True,
    finite_strain_tier="section-nonlinear",
)
