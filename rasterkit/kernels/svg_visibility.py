"""Visibility of line segments in vector precision: where each segment passes behind a face.

A point ``P`` of a segment (raster x, y and depth z) is hidden when a front face covers
``P`` and lies in front of it by more than ``eps`` (depth units). The candidate faces are
those the id buffer shows in the 3x3 pixels around ``P`` (a depth pass of the same faces,
back faces culled, as the hidden-line raster mode draws them); each candidate is tested
exactly, in float64: ``P`` inside its projected triangle and its plane's depth at ``P``
(depth ``zh / w`` is affine in raster x, y on a plane). The faces of the segment's own edge
(those with both its end vertices) never hide it, and a face in the same plane does not
either (its depth differs from the line's by rounding only): lines lying on a visible
face are visible, with no dashes from depth fighting.

Each segment is sampled every ``step`` pixels; between two samples whose states differ,
bisection finds the change to ``tol`` pixels. What this can miss, by construction: an
occluder narrower than ``step`` between two samples, and a face that covers ``P`` but no
pixel centre within one pixel of it (a sliver, or a face hidden at those centres by
others): errors within about a pixel of the true outline.

Faces with a corner behind the eye (``w <= 0``) have no raster triangle: for them the
depth buffer at ``P``'s pixel stands in, with the tolerance ``eps_buffer``.
"""

from __future__ import annotations

import math

from rasterkit._jit import kernel
from rasterkit.kernels.intrinsics import fetch_add

#: Segments are handed out to the threads in chunks of this many.
CHUNK = 1024


@kernel(inline="always")
def _own_face(faces, f, a, b):
    i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
    has_a = i0 == a or i1 == a or i2 == a
    has_b = i0 == b or i1 == b or i2 == b
    return has_a and has_b


@kernel(inline="always")
def _face_hides(proj, faces, f, x, y, z, eps):
    """Whether face ``f`` (all corners in front of the eye) covers (x, y) in front of depth z."""
    i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
    x0, y0, z0 = proj[i0, 0], proj[i0, 1], proj[i0, 2]
    e1x, e1y = proj[i1, 0] - x0, proj[i1, 1] - y0
    e2x, e2y = proj[i2, 0] - x0, proj[i2, 1] - y0
    d = e1x * e2y - e2x * e1y
    if d == 0.0:
        return False
    qx, qy = x - x0, y - y0
    l1 = (qx * e2y - e2x * qy) / d
    l2 = (e1x * qy - qx * e1y) / d
    slack = 1e-9
    if l1 < -slack or l2 < -slack or l1 + l2 > 1.0 + slack:
        return False
    zf = z0 + l1 * (proj[i1, 2] - z0) + l2 * (proj[i2, 2] - z0)
    return zf < z - eps


@kernel(inline="always")
def point_hidden(x, y, z, a, b, proj, front, faces, ids, depth, eps, eps_buffer):
    """Whether the point (x, y, z) of the edge from vertex ``a`` to ``b`` is hidden.

    ``proj`` (N, 3) float64: raster x, y, depth of the vertices; ``front`` (N,) uint8: 1 when
    the vertex is in front of the eye (w > 0, finite); ``ids`` (H, W) int32 face ids (-1
    none) and ``depth`` (H, W) float32 of the depth pass.
    """
    height, width = ids.shape[0], ids.shape[1]
    px = min(max(int(math.floor(x)), 0), width - 1)
    py = min(max(int(math.floor(y)), 0), height - 1)
    last = -1
    for j in range(max(py - 1, 0), min(py + 2, height)):
        for i in range(max(px - 1, 0), min(px + 2, width)):
            f = ids[j, i]
            if f < 0 or f == last:
                continue
            last = f
            if _own_face(faces, f, a, b):
                continue
            if front[faces[f, 0]] and front[faces[f, 1]] and front[faces[f, 2]]:
                if _face_hides(proj, faces, f, x, y, z, eps):
                    return True
            elif j == py and i == px and depth[py, px] < z - eps_buffer:
                return True
    return False


@kernel(inline="always")
def _hidden_at(seg, s, t, a, b, proj, front, faces, ids, depth, eps, eps_buffer):
    x = seg[s, 0] + t * (seg[s, 3] - seg[s, 0])
    y = seg[s, 1] + t * (seg[s, 4] - seg[s, 1])
    z = seg[s, 2] + t * (seg[s, 5] - seg[s, 2])
    return point_hidden(x, y, z, a, b, proj, front, faces, ids, depth, eps, eps_buffer)


@kernel(inline="always")
def segment_runs(seg, ends, s, row, proj, front, faces, ids, depth, step, tol, eps, eps_buffer, out_t):
    """Split segment ``s`` into runs of one visibility: writes the parameters where the
    state changes into ``out_t[row, 1:]`` (as many as fit; ``out_t[row, 0] = 0`` and the
    last is 1) and returns ``(number of runs, hidden state of the first run)``."""
    a, b = ends[s, 0], ends[s, 1]
    dx, dy = seg[s, 3] - seg[s, 0], seg[s, 4] - seg[s, 1]
    length = math.sqrt(dx * dx + dy * dy)
    n = max(1, int(math.ceil(length / step)))
    slots = out_t.shape[1]
    first = _hidden_at(seg, s, 0.0, a, b, proj, front, faces, ids, depth, eps, eps_buffer)
    state = first
    runs = 1
    out_t[row, 0] = 0.0
    for k in range(1, n + 1):
        t = k / n
        now = _hidden_at(seg, s, t, a, b, proj, front, faces, ids, depth, eps, eps_buffer)
        if now == state:
            continue
        lo, hi = (k - 1) / n, t
        while (hi - lo) * length > tol:
            mid = 0.5 * (lo + hi)
            if _hidden_at(seg, s, mid, a, b, proj, front, faces, ids, depth, eps, eps_buffer) == state:
                lo = mid
            else:
                hi = mid
        if runs < slots - 1:
            out_t[row, runs] = 0.5 * (lo + hi)
        runs += 1
        state = now
    if runs < slots:
        out_t[row, runs] = 1.0
    return runs, first


@kernel(refcounts=False)
def visible_runs(slot, counter, seg, ends, todo, proj, front, faces, ids, depth, step, tol, eps, eps_buffer,
                 out_t, out_n, out_first):
    """Worker of :func:`rasterkit._jit.run_workers`: :func:`segment_runs` of the segments
    ``todo`` (K,) int64 (indices into ``seg`` (S, 6) float64: raster x, y, z of both ends,
    and ``ends`` (S, 2) int64: their edge's vertices). Row k of the outputs is ``todo[k]``'s:
    ``out_t`` (K, R) float64 the run boundaries, ``out_n`` (K,) int64 the number of runs
    (more than R - 1: ``out_t`` held too few) and ``out_first`` (K,) uint8 (1: the first run
    is hidden)."""
    n_todo = todo.shape[0]
    while True:
        chunk = fetch_add(counter, 0, 1)
        if chunk * CHUNK >= n_todo:
            break
        for k in range(chunk * CHUNK, min(n_todo, (chunk + 1) * CHUNK)):
            s = todo[k]
            runs, first = segment_runs(seg, ends, s, k, proj, front, faces, ids, depth, step, tol, eps, eps_buffer,
                                       out_t)
            out_n[k] = runs
            out_first[k] = 1 if first else 0
    return 0
