"""Plotting set-up: every figure softcath draws goes to a file, through matplotlib's Agg backend."""

from __future__ import annotations

__all__ = ["pyplot"]


def pyplot():
    """``matplotlib.pyplot`` with the Agg (file-only) backend selected, so no display is needed.

    matplotlib is imported here, on the first figure, not when a module is imported: it is a
    heavy optional path and ``softcath --help`` must stay fast.
    """
    import matplotlib  # heavy: loaded on the first figure only

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # heavy: loaded on the first figure only

    return plt
