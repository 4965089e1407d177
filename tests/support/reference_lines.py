"""Slow, obviously-correct pure-Python references for the line kernels.

Nothing here is fast or clever: exact rational arithmetic (``Fraction``) for the integer
lines, the clipping and the depths, and a plain loop over every column (or row) of the image
where the kernels clip in closed form. Only Wu's anti-aliasing weights are computed in
floating point, from the exact clipped ends; the tests compare those with a tolerance.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from rasterkit.raster.kernels.segments import MAX_COORDINATE
from rasterkit.raster.kernels.segments import SEGMENT_GUARD_BAND as GUARD_BAND
from rasterkit.raster.kernels.edges import MODE_ANTIALIAS, MODE_DEPTH_TEST

# A depth or slope closer than this to a decision boundary may land on either side of it.
TOLERANCE = 1e-6


def round_half_up(value: Fraction) -> int:
    """The integer nearest to ``value``; exact halves go up."""
    return math.floor(value + Fraction(1, 2))


def line_point(x0: int, y0: int, x1: int, y1: int, t: int) -> tuple[int, int]:
    """Pixel ``t`` of the integer line: the exact point ``t / n`` of the way, rounded half up.

    ``n = max(|dx|, |dy|)``, so one coordinate of the exact point is already an integer.
    """
    n = max(abs(x1 - x0), abs(y1 - y0))
    if n == 0:
        return x0, y0
    return round_half_up(x0 + Fraction((x1 - x0) * t, n)), round_half_up(y0 + Fraction((y1 - y0) * t, n))


def reference_line(x0: int, y0: int, x1: int, y1: int) -> list[tuple[int, int]]:
    """All pixels of the integer line from (x0, y0) to (x1, y1), in drawing order."""
    n = max(abs(x1 - x0), abs(y1 - y0))
    return [line_point(x0, y0, x1, y1, t) for t in range(n + 1)]


def line_in_image(x0: int, y0: int, x1: int, y1: int, width: int, height: int) -> list[tuple[int, int]]:
    """The pixels of the (possibly huge) integer line that lie in a width x height image.

    Tries every major-axis coordinate of the image instead of every step of the line.
    """
    dx, dy = x1 - x0, y1 - y0
    n = max(abs(dx), abs(dy))
    if n == 0:
        steps = [0]
    elif abs(dx) >= abs(dy):
        steps = [(x - x0) * (1 if dx > 0 else -1) for x in range(width)]
    else:
        steps = [(y - y0) * (1 if dy > 0 else -1) for y in range(height)]
    pixels = [line_point(x0, y0, x1, y1, t) for t in steps if 0 <= t <= n]
    return [(x, y) for x, y in pixels if 0 <= x < width and 0 <= y < height]


def clip_edge(p, q):
    """Clip a homogeneous segment exactly, then divide.

    Keeps ``0 <= zh <= w`` and ``|xh|, |yh| <= GUARD_BAND * w`` (Liang-Barsky in rational
    arithmetic). Returns ``None`` when nothing is left, else ``(a, b, moved)``: the exact
    raster-space ends ``(x, y, z)`` and, per end, whether it differs from the input vertex.
    """
    kept = _clip_homogeneous(p, q)
    if kept is None:
        return None
    a, b, moved = kept
    if not (a[3] > 0 and b[3] > 0):
        return None
    return tuple(c / a[3] for c in a[:3]), tuple(c / b[3] for c in b[:3]), moved


def _clip_homogeneous(p, q):
    """The Liang-Barsky part of :func:`clip_edge`: ``(a, b, moved)`` with the ends still
    homogeneous (exact), or None."""
    p, q = [Fraction(c) for c in p], [Fraction(c) for c in q]
    g = Fraction(GUARD_BAND)

    def distances(v):
        xh, yh, zh, w = v
        return [zh, w - zh, g * w + xh, g * w - xh, g * w + yh, g * w - yh]

    t0, t1 = Fraction(0), Fraction(1)
    for d0, d1 in zip(distances(p), distances(q)):
        if d0 < 0 and d1 < 0:
            return None
        if d0 < 0:
            t0 = max(t0, d0 / (d0 - d1))
        elif d1 < 0:
            t1 = min(t1, d0 / (d0 - d1))
    if t0 > t1:
        return None
    a = [pi + t0 * (qi - pi) for pi, qi in zip(p, q)]
    b = [pi + t1 * (qi - pi) for pi, qi in zip(p, q)]
    return a, b, (t0 > 0, t1 < 1)


def is_usable(v) -> bool:
    return all(abs(float(c)) <= MAX_COORDINATE for c in v)


def depth_along(a, b, major: int, m):
    """Depth of segment a-b at the centre of major coordinate ``m`` (axis index ``major``)."""
    lo, hi = a[major], b[major]
    if hi < lo:
        a, b, lo, hi = b, a, hi, lo
    if hi == lo:
        return a[2]
    s = min(max((m + Fraction(1, 2) - lo) / (hi - lo), 0), 1)
    return a[2] + s * (b[2] - a[2])


class Target:
    """A colour buffer being drawn into, with the depth buffer it is tested against.

    ``uncertain`` marks pixels whose depth test was too close to call in floating point.
    """

    def __init__(self, color, depth, rgba, depth_test, bias):
        self.color, self.depth, self.rgba = color, depth, [int(c) for c in rgba]
        self.depth_test, self.bias = depth_test, bias
        self.uncertain = np.zeros(depth.shape, dtype=bool)

    def passes(self, x, y, z) -> bool:
        if not self.depth_test:
            return True
        margin = float(z) - self.bias - float(self.depth[y, x])
        if abs(margin) < TOLERANCE:
            self.uncertain[y, x] = True
        return margin <= 0

    def blend(self, x, y, weight):
        for ch, src in enumerate(self.rgba):
            old = float(self.color[y, x, ch])
            self.color[y, x, ch] = int(old + (src - old) * weight + 0.5)


def draw_bresenham(target, a, b):
    """The integer line between the pixels containing the ends, depth at pixel centres."""
    height, width = target.depth.shape
    x0, y0, x1, y1 = math.floor(a[0]), math.floor(a[1]), math.floor(b[0]), math.floor(b[1])
    major = 1 if abs(y1 - y0) > abs(x1 - x0) else 0
    for x, y in line_in_image(x0, y0, x1, y1, width, height):
        if target.passes(x, y, depth_along(a, b, major, (x, y)[major])):
            target.color[y, x] = target.rgba


def draw_wu(target, a, b):
    """Xiaolin Wu: each major column's coverage split between the two nearest pixel centres."""
    a, b = [float(c) for c in a], [float(c) for c in b]
    height, width = target.depth.shape
    major = 1 if abs(b[1] - a[1]) > abs(b[0] - a[0]) else 0
    minor = 1 - major
    if b[major] < a[major]:
        a, b = b, a
    if b[major] == a[major]:
        return
    size_major, size_minor = (width, height) if major == 0 else (height, width)
    slope = (b[minor] - a[minor]) / (b[major] - a[major])
    for m in range(size_major):
        coverage = min(b[major], m + 1.0) - max(a[major], float(m))
        if coverage <= 0:
            continue
        below = a[minor] + (m + 0.5 - a[major]) * slope - 0.5
        j = math.floor(below)
        frac = below - j
        z = depth_along(a, b, major, m)
        for k, weight in ((j, 1.0 - frac), (j + 1, frac)):
            if 0 <= k < size_minor:
                x, y = (m, k) if major == 0 else (k, m)
                if target.passes(x, y, z):
                    target.blend(x, y, coverage * weight)


