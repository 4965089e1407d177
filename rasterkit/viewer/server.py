"""``rasterkit view``'s web page: a small HTTP server on 127.0.0.1, built on the standard
library's :mod:`http.server` (one thread per request; the page needs four kinds of request,
none of them a WebSocket, so no framework is needed).

The page (``static/``) asks for ``GET state`` (the choices and the model's name) once, then
for ``GET frame?after=N`` in a loop: the answer comes when there is a frame newer than N
(within :data:`POLL_SECONDS`, else 204), the picture's bytes with its number, whether it is
the full-quality one, the event it shows (``X-Event-Seq``) and its camera (``X-Camera``, JSON)
in headers. The mouse's events go up as ``POST event`` (JSON, at most :data:`MAX_EVENT_BYTES`).

Safe by default: the server listens on 127.0.0.1 only, answers only these paths, and refuses
(403) any request whose ``Host`` is not its own address (a DNS-rebinding page) or whose
``Origin``, when there is one, is not its own page (another site's script), so a page of
another site cannot drive the viewer or read its frames.
"""

from __future__ import annotations

import json
import sys
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from urllib.parse import parse_qs, urlsplit

__all__ = ["POLL_SECONDS", "ViewerServer"]

#: How long a frame request waits for a new frame before it is answered 204 (and asked again).
POLL_SECONDS = 10.0
#: The largest event a page may send, bytes.
MAX_EVENT_BYTES = 4096
_FILES = {"/": ("page.html", "text/html; charset=utf-8"),
          "/page.js": ("page.js", "text/javascript; charset=utf-8"),
          "/controls.js": ("controls.js", "text/javascript; charset=utf-8")}


def static_file(name: str) -> bytes:
    """The viewer's own file ``name`` (of ``rasterkit/viewer/static``)."""
    return resources.files("rasterkit.viewer").joinpath("static").joinpath(name).read_bytes()


class ViewerServer(ThreadingHTTPServer):
    """The page and its requests for the frames of ``loop`` (a
    :class:`rasterkit.viewer.loop.FrameLoop`); ``state`` the JSON of ``GET state``. Port 0:
    a free one (:attr:`port` tells which)."""

    daemon_threads = True
    allow_reuse_address = False

    def __init__(self, loop, state: dict, port: int = 0):
        self.loop, self.state = loop, state
        super().__init__(("127.0.0.1", port), _Handler)
        self.port = self.server_address[1]
        self.origins = {f"http://127.0.0.1:{self.port}", f"http://localhost:{self.port}"}
        self.hosts = {f"127.0.0.1:{self.port}", f"localhost:{self.port}"}

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}/"

    def handle_error(self, request, client_address) -> None:
        """A page that went away mid-answer is no error; anything else is one line on stderr."""
        error = sys.exc_info()[1]
        if not isinstance(error, ConnectionError):
            print(f"rasterkit view: {type(error).__name__}: {error}".splitlines()[0], file=sys.stderr)

    def start(self) -> threading.Thread:
        """Serve on a thread of its own (:meth:`shutdown` ends it)."""
        thread = threading.Thread(target=self.serve_forever, name="rasterkit-view-server", daemon=True)
        thread.start()
        return thread


class _Handler(BaseHTTPRequestHandler):
    server: ViewerServer
    protocol_version = "HTTP/1.1"
    # headers and body go out as two writes: without TCP_NODELAY the body would wait for the
    # page's delayed acknowledgement of the headers (about 40 ms on Linux) on every frame
    disable_nagle_algorithm = True

    def log_message(self, format, *args) -> None:  # quiet: the terminal shows the flags at the end
        pass

    def _allowed(self) -> bool:
        origin = self.headers.get("Origin")
        if self.headers.get("Host") not in self.server.hosts or origin is not None and origin not in self.server.origins:
            self._answer(403, b"forbidden: not this viewer's page\n", "text/plain; charset=utf-8")
            return False
        return True

    def _answer(self, status: int, body: bytes, kind: str, headers: dict | None = None) -> None:
        self.send_response(status)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        for key, value in (headers or {}).items():
            self.send_header(key, value)
        self.end_headers()
        self.wfile.write(body)

    def do_GET(self) -> None:
        if not self._allowed():
            return
        url = urlsplit(self.path)
        if url.path in _FILES:
            name, kind = _FILES[url.path]
            self._answer(200, static_file(name), kind)
        elif url.path == "/state":
            self._answer(200, json.dumps(self.server.state).encode(), "application/json")
        elif url.path == "/frame":
            self._frame(parse_qs(url.query).get("after", ["0"])[0])
        else:
            self._answer(404, b"not found\n", "text/plain; charset=utf-8")

    def _frame(self, after: str) -> None:
        try:
            after = int(after)
        except ValueError:
            self._answer(400, b"after must be a whole number\n", "text/plain; charset=utf-8")
            return
        frame = self.server.loop.wait_frame(after, POLL_SECONDS)
        if frame is None:
            self._answer(204, b"", "text/plain")
            return
        self._answer(200, frame.data, frame.mime, {
            "X-Frame-Number": str(frame.number), "X-Frame-Final": "1" if frame.final else "0",
            "X-Event-Seq": str(frame.seq), "X-Camera": json.dumps(frame.camera),
            "X-Error": (self.server.loop.error or "").encode("ascii", "replace").decode()})

    def do_POST(self) -> None:
        if not self._allowed():
            return
        if urlsplit(self.path).path != "/event":
            self._answer(404, b"not found\n", "text/plain; charset=utf-8")
            return
        try:
            length = int(self.headers.get("Content-Length", ""))
        except ValueError:
            length = -1
        if not 0 <= length <= MAX_EVENT_BYTES:
            self.close_connection = True
            self._answer(413, f"an event is at most {MAX_EVENT_BYTES} bytes\n".encode(), "text/plain; charset=utf-8")
            return
        try:
            self.server.loop.post(json.loads(self.rfile.read(length)))
        except (ValueError, TypeError, KeyError) as error:  # JSONDecodeError is a ValueError
            self._answer(400, f"{error}\n".splitlines()[0].encode() + b"\n", "text/plain; charset=utf-8")
            return
        self._answer(204, b"", "text/plain")
