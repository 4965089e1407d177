"""Triangle setup and rasterization in integer fixed point.

Coverage
    Vertices are snapped to 1/256 pixel (``SUBPIXEL_BITS = 8``) and every triangle is stored
    with a positive raster signed area (clockwise on screen), so that the edge function of
    edge ``a -> b``,

        E(P) = (Xb - Xa) * (Py - Ya) - (Yb - Ya) * (Px - Xa),

    is positive inside for all three edges. ``E`` is evaluated exactly in int64 at pixel
    centres ``P = (256 i + 128, 256 j + 128)``. A centre is covered when, for each edge,
    ``E > 0``, or ``E == 0`` and the edge is a *top* edge (horizontal, interior below it:
    ``dy == 0 and dx > 0``) or a *left* edge (``dy < 0``). That is the top-left rule of
    Direct3D / OpenGL: two triangles sharing an edge never cover a centre twice and leave no
    gap, because the shared edge is left/top for exactly one of them.

Spans
    For a row ``j`` each edge function is affine in ``i`` with integer slope
    ``s = -256 dy``, so its covered half-line is ``i >= ceil(-c / s)`` or
    ``i <= floor(c / -s)``. The row's span is the intersection of the three half-lines
    with the bounding box; each bound is stepped exactly from row to row (quotient and
    remainder, no division per row), so the pixel loop touches only covered pixels and has
    no coverage test. Triangles at most BLOCK pixels wide skip the spans: testing one
    vector block of pixels per row for coverage is cheaper for them.

Depth
    ``z = zh / w`` is affine in raster space: ``z(i, j) = zc + gx * i + gy * j``, a plane
    through the three snapped vertices. Along a span it is evaluated in float64 at the
    span's start and stepped in float32 (both ends are inside the triangle, so the step
    adds at most the triangle's depth range and the error stays near float32 rounding);
    in a block (narrow triangles) it is computed in float64 per pixel, as the block may
    start outside the triangle. The test is ``z < depth`` (less-than; the first of
    equal-depth triangles wins), and a passing pixel writes ``depth`` and the
    band's visibility buffer ``lid`` (the index of the triangle's face); colours are
    written once per pixel afterwards (:func:`rasterkit.kernels.shade.resolve_row`).

Records
    The setup stage turns face ``f`` into record ``f`` or, when clipping cut it, into a fan
    of records numbered from M up (``fan_face[t - M]`` is their face): ``tri_xy (T, 6)
    int32`` fixed-point ``X0, Y0, X1, Y1, X2, Y2``; ``tri_z (T, 3) float32`` depths;
    ``tri_box (T, 4) int32`` the clamped pixel bounding box ``i_lo, i_hi, j_lo, j_hi``
    (empty when ``j_lo > j_hi``: culled, empty, outside or cut).
"""

from __future__ import annotations

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.clip import (
    CUT_MASK,
    DEGENERATE_BIT,
    FACE_INSIDE,
    FACE_NEEDS_CUT,
    FACE_NONFINITE,
    MAX_POLYGON,
    NONFINITE_BIT,
    classify_face,
    clip_planes,
    cut_face,
    project_vertex,
    vertex_code,
)
from rasterkit.kernels.cull import is_culled
from rasterkit.kernels.intrinsics import fetch_add, prefetch_row
from rasterkit.kernels.shade import flat_colors

SUBPIXEL_BITS = 8
ONE = 1 << SUBPIXEL_BITS
HALF = ONE >> 1

#: Most triangles one cut face can become (a fan over a MAX_POLYGON-gon).
MAX_FAN = MAX_POLYGON - 2

# What happened to a face; the setup kernels count faces per outcome (their ``tally``).
STATUS_DRAWN = 0
STATUS_CULLED = 1
STATUS_EMPTY = 2  # zero area after snapping, or covers no pixel centre of the image
STATUS_OUTSIDE = 3
STATUS_NONFINITE = 4
N_STATUS = 5

