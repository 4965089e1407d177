"""Image files: PNG, and animated GIF and APNG streamed frame by frame, written atomically.

Every writer goes through :func:`atomic_write` (:mod:`rasterkit.image.atomic`): the image is
written to a temporary file in the destination's folder and renamed over the destination
only when it is complete, so a failure never leaves a half-written file nor replaces a good
one. A new file gets the mode the umask gives (0644 under umask 022), a replaced file keeps
its mode, and an error names the destination, never the temporary file.

PNG is encoded here (:mod:`rasterkit.image.png`); animations are written one frame at a time
(:mod:`rasterkit.image.animation`), so their memory does not grow with the number of frames.
"""

from __future__ import annotations

import math
import numbers
import os
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np
from PIL import Image

from rasterkit.image import animation as _animation
from rasterkit.image import png as _png
from rasterkit.image.atomic import atomic_write

__all__ = ["to_pil", "encode_png", "save_image", "save_animation", "save_npy", "atomic_write"]

#: zlib level of PNG files (see :mod:`rasterkit.image.png`).
PNG_COMPRESS_LEVEL = _png.PNG_COMPRESS_LEVEL

_IDAT_BYTES = _png.IDAT_BYTES


def _colour(color) -> np.ndarray:
    """``color`` as a uint8 (H, W, 3) RGB or (H, W, 4) RGBA array with pixels, or ValueError."""
    color = np.asarray(color)
    if color.dtype != np.uint8 or color.ndim != 3 or color.shape[2] not in (3, 4) or 0 in color.shape:
        raise ValueError(f"colour must be uint8 (H, W, 3|4), got {color.dtype} {color.shape}")
    return color


def to_pil(color: np.ndarray) -> Image.Image:
    """A Pillow image of a uint8 (H, W, 3) RGB or (H, W, 4) RGBA array."""
    color = _colour(color)
    return Image.fromarray(np.ascontiguousarray(color), "RGBA" if color.shape[2] == 4 else "RGB")


def _format(path: Path, allowed: Sequence[str]) -> str:
    ext = path.suffix.lower().lstrip(".")
    fmt = {"png": "PNG", "gif": "GIF", "apng": "PNG"}.get(ext)
    if fmt is None or ext not in allowed:
        raise ValueError(f"{path}: unsupported image extension {path.suffix!r} "
                         f"(use {', '.join('.' + a for a in allowed)})")
    return fmt


def encode_png(color: np.ndarray) -> bytes:
    """The PNG file of a uint8 (H, W, 3) RGB or (H, W, 4) RGBA array: 8 bits per channel,
    no interlacing, filter type 0 (none) on every row, one zlib stream at
    :data:`PNG_COMPRESS_LEVEL`."""
    color = _colour(color)
    # a chunk holds less than 2**31 bytes: a huge image's stream goes in several IDAT chunks
    idat = b"".join(_png.chunk(b"IDAT", p) for p in _png.pieces(_png.compressed(color), _IDAT_BYTES))
    return _png.SIGNATURE + _png.header(color) + idat + _png.chunk(b"IEND", b"")


def save_image(color: np.ndarray, path: str | os.PathLike) -> None:
    """Write one image as PNG (the only still format), atomically."""
    _format(Path(path), ("png",))  # ``path`` itself goes on: "x.png/" names a folder, not x.png
    color = _colour(color)
    with atomic_write(path) as tmp:
        with open(tmp, "wb") as f:  # encode_png's bytes, streamed: no copy of the stream in memory
            _png.write_png(f, color)


class _Chunks:
    """A file that NumPy writes through ``write`` (16 MiB at a time), not ``ndarray.tofile``:
    a short write then raises the system's error (``No space left on device``) instead of
    NumPy's ``N requested and M written``."""

    def __init__(self, f):
        self._f = f

    def write(self, data) -> int:
        return self._f.write(data)


def save_npy(array: np.ndarray, path: str | os.PathLike) -> None:
    """Write ``array`` as a ``.npy`` file, atomically."""
    with atomic_write(path) as tmp:
        with open(tmp, "wb") as f:
            np.save(_Chunks(f), np.asarray(array), allow_pickle=False)


#: The longest a frame can be shown: 655.35 s (a GIF counts hundredths of a second in 16 bits).
MIN_FPS = 1000.0 / 655350


def save_animation(frames: Iterable[np.ndarray], path: str | os.PathLike, fps: float = 25.0) -> None:
    """Write frames as an endlessly looping animated GIF (``.gif``) or APNG (``.png``/``.apng``).

    ``frames`` is any iterable of uint8 (H, W, 3|4) arrays of one shape (a list, or a
    generator that renders them one by one): each frame is encoded and written as it comes,
    so memory does not grow with their number. Each is shown ``round(1000 / fps)``
    milliseconds (a GIF keeps whole hundredths); a frame identical to the one before is not
    stored again, the one before is shown longer. Written atomically: if a frame fails, or
    there is none, nothing is written.
    """
    fmt = _format(Path(path), ("gif", "png", "apng"))
    if isinstance(fps, bool) or not isinstance(fps, numbers.Real) or not math.isfinite(fps) or fps < MIN_FPS:
        raise ValueError(f"fps must be a number of at least {MIN_FPS:.3g}, got {fps!r}")
    duration = int(round(1000.0 / fps))
    write = _animation.write_gif if fmt == "GIF" else _animation.write_apng
    with atomic_write(path) as tmp:
        with open(tmp, "wb") as f:
            write((_colour(frame) for frame in frames), f, duration)
