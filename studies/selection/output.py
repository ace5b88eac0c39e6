"""Writing a selection: ``selection.json``, atomically, never over a file softcath did not write."""

from __future__ import annotations

import json
from pathlib import Path

from softcath.studies.selection.ranking import Selection

__all__ = ["write_selection"]


def write_selection(selection: Selection, out_dir: str | Path) -> Path:
    """Write ``DIR/selection.json`` (atomically; :class:`softcath.studies.atomic.Outputs`).

    Raises
    ------
    DesignError
        ``DIR/selection.json`` exists and softcath did not write it, or it is an input.
    """
    from softcath.studies.atomic import Outputs

    with Outputs(out_dir) as o:
        path = o.text("selection.json", json.dumps(selection.to_json(), indent=1))
    return Path(path)
