r"""The tube pre-stretched as built: its law at :math:`F F_\text{pre}` and the rest state it makes.

The tip is built by pulling the silicone tube through the coil and sealing its
ends, so the fitted (as-built) tube is the catalogue tube stretched axially by
:math:`\lambda_\text{pre}` (incompressible: catalogue wall area over as-built
wall area). The as-built section stays the model's reference; the tube's
stress-free state is the catalogue tube, reached from the reference by
:math:`F_\text{pre}^{-1}` with

.. math::

    F_\text{pre} = \operatorname{diag}(\lambda_\text{pre}^{-1/2},\,
    \lambda_\text{pre}^{-1/2},\, \lambda_\text{pre}).

Since :math:`\det F_\text{pre} = 1` the energy per as-built volume is
:math:`W(F F_\text{pre})`; the first Piola-Kirchhoff stress is
:math:`P_0(F F_\text{pre}) F_\text{pre}^T` and the tangent
:math:`A_{iJkL} = A^0_{iMkN} F^\text{pre}_{JM} F^\text{pre}_{LN}`. The volumetric
energy depends on :math:`J = \det F` only, so a law that splits it off keeps
its split unchanged.

The sealed tube pulls; the coil takes the pull in compression and, the tube
lying off the section's axial-stiffness centroid, the tip bends at rest
(:func:`rest_state`: Newton at zero pressure, :math:`\lambda_\text{pre}` ramped
from 1 when a full step fails).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.geometry import TUBE
from softcath.fem.hyperelastic.laws import IsotropicLaw
from softcath.fem.section_model.finite_strain.newton import (
    Loading,
    SectionConvergenceError,
    SectionProblem,
    State,
    factorise,
    pressures_after,
    residual_tangent,
)

__all__ = [
    "PRESTRETCH_MAX",
    "PreDeformed",
    "Prestretched",
    "check_prestretch",
    "prestretched_laws",
    "ramped_rest_state",
    "rest_state",
]

log = logging.getLogger(__name__)

#: Largest tube pre-stretch accepted: past the sister prototypes' catalogue/as-built ratio (3.8).
PRESTRETCH_MAX = 4.0


def check_prestretch(value) -> float:
    """``value`` as a float in [1, :data:`PRESTRETCH_MAX`], else a :class:`DesignError` naming it."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DesignError("tube_prestretch", value, "must be a number in [1, 4]") from None
    if not (math.isfinite(v) and 1.0 <= v <= PRESTRETCH_MAX):
        raise DesignError("tube_prestretch", value, f"must be in [1, {PRESTRETCH_MAX:g}] (1: no pre-stretch)")
    return v


class PreDeformed:
    """What a law evaluated at F F_pre takes from its base law ``law`` unchanged: the moduli, the
    volumetric split and the small-strain tensor (the section's stiffness-weighted centroid and the
    reported Poisson ratio stay those of the undeformed material)."""

    law: IsotropicLaw

    @property
    def splits_volume(self) -> bool:
        return bool(getattr(self.law, "splits_volume", False))

    @property
    def bulk_modulus(self) -> float:
        return self.law.bulk_modulus

    @property
    def shear_modulus(self) -> float:
        return self.law.shear_modulus

    def small_strain_tensor(self) -> np.ndarray:
        return self.law.small_strain_tensor()


