"""The Numba kernel that splits the triangles and convex quads of an OBJ file, almost every
polygon of a real model, in one pass: as :mod:`rasterkit.obj.split` splits them (a triangle
as it is, a quad of four different vertices that turns the way of its Newell normal at every
corner, or has no normal, as the fan from corner 0), in the same IEEE arithmetic
(``fastmath=False``: NumPy's operations, in NumPy's order), so the same quads are fans. Every
other polygon is left to :mod:`rasterkit.obj.split` and the polygon kernels.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["simple_polygons"]


@kernel(fastmath=False)
def simple_polygons(vertices, corners, offsets, keep):
    """Split the kept triangles and convex quads.

    Parameters
    ----------
    vertices : (N, 3) float64
    corners : (C,) int64
        Vertex index of each polygon corner (all in [0, N)), polygon p at
        ``offsets[p]:offsets[p + 1]``.
    offsets : (P + 1,) int64
    keep : (P,) bool

    Returns
    -------
    triangles : (T, 3) int64
        The triangles, as corners (indices into ``corners``), in polygon order; a triangle
        with a repeated vertex is left out.
    counts : (P,) int64
        The triangles of each polygon (0 for one not kept or left).
    left : (P,) bool
        Kept polygons that are not split here.
    """
    polygons = len(keep)
    counts = np.empty(polygons, np.int64)
    left = np.empty(polygons, np.bool_)
    total = 0
    for p in range(polygons):
        m = offsets[p + 1] - offsets[p]
        counts[p] = 0
        left[p] = False
        if not keep[p]:
            continue
        if m == 3 or m == 4:
            o = offsets[p]
            a, b, c = corners[o], corners[o + 1], corners[o + 2]
            if m == 3:
                counts[p] = 1 if a != b and b != c and c != a else 0
            elif a != b and a != c and b != c and _distinct_last(corners, o) and _quad_fan(vertices, corners, o):
                counts[p] = 2
            else:
                left[p] = True
        else:
            left[p] = True
        total += counts[p]
    triangles = np.empty((total, 3), np.int64)
    t = 0
    for p in range(polygons):
        o = offsets[p]
        if counts[p] >= 1:
            triangles[t, 0], triangles[t, 1], triangles[t, 2] = o, o + 1, o + 2
            t += 1
        if counts[p] == 2:
            triangles[t, 0], triangles[t, 1], triangles[t, 2] = o, o + 2, o + 3
            t += 1
    return triangles, counts, left


@kernel(inline="always")
def _distinct_last(corners, o):
    """The fourth corner of the quad at o is none of the other three's vertex."""
    d = corners[o + 3]
    return d != corners[o] and d != corners[o + 1] and d != corners[o + 2]


@kernel(inline="always")
def _quad_fan(vertices, corners, o):
    """:func:`rasterkit.obj.split._quad_fans` for the quad at o: the Newell normal of the
    corners relative to corner 0, the turn at each corner from the coordinates; a fan when
    every turn is positive or there is no normal."""
    q0, q1, q2, q3 = corners[o], corners[o + 1], corners[o + 2], corners[o + 3]
    x0, y0, z0 = vertices[q0, 0], vertices[q0, 1], vertices[q0, 2]
    rx = (0.0, vertices[q1, 0] - x0, vertices[q2, 0] - x0, vertices[q3, 0] - x0)
    ry = (0.0, vertices[q1, 1] - y0, vertices[q2, 1] - y0, vertices[q3, 1] - y0)
    rz = (0.0, vertices[q1, 2] - z0, vertices[q2, 2] - z0, vertices[q3, 2] - z0)
    nx = ny = nz = 0.0
    for k in range(4):
        j = (k + 1) % 4
        nx = nx + (ry[k] - ry[j]) * (rz[k] + rz[j])
        ny = ny + (rz[k] - rz[j]) * (rx[k] + rx[j])
        nz = nz + (rx[k] - rx[j]) * (ry[k] + ry[j])
    px = (vertices[q0, 0], vertices[q1, 0], vertices[q2, 0], vertices[q3, 0])
    py = (vertices[q0, 1], vertices[q1, 1], vertices[q2, 1], vertices[q3, 1])
    pz = (vertices[q0, 2], vertices[q1, 2], vertices[q2, 2], vertices[q3, 2])
    fan = True
    for k in range(4):
        j, h = (k + 1) % 4, (k + 2) % 4
        sx, sy, sz = px[j] - px[k], py[j] - py[k], pz[j] - pz[k]
        tx, ty, tz = px[h] - px[j], py[h] - py[j], pz[h] - pz[j]
        turn = ((sy * tz - sz * ty) * nx + (sz * tx - sx * tz) * ny + (sx * ty - sy * tx) * nz)
        fan = fan and turn > 0.0
    return fan or not (nx * nx + ny * ny + nz * nz > 0.0)
