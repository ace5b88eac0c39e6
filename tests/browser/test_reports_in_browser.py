"""The HTML reports as a user sees them: opened in headless Chromium (Debian's, driven by Playwright),
offline.

Each page must load with every image decoded, no console error or page error,
the sections it promises, and no network request (all are blocked and
recorded). The 3-D tip view must draw (non-blank canvas) and turn under a
mouse drag. A full-page screenshot of each page goes to ``tmp_path`` and, when
``SOFTCATH_SCREENSHOTS`` is set, to ``out/browser-screenshots/``.
"""

from __future__ import annotations

import io
import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from softcath.cli.main import main
from tests.browser._chromium import CHROMIUM, SKIP_REASON, record_errors

ROOT = Path(__file__).resolve().parents[2]

# The viewer and the checks' own tests take a second or so each; a report page needs a run of softcath
# first (3-15 s): those are marked slow.
pytestmark = [
    pytest.mark.skipif(
        not CHROMIUM.is_file(),
        reason=SKIP_REASON,
    ),
]


class Opened:
    """One page opened offline, with what went wrong on the way."""

    def __init__(self, browser, html: Path, shots: Path, name: str) -> None:
        self.context = browser.new_context(viewport={"width": 1200, "height": 900}, service_workers="block")
        self.blocked: list[str] = []
        self.errors: list[str] = []
        self.context.route("**/*", self._route)
        self.page = self.context.new_page()
        record_errors(self.page, self.errors)
        self.page.goto(html.resolve().as_uri(), wait_until="load")
        self.shots, self.name = shots, name

    def _route(self, route) -> None:
        if route.request.url.startswith("file://"):
            route.continue_()
        else:  # offline: the page must not need (or try) the network
            self.blocked.append(route.request.url)
            route.abort()

    def check(self, *, ids: tuple[str, ...] = (), headings: tuple[str, ...] = ()) -> None:
        """Images decoded, the expected sections there, no errors, no network; and a screenshot."""
        page = self.page
        images = page.evaluate(
            "Array.from(document.images).map(i => [i.getAttribute('src'), i.complete && i.naturalWidth > 0])"
        )
        assert [src for src, ok in images if not ok] == [], "broken images"
        for i in ids:
            assert page.locator(f"[id='{i}']").count() == 1, f"no element with id {i!r}"
        found = page.evaluate(
            "Array.from(document.querySelectorAll('h1,h2,h3')).map(h => h.textContent.trim())"
        )
        for h in headings:
            assert any(t.startswith(h) for t in found), f"no heading {h!r} in {found}"
        shot = self.shots / f"{self.name}.png"
        page.screenshot(path=str(shot), full_page=True)
        if os.environ.get("SOFTCATH_SCREENSHOTS"):
            keep = ROOT / "out" / "browser-screenshots"
            keep.mkdir(parents=True, exist_ok=True)
            shutil.copy(shot, keep / shot.name)
        self.assert_clean()

    def assert_clean(self) -> None:
        """No network request and no console or page error so far."""
        assert self.blocked == [], f"network requests attempted: {self.blocked}"
        assert self.errors == [], self.errors

    def close(self) -> None:
        self.context.close()


def _pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def check_tip_view(opened: Opened, n: int = 1) -> None:
    """Each 3-D view draws the tip (many non-white pixels) and a drag and a wheel change the picture."""
    page = opened.page
    views = page.locator("figure.tip-view canvas")
    assert views.count() == n
    for k in range(n):
        canvas = views.nth(k)
        canvas.scroll_into_view_if_needed()
        assert page.evaluate("c => !!c.getContext('webgl')", canvas.element_handle()), "no WebGL"
        before = _pixels(canvas.screenshot())
        drawn = np.any(np.abs(before - 255) > 30, axis=2).mean()
        assert drawn > 0.02, f"canvas almost blank ({drawn:.1%} drawn)"
        assert len(np.unique(before.reshape(-1, 3), axis=0)) > 50  # shaded and coloured, not one flat fill
        box = canvas.bounding_box()
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(cx, cy)
        page.mouse.down()
        page.mouse.move(cx + 150, cy + 60, steps=8)
        page.mouse.up()
        turned = _pixels(canvas.screenshot())
        assert np.any(np.abs(turned - before) > 30, axis=2).mean() > 0.01, "a drag did not rotate the view"
        page.mouse.wheel(0, -400)
        zoomed = _pixels(canvas.screenshot())
        assert np.any(np.abs(zoomed - turned) > 30, axis=2).mean() > 0.01, "the wheel did not zoom"


