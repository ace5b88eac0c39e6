"""From a :class:`design.TipDesign` to what the FEM meshes and solves.

Homogenised coils (outer coil and hollow channel) are transversely isotropic
annuli (axis z), from :func:`design.coil_stiffness`:

- hoop / in-plane modulus E_T = E_wire * phi (the wire runs around: this is
  what confines the silicone), in-plane Poisson ratio = the wire's;
- axial modulus E_L: ``coil_modulus="tension"`` (default) uses the spring's
  tension modulus k L / A, the paper's E_eq, so the section's axial stiffness
  EA and neutral axis match the analytic model. A homogenised annulus then
  bends about its own centre with E_L * I_annulus, which is 0.45x (outer
  coil) and 0.49x (channel) of the helical-spring (Wahl) bending stiffness the
  analytic model uses; no positive axial modulus distribution over the
  annulus can give both (Wahl's EI/EA exceeds r_o^2/2, the largest I/A of
  any annulus fibre). ``coil_modulus="bending"`` uses EI_Wahl / I_annulus
  instead: own bending right, EA too high. The difference between the two
  is reported, not hidden (docs/fem.md).
- axial shear modulus E_L / (2 (1 + nu_wire)): the tip carries no transverse
  shear force under pressure (pure moment + axial force), so it barely matters;
- no axial/in-plane Poisson coupling (nu_c = 0): a spring's diameter barely
  changes when it is stretched, and any coupling against the stiff hoop
  stiffens the axis: nu_c = 0.29 made the coils 31 % stiffer axially
  (C_zz = E_L / (1 - 2 nu_c^2 / (1 - nu_TT))), an artefact.
"""

from __future__ import annotations

from softcath.design import TipDesign, coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.geometry import CHANNEL, COIL, FILLER, TUBE, TipGeometry
from softcath.fem.materials import Isotropic, TransverselyIsotropic

__all__ = [
    "geometry_from_design",
    "fem_laws_from_design",
    "coil_law",
    "silicone_parameters",
    "COIL_MODULI",
    "NU_CAP",
]

COIL_MODULI = ("tension", "bending")
#: Largest Poisson ratio the displacement-only P2 elements take without locking.
NU_CAP = 0.49


def geometry_from_design(design: TipDesign, *, land_gap: float = 0.01) -> TipGeometry:
    """The as-assembled geometry of ``design`` (mm) in the FEM's terms."""
    s = design.section
    return TipGeometry(
        coil_outer_radius=s.coil_outer_radius,
        coil_inner_radius=s.coil_inner_radius,
        channel_outer_radius=s.channel_outer_radius,
        channel_inner_radius=s.channel_inner_radius,
        channel_y=s.channel_center_y,
        tube_a=s.a,
        tube_b=s.b,
        tube_y=s.tube_center_y,
        lumen_a=s.a_int,
        lumen_b=s.b_int,
        lumen_y=s.lumen_center_y,
        length=design.tip.bending_length,
        cap_thickness=design.tip.cap_thickness,
        filled=design.filler is not None and design.assembly.filler != "none",
        filler_coat=design.assembly.filler_coat_thickness if design.assembly.filler == "coat" else 0.0,
        land_gap=land_gap,
    )


def coil_law(coil, coil_modulus: str) -> TransverselyIsotropic:
    """The homogenised transversely isotropic law of ``coil`` (module docstring)."""
    k = coil_stiffness(coil)
    nu = coil.material.poisson_ratio
    e_axial = k.axial_modulus_tension if coil_modulus == "tension" else k.bending_modulus
    return TransverselyIsotropic(
        axial_modulus=e_axial,
        transverse_modulus=k.hoop_modulus,
        transverse_poisson=nu,
        coupling_poisson=0.0,
        axial_shear_modulus=e_axial / (2 * (1 + nu)),
    )


def fem_laws_from_design(design: TipDesign, *, coil_modulus: str = "tension") -> dict[int, object]:
    """Region label -> 3-D elastic law (isotropic or homogenised coil) for ``design``.

    The 3-D FEM's laws; the section model's are
    :func:`softcath.fem.section_model.laws.section_laws_from_design`.
    Poisson ratios are capped at :data:`NU_CAP` (displacement-only P2 locks above).
    """
    if coil_modulus not in COIL_MODULI:
        raise DesignError("coil_modulus", coil_modulus, f"must be one of {COIL_MODULI}")

    def iso(m):
        return Isotropic(m.youngs_modulus, min(m.poisson_ratio, NU_CAP))

    laws = {
        COIL: coil_law(design.coil, coil_modulus),
        CHANNEL: coil_law(design.channel, coil_modulus),
        TUBE: iso(design.tube.material),
    }
    if design.filler is not None:
        laws[FILLER] = iso(design.filler)
    return laws


def silicone_parameters(design: TipDesign) -> dict[str, dict]:
    """The silicones' moduli and Poisson ratios the FEM uses, next to the design's (``capped``).

    A silicone with nu above :data:`NU_CAP` is solved at the cap: a nearly incompressible
    silicone (nu = 0.4999) gets the nu = 0.49 answer, which the section model, taking
    nu up to 0.49999, shows is too compliant. The FEM states this instead of hiding it.
    """
    regions = {"tube": design.tube.material}
    if design.filler is not None:
        regions["filler"] = design.filler
    return {
        name: {
            "material": m.name,
            "youngs_modulus_MPa": float(m.youngs_modulus),
            "poisson_ratio_design": float(m.poisson_ratio),
            "poisson_ratio_used": float(min(m.poisson_ratio, NU_CAP)),
            "capped": bool(m.poisson_ratio > NU_CAP),
        }
        for name, m in regions.items()
    }
