"""Resolved-wire coil: the helical wire as a 3-D frame, with contact between turns.

>>> from softcath import design
>>> from softcath.fem.coil import resolved_coil_stiffness
>>> r = resolved_coil_stiffness(design.resolve("paper").coil)
>>> round(r.bending_contact / r.bending, 2)   # turns pivot on the concave edge
1.88

numpy/scipy only. Modules: ``helix`` (geometry), ``frame`` (Timoshenko beam
elements), ``contact`` (penalty contact, active set), ``model`` (periodic
cell / end plates), ``closed_forms``, ``api``, ``sections`` (homogenised
models for comparison), ``picture``.
"""

from __future__ import annotations

from softcath.fem.coil.stiffness import CoilStiffnessResult, bending_curve, coil_wire, resolved_coil_stiffness

__all__ = ["CoilStiffnessResult", "bending_curve", "coil_wire", "resolved_coil_stiffness"]
