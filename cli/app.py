"""Design the tip interactively in a local web app (Panel): inputs, curves, compare, export, 3-D check.

Serves the app for DESIGN (default: paper) at http://127.0.0.1:PORT/, prints the
address and opens it in the browser. Every design field a sweep can vary is an
input (coil, tube and lumen, channel, tip length, materials, as built); the
section, κ and θ against pressure (the paper's formula and the linear section
model at once, the finite-strain section model in the background), the bent tip
and the numbers follow each change. The app writes no files: the design (TOML),
the curves (CSV) and the view (PNG) are downloads. Ctrl-C stops the server.
"""

from __future__ import annotations

import argparse

from softcath.cli.options import add_design
from softcath.core.errors import DesignError
from softcath.studies.app import make_server

HELP = "the interactive design app in the browser (local web server; Ctrl-C stops it)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design(parser, optional=True)
    parser.add_argument(
        "--port", type=int, default=0, help="TCP port to listen on (default: a free port, printed)"
    )
    parser.add_argument(
        "--address",
        default="127.0.0.1",
        help="address to bind (default 127.0.0.1: this machine only)",
    )
    parser.add_argument("--no-browser", action="store_true", help="do not open the browser, just serve")


def run(args: argparse.Namespace) -> int:
    if not 0 <= args.port <= 65535:
        raise DesignError("--port", args.port, "must be in 0..65535 (0: a free port)")
    import logging

    # The app's library imports Panel (Bokeh, Tornado) lazily: `softcath --help` stays fast.

    for noisy in ("panel", "tornado.access"):  # a line per poll and per request would drown --verbose
        logging.getLogger(noisy).setLevel(logging.WARNING)

    server = make_server(args.design, port=args.port, address=args.address)
    server.start()
    url = f"http://{args.address}:{server.port}/"
    print(f"softcath app: serving {args.design} at {url} (Ctrl-C stops)", flush=True)
    if not args.no_browser:
        import webbrowser

        webbrowser.open(url)
    try:
        server.io_loop.start()
    finally:
        server.stop()
    return 0
