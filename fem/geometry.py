"""The as-assembled tip geometry the FEM meshes, and its region rules.

The section frame is the project's: x horizontal, y
vertical, coil centre at the origin, hollow channel at the bottom, silicone
tube above it; the tip runs along z from the clamped base (z = 0) to z = L.

Tangent contacts (tube-coil at the top, tube-channel and channel-coil at the
bottom) are where CAD booleans and meshers fail: at a tangent point two
boundaries meet with zero angle, leaving a cusp of vanishing thickness. The
treatment here is a **bonded land**: wherever the gap between two touching
bodies is thinner than ``land_gap`` (mm), it is filled and bonded to both
bodies. The land is the strip ``|x| < x_land`` between the two boundaries,
where ``x_land`` is the first abscissa at which the vertical gap reaches
``land_gap``; so the remaining cusps start at thickness ``land_gap`` and a
mesher meets no zero-thickness wedge. A land must be fused with one of the two
bodies (a separate land region would itself be a zero-thickness sliver at the
tangent point): the tube-coil and tube-channel lands are tube silicone (the
squeezed tube conforms); the channel-coil land is given to the coil (it adds
< 0.5 % to the coil's area; the two steel coils are pressed together there).
Where the squeezed tube would overlap the coil or channel it is clipped by them.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
from dataclasses import dataclass, fields

import numpy as np

from softcath.design.assembly import Assembly
from softcath.design.cad import land_half_widths
from softcath.design.errors import DesignError

__all__ = [
    "TipGeometry",
    "REGIONS",
    "interface_kind",
    "COIL",
    "TUBE",
    "CHANNEL",
    "FILLER",
    "VOID",
]

_LAND_NAMES = ("tube_coil", "tube_channel", "channel_coil")


@functools.lru_cache(maxsize=64)
def _land_half_widths(*args: float) -> tuple[float, ...]:
    """:func:`softcath.design.cad.land_half_widths` by position, cached on the values.

    ~0.2 ms (6001 samples) and a morph asks twice for one geometry (its curves, then its
    region check). A tuple, so no caller can change what the cache holds.
    """
    names = ("coil_inner_radius", "channel_outer_radius", "channel_y", "tube_a", "tube_b", "tube_y")
    names += ("land_gap",)
    lands = land_half_widths(**dict(zip(names, args, strict=True)))
    return tuple(lands[name] for name in _LAND_NAMES)


# Region labels (per tetrahedron). VOID marks empty space (lumens, unfilled coil).
COIL, TUBE, CHANNEL, FILLER, VOID = 1, 2, 3, 4, 0
REGIONS = {COIL: "coil", TUBE: "tube", CHANNEL: "channel", FILLER: "filler"}


def interface_kind(assembly: Assembly, a: int, b: int) -> str:
    """Kind of the boundary between region labels ``a`` and ``b`` as ``assembly`` builds it."""
    pair = {a, b}
    if pair == {TUBE, FILLER}:
        return assembly.tube_channel if assembly.filler == "coat" else "bonded"
    if pair == {CHANNEL, FILLER}:
        return "bonded"
    return assembly.interface(REGIONS[a], REGIONS[b])


@dataclass(frozen=True)
class TipGeometry:
    """Dimensions (mm) of the as-assembled tip, as the mesher sees them.

    Parameters
    ----------
    coil_outer_radius, coil_inner_radius
        Homogenised outer coil annulus.
    channel_outer_radius, channel_inner_radius
        Hollow-channel coil annulus; its centre is at ``channel_y`` so that it is
        tangent to the coil ID at the bottom.
    tube_a, tube_b, tube_y
        Outer ellipse of the silicone tube (semi-axes x, y; centre y).
    lumen_a, lumen_b, lumen_y
        Lumen ellipse (semi-axes, centre y).
    length
        Bending length L (z from 0 to L).
    cap_thickness
        Sealed cap of the tube at the distal end (lumen ends at L - cap).
    filled
        True if the coil interior around tube and channel is filled with silicone.
    land_gap
        Bonded-land threshold (mm): contact gaps thinner than this are filled.
    filler_coat
        With ``filled``: 0 fills every void inside the coil; > 0 keeps only a coat of
        this thickness (mm) around the channel (the as-built ``coat`` filler), the
        rest of the coil interior void.
    """

    coil_outer_radius: float
    coil_inner_radius: float
    channel_outer_radius: float
    channel_inner_radius: float
    channel_y: float
    tube_a: float
    tube_b: float
    tube_y: float
    lumen_a: float
    lumen_b: float
    lumen_y: float
    length: float
    cap_thickness: float
    filled: bool = True
    land_gap: float = 0.01
    filler_coat: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):  # asdict's deep copy costs ~20 us a geometry, and every field is a scalar
            name, value = f.name, getattr(self, f.name)
            if name == "filled" or (name == "filler_coat" and value == 0.0):
                continue
            if not (math.isfinite(value) and (value > 0 or name in ("channel_y", "tube_y", "lumen_y"))):
                raise DesignError(f"geometry.{name}", value, "must be finite and > 0")
        if self.coil_inner_radius >= self.coil_outer_radius:
            raise DesignError(
                "geometry.coil_inner_radius",
                self.coil_inner_radius,
                f"must be < coil_outer_radius = {self.coil_outer_radius}",
            )
        if self.channel_inner_radius >= self.channel_outer_radius:
            raise DesignError(
                "geometry.channel_inner_radius",
                self.channel_inner_radius,
                f"must be < channel_outer_radius = {self.channel_outer_radius}",
            )
        if self.cap_thickness >= self.length:
            raise DesignError(
                "geometry.cap_thickness", self.cap_thickness, f"must be < length = {self.length}"
            )
        # The lumen must sit inside the tube with a wall left over. The sampled wall costs ~1 ms
        # (every design of a section sweep): it is needed only when the exact test cannot tell.
        if not self._lumen_clearly_inside() and self.min_lumen_wall() <= 0:
            raise DesignError(
                "geometry.lumen",
                (self.lumen_a, self.lumen_b, self.lumen_y),
                "lumen ellipse must lie strictly inside the tube ellipse",
            )
        if self.land_gap >= 0.5 * self.tube_b:
            raise DesignError("geometry.land_gap", self.land_gap, f"must be < tube_b/2 = {self.tube_b / 2}")

    # -- identity -----------------------------------------------------------
    def digest(self) -> str:
        """Content hash of the geometry (used to key the mesh cache)."""
        d = {f.name: getattr(self, f.name) for f in fields(self)}  # asdict, without its deep copy
        if d["filler_coat"] == 0.0:  # the fully filled tip keeps its historical digest
            del d["filler_coat"]
        blob = json.dumps(d, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    # -- shape queries --------------------------------------------------------
    def min_lumen_wall(self) -> float:
        """Smallest tube wall thickness around the lumen (mm), sampled on the lumen.

        Each lumen sample is projected onto the outer ellipse (a 64-point search,
        then Newton on the foot point's angle), and the thinnest place is refined
        by a fine lumen sample around it: ~1e-9 mm, in about a millisecond (it
        runs for every design of a section-model sweep).
        """
        a, b, yl = self.lumen_a, self.lumen_b, self.lumen_y

        def wall(t):
            x, y = a * np.cos(t), yl + b * np.sin(t)
            if not (((x / self.tube_a) ** 2 + ((y - self.tube_y) / self.tube_b) ** 2) < 1).all():
                return None
            return self._distance_to_outer(x, y)

        t = np.linspace(0, 2 * np.pi, 360, endpoint=False)
        d = wall(t)
        if d is None:
            return -1.0
        i = int(np.argmin(d))
        tf = t[i] + np.linspace(-1, 1, 101) * (t[1] - t[0])
        df = wall(tf)
        return -1.0 if df is None else float(min(df.min(), d[i]))

    def _lumen_clearly_inside(self, margin: float = 1e-9) -> bool:
        """True if the lumen ellipse lies inside the tube ellipse with ``margin`` to spare (exact).

        Both ellipses are centred on x = 0, so the tube's implicit function along the
        lumen, ``(a cos t / A)^2 + ((dy + b sin t) / B)^2``, is a quadratic in
        ``s = sin t``; its largest value on [-1, 1] is below ``1 - margin`` exactly when
        every lumen point is strictly inside the tube. Then every lumen sample of
        :meth:`min_lumen_wall` is inside and its wall is positive, so the validity test
        need not sample; ``False`` only means "not proven" (the sampled test decides).
        """
        ra, rb = self.lumen_a / self.tube_a, self.lumen_b / self.tube_b
        dy = (self.lumen_y - self.tube_y) / self.tube_b
        c0, c1, c2 = ra**2 + dy**2, 2 * dy * rb, rb**2 - ra**2
        values = [c0 - c1 + c2, c0 + c1 + c2]  # s = -1, 1
        if c2 < 0 and abs(c1) < -2 * c2:  # the vertex of a concave quadratic inside [-1, 1]
            values.append(c0 - c1**2 / (4 * c2))
        return max(values) < 1.0 - margin

    def _distance_to_outer(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Distance (mm) from points inside the tube ellipse to its boundary."""
        ta, tb, yt = self.tube_a, self.tube_b, self.tube_y
        s = np.linspace(0, 2 * np.pi, 64, endpoint=False)
        d2 = (x[:, None] - ta * np.cos(s)) ** 2 + (y[:, None] - yt - tb * np.sin(s)) ** 2
        u = s[np.argmin(d2, axis=1)]
        for _ in range(8):  # Newton on (P(u) - q) . P'(u) = 0
            c, n = np.cos(u), np.sin(u)
            px, py = ta * c - x, yt + tb * n - y
            f = -px * ta * n + py * tb * c
            df = (ta * n) ** 2 + (tb * c) ** 2 - px * ta * c - py * tb * n
            u = u - f / np.where(np.abs(df) > 1e-300, df, 1e-300)
        return np.hypot(ta * np.cos(u) - x, yt + tb * np.sin(u) - y)

    def lands(self) -> dict[str, float]:
        """Half-widths ``x_land`` (mm) of the three bonded lands (``softcath.design.cad``)."""
        return dict(
            zip(
                _LAND_NAMES,
                _land_half_widths(
                    self.coil_inner_radius,
                    self.channel_outer_radius,
                    self.channel_y,
                    self.tube_a,
                    self.tube_b,
                    self.tube_y,
                    self.land_gap,
                ),
                strict=True,
            )
        )

    def classify(self, x: np.ndarray, y: np.ndarray, z: np.ndarray | None = None) -> np.ndarray:
        """Region label of points (section coordinates, optional z), by priority.

        Steel first (coil, channel), then the tube (with its lands, clipped by
        steel), the lumens, then filler/land/void.
        """
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        x2, ax = x**2, np.abs(x)  # each used more than once (a morph classifies every design)
        r2 = x2 + y**2
        rc2 = x2 + (y - self.channel_y) ** 2
        lab = np.full(x.shape, VOID, dtype=np.int8)
        inner = r2 < self.coil_inner_radius**2
        lands = self.lands()
        in_tube_ell = (x / self.tube_a) ** 2 + ((y - self.tube_y) / self.tube_b) ** 2 < 1
        top_land = (ax < lands["tube_coil"]) & (y > self.tube_y)
        bot_land = (ax < lands["tube_channel"]) & (y < self.tube_y) & (y > self.channel_y)
        tube = (in_tube_ell | top_land | bot_land) & inner & (rc2 > self.channel_outer_radius**2)
        lumen = (x / self.lumen_a) ** 2 + ((y - self.lumen_y) / self.lumen_b) ** 2 < 1
        if z is not None:
            lumen = lumen & (np.asarray(z) < self.length - self.cap_thickness)
        cc_land = (ax < lands["channel_coil"]) & (y < self.channel_y)
        rest = inner & ~tube
        if self.filled and self.filler_coat > 0:
            lab[rest & (rc2 < (self.channel_outer_radius + self.filler_coat) ** 2)] = FILLER
        elif self.filled:
            lab[rest] = FILLER
        lab[tube & ~lumen] = TUBE
        lab[(r2 >= self.coil_inner_radius**2) & (r2 < self.coil_outer_radius**2)] = COIL
        lab[cc_land & (r2 < self.coil_outer_radius**2)] = COIL
        lab[rc2 < self.channel_outer_radius**2] = CHANNEL
        lab[rc2 < self.channel_inner_radius**2] = VOID
        lab[r2 >= self.coil_outer_radius**2] = VOID
        if z is not None:  # outside the tip's length (a volume mesher's bounding box)
            z = np.asarray(z, float)
            lab[(z < 0) | (z > self.length)] = VOID
        return lab

    def in_lumen(self, x: np.ndarray, y: np.ndarray, margin: float) -> np.ndarray:
        """True inside the lumen ellipse grown by ``margin`` mm (facet tagging)."""
        return (x / (self.lumen_a + margin)) ** 2 + ((y - self.lumen_y) / (self.lumen_b + margin)) ** 2 < 1

    def exact_areas(self) -> dict[str, float]:
        """Section areas (mm^2) of each region in the lumen part, by fine sampling.

        Closed forms exist for coil and channel; the tube with lands and clips
        has none, so all are integrated on a 2000 x 2000 grid (relative error
        ~1e-4, far below the 1 % check) for one consistent reference.
        """
        n = 2000
        r = self.coil_outer_radius
        g = (np.arange(n) + 0.5) / n * 2 * r - r
        xx, yy = np.meshgrid(g, g)
        lab = self.classify(xx.ravel(), yy.ravel())
        da = (2 * r / n) ** 2
        return {name: float((lab == k).sum() * da) for k, name in REGIONS.items()}
