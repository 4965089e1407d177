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

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add

#: Segments are handed out to the threads in chunks of this many.
CHUNK = 1024


#: Fields of a face record (:func:`face_records`): corner 0's raster x, y, depth; the edge
#: vectors to corners 1 and 2 (x, y, depth each); 1 / twice the signed area; the corners'
#: vertex indices (as float64: exact below 2**53). One contiguous row per face: a sample
#: tests up to 9 faces, found at random places, so each should cost one or two cache lines.
REC_FIELDS = 13
_X0, _Y0, _Z0, _E1X, _E1Y, _E1Z, _E2X, _E2Y, _E2Z, _INV, _V0, _V1, _V2 = range(REC_FIELDS)


@kernel
def face_records(proj, front, faces, rec):
    """Fill ``rec`` (M, REC_FIELDS) float64 from the vertices' raster x, y, depth ``proj``
    (N, 3) float64, ``front`` (N,) uint8 (1: in front of the eye) and ``faces`` (M, 3)
    int64. A face with a corner behind the eye gets x0 = NaN; a degenerate one 1/area = 0."""
    for f in range(faces.shape[0]):
        i0, i1, i2 = faces[f, 0], faces[f, 1], faces[f, 2]
        x0, y0, z0 = proj[i0, 0], proj[i0, 1], proj[i0, 2]
        e1x, e1y = proj[i1, 0] - x0, proj[i1, 1] - y0
        e2x, e2y = proj[i2, 0] - x0, proj[i2, 1] - y0
        d = e1x * e2y - e2x * e1y
        rec[f, _X0] = x0 if front[i0] and front[i1] and front[i2] else np.nan
        rec[f, _Y0] = y0
        rec[f, _Z0] = z0
        rec[f, _E1X] = e1x
        rec[f, _E1Y] = e1y
        rec[f, _E1Z] = proj[i1, 2] - z0
        rec[f, _E2X] = e2x
        rec[f, _E2Y] = e2y
        rec[f, _E2Z] = proj[i2, 2] - z0
        rec[f, _INV] = 1.0 / d if d != 0.0 and math.isfinite(d) else 0.0
        rec[f, _V0] = i0
        rec[f, _V1] = i1
        rec[f, _V2] = i2


@kernel(inline="always")
def _own_face(rec, f, a, b):
    """Whether face ``f`` has both vertices ``a`` and ``b`` (float64 indices)."""
    v0, v1, v2 = rec[f, _V0], rec[f, _V1], rec[f, _V2]
    return (v0 == a or v1 == a or v2 == a) and (v0 == b or v1 == b or v2 == b)


@kernel(inline="always")
def _face_hides(rec, f, x, y, z, eps):
    """Whether face ``f`` (all corners in front of the eye) covers (x, y) in front of depth z."""
    inv = rec[f, _INV]
    if inv == 0.0:
        return False
    qx, qy = x - rec[f, _X0], y - rec[f, _Y0]
    e1x, e1y, e2x, e2y = rec[f, _E1X], rec[f, _E1Y], rec[f, _E2X], rec[f, _E2Y]
    l1 = (qx * e2y - e2x * qy) * inv
    l2 = (e1x * qy - qx * e1y) * inv
    slack = 1e-9
    if l1 < -slack or l2 < -slack or l1 + l2 > 1.0 + slack:
        return False
    zf = rec[f, _Z0] + l1 * rec[f, _E1Z] + l2 * rec[f, _E2Z]
    return zf < z - eps


@kernel(inline="always")
def point_hidden(x, y, z, a, b, rec, ids, depth, eps, eps_buffer):
    """Whether the point (x, y, z) of the edge from vertex ``a`` to ``b`` is hidden.

    ``rec`` (M, REC_FIELDS) float64: the face records of :func:`face_records`; ``ids``
    (H, W) int32 face ids (-1 none) and ``depth`` (H, W) float32 of the depth pass.
    """
    height, width = ids.shape[0], ids.shape[1]
    px = min(max(int(math.floor(x)), 0), width - 1)
    py = min(max(int(math.floor(y)), 0), height - 1)
    seen0, seen1, seen2, seen3 = -1, -1, -1, -1  # the last faces tested: neighbours repeat
    for j in range(max(py - 1, 0), min(py + 2, height)):
        for i in range(max(px - 1, 0), min(px + 2, width)):
            f = ids[j, i]
            if f < 0 or f == seen0 or f == seen1 or f == seen2 or f == seen3:
                continue
            seen3, seen2, seen1, seen0 = seen2, seen1, seen0, f
            if _own_face(rec, f, a, b):
                continue
            if not math.isnan(rec[f, _X0]):
                if _face_hides(rec, f, x, y, z, eps):
                    return True
            elif j == py and i == px and depth[py, px] < z - eps_buffer:
                return True
    return False


