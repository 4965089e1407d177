"""Anti-aliased edges (Xiaolin Wu's lines), band by band: the ``MODE_ANTIALIAS`` worker of
:mod:`rasterkit.raster.kernels.edges`, compiled apart so that the other modes compile none of it.

Each segment is clipped and projected as for the other modes
(:func:`rasterkit.raster.kernels.edges._band_segment`) and drawn on its real-valued end points:
each major column is covered over the part of its width the segment spans, split between
the two pixels whose centres straddle the line at the column centre, and blended into the
colour buffer (depth-tested with ``MODE_DEPTH_TEST``).
"""

from __future__ import annotations

import math

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.edges import (DROPPED_BAND, MODE_DEPTH_TEST, band_buffers, band_frame, band_segment, depth_at,
                                     next_band, oriented)
from rasterkit.raster.kernels.line import blend_pixel


@kernel(inline="always")
def _wu_columns(u0f, v0f, u1f, g, ulo, uhi, vlo, vhi):
    """Major columns ``[first, last]`` of a Wu segment that can touch the band.

    Column ``u`` puts the line's minor coordinate ``v(u)`` between the centres of rows
    ``floor(v - 0.5)`` and the next, so it can touch ``[vlo, vhi]`` only when
    ``v in [vlo - 0.5, vhi + 1.5)``; that range is inverted once per edge (with a margin of
    one column for rounding) instead of testing every column.
    """
    first = max(math.floor(u0f), ulo)
    last = min(math.ceil(u1f) - 1, uhi)
    if g == 0.0:
        if not vlo - 0.5 <= v0f < vhi + 1.5:
            return 1, 0
    elif first <= last:
        ua = (vlo - 0.5 - v0f) / g + u0f - 0.5
        ub = (vhi + 1.5 - v0f) / g + u0f - 0.5
        lo = min(max(min(ua, ub), first - 1.0), last + 1.0)
        hi = min(max(max(ua, ub), first - 1.0), last + 1.0)
        first = max(first, math.floor(lo) - 1)
        last = min(last, math.ceil(hi) + 1)
    return first, last


@kernel(refcounts=False)
def _draw_wu(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias):
    """Draw one segment anti-aliased (Xiaolin Wu), restricted to rows ``[ylo, yhi]``.

    Each major column ``u`` is covered over ``min(u1, u + 1) - max(u0, u)`` of its width;
    that coverage is split between the two pixels whose centres straddle the line at the
    column centre, in proportion to their distance from it.
    """
    steep = abs(seg[4] - seg[1]) > abs(seg[3] - seg[0])
    swap = (seg[4] < seg[1]) if steep else (seg[3] < seg[0])
    u0f, v0f, u1f, v1f = oriented(seg[0], seg[1], seg[3], seg[4], steep, swap)
    z0, z1 = (seg[5], seg[2]) if swap else (seg[2], seg[5])
    du = u1f - u0f
    if du == 0.0:
        return
    ustride, vstride, ulo, uhi, vlo, vhi = band_frame(steep, width, ylo, yhi)
    g = (v1f - v0f) / du
    gz = (z1 - z0) / du
    first, last = _wu_columns(u0f, v0f, u1f, g, ulo, uhi, vlo, vhi)
    for u in range(first, last + 1):
        coverage = min(u1f, u + 1.0) - max(u0f, float(u))
        below = v0f + (u + 0.5 - u0f) * g - 0.5
        j = math.floor(below)
        frac = below - j
        z = depth_at(u, u0f, du, z0, gz) - bias
        for row, weight in ((j, 1.0 - frac), (j + 1, frac)):
            if vlo <= row <= vhi:
                pix = u * ustride + row * vstride
                if not depth_test or z <= dflat[pix]:
                    blend_pixel(cflat, pix, channels, rgba, coverage * weight)


@kernel(refcounts=False)
def _band_antialiased(cflat, dflat, width, channels, rgba, clip, proj, edges, ylo, yhi, depth_test, bias):
    """Anti-aliased (Wu) edges' parts in rows ``ylo .. yhi``, depth-tested or not; returns
    the number of dropped edges."""
    dropped = 0
    for e in range(edges.shape[0]):
        status, seg = band_segment(clip, proj, edges, e, ylo, yhi)
        dropped += status < 0
        if status > 0:
            _draw_wu(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias)
    return dropped


@kernel
def draw_antialiased_bands(slot, counter, color, depth, clip, edges, rgba, mode, bias, bounds, background,
                           scratch):
    """:func:`rasterkit.raster.kernels.edges_tested.draw_edge_bands` for anti-aliased edges (``MODE_ANTIALIAS``, depth-tested
    with ``MODE_DEPTH_TEST``): Xiaolin Wu's lines, compiled apart so that the other modes
    compile none of them."""
    proj = scratch.proj
    cflat, dflat, width, row_bytes, clear, pattern = band_buffers(color, depth, background)
    depth_test = (mode & MODE_DEPTH_TEST) != 0
    dropped = 0
    while True:  # claim the next band until none is left
        band, ylo, yhi = next_band(counter, bounds, cflat, row_bytes, clear, pattern)
        if band < 0:
            break
        lost = _band_antialiased(cflat, dflat, width, color.shape[2], rgba, clip, proj, edges, ylo, yhi, depth_test,
                                 bias)
        if band == DROPPED_BAND:
            dropped = lost
    return dropped
