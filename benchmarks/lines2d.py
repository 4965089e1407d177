"""2D lines: a million random segments into an RGB image, rasterkit against 2D libraries.

Segments start anywhere in the image and run in a random direction for up to
:data:`MAX_LENGTH` pixels (ends clamped into the image, since skimage.draw.line does not
clip); endpoints are integer pixels. Every side clears its image to white and draws every
segment in black, one pixel wide, no anti-aliasing; the inputs are converted to each
library's preferred batch form beforehand (outside the timed region, as rasterkit's arrays
are built beforehand too).

rasterkit's side is ``rasterkit.draw.lines``, the batch form of ``rasterkit.draw.line``, which
runs the same kernel as the renderer's wireframes.

Peers: ``cv2.polylines`` given the whole list at once (OpenCV's batch form), a ``cv2.line``
loop, Pillow's ``ImageDraw.line`` in a loop (its image then viewed as NumPy) and
``skimage.draw.line`` in a loop, each line's pixels set through NumPy indexing.
"""

from __future__ import annotations

import numpy as np

from .compare import RASTERKIT, compare
from .peers import PeerUnavailable

FAMILY = "lines2d"
MAX_LENGTH = 50.0
"""Longest segment, pixels (lengths are uniform in [0, MAX_LENGTH])."""
REPEAT = 5
"""Timed runs at most: the Python-loop peers take seconds per run, and five is the minimum."""


def segments(count: int, width: int, height: int, seed: int = 3) -> np.ndarray:
    """(count, 2, 2) int32 integer endpoints ``[[x0, y0], [x1, y1]]`` inside the image."""
    rng = np.random.default_rng(seed)
    start = rng.uniform([0, 0], [width, height], (count, 2))
    angle = rng.uniform(0.0, 2 * np.pi, count)
    offset = np.stack([np.cos(angle), np.sin(angle)], axis=1) * rng.uniform(0, MAX_LENGTH, (count, 1))
    end = np.clip(start + offset, 0, [width - 1, height - 1])
    return np.floor(np.stack([start, end], axis=1)).astype(np.int32)


def rasterkit_side(segs: np.ndarray, width: int, height: int):
    """rasterkit: ``rasterkit.draw.lines``, the batch form of its Bresenham lines."""
    from rasterkit.draw import lines

    image = np.empty((height, width, 3), np.uint8)

    def draw():
        image.fill(255)
        return lines(image, segs, color="black")

    return draw


def cv2_polylines(peers, segs, width, height):
    cv2 = peers.module("cv2")
    image = np.empty((height, width, 3), np.uint8)
    curves = list(segs.reshape(-1, 2, 1, 2))

    def draw():
        image.fill(255)
        cv2.polylines(image, curves, False, (0, 0, 0), 1, cv2.LINE_8)
        return image

    return draw


def cv2_line_loop(peers, segs, width, height):
    cv2 = peers.module("cv2")
    image = np.empty((height, width, 3), np.uint8)
    ends = [(tuple(a), tuple(b)) for a, b in segs.tolist()]

    def draw():
        image.fill(255)
        for a, b in ends:
            cv2.line(image, a, b, (0, 0, 0), 1, cv2.LINE_8)
        return image

    return draw


def pillow_loop(peers, segs, width, height):
    from PIL import Image, ImageDraw  # Pillow is a dependency of rasterkit itself

    ends = [tuple(xy) for xy in segs.reshape(-1, 4).tolist()]

    def draw():
        image = Image.new("RGB", (width, height), (255, 255, 255))
        pen = ImageDraw.Draw(image)
        for xy in ends:
            pen.line(xy, fill=(0, 0, 0), width=1)
        return np.asarray(image)

    return draw


def skimage_loop(peers, segs, width, height):
    line = peers.module("skimage.draw").line
    image = np.empty((height, width, 3), np.uint8)
    ends = segs.reshape(-1, 4).tolist()

    def draw():
        image.fill(255)
        for x0, y0, x1, y1 in ends:
            image[line(y0, x0, y1, x1)] = 0
        return image

    return draw


PEERS = {"cv2.polylines": cv2_polylines, "cv2.line loop": cv2_line_loop,
         "Pillow ImageDraw.line loop": pillow_loop, "skimage.draw.line loop": skimage_loop}


def run(settings, results, peers) -> None:
    """``settings.segments`` segments into a ``settings.segment_size`` image, every side."""
    width, height = settings.segment_size
    segs = segments(settings.segments, width, height)
    sides = {RASTERKIT: rasterkit_side(segs, width, height)}
    for name, make in PEERS.items():
        try:
            sides[name] = make(peers, segs, width, height)
        except PeerUnavailable as reason:
            results.skip(FAMILY, name, str(reason))
    lengths = np.abs(segs[:, 1] - segs[:, 0]).max(axis=1) + 1
    compare(results, FAMILY, f"lines2d/{settings.segments}seg/{width}x{height}", sides,
            repeat=min(settings.repeat, REPEAT), warmup=min(settings.warmup, 1), work=float(settings.segments), unit="segment/s",
            sizes={"width": width, "height": height, "segments": settings.segments,
                   "pixels": int(lengths.sum())},
            note="rasterkit side: rasterkit.draw.lines")
