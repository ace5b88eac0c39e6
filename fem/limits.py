"""What a linear FEM check of one tip will cost, and which tips it cannot resolve, known before meshing.

A mesh size far below the default asks for more memory than the machine has; the
meshing and the factorisation would run for minutes and then exhaust it. A lumen or
wall thinner than the geometry's bonded-land resolution (``softcath.fem.adapter``: gaps under
0.01 mm are filled) cannot be meshed into well-shaped elements and makes the
assembly's element mapping fail. Both are refused up front, naming the parameter.

The DOF estimate is empirical (P2 tetrahedra, the gmsh extruded-section mesher):
``layers × max(feature term, area term)`` with ``layers = L / (axial_ratio h)``. For the
paper design it reads 56k and 90k DOFs at h = 0.16 and 0.10 mm where the mesher gives
58.6k and 90.9k; at small h the area term (P2 triangles of side h over the section)
takes over. The memory model, 0.3 GB + 15 kB per DOF growing as N^(1/3) (the fill of a
3-D nested-dissection factorisation), matches the peak RSS measured for those two
meshes (0.77 and 1.25 GB).
"""

from __future__ import annotations

import logging
import math
import os

from softcath.design.errors import DesignError
from softcath.fem.section_mesh_size import MESH_SIZE, SEGMENTS, check_size

__all__ = [
    "MIN_FEATURE_MM",
    "MAX_SECTION_DOFS",
    "estimate_dofs",
    "estimate_memory_bytes",
    "check_fem_budget",
    "estimate_section_dofs",
    "estimate_section_memory_bytes",
    "check_section_budget",
    "estimate_section_seconds",
    "estimate_finite_strain_seconds",
    "finite_strain_curve_seconds",
    "check_work_seconds",
    "MAX_WORK_SECONDS",
    "WARN_WORK_SECONDS",
    "MAX_WORKERS",
    "check_workers",
]

log = logging.getLogger(__name__)

#: Longest estimated work a command starts, s: two hours (``predict``, ``optimise``, ``select --robust``,
#: ``section --nonlinear``): a run beyond is refused before any work with its estimate.
MAX_WORK_SECONDS = 2 * 3600.0
#: Estimated work above which a command says its estimate on stderr before it starts, s.
WARN_WORK_SECONDS = 60.0
#: One pressure of the finite-strain section walk per estimated (linear) section DOF, s: 64 ms a
#: pressure for the paper section (2.8k estimated DOFs) in a dense walk (2-3 Newton iterations).
_FINITE_STRAIN_SECONDS_PER_DOF = 2.3e-5
#: The extra cost of each of a walk's first ten pressures (large load steps take most Newton
#: iterations): 1.1 s a curve through 3 pressures of the paper section, measured in ``predict``.
_FINITE_STRAIN_FIRST_STEPS_PER_DOF = 9.0e-5

#: Thinnest lumen semi-axis or wall the FEM geometry resolves, mm (its bonded-land gap).
MIN_FEATURE_MM = 0.01
#: Section DOFs per element layer that the paper tip's wires and lumen force at any mesh size.
_FEATURE_DOFS_PER_LAYER = 9.0e3
#: P2 DOFs per layer per mm² of section at unit mesh size (3 components, vertex + edge nodes).
_AREA_DOFS_PER_LAYER = 55.0
_PAPER_SECTION_AREA = math.pi * 0.4**2


def estimate_dofs(*, length: float, section_area: float, mesh_size: float, axial_ratio: float = 5.0) -> float:
    """Estimated degrees of freedom of the extruded P2 mesh of a tip (see the module notes)."""
    layers = max(1.0, length / (axial_ratio * mesh_size))
    feature = _FEATURE_DOFS_PER_LAYER * section_area / _PAPER_SECTION_AREA
    area = _AREA_DOFS_PER_LAYER * section_area / mesh_size**2
    return layers * max(feature, area)


def estimate_memory_bytes(dofs: float) -> float:
    """Estimated peak memory of assembling and factorising ``dofs`` unknowns, bytes."""
    return 0.3e9 + 15e3 * dofs * (max(dofs, 1.0) / 90e3) ** (1 / 3)


