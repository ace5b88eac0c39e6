"""Section models of many designs at once: template meshes, a compiled element kernel, analyses reused.

Designs whose sections share a template mesh (``softcath.fem.section_model.template``)
differ only in node positions and region moduli, so everything that depends on the
connectivity is done once per template
(:mod:`softcath.fem.section_model.template_kernel`): the CCR DOF layout and reference
shape functions, the sparse pattern of the condensed stiffness with the scatter from
element blocks to it, the lumen edges' parent elements, the rigid-body
pins and the analysis (ordering, symbolic factorisation) of the free-free block. Per
design, the element blocks come from the compiled kernel
(:mod:`softcath.fem.section_model.element_kernel`, equal to scikit-fem's quadrature
assembly to 1e-10: tests/fem/section_model/test_fast_assembly.py), the block is
factorised numerically only (MKL PARDISO, or QDLDL where MKL is missing) and the four
right-hand sides (three unit global strains, the unit lumen pressure) are solved at once.

The answers are :func:`~softcath.fem.section_model.section_model`'s on the same
(template) mesh, to round-off (tests/fem/section_model/test_batch.py).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from softcath.analytic import design_inputs_many, gains_arrays
from softcath.core.interrupts import raise_pending_stop
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import TUBE
from softcath.fem.limits import check_section_budget
from softcath.fem.section_model import template as templates
from softcath.fem.section_model.api import COIL_BENDING, SectionResult, section_model
from softcath.fem.section_model.coil_models import coil_terms
from softcath.fem.section_model.end_zones import end_zones
from softcath.fem.section_model.laws import section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.solve import LOADS
from softcath.fem.section_model.strain import silicone_strain_range
from softcath.fem.section_model.template import log_fallback
from softcath.fem.section_model.template_kernel import _KERNELS as _KERNELS  # the cache, cleared by tests
from softcath.fem.section_model.template_kernel import _Kernel, _kernel

__all__ = ["BatchItem", "CHUNK", "TIMERS", "section_models"]

log = logging.getLogger(__name__)

#: Wall seconds of this process per stage (a cheap clock: the CPU clock costs ~1 ms a call
#: on a loaded machine): ``laws``, ``template``
#: (reference section and, once per template, its gmsh mesh), ``morph``, ``assembly``,
#: ``factorisation``, ``solve``, ``post``: the benchmark's time split.
TIMERS: dict[str, float] = {}
#: Most designs assembled at once. The compiled kernel works triangle by triangle, so a chunk
#: only bounds the memory of its outputs (~1.5 MB per paper-sized design).
CHUNK = 32


def _tick(name: str, t0: float) -> float:
    t = time.perf_counter()
    TIMERS[name] = TIMERS.get(name, 0.0) + t - t0
    return t


@dataclass(frozen=True)
class BatchItem:
    """One design's section model from :func:`section_models`.

    Attributes
    ----------
    result
        The :class:`~softcath.fem.section_model.SectionResult` (no fields).
    strain_range
        Load -> (smallest, largest) principal strain per MPa in the silicone.
    """

    result: object
    strain_range: dict[str, tuple[float, float]] = field(default_factory=dict)


def _solve_all(kernel: _Kernel, ops: dict) -> tuple[list, np.ndarray]:
    """Factorise and solve every design of an assembled chunk, one after the other.

    Returns per design its solutions (n_free, 4) of the four right-hand sides (three unit
    global strains' loads, the unit lumen pressure) or the exception it raised, and the
    right-hand sides (m, n_free, 4).
    """
    t0 = time.perf_counter()
    free = kernel.free
    rhs = np.concatenate([ops["K_ug"][:, free], ops["f"][:, free, None]], axis=2)
    factor = kernel.spd_factor()
    solved: list = []
    for j in range(rhs.shape[0]):  # back to back: the factor's memory stays warm
        try:
            factor.factorise(ops["data"][j])
            t0 = _tick("factorisation", t0)
            solved.append(factor.solve(rhs[j]))
        except Exception as exc:
            raise_pending_stop()
            solved.append(exc)
        t0 = _tick("solve", t0)
    return solved, rhs


def _condense(kernel: _Kernel, ops: dict, ok: np.ndarray, sol: np.ndarray, rhs: np.ndarray, loads, *, extra):
    """Section stiffnesses, global strains, lumen area changes and silicone strains of designs ``ok``.

    ``sol`` and ``rhs`` (len(ok), n_free, 4); ``extra`` the coils' bending stiffness added
    to the two bending terms, per design.
    """
    from softcath.fem.section_model.element_kernel import strain_extremes  # numba: heavy, first use

    t0 = time.perf_counter()
    k_ug = rhs[:, :, :3]
    x_g, x_p = sol[:, :, :3], sol[:, :, 3]
    coupled = np.einsum("mfi,mfj->mij", k_ug, sol)  # K_ugᵀ [x_g x_p]
    k_sec = ops["K_gg"][ok] - coupled[:, :, :3]
    k_sec = 0.5 * (k_sec + k_sec.transpose(0, 2, 1))
    k_sec[:, 1, 1] += extra
    k_sec[:, 2, 2] += extra
    area, centroid = ops["area"][ok], ops["centroid"][ok]
    cap = area[:, None] * np.column_stack([np.ones_like(area), centroid])
    f = ops["f"][ok]
    per_load = {}
    for ld in loads:
        lumen = ld == "lumen"
        f_g = cap - coupled[:, :, 3] if lumen else cap
        g = np.linalg.solve(k_sec, f_g[:, :, None])[:, :, 0]
        u = np.zeros((len(ok), kernel.n))
        u[:, kernel.free] = (x_p if lumen else 0.0) - np.einsum("mfi,mi->mf", x_g, g)
        per_load[ld] = (g, np.einsum("mn,mn->m", f, u), u)
    out = []
    for c, j in enumerate(ok):
        blocks = {key: ops[key][j] for key in ("xr", "xg", "inv", "xq")}
        strains = {
            ld: strain_extremes(u[c], kernel.dofs, kernel.silicone_elements, blocks, g[c], kernel.dphi)
            for ld, (g, _, u) in per_load.items()
        }
        out.append((k_sec[c], {ld: (g[c], float(da[c]), strains[ld]) for ld, (g, da, _) in per_load.items()}))
    _tick("post", t0)
    return out


def _result(
    d, laws, mesh, ops, j, k_sec, *, out, backward, kernel, mesh_size, segments, opts, seconds, formula_k
):

    ea = float(k_sec[0, 0])
    ybar = float(ops["ybar"][j])
    return SectionResult(
        design_name=d.name,
        end_zones=end_zones(d),
        loads=tuple(out),
        curvature_per_mm_per_MPa={ld: float(v[0][2]) for ld, v in out.items()},
        elongation_per_MPa={ld: float(v[0][0] + v[0][2] * ybar) for ld, v in out.items()},
        lumen_area_change_mm2_per_MPa={ld: v[1] for ld, v in out.items()},
        fem_formula_ratio={
            ld: float(v[0][2] / formula_k) if formula_k else float("nan") for ld, v in out.items()
        },
        EA_N=ea,
        EI_N_mm2=float(k_sec[2, 2] - k_sec[0, 2] ** 2 / ea),
        EI_lateral_N_mm2=float(k_sec[1, 1] - k_sec[0, 1] ** 2 / ea),
        coupling_N_mm=float(k_sec[0, 2]),
        neutral_axis_mm=float(k_sec[0, 2] / ea),
        axial_centroid_mm=ybar,
        lumen_area_mm2=float(ops["area"][j]),
        lumen_centroid_y_mm=float(ops["centroid"][j][1]),
        stiffness=tuple(tuple(float(v) for v in row) for row in k_sec),
        poisson_ratio_silicone=laws[TUBE].poisson_ratio,
        coil_modulus=opts["coil_modulus"],
        coil_bending=opts["coil_bending"],
        length_mm=float(d.tip.bending_length),
        mesh_size_mm=float(mesh_size),
        segments=int(segments),
        dofs=kernel.n + 3,
        n_triangles=kernel.nel,
        mesh_seconds=float(mesh.seconds),
        seconds=float(seconds),
        backward_error=backward,
        assembly=d.assembly.to_dict(),
    )


def _solve_chunk(members: list, results: list, loads, mesh_size, segments, opts) -> None:
    """Assemble a chunk of designs sharing a template at once and solve each; results in place."""

    t0 = time.perf_counter()
    kernel = _kernel(members[0][5])
    labels = kernel.labels
    keys = sorted({int(k) for k in np.unique(labels)})
    table = np.searchsorted(keys, labels)
    D = np.stack([np.stack([m[2][k].D for k in keys])[table] for m in members])
    lam = np.stack([np.array([m[2][k].lam for k in keys])[table] for m in members])
    ez = np.stack([np.array([m[2][k].axial_modulus for k in keys])[table] for m in members])
    ops = kernel.assemble(kernel.geometry([m[4] for m in members]), D, lam, ez)
    formula_k, _ = gains_arrays(design_inputs_many([m[1] for m in members]), "cap")
    share = (_tick("assembly", t0) - t0) / len(members)
    t1 = time.perf_counter()
    solved, rhs = _solve_all(kernel, ops)
    ok = np.array([j for j, v in enumerate(solved) if not isinstance(v, Exception)], dtype=int)
    for j, v in enumerate(solved):
        if isinstance(v, Exception):
            results[members[j][0]] = v
    if ok.size:
        extra = np.array([members[j][3] for j in ok])
        sol = np.stack([solved[j][0] for j in ok])
        try:
            condensed = _condense(kernel, ops, ok, sol, rhs[ok], loads, extra=extra)
        except Exception:  # one design's failure (a singular section stiffness) is its own
            raise_pending_stop()
            condensed = []
            for c, j in enumerate(ok):
                try:
                    condensed += _condense(
                        kernel,
                        ops,
                        ok[c : c + 1],
                        sol[c : c + 1],
                        rhs[j : j + 1],
                        loads,
                        extra=extra[c : c + 1],
                    )
                except Exception as exc:
                    raise_pending_stop()
                    condensed.append(exc)
        share += (time.perf_counter() - t1) / len(members)
        for done, j in zip(condensed, ok, strict=True):
            i, d, laws, _, mesh, _ = members[j]
            if isinstance(done, Exception):
                results[i] = done
                continue
            k_sec, out = done
            try:
                r = _result(
                    d,
                    laws,
                    mesh,
                    ops,
                    j,
                    k_sec,
                    out=out,
                    backward=solved[j][1],
                    kernel=kernel,
                    mesh_size=mesh_size,
                    segments=segments,
                    opts=opts,
                    seconds=share + mesh.seconds,
                    formula_k=float(formula_k[j]),
                )
                results[i] = BatchItem(r, {ld: v[2] for ld, v in out.items()})
            except Exception as exc:
                raise_pending_stop()
                results[i] = exc


def _solve_alone(d, mesher: str, loads, mesh_size, segments, opts):
    """A design solved by the per-design section model (its :class:`BatchItem` or its exception)."""

    try:
        r = section_model(
            d, loads=loads, mesh_size=mesh_size, segments=segments, mesher=mesher, keep_fields=True, **opts
        )
        strains = {ld: silicone_strain_range(r, ld) for ld in loads}
        return BatchItem(dataclasses.replace(r, fields=None), strains)
    except Exception as exc:
        raise_pending_stop()
        return exc


def section_models(
    designs: Sequence,
    *,
    loads: Sequence[str] = LOADS,
    mesh_size: float = MESH_SIZE,
    segments: int = SEGMENTS,
    coil_modulus: str = "tension",
    coil_bending: str = "annulus",
) -> list:
    """The section model of every design (template meshes, batched per template).

    Parameters
    ----------
    designs
        :class:`design.TipDesign` objects.
    loads, mesh_size, segments, coil_modulus, coil_bending
        As in :func:`~softcath.fem.section_model.section_model`.

    Returns
    -------
    list
        Per design, a :class:`BatchItem` or the exception that design raised (a
        design the template cannot morph to is solved on a fresh gmsh mesh; a design
        whose ``assembly`` is not the default bonded tip is solved alone by
        :func:`~softcath.fem.section_model.section_model`, which splits its interfaces).
    """

    loads = tuple(ld for ld in LOADS if ld in tuple(loads))
    if coil_bending not in COIL_BENDING:
        raise DesignError("coil_bending", coil_bending, f"must be one of {COIL_BENDING}")
    opts = {"coil_modulus": coil_modulus, "coil_bending": coil_bending}
    results: list = [None] * len(designs)
    groups: dict[str, list] = {}
    alone: dict[int, str] = {}  # designs solved one by one below, with the mesher to use
    for i, d in enumerate(designs):
        t0 = time.perf_counter()
        try:
            if not d.assembly.is_default:  # interfaces split, axial groups: the per-design path
                alone[i] = "template"
                continue
            g = geometry_from_design(d)
            check_section_budget(coil_outer_radius=g.coil_outer_radius, mesh_size=mesh_size)
            laws = section_laws_from_design(d, coil_modulus=coil_modulus)
            laws, extra = coil_terms(d, coil_bending, laws)
        except Exception as exc:  # reported per design by the caller
            raise_pending_stop()
            results[i] = exc
            continue
        t0 = _tick("laws", t0)
        try:
            # through the module: a test swaps the template builder for a failing one
            template = templates.section_template(g, mesh_size=mesh_size, segments=segments)
            t0 = _tick("template", t0)
            mesh = templates.morph(template, g)
            _tick("morph", t0)
        except Exception as exc:  # refused or failed: solved below on a fresh gmsh mesh
            raise_pending_stop()
            _tick("morph", t0)
            log_fallback(g, exc)
            alone[i] = "gmsh"
            continue
        groups.setdefault(template.mesh.key, []).append((i, d, laws, sum(extra.values()), mesh, template))
    # A group is assembled in chunks of CHUNK designs: a robust optimisation's task of 10⁴ variants
    # sharing a template would otherwise need ~100 GB at once.
    chunks = [m[k : k + CHUNK] for m in groups.values() for k in range(0, len(m), CHUNK)]
    for members in chunks:
        _solve_chunk(members, results, loads, mesh_size, segments, opts)
    for i, mesher in alone.items():
        results[i] = _solve_alone(designs[i], mesher, loads, mesh_size, segments, opts)
    return results
