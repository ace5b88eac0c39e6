"""Coil-bound compression and initial tension in the section model: curvature against pressure.

The coils' axial law is bilinear (``softcath.fem.section_model.fibres``): E_t where
the axial strain is tensile beyond the initial-tension pre-strain, E_c = E·φ
(coil-bound) where it is not. The concave side of a bent tip is then as
stiff as steel and the section pivots on it; with initial tension F₀ the
turns need the load to take F₀ off them first, so the tip barely bends below
a threshold pressure. The section solve is repeated per pressure with the
closed set iterated to consistency (the cracked-section iteration), so the
response is nonlinear in pressure.

Fibre placement (``coil_model``):

- ``annulus``: the coils' axial fibres are the quadrature points of their
  meshed annuli (the bimodular annulus; no couple): the 3-D FEM's
  homogenisation with the bilinear law;
- ``resolved``: what the resolved wire decomposes into (docs/coil.md, within
  0.3 %): a thin ring of fibres at the wire-centre radius R with the helix's
  EA_t and E_c·A, plus the couple EI_helix - 1/2 EA_t R^2 that does not
  depend on where the neutral axis is.

>>> import numpy as np
>>> from softcath.fem.section_model.bilinear import bend_curve
>>> c = bend_curve("paper", [0.1, 0.2], load="cap", initial_tension=(0.005, 0.0))
>>> round(c.threshold_pressure, 3)          # MPa: below it the tip barely bends
0.14
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from softcath import design as design_pkg
from softcath.analytic.pose import tip_pose
from softcath.core.deprecation import renamed_names
from softcath.core.response import TipResponse
from softcath.design import coil_stiffness
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import CHANNEL, COIL
from softcath.fem.section_model.coil_models import coil_terms, helix_stiffness
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.fibres import Fibres, ring_fibres, solve_fibres
from softcath.fem.section_model.laws import section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS, catheter_section_mesh
from softcath.fem.section_model.solve import solve

__all__ = ["BilinearCoilCurve", "bend_curve", "annulus_fibres", "PLACEMENTS"]

PLACEMENTS = ("resolved", "annulus")


@dataclass(frozen=True)
class BilinearCoilCurve:
    """The bilinear-coil section model's record: curvature against pressure of one design.

    :meth:`to_response` gives the tiers' one result type, :class:`~softcath.core.response.TipResponse`.

    Attributes
    ----------
    pressure
        MPa, as given.
    curvature, lateral_curvature, elongation
        k_2 (toward the channel, 1/mm), k_1 and the strain at the linear model's
        E_z-weighted centroid, per pressure.
    closed_fraction
        Share of each coil's fibre area closed (coil-bound), ``coil``/``channel`` -> per pressure.
    iterations
        Newton iterations per pressure.
    threshold_pressure
        Where the curve's large-pressure asymptote (the pivoting section, the
        closed set of F₀ = 0) meets zero curvature [MPa]; 0 without initial tension.
    opening_pressure
        Pressure at which the first fibre of a coil with initial tension
        opens (inf without initial tension) [MPa].
    gain_pivoting
        d(curvature)/dp of the asymptote [1/(mm MPa)] (the F₀ = 0 gain).
    gain_linear
        kappa/p of the linear section model with the same placement, E_c = E_t.
    initial_tension, compression_modulus
        (outer coil, channel) [N] and [MPa] (NaN: an open coil, linear).
    """

    design_name: str
    load: str
    coil_model: str
    pressure: np.ndarray
    curvature: np.ndarray
    lateral_curvature: np.ndarray
    elongation: np.ndarray
    closed_fraction: dict
    iterations: np.ndarray
    threshold_pressure: float
    opening_pressure: float
    gain_pivoting: float
    gain_linear: float
    initial_tension: tuple[float, float]
    compression_modulus: tuple[float, float]
    seconds: float

    def to_response(
        self,
        *,
        length_mm: float,
        tier: str = "section",
        warnings: tuple[str, ...] = (),
        seconds: float | None = None,
    ) -> TipResponse:
        """This curve as a :class:`~softcath.core.response.TipResponse`: a uniform arc (eq. 9).

        The arc is the bending length ``length_mm`` stretched by the curve's elongation, its
        curvature the section's (mid-span and tip-level alike); the lumen volume change and the
        strain are not computed (NaN). The lateral curvature, the Newton iterations and each
        coil's closed share go to ``extras``; the coil law to ``parameters``.

        Parameters
        ----------
        length_mm
            Bending length of the design [mm] (the curve keeps the design's name only).
        tier
            The tier's name in the response.
        warnings, seconds
            The response's validity warnings and wall time [s] (default: the curve's own).
        """
        if not (np.isfinite(length_mm) and length_mm > 0):
            raise DesignError("length_mm", length_mm, "must be a positive bending length [mm]")
        tip_x, tip_y, theta = tip_pose(self.curvature, length_mm * (1.0 + self.elongation))
        nan = np.full(np.shape(self.pressure), np.nan)
        return TipResponse(
            tier=tier,
            load=self.load,
            pressures=self.pressure,
            curvature_per_mm=self.curvature,
            tip_curvature_per_mm=self.curvature,
            elongation=self.elongation,
            bend_angle_rad=theta,
            tip_x_mm=tip_x,
            tip_y_mm=tip_y,
            lumen_volume_change_mm3=nan,
            max_strain=nan.copy(),
            warnings=tuple(warnings),
            parameters={
                "design": self.design_name,
                "bending_length_mm": float(length_mm),
                "coil_model": self.coil_model,
                "initial_tension": self.initial_tension,
                "compression_modulus": self.compression_modulus,
            },
            seconds=self.seconds if seconds is None else float(seconds),
            extras={
                "lateral_curvature_per_mm": self.lateral_curvature,
                "iterations": self.iterations,
                **{f"closed_fraction_{k}": np.asarray(v, float) for k, v in self.closed_fraction.items()},
            },
        )

    def to_json(self) -> dict:
        """Plain-JSON summary (an infinite opening pressure as ``None``)."""
        out = {}
        for k, v in self.__dict__.items():
            if isinstance(v, np.ndarray):
                v = v.tolist()
            elif isinstance(v, dict):
                v = {kk: np.asarray(vv).tolist() for kk, vv in v.items()}
            elif isinstance(v, float) and not np.isfinite(v):
                v = None
            elif isinstance(v, tuple):
                v = [None if not np.isfinite(x) else x for x in v]
            out[k] = v
        return out


def annulus_fibres(
    op, labels, label: int, *, compression_modulus: float | None, initial_tension: float
) -> Fibres:
    """The quadrature points of region ``label`` as fibres, E_t from the assembled law (E_c = E_t if None)."""
    sel = np.asarray(labels) == label
    w = op.basis.dx[sel]
    x, y = (np.asarray(c)[sel] for c in op.basis.global_coordinates())
    et = np.broadcast_to(op.D[sel, 2, 2][:, None], w.shape)
    n = np.ones(w.size)
    return Fibres(
        x=x.ravel(),
        y=y.ravel(),
        area=w.ravel(),
        tension_modulus=et.ravel().copy(),
        compression_modulus=et.ravel().copy() if compression_modulus is None else n * compression_modulus,
        prestress=n * initial_tension / w.sum(),
    )


def _coil_sources(d, initial_tension, compression_modulus):
    """The coils, their F0 and E_c (None: an open coil, linear: its turns do not touch at small strains)."""
    coils = ((d.coil, COIL, "coil"), (d.channel, CHANNEL, "channel"))
    f0 = tuple(c.initial_tension for c, _, _ in coils) if initial_tension is None else tuple(initial_tension)
    if len(f0) != 2 or any(not (np.isfinite(v) and v >= 0) for v in f0):
        raise DesignError("initial_tension", initial_tension, "must be two finite forces >= 0 N")
    for (c, _, name), v in zip(coils, f0, strict=True):
        try:  # the coil's own checks bound an override as they bound the design's value
            replace(c, initial_tension=float(v))
        except DesignError as exc:
            raise DesignError(f"initial_tension ({name})", v, exc.bound) from None
    if compression_modulus is None:
        ec = tuple(
            coil_stiffness(c).axial_modulus_compression if c.close_wound else None for c, _, _ in coils
        )
    else:
        ec = tuple(compression_modulus)
        if len(ec) != 2 or any(not (np.isfinite(v) and v > 0) for v in ec):
            raise DesignError("compression_modulus", compression_modulus, "must be two finite moduli > 0 MPa")
    return coils, f0, ec


def _section_problem(d, coils, f0, ec, *, load, coil_model, ring_points, **options):
    """The condensed section without the coils' axial part, and the coils as bilinear fibres.

    Returns (K_rest, fibres, owner index per fibre, coil names, condensed load of
    1 MPa, the linear model's E_z-weighted centroid y).
    """
    mesh_opts = {k: options.pop(k) for k in ("mesh_size", "segments")}
    laws = section_laws_from_design(d, coil_modulus="tension", **options)
    laws, extra = coil_terms(d, "resolved" if coil_model == "resolved" else "annulus", laws)
    geometry = geometry_from_design(d)
    mesh = catheter_section_mesh(geometry, **mesh_opts)
    op = assemble(mesh, laws)
    sol = solve(op, (load,), extra_bending=sum(extra.values()))
    k_rest = sol.stiffness
    f_unit = k_rest @ sol.loads[load].strains  # the condensed load of 1 MPa
    groups = []
    for (coil, label, name), force, e_c in zip(coils, f0, ec, strict=True):
        fib = annulus_fibres(op, mesh.labels, label, compression_modulus=e_c, initial_tension=force)
        k_rest = k_rest - fib.linear_stiffness(fib.tension_modulus)  # the annulus's own axial part out
        if coil_model == "resolved":
            ea, ei = helix_stiffness(coil)
            area, r = coil_stiffness(coil).area, coil.mean_radius
            centre = (0.0, 0.0) if label == COIL else (0.0, geometry.channel_y)
            fib = ring_fibres(
                centre=centre,
                radius=r,
                area=area,
                tension_axial=ea,
                initial_tension=force,
                compression_modulus=ea / area if e_c is None else e_c,
                points=ring_points,
            )
            # The couple replaces the annulus's: EI_helix - 1/2 EA R^2 beyond the ring's own.
            couple = ei - 0.5 * ea * r**2 - extra[label]
            k_rest = k_rest + np.diag([0.0, couple, couple])
        groups.append((name, fib))
    fibres = groups[0][1].join(groups[1][1])
    owner = np.concatenate([np.full(f.x.size, i) for i, (_, f) in enumerate(groups)])
    return k_rest, fibres, owner, [n for n, _ in groups], f_unit, float(op.axial_centroid_y)


def bend_curve(
    design,
    pressures: Sequence[float] | np.ndarray,
    *,
    load: str = "lumen",
    coil_model: str = "resolved",
    initial_tension: Sequence[float] | None = None,
    compression_modulus: Sequence[float] | None = None,
    ring_points: int = 720,
    mesh_size: float = MESH_SIZE,
    segments: int = SEGMENTS,
    silicone_poisson: float | None = None,
    poisson_cap: float | None = None,
) -> BilinearCoilCurve:
    """Curvature, elongation and threshold pressure of ``design`` with coil-bound, bilinear coils.

    Parameters
    ----------
    design
        A :class:`design.TipDesign`, preset name or TOML path.
    pressures
        Pressures [MPa] (any order; solved in the given order, each warm-started).
    load
        ``"cap"`` or ``"lumen"`` (``softcath.fem.section_model.solve.LOADS``).
    coil_model
        Fibre placement, one of :data:`PLACEMENTS` (module docstring).
    initial_tension
        (outer coil, channel) F₀ [N]; default: the design's ``Coil.initial_tension``.
    compression_modulus
        (outer coil, channel) E_c [MPa]; default E·φ (``design.coil_stiffness``)
        for a close-wound coil and E_t for an open one (pitch > wire: its turns
        do not touch until the gap has closed, far beyond these strains).
        Equal to E_t (and F₀ = 0) it reproduces the linear section model.
    ring_points
        Fibres per coil ring (``resolved``).
    mesh_size, segments, silicone_poisson, poisson_cap
        As in :func:`softcath.fem.section_model.section_model`.
    """
    p = _checked_inputs(coil_model, pressures)
    t0 = time.perf_counter()
    d = design_pkg.resolve(design)
    coils, f0, ec = _coil_sources(d, initial_tension, compression_modulus)
    k_rest, fibres, owner, names, f_unit, centroid_y = _section_problem(
        d,
        coils,
        f0,
        ec,
        load=load,
        coil_model=coil_model,
        ring_points=ring_points,
        mesh_size=mesh_size,
        segments=segments,
        silicone_poisson=silicone_poisson,
        poisson_cap=poisson_cap,
    )
    gain_linear = float(np.linalg.solve(k_rest + fibres.linear_stiffness(fibres.tension_modulus), f_unit)[2])

    gain_pivot, threshold, opening = _asymptotes(k_rest, fibres, f_unit)
    g_all, closed_share, iters = _walk(k_rest, fibres, f_unit, p, owner, names)
    return BilinearCoilCurve(
        design_name=d.name,
        load=load,
        coil_model=coil_model,
        pressure=p,
        curvature=g_all[:, 2],
        lateral_curvature=g_all[:, 1],
        elongation=g_all[:, 0] + g_all[:, 2] * centroid_y,
        closed_fraction={k: np.array(v) for k, v in closed_share.items()},
        iterations=np.array(iters),
        threshold_pressure=threshold,
        opening_pressure=opening,
        gain_pivoting=gain_pivot,
        gain_linear=gain_linear,
        initial_tension=(float(f0[0]), float(f0[1])),
        compression_modulus=tuple(float("nan") if v is None else float(v) for v in ec),
        seconds=time.perf_counter() - t0,
    )


def _checked_inputs(coil_model: str, pressures: Sequence[float] | np.ndarray) -> np.ndarray:
    """The pressures as a flat array; :class:`DesignError` for an unknown placement or no finite pressures."""
    if coil_model not in PLACEMENTS:
        raise DesignError("coil_model", coil_model, f"must be one of {PLACEMENTS}")
    p = np.asarray(pressures, dtype=float).ravel()
    if p.size == 0 or not np.all(np.isfinite(p)):
        raise DesignError("pressures", pressures, "must be a non-empty list of finite pressures [MPa]")
    return p


def _asymptotes(k_rest, fibres: Fibres, f_unit) -> tuple[float, float, float]:
    """Pivoting gain, threshold pressure (0 without preload) and first opening pressure [MPa]."""
    # The pivoting asymptote: the closed set without initial tension, then F₀'s preload on the open fibres.
    free = Fibres(**{**fibres.__dict__, "prestress": np.zeros_like(fibres.prestress)})
    g1, closed1, _ = solve_fibres(k_rest, free, f_unit)
    k_t = k_rest + free.linear_stiffness(np.where(closed1, free.compression_modulus, free.tension_modulus))
    pre = free.phi.T @ (np.where(closed1, 0.0, fibres.prestress) * fibres.area)
    gain_pivot = float(g1[2])
    threshold = float(np.linalg.solve(k_t, pre)[2] / np.linalg.solve(k_t, f_unit)[2])
    # First opening: every preloaded fibre closed (stiff), the rest bilinear without preload.
    loaded = fibres.prestress > 0
    opening = np.inf
    if loaded.any():
        shut = Fibres(
            **{
                **free.__dict__,
                "tension_modulus": np.where(loaded, free.compression_modulus, free.tension_modulus),
            }
        )
        g_s, _, _ = solve_fibres(k_rest, shut, f_unit)
        eps = free.phi[loaded] @ g_s
        ep = fibres.opening_strain()[loaded]
        opening = float(np.min(np.where(eps > 0, ep / np.where(eps > 0, eps, 1.0), np.inf)))
    return gain_pivot, threshold if loaded.any() else 0.0, opening


def _walk(k_rest, fibres: Fibres, f_unit, p, owner, names):
    """Solve each pressure warm-started; returns the strains, closed area share per coil and iterations."""
    g_all, closed_share, iters = [], {n: [] for n in names}, []
    g = None
    for pi in p:
        g, closed, it = solve_fibres(k_rest, fibres, pi * f_unit, start=g)
        g_all.append(g)
        iters.append(it)
        for i, name in enumerate(names):
            mine = owner == i
            closed_share[name].append(float(fibres.area[mine & closed].sum() / fibres.area[mine].sum()))
    return np.array(g_all), closed_share, iters


#: The old name of the record, before every tier's record had its own.
__getattr__ = renamed_names(__name__, BendCurve=BilinearCoilCurve)
