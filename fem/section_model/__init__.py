"""The section model: 2-D generalised-plane-strain FEM of the tip's cross-section.

The 3-D FEM's bending of a long prismatic tip is a section property: the
Saint-Venant solution of the cross-section under the cap force and the lumen
pressure, with the axial strain and two curvatures as global unknowns. This
package solves it on the same as-assembled section (regions, bonded lands,
transversely isotropic coils) in a fraction of a second, locking-free up to
nu = 0.49999.

Modules: ``mesh`` (labelled section meshes), ``laws`` (region laws in
generalised plane strain), ``element`` (the element pair and the assembled operator),
``solve`` (condensation and loads), ``api`` (:func:`section_model`),
``template`` (one gmsh mesh per section topology and size class, morphed to
each design), ``batch`` (many designs per template: one vectorised kernel, the
symbolic factorisation reused), ``picture`` (the deformed section coloured by
axial stress), ``coil_models``
(coil homogenisations against the resolved wire), ``fibres`` and
``bilinear`` (coil-bound compression and initial tension:
:func:`bend_curve`, whose record is :class:`BilinearCoilCurve`).
"""

from __future__ import annotations

from softcath.core.deprecation import renamed_names
from softcath.fem.section_model.api import COIL_BENDING, SectionResult, section_model, section_response
from softcath.fem.section_model.bilinear import BilinearCoilCurve, bend_curve
from softcath.fem.section_model.coil_models import COIL_MODELS
from softcath.fem.section_model.solve import LOADS

__all__ = [
    "COIL_BENDING",
    "COIL_MODELS",
    "LOADS",
    "BilinearCoilCurve",
    "SectionResult",
    "bend_curve",
    "section_model",
    "section_response",
]


#: The old name of the bilinear-coil record.
__getattr__ = renamed_names(__name__, BendCurve=BilinearCoilCurve)
