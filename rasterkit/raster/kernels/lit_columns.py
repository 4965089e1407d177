"""The scratch of a chunk of pixels lit per pixel (:mod:`rasterkit.raster.kernels.phong_rows`):
its layout, one column of :data:`CHUNK` values per quantity, and the chunk-wide steps that
need nothing but the scratch: unit vectors and the highlights' powers."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.powers import power
from rasterkit.runtime.jit import kernel

#: Pixels lit at a time.
CHUNK = 64

#: Columns of the scratch, CHUNK values each: first the values interpolated across a face
#: (position, normal, base colour), then those a face has one of (specular colour,
#: shininess, emission, its plane's normal, two-sided or not), then the pixel's own.
FIELDS = 28
INTERPOLATED = 9
CONSTANT = 11
SCRATCH = FIELDS * CHUNK  # a literal for stack_floats

#: Where each column starts in the scratch (unsigned: no negative-index arithmetic).
(X, Y, Z, NX, NY, NZ, BR, BG, BB, SR, SG, SB, SHINE, AR, AG, AB, PX, PY, PZ, TWO,
 COLUMN, VX, VY, VZ, SHADE, NDL, NDH, POWER) = (np.uint64(k * CHUNK) for k in range(FIELDS))

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
