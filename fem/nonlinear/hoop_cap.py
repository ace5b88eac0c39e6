"""What the coils' capped hoop modulus costs: the linear tip angle, capped against the steel hoop.

The finite-strain model caps the coils' hoop (transverse) modulus at
:data:`~softcath.fem.nonlinear.catheter.HOOP_CAP` times the stiffest silicone's E
(:func:`~softcath.fem.nonlinear.catheter.catheter_laws`): the steel value, ~10⁵ MPa,
shrinks Newton's convergence radius through the coil's Green-strain terms. The cap is a
model change, not a discretisation error, so the stated error does not hold it; this
module measures it on the run's own mesh, in the linear range, by solving the unit
pressure once more with the steel hoop. On the paper's design (0.15 mm, 12 segments,
4 layers) the capped tip turns 0.64 % less than the steel one; the finite-strain
section model, which caps nothing by default, sees the same difference with
``hoop_cap=1000`` (tests/fem/nonlinear/test_hoop_cap.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.design import coil_stiffness
from softcath.fem.nonlinear.body import HyperelasticBody
from softcath.fem.nonlinear.catheter import capped_hoop_modulus, catheter_laws
from softcath.fem.nonlinear.linsolve import TangentSolver
from softcath.fem.nonlinear.post import bend_angle

__all__ = ["HoopCapEffect", "hoop_cap_effect", "linear_unit_angle"]


@dataclass(frozen=True)
class HoopCapEffect:
    """The linear tip angle per MPa with the capped and with the steel hoop modulus.

    Attributes
    ----------
    cap
        The cap, as a multiple of the stiffest silicone's Young's modulus (None: uncapped).
    hoop_modulus
        The outer coil's hoop modulus the model uses [MPa] (capped).
    steel_hoop_modulus
        The outer coil's homogenised steel hoop modulus [MPa].
    angle_capped, angle_steel
        dθ/dp of the linear FEM on the same mesh [rad/MPa].
    """

    cap: float | None
    hoop_modulus: float
    steel_hoop_modulus: float
    angle_capped: float
    angle_steel: float

    @property
    def relative(self) -> float:
        """angle_capped / angle_steel − 1: negative when the cap makes the tip stiffer."""
        return self.angle_capped / self.angle_steel - 1.0

    def to_json(self) -> dict:
        return {
            "cap_times_stiffest_silicone": self.cap,
            "hoop_modulus_MPa": self.hoop_modulus,
            "steel_hoop_modulus_MPa": self.steel_hoop_modulus,
            "linear_angle_per_MPa_capped": self.angle_capped,
            "linear_angle_per_MPa_steel": self.angle_steel,
            "relative": self.relative,
            "method": "linear FEM on the run's mesh, unit lumen or cap pressure, capped against steel hoop "
            "modulus; a model change, not part of discretisation_error_estimate",
        }


def linear_unit_angle(body: HyperelasticBody, pressure, fixed: np.ndarray, end: np.ndarray) -> float:
    """dθ/dp [rad/MPa] of the linear FEM: the tangent at zero load under unit ``pressure``.

    ``pressure`` is a :class:`~softcath.fem.nonlinear.body.FollowerPressure` on a body with
    the same mesh; ``fixed`` the constrained DOFs, ``end`` the mask of the tip-end nodes.
    """
    free = np.setdiff1d(np.arange(body.ndofs), fixed)
    mask, tmpl = body.pattern.restrict(free)
    u0 = np.zeros(body.ndofs)
    _, data = body.internal(u0)
    f = np.zeros(body.ndofs)
    pressure.add_to(u0, 1.0, f, np.zeros_like(data))
    k = tmpl.copy()
    k.data = data[mask]
    u = np.zeros(body.ndofs)
    with TangentSolver(tmpl) as lin:
        u[free] = lin(k, -f[free])
    eps = 1e-6 / max(np.abs(u).max(), 1e-300)  # probe the rotation in the small-rotation range
    return bend_angle(body.nodes, eps * u.reshape(-1, 3), end) / eps


def hoop_cap_effect(model) -> HoopCapEffect:
    """The cap's effect on the linear tip angle of a bend model (``NonlinearFemCurve.model``).

    One more body on the model's mesh with the steel hoop and one more factorisation.
    """
    design, cmesh, body = model.design, model.cmesh, model.body
    if model.hoop_cap is None:  # an uncapped model: the steel hoop already, nothing to solve again
        angle_steel = model.linear_unit_angle
    else:
        steel = HyperelasticBody(
            cmesh.mesh, cmesh.labels, catheter_laws(design, hoop_cap=None), mixed=body.mixed
        )
        angle_steel = linear_unit_angle(steel, model.pressure, model.fixed, model.end)
    return HoopCapEffect(
        cap=None if model.hoop_cap is None else float(model.hoop_cap),
        hoop_modulus=float(capped_hoop_modulus(design, design.coil, model.hoop_cap)),
        steel_hoop_modulus=float(coil_stiffness(design.coil).hoop_modulus),
        angle_capped=float(model.linear_unit_angle),
        angle_steel=float(angle_steel),
    )
