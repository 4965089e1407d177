"""Which part of the pixel: the exact area of a triangle within one pixel square.

The lecture's extension of rasterization asks not whether a primitive covers a pixel's
centre but how much of the pixel it covers. For a polygon and the unit square that is
(Green's theorem, cut into vertical slices) the sum over the polygon's edges of the signed
integral, over the part of the edge's x-range inside the square, of the edge's height
clamped to the square: at each x the polygon's slice is the difference of its two edges'
clamped heights. Each integral has a closed form (a linear height clamped to [0, 1] is
piecewise linear), so a triangle's area in a pixel costs three short branch-light terms,
no clipping into a vertex list. Multi-sample renders use it where a pixel's samples saw
one face and the background (:mod:`rasterkit.raster.kernels.sample_bands`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def _positive_mean(a, b):
    """Mean of ``max(y, 0)`` over a segment along which ``y`` runs linearly from ``a`` to ``b``."""
    if a >= 0.0 and b >= 0.0:
        return 0.5 * (a + b)
    if a <= 0.0 and b <= 0.0:
        return 0.0
    top = max(a, b)  # one end above 0, the other below: the part above is a triangle
    return 0.5 * top * top / (abs(a) + abs(b))


@kernel(inline="always")
def _edge_term(xa, ya, xb, yb):
    """Signed integral over x of the height of the edge ``a -> b`` clamped to [0, 1], over
    the part of its x-range within [0, 1] (pixel-local coordinates)."""
    lo, hi = min(max(xa, 0.0), 1.0), min(max(xb, 0.0), 1.0)
    if lo == hi:  # vertical, or wholly beside the square
        return 0.0
    slope = (yb - ya) / (xb - xa)
    y_lo, y_hi = ya + slope * (lo - xa), ya + slope * (hi - xa)
    # clamp(y, 0, 1) = max(y, 0) - max(y - 1, 0)
    return (hi - lo) * (_positive_mean(y_lo, y_hi) - _positive_mean(y_lo - 1.0, y_hi - 1.0))


@kernel
def pixel_area(x0, y0, x1, y1, x2, y2, i, j):
    """Area of the triangle with fixed-point raster corners ``(x0, y0) .. (x2, y2)`` (1/256
    pixel, as the setup snaps them) within the square of pixel ``(i, j)``, ``[i, i + 1] x
    [j, j + 1]`` in raster units: in [0, 1], for either winding."""
    ox, oy = 256.0 * i, 256.0 * j
    ax, ay = (x0 - ox) / 256.0, (y0 - oy) / 256.0
    bx, by = (x1 - ox) / 256.0, (y1 - oy) / 256.0
    cx, cy = (x2 - ox) / 256.0, (y2 - oy) / 256.0
    total = _edge_term(ax, ay, bx, by) + _edge_term(bx, by, cx, cy) + _edge_term(cx, cy, ax, ay)
    return min(abs(total), 1.0)


@kernel
def pixel_areas(corners, pixels):
    """:func:`pixel_area` of one fixed-point triangle ``corners`` (6,) int64 in each pixel
    ``pixels`` (n, 2) int64 ``(i, j)``: (n,) float64. For tests and the lecture's pictures."""
    out = np.empty(pixels.shape[0])
    for k in range(pixels.shape[0]):
        out[k] = pixel_area(corners[0], corners[1], corners[2], corners[3], corners[4], corners[5], pixels[k, 0],
                            pixels[k, 1])
    return out
