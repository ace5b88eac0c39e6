"""The sweep directory: one file per finished task, written atomically, so a killed sweep resumes.

Layout of ``DIR``::

    sweep.json         the spec as run, its fingerprint, design and task counts
    designs.csv        design_id and the swept values of every design
    tasks/t000042.parquet   rows of one finished task (written to a temp file, then renamed)
    events.jsonl       one line per task evaluated, by which run (the evaluator call log)
    results.parquet, results.csv, columns.json   the merged table (after the run)
"""

from __future__ import annotations

import json
import logging
import os
import time
import uuid
from pathlib import Path

from softcath.core.errors import DataError
from softcath.studies.sweep.results import _TEXT_COLUMNS, _stringify_objects

__all__ = ["SweepStore", "arrow_table", "design_counts"]

log = logging.getLogger(__name__)


class SweepStore:
    """Read and write the finished tasks of one sweep directory."""

    def __init__(self, out_dir: str | Path) -> None:
        self.root = Path(out_dir)
        self.tasks_dir = self.root / "tasks"

    def recorded_spec(self) -> dict | None:
        """The spec a prepared directory was run with (its ``sweep.json``), or None."""
        path = self.root / "sweep.json"
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError, UnicodeDecodeError):
            return None  # absent, or unreadable: prepare() reports it
        spec = old.get("spec") if isinstance(old, dict) else None
        return spec if isinstance(spec, dict) else None

    def prepare(self, manifest: dict, designs_frame) -> None:
        """Create the directory, or check that it holds the same sweep (same fingerprint)."""
        self.root.mkdir(parents=True, exist_ok=True)
        self.tasks_dir.mkdir(exist_ok=True)
        path = self.root / "sweep.json"
        if path.is_file():
            try:
                old = json.loads(path.read_text(encoding="utf-8"))
            except (json.JSONDecodeError, UnicodeDecodeError) as exc:
                raise DataError(
                    f"{path}: unreadable sweep manifest ({exc}); use another output folder"
                ) from None
            if old.get("spec", {}).get("fingerprint") != manifest["spec"]["fingerprint"]:
                raise DataError(
                    f"{self.root} holds a different sweep (fingerprint "
                    f"{old.get('spec', {}).get('fingerprint')}, "
                    f"this spec is {manifest['spec']['fingerprint']}); use another output folder"
                )
        else:
            # designs.csv first: sweep.json marks a prepared directory
            tmp = self.root / f".designs.{uuid.uuid4().hex}.tmp"
            designs_frame.to_csv(tmp, index=False)
            os.replace(tmp, self.root / "designs.csv")
            self._atomic_text(path, json.dumps(manifest, indent=1, default=str))
        for stale in self.tasks_dir.glob(".*.tmp"):
            stale.unlink(missing_ok=True)  # half-written files of a killed run
        self._set_aside_corrupted()

    def _set_aside_corrupted(self) -> None:
        """Rename task files whose parquet footer cannot be read, so their tasks are recomputed.

        A task file is renamed into place whole, so damage comes from outside (a disk
        fault, a copy cut short); the resumed sweep must neither crash on it nor trust it.
        """
        import pyarrow.parquet as pq

        for path in sorted(self.tasks_dir.glob("t*.parquet")):
            try:
                pq.read_metadata(path)
            except Exception as exc:  # pyarrow raises several types for a damaged file
                aside = path.with_name(path.name + ".corrupt")
                os.replace(path, aside)
                log.warning(
                    "%s: unreadable (%s); set aside as %s, its task will be computed again",
                    path,
                    " ".join(str(exc).split())[:120],
                    aside.name,
                )

    def task_path(self, task_id: int) -> Path:
        return self.tasks_dir / f"t{task_id:06d}.parquet"

    def finished(self) -> set[int]:
        """Ids of the tasks whose result file is complete."""
        return {int(p.stem[1:]) for p in self.tasks_dir.glob("t*.parquet")}

    def write_task(self, task_id: int, frame, *, run_id: str) -> None:
        """Write one task's rows atomically (temp file + rename), then log the evaluation."""
        import pyarrow.parquet as pq

        tmp = self.tasks_dir / f".t{task_id:06d}.{uuid.uuid4().hex}.tmp"
        # A task file is read whole by read_all only: column statistics and dictionary pages
        # (a third of the write time of a 150-row file) would never be used.
        pq.write_table(arrow_table(frame), tmp, use_dictionary=False, write_statistics=False)
        os.replace(tmp, self.task_path(task_id))
        designs, failed = design_counts(frame)
        line = json.dumps(
            {
                "run": run_id,
                "task": task_id,
                "designs": designs,
                "failed": failed,
                "t": round(time.time(), 3),
            }
        )
        with open(self.root / "events.jsonl", "a", encoding="utf-8") as fh:
            fh.write(line + "\n")

    def events(self) -> list[dict]:
        """The evaluation log: one record per task evaluated (``run``, ``task``, ``designs``, ``failed``,
        ``t`` = Unix time [s] when its result was saved)."""
        path = self.root / "events.jsonl"
        if not path.is_file():
            return []
        out = []
        for line in path.read_text(encoding="utf-8").splitlines():
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                continue  # a line cut by a kill
        return out

    def read_all(self):
        """All finished task rows as one DataFrame, ordered by design, load, pressure."""
        import pandas as pd
        import pyarrow as pa
        import pyarrow.parquet as pq

        files = sorted(self.tasks_dir.glob("t*.parquet"))
        if not files:
            raise DataError(f"{self.root}: no finished designs")
        tables = []
        for f in files:
            try:
                # ParquetFile.read, not read_table: the dataset machinery of read_table costs
                # ~3 ms per file, the whole merge of a 10^5-design sweep's 4,000 task files.
                with pq.ParquetFile(f) as pf:
                    tables.append(pf.read())
            except Exception as exc:  # pyarrow raises several types for a damaged file
                raise DataError(
                    f"{f}: cannot be read ({type(exc).__name__}); rerun the same `softcath sweep` "
                    "command: it sets damaged task files aside and computes those tasks again"
                ) from None
        try:
            df = pa.concat_tables(tables, promote_options="permissive").to_pandas()
        except (
            pa.ArrowInvalid,
            pa.ArrowTypeError,
        ):  # e.g. a swept column numeric in one task, text in another
            df = pd.concat([t.to_pandas() for t in tables], ignore_index=True)
        return df.sort_values(["design_id", "load", "pressure_MPa"], kind="stable", ignore_index=True)

    @staticmethod
    def _atomic_text(path: Path, text: str) -> None:
        tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)


