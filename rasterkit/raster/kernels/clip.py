"""Clipping in homogeneous raster space: triangles (Sutherland–Hodgman).

A vertex is one row ``(xh, yh, zh, w)`` of the ``clip`` array: after the divide,
``x = xh / w`` and ``y = yh / w`` are raster pixel coordinates and ``z = zh / w`` is the
depth. Every test below is a linear inequality ``plane · v >= 0`` in that 4D space, so it
means the same thing for vertices behind the eye (``w <= 0``): nothing wraps around.

The planes, as rows of :func:`clip_planes` (inside is ``plane · (xh, yh, zh, w) >= 0``):

- ``NEAR`` (``zh >= 0``) and ``FAR`` (``zh <= w``): triangles crossing them are cut.
- the guard band ``-GUARD_BAND <= x <= width + GUARD_BAND`` (same for ``y``): the
  rasterizer works in fixed point (:mod:`rasterkit.raster.kernels.triangle`), and coordinates past
  the guard band could overflow its int64 edge functions, so triangles reaching past it are
  cut too. Inside the guard band nothing is cut: the rasterizer clamps its bounding box to
  the image instead, which is cheaper and keeps shared edges exactly shared.
- the viewport sides ``0 <= x <= width``, ``0 <= y <= height``: never cut against; a
  triangle whose three vertices all lie outside one of them (or outside ``NEAR``/``FAR``)
  is rejected whole.

:func:`vertex_code` classifies a vertex once (the setup stage runs it per vertex, not per
face corner); :func:`classify_face` combines three codes; :func:`cut_face` does the
Sutherland–Hodgman cut of the few faces that need it.

Segments (the edges of the line path) are clipped by :mod:`rasterkit.raster.kernels.segments`.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.limits import MAX_IMAGE_SIZE

#: Guard band in pixels on each side of the image (see the module docstring). With images of
#: at most ``MAX_IMAGE_SIZE`` pixels a side and 8 sub-pixel bits, fixed-point coordinates
#: stay below 2**29 and edge functions below 2**60.
GUARD_BAND = 2**20

# Rows of clip_planes(). CUT_MASK: planes a triangle is cut against; REJECT_MASK: planes
# whose outside is invisible, so three vertices outside one of them reject the face.
NEAR, FAR = 0, 1
GUARD_LEFT, GUARD_RIGHT, GUARD_TOP, GUARD_BOTTOM = 2, 3, 4, 5
VIEW_LEFT, VIEW_RIGHT, VIEW_TOP, VIEW_BOTTOM = 6, 7, 8, 9
N_PLANES = 10
CUT_MASK = 0b0000111111
REJECT_MASK = 0b1111000011

# Cut vertices lie within GUARD_BAND of the image up to rounding; anything beyond this came
# from overflowing arithmetic and must not reach the fixed-point rasterizer.
_COORDINATE_LIMIT = float(GUARD_BAND + MAX_IMAGE_SIZE + 1)

#: A convex polygon cut by the six CUT_MASK planes has at most 3 + 6 vertices.
MAX_POLYGON = 9

# Extra vertex_code() bits: a NaN or infinite coordinate; w <= 0 without being outside
# NEAR or FAR, which only (0, 0, 0, 0) manages (a degenerate matrix, not a point).
NONFINITE_BIT = 1 << N_PLANES
DEGENERATE_BIT = 1 << (N_PLANES + 1)

# Face classes returned by classify_face().
FACE_INSIDE = 0
FACE_NEEDS_CUT = 1
FACE_OUTSIDE = 2
FACE_NONFINITE = 3


@kernel
def clip_planes(width, height):
    """Planes of the view volume in homogeneous raster space.

    Parameters
    ----------
    width, height : int
        Image size in pixels.

    Returns
    -------
    (N_PLANES, 4) float64
        Row ``p`` is a plane; a vertex ``v = (xh, yh, zh, w)`` is inside when ``p · v >= 0``.
        Row order: NEAR, FAR, the four guard-band planes, the four viewport sides.
    """
    g = float(GUARD_BAND)
    planes = np.zeros((N_PLANES, 4))
    planes[NEAR, 2] = 1.0
    planes[FAR, 2], planes[FAR, 3] = -1.0, 1.0
    planes[GUARD_LEFT, 0], planes[GUARD_LEFT, 3] = 1.0, g
    planes[GUARD_RIGHT, 0], planes[GUARD_RIGHT, 3] = -1.0, width + g
    planes[GUARD_TOP, 1], planes[GUARD_TOP, 3] = 1.0, g
    planes[GUARD_BOTTOM, 1], planes[GUARD_BOTTOM, 3] = -1.0, height + g
    planes[VIEW_LEFT, 0] = 1.0
    planes[VIEW_RIGHT, 0], planes[VIEW_RIGHT, 3] = -1.0, float(width)
    planes[VIEW_TOP, 1] = 1.0
    planes[VIEW_BOTTOM, 1], planes[VIEW_BOTTOM, 3] = -1.0, float(height)
    return planes


@kernel(inline="always")
def vertex_code(xh, yh, zh, w, width, height):
    """Outcode of vertex ``(xh, yh, zh, w)``: bit ``p`` set when it is outside plane ``p``.

    The same tests as ``plane · v < 0`` for the rows of :func:`clip_planes`, written out
    because this runs for every vertex. NONFINITE_BIT (alone) flags a NaN or infinite
    coordinate, DEGENERATE_BIT a ``w <= 0`` that no plane caught.
    """
    if not (np.isfinite(xh) and np.isfinite(yh) and np.isfinite(zh) and np.isfinite(w)):
        return NONFINITE_BIT
    guard = GUARD_BAND * w
    code = 0
    if zh < 0.0:
        code |= 1 << NEAR
    if zh > w:
        code |= 1 << FAR
    if xh < -guard:
        code |= 1 << GUARD_LEFT
    if xh > (width + GUARD_BAND) * w:
        code |= 1 << GUARD_RIGHT
    if yh < -guard:
        code |= 1 << GUARD_TOP
    if yh > (height + GUARD_BAND) * w:
        code |= 1 << GUARD_BOTTOM
    if xh < 0.0:
        code |= 1 << VIEW_LEFT
    if xh > width * w:
        code |= 1 << VIEW_RIGHT
    if yh < 0.0:
        code |= 1 << VIEW_TOP
    if yh > height * w:
        code |= 1 << VIEW_BOTTOM
    if not w > 0.0:
        code |= DEGENERATE_BIT
    return code


@kernel(inline="always")
def classify_face(code0, code1, code2):
    """Class of a face from its vertices' :func:`vertex_code`.

    Returns
    -------
    (int, int)
        One of FACE_INSIDE, FACE_NEEDS_CUT, FACE_OUTSIDE, FACE_NONFINITE, and for
        FACE_NEEDS_CUT the planes :func:`cut_face` has to cut against (else 0).
    """
    any_out = code0 | code1 | code2
    if any_out & NONFINITE_BIT:
        return FACE_NONFINITE, 0
    if code0 & code1 & code2 & REJECT_MASK:
        return FACE_OUTSIDE, 0
    if any_out & CUT_MASK:
        return FACE_NEEDS_CUT, any_out & CUT_MASK
    if any_out & DEGENERATE_BIT:
        return FACE_OUTSIDE, 0
    return FACE_INSIDE, 0


@kernel(inline="always")
def _distance(planes, p, v):
    """Signed distance-like value of vertex ``v`` (4,) to plane row ``p``; >= 0 is inside."""
    return planes[p, 0] * v[0] + planes[p, 1] * v[1] + planes[p, 2] * v[2] + planes[p, 3] * v[3]


@kernel
def _on_plane(planes, p, v):
    """Move ``v`` (4,) exactly onto plane ``p`` along the coordinate the plane bounds.

    Every plane bounds one of xh, yh, zh (coefficient +-1) against w. Interpolating that
    coordinate loses everything when the edge is huge (1e30 - 1e30 = 0); solving the plane
    for it from the interpolated w is exact up to one rounding.
    """
    axis = 0 if planes[p, 0] != 0.0 else (1 if planes[p, 1] != 0.0 else 2)
    rest = 0.0
    for c in range(4):
        if c != axis:
            rest += planes[p, c] * v[c]
    v[axis] = -rest / planes[p, axis]


@kernel
def _cut_polygon(src, n, dst, planes, p):
    """One Sutherland–Hodgman step: cut the polygon ``src[:n]`` by plane ``p`` into ``dst``.

    The intersection of an edge is always computed from its inside end towards its outside
    end, so the two faces sharing an edge get bit-identical new vertices (no cracks).
    Returns the vertex count of the result (0 when nothing is left).
    """
    m = 0
    for k in range(n):
        a = src[k]
        b = src[(k + 1) % n]
        da = _distance(planes, p, a)
        db = _distance(planes, p, b)
        if da >= 0.0:
            dst[m] = a
            m += 1
        if (da >= 0.0) != (db >= 0.0):
            if da >= 0.0:
                inside, outside, din, dout = a, b, da, db
            else:
                inside, outside, din, dout = b, a, db, da
            s = din / (din - dout)
            for c in range(4):
                dst[m, c] = inside[c] + (outside[c] - inside[c]) * s
            _on_plane(planes, p, dst[m])
            m += 1
    return m


@kernel
def cut_face(clip, faces, f, planes, mask, out):
    """Cut face ``f`` against the planes whose bit is set in ``mask``; write the screen polygon.

    Parameters
    ----------
    clip : (N, 4) float64
        Homogeneous raster coordinates of the vertices.
    faces : (M, 3) int64
        Vertex indices, already checked to be in range.
    f : int
        Face index.
    planes : (N_PLANES, 4) float64
        From :func:`clip_planes`.
    mask : int
        Planes to cut against (from :func:`classify_face`).
    out : (MAX_POLYGON, 3) float64
        Receives the polygon's vertices in raster space ``(x, y, z)``, z clamped to [0, 1],
        in the face's winding order.

    Returns
    -------
    int
        Vertex count of the polygon: 0 when nothing is left, otherwise >= 3. Also 0 when
        a vertex lands at ``w <= 0`` or off the guard band, which only degenerate
        matrices or coordinates near the float64 limit (where the arithmetic overflows)
        produce.
    """
    buf = np.empty((2, MAX_POLYGON, 4))
    for k in range(3):
        buf[0, k] = clip[faces[f, k]]
    n = 3
    cur = 0
    for p in range(N_PLANES):
        if mask & (1 << p) and n > 0:
            n = _cut_polygon(buf[cur], n, buf[1 - cur], planes, p)
            cur = 1 - cur
    if n < 3:
        return 0
    for k in range(n):
        w = buf[cur, k, 3]
        x, y = buf[cur, k, 0] / w, buf[cur, k, 1] / w
        if not (w > 0.0 and abs(x) <= _COORDINATE_LIMIT and abs(y) <= _COORDINATE_LIMIT):
            return 0
        out[k, 0], out[k, 1] = x, y
        out[k, 2] = min(max(buf[cur, k, 2] / w, 0.0), 1.0)
    return n


@kernel(inline="always")
def project_vertex(clip, i):
    """Raster ``(x, y, z)`` of vertex ``i``, meaningful when its code has no CUT_MASK bit.

    Such vertices have ``0 <= zh <= w`` and ``w > 0`` and lie in the guard band, so ``z``
    is in [0, 1] (the ``min`` only removes a rounding excess) and ``x, y`` fit the
    rasterizer's fixed point.
    """
    inv_w = 1.0 / clip[i, 3]
    return clip[i, 0] * inv_w, clip[i, 1] * inv_w, min(clip[i, 2] * inv_w, 1.0)
