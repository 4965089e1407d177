"""The viewer page's WebSocket: the protocol's parts against RFC 6455's own examples, and the
server's socket driven by a small client written here (events in, frames out, the page's
origin only)."""

from __future__ import annotations

import base64
import io
import json
import os
import socket
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rasterkit as rk
from rasterkit.batch.render_one import load_drawn
from rasterkit.viewer import websocket
from rasterkit.viewer.loop import FrameLoop
from rasterkit.viewer.server import MAX_EVENT_BYTES, ViewerServer
from rasterkit.viewer.session import ViewerSession, choices


def _masked(opcode: int, payload: bytes, final: bool = True, mask: bytes = b"\x37\xfa\x21\x3d") -> bytes:
    """A client's frame, masked as RFC 6455 section 5.3 says (a slow reference: byte by byte)."""
    n = len(payload)
    head = bytes([(0x80 if final else 0) | opcode])
    if n < 126:
        head += bytes([0x80 | n])
    elif n < 1 << 16:
        head += bytes([0x80 | 126]) + n.to_bytes(2, "big")
    else:
        head += bytes([0x80 | 127]) + n.to_bytes(8, "big")
    return head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


def _read(data: bytes, limit: int = 1000):
    controls = []
    message = websocket.read_message(io.BytesIO(data), limit, lambda kind, payload: controls.append((kind, payload)))
    return message, controls


def test_the_handshake_key_and_the_frames_of_the_rfcs_examples():
    assert websocket.accept_key("dGhlIHNhbXBsZSBub25jZQ==") == "s3pPLMBiTxaQ9kYGzzhZRbK+xOo="  # section 1.3
    # section 5.7: a single-frame masked text message "Hello", and the server's unmasked one
    masked_hello = bytes([0x81, 0x85, 0x37, 0xFA, 0x21, 0x3D, 0x7F, 0x9F, 0x4D, 0x51, 0x58])
    assert _read(masked_hello) == ((websocket.TEXT, b"Hello"), [])
    assert websocket.encode(websocket.TEXT, b"Hello") == bytes([0x81, 0x05, 0x48, 0x65, 0x6C, 0x6C, 0x6F])
    # 256 bytes and 64 KiB of binary data: 16- and 64-bit lengths
    assert websocket.encode(websocket.BINARY, bytes(256))[:4] == bytes([0x82, 0x7E, 0x01, 0x00])
    assert websocket.encode(websocket.BINARY, bytes(65536))[:10] == bytes([0x82, 0x7F, 0, 0, 0, 0, 0, 1, 0, 0])


@pytest.mark.parametrize("size", [0, 1, 125, 126, 300, 65535, 65536, 70001])
def test_a_masked_message_of_any_length_reads_back(size):
    payload = os.urandom(size)
    assert _read(_masked(websocket.BINARY, payload), limit=1 << 20)[0] == (websocket.BINARY, payload)


def test_fragments_are_joined_and_a_ping_between_them_is_answered():
    data = (_masked(websocket.TEXT, b"Hel", final=False) + _masked(websocket.PING, b"are you there")
            + _masked(0x0, b"lo", final=True, mask=b"\x01\x02\x03\x04"))
    assert _read(data) == ((websocket.TEXT, b"Hello"), [(websocket.PING, b"are you there")])
    # a control frame between fragments may be as long as control frames may, whatever is left
    data = _masked(websocket.TEXT, b"x" * 990, final=False) + _masked(websocket.PING, b"p" * 125) \
        + _masked(0x0, b"y" * 10)
    assert _read(data) == ((websocket.TEXT, b"x" * 990 + b"y" * 10), [(websocket.PING, b"p" * 125)])
    close = _masked(websocket.CLOSE, struct.pack("!H", 1000))
    assert _read(close) == ((websocket.CLOSE, struct.pack("!H", 1000)), [(websocket.CLOSE, struct.pack("!H", 1000))])


@pytest.mark.parametrize("data, code", [
    (websocket.encode(websocket.TEXT, b"not masked"), 1002),
    (_masked(websocket.TEXT, b"x" * 1001), 1009),  # over the limit
    (_masked(websocket.TEXT, b"x" * 600, final=False) + _masked(0x0, b"x" * 600), 1009),  # in all
    (_masked(0x0, b"nothing to continue"), 1002),
    (_masked(websocket.TEXT, b"a", final=False) + _masked(websocket.TEXT, b"b"), 1002),
    (_masked(websocket.PING, b"x" * 126), 1002),
    (_masked(websocket.PING, b"", final=False), 1002),
    (_masked(0x3, b"reserved opcode"), 1002),
    (bytes([0xC1, 0x80]) + bytes(4), 1002),  # RSV1 set: no extension was agreed
])
def test_what_the_protocol_does_not_allow_is_refused_with_its_close_code(data, code):
    with pytest.raises(websocket.ProtocolError) as refused:
        _read(data)
    assert refused.value.code == code


def test_a_connection_that_ends_mid_frame_is_an_end_not_a_hang():
    for data in (b"", b"\x81", _masked(websocket.TEXT, b"Hello")[:-2]):
        with pytest.raises(EOFError):
            _read(data)


@settings(max_examples=400, deadline=None, database=None, derandomize=True)
@given(st.one_of(st.binary(max_size=64),
                 st.lists(st.tuples(st.integers(0, 15), st.binary(max_size=40), st.booleans()), max_size=5)
                 .map(lambda frames: b"".join(_masked(k, p, final=f) for k, p, f in frames))),
       st.integers(0, 300))
