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


def record_errors(page, errors: list[str]) -> None:
    """Append every console error and uncaught page error of ``page`` to ``errors``."""
    page.on("console", lambda m: errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(f"page error: {e}"))
