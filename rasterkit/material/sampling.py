"""The sampling kernels' arguments for a set of textures, and :func:`sample`, the lookup of
points from Python (one thread; for tests, tools and the texture-space work of a caller).

A draw hands the kernels (:mod:`rasterkit.material.kernels.sample`) one :class:`TextureArgs`
for all its textures: one texture's mipmaps are used as they are, with no copy; several are
put in one buffer (their levels and samplers one after the other), which a caller that
draws them often makes once and keeps.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.material.colorspace import DECODE
from rasterkit.material.kernels.sample import (
    FILTER, FILTER_BILINEAR, FILTER_NEAREST, FILTER_TRILINEAR, WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT, sample_points,
)

__all__ = ["FILTER_CODES", "TextureArgs", "WRAP_CODES", "sample", "texture_args", "with_filter"]

#: The kernels' code of each filter and wrap name.
FILTER_CODES = {"nearest": FILTER_NEAREST, "bilinear": FILTER_BILINEAR, "trilinear": FILTER_TRILINEAR}
WRAP_CODES = {"repeat": WRAP_REPEAT, "clamp": WRAP_CLAMP, "mirror": WRAP_MIRROR}


class TextureArgs(NamedTuple):
    """The arrays of :mod:`rasterkit.material.kernels.sample` for textures 0..T-1: ``texels``
    (n,) uint8, ``levels`` (L, 3) int64, ``samplers`` (T, 6) int64, ``transforms`` (T, 4)
    float64, ``decode`` (2, 256) float64. All read-only."""

    texels: np.ndarray
    levels: np.ndarray
    samplers: np.ndarray
    transforms: np.ndarray
    decode: np.ndarray


def _readonly(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def texture_args(textures) -> TextureArgs:
    """The kernels' arguments for the :class:`~rasterkit.Texture` objects ``textures`` (a
    sequence; texture ``t`` is ``textures[t]``). Builds each one's mipmaps on first use."""
    textures = list(textures)
    if not textures:
        raise ValueError("texture_args needs at least one texture")
    chains = [texture.mipmaps for texture in textures]
    for chain in chains:
        chain.check_intact()
    if len(chains) == 1:
        texels, levels = chains[0].texels, chains[0].levels
    else:
        texels = _readonly(np.concatenate([c.texels for c in chains]))
        starts = np.cumsum([0] + [len(c.texels) for c in chains[:-1]])
        levels = _readonly(np.concatenate([c.levels + [start, 0, 0] for c, start in zip(chains, starts)]))
    firsts = np.cumsum([0] + [len(c.levels) for c in chains[:-1]])
    samplers = np.array([(first, len(c.levels), c.channels, FILTER_CODES[t.filter], WRAP_CODES[t.wrap], int(c.srgb))
                         for t, c, first in zip(textures, chains, firsts)], np.int64)
    transforms = np.array([(*t.scale, *t.offset) for t in textures], np.float64)
    return TextureArgs(texels, levels, _readonly(samplers), _readonly(transforms), DECODE)


def with_filter(args: TextureArgs, filter: str) -> TextureArgs:
    """``args`` with every texture filtered by ``filter`` (a name of :data:`FILTER_CODES`)."""
    samplers = np.array(args.samplers)
    samplers[:, FILTER] = FILTER_CODES[filter]
    return args._replace(samplers=_readonly(samplers))


def sample(texture, uv, lod=0.0) -> np.ndarray:
    """Look ``texture`` up at the points ``uv`` (N, 2) (u right, v up: see
    :class:`~rasterkit.Texture`) with levels of detail ``lod`` (a number or (N,); only the
    ``trilinear`` filter uses it). Returns (N, 4) float32 RGBA: linear light for an sRGB
    texture, alpha 1 for an RGB one. NaN and infinite coordinates are allowed (they wrap as
    the kernels say)."""
    uv = np.ascontiguousarray(real_array(uv, "uv"), np.float64)
    if uv.ndim != 2 or uv.shape[1] != 2:
        raise ValueError(f"uv must have shape (N, 2), got {uv.shape}")
    lod = real_array(lod, "lod")
    if lod.shape not in ((), (len(uv),)):
        raise ValueError(f"lod must be a number or have shape ({len(uv)},), got {lod.shape}")
    lod = np.ascontiguousarray(np.broadcast_to(lod, (len(uv),)))
    args = texture_args([texture])
    out = np.empty((len(uv), 4), np.float32)
    sample_points(*args, 0, uv, lod, out)
    return out
