"""The physical ingredients a built tip can have, each with its sourced range.

An ingredient either changes the finite-strain section model that is solved
(``kind = "model"``: a material, the filler, the coils' initial tension with
coil-bound coils) or acts on its curve in a way that is exact by construction
(``kind = "curve"``: a pressure offset, a rest curvature, the vision's under-read).
A hypothesis may give an ingredient's parameter only values inside its range; the
record says which it chose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

__all__ = ["Ingredient", "INGREDIENTS", "SEPARATING", "tube_prestretch_for", "tube_squeeze_for"]

#: Catalogue over fitted wall area of the sister prototypes' tubes (the authors' scripts: 1.5 mm tip,
#: OD 0.30 -> 0.20 mm, (0.30/0.20)^2; 2.5 mm tip, 0.597/0.3175 -> 0.30/0.15 mm, wall areas).
SISTER_PRESTRETCH = (2.25, 3.79)


@dataclass(frozen=True)
class Ingredient:
    """One candidate cause of a measured curve.

    Attributes
    ----------
    name
        Its name in hypotheses and on the command line.
    kind
        ``"model"`` (a different finite-strain solve) or ``"curve"`` (applied to the solved curve).
    parameter, unit
        The parameter a hypothesis chooses (None for a switch) and its unit.
    low, high
        The sourced range of the parameter.
    source
        Where the range comes from.
    effect
        What it does to the curvature-pressure curve, in words.
    """

    name: str
    kind: str
    parameter: str | None
    unit: str
    low: float
    high: float
    source: str
    effect: str


INGREDIENTS: dict[str, Ingredient] = {
    i.name: i
    for i in (
        Ingredient(
            name="tube_modulus",
            kind="model",
            parameter="tube_youngs_modulus",
            unit="MPa",
            low=1.648,
            high=4.43,
            source="1.648 MPa: the tube modulus of the authors' sister-prototype scripts; 4.43 MPa: "
            "Shore 65A (the top of medical silicone tubing's 50-65A) via Gent's relation",
            effect="scales the silicone's share of the bending stiffness: a softer tube bends more",
        ),
        Ingredient(
            name="coil_spring_rate",
            kind="model",
            parameter="coil_spring_rate",
            unit="N/m",
            low=35.0,
            high=56.0,
            source="35 N/m: the spring constant of the authors' sister-prototype scripts; 56 N/m: "
            "k = G d^4 / (8 D^3 n) of the outer coil (G 77 GPa for 304 stainless, d = 0.1 mm, "
            "D = 0.7 mm, 50 turns over 5 mm); the homogenised annulus has 54.5 N/m",
            effect="the open coil's axial spring: a softer coil lets the tube's pressure bend the tip more",
        ),
        Ingredient(
            name="filler_none",
            kind="model",
            parameter=None,
            unit="",
            low=0.0,
            high=0.0,
            source="the dip coat may not fill the coil (the seed's fabrication paragraph gives no "
            "filling check); a switch, no parameter",
            effect="the tube balloons into the empty coil: the lumen grows with pressure and so does "
            "the cap force, a gain that rises with pressure",
        ),
        Ingredient(
            name="tube_prestretch",
            kind="model",
            parameter="tube_prestretch",
            unit="",
            low=1.0,
            high=SISTER_PRESTRETCH[1],
            source="the fabrication pulls the tube through the coil by a thread and seals its ends; the "
            "sister prototypes' scripts state the stretched tube's size: catalogue/fitted wall area "
            "(0.30/0.20)^2 = 2.25 (1.5 mm tip) and 3.79 (2.5 mm tip); a design with catalogue tube data "
            "takes its own catalogue/as-built wall-area ratio (tube_prestretch_for)",
            effect="the sealed tube pulls and the coil takes the pull: the tip shortens and bends toward "
            "the tube at rest, and the stretched tube's tangent stiffness changes the gain",
        ),
        Ingredient(
            name="tube_squeeze",
            kind="model",
            parameter="tube_squeeze",
            unit="",
            low=0.0,
            high=1.0,
            source="the catalogue tube is a circular annulus, squeezed as built into the elliptical ring "
            "between the coil and the channel; 1 is the whole squeeze (the stress-free state the "
            "catalogue tube), 0 none (tube_squeeze_for: the design's own numbers)",
            effect="the tube's stress-free state is the catalogue annulus: the squeezed tube presses on "
            "the coil and channel and bulges into its lumen, and its thinner wall is a longer tube "
            "that pulls (not with tube_prestretch, which is that pull alone)",
        ),
        Ingredient(
            name="nu_0.4999",
            kind="model",
            parameter=None,
            unit="",
            low=0.0,
            high=0.0,
            source="silicone rubber's Poisson ratio 0.4995-0.4999 (bulk modulus ~1 GPa against a "
            "shear modulus of ~1 MPa); a switch, no parameter",
            effect="near-incompressible silicone transfers more of the wall pressure into bending",
        ),
        Ingredient(
            name="coil_initial_tension",
            kind="model",
            parameter="initial_tension",
            unit="N",
            low=0.0,
            high=0.075,
            source="extension-spring initial-tension stress for the outer coil's index C = D/d = 7: "
            "87-134 MPa (Shigley, tau_i = 33500/exp(0.105 C) +- 1000 (4 - (C - 3)/6.5) psi), "
            "F0 = tau_i pi d^3 / (8 D) <= 0.075 N; 0 for a coil wound without it",
            effect="close-wound turns are coil-bound in compression and stay closed until the load "
            "takes F0 off them: a threshold pressure, then the pivoting section's gain",
        ),
        Ingredient(
            name="pressure_offset",
            kind="curve",
            parameter="pressure_offset",
            unit="MPa",
            low=0.0,
            high=0.21,
            source="the logged pressure at rest, tip at its rest shape: 2.08-2.10 bar; an absolute "
            "gauge read as gauge pressure would add 0.101 MPa; 0 for a gauge zeroed at atmosphere",
            effect="the logged pressure exceeds the lumen's by p0: the curve shifts right (a threshold)",
        ),
        Ingredient(
            name="rest_curvature",
            kind="curve",
            parameter="rest_curvature",
            unit="1/mm",
            low=0.0,
            high=0.03,
            source="the lowest-pressure frames of a recording (kappa ~ 0.024 1/mm, R ~ 40 mm, which "
            "may be the rest shape or the circle fit's floor), with margin",
            effect="a curvature at zero pressure added to the whole curve",
        ),
        Ingredient(
            name="vision_bias",
            kind="curve",
            parameter="vision_factor",
            unit="",
            low=0.60,
            high=0.82,
            source="the paper's edge-based pipeline reads curvature 18-40 % low on rendered frames "
            "up to 120 deg (measured / true = 0.60-0.82)",
            effect="the measured curvature is the true one times the factor",
        ),
    )
}

#: The bench measurement that settles each ingredient directly.
SEPARATING: dict[str, str] = {
    "tube_modulus": "a tensile test of the tube itself (its modulus)",
    "coil_spring_rate": "the coil's own force-extension curve (its spring rate once the turns are open)",
    "filler_none": "a cut section of the tip (is the coil filled?) or the lumen volume against pressure",
    "tube_prestretch": "the tip's length and shape at rest with the line open, against a tip cut free "
    "of its tube (or the tube's length once cut out)",
    "tube_squeeze": "a cut section of the tip (the tube's shape and wall as built) against the catalogue "
    "tube, and the tip's length and shape at rest",
    "nu_0.4999": "the tip's elongation against pressure",
    "coil_initial_tension": "the coil's own force-extension curve (the force at which its turns separate)",
    "pressure_offset": "a run from 0 MPa with the gauge zeroed at atmosphere",
    "rest_curvature": "a photograph of the tip at rest with the line open to atmosphere",
    "vision_bias": "an independent curvature reading (a calibrated arc or a second camera)",
}


def tube_prestretch_for(design) -> Ingredient:
    """The ``tube_prestretch`` ingredient with the range of ``design``'s own tube.

    The incompressible stretch from the catalogue tube to the as-built one is the ratio of their
    wall areas (the catalogue annulus over the as-built ellipse ring); when the as-built wall is
    not the thinner, the sister prototypes' ratios stand.
    """
    ing = INGREDIENTS["tube_prestretch"]
    t, s = design.tube, design.section
    catalogue = math.pi / 4 * (t.catalogue_outer_diameter**2 - t.catalogue_inner_diameter**2)
    built = math.pi * (s.a * s.b - s.a_int * s.b_int)
    ratio = catalogue / built
    if not ratio > 1.0 + 1e-6:
        return ing
    return replace(
        ing,
        high=float(ratio),
        source=f"the catalogue tube's wall ({t.catalogue_outer_diameter:g}/{t.catalogue_inner_diameter:g} "
        f"mm, {catalogue:.4g} mm^2) over the as-built tube's ({built:.4g} mm^2): stretched by up to "
        f"{ratio:.3g} when pulled through the coil by a thread and sealed (incompressible); the sister "
        f"prototypes' scripts give {SISTER_PRESTRETCH[0]:g} and {SISTER_PRESTRETCH[1]:g}",
    )


def tube_squeeze_for(design) -> Ingredient:
    """The ``tube_squeeze`` ingredient with the source of ``design``'s own tube.

    Its range stays [0, 1] (a share of the squeeze); the source states the catalogue annulus and
    the as-built ring it is squeezed into (for a tube built at its catalogue shape the squeeze is
    the identity and the parameter changes nothing).
    """
    ing = INGREDIENTS["tube_squeeze"]
    t, s = design.tube, design.section
    catalogue = math.pi / 4 * (t.catalogue_outer_diameter**2 - t.catalogue_inner_diameter**2)
    built = math.pi * (s.a * s.b - s.a_int * s.b_int)
    outer, inner = t.catalogue_outer_diameter / 2, t.catalogue_inner_diameter / 2
    pairs = zip((s.a, s.b, s.a_int, s.b_int, s.h), (outer, outer, inner, inner, 0.0), strict=True)
    if all(math.isclose(x, y, abs_tol=1e-12) for x, y in pairs):
        return replace(ing, source="the as-built tube is the catalogue annulus: the squeeze is the identity")
    return replace(
        ing,
        source=f"the catalogue annulus ({t.catalogue_outer_diameter:g}/{t.catalogue_inner_diameter:g} mm, "
        f"wall {catalogue:.4g} mm^2) squeezed into the as-built ring (outer {2 * s.a:.3g} x {2 * s.b:.3g} "
        f"mm, lumen {2 * s.a_int:.3g} x {2 * s.b_int:.3g} mm, wall {built:.4g} mm^2): 1 the whole "
        "squeeze, its axial stretch (the wall-area ratio) included",
    )
