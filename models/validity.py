"""Where a tier's answer holds: the bend range of each tier and the warnings past it (one place).

The linear models (the paper's composite beam, the linear section model and the linear
FEM) are small-deflection, small-strain models driven by a positive lumen pressure.
docs/nonlinear.md measures where they stop holding for the paper design: the linear FEM
departs from the finite-strain FEM by 5 % at about 5° of bend (lumen load; about 1° under
the cap load), and the sweeps' silicone strain limit is 0.3. A tier's
:attr:`~softcath.models.Tier.valid_to_deg` is :data:`LINEAR_BEND_LIMIT_DEG` for a linear tier
and infinite for a finite-strain one; every tier stops at self-contact
(:data:`SELF_CONTACT_DEG`), which no model of softcath represents.
:mod:`softcath.studies.model_validity` re-exports these for the command line's checks.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "LINEAR_BEND_LIMIT_DEG",
    "SELF_CONTACT_DEG",
    "SILICONE_STRAIN_LIMIT",
    "linear_range_warnings",
    "response_warnings",
    "self_contact_warning",
]

#: Bend angle beyond which the linear models depart from finite strain by ≳ 5 % (docs/nonlinear.md).
LINEAR_BEND_LIMIT_DEG = 5.0
#: The silicone strain limit the sweeps use by default (``softcath.studies.sweep.spec``).
SILICONE_STRAIN_LIMIT = 0.3
#: Bend angle of a uniform arc past which the tip passes through itself (a full turn: the arc's end
#: meets its start). No model of softcath has self-contact, so its numbers beyond are not physical.
SELF_CONTACT_DEG = 360.0


def self_contact_warning(pressures, bend_angle_rad, *, model: str) -> str | None:
    """The message for a bend past :data:`SELF_CONTACT_DEG` (the tip passing through itself), or None."""
    p = np.atleast_1d(np.asarray(pressures, dtype=float))
    theta = np.degrees(np.abs(np.atleast_1d(np.asarray(bend_angle_rad, dtype=float))))
    if p.shape != theta.shape:
        p = np.full(theta.shape, np.nan)
    past = np.isfinite(theta) & (theta > SELF_CONTACT_DEG)
    if not past.any():
        return None
    first = int(np.argmax(past))
    where = f" from {p[first]:g} MPa" if np.isfinite(p[first]) else ""
    return (
        f"bend {np.nanmax(theta):.4g} deg is past {SELF_CONTACT_DEG:g} deg{where}: the tip would pass "
        f"through itself; {model} has no self-contact, so its answers there are not physical"
    )


def linear_range_warnings(
    pressures, bend_angle_rad, *, max_strain=None, elongation=None, model: str = "the linear model"
) -> list[str]:
    """Messages for every way ``pressures`` and the linear results leave the linear model's validity."""
    p = np.atleast_1d(np.asarray(pressures, dtype=float))
    msgs = []
    if np.any(p < 0):
        msgs.append(
            f"negative pressure ({p.min():g} MPa): {model} assumes an inflating lumen "
            "(p >= 0); suction and lumen collapse are not modelled"
        )
    theta = np.degrees(np.abs(np.atleast_1d(np.asarray(bend_angle_rad, dtype=float))))
    theta = theta[np.isfinite(theta)]
    if theta.size and theta.max() > LINEAR_BEND_LIMIT_DEG:
        msgs.append(
            f"bend {theta.max():.3g} deg is beyond the ~{LINEAR_BEND_LIMIT_DEG:g} deg where {model} "
            "departs from finite strain by 5 %; use `softcath fem --nonlinear` for large bends"
        )
    contact = self_contact_warning(p, bend_angle_rad, model=model)
    if contact:
        msgs.append(contact)
    if max_strain is not None:
        e = np.atleast_1d(np.asarray(max_strain, dtype=float))
        e = e[np.isfinite(e)]
        if e.size and e.max() > SILICONE_STRAIN_LIMIT:
            msgs.append(
                f"silicone strain {e.max():.3g} exceeds the small-strain limit {SILICONE_STRAIN_LIMIT:g} "
                "of the linear model; use `softcath fem --nonlinear`"
            )
    if elongation is not None:
        e = np.atleast_1d(np.asarray(elongation, dtype=float))
        e = e[np.isfinite(e)]
        if e.size and np.abs(e).max() > SILICONE_STRAIN_LIMIT:
            worst = float(e[np.argmax(np.abs(e))])
            what = " (a length <= 0)" if worst <= -1 else ""
            msgs.append(
                f"elongation {worst:.3g}{what} is beyond the small-strain limit ±{SILICONE_STRAIN_LIMIT:g} "
                f"of {model}; use `softcath fem --nonlinear`"
            )
    return msgs


def response_warnings(
    tier, pressures, bend_angle_rad, *, max_strain=None, elongation=None
) -> tuple[str, ...]:
    """The validity warnings of one response of ``tier`` (a :class:`~softcath.models.Tier`).

    A tier valid to a finite bend (a linear tier) gets every message of
    :func:`linear_range_warnings`; a finite-strain tier only the self-contact one.
    """
    if math.isfinite(tier.valid_to_deg):
        return tuple(
            linear_range_warnings(
                pressures, bend_angle_rad, max_strain=max_strain, elongation=elongation, model=tier.label
            )
        )
    msg = self_contact_warning(pressures, bend_angle_rad, model=tier.label)
    return (msg,) if msg else ()
