"""Mipmaps: a texture and its reductions down to 1x1, in one flat buffer.

The chain is built once per texture (:attr:`rasterkit.Texture.mipmaps`, on first use) and
kept with it, so every frame and every mesh that draws the texture shares it.

Level sizes are OpenGL's: level ``k + 1`` is ``max(1, width // 2) x max(1, height // 2)`` of
level ``k``, down to 1x1 (``floor(log2(max(width, height))) + 1`` levels), so that a level of
detail means the same texel size as on a GPU.

Each level is made from the one before by a box filter in linear light: an output texel is
the mean of the part of the previous level that it covers. When a side is even that is the
mean of 2 texels along it (a 2x2 box for the texel); when it is odd (5 texels into 2) each
output texel covers 2.5 input texels, the middle one shared half and half: weights (1, 1,
0.5) and (0.5, 1, 1), three taps at most along each axis, every input texel counted with
the same total weight. So an odd side neither drops its last row or column nor shifts the
image, and the result does not depend on which way up the rows are. sRGB colours are decoded
exactly (:mod:`rasterkit.material.colorspace`), averaged and encoded back to the nearest
8-bit code; alpha and data textures (``srgb=False``) are averaged as they are, and rounded
(half up). Every level is made from the previous level's rounded texels, so each level is
exactly what :func:`reduce_level` makes of the one before.

Layout (what the sampling kernels read): ``texels`` (n,) uint8 holds every level, rows top
first as in the image (the kernels count OpenGL's texel rows, ``v`` upwards, from the last
row), texels of a row left to right, ``channels`` bytes each; ``levels`` (L, 3) int64 holds
each level's offset into ``texels``, width and height. Level 0 is the image itself: once the
chain is built, :attr:`rasterkit.Texture.image` is a view of it, so a texture and its
mipmaps hold the image's bytes once. Memory: the levels add at most a third to the image,
plus about two rows' worth for strips (a side of 1 stops halving): ``(4/3) * W * H * C + 2 *
max(W, H) * C`` bytes at most; 1.33x for a 1024x1024 texture.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.limits import check_memory
from rasterkit.material.colorspace import DECODE, SRGB_ROW, encode_srgb8

__all__ = ["Mipmaps", "box_taps", "build_mipmaps", "level_sizes", "mipmaps_bytes", "reduce_level"]

#: Values (float64) of one block of a level decoded at once while reducing it: bounds the
#: working memory to about 64 MiB whatever the texture's size.
_BLOCK_VALUES = 1 << 21


@dataclass(frozen=True, eq=False)
class Mipmaps:
    """Every level of a texture in one buffer (see the module documentation for the layout).

    Attributes
    ----------
    texels : (n,) uint8
        Every level, level 0 first; rows top first. Read-only.
    levels : (L, 3) int64
        Per level: offset into ``texels``, width, height. Read-only.
    channels : int
        3 (RGB) or 4 (RGBA).
    srgb : bool
        Whether the colours were filtered in linear light (decoded from sRGB).
    """

    texels: np.ndarray
    levels: np.ndarray
    channels: int
    srgb: bool

    @property
    def nbytes(self) -> int:
        return int(self.texels.nbytes + self.levels.nbytes)

    def level(self, k: int) -> np.ndarray:
        """Level ``k`` as an image (h, w, channels) uint8, row 0 at the top (a view)."""
        offset, width, height = (int(x) for x in self.levels[k])
        size = width * height * self.channels
        return self.texels[offset:offset + size].reshape(height, width, self.channels)

    def check_intact(self) -> None:
        """Raise ``ValueError`` when the arrays' shape, dtype or layout changed since they
        were built (NumPy lets anyone set ``shape`` in place): the kernels trust them."""
        offset, width, height = self.levels[-1]
        ok = (self.texels.dtype == np.uint8 and self.texels.ndim == 1 and self.texels.flags.c_contiguous
              and self.levels.dtype == np.int64 and self.levels.ndim == 2 and self.levels.shape[1] == 3
              and self.levels.flags.c_contiguous and offset + width * height * self.channels == len(self.texels))
        if not ok:
            raise ValueError("a texture's mipmaps were changed in place: make a new Texture")


def level_sizes(width: int, height: int) -> list[tuple[int, int]]:
    """``[(width, height), ...]`` of every level, down to (1, 1)."""
    sizes = [(int(width), int(height))]
    while sizes[-1] != (1, 1):
        w, h = sizes[-1]
        sizes.append((max(1, w // 2), max(1, h // 2)))
    return sizes


def mipmaps_bytes(width: int, height: int, channels: int) -> int:
    """Bytes of the mipmaps of a ``width`` x ``height`` texture, and the working memory of
    building them (the largest level decoded in blocks: :data:`_BLOCK_VALUES`)."""
    texels = sum(w * h for w, h in level_sizes(width, height)) * channels
    return texels + min(width * height * channels, _BLOCK_VALUES) * 8 * 3


def box_taps(n_in: int, n_out: int) -> tuple[np.ndarray, np.ndarray]:
    """The box filter from ``n_in`` texels to ``n_out`` (``n_in // 2`` or 1) along one axis:
    ``(index, weight)``, each (n_out, 3): output texel ``i`` is the sum of ``weight[i, k] *
    input[index[i, k]]``; its weights (the parts of input texels that its footprint
    ``[i * n_in / n_out, (i + 1) * n_in / n_out)`` covers, over the footprint's length) add up
    to 1. For an even ``n_in`` they are (0.5, 0.5, 0)."""
    step = n_in / n_out
    lo = np.arange(n_out) * step
    hi = lo + step
    first = np.floor(lo).astype(np.int64)
    index = first[:, None] + np.arange(3)
    overlap = np.minimum(hi[:, None], index + 1) - np.maximum(lo[:, None], index)
    weight = np.maximum(overlap, 0.0) / step
    return np.minimum(index, n_in - 1), weight


def reduce_level(level: np.ndarray, width: int, height: int, srgb: bool) -> np.ndarray:
    """The next level (height, width, C) uint8 of ``level`` (h, w, C) uint8 (rows in either
    order: the filter is symmetric), by the box filter of :func:`box_taps` in linear light."""
    h, w, channels = level.shape
    ix, wx = box_taps(w, width)
    iy, wy = box_taps(h, height)
    out = np.empty((height, width, channels), np.uint8)
    colour = min(channels, 3)
    step = max(1, _BLOCK_VALUES // (3 * w * channels))  # output rows per block
    for r0 in range(0, height, step):
        r1 = min(height, r0 + step)
        top, bottom = int(iy[r0, 0]), int(iy[r1 - 1].max()) + 1
        block = level[top:bottom]
        linear = np.empty(block.shape, np.float64)
        # colours decoded to linear light (0..1); alpha and data kept as codes (0..255), so
        # that their sums, and a mean of 2 or 4, are exact
        linear[..., :colour] = DECODE[SRGB_ROW][block[..., :colour]] if srgb else block[..., :colour]
        linear[..., colour:] = block[..., colour:]
        across = linear[:, ix[:, 0]] * wx[:, 0, None] + linear[:, ix[:, 1]] * wx[:, 1, None] \
            + linear[:, ix[:, 2]] * wx[:, 2, None]
        rows = iy[r0:r1] - top
        mean = across[rows[:, 0]] * wy[r0:r1, 0, None, None] + across[rows[:, 1]] * wy[r0:r1, 1, None, None] \
            + across[rows[:, 2]] * wy[r0:r1, 2, None, None]
        if srgb:
            out[r0:r1, :, :colour] = encode_srgb8(mean[..., :colour])
            out[r0:r1, :, colour:] = np.floor(mean[..., colour:] + 0.5)
        else:
            out[r0:r1] = np.floor(mean + 0.5)
    return out


def build_mipmaps(image: np.ndarray, srgb: bool) -> Mipmaps:
    """The mipmaps of ``image`` (H, W, 3|4) uint8, row 0 at the top."""
    height, width, channels = image.shape
    check_memory(mipmaps_bytes(width, height, channels), f"the mipmaps of a {width}x{height} texture")
    sizes = level_sizes(width, height)
    counts = [w * h * channels for w, h in sizes]
    offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    texels = np.empty(int(offsets[-1]), np.uint8)
    level = texels[:counts[0]].reshape(height, width, channels)
    level[:] = image
    for k, (w, h) in enumerate(sizes[1:], start=1):
        reduced = texels[offsets[k]:offsets[k + 1]].reshape(h, w, channels)
        reduced[:] = reduce_level(level, w, h, srgb)
        level = reduced
    texels = np.frombuffer(texels.tobytes(), np.uint8)  # immutable: a view of bytes, as a Mesh's arrays
    table = np.array([(offsets[k], w, h) for k, (w, h) in enumerate(sizes)], np.int64).reshape(-1, 3)
    levels = np.frombuffer(table.tobytes(), np.int64).reshape(table.shape)
    return Mipmaps(texels, levels, channels, bool(srgb))
