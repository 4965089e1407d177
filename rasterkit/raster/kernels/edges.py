"""Drawing edges into a framebuffer, band by band: the wireframe's plain edges, and the general
path that the depth-tested ones (:mod:`rasterkit.raster.kernels.edges_tested`) and the anti-aliased
ones (:mod:`rasterkit.raster.kernels.edges_wu`) share.

:func:`draw_edges` draws many edges given in homogeneous raster space (see
``ARCHITECTURE.md``). Per vertex, once: classify it and, when it is inside the visible
region, divide by ``w``. Per edge whose ends are not both inside: drop non-finite input;
clip before the divide against the near plane ``zh >= 0``, the far plane ``zh <= w`` and a
guard band of ``+-SEGMENT_GUARD_BAND`` pixels (Liang-Barsky from a point inside, found by bisection
when both ends are far away, so that even ends at 1e300 clip accurately); divide by ``w``.
Per band of image rows: round the endpoints down to their pixels, find in closed form the
Bresenham steps inside the band and step only those, so a segment costs its visible pixels
however long it is (clipping a segment again in every band it crosses). Each thread owns a
band of rows, so no two threads write the same pixel, and since every per-pixel value is computed in
closed form the image does not depend on the number of bands or threads.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.clear import PATTERN_BYTES, background_pattern, fill_bytes
from rasterkit.raster.kernels.segments import project_segment
from rasterkit.raster.kernels.edge_setup import (BLOCK, BLOCK_GENERAL, BLOCK_HI, BLOCK_LO, REC_PIX, REC_ROWS,
                                          REC_STEPS)
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.line import minor_steps, put_pixel, step_line, step_mask, step_range, tie_offset
from rasterkit.raster.kernels.paint import paint_marked, paint_tables

MODE_PLAIN = 0
MODE_DEPTH_TEST = 1
MODE_ANTIALIAS = 2
#: The band whose count of dropped edges the band workers report
#: (:func:`rasterkit.raster.kernels.edges_tested.draw_edge_bands`).
DROPPED_BAND = 0

#: The scratch arrays of a draw (:func:`rasterkit.raster.edge_pass.scratch`): ``proj`` (N, 4) float64
#: from :func:`rasterkit.raster.kernels.edge_setup.project_vertices`; for plain and depth-tested
#: edges ``pixels`` (N,) int64, ``recs`` (REC_FIELDS, E) int32 and ``blocks`` (BLOCK_FIELDS,
#: B) int32 from :func:`rasterkit.raster.kernels.edge_setup.plain_setup`; for plain edges ``mask``
#: (H * W,) uint8, the bands' byte masks (empty arrays otherwise).
EdgeScratch = namedtuple("EdgeScratch", "proj pixels recs blocks mask")


@kernel(inline="always")
def _edge_segment(clip, proj, i, j):
    """Edge ``i``-``j`` in raster space: ``(status, (x0, y0, z0, x1, y1, z1))``.

    ``status`` is 1 for a segment to draw, 0 when nothing of it is visible and -1 when it
    is dropped for a non-finite or too large coordinate. Both ends projected by
    :func:`project_vertices` are taken as they are; otherwise the segment is clipped here.
    """
    fi, fj = proj[i, 3], proj[j, 3]
    if fi > 0.0 and fj > 0.0:
        return 1, (proj[i, 0], proj[i, 1], proj[i, 2], proj[j, 0], proj[j, 1], proj[j, 2])
    if fi < 0.0 or fj < 0.0:
        return -1, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    p = (clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3])
    q = (clip[j, 0], clip[j, 1], clip[j, 2], clip[j, 3])
    visible, x0, y0, z0, x1, y1, z1 = project_segment(p, q)
    return (1 if visible else 0), (x0, y0, z0, x1, y1, z1)


@kernel(inline="always")
def band_frame(steep, width, ylo, yhi):
    """Strides and ranges of the band in (major u, minor v) terms.

    Returns ``(ustride, vstride, ulo, uhi, vlo, vhi)``: pixel index steps (in pixels of the
    flattened (H, W) image) and the inclusive coordinate ranges of the band.
    """
    if steep:
        return width, 1, ylo, yhi, 0, width - 1
    return 1, width, 0, width - 1, ylo, yhi


@kernel(inline="always")
def oriented(x0, y0, x1, y1, steep, swap):
    """The segment as ``(u0, v0, u1, v1)``: transposed if steep, reversed if swap."""
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    if swap:
        return u1, v1, u0, v0
    return u0, v0, u1, v1


@kernel(inline="always")
def depth_at(u, u0f, du, z0, gz):
    """Depth of the segment at the centre of major coordinate ``u``, clamped to its ends."""
    return z0 + min(max(u + 0.5 - u0f, 0.0), du) * gz


@kernel(inline="always")
def bresenham_start(seg, width, ylo, yhi):
    """Where one segment's integer line starts in rows ``[ylo, yhi]`` of the image:
    ``(count, pix, r, two_a, two_n, ustride, vstride, u0, u0f, du, z0, gz)``, the loop
    state of :func:`rasterkit.raster.kernels.line.step_line` (``count`` 0: nothing in the band)
    and the depth terms of its major steps (:func:`depth_at` of ``u0 + t``)."""
    xi0, yi0 = math.floor(seg[0]), math.floor(seg[1])
    xi1, yi1 = math.floor(seg[3]), math.floor(seg[4])
    steep = abs(yi1 - yi0) > abs(xi1 - xi0)
    # Step towards increasing major coordinate; deciding on the real ends also orders the
    # integer ones, and keeps the depth slope's denominator >= 0.
    swap = (seg[4] < seg[1]) if steep else (seg[3] < seg[0])
    u0, v0, u1, v1 = oriented(xi0, yi0, xi1, yi1, steep, swap)
    u0f, _, u1f, _ = oriented(seg[0], seg[1], seg[3], seg[4], steep, swap)
    z0, z1 = (seg[5], seg[2]) if swap else (seg[2], seg[5])
    ustride, vstride, ulo, uhi, vlo, vhi = band_frame(steep, width, ylo, yhi)

    n = u1 - u0
    dv = v1 - v0
    a = abs(dv)
    sv = 1 if dv >= 0 else -1
    c = tie_offset(dv)
    if min(xi0, xi1) >= 0 and max(xi0, xi1) < width and min(yi0, yi1) >= ylo and max(yi0, yi1) <= yhi:
        tlo, thi, k, r = 0, n, 0, n - c  # the whole line is in the band: the usual case
    else:
        tlo, thi = step_range(u0, v0, n, a, sv, c, ulo, uhi, vlo, vhi)
        k, r = minor_steps(tlo, n, a, c) if tlo <= thi else (0, 0)
    pix = (u0 + tlo) * ustride + (v0 + sv * k) * vstride
    du = u1f - u0f
    gz = (z1 - z0) / du if du > 0.0 else 0.0
    return (max(thi - tlo + 1, 0), pix, r, 2 * a, 2 * n, ustride, sv * vstride, u0 + tlo, u0f, du, z0, gz)


@kernel(inline="always")
def _draw_bresenham(cflat, width, channels, rgba, seg, ylo, yhi):
    """Draw one segment's integer line, restricted to rows ``[ylo, yhi]`` of the image."""
    count, pix, r, two_a, two_n, ustride, vstride, _, _, _, _, _ = bresenham_start(seg, width, ylo, yhi)
    step_line(cflat, channels, rgba, pix, count, r, two_a, two_n, ustride, vstride)


