"""Slow, plain references for the texture tests: OpenGL's texture lookup (nearest, linear,
linear-mipmap-linear; repeat, clamp to edge, mirrored repeat) as the GL specification words it,
one point at a time in Python floats, and the mipmap box filter as a mean over replicated
texels. Written from the specification, not from the kernels."""

from __future__ import annotations

import math

import numpy as np


def srgb_to_linear(code: int) -> float:
    """IEC 61966-2-1, from an 8-bit code."""
    c = code / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def linear_to_srgb(x: float) -> float:
    x = min(max(x, 0.0), 1.0)
    return 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055


def wrap(i: int, size: int, mode: str) -> int:
    """GL 4.6 section 8.14.2, on an integer texel coordinate."""
    if mode == "repeat":
        return i - size * math.floor(i / size)
    if mode == "clamp":
        return min(max(i, 0), size - 1)
    m = i - 2 * size * math.floor(i / (2 * size)) - size  # (i mod 2size) - size
    mirrored = m if m >= 0 else -(1 + m)
    return size - 1 - mirrored


class Reference:
    """A texture as the GL specification samples it: ``levels`` top-row-first images."""

    def __init__(self, levels: list, srgb: bool, filter: str, wrap: str, scale=(1.0, 1.0), offset=(0.0, 0.0)):
        self.levels = [np.asarray(level, np.int64) for level in levels]
        self.srgb, self.filter, self.wrap = srgb, filter, wrap
        self.scale, self.offset = scale, offset

    def texel(self, level: int, i: int, j: int) -> np.ndarray:
        """Texel (i, j) of a level, j counted from the bottom row, decoded."""
        image = self.levels[level]
        height, width, channels = image.shape
        codes = image[height - 1 - wrap(j, height, self.wrap), wrap(i, width, self.wrap)]
        colour = [srgb_to_linear(int(c)) if self.srgb else int(c) / 255.0 for c in codes[:3]]
        alpha = int(codes[3]) / 255.0 if channels == 4 else 1.0
        return np.array(colour + [alpha])

    def nearest(self, level: int, u: float, v: float) -> np.ndarray:
        height, width = self.levels[level].shape[:2]
        return self.texel(level, math.floor(u * width), math.floor(v * height))

    def linear(self, level: int, u: float, v: float) -> np.ndarray:
        height, width = self.levels[level].shape[:2]
        x, y = u * width - 0.5, v * height - 0.5
        i0, j0 = math.floor(x), math.floor(y)
        a, b = x - i0, y - j0
        return ((1 - a) * (1 - b) * self.texel(level, i0, j0) + a * (1 - b) * self.texel(level, i0 + 1, j0)
                + (1 - a) * b * self.texel(level, i0, j0 + 1) + a * b * self.texel(level, i0 + 1, j0 + 1))

    def sample(self, u: float, v: float, lod: float = 0.0) -> np.ndarray:
        u = u * self.scale[0] + self.offset[0]
        v = v * self.scale[1] + self.offset[1]
        if self.filter == "nearest":
            return self.nearest(0, u, v)
        if self.filter == "bilinear":
            return self.linear(0, u, v)
        lod = min(max(0.0 if math.isnan(lod) else lod, 0.0), len(self.levels) - 1.0)
        d = math.floor(lod)
        f = lod - d
        low = self.linear(d, u, v)
        if f == 0.0:
            return low
        return (1 - f) * low + f * self.linear(d + 1, u, v)


def box_mean(linear: np.ndarray, width: int, height: int) -> np.ndarray:
    """The area-weighted mean of ``linear`` (h, w, C) float over ``height`` x ``width``
    equal cells: each texel replicated ``height`` x ``width`` times, then blocks of h x w
    averaged (exact up to float rounding)."""
    h, w, _ = linear.shape
    fine = np.repeat(np.repeat(linear, height, axis=0), width, axis=1)
    return fine.reshape(height, h, width, w, -1).mean(axis=(1, 3))
