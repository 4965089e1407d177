"""Numba kernels that turn OBJ polygons into triangles and edges.

A polygon is triangulated in the plane of its Newell normal, at a cost linear in its corner
count except where ear clipping is needed:

- Triangles and convex quads are split as a fan from their first corner.
- Consecutive repeats of a vertex are merged (``f 1 2 2 3`` is a triangle), and a polygon that
  walks one cycle of vertices several times (``f 1 2 3 1 2 3``) is that cycle once.
- A polygon whose every corner turns left, and every triangle of the fan from its last corner
  too, is that fan (convex polygons: a test in O(m)); it is what ear clipping would give.
- Every other polygon of up to :data:`~rasterkit.obj.kernels.ears.EAR_CLIP_LIMIT` corners is
  ear clipped (:mod:`rasterkit.obj.kernels.ears`), larger ones are split into monotone pieces
  by a plane sweep in O(m log m) (:mod:`rasterkit.obj.kernels.monotone`): both cover concave
  polygons (and holes joined by a bridge) exactly, and both say when they could not (a
  self-intersecting polygon, or work beyond their limits), so that the loader can warn.
  Corners at the same place as the one before them make no triangle (ear clipping is done
  again without them when they made it cut wrong triangles).
- A larger polygon whose sides do not turn round exactly once (:func:`_turning_number`: it
  crosses itself, or winds round several times) cannot be simple: it is split as a fan, in
  O(m), and reported like the above.

Most polygons of real files never reach these kernels: :mod:`rasterkit.obj.split` finds
their triangles (these kernels' own) with NumPy, and :mod:`rasterkit.obj.assemble` calls
:func:`triangulate` only for the rest, and :func:`split_large` (the monotone sweep, a kernel
of its own) only for polygons larger than ear clipping takes. Inputs are vertex indices
already checked by the caller. A triangle's corners come out as corners of its polygon
(positions in it, or indices into the array of every polygon's corners), not as vertex
indices: the caller takes each corner's vertex, texture coordinate and normal from them,
so that a corner keeps the attributes the file gave it (a vertex repeated in a polygon,
as a hole's bridge repeats two, may have different ones at each visit)."""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.ears import EAR_CLIP_LIMIT, covers, cross, distinct_places, ear_clip
from rasterkit.obj.kernels.monotone import triangulate_monotone


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
    """The polygon without consecutive (cyclically) repeated vertex indices, and walked once
    when it is one cycle of vertices walked several times (``1 2 3 1 2 3``): the positions
    (k,) in polygon of the corners kept (the first of each run of repeats, the first walk
    of a cycle), and their vertex indices (k,)."""
    m = len(polygon)
    at = np.empty(m, np.int64)
    k = 0
    for j in range(m):
        if k == 0 or polygon[j] != polygon[at[k - 1]]:
            at[k] = j
            k += 1
    while k > 1 and polygon[at[k - 1]] == polygon[at[0]]:
        k -= 1
    ring = np.empty(k, np.int64)
    for j in range(k):
        ring[j] = polygon[at[j]]
    period = _period(ring)
    return at[:period], ring[:period]


@kernel
def _period(ring):
    """The length of the shortest cycle that ring repeats a whole number of times (len(ring)
    when it repeats none), by Knuth-Morris-Pratt's prefix function in O(m)."""
    m = len(ring)
    if m < 6:
        return m
    border = np.zeros(m, np.int64)  # border[k]: longest proper border of ring[:k + 1]
    for k in range(1, m):
        b = border[k - 1]
        while b > 0 and ring[k] != ring[b]:
            b = border[b - 1]
        border[k] = b + 1 if ring[k] == ring[b] else 0
    period = m - border[m - 1]
    return period if m % period == 0 else m