def test_tip_view_draws_and_rotates_offline(browser, tmp_path):
    """The viewer alone, on a small bent tube (no FEM): the quick check of the WebGL page."""
    import pyvista as pv

    from softcath.fem.html_view import surface_of_grid, write_view_html

    tube = pv.CylinderStructured(
        radius=np.linspace(0.2, 0.5, 3), height=6.0, direction=(0, 0, 1), theta_resolution=24, z_resolution=30
    ).cast_to_unstructured_grid()
    grid = tube.triangulate()
    z = grid.points[:, 2] + 3.0
    grid.point_data["displacement"] = np.column_stack([0 * z, -0.05 * z**2, 0 * z])
    grid.cell_data["max_principal_strain"] = np.linspace(0.0, 0.3, grid.n_cells)
    html = write_view_html(surface_of_grid(grid), tmp_path / "tip.html", title="bent tube")
    opened = Opened(browser, html, tmp_path, "tip_view")
    try:
        opened.check(headings=("bent tube",))
        check_tip_view(opened)
        opened.assert_clean()
    finally:
        opened.close()


@pytest.mark.slow
def test_demo_page_quick(browser, tmp_path):
    """`softcath demo --no-fem` on three sections: the page, its figures, the linked sweep report."""
    out = tmp_path / "demo"
    assert (
        main(["demo", "--out", str(out), "--only", "model,sweep,verdict", "--workers", "1", "--no-fem"]) == 0
    )
    opened = Opened(browser, out / "index.html", tmp_path, "demo_quick")
    try:
        opened.check(ids=("model", "sweep", "verdict"), headings=("softcath demo", "1. The paper's model"))
        assert opened.page.locator("img").count() >= 3
    finally:
        opened.close()


@pytest.mark.slow
def test_demo_page_with_the_3d_view(browser, tmp_path):
    """The demo's FEM section (3-D FEM, ~10-30 s) with the rotatable view of the deformed tip."""
    from softcath.studies.sweep import fem_check_function

    if fem_check_function() is None:
        pytest.skip("fem.check is not installed")
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--only", "model,fem", "--workers", "1"]) == 0
    opened = Opened(browser, out / "index.html", tmp_path, "demo_3d")
    try:
        opened.check(ids=("model", "fem", "fem-3d"), headings=("The deformed tip in 3-D",))
        check_tip_view(opened)
        opened.assert_clean()
    finally:
        opened.close()


@pytest.mark.slow
def test_sweep_report_page(browser, tmp_path, spec_writer):
    spec = spec_writer(
        """
        [sweep]
        name = "browser"
        base = "paper"
        pressures_MPa = [0.5, 1.0]
        loads = ["cap", "lumen"]
        [parameters]
        "tube.h" = { values = [-0.03, 0.0, 0.03] }
        "tip.bending_length" = { values = [4.0, 6.0] }
        """
    )
    out = tmp_path / "run"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert main(["report", str(out)]) == 0
    opened = Opened(browser, out / "report" / "index.html", tmp_path, "sweep_report")
    try:
        opened.check(
            headings=("Overview", "Against each swept parameter", "Heat maps", "Renders", "Selection")
        )
        assert opened.page.locator("img").count() >= 3
    finally:
        opened.close()


