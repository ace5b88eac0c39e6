"""The finite-strain section's laws: :func:`section_laws` (silicones, homogenised coils).

Silicones are the decoupled Yeoh law of ``softcath.fem.nonlinear`` (its fit scaled to the
design's E); coils are Saint Venant-Kirchhoff with the linear section model's homogenised
transversely isotropic tensor, or with ``coil_bound`` the close-wound coils' bilinear axial
law of :mod:`.coil_bound` (coil-bound in compression, closed up to their initial tension).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from softcath.design import coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.adapter import coil_law
from softcath.fem.geometry import CHANNEL, COIL, FILLER, TUBE
from softcath.fem.hyperelastic.laws import AnisotropicSVK, isotropic_from_young, yeoh_at_modulus
from softcath.fem.section_model.finite_strain.coil_bound import CoilBoundSVK
from softcath.fem.section_model.laws import NU_MAX

__all__ = ["COIL_AXIAL_SCALE_MAX", "section_laws"]

#: Largest factor on the outer coil's axial moduli (:func:`section_laws`): two decades past any
#: spring rate a coil's catalogue range spans, well inside the tangent's conditioning.
COIL_AXIAL_SCALE_MAX = 100.0


def _checked(
    design, *, silicone_poisson, hoop_cap, coil_axial_scale, coil_bound, initial_tension, compression_modulus
):
    """Raise :class:`DesignError` (a ``ValueError``) naming the first option out of its bounds."""
    if not isinstance(coil_bound, bool | np.bool_):  # bool("no") would switch it on
        raise DesignError("coil_bound", coil_bound, "must be True or False")
    if silicone_poisson is not None and not (0.0 <= silicone_poisson <= NU_MAX):
        raise DesignError("silicone_poisson", silicone_poisson, f"must be in [0, {NU_MAX}]")
    if hoop_cap is not None and not (np.isfinite(hoop_cap) and hoop_cap > 0):
        raise DesignError("hoop_cap", hoop_cap, "must be finite and > 0 (or None for no cap)")
    if not 0.0 < coil_axial_scale <= COIL_AXIAL_SCALE_MAX:
        raise DesignError("coil_axial_scale", coil_axial_scale, f"must be in (0, {COIL_AXIAL_SCALE_MAX:g}]")
    if initial_tension is not None:
        if not (np.isfinite(initial_tension) and initial_tension >= 0):
            raise DesignError("initial_tension", initial_tension, "must be finite and >= 0 N")
        try:  # the coil's own checks bound an override as they bound the design's value
            replace(design.coil, initial_tension=float(initial_tension))
        except DesignError as exc:
            raise DesignError("initial_tension", initial_tension, exc.bound) from None
    if compression_modulus is not None and not (np.isfinite(compression_modulus) and compression_modulus > 0):
        raise DesignError("compression_modulus", compression_modulus, "must be finite and > 0 MPa")


def section_laws(
    design,
    *,
    silicone_poisson: float | None = None,
    hoop_cap: float | None = None,
    coil_axial_scale: float = 1.0,
    coil_bound: bool = False,
    initial_tension: float | None = None,
    compression_modulus: float | None = None,
) -> dict:
    """Region label -> finite-strain law whose small-strain limit is the linear section model's.

    Silicones: the decoupled Yeoh law of ``softcath.fem.nonlinear``, its fit scaled to the
    design's E (neo-Hookean from E, nu when the material has no Yeoh fit); coils: Saint
    Venant-Kirchhoff with the linear section model's homogenised transversely isotropic tensor.

    Parameters
    ----------
    silicone_poisson
        Replace every silicone's Poisson ratio (e.g. 0.4999 for the incompressible limit).
    hoop_cap
        Cap the coils' hoop modulus at this multiple of the stiffest silicone's E, as the
        3-D finite-strain FEM does for its conditioning (None: no cap).
    coil_axial_scale
        Multiply the outer coil's axial modulus and axial shear modulus by this factor in
        (0, :data:`COIL_AXIAL_SCALE_MAX`] (its axial spring rate scaled; 1: the design's own).
    coil_bound
        Give each close-wound coil the bilinear axial law of :class:`.coil_bound.CoilBoundSVK`
        (False: every coil linear, the laws exactly as without the option). An open coil
        (pitch > wire) stays linear, as in the linear model's bilinear coils.
    initial_tension
        The outer coil's F0 [N] with ``coil_bound`` (None: the design's ``coil.initial_tension``;
        the channel's coil keeps its own), within the coil's own bounds.
    compression_modulus
        The outer coil's coil-bound axial modulus E_c [MPa] with ``coil_bound`` (None: the
        touching turns' E phi, ``design.coil_stiffness(coil).axial_modulus_compression``, the
        linear model's default; it must not be below the scaled tension modulus).
    """
    _checked(
        design,
        silicone_poisson=silicone_poisson,
        hoop_cap=hoop_cap,
        coil_axial_scale=coil_axial_scale,
        coil_bound=coil_bound,
        initial_tension=initial_tension,
        compression_modulus=compression_modulus,
    )
    silicones = [design.tube.material] + ([design.filler] if design.filler is not None else [])
    e_max = max(m.youngs_modulus for m in silicones)

    def silicone(m):
        nu = m.poisson_ratio if silicone_poisson is None else silicone_poisson
        yeoh = yeoh_at_modulus(m.yeoh, youngs_modulus=m.youngs_modulus, poisson_ratio=nu)  # the design's E
        return isotropic_from_young(youngs_modulus=m.youngs_modulus, poisson_ratio=nu, yeoh=yeoh)

    def coil(c, axial_scale=1.0, f0=None, e_c=None):
        law = coil_law(c, "tension")
        if axial_scale != 1.0:  # the outer coil's spring rate as a model parameter
            law = replace(
                law,
                axial_modulus=law.axial_modulus * axial_scale,
                axial_shear_modulus=law.axial_shear_modulus * axial_scale,
            )
        if hoop_cap is not None and law.transverse_modulus > hoop_cap * e_max:
            law = replace(law, transverse_modulus=hoop_cap * e_max)
        if not (coil_bound and c.close_wound):
            return AnisotropicSVK(law.tensor())
        k = coil_stiffness(c)
        force = c.initial_tension if f0 is None else float(f0)
        return CoilBoundSVK(
            law.tensor(),
            compression_modulus=k.axial_modulus_compression if e_c is None else float(e_c),
            prestress=force / k.area,
        )

    laws = {
        COIL: coil(design.coil, coil_axial_scale, initial_tension, compression_modulus),
        CHANNEL: coil(design.channel),
        TUBE: silicone(design.tube.material),
    }
    if design.filler is not None:
        laws[FILLER] = silicone(design.filler)
    return laws
