"""Thumbnails of the images a batch wrote, read in bounded memory and without Pillow's
decompression-bomb limit.

A batch's images are rasterkit's own files, however large: Pillow's ``Image.open`` would
refuse one of more than 2 x ``PIL.Image.MAX_IMAGE_PIXELS`` pixels
(``DecompressionBombError``), warn above it, and decode the whole image before shrinking
it. Here a PNG (or the first frame of an APNG) as rasterkit writes them (8-bit RGB or RGBA,
not interlaced, no row filter) is decompressed a few rows at a time, each block of
``kx x ky`` pixels averaged as it passes (the factors Pillow's ``thumbnail`` reduces by
before its last resampling, which is then Pillow's): the memory is a few rows, whatever
the image's size. Any other PNG, and
a GIF's first frame, is decoded by Pillow's format reader itself, which has no limit of
its own (``Image.open`` is what checks it), after :func:`rasterkit.limits.check_memory`
(a GIF is rewritten without its frame's disposal, which Pillow checks too), and shrunk by
Pillow's ``thumbnail``. Nothing global is changed: other threads keep Pillow's limit.
"""

from __future__ import annotations

import io
import math
import struct
import zlib
from pathlib import Path

import numpy as np

from rasterkit.image import png as _png

__all__ = ["thumbnail"]

_READ = 1 << 20  # compressed bytes read from the file at a time
_ROWS = 1 << 19  # bytes of rows decompressed at a time (summed as uint64: 4 MiB)


