"""The scratch of a chunk of pixels lit per pixel (:mod:`rasterkit.raster.kernels.phong_rows`):
its layout, one column of :data:`CHUNK` values per quantity, and the chunk-wide steps that
need nothing but the scratch: unit vectors and the highlights' powers."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.powers import power
from rasterkit.raster.kernels.surface import ENCODE_STEPS
from rasterkit.runtime.jit import kernel

#: Pixels lit at a time.
CHUNK = 64

#: Columns of the scratch, CHUNK values each: first the values interpolated across a face
#: (position, normal, base colour), then those a face has one of (specular colour,
#: shininess, emission, its plane's normal, two-sided or not), then the pixel's own.
FIELDS = 32
INTERPOLATED = 9
CONSTANT = 11
SCRATCH = FIELDS * CHUNK  # a literal for stack_floats

#: Where each column starts in the scratch (unsigned: no negative-index arithmetic). The
#: last four hold a shadow lookup's terms of each pixel's face
#: (:mod:`rasterkit.raster.kernels.lit_shadows`).
(X, Y, Z, NX, NY, NZ, BR, BG, BB, SR, SG, SB, SHINE, AR, AG, AB, PX, PY, PZ, TWO,
 COLUMN, VX, VY, VZ, SHADE, NDL, NDH, POWER, GI, GJ, LEEWAY, ABOVE) = (np.uint64(k * CHUNK) for k in range(FIELDS))

#: Shininess raised by squarings when every pixel of a chunk has the same whole one below
#: this (:func:`highlights`); other exponents through :func:`~rasterkit.raster.kernels.powers.power`.
WHOLE_LIMIT = 65536.0

#: The kind codes of :data:`rasterkit.raster.lights.KINDS`.
AMBIENT, DIRECTIONAL, POINT, SPOT, HEADLIGHT = 0, 1, 2, 3, 4


@kernel(inline="always")
def unit(x, y, z):
    """(x, y, z) made unit length; zero when it has none (or is not finite)."""
    length = np.sqrt(x * x + y * y + z * z)
    scale = 1.0 / length if length > 0.0 else 0.0  # noqa: FURB136 - a select
    scale = scale if np.isfinite(scale) else 0.0  # noqa: FURB136
    return x * scale, y * scale, z * scale


@kernel(inline="always")
def whole_exponent(s, n):
    """The shininess of the chunk's ``n`` pixels when they all have the same one and it is a
    whole number from 0 to below :data:`WHOLE_LIMIT`, else -1."""
    first = s[SHINE]
    same = True
    for q in range(n):
        same &= s[SHINE + np.uint64(q)] == first
    return first if same and first >= 0.0 and first < WHOLE_LIMIT and first == np.floor(first) else -1.0


@kernel(inline="always")
def highlights(s, n, whole):
    """Each pixel's ``max(n.h, 0)`` (column NDH) raised to its shininess, into column
    POWER: for a chunk of one ``whole`` exponent (:func:`whole_exponent`) by squarings, one
    pass over the chunk for each (exact to a few units of the last place), else by
    :func:`~rasterkit.raster.kernels.powers.power`."""
    if whole < 0.0:
        for q in range(n):
            s[POWER + np.uint64(q)] = power(s[NDH + np.uint64(q)], s[SHINE + np.uint64(q)])
        return
    e = np.int64(whole)
    for q in range(n):
        s[POWER + np.uint64(q)] = 1.0
    while e > 0:  # the bits of the exponent from the lowest: the product of those squares
        if e & 1:
            for q in range(n):
                s[POWER + np.uint64(q)] *= s[NDH + np.uint64(q)]
        e >>= 1
        if e > 0:
            for q in range(n):
                s[NDH + np.uint64(q)] *= s[NDH + np.uint64(q)]


@kernel(inline="always")
def encode_chunk(s, n, table):
    """The chunk's linear sums (columns AR, AG, AB) encoded to sRGB and packed into one RGBA
    (opaque) per pixel, into column SHADE: ``to_u8(255 encode(x))`` per channel, as
    :func:`rasterkit.raster.kernels.surface.encode` and
    :func:`rasterkit.raster.kernels.shade.to_u8` compute it, in passes a channel at a time.
    Only the table lookups go one value at a time; the clamps, the splits of the table
    position and the rounding run without branches, so LLVM turns them into vector
    instructions (one loop doing it all per pixel does not vectorise: its table lookups
    make it scalar throughout). Overwrites columns X .. Z and NX .. NZ."""
    for q in range(n):
        s[SHADE + np.uint64(q)] = 4278190080.0  # alpha 255
    for channel in range(3):
        at, index = AR + np.uint64(channel * CHUNK), X + np.uint64(channel * CHUNK)
        low = NX + np.uint64(channel * CHUNK)
        for q in range(n):  # the table position: its entry (int32: a vector conversion) and fraction
            x = s[at + np.uint64(q)]
            x = x if x > 0.0 else 0.0  # noqa: FURB136 - the select sends NaN to 0
            x = x if x < 1.0 else 1.0  # noqa: FURB136
            pos = x * ENCODE_STEPS
            k = np.int32(pos)
            s[at + np.uint64(q)] = pos - k
            s[index + np.uint64(q)] = k
        for q in range(n):  # the lookups
            k = np.uint64(np.int64(s[index + np.uint64(q)]))
            first = table[k]
            s[low + np.uint64(q)] = first
            s[index + np.uint64(q)] = table[k + np.uint64(1)] - first
        shift = np.float64(1 << (8 * channel))
        for q in range(n):  # interpolated, rounded half up, clamped, shifted into place
            value = (s[low + np.uint64(q)] + s[index + np.uint64(q)] * s[at + np.uint64(q)]) * 255.0
            value = value if value > 0.0 else 0.0  # noqa: FURB136
            value = value if value < 255.0 else 255.0  # noqa: FURB136
            s[SHADE + np.uint64(q)] += np.floor(value + 0.5) * shift