#: Faces (and vertices) are processed in this many contiguous chunks, setup and binning
#: using the same ones. A constant, so that nothing depends on the thread count.
N_CHUNKS = 64


@kernel(inline="always")
def chunk_range(n, c):
    """Items ``[start, stop)`` of chunk ``c`` of ``N_CHUNKS`` chunks of ``n`` faces or vertices."""
    return (n * c) // N_CHUNKS, (n * (c + 1)) // N_CHUNKS


@kernel(inline="always")
def snap(v):
    """Raster coordinate ``v`` (pixels, float) -> fixed point (int64, 1/256 px), rounded."""
    return np.int64(np.floor(v * ONE + 0.5))


@kernel(inline="always")
def _ceil_div(a, b):
    """``ceil(a / b)`` for int64 ``a`` and ``b > 0``."""
    return -((-a) // b)


@kernel(inline="always")
def pixel_bounds(lo, hi):
    """Pixel indices whose centres ``256 k + 128`` lie in the fixed-point range [lo, hi]."""
    return _ceil_div(lo - HALF, ONE), (hi - HALF) // ONE


@kernel(inline="always")
def signed_area2(x0, y0, x1, y1, x2, y2):
    """Twice the raster signed area of a fixed-point triangle (int64, exact)."""
    return (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)


@kernel(inline="always")
def _empty_box(t, tri_box):
    """Mark record ``t`` as not drawn (binning skips it)."""
    tri_box[t, 0], tri_box[t, 1], tri_box[t, 2], tri_box[t, 3] = 0, -1, 0, -1


@kernel(inline="always")
def setup_triangle(x0, y0, z0, x1, y1, z1, x2, y2, z2, width, height, cull_mode, t, tri_xy, tri_z, tri_box):
    """Cull and bound a fixed-point triangle into record ``t``.

    Parameters
    ----------
    x0, y0, z0, x1, y1, z1, x2, y2, z2
        Vertices in the face's winding order: fixed-point raster ``x, y`` (:func:`snap`,
        within the guard band) and depth ``z``.
    width, height : int
        Image size; the bounding box is clamped to it.
    cull_mode : int
        A :mod:`rasterkit.kernels.cull` mode.
    t : int
        Record to write.
    tri_xy, tri_z, tri_box
        Record arrays (see the module docstring). The box is left empty unless drawn.

    Returns
    -------
    int
        STATUS_DRAWN, STATUS_CULLED or STATUS_EMPTY.
    """
    _empty_box(t, tri_box)
    area2 = signed_area2(x0, y0, x1, y1, x2, y2)
    if area2 == 0:
        return STATUS_EMPTY
    if is_culled(area2, cull_mode):
        return STATUS_CULLED
    i_lo, i_hi = pixel_bounds(min(x0, x1, x2), max(x0, x1, x2))
    j_lo, j_hi = pixel_bounds(min(y0, y1, y2), max(y0, y1, y2))
    i_lo, i_hi = max(i_lo, 0), min(i_hi, width - 1)
    j_lo, j_hi = max(j_lo, 0), min(j_hi, height - 1)
    if i_lo > i_hi or j_lo > j_hi:
        return STATUS_EMPTY
    if area2 < 0:  # store clockwise on screen, so every edge function is positive inside
        x1, y1, z1, x2, y2, z2 = x2, y2, z2, x1, y1, z1
    tri_xy[t, 0], tri_xy[t, 1], tri_xy[t, 2] = x0, y0, x1
    tri_xy[t, 3], tri_xy[t, 4], tri_xy[t, 5] = y1, x2, y2
    tri_z[t, 0], tri_z[t, 1], tri_z[t, 2] = z0, z1, z2
    tri_box[t, 0], tri_box[t, 1], tri_box[t, 2], tri_box[t, 3] = i_lo, i_hi, j_lo, j_hi
    return STATUS_DRAWN


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
        z = zs + gx * np.float32(k)
        old = depth[ru, i]
        closer = z < old
        depth[ru, i] = z if closer else old
        lid[ru, i] = t if closer else lid[ru, i]
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
        old = depth[ru, u]
        win = inside & (z < old)
        depth[ru, u] = z if win else old
        lid[ru, u] = t if win else lid[ru, u]
        covered += inside
    return covered


@kernel(inline="always")
def _raster_masked(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, t, row_lo, row_hi):
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
def _raster_spans(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, t, row_lo, row_hi):
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
    are left alone. A worker of :func:`rasterkit._jit.run_parallel` (``slot`` unused; the
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
    (:func:`_raster_masked`); wider ones compute each row's span (:func:`_raster_spans`).
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
    e0, e1, e2 = triangle_edges(x0, y0_, x1, y1_, x2, y2)
    zc, gx, gy = depth_plane(
        x0, y0_, x1, y1_, x2, y2, float(tri_z[t, 0]), float(tri_z[t, 1]), float(tri_z[t, 2])
    )
    i_lo, i_hi = np.int64(tri_box[t, 0]), np.int64(tri_box[t, 1])
    tag = np.int32(tag)
    if i_hi - i_lo < BLOCK and depth.shape[1] >= BLOCK:
        return _raster_masked(
            depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, tag, row_lo, row_hi
        )
    return _raster_spans(depth, lid, y0, j_lo, j_hi, i_lo, i_hi, e0, e1, e2, zc, gx, gy, tag, row_lo, row_hi)


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


#: Columns of the per-vertex rows of :func:`setup_vertices` (z in the float32 view).
_V_CODE, _V_X, _V_Y, _V_Z = range(4)


@kernel
def _setup_vertex_chunk(ch, clip, width, height, corners, depths):
    """:func:`setup_vertices` for the vertices of chunk ``ch``."""
    start, stop = chunk_range(clip.shape[0], ch)
    for i in range(np.uint64(start), np.uint64(stop)):
        code = vertex_code(clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3], width, height)
        corners[i, _V_CODE] = code
        if code & CUT_MASK or code & (NONFINITE_BIT | DEGENERATE_BIT):
            corners[i, _V_X], corners[i, _V_Y], depths[i, _V_Z] = 0, 0, 0.0
            continue
        x, y, z = project_vertex(clip, i)
        corners[i, _V_X], corners[i, _V_Y], depths[i, _V_Z] = snap(x), snap(y), z


@kernel
def setup_vertices(slot, counter, clip, width, height, corners, depths):
    """Vertex pass: classify every vertex once and, where it is safe, project and snap it.

    A vertex is shared by about six faces of a closed mesh, so doing this per vertex and
    not per face corner saves most of the setup work.

    Parameters
    ----------
    clip : (N, 4) float64
        Homogeneous raster coordinates.
    width, height : int
        Image size.
    corners : (N, 4) int32
        Out, one 16-byte row per vertex (what a face reads of each corner, in one cache
        line): column ``_V_CODE`` the :func:`rasterkit.kernels.clip.vertex_code`;
        ``_V_X, _V_Y`` the fixed-point raster ``x, y`` (:func:`snap`) of vertices whose code
        has no CUT_MASK, NONFINITE or DEGENERATE bit (0 otherwise).
    depths : (N, 4) float32
        The same memory as ``corners`` seen as float32: out, column ``_V_Z`` the depth
        ``zh / w`` of the same vertices.

    A worker of :func:`rasterkit._jit.run_parallel`: ``slot`` is unused, the N_CHUNKS
    chunks are claimed through ``counter``.
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        _setup_vertex_chunk(ch, clip, width, height, corners, depths)


@kernel(inline="always")
def count_bands(t, tri_box, band_shift, band_counts, ch):
    """Count drawn record ``t`` into the bands of ``1 << band_shift`` rows its box spans.

    This is the counting pass of binning (:mod:`rasterkit.kernels.tiles`), done here while
    the box is at hand: ``band_counts[ch, b]`` counts chunk ``ch``'s records in band ``b``.
    (A shift, not a division: the band height is a run-time value, and a 64-bit division
    costs tens of cycles per face.)
    """
    for b in range(tri_box[t, 2] >> band_shift, (tri_box[t, 3] >> band_shift) + 1):
        band_counts[ch, b] += 1


@kernel(inline="always")
def _setup_fast_face(faces, f, corners, depths, width, height, cull_mode, tri_xy, tri_z, tri_box):
    """Set up face ``f`` (FACE_INSIDE) into record ``f`` from the vertex pass; its status."""
    a, b, c = np.uint64(faces[f, 0]), np.uint64(faces[f, 1]), np.uint64(faces[f, 2])
    return setup_triangle(
        np.int64(corners[a, _V_X]), np.int64(corners[a, _V_Y]), depths[a, _V_Z],
        np.int64(corners[b, _V_X]), np.int64(corners[b, _V_Y]), depths[b, _V_Z],
        np.int64(corners[c, _V_X]), np.int64(corners[c, _V_Y]), depths[c, _V_Z],
        width, height, cull_mode, f, tri_xy, tri_z, tri_box,
    )


#: Faces ahead whose corners the face pass asks to be fetched: meshes whose vertices are
#: not in surface order (the bunny) gather each corner from anywhere in memory.
PREFETCH_AHEAD = 8


#: Mean jump between the first corners of consecutive faces (vertex rows) above which the
#: face pass prefetches; below it the rows come in order and the hardware fetches them.
SCATTERED_JUMP = 64


@kernel(inline="always")
def _scattered(faces, start, stop):
    """Whether the faces ``start .. stop - 1`` read their corners from scattered rows,
    judged on the first 32: the prefetches pay off only then."""
    n = min(stop - start, 33)
    jump = 0
    for f in range(start + 1, start + n):
        jump += abs(faces[f, 0] - faces[f - 1, 0])
    return jump > SCATTERED_JUMP * (n - 1)


@kernel(inline="always")
def _prefetch_corners(faces, f, corners):
    for k in range(3):
        prefetch_row(corners, faces[f, k])


@kernel
def _setup_chunk(
    ch,
    faces,
    corners,
    depths,
    width,
    height,
    cull_mode,
    tri_xy,
    tri_z,
    tri_box,
    cut_mask,
    n_fan,
    band_shift,
    band_counts,
    tally,
    lit,
    listed,
):
    """:func:`setup_faces` for the faces of chunk ``ch``; returns how many need cutting,
    or -1 (and stops) at a vertex index out of range.

    A face to cut only gets its mask here (and counts as STATUS_OUTSIDE until
    :func:`setup_cut_faces` has cut it).
    """
    start, stop = chunk_range(faces.shape[0], ch)
    on, normals, base, scale, light, ambient, two_sided, packed = lit
    seen, n_listed = listed
    cut = 0
    n_seen = 0
    n_vertices = np.uint64(corners.shape[0])
    scattered = _scattered(faces, start, stop)
    for f in range(np.uint64(start), np.uint64(stop)):
        if scattered and f + PREFETCH_AHEAD < stop:
            _prefetch_corners(faces, f + PREFETCH_AHEAD, corners)  # never faults, even out of range
        a, b, c = np.uint64(faces[f, 0]), np.uint64(faces[f, 1]), np.uint64(faces[f, 2])
        if a >= n_vertices or b >= n_vertices or c >= n_vertices:  # a negative index too
            return -1  # the caller raises before anything is drawn
        cls, mask = classify_face(corners[a, _V_CODE], corners[b, _V_CODE], corners[c, _V_CODE])
        cut_mask[f] = mask
        n_fan[f] = 0
        if cls == FACE_INSIDE:
            outcome = _setup_fast_face(faces, f, corners, depths, width, height, cull_mode, tri_xy, tri_z, tri_box)
            if outcome == STATUS_DRAWN:
                count_bands(f, tri_box, band_shift, band_counts, ch)
                seen[start + n_seen] = f
                n_seen += 1
        else:
            _empty_box(f, tri_box)
            outcome = STATUS_NONFINITE if cls == FACE_NONFINITE else STATUS_OUTSIDE
            if cls == FACE_NEEDS_CUT:
                cut += 1
                seen[start + n_seen] = f
                n_seen += 1
        tally[ch, outcome] += 1
    n_listed[ch] = n_seen
    # The colours in a loop of their own: inside the branches above they would wait on
    # every mispredicted drawn / culled decision.
    if on:
        flat_colors(normals, seen, start, n_seen, base, scale, light, ambient, two_sided, packed)
    return cut


@kernel
def setup_faces(
    slot,
    counter,
    faces,
    corners,
    depths,
    width,
    height,
    cull_mode,
    tri_xy,
    tri_z,
    tri_box,
    cut_mask,
    n_fan,
    band_shift,
    band_counts,
    tally,
    lit,
    listed,
    cut,
):
    """Face pass: classify every face; set up the ones that need no cutting.

    Record ``f`` belongs to face ``f`` (empty unless the face is drawn uncut). Faces that
    cross a NEAR/FAR/guard-band plane get ``cut_mask[f]`` (the planes);
    :func:`count_fans` and :func:`setup_cut_faces` handle those.

    Parameters
    ----------
    faces : (M, 3) int64
        Vertex indices (a face out of range makes the call return -1).
    corners, depths
        From :func:`setup_vertices`.
    width, height, cull_mode : int
    tri_xy, tri_z, tri_box
        Record arrays with at least M records.
    cut_mask, n_fan : (M,) int8
        Out: the planes cutting each face (0: none); 0 (filled in by :func:`count_fans`).
    band_shift : int
        log2 of the rows per band of the binning (:data:`rasterkit.kernels.tiles.BAND_SHIFT`).
    band_counts : (N_CHUNKS, n_bands) int64
        Zeros in; out: drawn records per chunk and band (:func:`count_bands`).
    tally : (N_CHUNKS, N_STATUS + 1) int64
        Zeros in; out: faces per chunk and STATUS_* (column N_STATUS: faces cut with
        something left, counted by :func:`setup_cut_faces`).
    lit : tuple
        ``(on, normals, base, scale, light, ambient, two_sided, packed)``: when ``on``,
        each face that is drawn uncut or is to be cut gets its flat Lambert colour in
        ``packed`` (M,) uint32 (:func:`rasterkit.kernels.shade.flat_colors`); the other
        entries are left as they were.
    listed : tuple
        ``(faces_listed, n_listed)``: out, the faces drawn uncut or to be cut, in order,
        chunk ``ch``'s from ``chunk_range(M, ch)[0]`` in ``faces_listed`` (M,) int32, their
        number in ``n_listed`` (N_CHUNKS,) int64. Binning and shading visit only these.

    cut : (N_CHUNKS,) int64
        Out: per chunk, the number of faces to cut, or -1 when a face has a vertex index
        outside ``0 .. N - 1`` (checked here, where every index is read anyway, instead of
        in a pass of its own; nothing is read through such an index, and the records are
        then incomplete: the caller must not go on).

    A worker of :func:`rasterkit._jit.run_parallel` (``slot`` unused, chunks claimed
    through ``counter``).
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        cut[ch] = _setup_chunk(
            ch,
            faces,
            corners,
            depths,
            width,
            height,
            cull_mode,
            tri_xy,
            tri_z,
            tri_box,
            cut_mask,
            n_fan,
            band_shift,
            band_counts,
            tally,
            lit,
            listed,
        )


@kernel
def _count_fan_chunk(ch, clip, faces, planes, cut_mask, n_fan):
    """:func:`count_fans` for the faces of chunk ``ch``; returns their record count."""
    p = np.empty((MAX_POLYGON, 3))
    start, stop = chunk_range(faces.shape[0], ch)
    records = 0
    for f in range(start, stop):
        if cut_mask[f] != 0:
            n_fan[f] = max(cut_face(clip, faces, f, planes, np.int64(cut_mask[f]), p) - 2, 0)
            records += n_fan[f]
    return records


@kernel
def count_fans(slot, counter, clip, faces, width, height, cut_mask, n_fan, records):
    """Cut pass 1: cut the faces flagged by :func:`setup_faces` to count their records.

    Parameters
    ----------
    clip, faces, width, height
        As for :func:`setup_vertices` and :func:`setup_faces`.
    cut_mask : (M,) int8
        From :func:`setup_faces`.
    n_fan : (M,) int8
        Out: records (fan triangles) of each cut face; left alone for the others.

    records : (N_CHUNKS,) int64
        Out: records needed by the cut faces of each chunk.

    A worker of :func:`rasterkit._jit.run_parallel` (``slot`` unused).
    """
    planes = clip_planes(width, height)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        records[ch] = _count_fan_chunk(ch, clip, faces, planes, cut_mask, n_fan)


@kernel
def _setup_fan_chunk(
    ch,
    clip,
    faces,
    width,
    height,
    cull_mode,
    planes,
    t,
    fan_face,
    tri_xy,
    tri_z,
    tri_box,
    cut_mask,
    band_shift,
    band_counts,
    tally,
):
    """:func:`setup_cut_faces` for the faces of chunk ``ch``, from record ``t`` on."""
    p = np.empty((MAX_POLYGON, 3))
    start, stop = chunk_range(faces.shape[0], ch)
    m = faces.shape[0]
    for f in range(start, stop):
        if cut_mask[f] == 0:
            continue
        n = cut_face(clip, faces, f, planes, np.int64(cut_mask[f]), p)
        best = STATUS_OUTSIDE
        for k in range(1, n - 1):
            fan_face[t - m] = f
            x0, y0, x1, y1 = snap(p[0, 0]), snap(p[0, 1]), snap(p[k, 0]), snap(p[k, 1])
            x2, y2 = snap(p[k + 1, 0]), snap(p[k + 1, 1])
            drawn = setup_triangle(
                x0,
                y0,
                p[0, 2],
                x1,
                y1,
                p[k, 2],
                x2,
                y2,
                p[k + 1, 2],
                width,
                height,
                cull_mode,
                t,
                tri_xy,
                tri_z,
                tri_box,
            )
            if drawn == STATUS_DRAWN:
                count_bands(t, tri_box, band_shift, band_counts, ch)
            best = min(best, drawn)
            t += 1
        tally[ch, STATUS_OUTSIDE] -= 1  # what setup_faces counted it as
        tally[ch, best] += 1
        tally[ch, N_STATUS] += best != STATUS_OUTSIDE


@kernel
def setup_cut_faces(
    slot,
    counter,
    clip,
    faces,
    width,
    height,
    cull_mode,
    fan_start,
    fan_face,
    tri_xy,
    tri_z,
    tri_box,
    cut_mask,
    band_shift,
    band_counts,
    tally,
):
    """Cut pass 2: cut the flagged faces again and set up their fans.

    The fans of chunk ``ch`` go to consecutive records from ``fan_start[ch]`` (>= M), in
    face order (binning walks them in the same order); ``fan_face[t - M]`` is the face of
    fan record ``t``. A cut face is STATUS_DRAWN when any of its triangles is drawn, else
    STATUS_CULLED when any is culled, else STATUS_EMPTY (STATUS_OUTSIDE when nothing was
    left of it). Drawn fan records are added to ``band_counts``, and the new statuses to
    ``tally``, as in :func:`setup_faces`. A worker of :func:`rasterkit._jit.run_parallel`
    (``slot`` unused).
    """
    planes = clip_planes(width, height)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        _setup_fan_chunk(
            ch,
            clip,
            faces,
            width,
            height,
            cull_mode,
            planes,
            fan_start[ch],
            fan_face,
            tri_xy,
            tri_z,
            tri_box,
            cut_mask,
            band_shift,
            band_counts,
            tally,
        )
