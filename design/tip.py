"""The assembled catheter tip: parts, materials and the as-assembled section."""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from dataclasses import field as _field

from softcath.core.errors import DesignError
from softcath.design import section as _section
from softcath.design.assembly import Assembly
from softcath.design.components import Coil, Tip, Tube
from softcath.design.materials import Material

__all__ = ["TipDesign"]


@dataclass(frozen=True, kw_only=True)
class TipDesign:
    """A complete, validated catheter-tip design (mm, MPa).

    Parameters
    ----------
    coil
        The outer helical coil (homogenised as an annulus centred on the axis).
    tube
        The silicone actuation tube (squeezed to an offset hollow ellipse).
    channel
        The hollow-channel coil (delivery lumen), tangent to the coil ID at the bottom.
    tip
        Bending length and cap thickness.
    filler
        The dip-coat silicone that fills the space inside the coil around tube
        and channel, or ``None`` for a void. The fabrication (paper Fig. 1c:
        dip-coating of the tip in Ecoflex 00-30) suggests filled.
    name
        A label for reports.
    assembly
        How the parts are put together (:class:`softcath.design.assembly.Assembly`);
        the default is one bonded, fully filled body clamped at the base.
    """

    coil: Coil
    tube: Tube
    channel: Coil
    tip: Tip
    filler: Material | None = None
    name: str = "design"
    assembly: Assembly = _field(default_factory=Assembly)

    def _check_coat(self) -> None:
        """Refuse a coat so thick that it reaches every void: it would be ``filler = "full"`` unsaid.

        The coat is the voids within ``t`` of the channel, which touches the coil's inner wall; the
        farthest void point is ``2 (R_i - r_c)`` from the channel's surface.
        """
        if not (isinstance(self.coil, Coil) and isinstance(self.channel, Coil)):
            return  # refused below, naming the part
        reach = self.coil.inner_diameter - self.channel.outer_diameter
        t = self.assembly.filler_coat_thickness
        if reach > 0 and t >= reach:
            raise DesignError(
                "assembly.filler_coat_thickness",
                t,
                f'must be < {reach:.6g} mm: a coat that thick fills every void, the same as filler = "full" '
                '(give filler = "full")',
            )

    def __post_init__(self) -> None:
        if not isinstance(self.assembly, Assembly):
            raise DesignError("assembly", self.assembly, "must be a design.Assembly")
        if self.assembly.filler == "coat" and self.filler is None:
            raise DesignError("assembly.filler", "coat", "needs a filler material ([filler] material)")
        if self.assembly.filler == "coat":
            self._check_coat()
        for field, cls in (("coil", Coil), ("tube", Tube), ("channel", Coil), ("tip", Tip)):
            if not isinstance(getattr(self, field), cls):
                raise DesignError(field, getattr(self, field), f"must be a design.{cls.__name__}")
        if self.filler is not None and not isinstance(self.filler, Material):
            raise DesignError("filler", self.filler, "must be a design.Material or None")
        b = self.vertical_semi_axis
        if b <= 0:
            raise DesignError(
                "channel.outer_diameter",
                self.channel.outer_diameter,
                f"must be < coil.inner_diameter = {self.coil.inner_diameter:.6g} (no room left for the tube)",
            )
        if b <= self.tube.min_wall:
            raise DesignError(
                "channel.outer_diameter",
                self.channel.outer_diameter,
                f"leaves tube height 2b = {2 * b:.6g} mm, must exceed 2*tube.min_wall = "
                f"{2 * self.tube.min_wall:.6g}",
            )
        _section.check_shape(
            coil_inner_radius=self.coil.inner_diameter / 2,
            b=b,
            shape=self.tube_shape,
            min_wall=self.tube.min_wall,
        )

    @property
    def vertical_semi_axis(self) -> float:
        """b = (coil ID − channel OD)/2 [mm]."""
        return _section.vertical_semi_axis(
            coil_inner_diameter=self.coil.inner_diameter,
            channel_outer_diameter=self.channel.outer_diameter,
        )

    @property
    def tube_shape(self) -> dict[str, float]:
        """x = [a, a_int, b_int, h] [mm]: explicit if the design fixes it, else the nominal rule."""
        t = self.tube
        if t.has_explicit_shape:
            return {"a": t.a, "a_int": t.a_int, "b_int": t.b_int, "h": t.h}
        return _section.nominal_tube_shape(
            coil_inner_radius=self.coil.inner_diameter / 2,
            b=self.vertical_semi_axis,
            catalogue_outer_diameter=t.catalogue_outer_diameter,
            catalogue_inner_diameter=t.catalogue_inner_diameter,
        )

    @functools.cached_property
    def section(self) -> _section.AssembledSection:
        """The as-assembled cross-section (frame in :mod:`softcath.design.section`)."""
        r_in = self.coil.inner_diameter / 2
        r_c = self.channel.outer_diameter / 2
        b = self.vertical_semi_axis
        return _section.AssembledSection(
            coil_outer_radius=self.coil.outer_diameter / 2,
            coil_inner_radius=r_in,
            channel_outer_radius=r_c,
            channel_inner_radius=self.channel.inner_diameter / 2,
            channel_center_y=-(r_in - r_c),
            tube_center_y=r_in - b,
            b=b,
            **self.tube_shape,
        )

    @property
    def catalogue_fits(self) -> bool:
        """Whether the free (catalogue) tube fits beside the channel inside the coil."""
        return self.tube.catalogue_outer_diameter + self.channel.outer_diameter <= self.coil.inner_diameter

    @property
    def outer_diameter(self) -> float:
        """The catheter's outer diameter at the tip [mm] (the coil OD)."""
        return self.coil.outer_diameter

    def with_tube_shape(self, *, a: float, a_int: float, b_int: float, h: float) -> TipDesign:
        """A copy whose tube takes the given as-assembled shape (validated)."""
        return replace(self, tube=replace(self.tube, a=a, a_int=a_int, b_int=b_int, h=h))

    def fit_report(self) -> str:
        """Plain-language statement of how the parts fit (``softcath design show`` and ``validate``).

        A catalogue tube wider than the room beside the channel is no error: the design
        squeezes it (the paper's prototype does); the first line says so as a note.
        """
        s = self.section
        t = self.tube
        need = t.catalogue_outer_diameter + self.channel.outer_diameter
        lines = []
        if self.catalogue_fits:
            lines.append("catalogue tube fits beside the channel inside the coil")
        else:
            lines.append(
                f"note: the catalogue tube is squeezed to fit: OD {t.catalogue_outer_diameter:g} beside "
                f"channel OD {self.channel.outer_diameter:g} needs a {need:g} mm enclosure, coil ID is "
                f"{self.coil.inner_diameter:g} mm; as assembled the tube is {2 * s.b:.4g} mm high (2b)"
            )
        cat_wall = 3.141592653589793 / 4 * (t.catalogue_outer_diameter**2 - t.catalogue_inner_diameter**2)
        wall = 3.141592653589793 * (s.a * s.b - s.a_int * s.b_int)
        shape_src = "explicit (from the design)" if t.has_explicit_shape else "nominal rule"
        lines.append(
            f"as-assembled tube ({shape_src}): a={s.a:.4g} b={s.b:.4g} a_int={s.a_int:.4g} "
            f"b_int={s.b_int:.4g} h={s.h:.4g} mm; min wall {s.min_wall:.4g} mm"
        )
        lines.append(f"tube wall area {wall:.4g} mm^2 as assembled vs {cat_wall:.4g} mm^2 catalogue")
        return "\n".join(lines)
