r"""Partial interaction along the tip: two axial groups joined by an interface spring layer.

The section model's Saint-Venant state has no slip varying along z, so an
interface that resists axial slip elastically (adhesive, friction before
sliding: slip modulus :math:`k`, N/mm² of shear flow per mm of slip) is a
1-D problem along the tip (Newmark, Siess & Viest 1951). With the section's
stiffness :math:`K` over :math:`g = (\varepsilon_{0,1}, \varepsilon_{0,2},
k_1, k_2)` (two axial groups, from
:mod:`softcath.fem.section_model.as_built`), the group forces are
:math:`N_1 = F_1 + \Delta N(z)`, :math:`N_2 = F_2 - \Delta N(z)`, the moments
are fixed by the tip load, and the slip :math:`s = w_2 - w_1` obeys

.. math::

    s' = \varepsilon_{0,2} - \varepsilon_{0,1} = s'_0 + \beta\,\Delta N, \qquad
    \Delta N' = -k s,

so :math:`\Delta N'' - \alpha^2 \Delta N = k s'_0` with
:math:`\alpha^2 = -k\beta`. At the clamped base the groups cannot slip
(:math:`s(0) = 0`, i.e. :math:`\Delta N'(0) = 0`); at the free tip they carry
the applied forces (:math:`\Delta N(L) = 0`):

.. math::

    \Delta N(z) = N_\infty \left(1 - \frac{\cosh \alpha z}{\cosh \alpha L}\right),
    \qquad N_\infty = -s'_0/\beta,

and the tip-level curvature (tip angle / L) is the section curvature at the
mean force :math:`\overline{\Delta N} = N_\infty (1 - \tanh(\alpha L)/(\alpha L))`.
:math:`k \to 0` is the sliding tip, :math:`k \to \infty` the bonded one.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.design.errors import DesignError

__all__ = ["tip_strains"]


def tip_strains(
    stiffness: np.ndarray, forces: np.ndarray, *, slip_modulus: float, length: float
) -> np.ndarray:
    r"""Length-averaged global strains of a two-group tip with an interface spring layer.

    Parameters
    ----------
    stiffness
        (4, 4) section stiffness over (eps_0 of group 1, eps_0 of group 2, k_1, k_2).
    forces
        (4,) tip loads (F_1, F_2, M_1, M_2): each group's axial force and the moments.
    slip_modulus
        k >= 0, N/mm^2 (shear flow per unit slip).
    length
        Tip length L > 0, mm.

    Returns
    -------
    numpy.ndarray
        (4,) the strains averaged over z (their curvatures are the tip-level ones).
    """
    K = np.asarray(stiffness, float)
    f = np.asarray(forces, float)
    if K.shape != (4, 4) or f.shape != (4,):
        raise DesignError("stiffness", K.shape, "must be (4, 4) with forces (4,): two axial groups")
    if not (math.isfinite(slip_modulus) and slip_modulus >= 0):
        raise DesignError("slip_modulus", slip_modulus, "must be finite and >= 0")
    if not (math.isfinite(length) and length > 0):
        raise DesignError("length", length, "must be finite and > 0")
    C = np.linalg.inv(K)
    g0 = C @ f
    dg = C @ np.array([1.0, -1.0, 0.0, 0.0])  # strains per unit force moved from group 2 to group 1
    s0 = g0[1] - g0[0]
    beta = dg[1] - dg[0]  # < 0 for a positive-definite K
    if slip_modulus == 0.0:
        return g0
    n_inf = -s0 / beta
    al = math.sqrt(-slip_modulus * beta) * length
    mean = n_inf * (1.0 - (math.tanh(al) / al if al > 1e-8 else 1.0 - al**2 / 3))
    return g0 + mean * dg
