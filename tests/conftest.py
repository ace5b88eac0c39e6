"""Test-wide settings (headless plotting and rendering, a session mesh cache) and shared fixtures."""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")


@pytest.fixture(scope="session", autouse=True)
def _fem_cache(tmp_path_factory):
    """Meshes are cached in a temporary folder shared by the session, never in the user's cache."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SOFTCATH_CACHE", str(tmp_path_factory.mktemp("softcath-cache")))
        yield


def write_spec(tmp_path: Path, body: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(body), encoding="utf-8")
    return path


@pytest.fixture
def spec_writer(tmp_path):
    """``spec_writer(body, name="spec.toml") -> Path``: write a dedented spec into tmp_path."""
    return lambda body, name="spec.toml": write_spec(tmp_path, body, name)


@pytest.fixture
def small_spec(tmp_path):
    """12 designs × 3 pressures × 2 loads, 2 of them invalid (|h| too large), chunks of 5 designs."""
    return write_spec(
        tmp_path,
        """
        [sweep]
        name = "small"
        base = "paper"
        pressures_MPa = [0.0, 0.5, 1.0]
        loads = ["cap", "lumen"]
        chunk_size = 5
        [parameters]
        "tube.h" = { values = [-0.03, 0.0, 0.01, 0.03, 0.05, 0.06] }
        "tip.bending_length" = { values = [4.0, 6.0] }
        """,
    )


class CliRun:
    """One in-process ``softcath`` run: exit status and captured stdout/stderr."""

    def __init__(self, status: int, out: str, err: str) -> None:
        self.status, self.out, self.err = status, out, err

    def error_line(self) -> str:
        """The one ``softcath CMD: error: ...`` line; fails the test unless the run is a clean refusal."""
        assert self.status == 2, f"expected a refusal (exit 2), got {self.status}: {self.err}"
        assert "Traceback" not in self.err, self.err
        errors = [ln for ln in self.err.splitlines() if ": error: " in ln]
        assert len(errors) == 1 and errors[0].startswith("softcath "), self.err
        assert "unexpected" not in errors[0], errors[0]  # an input error, not a bug report
        return errors[0]


@pytest.fixture
def cli(capsys):
    """``cli(*argv) -> CliRun``: run :func:`softcath.cli.main.main` in this process."""
    from softcath.cli.main import main

    def run(*argv) -> CliRun:
        capsys.readouterr()
        status = main([str(a) for a in argv])
        out, err = capsys.readouterr()
        return CliRun(status, out, err)

    return run