@pytest.mark.slow
def test_discrepancy_report_page(browser, tmp_path):
    out = tmp_path / "disc"
    data = ROOT / "studies" / "data" / "bench_hysteresis.csv"
    assert main(["discrepancy", "paper", str(data), "--out", str(out)]) == 0
    html = next(out.glob("*.html"))
    opened = Opened(browser, html, tmp_path, "discrepancy_report")
    try:
        opened.check(
            headings=("Steps", "Where the model is wrong", "Before and after", "Candidates (held-out)")
        )
        assert opened.page.locator("img").count() >= 3
    finally:
        opened.close()


@pytest.mark.parametrize(
    ("body", "what"),
    [
        ("<img src='missing.png'>", "broken images"),
        ("<script>console.error('boom')</script>", "console error: boom"),
        ("<script>null.x</script>", "page error"),
        ("<link rel='stylesheet' href='http://example.invalid/a.css'>", "network requests attempted"),
        ("<h2 id='other'>Other</h2>", "no element with id 'expected'"),
        ("<h2>Other</h2>", "no heading 'Expected'"),
    ],
)
def test_the_checks_catch_a_broken_page(browser, tmp_path, body, what):
    """The page checks are not vacuous: each fault above fails them."""
    html = tmp_path / "bad.html"
    html.write_text(f"<!doctype html><html><head><title>t</title></head><body>{body}</body></html>")
    opened = Opened(browser, html, tmp_path, "bad")
    try:
        with pytest.raises(AssertionError, match=re.escape(what)):
            if "id=" in body:
                opened.check(ids=("expected",))
            elif "<h2>" in body:
                opened.check(headings=("Expected",))
            else:
                opened.check()
    finally:
        opened.close()


# --- interactive (Plotly) pages: render offline, respond to a hover, a brush and a click ---------------


def check_charts(opened: Opened, ids: tuple[str, ...]) -> None:
    """Each Plotly chart drew its SVG, from the folder's own plotly.min.js."""
    page = opened.page
    assert page.evaluate("typeof Plotly") == "object", "plotly.min.js not loaded"
    scripts = page.evaluate("Array.from(document.scripts).map(s => s.getAttribute('src')).filter(Boolean)")
    assert scripts == ["plotly.min.js"]
    for i in ids:
        assert page.locator(f"[id='{i}'] .main-svg").count() >= 1, f"chart {i!r} did not render"


def check_hover(opened: Opened, div: str, expect: str) -> None:
    """Moving the mouse onto a point shows its hover label, which contains ``expect``."""
    page = opened.page
    point = page.locator(f"[id='{div}'] .scatterlayer .point").nth(1)
    point.scroll_into_view_if_needed()
    box = point.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.wait_for_selector(f"[id='{div}'] .hoverlayer .hovertext", timeout=5000)
    assert expect in page.locator(f"[id='{div}'] .hoverlayer").text_content()


def check_brush(opened: Opened, div: str) -> None:
    """A drag along the first axis of the parallel coordinates brushes a range (constraintrange)."""
    page = opened.page
    axis = page.locator(f"[id='{div}'] .axis-brush rect.background").first
    axis.scroll_into_view_if_needed()
    box = axis.bounding_box()
    x = box["x"] + box["width"] / 2
    assert page.evaluate(f"document.getElementById('{div}').data[0].dimensions[0].constraintrange") is None
    page.mouse.move(x, box["y"] + 0.2 * box["height"])
    page.mouse.down()
    page.mouse.move(x, box["y"] + 0.6 * box["height"], steps=6)
    page.mouse.up()
    brushed = page.evaluate(f"document.getElementById('{div}').data[0].dimensions[0].constraintrange")
    assert brushed is not None and len(brushed) == 2 and brushed[0] < brushed[1]


