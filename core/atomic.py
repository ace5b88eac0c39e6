"""Command outputs that appear whole or not at all.

Every file a ``softcath`` command writes goes through this module: it is
written under a temporary name in the same folder (same file system, so the
rename is atomic) and renamed over the real name only when the writer
succeeded. A command that fails therefore never leaves a half-written file
and never replaces an earlier good one. :class:`Outputs` extends this to a
group of files (e.g. ``calibration.json`` with its PNG and TOML): none of
them is replaced unless all were written.

JSON outputs refuse NaN and infinities (strict JSON has neither, and a NaN
in a result file is a silent wrong answer); the error names the key.

Streaming files that must survive a kill while being written (the
recorder's CSV, a sweep's per-task files) are the deliberate exception:
they are appended and fsync-ed, or written per chunk with the same
temp-and-rename step.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import shutil
import uuid
from collections.abc import Iterator
from pathlib import Path

from softcath.core.errors import DataError, DesignError
from softcath.core.output_ledger import check_replace, record, stale_files

__all__ = [
    "prepare_out_dir",
    "check_parent",
    "check_outputs",
    "atomic_path",
    "write_text",
    "write_json",
    "check_finite_json",
    "Outputs",
    "staged_dir",
    "unstage",
    "remove_stale_temps",
    "pid_alive",
    "remove_created_dirs",
    "folder_lock",
    "forget_created_dirs",
]


def prepare_out_dir(path: str | Path, *, param: str = "out_dir") -> Path:
    """Create the output folder ``path`` (and its parents), or refuse in one line.

    The folder is also checked to be writable (a file is created and removed), so a
    command refuses an unwritable folder before its work, not when it writes results.
    Folders created here are remembered: :func:`remove_created_dirs` takes them away
    again, if still empty, when the command is refused or fails.

    Raises
    ------
    DesignError
        ``path`` or one of its parents exists and is not a folder, cannot be created, or
        is not writable.
    """
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise DesignError(param, str(out), "exists and is not a folder; give a folder path")
    for parent in out.parents:
        if parent.exists() and not parent.is_dir():
            raise DesignError(param, str(out), f"{parent} is a file, not a folder")
    missing = [p for p in (out, *out.parents) if not p.exists()]
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise DesignError(param, str(out), f"cannot be created ({exc.strerror or exc})") from None
    _CREATED.extend(reversed(missing))  # parents first, so removal runs deepest first
    probe = _temp_name(out / "write-check")
    try:
        probe.touch()
    except OSError as exc:
        raise DesignError(param, str(out), f"is not writable ({exc.strerror or exc})") from None
    finally:
        with contextlib.suppress(OSError):
            probe.unlink()
    remove_stale_temps(out)
    return out


@contextlib.contextmanager
def folder_lock(folder: str | Path, *, param: str = "out_dir", what: str = "command") -> Iterator[Path]:
    """Hold an exclusive lock on ``folder`` for the block, or refuse at once if another process holds it.

    The lock is an ``flock`` on the hidden file ``.softcath.lock`` in the folder: the kernel
    releases it when the holder exits, even on SIGKILL, so a stale lock cannot exist.

    Raises
    ------
    DesignError
        Another process holds the lock (names ``param``, the folder and that process).
    """
    lock = Path(folder) / ".softcath.lock"
    fh = open(lock, "a+", encoding="ascii")  # noqa: SIM115 - closed in the finally below
    try:
        try:
            import fcntl

            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except ImportError:  # no flock on this platform: no protection, as before
            pass
        except OSError:
            fh.seek(0)
            holder = fh.read().strip() or "unknown"
            raise DesignError(
                param,
                str(folder),
                f"another {what} is writing into this folder (pid {holder}); "
                "wait for it to finish or choose another folder",
            ) from None
        fh.seek(0)
        fh.truncate()
        fh.write(str(os.getpid()))
        fh.flush()
        yield Path(folder)
    finally:
        fh.close()


#: Output folders this process created (see :func:`remove_created_dirs`).
_CREATED: list[Path] = []


def remove_created_dirs() -> None:
    """Remove the folders :func:`prepare_out_dir` created in this process that are still empty.

    Called when a command is refused or fails, so a refusal leaves no empty ``--out``
    behind; a folder holding anything (another writer's file) is kept.
    """
    while _CREATED:
        folder = _CREATED.pop()
        with contextlib.suppress(OSError):
            folder.rmdir()  # only succeeds if empty


def forget_created_dirs() -> None:
    """Keep the folders created so far (the command succeeded)."""
    _CREATED.clear()


_TEMP = re.compile(
    r"^\.(?:.+\.(?P<pid>\d+)-[0-9a-f]{8}\.tmp(?:\.[^.]*)?|softcath-staging-(?P<spid>\d+)-[0-9a-f]{8})$"
)


def _temp_name(path: Path) -> Path:
    # The suffix is kept so that writers choosing the format by extension (matplotlib, VTK,
    # OpenCV) still do; the leading dot hides the temp file from globbing readers; the pid
    # lets a later run tell a killed writer's leftovers from a live writer's files.
    return path.with_name(f".{path.stem}.{os.getpid()}-{uuid.uuid4().hex[:8]}.tmp{path.suffix}")


def pid_alive(pid: int) -> bool:
    """True while process ``pid`` runs (a zombie, killed but not yet reaped, does not)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # runs under another user
        return True
    except OverflowError:
        return False
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            state = fh.read().rsplit(b")", 1)[1].split()[0]
        return state not in (b"Z", b"X")
    except (OSError, IndexError):  # no /proc (macOS): existence is all we know
        return True


def remove_stale_temps(folder: Path) -> int:
    """Delete the temporary files and staging folders of writers that no longer run (a SIGKILL)."""
    removed = 0
    for entry in folder.glob(".*"):
        m = _TEMP.match(entry.name)
        if not m:
            continue
        pid = int(m.group("pid") or m.group("spid"))
        if pid == os.getpid() or pid_alive(pid):
            continue
        if entry.is_dir():
            shutil.rmtree(entry, ignore_errors=True)
        else:
            entry.unlink(missing_ok=True)
        removed += 1
    return removed


def check_outputs(
    paths: dict[str, str | Path | None], *, inside: str | Path | None = None, inputs=()
) -> dict[str, Path]:
    """Resolve a command's output files and refuse collisions, before anything is written.

    Parameters
    ----------
    paths
        ``{parameter: path}``; ``None`` entries are left out.
    inside
        The output folder: a relative path is taken inside it and must stay inside it
        (``../x`` is refused); an absolute path is taken as given.
    inputs
        Files the command reads; an output naming one of them is refused (it would be
        overwritten by the run that reads it).

    Raises
    ------
    DesignError
        Naming the parameter: a path leaving ``inside``, two outputs naming one file, or an
        output naming an input.
    """
    base = None if inside is None else Path(inside).resolve()
    done: dict[str, Path] = {}
    seen: dict[Path, str] = {}
    read = {Path(p).resolve(): str(p) for p in inputs if p is not None and Path(p).exists()}
    for param, given in paths.items():
        if given is None:
            continue
        p = Path(given)
        if base is not None and not p.is_absolute():
            full = (base / p).resolve()
            if full != base and base not in full.parents:
                raise DesignError(
                    param,
                    str(given),
                    f"leaves the output folder {inside} (give a path inside it, or an absolute path)",
                )
        else:
            full = p.resolve()
        if full in seen:
            raise DesignError(param, str(given), f"names the same file as {seen[full]}; give another path")
        if full in read:
            raise DesignError(param, str(given), f"is the input {read[full]}; it would be overwritten")
        seen[full] = param
        done[param] = p if base is None or p.is_absolute() else Path(inside) / p
    return done


def check_parent(path: str | Path, *, param: str) -> Path:
    """The output file ``path`` with its folder created; refuse a path whose folder cannot exist."""
    p = Path(path)
    if p.exists() and p.is_dir():
        raise DesignError(param, str(p), "is a folder; give a file path")
    for parent in p.parents:
        if parent.exists() and not parent.is_dir():
            raise DesignError(param, str(p), f"{parent} is a file, not a folder")
    prepare_out_dir(p.parent, param=param)
    return p


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary sibling of ``path``; rename it to ``path`` only if the block succeeds.

    The writer inside the block must create the yielded path. If the block raises,
    or leaves no file, ``path`` is left untouched and the temporary file removed.
    """
    final = Path(path)
    tmp = _temp_name(final)
    try:
        yield tmp
        if not tmp.exists():
            raise DataError(f"{final}: the writer produced no file; nothing written")
        _fsync(tmp)
        os.replace(tmp, final)
    finally:
        with contextlib.suppress(FileNotFoundError, IsADirectoryError):
            tmp.unlink()


def _fsync(path: Path) -> None:
    with contextlib.suppress(OSError):  # fsync is best effort (e.g. some network file systems)
        fd = os.open(path, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def check_finite_json(obj: object, *, where: str = "") -> None:
    """Raise :class:`DataError` naming the first NaN or infinite number in a JSON-like ``obj``."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return
    if isinstance(obj, dict):
        for k, v in obj.items():
            check_finite_json(v, where=f"{where}.{k}" if where else str(k))
        return
    if isinstance(obj, list | tuple):
        for i, v in enumerate(obj):
            check_finite_json(v, where=f"{where}[{i}]")
        return
    try:
        x = float(obj)  # numbers, numpy scalars
    except (TypeError, ValueError):
        return
    if not math.isfinite(x):
        raise DataError(f"result {where or 'value'} = {x!r}: not finite; nothing written")


def _strict_json(obj: object, name: str, indent: int | None, default) -> str:
    check_finite_json(obj)
    try:
        return json.dumps(obj, indent=indent, allow_nan=False, default=default) + "\n"
    except ValueError as exc:  # a non-finite number hidden behind ``default``
        raise DataError(f"{name}: {exc}; nothing written") from None


def write_json(path: str | Path, obj: object, *, indent: int | None = 2, default=None) -> Path:
    """Write ``obj`` as strict JSON to ``path`` atomically; refuse NaN and infinities."""
    return write_text(path, _strict_json(obj, Path(path).name, indent, default))


class Outputs:
    """A group of output files committed together.

    ``with Outputs(out) as o:`` then ``o.path("calibration.json")`` gives a temporary
    path to write; :meth:`text` and :meth:`json` write through it. When the block ends
    without an exception every file is renamed to its real name; otherwise all
    temporary files are removed and the earlier outputs stay as they were. A file that
    softcath did not write, or one the command reads, is never replaced
    (:mod:`softcath.core.output_ledger`); with ``owner``, the files that owner wrote
    into the folder before and this commit did not are removed.
    """

    def __init__(self, folder: str | Path, *, owner: str | None = None) -> None:
        self.folder = Path(folder)
        self.owner = owner
        self._pending: dict[Path, Path] = {}

    def __enter__(self) -> Outputs:
        return self

    def path(self, name: str | Path) -> Path:
        """A temporary path for the output ``folder/name`` (renamed on success)."""
        final = self.folder / name
        if final not in self._pending:
            self._pending[final] = _temp_name(final)
        return self._pending[final]

    def text(self, name: str | Path, text: str) -> Path:
        """Stage ``text`` for ``folder/name``."""
        self.path(name).write_text(text, encoding="utf-8")
        return self.folder / name

    def json(self, name: str | Path, obj: object, *, indent: int | None = 2, default=None) -> Path:
        """Stage ``obj`` as strict JSON for ``folder/name``; refuse NaN and infinities."""
        return self.text(name, _strict_json(obj, str(name), indent, default))

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                missing = [f for f, t in self._pending.items() if not t.exists()]
                if missing:
                    raise DataError(f"{missing[0]}: the writer produced no file; nothing written")
                check_replace(self.folder, self._pending)
                for tmp in self._pending.values():
                    _fsync(tmp)
                for final, tmp in self._pending.items():
                    os.replace(tmp, final)
                _settle(self.folder, list(self._pending), self.owner)
        finally:
            for tmp in self._pending.values():
                with contextlib.suppress(FileNotFoundError, IsADirectoryError):
                    tmp.unlink()


def _settle(root: Path, written: list[Path], owner: str | None) -> None:
    """After a commit: remove the owner's stale files, then record what was written."""
    stale = stale_files(root, owner, written) if owner else []
    for path in stale:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
    record(root, written, owner=owner, removed=stale)


@contextlib.contextmanager
def staged_dir(out: str | Path, *, owner: str | None = None) -> Iterator[Path]:
    """Yield a hidden staging folder inside ``out`` for a writer that fills a whole folder.

    When the block succeeds every file written under the staging folder is renamed to
    the same relative path under ``out`` (each rename atomic; softcath's earlier files
    replaced); when it fails the staging folder is deleted and ``out`` keeps its earlier
    files. Nothing is moved if one destination is a file softcath did not write or one
    the command reads (:func:`softcath.core.output_ledger.check_replace`). With
    ``owner`` (e.g. ``"optimise"``), the files that owner wrote into ``out`` before and
    this run did not (stale Pareto designs, figures) are removed after the move.
    """
    root = prepare_out_dir(out)
    stage = root / f".softcath-staging-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    stage.mkdir()
    try:
        yield stage
        moves = [(src, root / src.relative_to(stage)) for src in sorted(stage.rglob("*")) if not src.is_dir()]
        for _, dst in moves:
            if dst.is_dir():
                raise DataError(f"{dst}: is a folder where the output file goes; nothing written")
        check_replace(root, [dst for _, dst in moves])
        for src, dst in moves:
            dst.parent.mkdir(parents=True, exist_ok=True)
            _fsync(src)
            os.replace(src, dst)
        _settle(root, [dst for _, dst in moves], owner)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def unstage(path: str | Path, stage: Path, out: Path) -> Path:
    """Where a path reported inside the staging folder ``stage`` ends up under ``out``."""
    p = Path(path)
    try:
        return out / p.relative_to(stage)
    except ValueError:
        return p
