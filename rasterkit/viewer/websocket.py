"""The few parts of the WebSocket protocol (RFC 6455) the viewer's page needs: the opening
handshake's answer, reading the page's messages (masked, maybe fragmented, at most a given
size) and writing the server's (unmasked, one frame each).

A WebSocket is one connection kept open both ways: the page sends its mouse events and
receives its frames on it without a request per message, which in a browser costs a few
milliseconds of CPU each (an HTTP request goes through the browser's network process).
"""

from __future__ import annotations

import base64
import hashlib
import struct

__all__ = ["BINARY", "CLOSE", "PING", "PONG", "TEXT", "ProtocolError", "accept_key", "encode", "read_message"]

TEXT, BINARY, CLOSE, PING, PONG = 0x1, 0x2, 0x8, 0x9, 0xA
_CONTINUATION = 0x0
_GUID = b"258EAFA5-E914-47DA-95CA-C5AB0DC85B11"  # RFC 6455, section 1.3


class ProtocolError(ValueError):
    """A message the protocol does not allow, or larger than allowed; ``code`` is the close
    code to answer with (1002 protocol error, 1003 unsupported data, 1009 too big)."""

    def __init__(self, message: str, code: int = 1002):
        super().__init__(message)
        self.code = code


def accept_key(key: str) -> str:
    """The ``Sec-WebSocket-Accept`` answering the page's ``Sec-WebSocket-Key``."""
    return base64.b64encode(hashlib.sha1(key.strip().encode("ascii") + _GUID).digest()).decode("ascii")


def encode(opcode: int, payload: bytes) -> bytes:
    """One unmasked, final frame of ``payload`` (a server's message)."""
    n = len(payload)
    if n < 126:
        head = struct.pack("!BB", 0x80 | opcode, n)
    elif n < 1 << 16:
        head = struct.pack("!BBH", 0x80 | opcode, 126, n)
    else:
        head = struct.pack("!BBQ", 0x80 | opcode, 127, n)
    return head + payload


def _exactly(stream, n: int) -> bytes:
    data = stream.read(n) if n else b""
    if len(data) != n:
        raise EOFError("the connection closed")
    return data


def _frame(stream, limit: int) -> tuple[bool, int, bytes]:
    """``(final, opcode, payload)`` of the next frame from the page (masked, as a client's
    must be; at most ``limit`` bytes of payload)."""
    first, second = _exactly(stream, 2)
    if first & 0x70:
        raise ProtocolError("reserved bits set (no extension was agreed)")
    if not second & 0x80:
        raise ProtocolError("a frame from the page must be masked")
    n = second & 0x7F
    if n == 126:
        n = struct.unpack("!H", _exactly(stream, 2))[0]
    elif n == 127:
        n = struct.unpack("!Q", _exactly(stream, 8))[0]
    if n > limit:
        raise ProtocolError(f"a message is at most {limit} bytes", 1009)
    mask = _exactly(stream, 4)
    data = _exactly(stream, n)
    if n:
        key = int.from_bytes((mask * (n // 4 + 1))[:n], "big")
        data = (int.from_bytes(data, "big") ^ key).to_bytes(n, "big")
    return bool(first & 0x80), first & 0x0F, data


def read_message(stream, limit: int, control) -> tuple[int, bytes]:
    """The next data message from the page, ``(TEXT or BINARY, payload)``, its fragments
    joined (at most ``limit`` bytes in all); ``control(opcode, payload)`` is called for each
    ping or close frame met on the way (a close ends with ``(CLOSE, payload)`` returned).
    Raises :class:`ProtocolError` for a message the protocol does not allow and EOFError
    when the connection ends."""
    opcode, parts, size = None, [], 0
    while True:
        final, kind, data = _frame(stream, max(limit - size, 125))  # (a control frame may be 125 bytes)
        if kind < 0x8 and size + len(data) > limit:
            raise ProtocolError(f"a message is at most {limit} bytes", 1009)
        if kind >= 0x8:  # control frames: short, never fragmented, may come between fragments
            if not final or len(data) > 125:
                raise ProtocolError("a control frame is final and at most 125 bytes")
            if kind not in (CLOSE, PING, PONG):
                raise ProtocolError(f"unknown control frame {kind:#x}")
            control(kind, data)
            if kind == CLOSE:
                return CLOSE, data
            continue
        if kind == _CONTINUATION:
            if opcode is None:
                raise ProtocolError("a continuation frame with no message to continue")
        elif kind in (TEXT, BINARY):
            if opcode is not None:
                raise ProtocolError("a new message before the last one ended")
            opcode = kind
        else:
            raise ProtocolError(f"unknown data frame {kind:#x}")
        parts.append(data)
        size += len(data)
        if final:
            return opcode, b"".join(parts)
