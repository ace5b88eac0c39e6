"""Writing a selection: ``selection.json`` and the chosen design files, atomically, together.

Nothing is written over a file softcath did not write; design files an earlier
``select`` wrote into the folder and this one did not are removed.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path

from softcath.core.atomic import Outputs
from softcath.studies.selection.ranking import Selection

__all__ = ["write_selection"]


def write_selection(
    selection: Selection, out_dir: str | Path, *, designs: Mapping[str, str] | None = None
) -> Path:
    """Write ``DIR/selection.json`` and ``designs`` (``{relative path: text}``) in one commit.

    Uses :class:`softcath.core.atomic.Outputs`: either every file is written or none.

    Raises
    ------
    DesignError
        A destination exists and softcath did not write it, or it is an input.
    """

    out = Path(out_dir)
    for name in designs or {}:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
    with Outputs(out, owner="select") as o:
        path = o.text("selection.json", json.dumps(selection.to_json(), indent=1))
        for name, text in (designs or {}).items():
            o.text(name, text)
    return Path(path)
