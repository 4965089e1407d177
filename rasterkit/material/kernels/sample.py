"""Texture sampling kernels: nearest, bilinear and trilinear lookups with repeat, clamp and
mirror wrapping, and the level of detail from UV derivatives, as OpenGL defines them.

Everything a lookup needs is a handful of arrays and scalars, so that a band worker calls
:func:`sample` per pixel (the arrays made once per texture by
:mod:`rasterkit.material.sampling`):

``texels`` (n,) uint8, ``levels`` (L, 3) int64
    Every mipmap level of every texture of a draw: a level's offset into ``texels``, its
    width and height; rows top first, as in the image (:mod:`rasterkit.material.mipmaps`):
    texel row ``j``, counted from the bottom as OpenGL's ``v`` grows, is row ``height - 1 - j``.
``samplers`` (T, 6) int64, ``transforms`` (T, 4) float64, row ``t`` for texture ``t``
    Its first level (a row of ``levels``), its level count, channels (3 or 4), filter
    (``FILTER_*``), wrap (``WRAP_*``) and whether its colours are sRGB; its ``scale`` (u, v)
    and ``offset`` (u, v).
``decode`` (2, 256) float64
    :data:`rasterkit.material.colorspace.DECODE`: each code's value, linear or from sRGB.

Coordinates are OpenGL's: ``u`` to the right, ``v`` up (``v = 0`` is the bottom of the image),
texel centres at ``(i + 0.5) / width``; the texture's ``scale`` and ``offset`` apply first,
``u * scale + offset``. A lookup returns ``(r, g, b, a)`` float32 in [0, 1]: linear light for
an sRGB texture (the texels are decoded, then blended; the caller encodes the shaded colour
back to sRGB once), the codes / 255 otherwise; alpha is linear, 1 for an RGB texture.

Filters (OpenGL's names): ``nearest`` is GL_NEAREST on level 0 (the texel that contains the
point), ``bilinear`` GL_LINEAR on level 0 (the 4 texels around the point, weighted by
distance from their centres), ``trilinear`` GL_LINEAR_MIPMAP_LINEAR: GL_LINEAR on levels
``floor(lod)`` and ``floor(lod) + 1`` blended by ``lod - floor(lod)``, the level of detail
clamped to ``[0, levels - 1]`` (so a magnified texture is GL_LINEAR on level 0).

Wrapping (applied to the integer texel indices, as GL does): ``repeat`` takes the index
modulo the size, ``clamp`` clamps it to the edge texels (GL_CLAMP_TO_EDGE), ``mirror`` repeats
the texture mirrored every other time (GL_MIRRORED_REPEAT). Before that, the coordinate is
brought into a bounded range that the wrap does not change (``repeat``: its fractional part;
``mirror``: modulo 2; ``clamp``: clamped to [-1, 2]), and NaN is taken as 0 (an infinity
too with ``repeat`` and ``mirror``, which have no edge to send it to; ``clamp`` sends it to
its edge): no input, however large or undefined, makes an index outside the texture.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.intrinsics import bits_float, float_bits
from rasterkit.runtime.jit import kernel

FILTER_NEAREST, FILTER_BILINEAR, FILTER_TRILINEAR = 0, 1, 2
WRAP_REPEAT, WRAP_CLAMP, WRAP_MIRROR = 0, 1, 2

#: Columns of a ``samplers`` row.
FIRST, COUNT, CHANNELS, FILTER, WRAP, SRGB = 0, 1, 2, 3, 4, 5
#: Columns of a ``transforms`` row.
SCALE_U, SCALE_V, OFFSET_U, OFFSET_V = 0, 1, 2, 3


@kernel(inline="always")
def bounded_coordinate(u, wrap):
    """``u`` in a range of a few units that ``wrap`` maps as it maps ``u``; NaN gives 0, and
    so do the infinities with repeat and mirror (their fractional part is NaN)."""
    if wrap == WRAP_REPEAT:
        u = u - np.floor(u)
    elif wrap == WRAP_MIRROR:
        u = u - 2.0 * np.floor(0.5 * u)
    elif u < -1.0:
        u = -1.0
    elif u > 2.0:
        u = 2.0
    if u != u:
        u = 0.0
    return u


@kernel(inline="always")
def wrap_index(i, n, wrap):
    """Texel index ``i`` wrapped into [0, n), for the indices that bounded coordinates
    (:func:`bounded_coordinate`) give on a level ``n`` texels wide and their right or upper
    neighbours: ``-1 .. n + 1`` for repeat, ``-1 .. 2n + 1`` for mirror, any for clamp. With
    selects, not a division."""
    if wrap == WRAP_REPEAT:
        i = i + n if i < 0 else i
        return i - n if i >= n else i
    if wrap == WRAP_MIRROR:
        i = -1 - i if i < 0 else i
        i = i - 2 * n if i >= 2 * n else i
        return 2 * n - 1 - i if i >= n else i
    return min(max(i, 0), n - 1)


@kernel(inline="always")
def texel(texels, decode, srgb, channels, at):
    """The texel at byte ``at`` (np.uint64): (r, g, b, a) float64, colours through row
    ``srgb`` (np.uint64) of ``decode``, alpha linear (1 without an alpha channel). Unsigned
    indices: Numba adds no wraparound of negative indices to the loads."""
    a = decode[np.uint64(0), texels[at + np.uint64(3)]] if channels == 4 else 1.0
    return (decode[srgb, texels[at]], decode[srgb, texels[at + np.uint64(1)]],
            decode[srgb, texels[at + np.uint64(2)]], a)


@kernel(inline="always")
def log2(x):
    """``log2(x)`` within 1e-15 of the exact value, inline (a call of the C library's log2
    in a pixel loop costs the spilling of every live float register around it): the binary
    exponent of ``x`` plus log2 of its significand ``m`` in [sqrt(1/2), sqrt(2)), from the
    series ``ln m = 2 (s + s^3 / 3 + s^5 / 5 + ...)``, ``s = (m - 1) / (m + 1)``, ``|s| <=
    0.172``, to its ``s^17`` term. ``-inf`` for 0, ``inf`` for ``inf``, NaN for NaN and
    negative ``x``."""
    tiny = x < 2.2250738585072014e-308  # subnormal: scaled by 2^54 into the normal range
    bits = float_bits(x * 18014398509481984.0 if tiny else x)
    e = np.float64((bits >> 52) - 1023) - (54.0 if tiny else 0.0)
    m = bits_float((bits & 0xFFFFFFFFFFFFF) | 0x3FF0000000000000)  # the significand, in [1, 2)
    high = m > 1.4142135623730951
    m = 0.5 * m if high else m
    e = e + 1.0 if high else e
    s = (m - 1.0) / (m + 1.0)
    z = s * s
    p = 1.0 / 17.0
    for c in (15.0, 13.0, 11.0, 9.0, 7.0, 5.0, 3.0, 1.0):
        p = p * z + 1.0 / c
    y = e + 2.8853900817779268 * s * p  # 2 / ln 2
    y = y if x < np.inf else x  # inf and NaN as they are
    y = y if x != 0.0 else -np.inf
    return y if x >= 0.0 or x != x else np.nan


@kernel(inline="always")
def lod_from_derivatives(dudx, dvdx, dudy, dvdy, width, height):
    """OpenGL's level of detail: log2 of the longer of the two screen-space derivative
    vectors of the texel coordinates, ``(dudx * width, dvdx * height)`` and ``(dudy * width,
    dvdy * height)`` (u, v as the texture sees them: after its scale). -inf for no change,
    NaN for NaN derivatives (both taken as 0 by :func:`sample`)."""
    x = (dudx * width) ** 2 + (dvdx * height) ** 2
    y = (dudy * width) ** 2 + (dvdy * height) ** 2
    return 0.5 * log2(max(x, y)) if x == x and y == y else np.nan


@kernel(inline="always")
def texture_lod(levels, samplers, transforms, t, dudx, dvdx, dudy, dvdy):
    """:func:`lod_from_derivatives` for texture ``t``: the derivatives of the mesh's (u, v),
    scaled by the texture's ``scale``, over its level 0."""
    t = np.uint64(t)
    first = np.uint64(samplers[t, FIRST])
    su = transforms[t, SCALE_U]
    sv = transforms[t, SCALE_V]
    return lod_from_derivatives(dudx * su, dvdx * sv, dudy * su, dvdy * sv, levels[first, 1], levels[first, 2])


