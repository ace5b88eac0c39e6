"""Finite-strain material laws and kinematics, shared by the finite-strain section model and 3-D FEM.

- :mod:`~softcath.fem.hyperelastic.laws`: hyperelastic laws, P(F) and dP/dF (Yeoh, neo-Hookean,
  Saint Venant–Kirchhoff for the coil);
- :mod:`~softcath.fem.hyperelastic.tensors`: determinants and cofactors of batches of 3x3 tensors.

Both finite-strain solvers (:mod:`softcath.fem.section_model.finite_strain` and
:mod:`softcath.fem.nonlinear`) import them from here, below both, so neither imports the other's
package to reach its laws.
"""
