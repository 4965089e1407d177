"""Numba kernels that turn OBJ polygons into triangles and edges.

Triangles and convex quads are split as a fan; every other polygon by ear clipping in the plane
of its Newell normal, so that concave polygons (and holes joined by a bridge) are covered
exactly. The sides of the polygons become the mesh's edges (:func:`side_keys`). Inputs are
vertex indices already checked by the caller (:mod:`rasterkit._obj_assemble`).
"""

from __future__ import annotations

import numpy as np

from rasterkit._jit import kernel


@kernel
def _newell_normal(vertices, ring):
    """Newell's normal (nx, ny, nz) of the closed polygon vertices[ring]: it follows the
    winding by the right-hand rule and its length is twice the area of a planar polygon.
    Coordinates are taken relative to the first vertex to keep them precise."""
    nx = ny = nz = 0.0
    m = len(ring)
    o = vertices[ring[0]]
    for k in range(m):
        p = vertices[ring[k]]
        q = vertices[ring[(k + 1) % m]]
        px, py, pz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
        qx, qy, qz = q[0] - o[0], q[1] - o[1], q[2] - o[2]
        nx += (py - qy) * (pz + qz)
        ny += (pz - qz) * (px + qx)
        nz += (px - qx) * (py + qy)
    return nx, ny, nz


@kernel
def _plane_coordinates(vertices, ring, nx, ny, nz):
    """(m, 2) coordinates of vertices[ring] in the polygon's plane, in a basis (u, w) with
    u x w along the normal (nx, ny, nz): a polygon wound around its normal is CCW there."""
    length = np.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / length, ny / length, nz / length
    # u = n x (the coordinate axis least aligned with n), then w = n x u.
    if abs(nx) <= abs(ny) and abs(nx) <= abs(nz):
        ux, uy, uz = 0.0, nz, -ny
    elif abs(ny) <= abs(nz):
        ux, uy, uz = -nz, 0.0, nx
    else:
        ux, uy, uz = ny, -nx, 0.0
    length = np.sqrt(ux * ux + uy * uy + uz * uz)
    ux, uy, uz = ux / length, uy / length, uz / length
    wx, wy, wz = ny * uz - nz * uy, nz * ux - nx * uz, nx * uy - ny * ux
    o = vertices[ring[0]]
    xy = np.empty((len(ring), 2))
    for k in range(len(ring)):
        p = vertices[ring[k]]
        px, py, pz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
        xy[k, 0] = px * ux + py * uy + pz * uz
        xy[k, 1] = px * wx + py * wy + pz * wz
    return xy


@kernel
def _cross(xy, a, b, c):
    """z of (b - a) x (c - b): > 0 when a, b, c turn left (counter-clockwise)."""
    return ((xy[b, 0] - xy[a, 0]) * (xy[c, 1] - xy[b, 1])
            - (xy[b, 1] - xy[a, 1]) * (xy[c, 0] - xy[b, 0]))


@kernel
def _same_point(xy, a, b):
    return xy[a, 0] == xy[b, 0] and xy[a, 1] == xy[b, 1]


@kernel
def _is_ear(xy, prev, nxt, i):
    """True when the triangle (prev[i], i, nxt[i]) turns left and no other reflex or straight
    vertex of the remaining polygon lies inside it or on its border (vertices at the same
    place as a corner of the triangle do not count: polygons with holes repeat them)."""
    a = prev[i]
    c = nxt[i]
    if not _cross(xy, a, i, c) > 0.0:
        return False
    r = nxt[c]
    while r != a:
        if not (_same_point(xy, r, a) or _same_point(xy, r, i) or _same_point(xy, r, c)):
            if (_cross(xy, a, i, r) >= 0.0 and _cross(xy, i, c, r) >= 0.0
                    and _cross(xy, c, a, r) >= 0.0 and _cross(xy, prev[r], r, nxt[r]) <= 0.0):
                return False
        r = nxt[r]
    return True


@kernel
def _most_convex(xy, prev, nxt, start, remaining):
    """The remaining vertex with the largest left turn: the fallback when no ear exists (a
    self-intersecting or degenerate polygon), so that clipping always ends."""
    best = start
    best_turn = -np.inf
    i = start
    for _ in range(remaining):
        turn = _cross(xy, prev[i], i, nxt[i])
        if turn > best_turn:
            best, best_turn = i, turn
        i = nxt[i]
    return best


@kernel
def _ear_clip(xy, ring, out):
    """Triangulate the polygon ring (m,) whose plane coordinates xy (m, 2) wind CCW, writing
    its m - 2 triangles (vertex indices from ring, same winding) into out."""
    m = len(ring)
    prev = np.empty(m, np.int64)
    nxt = np.empty(m, np.int64)
    for k in range(m):
        prev[k] = (k + m - 1) % m
        nxt[k] = (k + 1) % m
    i = 0
    remaining = m
    failures = 0
    t = 0
    while remaining > 3:
        if failures >= remaining:
            i = _most_convex(xy, prev, nxt, i, remaining)
        elif not _is_ear(xy, prev, nxt, i):
            i = nxt[i]
            failures += 1
            continue
        out[t, 0], out[t, 1], out[t, 2] = ring[prev[i]], ring[i], ring[nxt[i]]
        t += 1
        nxt[prev[i]] = nxt[i]
        prev[nxt[i]] = prev[i]
        i = nxt[i]
        remaining -= 1
        failures = 0
    out[t, 0], out[t, 1], out[t, 2] = ring[prev[i]], ring[i], ring[nxt[i]]


