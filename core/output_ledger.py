"""Which files in an output folder softcath wrote, and which files a command reads.

A command may replace its own earlier outputs, never anything else: not a file the
user put into ``--out`` (a photo, notes, a design), and not a file the command itself
reads (``section --measured OUT/section.csv --out OUT``). Each output folder keeps a
hidden ledger, ``.softcath-outputs.json``, of the files softcath committed there and
the command that wrote each. :mod:`softcath.core.atomic` consults it before every
commit:

- a destination that is one of the command's inputs (:func:`protect_inputs`) is refused;
- a destination that exists but is not in the ledger, or was changed since (its size or
  modification time differ), is refused: softcath did not write it, so it is the user's;
- after a commit made for an ``owner`` (``optimise``, ``report``), the files that owner
  wrote into the folder before and this run did not write again (stale Pareto designs, an
  earlier report's figures) are removed; they are in the ledger, so they are softcath's.

The refusals name ``out_dir`` (the command line says ``--out``).
"""

from __future__ import annotations

import contextlib
import json
import os
import uuid
from collections.abc import Iterable
from pathlib import Path

from softcath.core.errors import DesignError

__all__ = [
    "LEDGER",
    "protect_inputs",
    "forget_inputs",
    "check_replace",
    "check_inputs_outside",
    "record",
    "stale_files",
]

#: The ledger's file name inside an output folder (hidden, like the staging folders).
LEDGER = ".softcath-outputs.json"

#: Resolved paths of the files the running command reads (see :func:`protect_inputs`).
_INPUTS: dict[Path, str] = {}


def protect_inputs(paths: Iterable[tuple[str, object]]) -> None:
    """Remember the command's input files ``(option, path)``: no output may replace one.

    Paths that are not existing files (preset names, folders) are ignored.
    """
    for option, path in paths:
        if not isinstance(path, str | os.PathLike):
            continue
        try:
            p = Path(path)
            if p.is_file():
                _INPUTS[p.resolve()] = option
        except (OSError, ValueError):  # an unprintable or impossible path: not a file
            continue


def forget_inputs() -> None:
    """Forget the inputs (a command ended)."""
    _INPUTS.clear()


def _read(root: Path) -> dict[str, dict]:
    """``{relative path: {"owner", "size", "mtime_ns"}}`` of the ledger (empty if missing or damaged)."""
    try:
        doc = json.loads((root / LEDGER).read_text(encoding="utf-8"))
        files = doc.get("files", {}) if isinstance(doc, dict) else {}
        return {str(k): v for k, v in files.items() if isinstance(v, dict)} if isinstance(files, dict) else {}
    except (OSError, ValueError):
        return {}


def _stamp(path: Path) -> tuple[int, int]:
    st = path.stat()
    return st.st_size, st.st_mtime_ns


def _unchanged(path: Path, entry: dict) -> bool:
    """The file is still the one softcath committed (same size and modification time)."""
    try:
        return _stamp(path) == (entry.get("size"), entry.get("mtime_ns"))
    except OSError:
        return False


def _rel(root: Path, path: Path) -> str:
    return path.resolve().relative_to(root.resolve()).as_posix()


def check_replace(root: str | Path, destinations: Iterable[str | Path]) -> None:
    """Refuse a commit into ``root`` that would replace an input or a file softcath did not write.

    Raises
    ------
    DesignError
        Naming ``out_dir`` with the folder, the file and why it is kept.
    """
    root = Path(root)
    known = _read(root)
    for dst in map(Path, destinations):
        full = dst.resolve()
        if full in _INPUTS:
            raise DesignError(
                "out_dir",
                str(root),
                f"the output {dst.name} would overwrite the input {dst} ({_INPUTS[full]}); "
                "write into another folder",
            )
        if dst.exists() and not dst.is_dir():
            try:
                rel = _rel(root, dst)
            except ValueError:  # outside the folder: an explicitly named output file
                continue
            if rel not in known:
                raise DesignError(
                    "out_dir",
                    str(root),
                    f"holds {rel}, which softcath did not write; it is left as it is: move it or "
                    "write into another folder",
                )
            if not _unchanged(dst, known[rel]):
                raise DesignError(
                    "out_dir",
                    str(root),
                    f"holds {rel}, changed since softcath wrote it; it is left as it is: move it or "
                    "write into another folder",
                )


def check_inputs_outside(root: str | Path, under: str = "") -> None:
    """Refuse, before any work, an input inside ``root/under`` (a folder the command refills).

    Raises
    ------
    DesignError
        Naming ``out_dir``, the input and its option.
    """
    folder = (Path(root) / under).resolve()
    for path, option in _INPUTS.items():
        if folder in path.parents:
            raise DesignError(
                "out_dir",
                str(root),
                f"holds the input {path} ({option}) where this command writes its outputs; "
                "write into another folder (or move the input out)",
            )


def stale_files(root: str | Path, owner: str, written: Iterable[str | Path]) -> list[Path]:
    """Files ``owner`` wrote into ``root`` before that are not among ``written`` now (and exist)."""
    root = Path(root)
    now = set()
    for p in written:
        with contextlib.suppress(ValueError):
            now.add(_rel(root, Path(p)))
    return [
        root / rel
        for rel, entry in _read(root).items()
        if entry.get("owner") == owner
        and rel not in now
        and (root / rel).is_file()
        and _unchanged(root / rel, entry)
        and (root / rel).resolve() not in _INPUTS
    ]


def record(root: str | Path, written: Iterable[str | Path], *, owner: str | None, removed=()) -> None:
    """Add ``written`` (files now committed in ``root``) to its ledger; drop ``removed``."""
    root = Path(root)
    files = _read(root)
    for p in removed:
        with contextlib.suppress(ValueError):
            files.pop(_rel(root, Path(p)), None)
    for p in written:
        with contextlib.suppress(ValueError, OSError):
            size, mtime = _stamp(Path(p))
            files[_rel(root, Path(p))] = {"owner": owner or "", "size": size, "mtime_ns": mtime}
    tmp = root / f".{LEDGER.lstrip('.')}.{os.getpid()}-{uuid.uuid4().hex[:8]}.tmp.json"
    try:
        tmp.write_text(json.dumps({"files": dict(sorted(files.items()))}, indent=1) + "\n", encoding="utf-8")
        os.replace(tmp, root / LEDGER)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
