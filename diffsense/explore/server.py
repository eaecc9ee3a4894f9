"""Serving the explorer as a local web page, and showing it in a Jupyter cell.

The spec is read and its program compiled once (:class:`~diffsense.explore.session.ExplorerSession`);
every browser tab gets its own point (:meth:`ExplorerSession.fork`) on the same compiled
program. The server listens on the loopback address only and answers only requests addressed
to it by that name (:func:`answer_local_hosts_only`).
"""

from __future__ import annotations

import os
import re
import socket
from typing import Optional

from diffsense.explore.session import ExplorerSession

#: XLA:CPU compiles the explorer's program about twice as fast without its fusion emitters
#: (5.7 s instead of 15.5 s for the ore-pass design on a busy 2-core machine), at equal run
#: time; the flag is read when JAX's backend starts.
XLA_FLAG = "--xla_cpu_use_fusion_emitters=false"


def prefer_fast_compilation() -> None:
    """Add :data:`XLA_FLAG` to ``XLA_FLAGS`` (effective only before JAX's backend starts)."""
    flags = os.environ.get("XLA_FLAGS", "")
    if XLA_FLAG not in flags:
        os.environ["XLA_FLAGS"] = (flags + " " + XLA_FLAG).strip()


def free_port() -> int:
    """A TCP port on 127.0.0.1 that is free now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _local_hosts(port: int) -> frozenset:
    return frozenset({f"127.0.0.1:{port}", f"localhost:{port}"})


def answer_local_hosts_only(http_server, port: int) -> None:
    """Make ``http_server`` (Tornado's, under the Bokeh server) answer only requests whose
    ``Host`` header names this machine's loopback address and ``port``: a page of another site
    whose name resolves to 127.0.0.1 (DNS rebinding) sends its own name as ``Host``, and gets
    403 for the page and for the websocket alike (Bokeh's origin allow-list alone is not asked
    when Tornado already found the websocket's ``Origin`` equal to its ``Host``)."""
    from tornado import httputil

    allowed = _local_hosts(port)
    inner = http_server.request_callback

    class Refusing(httputil.HTTPMessageDelegate):
        def __init__(self, server_conn, request_conn):
            self.server_conn, self.request_conn = server_conn, request_conn
            self.delegate = None

        def headers_received(self, start_line, headers):
            if headers.get("Host", "") in allowed:
                self.delegate = inner.start_request(self.server_conn, self.request_conn)
                return self.delegate.headers_received(start_line, headers)
            body = b"diffsense explore answers only http://127.0.0.1:%d/ and http://localhost:%d/\n" % (port, port)
            self.request_conn.write_headers(
                httputil.ResponseStartLine("HTTP/1.1", 403, "Forbidden"),
                httputil.HTTPHeaders({"Content-Type": "text/plain; charset=utf-8", "Content-Length": str(len(body)),
                                      "Connection": "close"}), body)
            self.request_conn.finish()
            return None

        def data_received(self, chunk):
            return None if self.delegate is None else self.delegate.data_received(chunk)

        def finish(self):
            if self.delegate is not None:
                self.delegate.finish()

        def on_connection_close(self):
            if self.delegate is not None:
                self.delegate.on_connection_close()

    class LocalOnly(httputil.HTTPServerConnectionDelegate):
        def start_request(self, server_conn, request_conn):
            return Refusing(server_conn, request_conn)

        def on_close(self, server_conn):
            inner.on_close(server_conn)

    http_server.request_callback = LocalOnly()


def _panel():
    import panel as pn

    pn.extension(notifications=False)
    return pn


def explore(spec_or_path, *, session: Optional[ExplorerSession] = None, out_dir=None):
    """The explorer of a spec (a TOML path or a loaded spec) as a Panel object: shown by a
    Jupyter cell that ends with it; ``.session`` holds the point and ``.page`` the widgets;
    ``out_dir``: the folder its files go to (default: ``<spec name>_explored`` beside the spec)."""
    prefer_fast_compilation()
    _panel()
    from diffsense.explore.page import ExplorerPage

    session = session or ExplorerSession(spec_or_path, out_dir=out_dir)
    # a notebook cell shows the whole explorer when it finishes: every program compiled first
    # (the served page instead loads in steps, see ExplorerPage.prepare_extras)
    session.prepare_core()
    session.prepare_extras()
    page = ExplorerPage(session)
    view = page.layout
    view.page = page
    view.session = page.session
    return view


def tab_title(title: str) -> str:
    """The browser tab's text for a spec ``title``: without the characters HTML gives a meaning
    (``< > & " '``), so that it reads the same whether a page template escapes it (Panel's
    page does) or not (its error page does not), and never becomes markup.

    >>> tab_title('<img src=x onerror="alert(1)">')
    'diffsense explore: img src=x onerror=alert(1)'
    """
    return "diffsense explore: " + re.sub(r"[<>&\"']", "", title)


def serve(session: ExplorerSession, *, port: int = 0, show: bool = True, on_ready=None):
    """Serve the explorer of ``session`` on http://127.0.0.1:``port`` (0: a free port) until
    interrupted; ``on_ready(url)`` is called once the server listens."""
    pn = _panel()
    from diffsense.explore.page import ExplorerPage

    def app():
        return ExplorerPage(session.fork()).layout

    port = port or free_port()
    server = pn.serve({"/": app}, port=port, address="127.0.0.1", show=False, start=False,
                      title=tab_title(session.spec.title),
                      websocket_origin=sorted(_local_hosts(port)), threaded=False)
    answer_local_hosts_only(server._http, port)
    server.start()
    url = f"http://127.0.0.1:{server.port}/"
    if on_ready is not None:
        on_ready(url)
    if show:
        import webbrowser

        server.io_loop.add_callback(webbrowser.open, url)
    server.io_loop.start()


__all__ = ["explore", "serve", "prefer_fast_compilation", "answer_local_hosts_only", "XLA_FLAG"]
