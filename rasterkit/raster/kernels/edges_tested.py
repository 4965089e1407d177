"""Depth-tested edges (the hidden-line mode and the edges of solid+wire), band by band.

An edge is drawn where its depth at the pixel's major-axis centre, less a bias, is at most
the depth buffer's (the faces, drawn first with a polygon offset). The plain path's records
(:func:`rasterkit.raster.kernels.edge_setup.plain_setup`) serve here too: an edge inside the image is
stepped from its record, with the depth terms of the general path made from its ends
(:func:`_depth_terms`), and a band skips the blocks of records outside it; any other edge is
clipped and set up per band by the general path (:mod:`rasterkit.raster.kernels.edges`). Both give
the same pixels, to the bit. Edges write no depth: their order changes no pixel, so the
general path is a pass of its own (:func:`draw_general_edge_bands`), run only when some edge
needs it: a model in full view compiles none of the clipper.
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.edge_setup import BLOCK, BLOCK_GENERAL, REC_ROWS, REC_STEPS
from rasterkit.raster.kernels.edges import (DROPPED_BAND, band_buffers, band_segment, block_in_band, bresenham_start,
                                     depth_at, next_band, record_steps)
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.line import put_pixel


@kernel(inline="always")
def _draw_bresenham_tested(cflat, dflat, width, channels, rgba, seg, ylo, yhi, bias):
    """:func:`rasterkit.raster.kernels.edges._draw_bresenham` with the depth test: a pixel is drawn where the segment's
    depth at its major-axis centre, less ``bias``, is at most the depth buffer's."""
    count, pix, r, two_a, two_n, ustride, vstride, u, u0f, du, z0, gz = bresenham_start(seg, width, ylo, yhi)
    for t in range(count):
        if depth_at(u + t, u0f, du, z0, gz) - bias <= dflat[pix]:
            put_pixel(cflat, pix, channels, rgba)
        r += two_a
        step = r >= two_n
        r -= two_n if step else 0
        pix += ustride + (vstride if step else 0)


@kernel(refcounts=False)
def _band_depth_tested(cflat, dflat, width, channels, rgba, clip, proj, edges, recs, blocks, ylo, yhi, bias):
    """Depth-tested edges' parts in rows ``ylo .. yhi`` (Bresenham), of the edges with a
    record (``recs`` and ``blocks`` of :func:`rasterkit.raster.kernels.edge_setup.plain_setup`):
    each is stepped from its record with its depth terms (:func:`_depth_terms`), the blocks
    outside the band skipped, as :func:`rasterkit.raster.kernels.edges._band_wire` does. The others
    (rows -1) are :func:`_band_general_tested`'s."""
    m = edges.shape[0]
    for b in range(blocks.shape[1]):
        outside, inside = block_in_band(blocks, b, ylo, yhi)
        if outside:
            continue
        for e in range(b * BLOCK, min((b + 1) * BLOCK, m)):
            if not inside:
                rows = recs[REC_ROWS, e]
                if rows < 0 or (rows >> 16) < ylo or (rows & 0xFFFF) > yhi:
                    continue
            pix, count, r, two_a, two_n, ustride, vstride = record_steps(width, recs, e)
            u, u0f, du, z0, gz = _depth_terms(proj, edges, recs, e)
            # the pixels of the band only (all of them for a record wholly inside it)
            plo, phi = ylo * width, (yhi + 1) * width
            for t in range(count):
                if plo <= pix < phi and depth_at(u + t, u0f, du, z0, gz) - bias <= dflat[pix]:
                    put_pixel(cflat, pix, channels, rgba)
                r += two_a
                step = r >= two_n
                r -= two_n if step else 0
                pix += ustride + (vstride if step else 0)


@kernel(refcounts=False)
def _band_general_tested(cflat, dflat, width, channels, rgba, clip, proj, edges, recs, blocks, ylo, yhi, bias):
    """Depth-tested edges' parts in rows ``ylo .. yhi`` of the edges without a record (rows
    -1: clipped, or crossing the image's border), by the general path; returns the number
    of dropped edges."""
    dropped = 0
    m = edges.shape[0]
    for b in range(blocks.shape[1]):
        if blocks[BLOCK_GENERAL, b] == 0:
            continue
        for e in range(b * BLOCK, min((b + 1) * BLOCK, m)):
            if recs[REC_ROWS, e] < 0:
                dropped += _tested_segment(cflat, dflat, width, channels, rgba, clip, proj, edges, e, ylo, yhi, bias)
    return dropped


@kernel(inline="always")
def _depth_terms(proj, edges, recs, e):
    """``(u0, u0f, du, z0, gz)`` of record ``e`` (:func:`bresenham_start`'s depth terms):
    the same operations on the same ends ``proj``, so the depth tested at each pixel is the
    same to the bit. The direction is decided on the real ends, as there; it differs from
    the record's (integer) one only for an edge within one pixel, whose single pixel is the
    same either way. (Made here, once per edge and band that draws it, not in a pass of its
    own: as fast, and nothing more to compile and keep.)"""
    i, j = edges[e, 0], edges[e, 1]
    steep = ((np.int64(recs[REC_STEPS, e]) >> 30) & 1) == 1
    axis = 1 if steep else 0
    swap = proj[j, axis] < proj[i, axis]
    start, end = (j, i) if swap else (i, j)
    u0f, u1f = proj[start, axis], proj[end, axis]
    z0, z1 = proj[start, 2], proj[end, 2]
    du = u1f - u0f
    return np.int64(math.floor(u0f)), u0f, du, z0, (z1 - z0) / du if du > 0.0 else 0.0


