"""The 3-D FEM's lumen load: the pressure on every wetted face of the lumen.

``lumen`` (the real load) pushes on the lumen wall and on the sealed cap's
inner face; ``cap`` (the paper's end-cap force) on the cap's inner face only.
The faces are tagged geometrically (:func:`softcath.fem.tags.tag_facets`) and
a unit pressure on them becomes a load vector in
:meth:`softcath.fem.elasticity.ElasticProblem.pressure_load` (traction −n: the
fluid pushes into the material). The finite-strain FEM applies the same faces
as a follower pressure (:mod:`softcath.fem.nonlinear.catheter`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

__all__ = ["pressure_facets"]


def pressure_facets(tags: Mapping[str, np.ndarray], load: str) -> np.ndarray:
    """The boundary facets a pressure acts on under ``load`` (``"cap"`` or ``"lumen"``).

    Parameters
    ----------
    tags
        Facet tags of the tip mesh (:func:`softcath.fem.tags.tag_facets`).
    load
        ``"cap"``: the cap's inner face; ``"lumen"``: the cap's inner face and the lumen wall.
    """
    return tags["cap"] if load == "cap" else np.concatenate([tags["cap"], tags["lumen"]])
