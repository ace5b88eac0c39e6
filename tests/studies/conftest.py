"""Shared helpers for the studies tests: small sweep specifications written to tmp_path."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest


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
