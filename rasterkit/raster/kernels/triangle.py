"""Triangle rasterization in integer fixed point: coverage, spans and depth, per band.

Coverage    Vertices are snapped to 1/256 pixel (``SUBPIXEL_BITS = 8``) and every triangle is stored
    with a positive raster signed area (clockwise on screen), so that the edge function of
    edge ``a -> b``,

        E(P) = (Xb - Xa) * (Py - Ya) - (Yb - Ya) * (Px - Xa),

    is positive inside for all three edges. ``E`` is evaluated exactly in int64 at pixel
    centres ``P = (256 i + 128, 256 j + 128)``. A centre is covered when, for each edge,
    ``E > 0``, or ``E == 0`` and the edge is a *top* edge (horizontal, interior below it:
    ``dy == 0 and dx > 0``) or a *left* edge (``dy < 0``). That is the top-left rule of
    Direct3D / OpenGL: two triangles sharing an edge never cover a centre twice and leave no
    gap, because the shared edge is left/top for exactly one of them.
Spans    For a row ``j`` each edge function is affine in ``i`` with integer slope
    ``s = -256 dy``, so its covered half-line is ``i >= ceil(-c / s)`` or
    ``i <= floor(c / -s)``. The row's span is the intersection of the three half-lines
    with the bounding box; each bound is stepped exactly from row to row (quotient and
    remainder, no division per row), so the pixel loop touches only covered pixels and has
    no coverage test. Triangles at most BLOCK pixels wide skip the spans: testing one
    vector block of pixels per row for coverage is cheaper for them.
Depth    ``z = zh / w`` is affine in raster space: ``z(i, j) = zc + gx * i + gy * j``, a plane
    through the three snapped vertices. Along a span it is evaluated in float64 at the
    span's start and stepped in float32 (both ends are inside the triangle, so the step
    adds at most the triangle's depth range and the error stays near float32 rounding);
    in a block (narrow triangles) it is computed in float64 per pixel, as the block may
    start outside the triangle. The test is ``z < depth`` (less-than; the first of
    equal-depth triangles wins), and a passing pixel writes ``depth`` and the
    band's visibility buffer ``lid`` (the index of the triangle's face); colours are
    written once per pixel afterwards (:func:`rasterkit.raster.kernels.shade.resolve_row`).

The records come from the setup stage (:mod:`rasterkit.raster.kernels.face_setup`), binned into bands
by :mod:`rasterkit.raster.kernels.bands`, which calls :func:`raster_band` for each record of a band.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add, kept
from rasterkit.raster.kernels.face_setup import HALF, N_CHUNKS, ONE, chunk_range, pixel_bounds, signed_area2, snap


@kernel(inline="always")
def _edge(xa, ya, xb, yb):
    """Edge ``a -> b`` of a clockwise fixed-point triangle as row-wise constraints.

    Returns ``(c0, dc, s)``: in row ``j`` the edge covers the pixels ``i`` with
    ``c0 + dc * j + s * i >= 0``. The top-left rule is folded into ``c0``: a bias of -1 on
    edges that are neither top nor left turns ``E >= 0`` into ``E > 0`` (E is an integer).
    """
    dx = xb - xa
    dy = yb - ya
    top_left = dy < 0 or (dy == 0 and dx > 0)
    bias = 0 if top_left else 1
    c0 = dx * (HALF - ya) - dy * (HALF - xa) - bias
    return c0, ONE * dx, -ONE * dy


@kernel(inline="always")
def _bound(c, dc, s):
    """Exact, row-stepped pixel bound of one edge, starting at the row where it is ``c``.

    The edge covers the ``i`` with ``c + s * i >= 0``: for ``s > 0`` that is
    ``i >= ceil(-c / s)``, for ``s < 0`` it is ``i <= floor(c / -s)``. The bound is kept as
    a quotient and remainder (Bresenham-style) and stepped by ``dc`` per row with two
    additions and a compare, so no row needs a division.

    Returns ``(q, r, dq, dr, d, kind)``: ``kind`` 1 for a lower bound ``i >= q``, -1 for
    an upper bound ``i <= q``, 0 for a horizontal edge (``q`` is then ``c`` itself: the
    row is covered when ``q >= 0``).
    """
    if s == 0:
        return c, np.int64(0), dc, np.int64(0), np.int64(1), np.int64(0)
    if s > 0:
        d, a, step, kind = s, s - 1 - c, -dc, np.int64(1)
    else:
        d, a, step, kind = -s, c, dc, np.int64(-1)
    q, dq = a // d, step // d
    return q, a - q * d, dq, step - dq * d, d, kind


@kernel(inline="always")
def _step(bound):
    """``bound`` (:func:`_bound`) on the next row."""
    q, r, dq, dr, d, kind = bound
    q, r = q + dq, r + dr
    if r >= d:
        q, r = q + 1, r - d
    return q, r, dq, dr, d, kind


@kernel(inline="always")
def _clamp(bound, lo, hi):
    """Intersect the pixel range [lo, hi] with ``bound`` (:func:`_bound`)."""
    q, kind = bound[0], bound[5]
    if kind > 0:
        lo = max(lo, q)
    elif kind < 0:
        hi = min(hi, q)
    elif q < 0:
        hi = lo - 1
    return lo, hi


@kernel(inline="always")
def row_bounds(j, e0, e1, e2):
    """The three :func:`_bound` of a triangle's edges (:func:`triangle_edges`) at row ``j``."""
    return (
        _bound(e0[0] + e0[1] * j, e0[1], e0[2]),
        _bound(e1[0] + e1[1] * j, e1[1], e1[2]),
        _bound(e2[0] + e2[1] * j, e2[1], e2[2]),
    )


