"""The two pressure loads every model of the tip can apply.

``LOADS = ("cap", "lumen")``:

- ``"cap"`` — the closed-end force on the cap only: F = p·A_p at the lumen
  centre (the paper's load, eqs. 4 and 7).
- ``"lumen"`` — the pressure on the lumen wall plus the cap force (the real
  hydraulic load).

This tuple is the one definition of the load names; the models, studies and
command line import it. Its order is the reporting order (cap, then lumen).
"""

from __future__ import annotations

__all__ = ["LOADS"]

LOADS = ("cap", "lumen")
