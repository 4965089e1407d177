"""Per-frame setup of the edge path: the vertex pass, the per-edge records of plain edges,
and the split of the image into bands of about equal work.

Plain edges (a wireframe: no depth test, no anti-aliasing) whose ends are both inside the
image take a faster road to the same pixels. The vertex pass also records each such
vertex's pixel; :func:`plain_setup` turns every edge into a 12-byte record (first pixel,
packed ``n``, ``a`` and direction bits, rows spanned) with branch-free arithmetic that
vectorises, summarises each block of edges (the rows it spans) and counts the work per
row so the bands get equal work; each band marks its edges' pixels in a byte mask, then
clears its colour rows and paints the marked pixels 8 at a time
(:func:`rasterkit.raster.kernels.paint.paint_marked`).
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.segments import SEGMENT_GUARD_BAND, all_usable, clamp, segment_outcode
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.vertex import transform_row

VERTEX_CHUNKS = 16
ROWS_PER_BIN = 8


@kernel(refcounts=False)
def project_vertices(slot, counter, clip, proj, pixels, width, height, counts, points, matrix):
    """Vertex pass of :func:`draw_edges`: divide every vertex that needs no clipping, once.

    ``proj[i]`` becomes ``(x, y, z, 1.0)`` (raster space, exactly as :func:`project_segment`
    computes an end that is inside) for a vertex inside the visible region with ``w > 0``;
    ``(., ., ., 0.0)`` for a usable vertex outside it, whose edges are clipped one by one;
    ``(., ., ., -1.0)`` for a vertex with a NaN, infinite or too large coordinate, whose
    edges are dropped. A vertex is shared by several edges (three per vertex in a closed
    triangle mesh), so this saves most of the per-edge work.

    Unless ``pixels`` is empty, ``pixels[i]`` (int64) becomes the pixel of a projected
    vertex inside the ``width`` x ``height`` image, ``x | y << 32``, and -1 for every
    other vertex (what :func:`plain_setup` reads).

    ``counts`` (VERTEX_CHUNKS, n_bins) int64, zeros on entry, gets the number of projected
    vertices of each chunk in each ``ROWS_PER_BIN`` rows of an image ``height`` rows tall
    (``n_bins`` rows' worth), a cheap estimate of where the drawing work lies; it stays zero
    when ``pixels`` is given (the plain path balances its bands by the work that
    :func:`plain_setup` counts, and the count cost a sixth of this pass).

    Unless ``points`` is empty, ``clip`` is made here first, row by row, as
    :func:`rasterkit.raster.kernels.vertex.transform_chunks` makes it from ``points`` (N, 3) float64
    and ``matrix`` (4, 4) float64 (a wireframe, which needs ``clip`` for nothing else, saves a
    pass over the vertices).

    A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused, chunks claimed
    through ``counter``).
    """
    n = clip.shape[0]
    with_pixels = pixels.size > 0
    transform = points.shape[0] > 0
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= VERTEX_CHUNKS:
            break
        for i in range(n * ch // VERTEX_CHUNKS, n * (ch + 1) // VERTEX_CHUNKS):
            if transform:
                transform_row(points, matrix, clip, i)
            p = (clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3])
            pixel = -1
            if not all_usable(p):
                proj[i, 3] = -1.0
            elif segment_outcode(p) != 0 or not p[3] > 0.0:
                proj[i, 3] = 0.0
            else:
                inv = 1.0 / p[3]
                x = clamp(p[0] * inv, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
                y = clamp(p[1] * inv, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
                proj[i, 0] = x
                proj[i, 1] = y
                proj[i, 2] = p[2] * inv
                proj[i, 3] = 1.0
                if 0.0 <= y < height:
                    if not with_pixels:
                        counts[ch, np.int64(y) // ROWS_PER_BIN] += 1
                    if 0.0 <= x < width:
                        pixel = np.int64(math.floor(x)) | (np.int64(math.floor(y)) << 32)
            if with_pixels:
                pixels[i] = pixel


@kernel
def balanced_bands(counts, n_bands, height):
    """Row boundaries ``(n_bands + 1,)`` splitting ``height`` rows into bands holding about
    equal shares of ``counts`` (per ``ROWS_PER_BIN`` rows; equal row counts when all are
    zero). Band ``b`` is rows ``[bounds[b], bounds[b + 1])``, possibly empty."""
    bounds = np.empty(n_bands + 1, np.int64)
    total = 0
    for c in counts:
        total += c
    bounds[0] = 0
    acc = 0
    bin_ = 0
    for b in range(1, n_bands):
        if total == 0:
            bounds[b] = b * height // n_bands
            continue
        goal = total * b // n_bands
        while bin_ < counts.size and acc + counts[bin_] <= goal:
            acc += counts[bin_]
            bin_ += 1
        bounds[b] = min(max(bin_ * ROWS_PER_BIN, bounds[b - 1]), height)
    bounds[n_bands] = height
    return bounds


def band_work(counts, row_work, height):
    """The work per ``ROWS_PER_BIN`` rows for :func:`balanced_bands`: ``counts`` (chunks,
    n_bins) summed over its chunks, plus ``row_work`` for each of the bin's rows."""
    work = counts.sum(axis=0)
    if row_work:
        work += row_work * ROWS_PER_BIN
        work[-1] -= row_work * (len(work) * ROWS_PER_BIN - height)
    return work


