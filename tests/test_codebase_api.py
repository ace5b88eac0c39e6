"""Every public module is in the API reference (``docs/api.rst``).

A public module here is a package of softcath (a folder with ``__init__.py``) other than the
command line: it is documented when ``docs/api.rst`` lists it, or lists a package above it
with ``:recursive:``.
"""

from __future__ import annotations

import re

from tests.codebase_scan import ROOT, modules

API = ROOT / "docs" / "api.rst"


def _listed() -> tuple[set[str], set[str]]:
    """(modules listed, modules listed ``:recursive:``) in the autosummary blocks of api.rst."""
    listed: set[str] = set()
    recursive: set[str] = set()
    for block in re.split(r"^\.\. autosummary::\s*$", API.read_text(encoding="utf-8"), flags=re.M)[1:]:
        lines = block.splitlines()
        options = {m.group(1) for line in lines if (m := re.match(r"^\s+:(\w+):", line))}
        names = set()
        for line in lines[1:]:
            if line.strip() and not line.startswith(" "):
                break  # the block ends at the next unindented line
            m = re.match(r"^\s+(softcath[\w.]*)\s*$", line)
            if m:
                names.add(m.group(1))
        listed |= names
        if "recursive" in options:
            recursive |= names
    return listed, recursive


def _public_packages() -> list[str]:
    return sorted(
        name
        for name, path in modules()
        if path.name == "__init__.py" and name != "softcath" and not name.startswith("softcath.cli")
    )


def test_the_api_reference_lists_every_public_module():
    listed, recursive = _listed()
    packages = _public_packages()
    assert "softcath.fem" in packages and "softcath.core" in packages  # the scan finds packages
    missing = [
        name
        for name in packages
        if name not in listed and not any(name.startswith(r + ".") for r in recursive)
    ]
    assert missing == [], "add these to docs/api.rst"


def test_the_api_reference_lists_only_modules_that_exist():
    listed, _ = _listed()
    names = {name for name, _ in modules()}
    assert sorted(listed - names) == []