@kernel(refcounts=False)
def sample(texels, levels, samplers, transforms, decode, t, u, v, lod):
    """Texture ``t`` at (u, v) float64 with level of detail ``lod``: (r, g, b, a) float32
    (see the module documentation). Allocates nothing. A function of its own, for callers
    outside a hot loop; the band worker inlines :func:`lookup`."""
    return lookup(texels, levels, samplers, transforms, decode, t, u, v, lod)


@kernel(inline="always")
def lookup(texels, levels, samplers, transforms, decode, t, u, v, lod):
    """:func:`sample`, inlined into its caller.

    Written once for every filter, to keep what compiles small: one or two levels (two where
    ``trilinear`` falls between levels), each blended from the 4 texels around the point
    (``nearest``: the texel under it, the other 3 weighted 0). The texture's settings are read
    here, from the arrays, on every call: a caller's loop then has no branch LLVM could hoist
    out of it and copy the loop for (loop unswitching made a textured render's first compile
    take 45 s longer)."""
    t = np.uint64(t)
    first, count, channels = samplers[t, FIRST], samplers[t, COUNT], samplers[t, CHANNELS]
    mode, wrap, srgb = samplers[t, FILTER], samplers[t, WRAP], np.uint64(samplers[t, SRGB])
    u = bounded_coordinate(u * transforms[t, SCALE_U] + transforms[t, OFFSET_U], wrap)
    v = bounded_coordinate(v * transforms[t, SCALE_V] + transforms[t, OFFSET_V], wrap)
    level, between = first, 0.0
    if mode == FILTER_TRILINEAR:
        lod = 0.0 if lod != lod or lod < 0.0 else min(lod, count - 1.0)
        d = np.floor(lod)
        level, between = first + np.int64(d), lod - d
    offset = 0.5 if mode != FILTER_NEAREST else 0.0  # nearest: the texel containing the point, weight 1
    r = g = b = a = 0.0
    weight = 1.0 - between
    for k in range(2 if between > 0.0 else 1):
        at = np.uint64(level + k)
        start, width, height = levels[at, 0], levels[at, 1], levels[at, 2]
        x = u * width - offset
        y = v * height - offset
        fx = np.floor(x)
        fy = np.floor(y)
        ax = (x - fx) if mode != FILTER_NEAREST else 0.0
        ay = (y - fy) if mode != FILTER_NEAREST else 0.0
        i0 = np.uint64(wrap_index(np.int64(fx), width, wrap) * channels)
        i1 = np.uint64(wrap_index(np.int64(fx) + 1, width, wrap) * channels)
        row0 = np.uint64(start + (height - 1 - wrap_index(np.int64(fy), height, wrap)) * width * channels)
        row1 = np.uint64(start + (height - 1 - wrap_index(np.int64(fy) + 1, height, wrap)) * width * channels)
        r00, g00, b00, a00 = texel(texels, decode, srgb, channels, row0 + i0)
        r10, g10, b10, a10 = texel(texels, decode, srgb, channels, row0 + i1)
        r01, g01, b01, a01 = texel(texels, decode, srgb, channels, row1 + i0)
        r11, g11, b11, a11 = texel(texels, decode, srgb, channels, row1 + i1)
        w00 = weight * (1.0 - ax) * (1.0 - ay)
        w10 = weight * ax * (1.0 - ay)
        w01 = weight * (1.0 - ax) * ay
        w11 = weight * ax * ay
        r += w00 * r00 + w10 * r10 + w01 * r01 + w11 * r11
        g += w00 * g00 + w10 * g10 + w01 * g01 + w11 * g11
        b += w00 * b00 + w10 * b10 + w01 * b01 + w11 * b11
        a += w00 * a00 + w10 * a10 + w01 * a01 + w11 * a11
        weight = between
    return np.float32(r), np.float32(g), np.float32(b), np.float32(a)


@kernel
def sample_points(texels, levels, samplers, transforms, decode, t, uv, lod, out):
    """:func:`sample` at each point: ``uv`` (N, 2) float64, ``lod`` (N,) float64, into ``out``
    (N, 4) float32. The entry point of :func:`rasterkit.material.sampling.sample` and tests,
    in this thread."""
    for k in range(uv.shape[0]):
        r, g, b, a = sample(texels, levels, samplers, transforms, decode, t, uv[k, 0], uv[k, 1], lod[k])
        out[k, 0] = r
        out[k, 1] = g
        out[k, 2] = b
        out[k, 3] = a