def test_any_bytes_give_a_message_or_a_one_line_refusal(data, cut):
    """Fuzzed: random bytes and random sequences of frames (any opcode, fragments, cut
    short anywhere) read as a message, a ProtocolError with a close code, or EOFError."""
    try:
        kind, payload = _read(data[:len(data) - cut % (len(data) + 1)], limit=64)[0]
    except websocket.ProtocolError as error:
        assert error.code in (1002, 1003, 1009) and "\n" not in str(error)
    except EOFError:
        pass
    else:
        assert kind in (websocket.TEXT, websocket.BINARY, websocket.CLOSE) and len(payload) <= 64


# --- the server's socket ------------------------------------------------------------------


@pytest.fixture
def server():
    session = ViewerSession(load_drawn(None, rk.RenderOptions(mode="solid"), False), rk.View(size=(64, 48)))
    loop = FrameLoop(session)
    server = ViewerServer(loop, {"model": "demo", "size": [64, 48], "choices": choices(),
                                 "current": session.current()})
    server.start()
    yield server
    server.shutdown()
    server.server_close()
    loop.close()


class _Client:
    """A WebSocket client as small as a test needs (a browser's messages are masked)."""

    def __init__(self, port: int, origin: str | None = None, key: str | None = None):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=120)
        self.stream = self.sock.makefile("rb")
        origin = f"http://127.0.0.1:{port}" if origin is None else origin
        key = base64.b64encode(os.urandom(16)).decode() if key is None else key
        self.sock.sendall((f"GET /socket HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n"
                           f"Origin: {origin}\r\n\r\n").encode())
        self.status = int(self.stream.readline().split()[1])
        self.headers = {}
        while (line := self.stream.readline().strip()):
            name, _, value = line.decode().partition(":")
            self.headers[name.lower()] = value.strip()

    def send(self, message: dict) -> None:
        self.sock.sendall(_masked(websocket.TEXT, json.dumps(message).encode()))

    def receive(self) -> tuple[int, bytes]:
        first, second = self.stream.read(2)
        n = second & 0x7F
        if n == 126:
            n = struct.unpack("!H", self.stream.read(2))[0]
        elif n == 127:
            n = struct.unpack("!Q", self.stream.read(8))[0]
        return first & 0x0F, self.stream.read(n)

    def frame(self, after: int) -> tuple[dict, bytes]:
        self.send({"ready": after})
        kind, data = self.receive()
        assert kind == websocket.BINARY
        length = struct.unpack("!I", data[:4])[0]
        return json.loads(data[4:4 + length]), data[4 + length:]

    def close(self) -> None:
        self.stream.close()
        self.sock.close()


def test_the_page_sends_events_and_gets_the_frames_that_show_them(server):
    client = _Client(server.port, key="dGhlIHNhbXBsZSBub25jZQ==")
    try:
        assert client.status == 101 and client.headers["sec-websocket-accept"] == "s3pPLMBiTxaQ9kYGzzhZRbK+xOo="
        meta, png = client.frame(0)
        assert png.startswith(b"\x89PNG") and meta["final"] and meta["mime"] == "image/png"
        # the same frame as the long-polling answer gives (one source of frames)
        assert png == server.loop.frame.data
        client.send({"kind": "drag", "dx": 12, "dy": 0, "seq": 7})
        client.send({"kind": "release", "seq": 8})
        start = meta["camera"]["azimuth"]
        while not (meta["final"] and meta["seq"] == 8):
            meta, picture = client.frame(meta["number"])
        assert meta["camera"]["azimuth"] == pytest.approx(start + 12 * 180 / 48) and picture.startswith(b"\x89PNG")
        client.send({"kind": "drag", "dx": "far"})  # a bad event: one line back, the socket stays
        kind, text = client.receive()
        assert kind == websocket.TEXT and "dx must be" in json.loads(text)["error"]
        client.sock.sendall(_masked(websocket.PING, b"still there?"))
        assert client.receive() == (websocket.PONG, b"still there?")
        client.sock.sendall(_masked(websocket.TEXT, b"x" * (MAX_EVENT_BYTES + 1)))
        kind, data = client.receive()
        assert kind == websocket.CLOSE and struct.unpack("!H", data[:2])[0] == 1009
    finally:
        client.close()


def test_the_first_drag_frame_shows_the_turn(server):
    client = _Client(server.port)
    try:
        meta, _ = client.frame(0)
        start = meta["camera"]["azimuth"]
        client.send({"kind": "drag", "dx": 12, "dy": 0, "seq": 3})
        while meta["seq"] != 3:
            meta, picture = client.frame(meta["number"])
        assert not meta["final"] and meta["mime"] == "image/jpeg" and picture.startswith(b"\xff\xd8")
        assert meta["camera"]["azimuth"] == pytest.approx(start + 12 * 180 / 48)
    finally:
        client.close()


@pytest.mark.parametrize("origin", ["http://evil.example", "null"])
def test_a_socket_from_another_sites_page_is_refused(server, origin):
    client = _Client(server.port, origin=origin)
    try:
        assert client.status == 403
    finally:
        client.close()


def test_a_plain_request_for_the_socket_is_a_bad_request(server):
    import http.client

    connection = http.client.HTTPConnection("127.0.0.1", server.port, timeout=60)
    connection.request("GET", "/socket", headers={"Host": f"127.0.0.1:{server.port}"})
    assert connection.getresponse().status == 400
    connection.close()
