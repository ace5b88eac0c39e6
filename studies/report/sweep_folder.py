"""A sweep's output folder read back: its manifest and the designs it swept."""

from __future__ import annotations

import json
from pathlib import Path

from softcath.design.errors import DataError
from softcath.studies.sweep.variants import VariantBuilder

__all__ = ["design_of"]


def _manifest(sweep_dir: Path) -> dict:
    path = sweep_dir / "sweep.json"
    if not path.is_file():
        raise DataError(f"{sweep_dir}: no sweep.json (is this a `softcath sweep` output directory?)")
    fix = "rerun the sweep into a new --out folder"
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: unreadable sweep manifest ({exc}); {fix}") from None
    spec = doc.get("spec") if isinstance(doc, dict) else None
    params = spec.get("parameters") if isinstance(spec, dict) else None
    if not (
        isinstance(params, list)
        and all(isinstance(p, dict) and {"path", "kind"} <= set(p) for p in params)
        and isinstance(doc.get("base_table"), dict)
    ):
        raise DataError(f"{path}: not a sweep manifest (no spec.parameters or base_table); {fix}")
    return doc


def design_of(sweep_dir: str | Path, design_id: int):
    """Rebuild design ``design_id`` of a sweep (base design + its swept values)."""
    import pandas as pd

    sweep_dir = Path(sweep_dir)
    manifest = _manifest(sweep_dir)
    path = sweep_dir / "designs.csv"
    try:
        designs = pd.read_csv(path)
        row = designs[designs.design_id == design_id].iloc[0]
    except Exception as exc:  # pandas raises several types for a damaged table
        raise DataError(
            f"{path}: cannot be read ({type(exc).__name__}: {' '.join(str(exc).split())[:120]}); "
            "rerun the sweep into a new --out folder"
        ) from None
    variant = {k: v.item() if hasattr(v, "item") else v for k, v in row.items() if k != "design_id"}
    return VariantBuilder(manifest["base_table"]).build(variant, name=f"design {design_id}")
