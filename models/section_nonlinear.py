"""The ``section-nonlinear`` tier: the finite-strain section model, one Newton walk a design and load.

Valid at the large bends a tip is chosen for. Each load walks once through the positive
pressures; 0 MPa is the rest state and a negative pressure (which the walk does not take)
is NaN (:func:`softcath.models.section_nonlinear_eval.section_nonlinear_columns`).
"""

from __future__ import annotations

import numpy as np

from softcath.core.interrupts import raise_pending_stop
from softcath.models.section_nonlinear_eval import (
    SECTION_NONLINEAR_KEYS,
    section_nonlinear_columns,
    section_nonlinear_curve,
)
from softcath.models.tier import Tier

__all__ = ["SECTION_NONLINEAR", "SectionNonlinearTier", "SECTION_NONLINEAR_FIELDS"]

#: Sweep column of the finite-strain section evaluator -> response field (the evaluator's own table).
SECTION_NONLINEAR_FIELDS = SECTION_NONLINEAR_KEYS


class SectionNonlinearTier(Tier):
    """The finite-strain section model, design by design (a stalled walk is that design's error)."""

    def record(self, design, pressures, *, load: str | None = None, options=None):
        """The finite-strain curve of one design (its DOFs, Newton record, fields), walked with this
        tier's ``options`` as its responses are
        (:func:`~softcath.models.section_nonlinear_eval.section_nonlinear_curve`).

        Raises
        ------
        DesignError
            A load or option the tier does not take; the model's own errors propagate.
        """
        load = self.check_load(self.default_load if load is None else load)
        return section_nonlinear_curve(design, pressures, load, self.check_options(options))

    def _solve(self, designs, pressures, loads, options):
        n = len(designs)
        blocks = {
            ld: {c: np.full((n, pressures.size), np.nan) for c in SECTION_NONLINEAR_FIELDS} for ld in loads
        }
        seconds = {ld: np.full(n, np.nan) for ld in loads}
        errors: dict[int, Exception] = {}
        for i, d in enumerate(designs):
            try:
                values = section_nonlinear_columns(d, pressures, loads, options)
            except Exception as exc:  # a stalled Newton walk is this design's error, never the batch's
                raise_pending_stop()
                errors[i] = exc
                continue
            for ld in loads:
                for col in SECTION_NONLINEAR_FIELDS:
                    blocks[ld][col][i] = values[ld][col]
                if pressures.size:
                    seconds[ld][i] = values[ld]["section_nonlinear_seconds"][0]
        return {
            ld: self._batch(
                designs,
                pressures,
                ld,
                {f: blocks[ld][c] for c, f in SECTION_NONLINEAR_FIELDS.items()},
                seconds=seconds[ld],
                options=options,
                errors=errors,
            )
            for ld in loads
        }


#: The finite-strain section model.
SECTION_NONLINEAR = SectionNonlinearTier(
    "section-nonlinear",
    "the finite-strain section model",
    "finite-strain section model",
    "finite-strain section model: valid at large bends, ~1 s a design and load",
    "section_nonlinear",
    # tube_prestretch: the as-built tube's axial stretch from its catalogue state (1: none; above 1
    # the curve is solved on the reference path)
    options={"mesh_size": None, "mesher": "template", "tube_prestretch": 1.0},
    # its walk through a few pressures against one linear solve: about fifteen Newton iterations of a
    # tangent twice the linear model's size (~1 s for the paper section), 30x the section's cost
    dof_seconds=30.0 * 1.05e-5,
    seconds_per_design=1.0,
    section_mesh=True,
    # the tip as built on the reference path (fem.section_model.finite_strain.as_built)
    as_built=True,
)
