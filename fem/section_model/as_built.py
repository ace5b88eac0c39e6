r"""The section model of the tip as built: sliding interfaces, axial groups, the free tube.

Each region of the section (coil, tube, channel, filler) is its own body; the
mesh is split along every region boundary (:mod:`.interfaces`) and each
interface is tied according to the design's
:class:`softcath.design.assembly.Assembly`:

* ``bonded``: both displacement components tied (identical to the unsplit mesh);
* ``sliding`` and ``tied-at-tip``: the normal component tied, the in-plane
  tangential slip free.

**Axial slip in the Saint-Venant state.** Along a long tip under loads
uniform in z, the axial displacement of a body is
:math:`u_z = z(\varepsilon_{0,b} + k_1 x + k_2 y)`. Bodies in normal contact
along the whole length deflect together, so they share the curvatures
:math:`k_1, k_2`; a frictionless interface leaves the axial stretches free, so
each set of bodies that can slip axially against the rest (an *axial group*)
gets its own :math:`\varepsilon_{0,g}`, and its own axial force equation
:math:`N_g = \int_g \sigma_{zz}\,dA = F_g`, while the moments are summed.
Bodies tied at *both* ends cannot slip on average, and in the uniform state
the average is all there is (a slip varying along z needs end zones the
Saint-Venant state does not have), so:

* ``sliding`` (tied at no end along the tip): separate axial groups;
* ``tied-at-tip`` with ``proximal = "clamped"`` (tied at the sealed tip and
  both clamped at the base): one axial group, i.e. bonded axially but free
  in-plane tangentially;
* ``proximal = "tube-free"``: the tube slides freely into the catheter body,
  so a ``tied-at-tip`` interface of the tube's group does not merge axially;
  the tube's group then carries no axial force at the base
  (:math:`F_\text{tube} = 0`) and the cap force :math:`p A_\ell` is carried by
  the groups the tube is tied to at the tip (which, tied together through
  the cap and all clamped at the base, form one group). If the tube's group
  is tied at the tip to nothing, it carries the cap force itself (the
  pressurised tube is anchored far away in the body): ``tube-free`` then
  changes nothing in the uniform state.

Otherwise the cap force goes to the tube's group. The tube-filler and
channel-filler boundaries are bonded (the filler is cast on them); with
``filler = "coat"`` the coat is bonded to the channel and meets the tube with
the ``tube_channel`` kind.

A tangential spring layer of tiny modulus on every sliding interface
(``slip_modulus``, default :math:`10^{-9}` of the softest modulus per mm)
removes the free spin of bodies whose interfaces are all circles; it
carries no load, as every load is self-equilibrated on each body.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import splu

from softcath.design.assembly import Assembly
from softcath.design.errors import DesignError
from softcath.fem.geometry import COIL, TUBE, interface_kind
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.interfaces import split_interfaces, tie_projection
from softcath.fem.section_model.solve import LOADS, LoadSolution

__all__ = ["AxialPlan", "axial_plan", "interface_kind", "AsBuiltSolution", "solve_as_built"]


class _Union:
    def __init__(self, items):
        self.parent = {i: i for i in items}

    def find(self, i):
        while self.parent[i] != i:
            i = self.parent[i]
        return i

    def join(self, a, b):
        self.parent[self.find(a)] = self.find(b)


@dataclass(frozen=True)
class AxialPlan:
    """Axial groups of the region labels and the cap force's share of each.

    Attributes
    ----------
    group
        Region label -> group index (0..G-1).
    cap_share
        (G,) fraction of the cap force p A_lumen each group carries (sums to 1).
    """

    group: dict
    cap_share: np.ndarray

    @property
    def n_groups(self) -> int:
        """G, the number of axial groups."""
        return int(self.cap_share.size)


def axial_plan(assembly: Assembly, labels) -> AxialPlan:
    """Axial groups of the region ``labels`` present in a section (rules in the module docstring)."""
    labels = sorted(int(k) for k in labels)
    u = _Union(labels)
    tube_partners = []
    for i, a in enumerate(labels):
        for b in labels[i + 1 :]:
            kind = interface_kind(assembly, a, b)
            if kind == "bonded":
                u.join(a, b)
    tube_root = u.find(TUBE)
    for i, a in enumerate(labels):
        for b in labels[i + 1 :]:
            kind = interface_kind(assembly, a, b)
            if kind != "tied-at-tip":
                continue
            touches_tube = tube_root in (u.find(a), u.find(b)) and u.find(a) != u.find(b)
            if touches_tube and assembly.proximal == "tube-free":
                tube_partners.append(b if u.find(a) == tube_root else a)
            else:
                u.join(a, b)
                tube_root = u.find(TUBE)
    for p in tube_partners[1:]:  # tied together through the cap, clamped together at the base
        u.join(p, tube_partners[0])
    roots = sorted({u.find(k) for k in labels})
    group = {k: roots.index(u.find(k)) for k in labels}
    share = np.zeros(len(roots))
    carrier = tube_partners[0] if tube_partners else TUBE
    share[group[carrier]] = 1.0
    return AxialPlan(group=group, cap_share=share)


@dataclass(frozen=True)
class AsBuiltSolution:
    """Section stiffness and unit-pressure responses with G axial groups.

    ``stiffness`` is (G+2)x(G+2) over (eps_0 per group, k_1, k_2); ``loads`` as in
    :class:`softcath.fem.section_model.solve.SectionSolution`.
    """

    stiffness: np.ndarray
    loads: dict
    backward_error: float
    plan: AxialPlan


def solve_as_built(
    op, ties, plan: AxialPlan, loads=LOADS, *, extra_bending: float = 0.0, slip_modulus: float
):
    """Solve an operator assembled on a split mesh with axial groups, under normal ties.

    Parameters
    ----------
    op
        ``assemble(split.mesh, laws, axial_groups=...)``.
    ties
        :func:`softcath.fem.section_model.interfaces.tie_projection` on ``op.basis``.
    plan
        The axial groups and cap shares.
    loads, extra_bending
        As in :func:`softcath.fem.section_model.solve.solve`.
    slip_modulus
        Tangential spring modulus of the interfaces (N/mm^3).
    """
    loads = tuple(loads)
    if not loads or any(ld not in LOADS for ld in loads):
        raise DesignError("load", loads, f"must be a non-empty subset of {LOADS}")
    T = ties.T
    K = (T.T @ op.K_uu @ T + ties.spring(slip_modulus)).tocsr()
    kug = T.T @ op.K_ug
    fl = T.T @ op.f_lumen
    nh, ng = K.shape[0], kug.shape[1]
    pins = _pins(op, ties)
    free = np.setdiff1d(np.arange(nh), pins)
    kff = K[free][:, free].tocsc()
    lu = splu(kff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    rhs = np.column_stack([kug[free], fl[free]])
    sol = lu.solve(rhs)
    resid = kff @ sol - rhs
    scale = abs(kff).sum(axis=1).A.ravel().max() * np.abs(sol).max(axis=0) + np.abs(rhs).max(axis=0)
    backward = float((np.abs(resid).max(axis=0) / np.where(scale > 0, scale, 1.0)).max())
    x_g, x_p = sol[:, :ng], sol[:, ng]
    k_sec = op.K_gg - kug[free].T @ x_g
    k_sec = 0.5 * (k_sec + k_sec.T)
    k_sec[-2, -2] += extra_bending
    k_sec[-1, -1] += extra_bending
    xl, yl = op.lumen_centroid
    cap = np.concatenate([plan.cap_share, [xl, yl]]) * op.lumen_area
    out = {}
    for ld in loads:
        f_g = cap.copy()
        u_p = np.zeros(nh)
        if ld == "lumen":
            f_g -= kug[free].T @ x_p
            u_p[free] = x_p
        g = np.linalg.solve(k_sec, f_g)
        u_hat = u_p.copy()
        u_hat[free] -= x_g @ g
        u = T @ u_hat
        out[ld] = LoadSolution(strains=g, U=op.full_field(u, g), lumen_area_change=float(op.f_lumen @ u))
    return AsBuiltSolution(stiffness=k_sec, loads=out, backward_error=backward, plan=plan)


def _pins(op, ties) -> np.ndarray:
    """Three reduced unknowns (vertex DOFs kept as they are) that remove in-plane rigid motion."""
    nd = op.basis.nodal_dofs
    p = np.asarray(op.mesh.doflocs)[:, : nd.shape[1]]
    col = {int(d): i for i, d in enumerate(ties.retained) if d >= 0}
    ok = np.array([int(nd[0, v]) in col and int(nd[1, v]) in col for v in range(nd.shape[1])])
    c = p.mean(axis=1)
    dist = np.where(ok, np.hypot(p[0] - c[0], p[1] - c[1]), np.inf)
    a = int(np.argmin(dist))
    b = int(np.argmax(np.where(ok, np.abs(p[1] - p[1, a]), -1.0)))
    return np.array([col[int(nd[0, a])], col[int(nd[1, a])], col[int(nd[0, b])]])


def bodies_and_ties(section, assembly: Assembly):
    """Split ``section`` at every region boundary; bonded boundaries tied in full.

    Returns ``(split, tie)``: the :class:`~.interfaces.InterfaceSplit` (one body
    per region label) and per interface edge True where only the normal is tied.
    """
    split = split_interfaces(section, section.labels.astype(np.int64))
    kinds = [interface_kind(assembly, int(a), int(b)) for a, b in split.edge_bodies]
    return split, np.array([k != "bonded" for k in kinds], bool)


COIL_LABEL = COIL  # the outer coil: its group's stretch is the tip's elongation


def as_built_operator(
    section,
    laws,
    assembly: Assembly,
    loads=LOADS,
    *,
    extra_bending: float = 0.0,
    slip_modulus: float | None = None,
):
    """Split, assemble and solve ``section`` as built: ``(split mesh, op, solution)``.

    ``slip_modulus`` None takes 1e-9 of the softest region's axial modulus per mm
    (only to remove free spins; see the module docstring).
    """
    split, tie = bodies_and_ties(section, assembly)
    plan = axial_plan(assembly, np.unique(section.labels))
    groups = np.array([plan.group[int(k)] for k in section.labels])
    op = assemble(split.mesh, laws, axial_groups=groups)
    ties = tie_projection(split, op.basis, tie=tie)
    if slip_modulus is None:
        slip_modulus = 1e-9 * min(laws[int(k)].axial_modulus for k in np.unique(section.labels))
    sol = solve_as_built(op, ties, plan, loads, extra_bending=extra_bending, slip_modulus=slip_modulus)
    return split.mesh, op, sol


def summary(op, sol: AsBuiltSolution) -> dict:
    r"""Beam quantities of an as-built solution.

    Returns ``stiffness`` (3x3, (N, M_1, M_2) per (eps_0, k_1, k_2) with every group
    stretching alike), ``EI`` and ``EI_lateral`` (bending with each group's axial
    force zero: the groups' stretches condensed out, :math:`\sum EI` about each
    group's own axis when all slip), ``elongation`` per load (the outer coil's
    group at the stiffness-weighted centroid) and ``curvature`` per load.
    """
    K = sol.stiffness
    G = sol.plan.n_groups
    R = np.zeros((G + 2, 3))
    R[:G, 0] = 1.0
    R[G, 1] = R[G + 1, 2] = 1.0
    K3 = R.T @ K @ R
    kee, kek, kkk = K[:G, :G], K[:G, G:], K[G:, G:]
    kb = kkk - kek.T @ np.linalg.solve(kee, kek)
    gc = sol.plan.group.get(COIL_LABEL, 0)
    return {
        "stiffness": K3,
        "EI": float(kb[1, 1]),
        "EI_lateral": float(kb[0, 0]),
        "curvature": {ld: float(s.strains[-1]) for ld, s in sol.loads.items()},
        "elongation": {
            ld: float(s.strains[gc] + s.strains[-1] * op.axial_centroid_y) for ld, s in sol.loads.items()
        },
    }
