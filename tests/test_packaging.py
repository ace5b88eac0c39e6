"""Packaging: one ``softcath.`` namespace over the top-level folders, proven on a built wheel.

The wheel is built from the checkout and installed with ``--no-deps`` into a
clean venv; the dependencies come from the development venv's
``site-packages`` through a plain path entry (its ``.pth`` files, among them
the editable install's finder, are not processed), so every ``softcath``
module the clean venv imports comes from the wheel and nothing else.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import venv
import zipfile
from pathlib import Path

import pytest

import softcath

ROOT = Path(__file__).resolve().parents[1]
NOT_SOURCES = (
    ".venv",
    ".git",
    "out",
    "build",
    "dist",
    "*.egg-info",
    "__pycache__",
    ".pytest_cache",
    ".hypothesis",
)
OLD_TOP_LEVEL = ("design", "analytic", "fem", "hardware", "studies", "virtualbench", "cli")


def _pyproject() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_the_package_is_src_softcath_with_the_rooms_linked_in():
    """``src/softcath`` is the package; each room is a link to its top-level folder."""
    package = ROOT / "src" / "softcath"
    assert _pyproject()["tool"]["setuptools"]["packages"]["find"] == {"where": ["src"]}
    for room in OLD_TOP_LEVEL:
        link = package / room
        assert link.is_symlink() and link.resolve() == (ROOT / room).resolve(), room
    assert not (ROOT / "softcath").exists()  # one package directory, not two


@pytest.mark.parametrize("room", OLD_TOP_LEVEL)
def test_a_bare_room_name_does_not_import_from_the_checkout(room):
    """``import fem`` from the repository root would load a second copy of every module."""
    run = subprocess.run(
        [sys.executable, "-c", f"import {room}"], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert run.returncode != 0
    assert f"import softcath.{room}, not {room}" in run.stderr


def test_no_module_imports_a_bare_top_level_name():
    # `import design` works only from a checkout; in a wheel only `softcath.` exists.
    bare = re.compile(rf"^\s*(?:from|import)\s+(?:{'|'.join(OLD_TOP_LEVEL)})(?:\.|\s|$)", re.M)
    offenders = []
    for folder in ("src", *OLD_TOP_LEVEL, "tests", "benchmarks", "examples"):
        for path in (ROOT / folder).rglob("*.py"):
            text = path.read_text()
            offenders += [f"{path.relative_to(ROOT)}: {m.group(0).strip()}" for m in bare.finditer(text)]
    assert offenders == []


def test_version_is_one_number():
    assert softcath.__version__ == _pyproject_version()


def _pyproject_version() -> str:
    spec = _pyproject()["tool"]["setuptools"]["dynamic"]["version"]
    assert spec == {"attr": "softcath.__version__"}
    return re.search(
        r'__version__ = "([^"]+)"', (ROOT / "src" / "softcath" / "__init__.py").read_text()
    ).group(1)


def test_gmsh_is_a_core_dependency():
    deps = _pyproject()["project"]["dependencies"]
    assert any(re.match(r"gmsh\b", d) for d in deps)


@pytest.fixture(scope="module")
def wheel_venv(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wheel")
    # Build from a copy: setuptools writes build/ beside the sources, and the checkout stays untouched.
    src = tmp / "src"
    shutil.copytree(ROOT, src, symlinks=True, ignore=shutil.ignore_patterns(*NOT_SOURCES))
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", str(tmp / "dist"), str(src)],
        check=True,
        capture_output=True,
        timeout=600,
    )
    (whl,) = (tmp / "dist").glob("softcath-*.whl")
    env_dir = tmp / "clean"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    subprocess.run(
        [str(py), "-m", "pip", "install", "--quiet", "--no-deps", str(whl)], check=True, timeout=600
    )
    site = subprocess.run(
        [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    # Dependencies only: a path entry appended after the wheel's own site-packages.
    (Path(site) / "zz_dev_deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    return whl, env_dir


@pytest.mark.slow
def test_the_wheel_holds_one_top_level_package(wheel_venv):
    whl, _ = wheel_venv
    names = zipfile.ZipFile(whl).namelist()
    tops = {n.split("/")[0] for n in names}
    assert tops == {"softcath", f"softcath-{softcath.__version__}.dist-info"}
    for data in ("softcath/design/presets/paper.toml", "softcath/studies/data/paper_sine.csv"):
        assert data in names
    meta = zipfile.ZipFile(whl).read(f"softcath-{softcath.__version__}.dist-info/METADATA").decode()
    assert re.search(r"^Requires-Dist: gmsh", meta, re.M)


@pytest.mark.slow
def test_the_installed_wheel_imports_every_module_and_runs_fem(wheel_venv, tmp_path):
    whl, env_dir = wheel_venv
    modules = sorted(
        n[: -len(".py")].replace("/", ".").removesuffix(".__init__")
        for n in zipfile.ZipFile(whl).namelist()
        if n.endswith(".py") and not n.endswith("__main__.py")
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["MPLBACKEND"] = "Agg"
    code = (
        "import importlib, sys, softcath\n"
        f"for m in {modules!r}: importlib.import_module(m)\n"
        "bad = [m for m in sys.modules if m.split('.')[0] in "
        f"{OLD_TOP_LEVEL!r}]\n"
        "assert not bad, bad\n"
        "assert softcath.__file__.startswith(sys.prefix), softcath.__file__\n"
    )
    run = subprocess.run(
        [str(env_dir / "bin" / "python"), "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr[-2000:]
    exe = str(env_dir / "bin" / "softcath")
    version = subprocess.run([exe, "--version"], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert version.stdout.strip() == f"softcath {softcath.__version__}"
    fem = subprocess.run(
        [exe, "fem", "paper", "--pressure", "0.1", "--mesh-size", "0.3", "--out", str(tmp_path / "fem")],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert fem.returncode == 0, fem.stderr[-2000:]
    assert (tmp_path / "fem" / "fem.json").is_file()
