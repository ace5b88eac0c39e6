"""The chosen designs of a selection as design files, ready to build and to re-check.

Each of the first ranked designs is rebuilt from the sweep (base design plus its
swept values, :func:`softcath.studies.report.html_report.design_of`) and written as a
TOML design file that ``softcath design validate``, ``softcath section`` and
``softcath fem`` take as it is. The file's header says where the design came from:
the selection's tier and load, its rank and its objective values.
"""

from __future__ import annotations

import dataclasses
import logging
from pathlib import Path

from softcath import design
from softcath.design.errors import DataError, DesignError
from softcath.studies.report.html_report import design_of
from softcath.studies.selection.ranking import Selection
from softcath.studies.tiers import TIERS

__all__ = ["DESIGNS_FOLDER", "DEFAULT_DESIGN_FILES", "design_file_name", "chosen_design_files"]

log = logging.getLogger(__name__)

#: Folder (inside the selection's output folder) that holds the chosen designs.
DESIGNS_FOLDER = "designs"
#: How many ranked designs get a file by default (the ones the summary prints).
DEFAULT_DESIGN_FILES = 5


def design_file_name(design_id: int) -> str:
    """Relative path of design ``design_id``'s file, e.g. ``designs/design_20.toml``."""
    return f"{DESIGNS_FOLDER}/design_{int(design_id)}.toml"


def _header(selection: Selection, entry: dict) -> str:
    tier = TIERS[selection.model].label if selection.model in TIERS else "the table as given"
    lines = [
        f"softcath select: design {entry['design_id']}, rank {entry['rank']} of {selection.n_feasible} "
        f"feasible{' (Pareto front)' if entry.get('pareto') else ''}",
        f"tier: {tier} ({selection.model}), {selection.load} load",
    ]
    src = selection.source  # every value says its tier and load, as the summary's lines do
    where = f"[{src['tier']}{' ' + src['statistic'] if 'statistic' in src else ''}, {src['load']} load]"
    lines += [f"constraint: {c} {where}" for c in selection.constraints]
    lines += [f"{k} -> {v:.6g} {where}" for k, v in entry["objectives"].items()]
    return "\n".join(lines)


def chosen_design_files(
    selection: Selection, sweep_dir: str | Path, *, count: int = DEFAULT_DESIGN_FILES
) -> tuple[Selection, dict[str, str]]:
    """The first ``count`` ranked designs as design-file text, and the selection that names them.

    Parameters
    ----------
    selection
        A selection of the sweep in ``sweep_dir``.
    sweep_dir
        The sweep's output folder (``sweep.json`` and ``designs.csv``).
    count
        How many ranked designs get a file (0: none).

    A sweep folder whose designs cannot be rebuilt (no ``designs.csv``, a damaged manifest) gets
    no files; a warning says why and the ranking stands.

    Returns
    -------
    selection, files
        ``selection`` whose ranked entries with a file carry ``design_file`` (the path relative
        to the output folder), and ``{relative path: TOML text}``.
    """

    files: dict[str, str] = {}
    ranked = []
    for entry in selection.ranked:
        if len(files) < count:
            try:
                d = design_of(sweep_dir, entry["design_id"])
            except (DataError, DesignError) as exc:  # a damaged or older sweep folder: the ranking stands
                log.warning("no design files written: %s", exc)
                return selection, {}
            name = design_file_name(entry["design_id"])
            files[name] = design.dumps(d, header=_header(selection, entry))
            entry = {**entry, "design_file": name}
        ranked.append(entry)
    return dataclasses.replace(selection, ranked=ranked), files
