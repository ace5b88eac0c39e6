"""The finite-strain section model: large bends of a pressurised tip as a 2-D problem.

Far from the clamp and the cap, a long prismatic tip under a lumen pressure
uniform along its axis bends into a circular arc with the same deformed
cross-section at every arc length. This semi-inverse state (Rivlin's finite
flexure is its one-material case) maps each section by an in-plane field,
stretches it axially by lambda and bends it with curvature k, so equilibrium
is a 2-D nonlinear problem with (lambda, k_1, k_2) as global unknowns. This
package solves it with Newton's method and load stepping on the same
section mesh and regions as the linear section model, with the finite-strain
laws of the 3-D FEM.

Modules: ``discretisation`` (element pair, quadrature data, projection),
``lumen`` (the lumen's volume per unit length, the pressure's potential),
``residual`` (internal forces and tangent), ``newton`` (load stepping),
``prestretch`` (the tube pre-stretched as built and its rest state), ``squeeze`` (the
tube's stress-free state the catalogue annulus: a per-point pre-deformation),
``laws`` (:func:`section_laws`, the regions' finite-strain laws), ``coil_bound`` (a
close-wound coil's axial law: coil-bound in compression, closed up to its initial tension),
``curve`` (:func:`section_curve`, the public entry point).
"""

from __future__ import annotations

from softcath.fem.section_model.finite_strain.curve import SectionCurve, section_curve, section_laws
from softcath.fem.section_model.finite_strain.newton import SectionConvergenceError

__all__ = ["SectionCurve", "SectionConvergenceError", "section_curve", "section_laws"]
