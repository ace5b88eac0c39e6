"""Coil homogenisations of the section model, and what each gives the coil alone.

A coil's homogenised annulus enters the section model through two numbers
only, because its law has no axial/in-plane Poisson coupling (nu_c = 0,
``softcath.fem.adapter``): the axial modulus E_z weights the axial strain
eps_zz = eps_0 + k_1 x + k_2 y, so it contributes E_z * int phi phi^T dA
(phi = (1, x, y)) to the global block of the section stiffness and nothing
to the in-plane blocks. The coil's own bending beyond E_z * I_annulus is a
pure couple (``solve(..., extra_bending=...)``). The models
(:data:`COIL_MODELS`):

- ``annulus``: E_z = E_t = k L / A, the spring rate (the paper's E_eq; the 3-D
  FEM's default). Own EI = E_t I_a, 0.45x (outer coil) / 0.49x (channel) of Wahl;
- ``annulus-bending``: E_z = EI_Wahl / I_a: own EI right, EA 2.2x / 2.0x too stiff;
- ``wahl``: E_t plus the rest of Wahl's EI as a couple (the paper's formula);
- ``resolved``: EA and open-coil EI of the resolved wire (``softcath.fem.coil``), from
  the exact helix energies (``softcath.fem.coil.closed_forms``: shear-flexible rod with
  the helix angle, which the resolved wire reproduces to its 0.4 % chord
  error): E_z = EA_helix / A, couple EI_helix - E_z I_a. It differs from
  ``wahl`` where the spring-rate formula fails: the channel's D/d = 3 (direct
  shear, EA 0.94x the spring rate).

With contact between turns (coil-bound compression, initial tension) the
law is bilinear: ``softcath.fem.section_model.bilinear``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from softcath import design as design_pkg
from softcath.design import coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.coil.closed_forms import helix_axial_energy, helix_bending_energy
from softcath.fem.coil.stiffness import coil_wire
from softcath.fem.geometry import CHANNEL, COIL
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.laws import SectionLaw, section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS, catheter_section_mesh

__all__ = [
    "COIL_MODELS",
    "model_options",
    "helix_stiffness",
    "with_axial_modulus",
    "coil_terms",
    "coil_section_stiffness",
]

#: Coil homogenisations, each -> the (coil_modulus, coil_bending) pair of ``section_model``.
COIL_MODELS = {
    "annulus": ("tension", "annulus"),
    "annulus-bending": ("bending", "annulus"),
    "wahl": ("tension", "wahl"),
    "resolved": ("tension", "resolved"),
}


def model_options(coil_model: str) -> dict[str, str]:
    """``section_model`` keywords (coil_modulus, coil_bending) of a :data:`COIL_MODELS` name."""
    if coil_model not in COIL_MODELS:
        raise DesignError("coil_model", coil_model, f"must be one of {tuple(COIL_MODELS)}")
    modulus, bending = COIL_MODELS[coil_model]
    return {"coil_modulus": modulus, "coil_bending": bending}


def helix_stiffness(coil) -> tuple[float, float]:
    """(EA [N], EI [N mm^2]) per unit length of the open coil from the exact helix energies."""
    wire = coil_wire(coil)
    r, p = coil.mean_radius, coil.pitch
    return helix_axial_energy(wire, radius=r, pitch=p), helix_bending_energy(wire, radius=r, pitch=p)


def with_axial_modulus(law: SectionLaw, axial_modulus: float) -> SectionLaw:
    """``law`` with another axial modulus (valid for laws without axial/in-plane coupling)."""
    d = np.array(law.D, dtype=float)
    if np.any(d[2, [0, 1, 3]] != 0) or np.any(d[[0, 1, 3], 2] != 0):
        raise DesignError("law", "coupled", "the axial modulus can be replaced only without Poisson coupling")
    d[2, 2] = axial_modulus
    return SectionLaw(d, law.lam, float(axial_modulus), law.poisson_ratio)


def coil_terms(design, coil_bending: str, laws: Mapping[int, SectionLaw]) -> tuple[dict, dict]:
    """(laws with the coils' axial moduli of the model, region label -> couple EI [N mm^2]).

    The couples add to both bending axes of the section.

    ``laws`` are the section laws with the ``coil_modulus`` already chosen;
    ``coil_bending`` is ``annulus`` (no couple), ``wahl`` or ``resolved``.
    """
    out = dict(laws)
    extra = {COIL: 0.0, CHANNEL: 0.0}
    for coil, label in ((design.coil, COIL), (design.channel, CHANNEL)):
        k = coil_stiffness(coil)
        if coil_bending == "wahl":
            extra[label] = k.bending_stiffness - laws[label].axial_modulus * k.second_moment
        elif coil_bending == "resolved":
            ea, ei = helix_stiffness(coil)
            out[label] = with_axial_modulus(laws[label], ea / k.area)
            extra[label] = ei - ea / k.area * k.second_moment
    return out, extra


def coil_section_stiffness(
    design, *, coil_model: str = "annulus", mesh_size: float | None = None, segments: int | None = None
) -> dict[str, dict[str, float]]:
    """What each coil carries in the section model: ``coil``/``channel`` -> EA [N], EI [N mm^2], y [mm].

    EA = int E_z dA over the coil's meshed annulus, EI about its own
    E_z-weighted centre y plus the model's couple: the coil's share of the
    section stiffness (its axial modulus enters nowhere else, module docstring).
    """
    d = design_pkg.resolve(design)
    opts = model_options(coil_model)
    laws, extra = coil_terms(
        d, opts["coil_bending"], section_laws_from_design(d, coil_modulus=opts["coil_modulus"])
    )
    mesh = catheter_section_mesh(
        geometry_from_design(d),
        mesh_size=MESH_SIZE if mesh_size is None else mesh_size,
        segments=SEGMENTS if segments is None else segments,
    )
    op = assemble(mesh, laws)
    w = op.basis.dx
    _, yq = np.asarray(op.basis.global_coordinates())
    out = {}
    for name, label in (("coil", COIL), ("channel", CHANNEL)):
        sel = np.asarray(mesh.labels) == label
        ew = op.D[sel, 2, 2][:, None] * w[sel]
        ea = float(ew.sum())
        yc = float((ew * yq[sel]).sum() / ea)
        ei = float((ew * (yq[sel] - yc) ** 2).sum()) + extra[label]
        out[name] = {"EA_N": ea, "EI_N_mm2": ei, "y_mm": yc}
    return out
