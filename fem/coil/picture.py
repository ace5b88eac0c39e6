"""A picture of resolved coils bent with contact: the helix, deformed, coloured by contact force."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softcath.core.plotting import pyplot
from softcath.design.components import Coil
from softcath.fem.coil.stiffness import REFERENCE_CURVATURE, assemble_coil

__all__ = ["bent_coil_picture"]

PICTURE_TURNS = 10
PICTURE_ELEMENTS_PER_TURN = 48


def _bent(coil: Coil, turns: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The periodic cell bent with contact and repeated over ``turns`` turns (linear theory).

    Returns undeformed nodes, displacements, contact force per node, the moment
    and the rotation per turn. Turn j adds the increment: u(k + j m) = u(k) +
    j Δc + Δθ × (j x_k + j(j − 1)/2 · p e_z), θ(k + j m) = θ(k) + j Δθ.
    """
    model, base, mode = assemble_coil(coil, elements_per_turn=PICTURE_ELEMENTS_PER_TURN)
    free = model.solve(np.array([0, 0, 0, 1.0, 0, 0]), mode="free")
    moment = coil.pitch / model.per_turn(free)[1][0] * REFERENCE_CURVATURE
    state = model.solve(np.array([0, 0, 0, moment, 0, 0]), mode=mode, base=base)
    dc, dtheta = state.reduced[-6:-3], state.reduced[-3:]
    m, p = model.mesh.elements_per_turn, coil.pitch
    cell_x, cell_u = model.mesh.nodes[:m], state.displacement[:m]
    nodes, disp, force = [], [], []
    for j in range(turns):
        shift = j * cell_x + j * (j - 1) / 2 * np.array([0.0, 0.0, p])
        nodes.append(cell_x + [0.0, 0.0, j * p])
        disp.append(np.hstack([cell_u[:, :3] + j * dc + np.cross(dtheta, shift), cell_u[:, 3:] + j * dtheta]))
        force.append(state.contact_force)
    return np.vstack(nodes), np.vstack(disp), np.concatenate(force), moment, float(dtheta[0])


def bent_coil_picture(path: str | Path, coils: dict[str, Coil]) -> Path:
    """Write a PNG with one 3-D panel per coil (name → coil), bent about x by the reference moment.

    The periodic cell (the middle of a long coil) is repeated over
    :data:`PICTURE_TURNS` turns; displacements are magnified so the top turns by
    about 0.4 rad; the wire is coloured by the contact force of its pairs per
    unit wire length [N/mm] — the pivot line on the concave side.
    """
    plt = pyplot()
    from mpl_toolkits.mplot3d.art3d import Line3DCollection  # heavy: matplotlib loads on the first picture

    path = Path(path)
    fig = plt.figure(figsize=(5.0 * len(coils), 5.5))
    for i, (name, coil) in enumerate(coils.items(), start=1):
        nodes, u, line_force, moment, turn_rotation = _bent(coil, PICTURE_TURNS)
        scale = 0.4 / max(abs(turn_rotation) * PICTURE_TURNS, 1e-300)
        x = nodes + scale * u[:, :3]
        length = np.linalg.norm(np.diff(nodes, axis=0), axis=1)[0]
        per_element = 0.5 * (line_force[:-1] + line_force[1:]) / length
        segments = np.stack([x[:-1], x[1:]], axis=1)
        ax = fig.add_subplot(1, len(coils), i, projection="3d")
        lc = Line3DCollection(segments, cmap="viridis", linewidths=2.5)
        lc.set_array(per_element)
        ax.add_collection3d(lc)
        span = np.ptp(x, axis=0).max()
        centre = x.mean(axis=0)
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
            setter(c - span / 2, c + span / 2)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")
        ax.view_init(elev=12, azim=-20)
        ax.set_title(
            f"{name}: d {coil.wire_diameter:g}, p {coil.pitch:g}, R {coil.mean_radius:g} mm\n"
            f"M_x = {moment:.3g} N mm, x{scale:.3g} displacement",
            fontsize=9,
        )
        fig.colorbar(lc, ax=ax, shrink=0.6, pad=0.12, label="contact force per wire length [N/mm]")
    fig.suptitle(
        "resolved wire bent with contact, zero axial load (periodic cell repeated; turns pivot on the "
        "concave side)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