@kernel
def _fans_like_ear_clipping(xy):
    """True when ear clipping (:func:`rasterkit.obj.kernels.ears.ear_clip`) would cut the
    fan from the last corner, checked in O(m): every corner turns left (so no corner is reflex
    or straight and no ear can be blocked), and so does every triangle of that fan but the
    last (so each is an ear when its turn comes). This is the case of convex polygons."""
    m = len(xy)
    for k in range(m):
        if not cross(xy, (k + m - 1) % m, k, (k + 1) % m) > 0.0:
            return False
    for k in range(m - 3):
        if not cross(xy, m - 1, k, k + 1) > 0.0:
            return False
    return True


@kernel
def _turning_number(xy):
    """How many times the sides of the closed polygon xy turn round, in O(m): 1 for a simple
    polygon wound counter-clockwise (also one with holes joined by bridges); a polygon that
    crosses itself or winds round several times mostly has another."""
    m = len(xy)
    total = 0.0
    px = xy[0, 0] - xy[m - 1, 0]
    py = xy[0, 1] - xy[m - 1, 1]
    for k in range(m):
        qx = xy[(k + 1) % m, 0] - xy[k, 0]
        qy = xy[(k + 1) % m, 1] - xy[k, 1]
        if qx == 0.0 and qy == 0.0:
            continue  # a side of length 0 turns nothing: the next side turns from the last
        if px != 0.0 or py != 0.0:
            total += np.arctan2(px * qy - py * qx, px * qx + py * qy)
        px, py = qx, qy
    return round(total / (2.0 * np.pi))


@kernel
def _ear_clip_with_repeated_places(xy, ring, out):
    """Ear clipping; where corners are at the same place as the one before them (a side of
    length 0), it may cut wrong triangles: then the polygon is clipped again without them. (The
    first cut is kept when it is right: the triangles of the polygons it always served stay as
    they were.)"""
    places = distinct_places(xy)
    if len(places) == len(ring):
        return ear_clip(xy, ring, out)
    m = len(ring)
    local = np.full((m - 2, 3), -1, np.int64)
    exact = ear_clip(xy, np.arange(m), local)
    if exact and covers(xy, local):
        for q in range(m - 2):
            for k in range(3):
                out[q, k] = ring[local[q, k]]
        return True
    if len(places) < 3:
        return True
    local = np.full((len(places) - 2, 3), -1, np.int64)
    exact = ear_clip(np.ascontiguousarray(xy[places]), np.arange(len(places)), local)
    for q in range(len(places) - 2):
        for k in range(3):
            out[q, k] = ring[places[local[q, k]]]
    return exact


#: What the split of one polygon came to.
EXACT, INEXACT, LARGE = 0, 1, 2
_SPLIT = 3  # (only between _prepare and its callers: still to split in the plane)


@kernel
def _prepare(vertices, polygon, out):
    """The steps every split begins with: repeats merged, the polygons that need no search
    split as a fan into out (m - 2, 3), as positions in polygon. Returns (at, xy, state):
    state EXACT or INEXACT when out is done, else _SPLIT: the corners at positions at (k,)
    are still to split in their plane coordinates xy (k, 2)."""
    at, ring = _merge_repeats(polygon)
    nowhere = np.empty((0, 2))
    if len(ring) < 3:
        return at, nowhere, EXACT
    nx, ny, nz = _newell_normal(vertices, ring)
    if len(ring) == 3 or not nx * nx + ny * ny + nz * nz > 0.0:
        _fan(at, out)
        return at, nowhere, EXACT
    xy = _plane_coordinates(vertices, ring, nx, ny, nz)
    if not np.isfinite(xy).all():
        _fan(at, out)
        return at, xy, INEXACT
    if _fans_like_ear_clipping(xy):
        last = len(at) - 1
        for k in range(last - 1):
            out[k, 0], out[k, 1], out[k, 2] = at[last], at[k], at[k + 1]
        return at, xy, EXACT
    return at, xy, _SPLIT