def reference_draw_edges(color, depth, clip, edges, rgba, mode, bias):
    """What ``draw_edges`` should do, one edge at a time.

    Returns ``(color, dropped, uncertain)``: the new colour buffer, the number of edges with
    unusable vertices, and the (H, W) bool mask of pixels whose depth test was a near tie.
    """
    target = Target(color.copy(), depth, rgba, bool(mode & MODE_DEPTH_TEST), bias)
    draw = draw_wu if mode & MODE_ANTIALIAS else draw_bresenham
    dropped = 0
    for i, j in edges:
        if not (is_usable(clip[i]) and is_usable(clip[j])):
            dropped += 1
            continue
        clipped = clip_edge(clip[i], clip[j])
        if clipped is not None:
            draw(target, clipped[0], clipped[1])
    return target.color, dropped, target.uncertain


def _near_integer(value) -> bool:
    """Within float64 rounding (generously: 1e-9 relative) of a pixel boundary."""
    return abs(value - round(value)) < 1e-9 * max(1, abs(value))


def ambiguous_edge(p, q, antialias: bool = False) -> bool:
    """Whether float rounding in the kernel could legitimately change how this edge is drawn.

    The kernel divides and clips in floating point. An end that is neither an input vertex
    with ``w == 1`` (then ``x = xh`` exactly) nor clear of pixel boundaries may floor to a
    neighbouring pixel; with ``antialias``, a segment with ``|dx|`` almost equal to ``|dy|``
    may be stepped along the other axis by Wu's algorithm.
    """
    if not (is_usable(p) and is_usable(q)):
        return False
    kept = _clip_homogeneous(p, q)
    if kept is not None and (kept[0][3] == 0 or kept[1][3] == 0):
        # what is left reaches the eye's plane (w = 0), where the divide is undefined: all of
        # it may be one point (an end on the near plane at the eye's x, y), which the exact
        # clip drops and the kernel's float clip may keep as a pixel
        return True
    clipped = clip_edge(p, q)
    if clipped is None:
        return False
    a, b, moved = clipped
    for end, vertex, was_moved in ((a, p, moved[0]), (b, q, moved[1])):
        if (was_moved or vertex[3] != 1.0) and (_near_integer(end[0]) or _near_integer(end[1])):
            return True
    return antialias and abs(abs(b[0] - a[0]) - abs(b[1] - a[1])) < TOLERANCE
