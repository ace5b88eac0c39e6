"""At most six positional parameters a function: the rest are keyword-only or grouped.

A call with seven or more positional arguments cannot be read without the signature beside
it, and swapping two of them goes unnoticed. ``self`` and ``cls`` are not counted.
"""

from __future__ import annotations

import ast

from tests.codebase_scan import modules, parsed, relative

MAX_POSITIONAL = 6
#: Functions over the limit, with their positional parameters when this list was made: they may
#: lose parameters, not gain them. Make the rest keyword-only (or group them in a small frozen
#: dataclass), then drop the function from here.
OVER = {
    # numba-compiled kernels take their arrays positionally (nopython mode has no keyword dataclasses)
    "fem/section_model/element_kernel.py::_blocks": 18,
    "fem/section_model/element_kernel.py::_condense": 11,
    "fem/section_model/element_kernel.py::_integrate": 11,
    "fem/section_model/element_kernel.py::_strain_extremes": 9,
    "fem/section_model/finite_strain/kernel.py::_svk": 8,
    "fem/section_model/finite_strain/kernel.py::_yeoh": 9,
    "fem/section_model/finite_strain/kernel.py::assemble": 28,
    "fem/section_model/finite_strain/kernel.py::lumen": 11,
    "fem/nonlinear/kernel.py::_yeoh": 7,
    "fem/nonlinear/kernel.py::assemble": 11,
}


def _positional_counts() -> dict[str, int]:
    counts: dict[str, int] = {}
    for _, path in modules():
        for node in ast.walk(parsed(path)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                names = [a.arg for a in node.args.posonlyargs + node.args.args]
                if names and names[0] in ("self", "cls"):
                    names = names[1:]
                key = f"{relative(path)}::{node.name}"
                counts[key] = max(counts.get(key, 0), len(names))
    return counts


def test_no_function_takes_more_than_six_positional_parameters():
    counts = _positional_counts()
    assert len(counts) > 1000  # guards the scan against finding nothing
    over = {k: n for k, n in counts.items() if n > max(MAX_POSITIONAL, OVER.get(k, 0))}
    assert over == {}, f"more than {MAX_POSITIONAL} positional parameters: make the rest keyword-only"


def test_the_list_of_long_signatures_is_current():
    counts = _positional_counts()
    stale = {k: counts.get(k) for k in OVER if counts.get(k, 0) <= MAX_POSITIONAL}
    assert stale == {}, "these functions are within the limit now: drop them from OVER"