@kernel(refcounts=False)
def _tested_segment(cflat, dflat, width, channels, rgba, clip, proj, edges, e, ylo, yhi, bias):
    """Edge ``e`` by the general path with the depth test; 1 when it is dropped. Compiled on
    its own (the clipper it holds is large)."""
    status, seg = band_segment(clip, proj, edges, e, ylo, yhi)
    if status > 0:
        _draw_bresenham_tested(cflat, dflat, width, channels, rgba, seg, ylo, yhi, bias)
    return 1 if status < 0 else 0


@kernel
def draw_edge_bands(slot, counter, color, depth, clip, edges, rgba, mode, bias, bounds, background, scratch):
    """Draw depth-tested edges (hidden lines, the edges of solid+wire) into a framebuffer,
    band by band: each the next band that no worker has claimed yet (through ``counter``),
    until none are left; returns 0. This draws the edges with a record; the driver then runs
    :func:`draw_general_edge_bands` for the others when there are any, which returns the
    number of edges dropped (each band sees every edge, so the dropped edges of any one band
    are all of them: it reports band :data:`DROPPED_BAND`'s).

    A worker of :func:`rasterkit.runtime.threads.run_parallel`; ``slot`` is unused. The driver,
    :mod:`rasterkit.raster.edge_pass`, runs :func:`project_vertices` first, :func:`balanced_bands`
    gives ``bounds``, and it picks the worker by mode: this one for ``MODE_DEPTH_TEST``,
    :func:`draw_wire_bands` for ``MODE_PLAIN``,
    :func:`rasterkit.raster.kernels.edges_wu.draw_antialiased_bands` for ``MODE_ANTIALIAS`` (with or without the depth test). Each is compiled on its own, so
    a mode compiles only its own drawing code.

    Parameters
    ----------
    color : (H, W, C) uint8, C-contiguous, C in {3, 4}
        Colour buffer, modified in place.
    depth : (H, W) float32, C-contiguous
        Depth buffer (smaller = nearer, +inf = empty). Read only with ``MODE_DEPTH_TEST``
        and never written; without the depth test any float32 array will do (e.g.
        ``np.empty((0, 0), np.float32)``).
    clip : (N, 4) float64
        Vertices in homogeneous raster space ``(xh, yh, zh, w)``.
    edges : (E, 2) int64
        Vertex indices into ``clip``, each in ``[0, N)`` (the caller checks).
    rgba : (C,) uint8
        Line colour.
    mode : int
        Bit set of ``MODE_DEPTH_TEST`` and ``MODE_ANTIALIAS``; ``MODE_PLAIN`` (0) is a
        wireframe with neither.
    bias : float
        Depth-test mode draws a pixel only where ``z - bias <= depth[y, x]``, ``z`` being the
        edge's depth (affine in screen space, so interpolated linearly) at the pixel's
        major-axis centre. A small positive bias lets the edges of visible faces pass the
        test against those faces' own depths.
    bounds : (n_bands + 1,) int64
        Band ``b`` is rows ``bounds[b] .. bounds[b + 1] - 1`` (possibly none). The image is
        the same for any bands.
    background : (C,) uint8 or (0,)
        Written to every pixel of a band by the worker that draws the band, right before
        its edges (nothing is cleared when it is empty).
    scratch : EdgeScratch
        :func:`rasterkit.raster.edge_pass.scratch`'s arrays: ``proj`` (N, 4) float64 from
        :func:`project_vertices`; the others are read by :func:`draw_wire_bands` only.

    Notes
    -----
    Plain and depth-tested edges write ``rgba`` to the pixels of the integer line between
    the pixels containing the (clipped) endpoints, exactly as :func:`line_pixels` draws it
    with Bresenham. Anti-aliased edges use Xiaolin Wu's algorithm on the real-valued
    endpoints and blend ``rgba`` into the colour buffer, all C channels, by coverage; their
    total weight is the segment's extent along its major axis. Edges are drawn in order, so
    overlapping anti-aliased edges blend in index order. Segments are clipped to the near
    and far planes and to the guard band ``[-SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND]^2`` in homogeneous
    space; a segment with both ends inside the guard band is drawn exactly. Edges with a
    coordinate beyond ``MAX_COORDINATE`` (or NaN, inf) are dropped and counted. The image
    must be smaller than ``SEGMENT_GUARD_BAND`` on each side.
    """
    proj = scratch.proj
    cflat, dflat, width, row_bytes, clear, pattern = band_buffers(color, depth, background)
    while True:  # claim the next band until none is left
        band, ylo, yhi = next_band(counter, bounds, cflat, row_bytes, clear, pattern)
        if band < 0:
            break
        _band_depth_tested(cflat, dflat, width, color.shape[2], rgba, clip, proj, edges, scratch.recs,
                           scratch.blocks, ylo, yhi, bias)
    return 0


@kernel
def draw_general_edge_bands(slot, counter, color, depth, clip, edges, rgba, mode, bias, bounds, background, scratch):
    """The second pass of :func:`draw_edge_bands` (same arguments; ``background`` unused:
    the bands are cleared already): the edges without a record, by the general path, band
    by band; returns the number of edges dropped (:data:`DROPPED_BAND`'s count). The driver
    runs it only when :func:`rasterkit.raster.kernels.edge_setup.plain_setup` marked such edges
    (``blocks[BLOCK_GENERAL]``)."""
    proj = scratch.proj
    cflat, dflat, width = color.reshape(color.size), depth.reshape(depth.size), color.shape[1]
    dropped = 0
    while True:  # claim the next band until none is left
        band = fetch_add(counter, 0, 1)
        if band >= bounds.size - 1:
            break
        lost = _band_general_tested(cflat, dflat, width, color.shape[2], rgba, clip, proj, edges, scratch.recs,
                                    scratch.blocks, bounds[band], bounds[band + 1] - 1, bias)
        if band == DROPPED_BAND:
            dropped = lost
    return dropped
