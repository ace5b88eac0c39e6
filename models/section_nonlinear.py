"""The ``section-nonlinear`` tier: the finite-strain section model, one Newton walk a design and load.

Valid at the large bends a tip is chosen for. Each load walks once through the positive
pressures; 0 MPa is the rest state and a negative pressure (which the walk does not take)
is NaN (:func:`softcath.models.section_nonlinear_eval.section_nonlinear_columns`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from softcath.core.interrupts import raise_pending_stop
from softcath.fem.section_model.finite_strain import SectionConvergenceError
from softcath.fem.section_model.finite_strain.curve import COIL_AXIAL_SCALE_MAX
from softcath.fem.section_model.finite_strain.prestretch import PRESTRETCH_MAX
from softcath.fem.section_model.laws import NU_MAX
from softcath.models.section_nonlinear_eval import (
    SECTION_NONLINEAR_KEYS,
    SECTION_NONLINEAR_OPTIONS,
    load_columns,
    partial_columns,
    section_nonlinear_curve,
)
from softcath.models.tier import OptionBound, Tier

__all__ = ["SECTION_NONLINEAR", "SectionNonlinearTier", "SECTION_NONLINEAR_FIELDS"]

#: Sweep column of the finite-strain section evaluator -> response field (the evaluator's own table).
SECTION_NONLINEAR_FIELDS = SECTION_NONLINEAR_KEYS


class SectionNonlinearTier(Tier):
    """The finite-strain section model, design by design (a stalled walk is that design's error).

    A design whose Newton walk stalled stays in the batch's ``errors`` with NaN rows; the
    pressures it reached are its :meth:`~softcath.core.response.ResponseBatch.partial_response`.
    """

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
        partial: dict[str, dict] = {ld: {} for ld in loads}
        for i, d in enumerate(designs):
            done = {}
            for ld in loads:
                try:
                    done[ld] = load_columns(d, pressures, ld, options)
                except Exception as exc:  # a stalled Newton walk is this design's error, never the batch's
                    raise_pending_stop()
                    errors[i] = exc
                    if isinstance(exc, SectionConvergenceError) and exc.curve is not None:
                        done[ld] = partial_columns(exc.curve, pressures)
                    break
            if i in errors:  # what the walks reached, the stalled one up to its last pressure
                for ld, cols in done.items():
                    partial[ld][i] = self._partial(d, pressures, ld, cols, options, errors[i])
                continue
            for ld in loads:
                for col in SECTION_NONLINEAR_FIELDS:
                    blocks[ld][col][i] = done[ld][col]
                if pressures.size:
                    seconds[ld][i] = done[ld]["section_nonlinear_seconds"][0]
        return {
            ld: self._batch(
                designs,
                pressures,
                ld,
                {f: blocks[ld][c] for c, f in SECTION_NONLINEAR_FIELDS.items()},
                seconds=seconds[ld],
                options=options,
                errors=errors,
                partial=partial[ld],
            )
            for ld in loads
        }

    def _partial(self, design, pressures, load, cols, options, error):
        """The response of one design from its (partial) columns, the stall among its warnings."""
        values = {f: np.asarray(cols[c], float)[None, :] for c, f in SECTION_NONLINEAR_FIELDS.items()}
        r = self._batch([design], pressures, load, values, options=options)[0]
        if isinstance(error, SectionConvergenceError):
            r = dataclasses.replace(r, warnings=(*r.warnings, f"walk stopped short: {error}"))
        return r


#: The finite-strain section model.
SECTION_NONLINEAR = SectionNonlinearTier(
    "section-nonlinear",
    "the finite-strain section model",
    "finite-strain section model",
    "finite-strain section model: valid at large bends, ~1 s a design and load",
    "section_nonlinear",
    # each option is section_curve's keyword of its name (the evaluator's table)
    options=SECTION_NONLINEAR_OPTIONS,
    option_choices={"coil_bound": (False, True)},
    option_bounds={
        "silicone_poisson": OptionBound(0.0, NU_MAX),
        "coil_axial_scale": OptionBound(0.0, COIL_AXIAL_SCALE_MAX, open_low=True),
        "tube_prestretch": OptionBound(1.0, PRESTRETCH_MAX),
        "tube_squeeze": OptionBound(0.0, 1.0),
    },
    # its walk through a few pressures against one linear solve: about fifteen Newton iterations of a
    # tangent twice the linear model's size (~1 s for the paper section), 30x the section's cost
    dof_seconds=30.0 * 1.05e-5,
    seconds_per_design=1.0,
    section_mesh=True,
    # the tip as built on the reference path (fem.section_model.finite_strain.as_built)
    as_built=True,
)