def check_click(opened: Opened, div: str, expect: str, image: bool = True) -> None:
    """A click on a Pareto point shows the design (and its picture) in the panel beside the chart."""
    page = opened.page
    point = page.locator(f"[id='{div}'] .scatterlayer .trace").last.locator(".point").first
    point.scroll_into_view_if_needed()
    box = point.bounding_box()
    page.mouse.click(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    panel = page.locator(f"[id='{div}-panel']")
    panel.locator(f"text={expect}").first.wait_for(timeout=5000)
    if image:
        img = panel.locator("img")
        img.wait_for(timeout=5000)
        page.wait_for_function(
            "i => i.complete && i.naturalWidth > 0", arg=img.element_handle(), timeout=5000
        )


def test_interactive_charts_respond_offline(browser, tmp_path):
    """The chart helpers alone (no softcath run): render, hover, brush, click; no network."""
    from softcath.studies.report import interactive as ia
    from softcath.studies.report.html_blocks import page

    ia.write_plotly_js(tmp_path)
    x = np.linspace(0.1, 1.0, 12)
    params = {"tube.h": np.linspace(-0.04, 0.04, 12)}
    info = [{"label": f"design {i}", "html": f"<b>design {i}</b>", "image": ""} for i in range(12)]
    body = ia.script_tag()
    body += ia.chart(ia.parity(x, 1.1 * x, params, xlabel="a", ylabel="b", name="cap"), "par", "parity")
    body += ia.chart(ia.parallel({"tube.h": params["tube.h"], "bend": 30 * x}, color="bend"), "pc", "pc")
    body += ia.chart(ia.pareto(x, x**2, info, xlabel="a", ylabel="b", on_front=x > 0.5), "po", "po")
    body += ia.click_panel("po", info)
    html = tmp_path / "charts.html"
    html.write_text(page("charts", body))
    opened = Opened(browser, html, tmp_path, "charts")
    try:
        opened.check(headings=("charts",))
        check_charts(opened, ("par", "pc", "po"))
        check_hover(opened, "par", "tube.h = ")
        check_brush(opened, "pc")
        check_click(opened, "po", "design", image=False)
        opened.assert_clean()
    finally:
        opened.close()


@pytest.mark.slow
def test_sweep_explore_page(browser, tmp_path, spec_writer):
    """`softcath report` after a two-objective select: explore.html's parity, parallel coordinates and
    Pareto."""
    spec = spec_writer(
        """
        [sweep]
        name = "explore"
        base = "paper"
        pressures_MPa = [0.5, 1.0]
        loads = ["cap", "lumen"]
        [parameters]
        "tube.h" = { values = [-0.03, 0.0, 0.03] }
        "tube.a_int" = { values = [0.08, 0.1, 0.12] }
        """
    )
    out = tmp_path / "run"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert (
        main(
            [
                "select",
                str(out),
                "--objective",
                "maximise bend_per_MPa_deg",
                "--objective",
                "minimise elongation at p_max",
            ]
        )
        == 0
    )
    assert main(["report", str(out)]) == 0
    opened = Opened(browser, out / "report" / "explore.html", tmp_path, "sweep_explore")
    try:
        opened.check(headings=("Parity", "Parameters and results", "Selection"))
        check_charts(opened, ("parity-cap", "parallel", "pareto"))
        check_hover(opened, "parity-cap", "tube.a_int = ")
        check_brush(opened, "parallel")
        check_click(opened, "pareto", "design")
        opened.assert_clean()
    finally:
        opened.close()


@pytest.mark.slow
def test_optimise_report_page(browser, tmp_path):
    """`softcath optimise` (NSGA-II on the formula): its report's parallel coordinates and Pareto click."""
    out = tmp_path / "opt"
    assert (
        main(
            [
                "optimise",
                "paper",
                "--model",
                "paper",
                "--vary",
                "tube.h=-0.03:0.03",
                "--vary",
                "materials.medical_silicone_tubing.youngs_modulus=1:4",
                "--objective",
                "maximise bend_angle_deg at p=0.5",
                "--objective",
                "minimise max_strain at p=0.5",
                "--budget",
                "40",
                "--no-fem-check",
                "--no-progress",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    opened = Opened(browser, out / "index.html", tmp_path, "optimise_report")
    try:
        opened.check(headings=("Winners", "Every evaluation", "Objectives", "Convergence"))
        check_charts(opened, ("opt-parallel", "opt-pareto"))
        check_brush(opened, "opt-parallel")
        check_click(opened, "opt-pareto", "pareto_")
        opened.assert_clean()
    finally:
        opened.close()
