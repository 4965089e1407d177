"""Slow, obviously-correct NumPy references for the triangle kernels.

Nothing here is fast or clever: every triangle is tested against every pixel centre of the
image, with the top-left rule written out as the definition says, and clipping is the
textbook Sutherland–Hodgman loop over the near plane. Coordinates are snapped to 1/256 pixel
first (as the kernels do); with the small coordinates the tests use, the edge functions are
then exact in float64 (at most 2 x 20 significant bits per product), so coverage must match
the integer kernels pixel for pixel.
"""

from __future__ import annotations

import numpy as np

SUBPIXEL = 256


def snap(v):
    """Round raster coordinates to the nearest 1/256 pixel (halves up), like the kernels."""
    return np.floor(np.asarray(v, dtype=np.float64) * SUBPIXEL + 0.5) / SUBPIXEL


def signed_area2(tri):
    """Twice the signed area of a raster triangle ``tri (3, >=2)``; negative = front-facing."""
    (x0, y0), (x1, y1), (x2, y2) = tri[0, :2], tri[1, :2], tri[2, :2]
    return (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)


def coverage(tri, width, height):
    """Boolean (H, W) mask of the pixel centres covered by ``tri (3, >=2)`` (top-left rule).

    The triangle is made clockwise on screen (positive ``signed_area2``); then a centre is
    covered when every edge function is positive, or zero on a top edge (horizontal, the
    triangle below it) or a left edge (going up the screen).
    """
    tri = np.asarray(tri, dtype=np.float64)
    area2 = signed_area2(tri)
    if area2 == 0:
        return np.zeros((height, width), bool)
    if area2 < 0:
        tri = tri[[0, 2, 1]]
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    inside = np.ones((height, width), bool)
    for k in range(3):
        (xa, ya), (xb, yb) = tri[k, :2], tri[(k + 1) % 3, :2]
        dx, dy = xb - xa, yb - ya
        e = dx * (py - ya) - dy * (px - xa)
        top = dy == 0 and dx > 0
        left = dy < 0
        inside &= (e > 0) | ((e == 0) & (top or left))
    return inside


def interpolated_depth(tri, width, height):
    """(H, W) float64: the plane through the raster triangle ``tri (3, 3)`` at pixel centres."""
    tri = np.asarray(tri, dtype=np.float64)
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = tri
    area2 = signed_area2(tri)
    w0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area2
    w1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area2
    return w0 * z0 + w1 * z1 + (1.0 - w0 - w1) * z2


def reference_raster(triangles, width, height, cull="none"):
    """Rasterize raster-space triangles in order with a less-than depth test.

    Parameters
    ----------
    triangles : (K, 3, 3) float
        Vertices ``(x, y, z)`` in raster space; x and y are snapped here.
    width, height : int
    cull : {"none", "back", "front"}
        Front faces have a negative ``signed_area2``.

    Returns
    -------
    count : (H, W) int64
        How many triangles cover each centre (before the depth test).
    ids : (H, W) int64
        Index of the winning triangle (the first of the nearest), -1 where none.
    depth : (H, W) float64
        Its depth, +inf where none.
    margin : (H, W) float64
        How much nearer the winner is than the next nearest covering triangle (+inf when
        only one covers the centre): ids are only meaningful to compare where it is clearly
        positive, since the kernels round depth to float32.
    """
    count = np.zeros((height, width), np.int64)
    ids = np.full((height, width), -1, np.int64)
    depth = np.full((height, width), np.inf)
    second = np.full((height, width), np.inf)
    for k, tri in enumerate(np.asarray(triangles, dtype=np.float64)):
        tri = tri.copy()
        tri[:, :2] = snap(tri[:, :2])
        area2 = signed_area2(tri)
        if area2 == 0 or (cull == "back" and area2 > 0) or (cull == "front" and area2 < 0):
            continue
        inside = coverage(tri, width, height)
        z = interpolated_depth(tri, width, height)
        count += inside
        nearer = inside & (z < depth)
        second = np.where(nearer, depth, np.where(inside, np.minimum(second, z), second))
        depth = np.where(nearer, z, depth)
        ids = np.where(nearer, k, ids)
    margin = np.where(np.isinf(second), np.inf, second - np.where(np.isinf(depth), 0.0, depth))
    return count, ids, depth, margin


def clip_near(vertices):
    """Sutherland–Hodgman: cut a homogeneous polygon ``(n, 4)`` by the near plane ``zh >= 0``.

    Returns the ``(m, 4)`` polygon that remains (m = 0 when none). New points are computed
    from the inside end of an edge towards the outside end.
    """
    out = []
    n = len(vertices)
    for k in range(n):
        a, b = vertices[k], vertices[(k + 1) % n]
        if a[2] >= 0:
            out.append(a)
        if (a[2] >= 0) != (b[2] >= 0):
            inside, outside = (a, b) if a[2] >= 0 else (b, a)
            s = inside[2] / (inside[2] - outside[2])
            out.append(inside + (outside - inside) * s)
    return np.array(out).reshape(-1, 4)


def fan(polygon):
    """Triangles ``(n - 2, 3, k)`` of a convex polygon ``(n, k)``, fanned from vertex 0."""
    return np.array([[polygon[0], polygon[i], polygon[i + 1]] for i in range(1, len(polygon) - 1)])


def divide(h):
    """Homogeneous ``(..., 4)`` -> raster ``(..., 3)``: ``(xh / w, yh / w, zh / w)``."""
    h = np.asarray(h, dtype=np.float64)
    return h[..., :3] / h[..., 3:4]
