"""The parts of the catheter tip: helical coils, the silicone tube, the tip segment.

All lengths in mm. Each class checks its own numbers; the assembled design
(:class:`softcath.design.tip.TipDesign`) checks how the parts fit together.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from softcath.core.errors import DesignError
from softcath.design import validation
from softcath.design.materials import Material

__all__ = ["Coil", "Tube", "Tip"]


def _material(name: str, value: object) -> Material:
    if not isinstance(value, Material):
        raise DesignError(name, value, "must be a design.Material")
    return value


@dataclass(frozen=True, kw_only=True)
class Coil:
    """A close-wound helical coil of round wire (the outer coil or the hollow channel).

    Parameters
    ----------
    outer_diameter, inner_diameter
        Coil OD and ID [mm]; ID < OD.
    wire_diameter
        Wire diameter d [mm]; defaults to (OD − ID)/2, the only value consistent
        with a single layer of round wire.
    pitch
        Axial distance between turns [mm]; defaults to d (close-wound). Must be ≥ d.
    material
        The wire material (isotropic).
    initial_tension
        Initial tension [N] of a close-wound coil: the axial force the coil must
        carry before its turns separate (extension springs are wound with it).
        The turns press on each other with this force when the coil is unloaded.
        Default 0; must be 0 unless the coil is close-wound (pitch = wire_diameter).
    """

    outer_diameter: float
    inner_diameter: float
    material: Material
    wire_diameter: float | None = None
    pitch: float | None = None
    initial_tension: float = 0.0

    def __post_init__(self) -> None:
        od = validation.positive("outer_diameter", self.outer_diameter)
        validation.at_most(
            "outer_diameter", od, validation.MAX_COIL_DIAMETER_MM, "mm: 36 Fr, no catheter is larger"
        )
        idia = validation.positive("inner_diameter", self.inner_diameter)
        validation.less_than("inner_diameter", idia, "outer_diameter", od)
        wire = (od - idia) / 2 if self.wire_diameter is None else self.wire_diameter
        wire = validation.positive("wire_diameter", wire)
        if abs(wire - (od - idia) / 2) > 1e-9 * od:
            raise DesignError(
                "wire_diameter",
                wire,
                f"must equal (outer_diameter - inner_diameter)/2 = {(od - idia) / 2:.6g} "
                "for a single-layer coil",
            )
        index = (od + idia) / 2 / wire
        if index > validation.MAX_SPRING_INDEX:
            raise DesignError(
                "wire_diameter",
                wire,
                f"gives a spring index D/d = {index:.4g}, must be <= "
                f"{validation.MAX_SPRING_INDEX:g} (a wire that thin cannot hold a helix of this diameter)",
            )
        pitch = wire if self.pitch is None else validation.positive("pitch", self.pitch)
        mean_d = (od + idia) / 2
        if pitch > math.pi * mean_d:  # helix angle > 45 deg: a twisted wire, not a coil
            raise DesignError(
                "pitch",
                pitch,
                f"must be <= pi x mean diameter = {math.pi * mean_d:.6g} mm (a helix angle "
                "above 45 deg is no coil)",
            )
        if pitch < wire * (1 - 1e-9):
            raise DesignError("pitch", pitch, f"must be >= wire_diameter = {wire:.6g} (turns cannot overlap)")
        object.__setattr__(self, "outer_diameter", od)
        object.__setattr__(self, "inner_diameter", idia)
        object.__setattr__(self, "wire_diameter", wire)
        object.__setattr__(self, "pitch", pitch)
        tension = validation.nonnegative("initial_tension", self.initial_tension)
        if tension > 0 and pitch > wire * (1 + 1e-9):
            raise DesignError(
                "initial_tension",
                tension,
                f"must be 0 for an open coil (pitch = {pitch:.6g} > wire_diameter = {wire:.6g}: "
                "the turns do not touch)",
            )
        object.__setattr__(self, "initial_tension", tension)
        _material("material", self.material)
        # The wound-in tension twists the wire: 8 F0 D / (pi d^3) beyond its shear strength is no coil.
        f_max = (
            validation.MAX_INITIAL_STRESS_OVER_E
            * self.material.youngs_modulus
            * math.pi
            * wire**3
            / (8 * (od + idia) / 2)
        )
        if tension > f_max:
            raise DesignError(
                "initial_tension",
                tension,
                f"must be <= {f_max:.4g} N: beyond it the wound-in torsional "
                f"stress 8 F0 D/(pi d^3) exceeds {validation.MAX_INITIAL_STRESS_OVER_E:g} E of the wire "
                "(its shear strength)",
            )

    @property
    def close_wound(self) -> bool:
        """Whether neighbouring turns touch (pitch = wire diameter)."""
        return self.pitch <= self.wire_diameter * (1 + 1e-9)

    @property
    def mean_radius(self) -> float:
        """R = (OD + ID)/4 [mm], the helix radius of the wire centre line."""
        return (self.outer_diameter + self.inner_diameter) / 4


@dataclass(frozen=True, kw_only=True)
class Tube:
    """The silicone actuation tube, as catalogued and as squeezed into the coil.

    The catalogue numbers describe the free tube. Inside the catheter the tube
    is squeezed (see :mod:`softcath.design.section`); its as-assembled shape is the
    paper's x = [a, a_int, b_int, h]. Leave those four at ``None`` to use the
    nominal rule of :func:`softcath.design.section.nominal_tube_shape`, or give all four
    to fix the shape (e.g. a calibrated one).

    Parameters
    ----------
    catalogue_outer_diameter, catalogue_inner_diameter
        Free-tube OD and ID [mm].
    material
        The tube silicone.
    a, a_int, b_int, h
        As-assembled shape [mm]: outer horizontal semi-axis, lumen semi-axes, and the
        lumen-centre offset from the outer-ellipse centre (+y toward the coil wall).
    min_wall
        Smallest wall the shape may have, along the ellipse axes [mm].
    """

    catalogue_outer_diameter: float
    catalogue_inner_diameter: float
    material: Material
    a: float | None = None
    a_int: float | None = None
    b_int: float | None = None
    h: float | None = None
    min_wall: float = 0.02

    def __post_init__(self) -> None:
        od = validation.positive("catalogue_outer_diameter", self.catalogue_outer_diameter)
        idia = validation.positive("catalogue_inner_diameter", self.catalogue_inner_diameter)
        validation.less_than("catalogue_inner_diameter", idia, "catalogue_outer_diameter", od)
        object.__setattr__(self, "catalogue_outer_diameter", od)
        object.__setattr__(self, "catalogue_inner_diameter", idia)
        _material("material", self.material)
        object.__setattr__(self, "min_wall", validation.positive("min_wall", self.min_wall))
        shape = {k: getattr(self, k) for k in ("a", "a_int", "b_int", "h")}
        given = [k for k, v in shape.items() if v is not None]
        if given and len(given) != 4:
            missing = sorted(set(shape) - set(given))
            raise DesignError(missing[0], None, "give all of a, a_int, b_int, h or none of them")
        if given:
            for k in ("a", "a_int", "b_int"):
                object.__setattr__(self, k, validation.positive(k, shape[k]))
            object.__setattr__(self, "h", validation.finite("h", shape["h"]))

    @property
    def has_explicit_shape(self) -> bool:
        return self.a is not None


@dataclass(frozen=True, kw_only=True)
class Tip:
    """The bending segment.

    Parameters
    ----------
    bending_length
        Free length L0 between the heat-shrink edge (clamp) and the tip end [mm].
    cap_thickness
        Axial length of the sealed tube end (glue plug) at the distal end [mm].
    """

    bending_length: float
    cap_thickness: float

    def __post_init__(self) -> None:
        length = validation.positive("bending_length", self.bending_length)
        validation.at_most(
            "bending_length", length, validation.MAX_BENDING_LENGTH_MM, "mm: catheter tips bend over 5-100 mm"
        )
        cap = validation.positive("cap_thickness", self.cap_thickness)
        validation.less_than("cap_thickness", cap, "bending_length / 2", length / 2)
        object.__setattr__(self, "bending_length", length)
        object.__setattr__(self, "cap_thickness", cap)