def design_counts(frame) -> tuple[int, int]:
    """Designs in a task's rows and how many of them failed (status of each design's first row).

    The same counts as ``nunique`` and ``drop_duplicates("design_id")`` on the status, in numpy:
    the parent counts every task it stores.
    """
    import numpy as np

    _, first = np.unique(frame["design_id"].to_numpy(), return_index=True)
    status = frame["status"].to_numpy()[first]
    return len(first), int(np.count_nonzero(status == "failed"))


def arrow_table(frame):
    """The Arrow table a task file holds: ``pa.Table.from_pandas(_stringify_objects(frame))``, faster.

    A task's frame has numpy columns, pandas text columns and object columns of swept numbers
    only; each goes to Arrow as those two calls convert it (swept numbers to float64, NaN →
    null, text as ``large_string``) in a fraction of their time, without the pandas metadata
    (``read_all`` reads the tables back to the same DataFrame). A frame with any other column
    takes the two calls themselves.
    """
    import numpy as np
    import pandas as pd
    import pyarrow as pa

    if frame.columns.is_unique and all(isinstance(c, str) for c in frame.columns):
        arrays = []
        for name, col in frame.items():
            values = col.to_numpy() if isinstance(col.dtype, np.dtype) else None
            if values is not None and values.dtype == object and name not in _TEXT_COLUMNS:
                if not (len(values) and all(type(v) is float for v in values)):
                    break  # numbers and names: _stringify_objects decides
                values = values.astype(float)  # as _stringify_objects converts swept numbers
            if values is not None and values.dtype.kind in "biuf":
                arrays.append(pa.array(values, from_pandas=True))
            elif isinstance(col.dtype, pd.StringDtype) and col.dtype.storage == "pyarrow":
                arrays.append(pa.array(col.array))
            else:
                break
        else:
            return pa.Table.from_arrays(arrays, names=list(frame.columns))
    return pa.Table.from_pandas(_stringify_objects(frame), preserve_index=False)