@kernel(inline="always")
def _hidden_at(seg, s, t, a, b, rec, ids, depth, eps, eps_buffer):
    x = seg[s, 0] + t * (seg[s, 3] - seg[s, 0])
    y = seg[s, 1] + t * (seg[s, 4] - seg[s, 1])
    z = seg[s, 2] + t * (seg[s, 5] - seg[s, 2])
    return point_hidden(x, y, z, a, b, rec, ids, depth, eps, eps_buffer)


@kernel(inline="always")
def segment_runs(seg, ends, s, row, rec, ids, depth, step, tol, eps, eps_buffer, out_t):
    """Split segment ``s`` into runs of one visibility: writes the parameters where the
    state changes into ``out_t[row, 1:]`` (as many as fit; ``out_t[row, 0] = 0`` and the
    last is 1) and returns ``(number of runs, hidden state of the first run)``."""
    a, b = float(ends[s, 0]), float(ends[s, 1])
    dx, dy = seg[s, 3] - seg[s, 0], seg[s, 4] - seg[s, 1]
    length = math.sqrt(dx * dx + dy * dy)
    n = max(1, int(math.ceil(length / step)))
    slots = out_t.shape[1]
    # One loop with one test site, for the samples and the bisections alike: the test is
    # inlined code, compiled once per site.
    first = False
    state = False
    runs = 1
    out_t[row, 0] = 0.0
    k = 0  # the next sample
    bisecting = False
    lo, hi = 0.0, 0.0
    while True:
        if bisecting:
            t = 0.5 * (lo + hi)
        elif k <= n:
            t = k / n
        else:
            break
        now = _hidden_at(seg, s, t, a, b, rec, ids, depth, eps, eps_buffer)
        if not bisecting:
            k += 1
            if k == 1:
                first = state = now
                continue
            if now == state:
                continue
            lo, hi = (k - 2) / n, t  # a change between the last two samples
            bisecting = True
        elif now == state:
            lo = t
        else:
            hi = t
        if (hi - lo) * length <= tol:
            if runs < slots - 1:
                out_t[row, runs] = 0.5 * (lo + hi)
            runs += 1
            state = not state
            bisecting = False
    if runs < slots:
        out_t[row, runs] = 1.0
    return runs, first


@kernel(refcounts=False)
def visible_runs(slot, counter, seg, ends, todo, rec, ids, depth, step, tol, eps, eps_buffer,
                 out_t, out_n, out_first):
    """Worker of :func:`rasterkit.runtime.threads.run_workers`: :func:`segment_runs` of the segments
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
            runs, first = segment_runs(seg, ends, s, k, rec, ids, depth, step, tol, eps, eps_buffer,
                                       out_t)
            out_n[k] = runs
            out_first[k] = 1 if first else 0
    return 0


@kernel
def clip_edges(clip, edges, width, height, seg, t):
    """Clip the edges (E, 2) int64 of the homogeneous raster-space vertices ``clip`` (N, 4)
    float64 to ``0 <= zh <= w``, ``0 <= xh <= width w``, ``0 <= yh <= height w``
    (Liang-Barsky in homogeneous space). Writes the kept edges' raster x, y, z of both ends
    into ``seg`` (E, 6) float64 and their parameters on the edge into ``t`` (E, 2) float64,
    in order; returns ``kept`` (K,) int64, the indices of the K kept edges (those with a
    finite part inside)."""
    kept = np.empty(edges.shape[0], np.int64)
    k = 0
    for e in range(edges.shape[0]):
        a, b = edges[e, 0], edges[e, 1]
        t0, t1 = 0.0, 1.0
        inside = True
        for plane in range(6):
            axis = 2 if plane < 2 else 0 if plane < 4 else 1
            far = width if plane == 3 else height if plane == 5 else 1.0
            if plane % 2 == 0:  # coordinate >= 0
                fa = clip[a, axis]
                fb = clip[b, axis]
            else:  # coordinate <= far * w
                fa = far * clip[a, 3] - clip[a, axis]
                fb = far * clip[b, 3] - clip[b, axis]
            if not (math.isfinite(fa) and math.isfinite(fb)):
                inside = False
                break
            if fa < 0.0 and fb < 0.0:
                inside = False
                break
            if fa < 0.0:
                t0 = max(t0, fa / (fa - fb))
            elif fb < 0.0:
                t1 = min(t1, fa / (fa - fb))
        if not inside or t0 > t1:
            continue
        ok = True
        for end in range(2):
            u = t0 if end == 0 else t1
            w = clip[a, 3] + u * (clip[b, 3] - clip[a, 3])
            for c in range(3):
                v = (clip[a, c] + u * (clip[b, c] - clip[a, c])) / w
                if not math.isfinite(v):
                    ok = False
                seg[k, 3 * end + c] = v
        if not ok:
            continue
        t[k, 0] = t0
        t[k, 1] = t1
        kept[k] = e
        k += 1
    return kept[:k].copy()
