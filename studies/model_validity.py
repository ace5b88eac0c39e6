"""Range checks for the command line: refuse overflowing results, warn where a model leaves its validity.

The linear models (the paper's composite beam and the linear FEM) are small-deflection,
small-strain models driven by a positive lumen pressure. docs/nonlinear.md measures where
they stop holding for the paper design: the linear FEM departs from the finite-strain FEM
by 5 % at about 5° of bend (lumen load; about 1° under the cap load), and the sweeps'
silicone strain limit is 0.3. Beyond those, a linear answer is not wrong arithmetic but a
wrong model: the command still answers, and says so on stderr with the way out
(``softcath fem --nonlinear``).
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np

from softcath.core.limits import MAX_PRESSURE_MPA, check_pressure
from softcath.design.errors import DesignError
from softcath.models import TIERS, linear_names
from softcath.models.validity import (
    LINEAR_BEND_LIMIT_DEG,
    SELF_CONTACT_DEG,
    SILICONE_STRAIN_LIMIT,
    linear_range_warnings,
    self_contact_warning,
)

__all__ = [
    "LINEAR_BEND_LIMIT_DEG",
    "SILICONE_STRAIN_LIMIT",
    "check_finite_columns",
    "MAX_PRESSURE_MPA",
    "check_pressure",
    "linear_range_warnings",
    "linear_tier_warning",
    "warn_linear_range",
    "SELF_CONTACT_DEG",
    "self_contact_warning",
    "warn_self_contact",
    "check_measured_pressures",
    "self_contact_reasons",
    "fail_self_contact",
]

log = logging.getLogger("softcath.validity")


def check_finite_columns(columns: Mapping[str, object], *, param: str, value: object) -> None:
    """Refuse results with NaN or infinities (an overflow from an extreme input)."""
    for name, col in columns.items():
        arr = np.asarray(col, dtype=float)
        if not np.all(np.isfinite(arr)):
            raise DesignError(param, value, f"gives a non-finite {name} (overflow); use a smaller value")


#: Measured pressures above this multiple of a model's highest pressure are refused as a unit mistake
#: (a file in bar reads 10x the MPa); above :data:`_MEASURED_WARN_RATIO` they are named in a warning.
_MEASURED_REFUSE_RATIO = 5.0
_MEASURED_WARN_RATIO = 1.5


def warn_self_contact(pressures, bend_angle_rad, *, model: str) -> bool:
    """Log :func:`self_contact_warning` as a warning; True when the bend passed a full turn."""
    msg = self_contact_warning(pressures, bend_angle_rad, model=model)
    if msg:
        log.warning(msg)
    return msg is not None


def self_contact_reasons(df, column: str = "bend_angle_deg") -> dict[int, str]:
    """``{design_id: reason}`` of the designs in a results table whose bend passes a full turn.

    The table's ``column`` (degrees) is the model's bend; a design past :data:`SELF_CONTACT_DEG`
    at any of its pressures passes through itself there, which no model of softcath represents.
    """
    if column not in df.columns or df.empty:
        return {}
    theta = np.abs(df[column].to_numpy(float))
    past = np.isfinite(theta) & (theta > SELF_CONTACT_DEG)
    out: dict[int, str] = {}
    for i in np.flatnonzero(past):
        did = int(df["design_id"].iloc[i])
        if did not in out:
            out[did] = (
                f"bend {theta[i]:.4g} deg at {float(df['pressure_MPa'].iloc[i]):g} MPa is past "
                f"{SELF_CONTACT_DEG:g} deg: the tip passes through itself (self-contact is not modelled)"
            )
    return out


def fail_self_contact(df, column: str = "bend_angle_deg"):
    """``df`` with the designs of :func:`self_contact_reasons` marked failed, with their reason."""
    reasons = self_contact_reasons(df, column)
    if not reasons:
        return df
    df = df.copy()
    hit = df["design_id"].isin(list(reasons)).to_numpy()
    df.loc[hit, "status"] = "failed"
    df.loc[hit, "reason"] = df.loc[hit, "design_id"].map(reasons)
    return df


def check_measured_pressures(measured_MPa, model_top_MPa: float, *, param: str, value: object) -> None:
    """Refuse a measurement drawn against a model whose pressures it far exceeds (bar read as MPa).

    A measurement's ``pressure_MPa`` reaching more than 5x the model's highest pressure is
    refused (a file in bar reads 10x); more than 1.5x is said in a warning (the model is not
    drawn there).

    Raises
    ------
    DesignError
        Naming ``param`` (the measurement option) with the measured and the model's range.
    """
    p = np.asarray(measured_MPa, dtype=float)
    p = p[np.isfinite(p)]
    top = float(model_top_MPa)
    if p.size == 0 or not top > 0:
        return
    high = float(np.abs(p).max())
    ratio = high / top
    if ratio > _MEASURED_REFUSE_RATIO:
        raise DesignError(
            param,
            value,
            f"its pressure_MPa reaches {high:g}, {ratio:.3g}x the model's highest {top:g} MPa: is the file "
            "in bar (1 bar = 0.1 MPa) or kPa? convert pressure_MPa to MPa, or compute the model to "
            "the measured pressures",
        )
    if ratio > _MEASURED_WARN_RATIO:
        log.warning(
            "the measurement %s reaches %g MPa, %.3gx the model's highest %g MPa: the model is not drawn "
            "beyond %g MPa",
            value,
            high,
            ratio,
            top,
            top,
        )


#: The small-rotation tiers: valid to :data:`LINEAR_BEND_LIMIT_DEG` of bend (:attr:`Tier.valid_to_deg`).
LINEAR_TIERS = linear_names()


def linear_tier_warning(
    model: str, bend_deg: float, pressure_MPa: float, *, how: str, way_out: str
) -> str | None:
    """The message when a linear tier is asked about bends past its validity, or None.

    Parameters
    ----------
    model
        The tier's name (only :data:`LINEAR_TIERS` can be out of range).
    bend_deg
        The largest bend [deg] the question involves.
    pressure_MPa
        The pressure [MPa] of that bend.
    how
        Where ``bend_deg`` comes from (e.g. "designs in the --vary box, by the paper's formula").
    way_out
        What to do instead (e.g. "give --model section-nonlinear").
    """
    tier = TIERS.get(model)
    if tier is None or not np.isfinite(bend_deg) or abs(bend_deg) <= tier.valid_to_deg:
        return None
    return (
        f"{tier.label} ({model}) is a linear tier, valid to ~{tier.valid_to_deg:g} deg of bend, "
        f"but {how} bend up to {abs(bend_deg):.3g} deg at {pressure_MPa:g} MPa: its values there are off "
        f"by more than 5 %; {way_out}"
    )


def warn_linear_range(
    pressures, bend_angle_rad, *, max_strain=None, elongation=None, model: str = "the linear model"
) -> None:
    """Log each :func:`linear_range_warnings` message as a warning (stderr, one line each)."""
    for msg in linear_range_warnings(
        pressures, bend_angle_rad, max_strain=max_strain, elongation=elongation, model=model
    ):
        log.warning(msg)