@kernel
def _fan(ring, out):
    for t in range(len(ring) - 2):
        out[t, 0], out[t, 1], out[t, 2] = ring[0], ring[t + 1], ring[t + 2]


@kernel
def _convex_quad(vertices, polygon_vertices, o):
    """True when the quad polygon_vertices[o:o + 4] turns the same way as its Newell normal at
    every corner, so that the fan (0, 1, 2), (0, 2, 3) covers it exactly."""
    quad = polygon_vertices[o:o + 4]
    nx, ny, nz = _newell_normal(vertices, quad)
    for k in range(4):
        a = vertices[quad[k]]
        b = vertices[quad[(k + 1) % 4]]
        c = vertices[quad[(k + 2) % 4]]
        e0x, e0y, e0z = b[0] - a[0], b[1] - a[1], b[2] - a[2]
        e1x, e1y, e1z = c[0] - b[0], c[1] - b[1], c[2] - b[2]
        turn = ((e0y * e1z - e0z * e1y) * nx + (e0z * e1x - e0x * e1z) * ny
                + (e0x * e1y - e0y * e1x) * nz)
        if not turn > 0.0:
            return False
    return True


@kernel
def _merge_repeats(polygon):
    """The polygon without consecutive (cyclically) repeated vertex indices."""
    ring = np.empty(len(polygon), np.int64)
    k = 0
    for v in polygon:
        if k == 0 or v != ring[k - 1]:
            ring[k] = v
            k += 1
    while k > 1 and ring[k - 1] == ring[0]:
        k -= 1
    return ring[:k]


@kernel
def _triangulate_polygon(vertices, polygon, out):
    """Triangles of one polygon (m >= 4 vertex indices) into out (m - 2, 3) by ear clipping in
    the polygon's best-fit plane. Repeated consecutive vertices are merged first; rows left over
    stay -1."""
    ring = _merge_repeats(polygon)
    if len(ring) < 3:
        return
    nx, ny, nz = _newell_normal(vertices, ring)
    if len(ring) == 3 or not nx * nx + ny * ny + nz * nz > 0.0:
        _fan(ring, out)
        return
    _ear_clip(_plane_coordinates(vertices, ring, nx, ny, nz), ring, out)


@kernel
def triangulate(vertices, polygon_vertices, offsets, keep):
    """Triangulate polygons given as runs of vertex indices: triangles and convex quads by a
    fan, anything else by ear clipping (correct for concave polygons).

    Parameters
    ----------
    vertices : (N, 3) float64
    polygon_vertices : (C,) int64
        Vertex indices of all polygons, one after another; every index is in [0, N).
    offsets : (P + 1,) int64
        Polygon p is polygon_vertices[offsets[p]:offsets[p + 1]], with at least 3 vertices.
    keep : (P,) bool
        Polygons to triangulate; the others' rows stay -1.

    Returns
    -------
    triangles : (T, 3) int64
        T = sum(m - 2); polygon p's triangles start at row offsets[p] - 2 * p and keep its
        winding. Rows of -1 mark triangles left out: of polygons not kept, and those that
        repeated vertices make degenerate.
    """
    count = len(offsets) - 1
    triangles = np.full((offsets[count] - 2 * count, 3), -1, np.int64)
    for p in range(count):
        if not keep[p]:
            continue
        o = offsets[p]
        m = offsets[p + 1] - o
        t = o - 2 * p
        if m == 3 or (m == 4 and _convex_quad(vertices, polygon_vertices, o)):
            for j in range(m - 2):
                triangles[t + j, 0] = polygon_vertices[o]
                triangles[t + j, 1] = polygon_vertices[o + j + 1]
                triangles[t + j, 2] = polygon_vertices[o + j + 2]
        else:
            _triangulate_polygon(vertices, polygon_vertices[o:o + m], triangles[t:t + m - 2])
        for j in range(t, t + m - 2):
            a, b, c = triangles[j, 0], triangles[j, 1], triangles[j, 2]
            if a == b or b == c or c == a:
                triangles[j] = -1
    return triangles


@kernel
def side_keys(polygon_vertices, offsets, keep, n_vertices):
    """Undirected sides of the kept polygons as keys lo * N + hi (lo < hi), one per side:
    p[0]-p[1], ..., p[-1]-p[0]; sides from a vertex to itself are left out.

    Parameters
    ----------
    polygon_vertices, offsets : as for :func:`triangulate`
    keep : (P,) bool
    n_vertices : int
        N, the number of vertices.

    Returns
    -------
    keys : (E,) int64
    """
    keys = np.empty(offsets[-1], np.int64)
    e = 0
    for p in range(len(offsets) - 1):
        if not keep[p]:
            continue
        first = offsets[p]
        last = offsets[p + 1] - 1
        for k in range(first, last + 1):
            a = polygon_vertices[k]
            b = polygon_vertices[k + 1] if k < last else polygon_vertices[first]
            if a != b:
                keys[e] = min(a, b) * n_vertices + max(a, b)
                e += 1
    return keys[:e]
