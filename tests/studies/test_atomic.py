"""softcath.studies.atomic: outputs appear whole or not at all; strict JSON; output folders refused in one
line."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from softcath.design.errors import DataError, DesignError
from softcath.studies.atomic import (
    Outputs,
    atomic_path,
    check_parent,
    pid_alive,
    prepare_out_dir,
    remove_stale_temps,
    staged_dir,
    write_json,
    write_text,
)


def test_prepare_out_dir_creates_and_refuses_files(tmp_path):
    assert prepare_out_dir(tmp_path / "a" / "b").is_dir()
    (tmp_path / "f").write_text("x")
    with pytest.raises(DesignError, match=r"out_dir = '.*f': exists and is not a folder"):
        prepare_out_dir(tmp_path / "f")
    with pytest.raises(DesignError, match=r"out_dir = '.*f/sub': .*f is a file, not a folder"):
        prepare_out_dir(tmp_path / "f" / "sub")
    with pytest.raises(DesignError, match=r"--step = '.*': is a folder; give a file path"):
        check_parent(tmp_path / "a", param="--step")


def test_atomic_path_keeps_the_old_file_when_the_writer_fails(tmp_path):
    target = tmp_path / "r.json"
    target.write_text("good")
    with pytest.raises(RuntimeError, match="boom"):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("boom")
    assert target.read_text() == "good"
    assert os.listdir(tmp_path) == ["r.json"]  # no temp file left behind
    with atomic_path(target) as tmp:
        assert tmp.suffix == ".json" and tmp.parent == tmp_path  # same folder: the rename is atomic
        tmp.write_text("new")
    assert target.read_text() == "new"


def test_a_writer_that_writes_nothing_is_refused(tmp_path):
    with pytest.raises(DataError, match="the writer produced no file; nothing written"):
        with atomic_path(tmp_path / "tip.step"):
            pass
    assert not (tmp_path / "tip.step").exists()


def test_write_json_refuses_non_finite_numbers_naming_the_key(tmp_path):
    target = tmp_path / "c.json"
    write_json(target, {"x": [1.0, 2.0]})
    with pytest.raises(DataError, match=r"result fit\.x\[1\] = nan: not finite; nothing written"):
        write_json(target, {"fit": {"x": [1.0, float("nan")]}})
    with pytest.raises(DataError, match=r"result ratio = inf"):
        write_json(target, {"ratio": float("inf")})
    assert json.loads(target.read_text()) == {"x": [1.0, 2.0]}
    write_text(tmp_path / "t.txt", "é")
    assert (tmp_path / "t.txt").read_text(encoding="utf-8") == "é"


def test_outputs_commit_all_files_or_none(tmp_path):
    with Outputs(tmp_path) as o:  # an earlier run's outputs
        o.text("a.json", "old a")
        o.text("b.png", "old b")
    with pytest.raises(DataError, match="not finite"):
        with Outputs(tmp_path) as o:
            o.path("b.png").write_text("new b")
            o.json("a.json", {"v": float("nan")})
    assert (tmp_path / "a.json").read_text() == "old a" and (tmp_path / "b.png").read_text() == "old b"
    assert _visible(tmp_path) == ["a.json", "b.png"]
    with Outputs(tmp_path) as o:
        o.json("a.json", {"v": 1})
        o.text("b.png", "new b")
    assert json.loads((tmp_path / "a.json").read_text()) == {"v": 1}
    assert (tmp_path / "b.png").read_text() == "new b"


def test_staged_dir_moves_a_whole_tree_or_nothing(tmp_path):
    out = tmp_path / "out"
    with staged_dir(out) as stage:
        (stage / "sub").mkdir()
        (stage / "sub" / "x.txt").write_text("1")
        (stage / "y.txt").write_text("2")
    assert (out / "sub" / "x.txt").read_text() == "1" and (out / "y.txt").read_text() == "2"
    with pytest.raises(KeyError):
        with staged_dir(out) as stage:
            (stage / "y.txt").write_text("3")
            raise KeyError("fail")
    assert (out / "y.txt").read_text() == "2"
    assert _visible(out) == ["sub", "y.txt"]


def _visible(folder) -> list[str]:
    return sorted(n for n in os.listdir(folder) if not n.startswith("."))


def test_leftovers_of_a_killed_writer_are_removed_but_not_a_live_ones(tmp_path):
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    )
    dead_pid = int(dead.stdout)
    assert not pid_alive(dead_pid)
    (tmp_path / f".fem.{dead_pid}-0123abcd.tmp.json").write_text("half")
    (tmp_path / f".softcath-staging-{dead_pid}-0123abcd").mkdir()
    live = tmp_path / f".fem.{os.getpid()}-0123abcd.tmp.json"
    live.write_text("in progress")
    (tmp_path / ".hidden_user_file").write_text("keep")
    assert remove_stale_temps(tmp_path) == 2
    assert sorted(os.listdir(tmp_path)) == sorted([live.name, ".hidden_user_file"])
