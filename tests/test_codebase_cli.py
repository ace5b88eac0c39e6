"""``softcath --help`` lists every command without importing one: the command line's registry.

Each command's module is imported when that command is parsed, so it may import the library at
its top; the top-level help reads the one-line helps from the registry instead.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys

import pytest

from softcath.cli.main import HELP, SUBCOMMANDS
from tests.codebase_scan import ROOT

#: Libraries that make ``softcath --help`` slow; none of them may load for it.
HEAVY = ("cadquery", "pyvista", "skfem", "casadi", "cv2", "plotly", "pymoo", "dask", "panel", "matplotlib")


@pytest.mark.parametrize("name, module_name", SUBCOMMANDS)
def test_the_registry_help_is_the_module_help(name, module_name):
    assert HELP[name] == importlib.import_module(module_name).HELP


def test_top_level_help_imports_no_command():
    code = (
        "import contextlib, io, json, sys\n"
        "from softcath.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
        "    status = main(['--help'])\n"
        "print(json.dumps([status, out.getvalue(), sorted(sys.modules)]))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    status, text, loaded = json.loads(run.stdout)
    assert status == 0
    for name, _ in SUBCOMMANDS:  # every command is listed, with its help's first words
        assert f"    {name}" in text and HELP[name].split()[0] in text
    commands = {module for _, module in SUBCOMMANDS}
    assert sorted(commands & set(loaded)) == []
    assert sorted(m for m in loaded if m.split(".")[0] in HEAVY) == []


def test_a_command_parses_with_its_own_parser_only():
    from softcath.cli.main import build_parser

    parser = build_parser("design")
    args = parser.parse_args(["design", "validate", "paper"])
    assert args.command == "design" and callable(args._run)
