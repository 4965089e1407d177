"""sRGB and linear light: the exact sRGB transfer function (IEC 61966-2-1) both ways, and the
tables the sampling kernels decode texels with.

A texture's colours are sRGB-encoded, as image files store them; averaging them as they are
darkens every edge between a light and a dark colour (the mean of the codes 0 and 255 is 128,
which is 22 % light, not 50 %). So mipmaps are filtered, and the kernels blend texels, in
linear light: each 8-bit code is decoded through :data:`DECODE` (256 entries), blended, and
(for the mipmaps) encoded back with :func:`encode_srgb8`, rounding to the nearest code. Alpha
and the channels of textures that hold data, not colours (normal, specular and opacity
maps: ``srgb=False``), are linear already: code / 255.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DECODE", "LINEAR_ROW", "SRGB_ROW", "decode_srgb", "encode_srgb", "encode_srgb8"]


def decode_srgb(c: np.ndarray) -> np.ndarray:
    """Linear light (float64) of sRGB-encoded values ``c`` in [0, 1]."""
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def encode_srgb(linear: np.ndarray) -> np.ndarray:
    """sRGB-encoded values in [0, 1] of linear-light values (float, clipped to [0, 1]; the
    result has their float type)."""
    x = np.clip(linear, 0.0, 1.0)
    with np.errstate(invalid="ignore"):  # the unused branch of np.where
        return np.where(x <= 0.0031308, 12.92 * x, np.where(x >= 1.0, 1.0, 1.055 * x ** (1 / 2.4) - 0.055))


def encode_srgb8(linear: np.ndarray) -> np.ndarray:
    """The nearest 8-bit sRGB code (uint8) of each linear-light value (float, clipped to
    [0, 1]): ``floor(255 * encode(x) + 0.5)``."""
    return np.floor(encode_srgb(linear) * 255.0 + 0.5).astype(np.uint8)


#: Row of :data:`DECODE` for linear values (alpha, data textures): code / 255.
LINEAR_ROW = 0
#: Row of :data:`DECODE` for sRGB-encoded colours.
SRGB_ROW = 1

DECODE = np.stack([np.arange(256) / 255.0, decode_srgb(np.arange(256) / 255.0)])
"""(2, 256) float64: the value in [0, 1] of each 8-bit code, linear (row :data:`LINEAR_ROW`)
or decoded from sRGB (row :data:`SRGB_ROW`). Read-only."""
DECODE.flags.writeable = False