@kernel(inline="always")
def row_span(bounds, lo, hi):
    """Covered pixels of a row within [lo, hi] (empty when lo > hi), from its row_bounds."""
    lo, hi = _clamp(bounds[0], lo, hi)
    lo, hi = _clamp(bounds[1], lo, hi)
    return _clamp(bounds[2], lo, hi)


@kernel(inline="always")
def next_row(bounds):
    """:func:`row_bounds` stepped to the next row."""
    return _step(bounds[0]), _step(bounds[1]), _step(bounds[2])


@kernel(inline="always")
def triangle_edges(x0, y0, x1, y1, x2, y2):
    """The three :func:`_edge` constraints of a clockwise fixed-point triangle."""
    return _edge(x0, y0, x1, y1), _edge(x1, y1, x2, y2), _edge(x2, y2, x0, y0)


@kernel(inline="always")
def depth_plane(x0, y0, x1, y1, x2, y2, z0, z1, z2):
    """Coefficients ``(zc, gx, gy)`` with ``z(i, j) = zc + gx * i + gy * j`` at pixel centres.

    The plane passes through the three fixed-point vertices with depths ``z0, z1, z2``.
    """
    e1x, e1y = float(x1 - x0), float(y1 - y0)
    e2x, e2y = float(x2 - x0), float(y2 - y0)
    scale = ONE / (e1x * e2y - e2x * e1y)
    d1, d2 = z1 - z0, z2 - z0
    gx = (d1 * e2y - d2 * e1y) * scale
    gy = (e1x * d2 - e2x * d1) * scale
    zc = z0 + gx * ((HALF - x0) / ONE) + gy * ((HALF - y0) / ONE)
    return zc, gx, gy


@kernel(inline="always")
def _depth_test_span(depth, lid, r, lo, hi, zs, gx, t):
    """Less-than depth test of the covered pixels ``lo..hi`` of band row ``r``.

    Pixel ``lo + k`` has depth ``zs + gx * k``; winners go to ``depth[r]`` and ``lid[r]``.
    Written so that LLVM vectorises it: compare, then select-and-store, nothing else in
    the loop, and unsigned indices (a signed index makes Numba handle negative indices,
    which keeps LLVM from vectorising). Returns the number of pixels tested.
    """
    ru, base = np.uint64(r), np.uint64(lo)
    for k in range(hi - lo + 1):
        i = base + np.uint64(k)
        z = zs + gx * np.float32(np.int32(k))  # through int32: AVX2 converts those 8 at a time
        old, was = depth[ru, i], lid[ru, i]
        closer = z < old
        depth[ru, i] = z if closer else kept(old)  # a blend and a store, not a masked store
        lid[ru, i] = t if closer else was
    return hi - lo + 1


#: Pixels per block of :func:`_depth_test_block`: 16 float32 lanes of AVX-512.
BLOCK = 16


