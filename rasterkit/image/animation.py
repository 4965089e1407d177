"""Animated GIF and APNG written frame by frame: memory does not grow with the frame count.

Pillow's writers keep every frame of an animation until the end; these write each frame into
the (temporary) file as it comes, from any iterable of frames, so a turntable of 100 000
frames needs the memory of two. As Pillow's did, a frame identical to the one before is not
written again: the one before is shown longer (up to the longest delay the format holds).

- **APNG**: PNG chunks. ``acTL`` (frame count, loops) is written with a count of 0 and
  rewritten at the end, when the count is known; every frame is the whole image (``fcTL``
  with offset 0, 0, dispose ``none``, blend ``source``), the first in ``IDAT`` chunks (so a
  viewer without APNG shows it), the others in ``fdAT`` chunks. The pixels are compressed
  as still PNGs are (:mod:`rasterkit.image.png`).
- **GIF**: the GIF89a header (no global colour table) and the ``NETSCAPE2.0`` loop
  extension, then per frame a graphic control extension (delay, transparency) and an image
  with its own colour table. Pillow quantizes and LZW-encodes each frame alone (as it saves a
  one-frame GIF, with its adaptive palette) and the frame's colour table and data blocks
  are copied from that. A frame with transparent pixels is disposed of ("restore to
  background") before the next one is drawn, so that no frame shows through the next.

The frames are uint8 (H, W, 3|4) arrays, checked by the caller; they must have one shape.
The delay of a frame is given in milliseconds, as Pillow takes it (a GIF keeps whole
hundredths of a second).
"""

from __future__ import annotations

import io
import struct
from fractions import Fraction
from typing import BinaryIO, Iterable, Iterator

import numpy as np

from rasterkit.image import png as _png

__all__ = ["write_apng", "write_gif"]

_MAX_PNG_INT = 2**31 - 1  # PNG's four-byte numbers (frame counts, sequence numbers)


def _same_shape(first: tuple, color: np.ndarray, k: int) -> None:
    if color.shape != first:
        raise ValueError(f"frame {k} is {color.shape[1]}x{color.shape[0]} with {color.shape[2]} channels, "
                         f"frame 0 {first[1]}x{first[0]} with {first[2]}: the frames of an animation "
                         f"must all have one size and kind")


def _runs(frames: Iterable[np.ndarray], duration_ms: float, longest_ms: float) -> Iterator[tuple[np.ndarray, float]]:
    """``(frame, milliseconds)`` for each run of identical consecutive frames, a run lasting
    at most ``longest_ms`` (unless one frame alone lasts longer). A frame is copied as it
    comes (a generator may draw the next one into the same array) and handed on when the
    next different one arrives: two frames in memory at most."""
    pending, shown = None, 0.0
    for k, color in enumerate(frames):
        if pending is not None:
            _same_shape(pending.shape, color, k)
            if shown + duration_ms <= longest_ms and np.array_equal(color, pending):
                shown += duration_ms
                continue
            yield pending, shown
        pending, shown = np.array(color, copy=True), duration_ms
    if pending is not None:
        yield pending, shown


def write_apng(frames: Iterable[np.ndarray], f: BinaryIO, duration_ms: float, loop: int = 0) -> int:
    """Write ``frames`` to the seekable binary file ``f`` as an APNG; returns the number of
    frames written (identical consecutive frames are one, shown longer).

    ``duration_ms``: the time each frame is shown; ``loop``: plays, 0 for endlessly.
    Raises ``ValueError`` for no frames or frames of different shapes.
    """
    if Fraction(duration_ms / 1000).limit_denominator(65535).numerator > 65535:
        raise ValueError(f"an APNG cannot show a frame for {duration_ms} ms")
    shape, count, sequence, actl_at = None, 0, 0, 0
    for color, shown in _runs(frames, duration_ms, 65535):  # a run: whole ms over 1000 at most
        delay = Fraction(shown / 1000).limit_denominator(65535)
        if shape is None:
            shape = color.shape
            f.write(_png.SIGNATURE + _png.header(color))
            actl_at = f.tell()
            f.write(_png.chunk(b"acTL", struct.pack(">II", 0, loop)))  # the count comes at the end
        height, width = shape[:2]
        f.write(_png.chunk(b"fcTL", struct.pack(">IIIIIHHBB", sequence, width, height, 0, 0,
                                                delay.numerator, delay.denominator, 0, 0)))
        sequence += 1
        if count == 0:  # streamed as zlib makes it: no copy of the frame's stream in memory
            _png.write_chunks(f, color)
        else:
            sequence = _png.write_chunks(f, color, b"fdAT", _png.IDAT_BYTES - 4, sequence)
        count += 1
        if sequence > _MAX_PNG_INT:
            raise ValueError(f"an APNG holds at most {_MAX_PNG_INT} chunks of frames")
    if shape is None:
        raise ValueError("an animation needs at least one frame")
    f.write(_png.chunk(b"IEND", b""))
    end = f.tell()
    f.seek(actl_at)
    f.write(_png.chunk(b"acTL", struct.pack(">II", count, loop)))
    f.seek(end)
    return count


