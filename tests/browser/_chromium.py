"""Debian's Chromium as the browser tests drive it (through Playwright; no browser download)."""

from __future__ import annotations

from pathlib import Path

CHROMIUM = Path("/usr/bin/chromium")
LAUNCH_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    # WebGL without a GPU: SwiftShader (software), which headless Chromium refuses unless told
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
]
SKIP_REASON = "Chromium not installed: apt-get install chromium (CI's .ci/run does this)"