@kernel(inline="always")
def _depth_test_block(depth, lid, r, start, c0, s0, c1, s1, c2, s2, zs, gx, t):
    """Depth test the pixels ``start .. start + BLOCK - 1`` of band row ``r`` that are covered.

    Pixel ``i`` is covered when every ``c_k + s_k * i >= 0``; its depth is
    ``zs + gx * (i - start)``, in float64: the block may start outside the triangle, where
    a steep plane is far from [0, 1] and float32 would cancel digits. A fixed trip count and
    unsigned indices let LLVM turn the loop into a few vector instructions; the caller keeps
    the block inside the image. Returns the number of covered pixels.
    """
    covered = 0
    ru, base = np.uint64(r), np.uint64(start)
    for k in range(BLOCK):
        i = start + k
        inside = (c0 + s0 * i >= 0) & (c1 + s1 * i >= 0) & (c2 + s2 * i >= 0)
        u = base + np.uint64(k)
        z = np.float32(zs + gx * k)
        old, was = depth[ru, u], lid[ru, u]
        win = inside & (z < old)
        depth[ru, u] = z if win else kept(old)
        lid[ru, u] = t if win else was
        covered += inside
    return covered


@kernel(inline="always")
def raster_masked(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, t, row_lo, row_hi):
    """Rows ``j_lo..j_hi`` of a triangle at most BLOCK pixels wide: one block per row.

    The block starts at the box's left edge (shifted left at the image's right edge: the
    extra pixels fail the edge tests). The rows loop lives here, with the edge values
    stepped from row to row, so the work around each vectorised block is a few scalar
    instructions.
    """
    start = min(i_lo, depth.shape[1] - BLOCK)
    c0, c1, c2 = e0[0] + e0[1] * j_lo, e1[0] + e1[1] * j_lo, e2[0] + e2[1] * j_lo
    covered = 0
    for j in range(j_lo, j_hi + 1):
        r = j - y0
        zs = zc + gx * start + gy * j
        covered += _depth_test_block(depth, lid, r, start, c0, e0[2], c1, e1[2], c2, e2[2], zs, gx, t)
        c0, c1, c2 = c0 + e0[1], c1 + e1[1], c2 + e2[1]
        row_lo[r] = min(row_lo[r], i_lo)
        row_hi[r] = max(row_hi[r], i_hi)
    return covered


@kernel(inline="always")
def raster_spans(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, t, row_lo, row_hi):
    """Rows ``j_lo..j_hi`` of a wide triangle: find each row's span, depth test only it."""
    gx32 = np.float32(gx)
    bounds = row_bounds(j_lo, e0, e1, e2)
    covered = 0
    for j in range(j_lo, j_hi + 1):
        lo, hi = row_span(bounds, i_lo, i_hi)
        bounds = next_row(bounds)
        if lo > hi:
            continue
        r = j - y0
        zs = np.float32(zc + gx * lo + gy * j)
        covered += _depth_test_span(depth, lid, r, lo, hi, zs, gx32, t)
        row_lo[r] = min(row_lo[r], lo)
        row_hi[r] = max(row_hi[r], hi)
    return covered