def available_memory_bytes() -> float:
    """Memory the system can give this process now (``MemAvailable``), bytes; inf if unknown."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return math.inf


def check_fem_budget(
    design, *, mesh_size: float, axial_ratio: float = 5.0, param: str = "mesh_size"
) -> float:
    """Refuse a mesh size or tip the linear FEM cannot handle; return the estimated DOFs.

    Raises
    ------
    DesignError
        ``mesh_size`` is not a positive finite number, is larger than the tip's radius,
        needs more memory than is available, or a lumen semi-axis or wall of the design is
        below :data:`MIN_FEATURE_MM`.
    """
    if not (isinstance(mesh_size, int | float) and math.isfinite(mesh_size) and mesh_size > 0):
        raise DesignError(param, mesh_size, "must be a finite element size > 0 mm")
    radius = design.coil.outer_diameter / 2
    if mesh_size > radius:
        raise DesignError(param, mesh_size, f"must be <= the tip radius {radius:g} mm to resolve the section")
    s = design.section
    for name, value in (("tube.a_int", s.a_int), ("tube.b_int", s.b_int)):
        if value < MIN_FEATURE_MM:
            raise DesignError(
                name,
                value,
                f"a lumen semi-axis below {MIN_FEATURE_MM:g} mm cannot be meshed (the FEM geometry "
                "fills gaps thinner than that); the analytic model still applies",
            )
    dofs = estimate_dofs(
        length=design.tip.bending_length,
        section_area=math.pi * radius**2,
        mesh_size=mesh_size,
        axial_ratio=axial_ratio,
    )
    need, have = estimate_memory_bytes(dofs), available_memory_bytes()
    if need > 0.8 * have:
        raise DesignError(
            param,
            mesh_size,
            f"needs about {dofs:.3g} DOFs and {need / 1e9:.3g} GB of memory, but only "
            f"{have / 1e9:.3g} GB are available; use a coarser mesh (default 0.16 mm)",
        )
    return dofs


#: Section-model triangles the paper section's wires and lumen force at any mesh size.
_SECTION_FEATURE_TRIANGLES = 675.0
#: P2 triangles per mm² of section at unit mesh size (gmsh's Delaunay at the section's sizing).
_SECTION_AREA_TRIANGLES = 2.5
#: Section-model DOFs per triangle (P2, three displacement components, shared nodes).
_SECTION_DOFS_PER_TRIANGLE = 4.2
#: Most DOFs of one 2-D section solve: minutes of meshing and solving per design (the paper
#: section takes 0.7 s at 2.9k DOFs and 1.3 s at 22k), so a sweep of such designs never ends.
MAX_SECTION_DOFS = 1.0e6


def estimate_section_dofs(*, section_area: float, mesh_size: float) -> float:
    """Estimated DOFs of the 2-D section model's P2 mesh of a section of ``section_area`` mm².

    ``4.2 × max(675 × area / paper area, 2.5 × area / h²)``: 2.8k, 5.9k and 23k DOFs for the
    paper section at h = 0.08, 0.03 and 0.015 mm, where the mesher gives 2.9k, 6.4k and 22k.
    """
    feature = _SECTION_FEATURE_TRIANGLES * section_area / _PAPER_SECTION_AREA
    area = _SECTION_AREA_TRIANGLES * section_area / mesh_size**2
    return _SECTION_DOFS_PER_TRIANGLE * max(feature, area)


def estimate_section_memory_bytes(dofs: float) -> float:
    """Estimated peak memory of a 2-D section solve, bytes (0.18/0.30 GB measured at 2.9k/22k DOFs)."""
    return 0.18e9 + 6e3 * dofs * max(1.0, math.log(max(dofs, 2.0)) / math.log(22e3))


def estimate_section_seconds(dofs: float) -> float:
    """Estimated wall time of one section-model solve with a fresh mesh, s.

    ``0.2 s + 40 µs per estimated DOF`` (:func:`estimate_section_dofs`, conservative for large
    sections): 0.31 s for the paper section (a ``predict`` variant takes about 0.25 s), 3.0 s
    for a 4 mm coil (measured 2.95 s, 34k DOFs against 71k estimated), 26 s for a 12 mm one.
    """
    return 0.2 + 40e-6 * dofs


def check_section_budget(*, coil_outer_radius: float, mesh_size: float, param: str = "mesh_size") -> float:
    """Refuse a 2-D section model that cannot fit in memory or finish in minutes; return its DOFs.

    Raises
    ------
    DesignError
        Naming ``param`` (the mesh size) with the estimated DOFs and memory and the bound.
    """
    dofs = estimate_section_dofs(section_area=math.pi * coil_outer_radius**2, mesh_size=mesh_size)
    need, have = estimate_section_memory_bytes(dofs), available_memory_bytes()
    if dofs > MAX_SECTION_DOFS or need > 0.8 * have:
        raise DesignError(
            param,
            mesh_size,
            f"the {2 * coil_outer_radius:g} mm section needs about {dofs:.3g} DOFs and {need / 1e9:.3g} GB "
            f"(at most {MAX_SECTION_DOFS:.3g} DOFs and 80 % of the {have / 1e9:.3g} GB available); "
            "use a coarser mesh",
        )
    return dofs


def estimate_finite_strain_seconds(dofs: float, pressures: int) -> float:
    """Estimated wall time of one finite-strain section curve through ``pressures`` pressures, s.

    ``0.5 s + DOFs x (23 us x pressures + 90 us x min(pressures, 10))`` with the estimated section
    DOFs (:func:`estimate_section_dofs`): 1.4 s for 3 pressures of the paper section (measured
    about 1.1 s), 6.9 s for 60 (measured 3.9 s): an upper estimate.
    """
    n = int(pressures)
    return 0.5 + dofs * (_FINITE_STRAIN_SECONDS_PER_DOF * n + _FINITE_STRAIN_FIRST_STEPS_PER_DOF * min(n, 10))


def finite_strain_curve_seconds(design, pressures: int, *, mesh_size: float | None = None, param="mesh_size"):
    """Estimated seconds of one finite-strain section curve of ``design`` (mesh size checked first).

    Raises
    ------
    DesignError
        Naming ``param``: a mesh size outside the mesher's range or a section too large to solve.
    """
    h = MESH_SIZE if mesh_size is None else mesh_size
    try:
        check_size(h, SEGMENTS)
    except DesignError as exc:
        raise DesignError(param, exc.value, exc.bound) from None
    dofs = check_section_budget(coil_outer_radius=design.coil.outer_diameter / 2, mesh_size=h, param=param)
    return estimate_finite_strain_seconds(dofs, pressures)


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.3g} s"
    if seconds < 2 * 3600:
        return f"{seconds / 60:.3g} min"
    return f"{seconds / 3600:.3g} h"


def check_work_seconds(seconds: float, *, param: str, value: object, what: str, hint: str) -> float:
    """Refuse work estimated above :data:`MAX_WORK_SECONDS`; warn with the estimate above a minute.

    Parameters
    ----------
    seconds
        The estimate.
    param, value
        The input that sized the work (named in the refusal).
    what
        What is estimated (e.g. ``"10^6 pressures of the finite-strain section model"``).
    hint
        How to make it smaller.

    Raises
    ------
    DesignError
        Naming ``param`` with the estimate and the limit.
    """
    if not seconds <= MAX_WORK_SECONDS:
        raise DesignError(
            param,
            value,
            f"{what} is estimated at {_duration(seconds)}, above the {_duration(MAX_WORK_SECONDS)} "
            f"a command starts; {hint}",
        )
    if seconds > WARN_WORK_SECONDS:
        log.warning("%s: estimated %s before it finishes", what, _duration(seconds))
    return seconds


#: Most local worker processes a command starts: each is a Python process with its own memory
#: (~0.2 GB), and more processes than cores only queue.
MAX_WORKERS = 256


def check_workers(workers, *, param: str = "workers") -> None:
    """Refuse a worker count that is not an integer in [1, :data:`MAX_WORKERS`] (None: the default).

    Raises
    ------
    DesignError
        Naming ``param``.
    """
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS:
        raise DesignError(
            param,
            workers,
            f"must be an integer in [1, {MAX_WORKERS}] (this machine has {os.cpu_count()} CPUs)",
        )