@kernel
def _triangulate_polygon(vertices, polygon, out):
    """Triangles of one polygon (m >= 4 vertex indices) into out (m - 2, 3), as positions
    in polygon, in the polygon's best-fit plane; rows left over stay -1. Returns EXACT,
    INEXACT (could not be split exactly: see the module documentation) or LARGE (left for
    :func:`split_large`: more corners than ear clipping takes)."""
    at, xy, state = _prepare(vertices, polygon, out)
    if state != _SPLIT:
        return state
    if len(at) > EAR_CLIP_LIMIT:
        return LARGE
    return EXACT if _ear_clip_with_repeated_places(xy, at, out) else INEXACT


@kernel
def triangulate(vertices, polygon_vertices, offsets, keep):
    """Triangulate polygons given as runs of vertex indices: triangles and convex quads by a
    fan, anything else in the plane of its Newell normal (see the module documentation),
    except the polygons larger than ear clipping takes (:func:`split_large`).

    Parameters
    ----------
    vertices : (N, 3) float64
    polygon_vertices : (C,) int64
        Vertex indices of all polygons, one after another; every index is in [0, N).
    offsets : (P + 1,) int64
        Polygon p is polygon_vertices[offsets[p]:offsets[p + 1]], with at least 3 vertices.
    keep : (P,) bool
        Polygons to triangulate; the others give no triangles.

    Returns
    -------
    triangles : (T, 3) int64
        The triangles of the kept polygons in polygon order, each polygon's in its winding,
        as corners: indices into polygon_vertices (so that the caller finds each corner's
        attributes; its vertex is ``polygon_vertices[triangles]``). T <= sum(m - 2):
        triangles that repeated vertices make degenerate are left out. A view of an array of
        sum(m - 2) rows.
    counts : (P,) int64
        Triangles of each polygon.
    state : (P,) int8
        EXACT, INEXACT (could not be split exactly: see the module documentation) or LARGE
        (no triangles here: split it with :func:`split_large`).
    """
    count = len(offsets) - 1
    triangles = np.empty((offsets[count] - 2 * count, 3), np.int64)
    counts = np.zeros(count, np.int64)
    state = np.zeros(count, np.int8)
    n = 0  # rows kept so far: polygon p writes from row n, never past its own rows
    for p in range(count):
        if not keep[p]:
            continue
        o = offsets[p]
        m = offsets[p + 1] - o
        rows = triangles[n:n + m - 2]
        rows[:] = -1
        if m == 3 or (m == 4 and _convex_quad(vertices, polygon_vertices, o)):
            for j in range(m - 2):
                rows[j, 0], rows[j, 1], rows[j, 2] = 0, j + 1, j + 2
        else:
            state[p] = _triangulate_polygon(vertices, polygon_vertices[o:o + m], rows)
        start = n
        for j in range(m - 2):  # rows: positions in the polygon, -1 where none
            a, b, c = rows[j, 0], rows[j, 1], rows[j, 2]
            if a < 0:
                continue
            va, vb, vc = polygon_vertices[o + a], polygon_vertices[o + b], polygon_vertices[o + c]
            if va != vb and vb != vc and vc != va:
                triangles[n, 0], triangles[n, 1], triangles[n, 2] = o + a, o + b, o + c
                n += 1
        counts[p] = n - start
    return triangles[:n], counts, state


@kernel
def split_large(vertices, polygon):
    """The triangles (m - 2, 3) of one polygon that :func:`triangulate` left LARGE, as
    positions in polygon (its rows -1 where none), and whether the split is exact: a
    polygon whose sides do not turn round once is a fan, others are split by the monotone
    sweep. A kernel of its own: the sweep compiles for about 17 s, which only files with
    such polygons pay."""
    out = np.full((len(polygon) - 2, 3), -1, np.int64)
    at, xy, state = _prepare(vertices, polygon, out)
    if state != _SPLIT:
        return out, state == EXACT
    if _turning_number(xy) != 1:  # not simple: a fan, in O(m)
        _fan(at, out)
        return out, False
    return out, triangulate_monotone(xy, at, out)
