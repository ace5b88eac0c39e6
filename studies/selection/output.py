"""Writing a selection: ``selection.json``, atomically."""

from __future__ import annotations

import json
from pathlib import Path

from softcath.studies.selection.ranking import Selection

__all__ = ["write_selection"]


def write_selection(selection: Selection, out_dir: str | Path) -> Path:
    """Write ``DIR/selection.json`` (atomically)."""
    import os

    path = Path(out_dir) / "selection.json"
    tmp = path.with_name(".selection.json.tmp")
    tmp.write_text(json.dumps(selection.to_json(), indent=1), encoding="utf-8")
    os.replace(tmp, path)
    return path