@kernel(inline="always")
def record_steps(width, recs, e):
    """The Bresenham loop state of record ``e`` of :func:`plain_setup`: ``(pix, count, r,
    two_a, two_n, ustride, vstride)`` as :func:`rasterkit.raster.kernels.line.step_line` takes it."""
    packed = np.int64(recs[REC_STEPS, e]) & 0xFFFFFFFF
    n, a = packed & 0x7FFF, (packed >> 15) & 0x7FFF
    steep, negative = (packed >> 30) & 1, packed >> 31
    ustride = 1 + steep * (width - 1)
    vstride = (1 - 2 * negative) * (width - steep * (width - 1))
    r = n - (negative | np.int64(a == 0))  # tie_offset: dv <= 0
    return np.int64(recs[REC_PIX, e]), n + 1, r, 2 * a, 2 * n, ustride, vstride


@kernel(inline="always")
def band_segment(clip, proj, edges, e, ylo, yhi):
    """Edge ``e`` clipped and projected (:func:`_edge_segment`): ``(status, seg)``, status
    1 when it may touch rows ``ylo .. yhi``, 0 when it cannot (or nothing is left of it),
    -1 when it is dropped (a NaN, infinite or too large coordinate)."""
    status, seg = _edge_segment(clip, proj, edges[e, 0], edges[e, 1])
    # Wu's two pixels and its end-column centres reach up to 2 rows beyond the ends.
    if status > 0 and (math.floor(min(seg[1], seg[4])) - 2 > yhi or math.floor(max(seg[1], seg[4])) + 2 < ylo):
        status = 0
    return status, seg


