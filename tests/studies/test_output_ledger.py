"""softcath.studies.output_ledger: a command replaces its own earlier outputs, never a user's file or
an input; stale outputs of the same owner go; a failure leaves everything as it was."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.design.errors import DesignError
from softcath.studies.atomic import Outputs, staged_dir
from softcath.studies.output_ledger import LEDGER, forget_inputs, protect_inputs

NAMES = st.sampled_from(["a.json", "b.png", "c.csv", "sub/d.toml", "sub/e.png", "f.txt"])


def _digest(folder: Path) -> dict[str, str]:
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and not p.name.startswith(".")
    }


@settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    user=st.sets(NAMES, max_size=3),
    runs=st.lists(st.sets(NAMES, min_size=1, max_size=4), min_size=1, max_size=4),
    staged=st.booleans(),
)
def test_a_users_files_are_never_replaced_or_removed(tmp_path_factory, user, runs, staged):
    out = tmp_path_factory.mktemp("out")
    for name in user:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_text(f"user's {name}")
    for k, names in enumerate(runs):
        before = _digest(out)
        try:
            if staged:
                with staged_dir(out, owner="cmd") as stage:
                    for n in names:
                        (stage / n).parent.mkdir(parents=True, exist_ok=True)
                        (stage / n).write_text(f"run {k}")
            else:
                with Outputs(out, owner="cmd") as o:
                    for n in names:
                        (out / n).parent.mkdir(parents=True, exist_ok=True)
                        o.text(n, f"run {k}")
        except DesignError as exc:
            assert set(names) & user and "softcath did not write" in str(exc)
            assert _digest(out) == before  # refused as a whole: nothing moved
            continue
        assert not set(names) & user
        now = _digest(out)
        for name in user:
            assert (out / name).read_text() == f"user's {name}"
        # this run's files, plus the user's: the owner's earlier files that it did not rewrite are gone
        assert set(now) == set(names) | user
    for name in user:
        assert (out / name).read_text() == f"user's {name}"


def test_an_output_that_is_an_input_is_refused_before_anything_moves(tmp_path):
    out = tmp_path / "out"
    with Outputs(out.mkdir() or out) as o:
        o.text("section.csv", "a measurement softcath wrote earlier")
    protect_inputs([("--measured", out / "section.csv")])
    try:
        with pytest.raises(DesignError, match=r"would overwrite the input .*section.csv \(--measured\)"):
            with Outputs(out) as o:
                o.text("section.json", "{}")
                o.text("section.csv", "new")
        assert (out / "section.csv").read_text() == "a measurement softcath wrote earlier"
        assert not (out / "section.json").exists()
    finally:
        forget_inputs()


def test_a_file_changed_since_softcath_wrote_it_is_the_users(tmp_path):
    with Outputs(tmp_path) as o:
        o.text("notes.txt", "softcath's")
    (tmp_path / "notes.txt").write_text("edited by hand, longer than before")
    with pytest.raises(DesignError, match="changed since softcath wrote it"):
        with Outputs(tmp_path) as o:
            o.text("notes.txt", "new")
    assert (tmp_path / "notes.txt").read_text() == "edited by hand, longer than before"


def test_a_damaged_ledger_protects_everything(tmp_path):
    with Outputs(tmp_path) as o:
        o.text("r.json", "1")
    (tmp_path / LEDGER).write_text("{not json")
    with pytest.raises(DesignError, match="softcath did not write"):
        with Outputs(tmp_path) as o:
            o.text("r.json", "2")
    assert (tmp_path / "r.json").read_text() == "1"


def test_a_writer_killed_mid_commit_leaves_earlier_outputs_and_a_usable_ledger(tmp_path):
    """A real SIGKILL while a staged folder is being filled: the earlier outputs stay whole and the
    next run replaces them (the ledger still says they are softcath's)."""
    out = tmp_path / "out"
    with staged_dir(out, owner="cmd") as stage:
        (stage / "r.json").write_text("good")
    code = (
        "import os, signal, sys; from softcath.studies.atomic import staged_dir\n"
        f"with staged_dir({str(out)!r}, owner='cmd') as s:\n"
        "    (s / 'r.json').write_text('half')\n"
        "    os.kill(os.getpid(), signal.SIGKILL)\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, check=False)
    assert r.returncode == -9
    assert (out / "r.json").read_text() == "good"
    with staged_dir(out, owner="cmd") as stage:  # removes the killed writer's staging folder too
        (stage / "r.json").write_text("next")
    assert (out / "r.json").read_text() == "next"
    assert sorted(p.name for p in out.iterdir()) == [LEDGER, "r.json"]


def test_select_never_writes_over_a_users_selection_json(cli, spec_writer, tmp_path):
    spec = spec_writer(
        """
        [sweep]
        base = "paper"
        pressures_MPa = [0.0, 0.5]
        [parameters]
        "tube.h" = { values = [0.0, 0.02] }
        """
    )
    sweep = tmp_path / "s"
    assert cli("sweep", spec, "--out", sweep, "--workers", "1", "--no-progress").status == 0
    out = tmp_path / "sel"
    out.mkdir()
    (out / "selection.json").write_text("my notes")
    line = cli("select", sweep, "--objective", "maximise bend_angle_deg", "--out", out).error_line()
    assert "holds selection.json, which softcath did not write" in line
    assert (out / "selection.json").read_text() == "my notes"
    assert cli("select", sweep, "--objective", "maximise bend_angle_deg").status == 0  # into the sweep
    assert cli("select", sweep, "--objective", "minimise max_strain").status == 0  # its own: replaced