def blocks_end(data: bytes, pos: int) -> int:
    """The position after the data sub-blocks that start at ``pos`` (and their 0 terminator)."""
    while data[pos]:
        pos += data[pos] + 1
    return pos + 1


def _table_bits(table: bytes) -> int:
    """The size field of a colour table of ``len(table) // 3`` entries (2 ** (bits + 1))."""
    return (len(table) // 3).bit_length() - 2


def gif_frame(color: np.ndarray) -> tuple[bytes, int | None, int, bytes]:
    """One frame as Pillow saves a one-frame GIF of it: its colour table, transparent index
    (or None), interlace flag (0x40 or 0), and the LZW data (code size byte and sub-blocks)."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(color), "RGBA" if color.shape[2] == 4 else "RGB")
    out = io.BytesIO()
    image.save(out, format="GIF")
    data = out.getvalue()
    packed = data[10]
    pos, table, transparency = 13, b"", None
    if packed & 0x80:
        table, pos = data[pos: pos + (3 << ((packed & 7) + 1))], pos + (3 << ((packed & 7) + 1))
    while True:
        kind = data[pos]
        if kind == 0x21:  # an extension: label, sub-blocks
            if data[pos + 1] == 0xF9 and data[pos + 3] & 1:  # graphic control, transparent index
                transparency = data[pos + 6]
            pos = blocks_end(data, pos + 2)
        elif kind == 0x2C:  # the image: descriptor, optional table, code size, sub-blocks
            flags = data[pos + 9]
            pos += 10
            if flags & 0x80:
                table, pos = data[pos: pos + (3 << ((flags & 7) + 1))], pos + (3 << ((flags & 7) + 1))
            return table, transparency, flags & 0x40, data[pos: blocks_end(data, pos + 1)]
        else:
            raise ValueError(f"unexpected GIF block {kind:#x} from Pillow")


def write_gif(frames: Iterable[np.ndarray], f: BinaryIO, duration_ms: float, loop: int = 0) -> int:
    """Write ``frames`` to the binary file ``f`` as an animated GIF; returns the number of
    frames written (identical consecutive frames are one, shown longer).

    ``duration_ms``: the time each frame is shown (whole hundredths of a second are kept);
    ``loop``: plays after the first, 0 for endlessly. Raises ``ValueError`` for no frames or
    frames of different shapes.
    """
    if not 0 <= int(duration_ms / 10) <= 65535:
        raise ValueError(f"a GIF cannot show a frame for {duration_ms} ms")
    shape, count = None, 0
    for color, shown in _runs(frames, duration_ms, 655350):
        delay = int(shown / 10)
        if shape is None:
            shape = color.shape
            height, width = shape[:2]
            f.write(b"GIF89a" + struct.pack("<HHBBB", width, height, 0, 0, 0))
            f.write(b"!\xff\x0bNETSCAPE2.0\x03\x01" + struct.pack("<H", loop) + b"\x00")
        table, transparency, interlace, lzw = gif_frame(color)
        flags = (1 | 2 << 2) if transparency is not None else 0  # transparent: restore to background
        f.write(b"!\xf9\x04" + struct.pack("<BHB", flags, delay, transparency or 0) + b"\x00")
        f.write(b"," + struct.pack("<HHHHB", 0, 0, width, height, 0x80 | interlace | _table_bits(table)))
        f.write(table)
        f.write(lzw)
        count += 1
    if shape is None:
        raise ValueError("an animation needs at least one frame")
    f.write(b";")
    return count