class _Blocks:
    """Averages of the ``kx x ky`` blocks of an image whose rows arrive in order, as
    Pillow's ``Image.reduce`` makes them (blocks at the right and bottom edges average the
    pixels they have; RGBA is averaged with its colours weighted by their alpha)."""

    def __init__(self, width: int, height: int, channels: int, factors: tuple[int, int]):
        self.kx, self.ky = factors
        self.width, self.height, self.channels = width, height, channels
        self.starts = np.arange(0, width, self.kx)
        self.sums = np.zeros(((height + self.ky - 1) // self.ky, len(self.starts), channels), np.uint64)
        self.y = 0

    def add(self, rows: np.ndarray) -> None:
        """``rows``: (n, width, channels) uint8, the next n rows."""
        if self.channels == 4:  # colour weighted by alpha, then alpha
            weighted = rows[..., :3].astype(np.uint16) * rows[..., 3:]
            columns = np.concatenate([np.add.reduceat(weighted, self.starts, axis=1, dtype=np.uint64),
                                      np.add.reduceat(rows[..., 3:], self.starts, axis=1, dtype=np.uint64)], axis=2)
        else:
            columns = np.add.reduceat(rows, self.starts, axis=1, dtype=np.uint64)
        np.add.at(self.sums, (self.y + np.arange(len(rows))) // self.ky, columns)
        self.y += len(rows)

    def image(self) -> np.ndarray:
        """The (H/ky, W/kx, channels) uint8 averages, rounded."""
        rows = np.minimum(self.ky, self.height - np.arange(len(self.sums)) * self.ky)
        columns = np.minimum(self.kx, self.width - self.starts)
        counts = (rows[:, None] * columns[None, :]).astype(np.uint64)[..., None]
        if self.channels == 3:
            return ((self.sums + counts // 2) // counts).astype(np.uint8)
        alpha = self.sums[..., 3:]
        colour = (self.sums[..., :3] + alpha // 2) // np.maximum(alpha, 1)
        return np.concatenate([colour, (alpha + counts // 2) // counts], axis=2).astype(np.uint8)


def fitted_size(width: int, height: int, cell: int) -> tuple[int, int]:
    """The size ``Image.thumbnail((cell, cell))`` gives a ``width x height`` image: scaled
    to fit, the aspect ratio kept as closely as whole pixels allow, never enlarged."""
    if cell >= width and cell >= height:
        return width, height
    aspect = width / height

    def nearest(number: float, key) -> int:
        return max(min(math.floor(number), math.ceil(number), key=key), 1)

    if 1 >= aspect:
        return nearest(cell * aspect, key=lambda n: abs(aspect - n / cell)), cell
    return cell, nearest(cell / aspect, key=lambda n: 0 if n == 0 else abs(aspect - cell / n))


def _factors(width: int, height: int, size: tuple[int, int]) -> tuple[int, int]:
    """The box factors Pillow's resize shrinks by before resampling (``reducing_gap=2``)."""
    return max(1, int(width / size[0] / 2)), max(1, int(height / size[1] / 2))


def _chunks(f):
    """``(tag, length)`` of each chunk of a PNG file after its signature; ``f`` is left at
    the chunk's data (the caller reads or skips it, then the 4-byte CRC)."""
    while True:
        head = f.read(8)
        if len(head) < 8:
            raise ValueError("the PNG file ends early")
        yield struct.unpack(">I4s", head)[::-1]


def _read_png(f, cell: int):
    """``(pixels reduced by _factors, width, height)`` of a PNG as rasterkit writes it (its
    first frame for an APNG), or None for any other PNG."""
    if f.read(8) != _png.SIGNATURE:
        return None
    chunks = _chunks(f)
    tag, length = next(chunks)
    header = f.read(length)
    if tag != b"IHDR" or len(header) != 13:
        return None
    width, height, depth, kind, _, _, interlace = struct.unpack(">IIBBBBB", header)
    if depth != 8 or kind not in (2, 6) or interlace or not width or not height:
        return None
    f.read(4)
    channels = 3 if kind == 2 else 4
    blocks = _Blocks(width, height, channels, _factors(width, height, fitted_size(width, height, cell)))
    stride = 1 + width * channels
    most = max(1, _ROWS // stride) * stride  # bytes of rows decompressed at a time
    stream = zlib.decompressobj()
    pending = bytearray()
    for tag, length in chunks:
        if tag == b"IEND" or (tag != b"IDAT" and blocks.y):
            break  # the first frame's IDAT chunks are behind us
        if tag != b"IDAT":
            f.seek(length + 4, io.SEEK_CUR)
            continue
        left = length
        while left and blocks.y < height:
            data = f.read(min(left, _READ))
            if not data:
                raise ValueError("the PNG file ends early")
            left -= len(data)
            more = True
            while (data or more) and blocks.y < height:
                out = stream.decompress(data, most - len(pending))
                data, more = stream.unconsumed_tail, len(out) == most - len(pending)
                pending += out
                n = min(len(pending) // stride, height - blocks.y)
                if n:
                    rows = np.frombuffer(bytes(pending[: n * stride]), np.uint8).reshape(n, stride)
                    del pending[: n * stride]
                    if rows[:, 0].any():
                        return None  # row filters: not one of ours
                    blocks.add(rows[:, 1:].reshape(n, width, channels))
        f.seek(left + 4, io.SEEK_CUR)
    if blocks.y < height:
        raise ValueError("the PNG file ends before its last row")
    return blocks.image(), width, height


def _first_gif_frame(data: bytes) -> bytes:
    """A GIF of ``data``'s first frame alone, its disposal method cleared."""
    from rasterkit.image.animation import blocks_end

    out = bytearray(data[:13])
    pos = 13
    if data[10] & 0x80:
        pos += 3 << ((data[10] & 7) + 1)
        out += data[13:pos]
    while data[pos] == 0x21:  # extensions before the first image
        end = blocks_end(data, pos + 2)
        block = bytearray(data[pos:end])
        if block[1] == 0xF9:
            block[3] &= ~0x1C  # graphic control: no disposal
        out += block
        pos = end
    if data[pos] != 0x2C:
        raise ValueError("no image in the GIF file")
    flags = data[pos + 9]
    start, pos = pos, pos + 10 + ((3 << ((flags & 7) + 1)) if flags & 0x80 else 0)
    out += data[start: blocks_end(data, pos + 1)]
    return bytes(out + b";")


def _decoded(path: Path, head: bytes):
    """The image at ``path`` decoded by Pillow's reader of its format."""
    from PIL import GifImagePlugin, PngImagePlugin

    from rasterkit.limits import check_memory

    if head.startswith((b"GIF87a", b"GIF89a")):
        data = path.read_bytes()
        width, height = struct.unpack("<HH", data[6:10])
        check_memory(6 * width * height, f"the thumbnail of {path}")
        return GifImagePlugin.GifImageFile(io.BytesIO(_first_gif_frame(data)))
    if head == _png.SIGNATURE:
        image = PngImagePlugin.PngImageFile(str(path))
        check_memory(8 * image.width * image.height, f"the thumbnail of {path}")
        return image
    raise ValueError(f"{path}: not a PNG or GIF file")


def thumbnail(path: Path, cell: int):
    """A Pillow RGBA image of ``path`` shrunk to fit ``cell x cell`` (never enlarged), as
    ``Image.thumbnail`` makes it. Raises ``OSError`` or ``ValueError`` for a file that
    cannot be read."""
    path = Path(path)
    try:
        return _thumbnail(path, cell)
    except (zlib.error, struct.error, IndexError, EOFError) as e:  # a damaged file
        raise ValueError(f"{path}: not a readable image ({e})") from None


def _thumbnail(path: Path, cell: int):
    from PIL import Image

    with open(path, "rb") as f:
        head = f.read(8)
        f.seek(0)
        ours = _read_png(f, cell) if head == _png.SIGNATURE else None
    if ours is None:  # Pillow's own thumbnail: its resizing checks no size
        with _decoded(path, head) as decoded:
            decoded.load()
            image = decoded.convert("RGBA")
        image.thumbnail((cell, cell))
        return image
    pixels, width, height = ours
    size = fitted_size(width, height, cell)
    kx, ky = _factors(width, height, size)
    image = Image.fromarray(pixels, "RGBA" if pixels.shape[2] == 4 else "RGB").convert("RGBA")
    if image.size == size and (kx, ky) == (1, 1):
        return image
    return image.resize(size, Image.Resampling.BICUBIC, box=(0, 0, width / kx, height / ky))
