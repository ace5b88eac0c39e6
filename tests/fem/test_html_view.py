"""The inline WebGL view of the deformed tip: what goes into the page (tests/browser opens it in Chromium)."""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest

from softcath.fem.html_view import surface_of_grid, tip_view_fragment, write_view_html


@pytest.fixture
def bent_tube():
    """A thick tube along z (tets), bent in y by a parabola, strain rising along it."""
    import pyvista as pv

    tube = pv.CylinderStructured(
        radius=np.linspace(0.2, 0.5, 3), height=6.0, direction=(0, 0, 1), theta_resolution=30, z_resolution=60
    ).cast_to_unstructured_grid()
    grid = tube.triangulate()
    z = grid.points[:, 2] + 3.0
    grid.point_data["displacement"] = np.column_stack([0 * z, -0.05 * z**2, 0 * z])
    grid.cell_data["max_principal_strain"] = grid.cell_centers().points[:, 2] / 30 + 0.1
    return grid


def _payload(page: str) -> dict:
    return json.loads(re.search(r"const D=(\{.*?\}), root", page).group(1))


def test_surface_is_the_deformed_outer_surface(bent_tube):
    view = surface_of_grid(bent_tube)
    tip = view.points[:, 2] > 2.99
    # the free end moved down by 0.05 * 6² = 1.8 mm, at true scale
    assert view.points[tip, 1].mean() == pytest.approx(-1.8, abs=0.05)
    assert view.triangles.max() < len(view.points) < 65536
    lo, hi = view.clim
    assert lo == 0.0 and hi == pytest.approx(np.percentile(bent_tube.cell_data["max_principal_strain"], 99))
    assert view.values.min() >= 0.0 and view.values.max() <= 0.21


def test_decimation_caps_the_triangles_and_keeps_the_colours(bent_tube):
    full = surface_of_grid(bent_tube)
    small = surface_of_grid(bent_tube, max_triangles=1000)
    assert len(full.triangles) > 1000 >= len(small.triangles) > 500
    # nearest-vertex colours: the strain still rises along the tube
    assert np.corrcoef(small.points[:, 2], small.values)[0, 1] > 0.9


def test_page_is_self_contained_and_decodes(tmp_path, bent_tube):
    view = surface_of_grid(bent_tube, max_triangles=2000)
    page = write_view_html(view, tmp_path / "v.html", title="tube <1>").read_text()
    assert "http" not in page and "<script src" not in page and "tube &lt;1&gt;" in page
    d = _payload(page)
    idx = np.frombuffer(base64.b64decode(d["idx"]), "<u2").reshape(-1, 3)
    pos = np.frombuffer(base64.b64decode(d["pos"]), "<u2").reshape(-1, 3)
    np.testing.assert_array_equal(idx, view.triangles)
    back = np.asarray(d["lo"]) + pos / 65535 * np.asarray(d["span"])
    assert np.abs(back - view.points).max() < 1e-4 * max(d["span"])
    assert len(base64.b64decode(d["rgb"])) == 3 * len(view.points)


def test_fragments_get_distinct_ids(bent_tube):
    view = surface_of_grid(bent_tube, max_triangles=500)
    a, b = (tip_view_fragment(view, caption="x") for _ in range(2))
    ida, idb = (re.search(r"id='(tipview\d+)'", f).group(1) for f in (a, b))
    assert ida != idb
