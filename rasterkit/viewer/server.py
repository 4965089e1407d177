"""``rasterkit view``'s web page: a small HTTP server on 127.0.0.1, built on the standard
library's :mod:`http.server` (one thread per connection) and the few parts of the WebSocket
protocol the page uses (:mod:`rasterkit.viewer.websocket`), so no framework is needed.

The page (``static/``) asks for ``GET state`` (the choices and the model's name) once, then
opens a WebSocket at ``/socket``, on which it sends its mouse's events (JSON text messages,
at most :data:`MAX_EVENT_BYTES`, :data:`rasterkit.viewer.session.EVENTS`) and ``{"ready": N}``
when it can show a frame newer than N; the server answers each ``ready`` with the newest
frame once there is one newer than N: a binary message of a 4-byte big-endian length, that
many bytes of JSON (``number``, ``final``, ``seq``: the event it shows, ``mime``, ``camera``,
``error``) and the picture's bytes. A bad event is answered with a text message
``{"error": "..."}``. One frame at a time is on its way, so when the page is slower than the
frames only the newest is sent. The same is there without a WebSocket, for scripts: ``GET
frame?after=N`` (the answer comes when there is a frame newer than N, within
:data:`POLL_SECONDS`, else 204; the picture's bytes with the same fields as ``X-Frame-Number``,
``X-Frame-Final``, ``X-Event-Seq``, ``X-Camera`` and ``X-Error`` headers) and ``POST event``.

Safe by default: the server listens on 127.0.0.1 only, answers only these paths, and refuses
(403) any request, the WebSocket's opening one included, whose ``Host`` is not its own address
(a DNS-rebinding page) or whose ``Origin``, when there is one, is not its own page (another
site's script), so a page of another site cannot drive the viewer or read its frames.
"""

from __future__ import annotations

import json
import struct
import sys
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from importlib import resources
from urllib.parse import parse_qs, urlsplit

from rasterkit.viewer import websocket

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
        elif url.path == "/socket":
            self._socket()
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

    def _socket(self) -> None:
        """The page's WebSocket: its events in, its frames out, until either side closes."""
        key = self.headers.get("Sec-WebSocket-Key")
        if "websocket" not in self.headers.get("Upgrade", "").lower() or not key \
                or self.headers.get("Sec-WebSocket-Version") != "13":
            self._answer(400, b"a WebSocket opening handshake is expected here\n", "text/plain; charset=utf-8")
            return
        self.send_response(101)
        self.send_header("Upgrade", "websocket")
        self.send_header("Connection", "Upgrade")
        self.send_header("Sec-WebSocket-Accept", websocket.accept_key(key))
        self.end_headers()
        self.wfile.flush()
        self.close_connection = True
        _Channel(self.server.loop, self.rfile, self.wfile).run()

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


class _Channel:
    """One page's WebSocket (:mod:`rasterkit.viewer.websocket`): this thread reads its
    messages; a thread of its own sends a frame each time the page is ready for one."""

    def __init__(self, loop, rfile, wfile):
        self.loop, self.rfile, self.wfile = loop, rfile, wfile
        self._writing = threading.Lock()
        self._ready = threading.Condition()
        self._after: int | None = None  # the page is ready for a frame newer than this
        self._closed = False

    def run(self) -> None:
        sender = threading.Thread(target=self._send_frames, name="rasterkit-view-frames", daemon=True)
        sender.start()
        try:
            self._read_messages()
        except websocket.ProtocolError as error:
            self._send(websocket.CLOSE, struct.pack("!H", error.code) + str(error).encode()[:100])
        except (EOFError, OSError):
            pass
        finally:
            with self._ready:
                self._closed = True
                self._ready.notify_all()
            sender.join(timeout=5)

    def _read_messages(self) -> None:
        while True:
            kind, data = websocket.read_message(self.rfile, MAX_EVENT_BYTES, self._control)
            if kind == websocket.CLOSE:
                return
            if kind != websocket.TEXT:
                raise websocket.ProtocolError("the page's messages are JSON text", 1003)
            try:
                message = json.loads(data)
                if isinstance(message, dict) and set(message) == {"ready"}:
                    self._page_ready(message["ready"])
                else:
                    self.loop.post(message)
            except (ValueError, TypeError, KeyError) as error:  # JSONDecodeError is a ValueError
                self._send(websocket.TEXT, json.dumps({"error": str(error).splitlines()[0]}).encode())

    def _page_ready(self, after) -> None:
        if isinstance(after, bool) or not isinstance(after, int) or not 0 <= after < 2**53:
            raise ValueError("ready must be a frame number")
        with self._ready:
            self._after = after
            self._ready.notify_all()

    def _control(self, kind: int, data: bytes) -> None:
        if kind == websocket.PING:
            self._send(websocket.PONG, data)
        elif kind == websocket.CLOSE:
            self._send(websocket.CLOSE, data[:2])

    def _send(self, kind: int, payload: bytes) -> None:
        with self._writing:
            self.wfile.write(websocket.encode(kind, payload))
            self.wfile.flush()

    def _send_frames(self) -> None:
        while True:
            with self._ready:
                while self._after is None and not self._closed:
                    self._ready.wait()
                if self._closed:
                    return
                after = self._after
            frame = self.loop.wait_frame(after, 1.0)  # (then again: the page may have gone)
            if frame is None:
                if self.loop.closed:
                    return
                continue
            meta = json.dumps({"number": frame.number, "final": frame.final, "seq": frame.seq, "mime": frame.mime,
                               "camera": frame.camera, "error": self.loop.error or ""}).encode()
            with self._ready:
                if self._after != after:  # the page asked again meanwhile: answer that
                    continue
                self._after = None
            try:
                self._send(websocket.BINARY, struct.pack("!I", len(meta)) + meta + frame.data)
            except OSError:
                return
