"""Static tools see the package as users import it: basedpyright resolves every import.

The package is ``src/softcath`` with the rooms linked in, so an editor's go-to-definition, type
checks and renames reach every ``softcath.*`` module; this test keeps it that way.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_basedpyright_resolves_every_import():
    exe = shutil.which("basedpyright", path=str(Path(sys.executable).parent))
    assert exe, "basedpyright is in the dev extras"
    run = subprocess.run(
        [exe, "--outputjson", "--level", "error"], cwd=ROOT, capture_output=True, text=True, timeout=900
    )
    report = json.loads(run.stdout)
    assert report["summary"]["filesAnalyzed"] > 300  # the rooms, the tests, benchmarks and examples
    missing = [
        f"{Path(d['file']).relative_to(ROOT)}:{d['range']['start']['line'] + 1}: {d['message']}"
        for d in report["generalDiagnostics"]
        if d.get("rule") == "reportMissingImports"
        or (d.get("rule") == "reportAttributeAccessIssue" and 'of module "softcath' in d["message"])
    ]
    assert missing == []
