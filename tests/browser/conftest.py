"""The browser the browser tests share: headless Chromium launched once per test module."""

from __future__ import annotations

import pytest

from tests.browser._chromium import CHROMIUM, LAUNCH_ARGS


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="playwright not installed: pip install -e .[dev]"
    )
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=str(CHROMIUM), args=LAUNCH_ARGS)
        yield b
        b.close()