#: Rows of the per-edge records of :func:`plain_setup`, each (E,) int32: the first pixel,
#: the packed steps ``n | a << 15 | steep << 30 | negative << 31`` and the rows
#: ``jlo | jhi << 16`` (-1 for an edge of the general path).
REC_PIX, REC_STEPS, REC_ROWS = range(3)
REC_FIELDS = 3
#: Rows of the block summaries of :func:`plain_setup`, each (B,) int32 for the blocks of
#: ``BLOCK`` consecutive edges: the lowest first row and the highest last row of the block's
#: plain records (``BLOCK_EMPTY`` and -1 when it has none) and how many of its edges take the
#: general path. A band skips a block of plain edges wholly outside its rows and steps one
#: wholly inside without testing each edge: meshes list nearby faces together, so most
#: blocks lie in one band, and a band reads the records of few blocks besides its own.
BLOCK_LO, BLOCK_HI, BLOCK_GENERAL = range(3)
BLOCK_FIELDS = 3
BLOCK = 512
BLOCK_EMPTY = 1 << 20
#: Images at most this many pixels a side fit ``n``, ``a`` and the rows into 15 and 16
#: bits; larger ones draw every edge by the general path.
_PACKED_LIMIT = 1 << 15
#: Work of one plain edge beyond its pixels, in pixel steps (setup, loop entry and exit),
#: for balancing the bands.
_EDGE_WORK = 4
#: Work of one image row in the plain path, in pixel steps: clearing its colour and mask
#: bytes and painting the marked pixels (a band of rows with no edges is not free). Fitted
#: on the two bands' times at 1920x1080 (bunny, ogre, sportsCar and armadillo, perspective
#: and isometric; edges in a spatial order): 300 left the slower band 0-4 % above the mean,
#: 800 up to 11 %, 100 up to 9 %.
ROW_WORK = 300
SETUP_CHUNKS = 16
#: Records of each chunk that :func:`plain_setup` counts for the balance at most (about; it
#: samples beyond).
_WORK_SAMPLES = 1 << 10


def n_blocks(n_edges):
    """Blocks of :data:`BLOCK` edges (the last one partial) of ``n_edges`` edges."""
    return (n_edges + BLOCK - 1) // BLOCK