@dataclass(frozen=True)
class Prestretched(PreDeformed):
    """A finite-strain law evaluated at F F_pre: the as-built tube stretched by ``stretch`` from its
    stress-free (catalogue) state.

    Its small-strain tensor is the base law's (the section's stiffness-weighted centroid and the
    reported Poisson ratio stay those of the unstretched material).
    """

    law: IsotropicLaw
    stretch: float

    @property
    def diagonal(self) -> np.ndarray:
        """The diagonal of F_pre in (x, y, z)."""
        s = float(self.stretch)
        return np.array([s**-0.5, s**-0.5, s])

    def energy(self, f: np.ndarray, *, volumetric: bool = True) -> np.ndarray:
        """W(F F_pre) per as-built volume [MPa]."""
        return self.law.energy(f * self.diagonal, volumetric=volumetric)

    def stress_tangent(self, f: np.ndarray, *, volumetric: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """P = P0(F F_pre) F_pre^T and A[i, J, k, L] = A0[i, J, k, L] d_J d_L (F_pre = diag(d))."""
        dg = self.diagonal
        p0, a0 = self.law.stress_tangent(f * dg, volumetric=volumetric)  # F diag(d): columns scaled
        return p0 * dg, a0 * dg[:, None, None] * dg[None, None, :]


def prestretched_laws(laws: dict, stretch: float) -> dict:
    """``laws`` with the tube's law pre-stretched by ``stretch`` (the same dict at 1)."""
    if stretch == 1.0:
        return dict(laws)
    base = laws[TUBE]
    base = base.law if isinstance(base, Prestretched) else base
    return {**laws, TUBE: Prestretched(base, float(stretch))}


def _at(problem: SectionProblem, stretch: float) -> SectionProblem:
    """``problem`` with its tube pre-stretched by ``stretch``."""
    disc = replace(problem.disc, laws=prestretched_laws(problem.disc.laws, stretch))
    return replace(problem, disc=disc)


def _newton(problem: SectionProblem, q0: np.ndarray, *, tol: float, max_iter: int):
    """Newton at zero load from ``q0``; converged when the residual falls by ``tol`` from the
    pre-stretch's unbalanced force (or to round-off). Returns the :class:`State` or None."""
    loading = Loading(pressure=0.0)
    free = problem.free
    q, pressure, first = q0.copy(), None, None
    for it in range(1, max_iter + 1):
        r, k, _, tan = residual_tangent(problem, q, loading, 0.0, pressure)
        if r is None or k is None:  # (both None together: an inverted state)
            return None
        norm = float(np.linalg.norm(r[free]))
        first = norm if first is None else first
        floor = np.finfo(float).eps * float(abs(k).sum(axis=1).max()) * problem.size
        if norm <= max(tol * first, floor):
            return State(q, 0.0, it - 1, norm / max(first, 1e-300), tan.max_strain)
        if not np.isfinite(norm):
            return None
        try:
            dq = factorise(problem, k).solve(-r[free])
        except RuntimeError:
            return None
        if not np.all(np.isfinite(dq)):
            return None
        step = np.zeros_like(q)
        step[free] = dq
        pressure = pressures_after(problem, tan, step)
        q = q + step
    return None


def rest_state(
    problem: SectionProblem, stretch: float, *, tol: float = 1e-9, max_iter: int = 25, min_step: float = 1e-2
) -> tuple[SectionProblem, State]:
    """The pre-stretched ``problem`` and its equilibrium at zero pressure.

    ``problem`` carries the laws without pre-stretch; the stretch is ramped from 1 (a full step
    first, halved after a failure). Raises :class:`SectionConvergenceError` naming the stretch
    reached when the step falls below ``min_step``.
    """
    return ramped_rest_state(
        lambda s: _at(problem, s),
        (1.0, stretch),
        name="tube_prestretch",
        tol=tol,
        max_iter=max_iter,
        min_step=min_step,
    )


def ramped_rest_state(
    at: Callable[[float], SectionProblem],
    span: tuple[float, float],
    *,
    name: str,
    tol: float = 1e-9,
    max_iter: int = 25,
    min_step: float = 1e-2,
) -> tuple[SectionProblem, State]:
    """``at(target)`` and its equilibrium at zero pressure, the parameter ramped over ``span``.

    Parameters
    ----------
    at
        The problem at a value of the parameter (``at(start)`` is stress-free at rest).
    span
        ``(start, target)``: a full step to the target first, halved after a failure.
    name
        The parameter's name: :class:`SectionConvergenceError` names it and the value reached
        when the step falls below ``min_step``.
    """
    start, target = (float(v) for v in span)
    q = at(start).initial_state()
    done, step = start, target - start
    state = State(q, 0.0, 0, 0.0, 0.0)
    spent = 0
    while done < target:
        trial = min(done + step, target)
        got = _newton(at(trial), state.q, tol=tol, max_iter=max_iter)
        if got is None:
            step /= 2
            if step < min_step:
                raise SectionConvergenceError(done, target, name)
            log.debug("%s: cut back to step %.3g at %.4g", name, step, done)
            continue
        spent += got.iterations
        state, done = got, trial
    log.info("%s %.4g: rest state in %d Newton iterations", name, target, spent)
    return at(target), replace(state, iterations=spent)
