"""Benchmark of ``softcath app``: from an input change to the updated linear curve on screen.

In one run:

1. the app is served on a free 127.0.0.1 port and opened in headless Chromium
   (Debian's, driven by Playwright); for each of N edits of ``tube.h`` the
   page's own clock (``performance.now()``) runs from the moment the new value
   is committed in the input box (its ``change`` event) until the linear
   section model's curve in the page's Bokeh document holds the new design's
   data and the browser has painted the next frame; target <= 300 ms;
2. the baseline, measured in this process on the same designs: the bare linear
   section solve (``section_model(design, loads=("lumen",))``), and the
   session's whole server-side update (formula + linear section curves with the
   silicone strain, no page);

and prints the median and the largest latency against the baselines' medians, with
the ratios.

Run: ``python benchmarks/bench_app.py [--edits N]`` (``make bench``). Needs /usr/bin/chromium and
playwright (the dev extras).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1]))

from _timing import row  # noqa: E402

CHROMIUM = Path("/usr/bin/chromium")
TARGET_MS = 300.0

# Commit a value in the box and wait (in the page) until the named source's data changed and a frame
# was painted; returns the elapsed milliseconds of the page's clock.
_EDIT_JS = """async (input, [value, name]) => {
  const src = (() => {
    for (const d of Bokeh.documents) { const m = d.get_model_by_name(name); if (m) return m; }
  })();
  const last = () => { const k = src.data.kappa; return k[k.length - 1]; };
  const before = last();
  const frame = () => new Promise(r => requestAnimationFrame(r));
  const t0 = performance.now();
  input.value = value;
  input.dispatchEvent(new Event('change', {bubbles: true}));
  while (last() === before) {
    await frame();
    if (performance.now() - t0 > 30000) return -1;
  }
  await frame();
  return performance.now() - t0;
}"""


def _load() -> str:
    return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg()) + f" on {os.cpu_count()} cores"


def _values(n: int) -> list[float]:
    """N distinct lumen offsets h [mm] inside the paper section's range (never 0.005, the warm-up)."""
    return [round(-0.02 + 0.04 * i / max(n - 1, 1), 6) for i in range(n)]


def _busy_values(values: list[float]) -> list[float]:
    return [round(v + 0.0025, 6) for v in values]


def _baselines(values: list[float]) -> tuple[list[float], list[float]]:
    """Per design: the bare linear section solve and the session's server-side update [ms]."""
    from softcath.fem.section_model import section_model
    from softcath.studies.app.page import Session
    from softcath.studies.app.state import apply_value, initial_state

    state = initial_state("paper")
    designs = [apply_value(state, "tube.h", v).design for v in values]
    for v in [0.005, *values, *_busy_values(values)]:
        # imports, compiled kernels and the template meshes of every design timed below, so that
        # the two browser runs compare like with like (a new template costs one gmsh mesh, once)
        section_model(apply_value(state, "tube.h", v).design, loads=("lumen",))
    bare = []
    for d in designs:
        t0 = time.perf_counter()
        section_model(d, loads=("lumen",))
        bare.append(1e3 * (time.perf_counter() - t0))
    session = Session("paper", p_max=1.0)
    session.finite_job.close()  # the server-side update alone: no background worker starting up
    session.compute_fast()
    update = []
    for v in values:
        session.state = apply_value(session.state, "tube.h", v)
        t0 = time.perf_counter()
        session.compute_fast()
        update.append(1e3 * (time.perf_counter() - t0))
    session.close()
    return bare, update


def _in_browser(values: list[float]) -> dict[str, list[float]]:
    from playwright.sync_api import sync_playwright

    from softcath.studies.app import start_in_thread
    from tests.browser._chromium import LAUNCH_ARGS

    app = start_in_thread("paper", p_max=1.0)
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=LAUNCH_ARGS)
            page = browser.new_page(viewport={"width": 1400, "height": 1000})
            page.goto(app.url)
            page.locator(".app-version").get_by_text("linear curve of version 0").wait_for(timeout=60000)
            box = page.locator(".field-tube-h input")
            box.evaluate(_EDIT_JS, ["0.005", "curve-section"])  # warm: the first edit of a session
            version, times = 1, {"idle": [], "busy": []}
            for mode in ("idle", "busy"):
                for v in values if mode == "idle" else _busy_values(values):
                    if mode == "idle":  # wait for the background to finish
                        finite = page.locator(".app-finite").get_by_text(
                            f"up to date (design version {version})"
                        )
                        finite.wait_for(timeout=120000)
                    else:
                        time.sleep(0.6)  # the previous design's finite-strain curve is computing
                    ms = box.evaluate(_EDIT_JS, [str(v), "curve-section"])
                    if ms < 0:
                        raise RuntimeError(f"the curve did not change within 30 s for tube.h = {v}")
                    times[mode].append(ms)
                    version += 1
            browser.close()
    finally:
        app.stop()
    return times


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--edits", type=int, default=10, help="input changes timed (default 10)")
    args = parser.parse_args()
    if not CHROMIUM.is_file():
        print("bench_app: skipped, /usr/bin/chromium is not installed")
        return 0
    values = _values(args.edits)
    bare, update = _baselines(values)
    ui = _in_browser(values)
    med_bare, med_update = statistics.median(bare), statistics.median(update)
    print(
        "softcath app, input change -> updated linear curve on screen "
        f"({len(values)} edits of tube.h; {_load()})"
    )
    print(row("baseline: bare linear section solve, median", f"{med_bare:.1f} ms"))
    print(row("server-side update (formula + linear + strain), median", f"{med_update:.1f} ms"))
    target = f"target <= {TARGET_MS:.0f} ms"
    for mode, what in (("idle", "app idle"), ("busy", "finite strain computing")):
        med, top = statistics.median(ui[mode]), max(ui[mode])
        print(row(f"on screen, {what}: median", f"{med:.0f} ms", target, med <= TARGET_MS))
        print(row(f"on screen, {what}: largest", f"{top:.0f} ms", target, top <= TARGET_MS))
        print(row(f"ratio on screen / bare linear solve ({what}, medians)", f"{med / med_bare:.1f}x"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