@kernel
def plain_setup(slot, counter, pixels, edges, width, height, recs, blocks, work):
    """Per-edge Bresenham setup of plain (no depth test, no anti-aliasing) edges, once.

    An edge whose two ends have a pixel in ``pixels`` (:func:`project_vertices`) lies
    inside the image with its whole integer line; its record (column ``e`` of ``recs``,
    (REC_FIELDS, E) int32) gets the loop state that the general path
    (:func:`rasterkit.raster.kernels.edges.bresenham_start`) would start from: the first pixel
    (index into the flattened image), ``n`` and ``a = |dv|`` with
    two bits (steep; minor steps go negative), and the rows ``jlo <= jhi`` it spans.
    Every other edge gets rows -1 and is drawn by the general path. ``blocks``
    (BLOCK_FIELDS, :func:`n_blocks`) int32 gets each block's summary (``BLOCK_LO`` ...).

    ``work`` (SETUP_CHUNKS, n_bins) int64, zeros on entry, gets the work of each chunk's
    records (their pixels plus ``_EDGE_WORK`` each) per ``ROWS_PER_BIN`` image rows, by the
    row of their middle: what :func:`balanced_bands` shares out in plain mode (the vertex
    counts of :func:`project_vertices` follow the vertices, not the pixels, and left one of
    two bands 60 % of the work on some models). Records of the general path are not
    counted. Beyond ``_WORK_SAMPLES`` records a chunk counts only every ``s``-th edge
    (``e % s == 0``), ``s`` times over: an estimate is all the balance needs.

    In blocks of ``BLOCK`` edges (the chunks are whole blocks): first the ends are
    gathered, then the arithmetic runs over the block without a branch, which LLVM turns
    into vector instructions (16 edges at a time with AVX-512: ten times faster than edge by
    edge with branches). Stepping from the end with the smaller major coordinate is the same
    as deciding on the real ends (the integer ends differ along the major axis unless the
    line is a single pixel). A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot``
    unused, chunks claimed through ``counter``).
    """
    m = edges.shape[0]
    nb = (m + BLOCK - 1) // BLOCK  # n_blocks(m)
    packed = width <= _PACKED_LIMIT and height <= _PACKED_LIMIT
    ends = np.empty((2, BLOCK), np.int64)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= SETUP_CHUNKS:
            break
        first, last = nb * ch // SETUP_CHUNKS, nb * (ch + 1) // SETUP_CHUNKS
        for b in range(first, last):
            start = b * BLOCK
            count = min(BLOCK, m - start)
            for k in range(count):
                ends[0, k] = pixels[edges[start + k, 0]] if packed else -1
                ends[1, k] = pixels[edges[start + k, 1]]
            lo, hi, general = _setup_block(ends[0], ends[1], count, width, recs[REC_PIX], recs[REC_STEPS],
                                           recs[REC_ROWS], start)
            blocks[BLOCK_LO, b], blocks[BLOCK_HI, b], blocks[BLOCK_GENERAL, b] = lo, hi, general
        _count_work(recs, first * BLOCK, min(last * BLOCK, m), work[ch])


@kernel
def _setup_block(first, second, count, width, pix, steps, rows, offset):
    """Records ``offset .. offset + count - 1`` of :func:`plain_setup` from the end pixels
    ``first[k], second[k]`` (``x | y << 32``, -1 outside); returns the block's summary
    ``(lo, hi, general)``. 0/1 integers and products in place of if/else: no branch, so
    the loop vectorises (and edge directions are random: branches would be mispredicted
    half the time)."""
    w = np.int32(width)
    one = np.int32(1)
    lo, hi, general = np.int32(BLOCK_EMPTY), np.int32(-1), np.int32(0)
    for k in range(np.uint64(count)):
        p0, p1 = first[k], second[k]
        x0, y0 = np.int32(p0 & 0xFFFFFFFF), np.int32(p0 >> 32)
        x1, y1 = np.int32(p1 & 0xFFFFFFFF), np.int32(p1 >> 32)
        ok = np.int32((x0 | x1) >= 0)
        dx, dy = x1 - x0, y1 - y0
        sx, sy = dx >> np.int32(31), dy >> np.int32(31)  # 0 or -1: the signs
        adx, ady = (dx ^ sx) - sx, (dy ^ sy) - sy
        steep = np.int32(ady > adx)
        n = adx + steep * (ady - adx)
        a = ady + steep * (adx - ady)
        swap = (steep & -sy) | ((one - steep) & -sx)  # step from the second end
        dv = steep * dx + (one - steep) * dy
        negative = (np.int32(dv < 0) ^ swap) & np.int32(a != 0)
        u = np.uint64(offset) + k
        pix[u] = (y0 + swap * dy) * w + x0 + swap * dx
        steps[u] = n | (a << np.int32(15)) | (steep << np.int32(30)) | (negative << np.int32(31))
        jlo = y0 + dy * np.int32(dy < 0)
        jhi = y0 + y1 - jlo
        rows[u] = ok * ((jlo | (jhi << np.int32(16))) + one) - one
        lo = min(lo, jlo + (one - ok) * np.int32(BLOCK_EMPTY))
        hi = max(hi, ok * (jhi + one) - one)
        general += one - ok
    return lo, hi, general


@kernel(inline="always")
def _count_work(recs, start, stop, work):
    """Add the sampled work of records ``start .. stop - 1`` into ``work`` (n_bins,) int64
    (:func:`plain_setup`)."""
    stride = max((stop - start) // _WORK_SAMPLES, 1)
    for e in range(start + (-start) % stride, stop, stride):
        u = np.uint64(e)
        rows = np.int64(recs[REC_ROWS, u])
        if rows >= 0:
            middle = ((rows & 0xFFFF) + (rows >> 16)) >> 1
            work[middle // ROWS_PER_BIN] += stride * ((np.int64(recs[REC_STEPS, u]) & 0x7FFF) + 1 + _EDGE_WORK)