@kernel(inline="always")
def block_in_band(blocks, b, ylo, yhi):
    """``(outside, inside)``: whether block ``b`` of the records' summaries
    (:func:`rasterkit.raster.kernels.edge_setup.plain_setup`) has only plain records, all outside
    rows ``ylo .. yhi`` or all inside them."""
    plain = blocks[BLOCK_GENERAL, b] == 0
    lo, hi = blocks[BLOCK_LO, b], blocks[BLOCK_HI, b]
    return plain and (hi < ylo or lo > yhi), plain and lo >= ylo and hi <= yhi


@kernel(refcounts=False)
def _band_wire(cflat, width, channels, rgba, clip, proj, edges, recs, blocks, ylo, yhi):
    """Plain edges' parts in rows ``ylo .. yhi``, of the edges with a record: a record that
    lies wholly in the band is stepped as it is, one that crosses the band's edge with a
    test per pixel; a block of plain records wholly outside the band is skipped, one wholly
    inside stepped without testing each edge. ``channels`` 1 is a band's mask. The edges
    without a record are :func:`_band_general_wire`'s (a pass of its own: a model in full
    view compiles no clipper)."""
    m = edges.shape[0]
    for b in range(blocks.shape[1]):
        outside, inside = block_in_band(blocks, b, ylo, yhi)
        if outside:
            continue
        for e in range(b * BLOCK, min((b + 1) * BLOCK, m)):
            record = inside
            if not inside:
                rows = recs[REC_ROWS, e]
                if rows < 0:
                    continue
                jlo, jhi = rows & 0xFFFF, rows >> 16
                if jhi < ylo or jlo > yhi:
                    continue
                record = jlo >= ylo and jhi <= yhi
            pix, count, r, two_a, two_n, ustride, vstride = record_steps(width, recs, e)
            if record:
                if channels == 1:  # a band's mask
                    step_mask(cflat, rgba[0], pix, count, r, two_a, two_n, ustride, vstride)
                else:
                    step_line(cflat, channels, rgba, pix, count, r, two_a, two_n, ustride, vstride)
                continue
            plo, phi = ylo * width, (yhi + 1) * width  # the band's pixels of a record crossing its edge
            for _ in range(count):
                if plo <= pix < phi:
                    put_pixel(cflat, pix, channels, rgba)
                r += two_a
                step = r >= two_n
                r -= two_n if step else 0
                pix += ustride + (vstride if step else 0)


@kernel(refcounts=False)
def _band_general_wire(cflat, width, channels, rgba, clip, proj, edges, recs, blocks, ylo, yhi):
    """Plain edges' parts in rows ``ylo .. yhi`` of the edges without a record (rows -1:
    clipped, or crossing the image's border), by the general path; returns the number of
    dropped edges."""
    dropped = 0
    m = edges.shape[0]
    for b in range(blocks.shape[1]):
        if blocks[BLOCK_GENERAL, b] == 0:
            continue
        for e in range(b * BLOCK, min((b + 1) * BLOCK, m)):
            if recs[REC_ROWS, e] >= 0:
                continue
            status, seg = band_segment(clip, proj, edges, e, ylo, yhi)
            dropped += status < 0
            if status > 0:
                _draw_bresenham(cflat, width, channels, rgba, seg, ylo, yhi)
    return dropped


@kernel(inline="always")
def band_buffers(color, depth, background):
    """``(cflat, dflat, width, row_bytes, clear, pattern)``: the colour and depth buffers
    flattened, the image width, the bytes per colour row, whether to clear to
    ``background`` and its :func:`rasterkit.raster.kernels.clear.background_pattern`."""
    height, width, channels = color.shape
    clear = background.size == channels
    pattern = background_pattern(background) if clear else np.empty(0, np.uint8)
    return color.reshape(color.size), depth.reshape(depth.size), width, width * channels, clear, pattern


