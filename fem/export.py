"""VTU export (opens in ParaView) and an off-screen PNG of the bent tip."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from softcath.fem.geometry import REGIONS
from softcath.fem.pipeline import TipSolution

__all__ = ["to_grid", "write_vtu", "render_png", "render_grid_png", "quiet_vtk"]

log = logging.getLogger(__name__)


def to_grid(solution: TipSolution, load: str, pressure_MPa: float):
    """A pyvista ``UnstructuredGrid`` of the tip with the results at ``pressure_MPa``.

    Point data ``displacement`` (mm); cell data ``region`` (label),
    ``region_name`` is in the field data, ``max_principal_strain``.
    """
    import pyvista as pv

    mesh = solution.mesh
    nv = mesh.points.shape[0]
    u = pressure_MPa * solution.unit[load][:nv]  # P2 numbering: vertices first
    cells = np.column_stack([np.full(len(mesh.tets), 4), mesh.tets]).ravel()
    grid = pv.UnstructuredGrid(cells, np.full(len(mesh.tets), pv.CellType.TETRA), mesh.points)
    grid.point_data["displacement"] = u
    grid.cell_data["region"] = mesh.labels.astype(np.int32)
    grid.cell_data["max_principal_strain"] = pressure_MPa * solution.element_strain[load]
    grid.field_data["region_names"] = np.array([f"{k}={v}" for k, v in REGIONS.items()])
    grid.field_data["pressure_MPa"] = np.array([pressure_MPa])
    grid.field_data["load"] = np.array([load])
    return grid


def write_vtu(solution: TipSolution, load: str, pressure_MPa: float, path: str | Path) -> Path:
    """Write the deformed-tip data to a ``.vtu`` file (ParaView: Warp By Vector)."""
    path = Path(path)
    to_grid(solution, load, pressure_MPa).save(str(path))
    return path


def quiet_vtk() -> None:
    """Keep VTK's own log to errors only.

    Without a display VTK first tries X, logs "bad X server connection" at warning level,
    then renders off-screen through EGL or OSMesa correctly; that warning is noise on
    every headless run.
    """
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)


def render_png(
    solution: TipSolution,
    load: str,
    pressure_MPa: float,
    path: str | Path,
    *,
    window_size: tuple[int, int] = (1200, 700),
) -> Path:
    """Render the deformed tip coloured by max principal strain over the undeformed ghost.

    The tip is cut along its bending plane (x = 0) and seen from +x (y up), so
    the tube, lumen, filler and channel show. Displacements are at true scale.
    """
    return render_grid_png(
        to_grid(solution, load, pressure_MPa),
        path,
        title=f"{load} load, p = {pressure_MPa:g} MPa (true scale)",
        window_size=window_size,
    )


def cut_deformed(grid, displacement: str = "displacement"):
    """``grid`` deformed by ``displacement`` at true scale and cut along the bending plane, keeping x <= 0.

    The cut face looks towards +x, so the silicone inside the coil (tube,
    lumen, filler, channel) shows; ``tip.png`` and ``tip.html`` both show this half.
    """
    warped = grid.warp_by_vector(displacement, factor=1.0)
    return warped.clip(normal=(1.0, 0.0, 0.0), origin=(0.0, 0.0, 0.0))


def strain_clim(values) -> tuple[float, float]:
    """Colour limits of a strain picture: min(0, min) to the 99th percentile.

    The percentile keeps a few clamp-corner elements from washing the picture
    out (they show at the clamp colour); an empty or non-positive set gets 1.
    """
    values = np.asarray(values, float)
    hi = float(np.percentile(values, 99)) if values.size else 1.0
    return min(0.0, float(values.min(initial=0.0))), (hi if hi > 0 else 1.0)


def render_grid_png(
    grid,
    path: str | Path,
    *,
    title: str,
    scalars: str = "max_principal_strain",
    displacement: str = "displacement",
    scalar_title: str = "max principal strain",
    window_size: tuple[int, int] = (1200, 700),
) -> Path:
    """Render a tet ``grid`` of the tip deformed by ``displacement`` and coloured by cell data ``scalars``.

    The picture of :func:`render_png`, for any tip grid (the finite-strain one
    too): the deformed half :func:`cut_deformed` over the undeformed ghost,
    seen from +x with y up, coloured within :func:`strain_clim`.
    """
    import pyvista as pv

    quiet_vtk()
    path = Path(path)
    ghost = grid.extract_surface(algorithm="dataset_surface")
    half = cut_deformed(grid, displacement)
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    plotter.add_mesh(ghost, color="lightgrey", opacity=0.2)
    plotter.add_mesh(
        half,
        scalars=scalars,
        cmap="viridis",
        clim=strain_clim(half.cell_data[scalars]),
        scalar_bar_args={"title": scalar_title, "color": "black"},
    )
    plotter.add_text(title, font_size=12, color="black")
    plotter.view_vector((1.0, 0.0, 0.0), viewup=(0.0, 1.0, 0.0))
    plotter.camera.zoom(1.2)
    plotter.screenshot(str(path))
    plotter.close()
    return path
