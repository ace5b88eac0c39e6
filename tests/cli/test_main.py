"""softcath.cli.main: one error path for every command (one line, exit 2, --debug traceback, stdout
failures)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import softcath.cli.analytic
from softcath.cli.main import SUBCOMMANDS, main

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data"


def _commands_with_out(tmp_path: Path, out: Path) -> dict[str, list[str]]:
    """Every command that writes into a folder, with ``out`` as that folder and otherwise good input."""
    spec = tmp_path / "spec.toml"
    spec.write_text(
        '[sweep]\nbase = "paper"\npressures_MPa = [0.5]\n[parameters]\n"tube.h" = { values = [0.0] }\n'
    )
    csv = str(DATA / "paper_sine.csv")
    return {
        "analytic": ["analytic", "paper", "--out", out],
        "calibrate": ["calibrate", csv, "--out", out],
        "fem": ["fem", "paper", "--pressure", "0.1", "--out", out],
        "fem --nonlinear": ["fem", "paper", "--nonlinear", "--pressure", "0.1", "--out", out],
        "sweep": ["sweep", spec, "--out", out, "--workers", "1", "--no-progress"],
        "measure": ["measure", tmp_path, "--px-per-mm", "40", "--out", out],
        "record": ["record", "--pressure-port", "loop://", "--encoder-port", "loop://", "--out", out],
        "bench": ["bench", "--out", out],
        "discrepancy": ["discrepancy", csv, "--out", out],
        "demo": ["demo", "--out", out],
        "design show": ["design", "show", "paper", "--out", out],
        "design export": ["design", "export", "paper", "--step", out / "tip.step"],
    }


@pytest.mark.parametrize("nested", [False, True], ids=["file", "under-a-file"])
def test_out_naming_an_existing_file_is_refused_by_every_command(tmp_path, cli, nested):
    existing = tmp_path / "x"
    existing.write_text("not a folder")
    out = existing / "sub" if nested else existing
    for name, argv in _commands_with_out(tmp_path, out).items():
        r = cli(*argv)
        line = r.error_line()
        assert str(existing) in line, (name, line)
        assert (
            "is a file, not a folder" if nested or name == "design export" else "exists and is not a folder"
        ) in line
        assert existing.read_text() == "not a folder"


def test_an_unexpected_exception_is_one_line_and_exit_2(monkeypatch, cli):
    def broken(args):
        raise KeyError("internal")

    monkeypatch.setattr(softcath.cli.analytic, "run", broken)
    r = cli("analytic", "paper", "--out", "unused")
    assert r.status == 2 and "Traceback" not in r.err
    (line,) = r.err.strip().splitlines()
    assert line.startswith("softcath analytic: error: unexpected KeyError: 'internal'")
    assert "--debug" in line
    r = cli("--debug", "analytic", "paper", "--out", "unused")
    assert r.status == 2
    assert "Traceback (most recent call last)" in r.err and 'raise KeyError("internal")' in r.err
    assert r.err.strip().splitlines()[-1].startswith("softcath analytic: error: unexpected KeyError")


def test_stdout_to_a_full_device_is_an_error_not_a_traceback():
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full on this system")
    with open("/dev/full", "w") as full:
        proc = subprocess.run(
            [sys.executable, "-m", "softcath", "design", "show", "paper"],
            cwd=ROOT,
            env=dict(os.environ, PYTHONPATH=str(ROOT)),
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            timeout=60,
        )
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "softcath design show: error: cannot write the output to stdout (No space left on device)"
    ]


def test_a_closed_pipe_is_an_error_not_a_traceback():
    proc = subprocess.Popen(
        [sys.executable, "-m", "softcath", "design", "show", "paper", "--toml"],
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    proc.stdout.close()  # the reader went away (`softcath ... | head -0`)
    err = proc.stderr.read()
    proc.wait(timeout=60)
    proc.stderr.close()
    assert "Traceback" not in err and "Exception ignored" not in err
    assert proc.returncode in (0, 2)  # 0 if the text fit in the pipe before it closed
    if proc.returncode == 2:
        assert err.strip().startswith("softcath design show: error: cannot write the output to stdout")


def test_logged_tracebacks_only_with_debug(cli, tmp_path):
    # demo sections log their failure; without --debug one line, with --debug the traceback
    bad = tmp_path / "bad.toml"
    bad.write_text("this is = = not toml")
    r = cli("design", "validate", bad)
    assert "is not valid TOML" in r.error_line()


def test_main_returns_the_status_and_restores_signal_handlers(cli):
    import signal

    before = signal.getsignal(signal.SIGTERM)
    assert cli("design", "validate", "paper").status == 0
    assert signal.getsignal(signal.SIGTERM) is before
    assert main(["design", "validate", "nonexistent.toml"]) == 2


@pytest.mark.parametrize("name, module_name", SUBCOMMANDS)
def test_every_listed_subcommand_module_imports(name, module_name):
    import importlib

    module = importlib.import_module(module_name)
    assert module.HELP and callable(module.add_arguments) and callable(module.run), name


def test_a_subcommand_module_that_does_not_import_fails_the_parser(monkeypatch):
    import importlib

    cli_main = importlib.import_module("softcath.cli.main")  # the package's ``main`` is the function
    monkeypatch.setattr(cli_main, "SUBCOMMANDS", (*cli_main.SUBCOMMANDS, ("ghost", "softcath.cli.ghost")))
    with pytest.raises(ImportError):
        cli_main.build_parser()