@kernel
def offset_depths(slot, counter, tri_xy, tri_z, tri_box, n_records, factor, units):
    """Push every drawn record back by ``factor * max(|dz/dx|, |dz/dy|) + units``.

    OpenGL's polygon offset: the slope term grows with how steeply a face recedes, so the
    edges drawn over it afterwards (whose depth is sampled on the line, up to half a pixel
    from the centre where the face's depth was sampled) pass the depth test even on faces
    seen almost edge-on. Depths are in [0, 1] units per pixel; records with an empty box
    are left alone. A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused; the
    records are shared out in N_CHUNKS chunks through ``counter``).
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        start, stop = chunk_range(n_records, ch)
        for t in range(start, stop):
            if tri_box[t, 2] > tri_box[t, 3]:
                continue
            _, gx, gy = depth_plane(
                np.int64(tri_xy[t, 0]), np.int64(tri_xy[t, 1]), np.int64(tri_xy[t, 2]),
                np.int64(tri_xy[t, 3]), np.int64(tri_xy[t, 4]), np.int64(tri_xy[t, 5]),
                float(tri_z[t, 0]), float(tri_z[t, 1]), float(tri_z[t, 2]),
            )
            offset = np.float32(factor * max(abs(gx), abs(gy)) + units)
            for k in range(3):
                tri_z[t, k] += offset


@kernel(inline="always")
def raster_band(t, tag, tri_xy, tri_z, tri_box, y0, y1, depth, lid, row_lo, row_hi):
    """Rasterize record ``t`` into image rows ``[y0, y1)`` (one band).

    Triangles at most BLOCK pixels wide test a whole block per row for coverage
    (:func:`raster_masked`); wider ones compute each row's span (:func:`raster_spans`).
    Both give the same pixels and ids (depths to float32 rounding).

    Parameters
    ----------
    t : int
        Record index (see the module docstring).
    tag : int
        What to write into ``lid`` where the triangle is visible (its face index).
    tri_xy, tri_z, tri_box
        Record arrays.
    y0, y1 : int
        The band's rows.
    depth : (>= y1 - y0, W) float32
        The band's depth rows, row ``j - y0`` for image row ``j`` (rows of the image's depth
        buffer, or a thread's band-sized scratch when the depth is not kept).
    lid : (>= y1 - y0, W) int32
        The band's visibility buffer, row ``j - y0`` for image row ``j``.
    row_lo, row_hi : (>= y1 - y0,) int64
        Per band row, the range of columns that may have been written; widened here.

    Returns
    -------
    int
        Number of covered pixel centres (fragments) that reached the depth test.
    """
    j_lo, j_hi = max(tri_box[t, 2], y0), min(tri_box[t, 3], y1 - 1)
    if j_lo > j_hi:
        return 0
    x0, y0_, x1 = np.int64(tri_xy[t, 0]), np.int64(tri_xy[t, 1]), np.int64(tri_xy[t, 2])
    y1_, x2, y2 = np.int64(tri_xy[t, 3]), np.int64(tri_xy[t, 4]), np.int64(tri_xy[t, 5])
    return raster_vertices(x0, y0_, x1, y1_, x2, y2, tri_z, t, np.int64(tri_box[t, 0]), np.int64(tri_box[t, 1]),
                           j_lo, j_hi, tag, y0, depth, lid, row_lo, row_hi)


@kernel(inline="always")
def raster_vertices(x0, y0_, x1, y1_, x2, y2, tri_z, t, i_lo, i_hi, j_lo, j_hi, tag, y0, depth, lid, row_lo,
                    row_hi):
    """:func:`raster_band` of record ``t`` with its fixed-point vertices given (the
    record's own, or moved to a sample point) and its box ``i_lo..i_hi`` x ``j_lo..j_hi``
    (not empty, inside the band): edge functions, depth plane, then blocks or spans."""
    e0, e1, e2 = triangle_edges(x0, y0_, x1, y1_, x2, y2)
    zc, gx, gy = depth_plane(
        x0, y0_, x1, y1_, x2, y2, float(tri_z[t, 0]), float(tri_z[t, 1]), float(tri_z[t, 2])
    )
    tag = np.int32(tag)
    if i_hi - i_lo < BLOCK and depth.shape[1] >= BLOCK:
        return raster_masked(
            depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, tag, row_lo, row_hi
        )
    return raster_spans(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, tag, row_lo, row_hi)


@kernel
def triangle_pixels(x0, y0, x1, y1, x2, y2):
    """Pixels covered by one triangle under the top-left rule, with no image bounds.

    Parameters
    ----------
    x0, y0, x1, y1, x2, y2 : float
        Raster coordinates of the vertices (pixels), finite and within ``GUARD_BAND``.

    Returns
    -------
    (N, 2) int64
        ``(x, y)`` of the covered pixels, row by row (y ascending), x ascending in a row.
        Either winding gives the same set; zero area gives none.
    """
    sx0, sy0, sx1, sy1, sx2, sy2 = snap(x0), snap(y0), snap(x1), snap(y1), snap(x2), snap(y2)
    area2 = signed_area2(sx0, sy0, sx1, sy1, sx2, sy2)
    if area2 < 0:
        sx1, sy1, sx2, sy2 = sx2, sy2, sx1, sy1
    i_lo, i_hi = pixel_bounds(min(sx0, sx1, sx2), max(sx0, sx1, sx2))
    j_lo, j_hi = pixel_bounds(min(sy0, sy1, sy2), max(sy0, sy1, sy2))
    if area2 == 0:
        j_hi = j_lo - 1
    e0, e1, e2 = triangle_edges(sx0, sy0, sx1, sy1, sx2, sy2)
    n = 0
    bounds = row_bounds(j_lo, e0, e1, e2)
    for j in range(j_lo, j_hi + 1):
        lo, hi = row_span(bounds, i_lo, i_hi)
        bounds = next_row(bounds)
        n += max(hi - lo + 1, 0)
    out = np.empty((n, 2), np.int64)
    k = 0
    bounds = row_bounds(j_lo, e0, e1, e2)
    for j in range(j_lo, j_hi + 1):
        lo, hi = row_span(bounds, i_lo, i_hi)
        bounds = next_row(bounds)
        for i in range(lo, hi + 1):
            out[k, 0], out[k, 1] = i, j
            k += 1
    return out
