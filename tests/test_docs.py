"""The examples users read run: the README's Python tour and every ``>>>`` example in the package.

``make test`` runs this file with the rest of the suite, so an example that
drifts from the code fails CI.
"""

from __future__ import annotations

import doctest
import importlib
import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _modules_with_examples() -> list[str]:
    package = ROOT / "src" / "softcath"  # its rooms are links to the top-level folders
    names = []
    for folder, _, files in sorted(os.walk(package, followlinks=True)):
        for file in sorted(f for f in files if f.endswith(".py")):
            path = Path(folder) / file
            if ">>>" not in path.read_text(encoding="utf-8"):
                continue
            parts = path.relative_to(package.parent).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            names.append(".".join(parts))
    return names


MODULES = _modules_with_examples()


def test_the_package_has_examples_to_run():
    assert len(MODULES) >= 10  # guards the discovery above against finding nothing


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, monkeypatch):
    monkeypatch.chdir(ROOT)  # examples name bundled files relative to the checkout, as the README does
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, report=True)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name} (see stdout)"


def _python_blocks(markdown: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", markdown, flags=re.S | re.M)


def test_readme_python_tour_runs(monkeypatch, capsys):
    blocks = _python_blocks((ROOT / "README.md").read_text(encoding="utf-8"))
    assert blocks, "the README has no Python tour"
    monkeypatch.chdir(ROOT)
    namespace: dict = {"__name__": "readme_tour"}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)  # noqa: S102 - the README is ours
    # What the tour's comments promise.
    d, analytic, np = namespace["d"], namespace["analytic"], namespace["np"]
    assert analytic.pressure_for_bend_angle(d, np.pi / 2) == pytest.approx(3.99, abs=0.005)
    assert analytic.response_arrays(namespace["inp"], np.linspace(0, 3, 500)).curvature.shape == (1000, 500)
    assert "fit" in capsys.readouterr().out