@kernel(inline="always")
def next_band(counter, bounds, cflat, row_bytes, clear, pattern):
    """Claim the next band (``-1`` when none is left) and clear its colour rows (when
    ``clear``); returns ``(band, ylo, yhi)``."""
    band = fetch_add(counter, 0, 1)
    if band >= bounds.size - 1:
        return -1, 0, 0
    ylo, yhi = bounds[band], bounds[band + 1] - 1
    if clear:
        fill_bytes(cflat, ylo * row_bytes, (yhi + 1) * row_bytes, pattern)
    return band, ylo, yhi


@kernel
def draw_wire_bands(slot, counter, color, clip, edges, rgba, bounds, background, scratch):
    """:func:`rasterkit.raster.kernels.edges_tested.draw_edge_bands` for plain edges (``MODE_PLAIN``: no depth test, no
    anti-aliasing), the wireframe's fast road, compiled apart so that a wireframe compiles
    nothing of the other modes. The arguments are those of
    :func:`rasterkit.raster.kernels.edges_tested.draw_edge_bands`
    without ``depth``, ``mode`` and ``bias``; in ``scratch``, ``pixels`` and ``recs`` come
    from :func:`plain_setup`. With a background and a ``mask`` of H * W bytes, each band
    first marks its edges' pixels in the mask (one byte store per pixel, in a buffer a third
    the size of an RGB image that stays in the thread's cache), then clears its colour rows
    and paints the marked pixels 8 at a time. Returns 0: the edges without a record are
    :func:`draw_general_wire_bands`' (run after this one when there are any)."""
    proj, recs, blocks, mask = scratch.proj, scratch.recs, scratch.blocks, scratch.mask
    height, width, channels = color.shape
    cflat = color.reshape(color.size)
    clear = background.size == channels
    pattern = background_pattern(background) if clear else np.empty(0, np.uint8)
    marked = clear and mask.size >= height * width
    # the 8-pixel paint tables, only for the marked (mask) path
    select, paint = paint_tables(rgba if marked else rgba[:0])
    one = np.ones(1, np.uint8)
    zeros = np.zeros(PATTERN_BYTES, np.uint8)
    target, target_channels, ink = (mask, 1, one) if marked else (cflat, channels, rgba)
    while True:  # claim the next band until none is left
        band = fetch_add(counter, 0, 1)
        if band >= bounds.size - 1:
            break
        lo, hi = bounds[band] * width, bounds[band + 1] * width  # the band's pixels
        if marked:  # into the mask (one channel, value 1), then paint
            fill_bytes(mask, lo, hi, zeros)
        elif clear:
            fill_bytes(cflat, lo * channels, hi * channels, pattern)
        _band_wire(target, width, target_channels, ink, clip, proj, edges, recs, blocks, bounds[band],
                   bounds[band + 1] - 1)
        if marked:
            fill_bytes(cflat, lo * channels, hi * channels, pattern)
            paint_marked(cflat, mask, lo, hi, rgba, select, paint)
    return 0


@kernel
def draw_general_wire_bands(slot, counter, color, clip, edges, rgba, bounds, background, scratch):
    """The second pass of :func:`draw_wire_bands` (same arguments; ``background`` unused: the
    bands are drawn already): the edges without a record, by the general path, band by band;
    returns the number of edges dropped (:data:`DROPPED_BAND`'s count). The driver runs it
    only when :func:`rasterkit.raster.kernels.edge_setup.plain_setup` marked such edges
    (``blocks[BLOCK_GENERAL]``)."""
    cflat, width, channels = color.reshape(color.size), color.shape[1], color.shape[2]
    dropped = 0
    while True:  # claim the next band until none is left
        band = fetch_add(counter, 0, 1)
        if band >= bounds.size - 1:
            break
        lost = _band_general_wire(cflat, width, channels, rgba, clip, scratch.proj, edges, scratch.recs,
                                  scratch.blocks, bounds[band], bounds[band + 1] - 1)
        if band == DROPPED_BAND:
            dropped = lost
    return dropped
