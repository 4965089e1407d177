"""Ear clipping of OBJ polygons in their plane (for :mod:`rasterkit.obj.kernels.polygons`).

The clipper walks the polygon from its first corner: a corner is an *ear* when its triangle
(previous, corner, next) turns left and no reflex or straight corner of what remains of the
polygon lies inside it or on its border (corners at the same place as one of the triangle's do
not count: a hole joined by a bridge repeats them). An ear is cut off and the walk goes on at
the next corner; when a whole round finds no ear (a self-intersecting or degenerate polygon),
the corner with the largest left turn is cut, so that clipping always ends.

An ear test looks at every remaining corner, so clipping costs O(m^2) for most polygons and
O(m^3) at worst: it is used up to :data:`EAR_CLIP_LIMIT` corners (larger polygons go to
:mod:`rasterkit.obj.kernels.monotone`). Its work (corners looked at) is also limited to
:data:`WORK_PER_CORNER` times the corner count: a polygon that needs more (only a
self-intersecting one can) has the rest of it split as a fan from the current corner, and
:func:`ear_clip` says so, so that the loader can warn.

The helpers both methods share are here too: :func:`cross` (the turn of three corners),
:func:`distinct_places` and :func:`covers` (the check of a split's triangles).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

#: Largest polygon that is ear clipped (the largest in the shared test models has 66 corners).
EAR_CLIP_LIMIT = 80

#: Work allowed per corner of a polygon, in corners looked at.
WORK_PER_CORNER = 512


@kernel(inline="always")
def cross(xy, a, b, c):
    """z of (b - a) x (c - b): > 0 when a, b, c turn left (counter-clockwise)."""
    return ((xy[b, 0] - xy[a, 0]) * (xy[c, 1] - xy[b, 1])
            - (xy[b, 1] - xy[a, 1]) * (xy[c, 0] - xy[b, 0]))


@kernel(inline="always")
def _same_point(xy, a, b):
    return xy[a, 0] == xy[b, 0] and xy[a, 1] == xy[b, 1]


@kernel(inline="always")
def _blocks(xy, prev, nxt, a, i, c, r):
    """True when corner r, reflex or straight, lies in or on the triangle (a, i, c) and is not
    at the same place as one of its corners."""
    if _same_point(xy, r, a) or _same_point(xy, r, i) or _same_point(xy, r, c):
        return False
    return (cross(xy, a, i, r) >= 0.0 and cross(xy, i, c, r) >= 0.0
            and cross(xy, c, a, r) >= 0.0 and cross(xy, prev[r], r, nxt[r]) <= 0.0)


@kernel
def distinct_places(xy):
    """Positions of the corners that are not at the same place as the corner before them
    (cyclically): a side of length 0 has no direction, which both methods need."""
    m = len(xy)
    keep = np.empty(m, np.int64)
    n = 0
    for k in range(m):
        if n == 0 or xy[k, 0] != xy[keep[n - 1], 0] or xy[k, 1] != xy[keep[n - 1], 1]:
            keep[n] = k
            n += 1
    while n > 1 and xy[keep[n - 1], 0] == xy[keep[0], 0] and xy[keep[n - 1], 1] == xy[keep[0], 1]:
        n -= 1
    return keep[:n]


@kernel
def covers(xy, triangles):
    """True when no triangle turns right and their areas add up to the polygon's (shoelace),
    both to rounding: what a wrong split shows (a split that overlaps itself and leaves a gap
    of the same area would pass, but neither method makes such). triangles (T, 3) hold
    positions in xy."""
    m = len(xy)
    polygon = 0.0
    for k in range(1, m - 1):
        polygon += cross(xy, 0, k, k + 1)
    total = 0.0
    magnitude = 0.0
    for q in range(len(triangles)):
        doubled = cross(xy, triangles[q, 0], triangles[q, 1], triangles[q, 2])
        total += doubled
        magnitude += abs(doubled)
    tolerance = 1e-9 * magnitude
    smallest = 0.0
    for q in range(len(triangles)):
        smallest = min(smallest, cross(xy, triangles[q, 0], triangles[q, 1], triangles[q, 2]))
    return smallest >= -tolerance and abs(total - polygon) <= tolerance


@kernel
def _most_convex(xy, prev, nxt, start, remaining):
    """The remaining vertex with the largest left turn: the fallback when no ear exists (a
    self-intersecting or degenerate polygon), so that clipping always ends."""
    best = start
    best_turn = -np.inf
    i = start
    for _ in range(remaining):
        turn = cross(xy, prev[i], i, nxt[i])
        if turn > best_turn:
            best, best_turn = i, turn
        i = nxt[i]
    return best


@kernel
def ear_clip(xy, ring, out):
    """Triangulate the polygon ring (m,) whose plane coordinates xy (m, 2) wind CCW, writing
    its m - 2 triangles (vertex indices from ring, same winding) into out. Returns True when
    it is exact, False when the work limit was reached and the rest was split as a fan."""
    m = len(ring)
    prev = np.empty(m, np.int64)
    nxt = np.empty(m, np.int64)
    for k in range(m):
        prev[k] = (k + m - 1) % m
        nxt[k] = (k + 1) % m
    budget = WORK_PER_CORNER * m
    work = 0
    i = 0
    remaining = m
    failures = 0
    t = 0
    while remaining > 3 and work <= budget:
        if failures >= remaining:
            i = _most_convex(xy, prev, nxt, i, remaining)
            work += remaining
        else:
            a = prev[i]
            c = nxt[i]
            ear = cross(xy, a, i, c) > 0.0
            r = nxt[c]
            while ear and r != a:
                ear = not _blocks(xy, prev, nxt, a, i, c, r)
                r = nxt[r]
                work += 1
            work += 1
            if not ear:
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
    if remaining == 3:
        out[t, 0], out[t, 1], out[t, 2] = ring[prev[i]], ring[i], ring[nxt[i]]
        return True
    j = nxt[i]
    for _ in range(remaining - 2):  # over the work limit: the rest as a fan from i
        out[t, 0], out[t, 1], out[t, 2] = ring[i], ring[j], ring[nxt[j]]
        t += 1
        j = nxt[j]
    return False
