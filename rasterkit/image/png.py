"""PNG pieces: chunks, the header and the compressed pixel stream of an RGB or RGBA image.

Shared by the still PNG writer (:func:`rasterkit.image.encode_png`) and the streaming APNG
writer (:mod:`rasterkit.image.animation`). The arrays are checked by the caller.
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

#: zlib level of PNG files. Level 1 without PNG's row filters writes a 1920x1080 render in
#: about 15 ms (Pillow: 39 ms at level 1, 62 ms at its default 6), for files about a third
#: larger than Pillow's default.
PNG_COMPRESS_LEVEL = 1

SIGNATURE = b"\x89PNG\r\n\x1a\n"

#: The most bytes of compressed stream in one IDAT (or fdAT) chunk: a chunk holds less than
#: 2**31 bytes, so a huge image's stream goes in several chunks.
IDAT_BYTES = 1 << 30


def chunk(tag: bytes, data: bytes) -> bytes:
    """One PNG chunk: length, tag, data, CRC."""
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(data, zlib.crc32(tag)))


def header(color: np.ndarray) -> bytes:
    """The IHDR chunk of a uint8 (H, W, 3|4) image: 8 bits per channel, no interlacing."""
    height, width, channels = color.shape
    return chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2 if channels == 3 else 6, 0, 0, 0))


#: Rows go through zlib this many bytes at a time: the stream is made without a second
#: copy of the image (a 32768x32768 render would need 3 GiB more).
_BLOCK_BYTES = 1 << 22


#: Memory that writing a PNG stream takes besides the image (:func:`write_chunks`): the block
#: of rows, what zlib returns for it, and zlib's own state, with room to spare.
STREAM_BYTES = 4 * _BLOCK_BYTES


def compressed_parts(color: np.ndarray):
    """The zlib stream of a uint8 (H, W, 3|4) image's rows, each with filter type 0 (none),
    at :data:`PNG_COMPRESS_LEVEL`, in the pieces zlib returns, a block of rows at a time."""
    height, width, channels = color.shape
    rows_per_block = max(1, _BLOCK_BYTES // (1 + width * channels))
    block = np.empty((min(rows_per_block, height), 1 + width * channels), np.uint8)
    block[:, 0] = 0  # the filter type of each row
    stream = zlib.compressobj(PNG_COMPRESS_LEVEL)
    for y in range(0, height, rows_per_block):
        n = min(rows_per_block, height - y)
        block[:n, 1:] = color[y:y + n].reshape(n, width * channels)
        yield stream.compress(block[:n].data)
    yield stream.flush()


def compressed(color: np.ndarray) -> bytes:
    """The whole zlib stream of :func:`compressed_parts`."""
    return b"".join(compressed_parts(color))


def write_chunks(f, color: np.ndarray, tag: bytes = b"IDAT", limit: int | None = None,
                 sequence: int | None = None) -> int | None:
    """Write the chunks ``tag`` of ``color``'s compressed rows into the seekable binary file
    ``f``: the bytes of ``chunk(tag, piece)`` for each of ``pieces(compressed(color), limit)``
    (with ``sequence``: ``chunk(tag, pack(">I", sequence) + piece)``, the number counting up,
    as APNG's fdAT chunks), streamed as zlib makes them. Memory: :data:`STREAM_BYTES`, not
    the stream (a chunk's length is written when the chunk is complete). Returns the next
    sequence number (None without ``sequence``)."""
    limit = limit or IDAT_BYTES
    start = size = crc = None

    def open_chunk():
        nonlocal start, size, crc, sequence
        start, size, crc = f.tell(), 0, zlib.crc32(tag)
        f.write(b"\0\0\0\0" + tag)
        if sequence is not None:
            number = struct.pack(">I", sequence)
            f.write(number)
            crc, sequence = zlib.crc32(number, crc), sequence + 1

    def close_chunk():
        end = f.tell()
        f.seek(start)
        f.write(struct.pack(">I", end - start - 8))
        f.seek(end)
        f.write(struct.pack(">I", crc))

    for part in compressed_parts(color):
        view = memoryview(part)
        while len(view):
            if start is None or size == limit:
                if start is not None:
                    close_chunk()
                open_chunk()
            piece, view = view[: limit - size], view[limit - size:]
            f.write(piece)
            crc, size = zlib.crc32(piece, crc), size + len(piece)
    if start is None:  # an empty stream is one empty chunk (zlib never makes one)
        open_chunk()
    close_chunk()
    return sequence


def write_png(f, color: np.ndarray) -> None:
    """The PNG file of :func:`rasterkit.image.encode_png`, byte for byte, written into the
    seekable binary file ``f`` with :data:`STREAM_BYTES` of memory besides the image."""
    f.write(SIGNATURE + header(color))
    write_chunks(f, color)
    f.write(chunk(b"IEND", b""))


def pieces(data: bytes, limit: int | None = None) -> list[bytes]:
    """``data`` cut into pieces of at most ``limit`` (default :data:`IDAT_BYTES`) bytes."""
    limit = limit or IDAT_BYTES
    return [data[k: k + limit] for k in range(0, len(data), limit)] or [b""]
