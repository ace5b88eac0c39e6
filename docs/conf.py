"""Sphinx configuration: the pages under docs/, an API reference and the example gallery.

Build with ``make docs`` (``sphinx-build -W --keep-going -b html docs docs/_build/html``).
"""

from __future__ import annotations

import os

import softcath

os.environ.setdefault("MPLBACKEND", "Agg")

project = "softcath"
author = "the softcath authors"
copyright = "2026, the softcath authors"  # noqa: A001 - Sphinx's name
release = softcath.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "auto_gallery/*.ipynb", "auto_gallery/*.py"]

# MyST: GitHub-style anchors so the pages' links to sections work here and on the forge alike.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

# API reference: numpydoc docstrings through napoleon, one page per public module.
autosummary_generate = True
autosummary_imported_members = False
# The deprecated stand-ins of moved modules (softcath.core.deprecation.moved_names) are no public
# modules: the recursive walk of a package skips them (a mocked module has no page).
autosummary_mock_imports = [
    "softcath.fem.nonlinear.laws",
    "softcath.fem.nonlinear.tensors",
    "softcath.models.response",
    "softcath.studies.selection.criteria",
    "softcath.studies.selection.expressions",
    "softcath.studies.sweep.section_eval",
    "softcath.studies.sweep.section_nonlinear_eval",
]
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
nitpicky = False
# A class re-exported by a second module of the same package (hardware's RecorderConfig) is
# documented in both; a type hint naming it then has two targets, either of which is right.
suppress_warnings = ["ref.python"]

sphinx_gallery_conf = {
    "examples_dirs": "../examples/gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
}

html_theme = "furo"
html_title = f"softcath {release}"
html_static_path: list[str] = []
