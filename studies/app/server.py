"""Serve the app on a local address: one :class:`~softcath.studies.app.page.Session` per browser tab.

The server binds to 127.0.0.1 unless told otherwise and accepts websocket
connections from its own address only. It reads no file but the starting
design; uploads arrive over the websocket, limited in size
(:data:`WEBSOCKET_MAX_BYTES`, above :data:`~softcath.studies.app.measured.MAX_UPLOAD_BYTES`
so the app's own check gives the message).
"""

from __future__ import annotations

import asyncio
import logging
import threading
from dataclasses import dataclass
from typing import Any

from softcath.studies.app.layout import build
from softcath.studies.app.measured import MAX_UPLOAD_BYTES
from softcath.studies.app.page import Session
from softcath.studies.app.state import initial_state

__all__ = ["RunningApp", "WEBSOCKET_MAX_BYTES", "make_server", "start_in_thread", "view"]

log = logging.getLogger(__name__)

#: Largest websocket message [bytes]: an upload travels base64-encoded (4/3 of its size).
WEBSOCKET_MAX_BYTES = 2 * MAX_UPLOAD_BYTES


def view(spec: Any = "paper", **options: Any):
    """The app's page for ``spec`` as a Panel object (shows itself in a Jupyter notebook).

    Parameters
    ----------
    spec
        A preset name, a TOML path or a :class:`~softcath.design.TipDesign`.
    options
        ``p_max`` and ``pressure`` [MPa] of :class:`~softcath.studies.app.page.Session`.
    """
    return build(Session(spec, **options))


def _page(spec: Any, options: dict):
    import panel as pn

    session = Session(spec, **options)
    pn.state.on_session_destroyed(lambda _ctx: session.close())
    return build(session)


def make_server(spec: Any, *, port: int = 0, address: str = "127.0.0.1", loop=None, **options: Any):
    """A Bokeh server (not started) serving the app for ``spec`` at ``http://address:port/``.

    ``port`` 0 takes a free port (``server.port`` tells which). The design is checked
    first: an impossible design raises :class:`~softcath.design.errors.DesignError` here.
    """
    import panel as pn

    initial_state(spec)  # refuse a bad design before any socket is opened
    port = port or _free_port(address)
    origins = [f"{address}:{port}"] + ([f"localhost:{port}"] if address == "127.0.0.1" else [])
    server = pn.io.server.get_server(
        lambda: _page(spec, options),
        port=port,
        address=address,
        websocket_origin=origins,
        loop=loop,
        start=False,
        show=False,
        title="softcath app",
        websocket_max_message_size=WEBSOCKET_MAX_BYTES,
    )
    return server


def _free_port(address: str) -> int:
    """A port of ``address`` that is free now (the server binds it a moment later)."""
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((address, 0))
        return int(s.getsockname()[1])


@dataclass(frozen=True)
class RunningApp:
    """A server running on its own thread (tests, benchmarks, notebooks): its ``url`` and :meth:`stop`."""

    url: str
    server: Any
    loop: Any
    thread: threading.Thread

    def stop(self) -> None:
        """Stop the server and wait for its thread."""

        def _stop():
            self.server.stop()
            self.loop.stop()

        self.loop.add_callback(_stop)
        self.thread.join(timeout=10)


def start_in_thread(spec: Any = "paper", *, address: str = "127.0.0.1", **options: Any) -> RunningApp:
    """Start the app on a free port of ``address`` in a background thread; returns when it listens."""
    from tornado.ioloop import IOLoop

    ready = threading.Event()
    box: dict[str, Any] = {}

    def run() -> None:
        asyncio.set_event_loop(asyncio.new_event_loop())
        loop = IOLoop.current()
        try:
            server = make_server(spec, port=0, address=address, loop=loop, **options)
            server.start()
            box.update(server=server, loop=loop)
        except Exception as exc:  # handed to the caller
            box["error"] = exc
        finally:
            ready.set()
        if "server" in box:
            loop.start()
            loop.close(all_fds=True)

    thread = threading.Thread(target=run, name="softcath-app-server", daemon=True)
    thread.start()
    ready.wait(60)
    if "error" in box:
        raise box["error"]
    if "server" not in box:
        raise RuntimeError("the app's server did not start within 60 s")
    server = box["server"]
    return RunningApp(f"http://{address}:{server.port}/", server, box["loop"], thread)
