"""``softcath app`` as a user sees it: a real Panel server on 127.0.0.1 (a free port) driven by headless
Chromium through Playwright.

Each test opens its own page (a fresh session on the shared server) and checks
that the page loads without console errors or requests beyond the app's own
server, that an edit redraws the curve, that a refused value shows its message
and keeps the design, that an upload overlays a measured curve, and that the
downloads round-trip. The curves' data is read from the page's own Bokeh
document (the sources are named, ``softcath.studies.app.plots``).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from softcath import design
from softcath.studies.app import apply_value, initial_state, start_in_thread
from tests.browser._chromium import CHROMIUM, SKIP_REASON, record_errors

ROOT = Path(__file__).resolve().parents[2]
PAPER_SINE = ROOT / "studies" / "data" / "paper_sine.csv"

# A page load and its first solves take a few seconds, the finite-strain curve about one more.
pytestmark = [pytest.mark.skipif(not CHROMIUM.is_file(), reason=SKIP_REASON), pytest.mark.slow]

_SOURCE = """([name, column]) => {
  for (const doc of Bokeh.documents) {
    const m = doc.get_model_by_name(name);
    if (m) return Array.from(m.data[column]);
  }
  return null;
}"""


@pytest.fixture(scope="module")
def app():
    running = start_in_thread("paper", p_max=1.0)
    yield running
    running.stop()


class AppPage:
    """One session of the app in its own browser context, recording errors and foreign requests."""

    def __init__(self, browser, url: str) -> None:
        self.url = url
        self.context = browser.new_context(viewport={"width": 1400, "height": 1000}, accept_downloads=True)
        self.foreign: list[str] = []
        self.errors: list[str] = []
        self.context.route("**/*", self._route)
        self.page = self.context.new_page()
        record_errors(self.page, self.errors)
        self.page.goto(url)
        self.wait_version(0)

    def _route(self, route) -> None:
        if route.request.url.startswith(self.url.rstrip("/")):
            route.continue_()
        else:  # the app needs nothing beyond its own server
            self.foreign.append(route.request.url)
            route.abort()

    def wait_version(self, n: int) -> None:
        """Wait until the linear curve of design version ``n`` is on screen."""
        self.page.locator(".app-version").get_by_text(f"linear curve of version {n}").wait_for(timeout=30000)

    def source(self, name: str, column: str) -> list[float]:
        return self.page.evaluate(_SOURCE, [name, column])

    def wait_rows(self, name: str, column: str, at_least: int) -> None:
        """Wait until the source ``name`` holds at least ``at_least`` values of ``column``."""
        self.page.wait_for_function(
            f"args => (({_SOURCE})(args) || []).length >= {at_least}", arg=[name, column], timeout=10000
        )

    def type_into(self, path: str, value: str) -> None:
        box = self.page.locator(f".field-{path.replace('.', '-').replace('_', '-')} input")
        box.fill(value)
        box.press("Enter")

    def assert_clean(self) -> None:
        assert self.foreign == [], f"requests beyond the app's server: {self.foreign}"
        assert self.errors == [], self.errors

    def close(self) -> None:
        self.context.close()


@pytest.fixture
def page(browser, app):
    opened = AppPage(browser, app.url)
    yield opened
    opened.close()


def test_the_page_loads_without_errors(page, tmp_path):
    p = page.page
    assert p.title() == "softcath app"
    assert len(page.source("section-parts", "color")) == 6  # coil, filler, tube, lumen, channel, bore
    for tier in ("paper", "section"):
        assert len(page.source(f"curve-{tier}", "kappa")) == 61
    p.locator(".app-finite").get_by_text("up to date (design version 0)").wait_for(timeout=60000)
    assert len(page.source("curve-section-nonlinear", "kappa")) == 13
    numbers = p.locator(".app-numbers table")
    assert numbers.get_by_text("pressure for a 90° bend").count() == 3
    assert numbers.get_by_text("cap load (the formula's load by definition)").count() >= 1
    p.screenshot(path=str(tmp_path / "app.png"), full_page=True)
    page.assert_clean()


def test_changing_an_input_updates_the_curve(page):
    before = page.source("curve-section", "kappa")
    page.type_into("tube.h", "0.02")
    page.wait_version(1)
    page.page.wait_for_function(  # the marker and the data are separate messages: wait for the data
        f"args => {{ const k = ({_SOURCE})(args); return k && k[k.length - 1] !== {before[-1]!r}; }}",
        arg=["curve-section", "kappa"],
        timeout=10000,
    )
    after = page.source("curve-section", "kappa")
    assert len(after) == len(before) and after[-1] != pytest.approx(before[-1], rel=1e-3)
    # the finite-strain curve follows in the background
    page.page.locator(".app-finite").get_by_text("up to date (design version 1)").wait_for(timeout=60000)
    page.assert_clean()


def test_an_invalid_input_shows_its_message_and_keeps_the_design(page):
    before = page.source("curve-section", "kappa")
    page.type_into("tube.catalogue_inner_diameter", "0.7")
    message = page.page.locator(".field-error").get_by_text(
        "tube.catalogue_inner_diameter = 0.7: must be < catalogue_outer_diameter = 0.6"
    )
    message.wait_for(timeout=10000)
    assert page.source("curve-section", "kappa") == before  # the last valid design stays on screen
    assert page.page.locator(".app-version").get_by_text("design version 0").count() == 1
    page.type_into("tube.catalogue_inner_diameter", "0.35")  # a valid value clears the message
    page.wait_version(1)
    assert message.count() == 0
    page.assert_clean()


def test_an_upload_overlays_a_measured_curve(page):
    p = page.page
    assert page.source("measured", "p") == []
    p.locator(".app-upload input[type=file]").set_input_files(str(PAPER_SINE))
    p.locator(".app-message").get_by_text(re.compile(r"overlaid paper_sine\.csv: \d+ rows")).wait_for(
        timeout=10000
    )
    page.wait_rows("measured", "kappa", 100)
    p.locator(".app-upload input[type=file]").set_input_files(
        files=[{"name": "broken.csv", "mimeType": "text/csv", "buffer": b"time_s,curvature_per_mm\n0,1\n"}]
    )
    p.locator(".app-message").get_by_text(
        re.compile(r"measurement upload: broken\.csv: .*pressure_MPa")
    ).wait_for(timeout=10000)
    assert len(page.source("measured", "kappa")) > 100  # a bad file leaves the overlay as it was
    page.assert_clean()


def test_exports_round_trip(page, tmp_path, cli):
    page.type_into("tip.bending_length", "6.5")
    page.wait_version(1)
    with page.page.expect_download() as got:
        page.page.locator(".app-export-toml").click()
    toml = tmp_path / got.value.suggested_filename
    got.value.save_as(toml)
    assert toml.name == "design.toml"
    assert cli("design", "validate", toml).status == 0
    expected = apply_value(initial_state("paper"), "tip.bending_length", 6.5).design
    assert design.load(toml) == expected
    with page.page.expect_download() as got:
        page.page.locator(".app-export-csv").click()
    csv_path = tmp_path / "curves.csv"
    got.value.save_as(csv_path)
    lines = csv_path.read_text().splitlines()
    assert lines[0].startswith("design,tier,load,pressure_MPa,curvature_per_mm")
    assert {ln.split(",")[1] for ln in lines[1:]} >= {"paper", "section"}
    with page.page.expect_download() as got:
        page.page.locator(".app-export-png").click()
    png = tmp_path / "view.png"
    got.value.save_as(png)
    assert png.read_bytes().startswith(b"\x89PNG")
    page.assert_clean()


def test_pin_overlays_and_the_3d_check_runs_and_cancels(page):
    """Pin A, change the design: both curves drawn. Then the 3-D FEM check (~10 s on the paper design)
    reports next to the linear section model, and a second run is cancelled."""
    p = page.page
    p.locator(".app-pin button").click()
    page.wait_rows("pinned-section", "kappa", 61)
    page.type_into("tube.h", "-0.02")
    page.wait_version(1)
    page.page.wait_for_function(
        f"args => {{ const a = ({_SOURCE})(args[0]), b = ({_SOURCE})(args[1]);"
        " return a && b && a[a.length - 1] !== b[b.length - 1]; }",
        arg=[["curve-section", "kappa"], ["pinned-section", "kappa"]],
        timeout=10000,
    )
    assert p.locator(".app-numbers th").get_by_text("pinned A").count() == 1
    p.locator(".app-fem-run button").click()
    p.locator(".app-fem").get_by_text(re.compile(r"3-D linear FEM, lumen load, at 0\.5 MPa: κ = ")).wait_for(
        timeout=300000
    )
    assert "3-D / section = " in p.locator(".app-fem").get_by_text("3-D / section").text_content()
    p.locator(".app-fem-run button").click()
    p.locator(".app-fem").get_by_text("3-D linear FEM: running").wait_for(timeout=10000)
    p.locator(".app-fem-cancel button").click()
    p.locator(".app-fem").get_by_text("3-D linear FEM: cancelled").wait_for(timeout=10000)
    page.assert_clean()
