"""The second half of :mod:`rasterkit.obj.kernels.monotone`: the faces that a polygon's sides
and its diagonals make (:func:`faces`), and the triangles of one y-monotone face
(:func:`cut_piece`, the stack walk down its two chains, in linear time).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.ears import cross


@kernel
def faces(xy, pairs):
    """The faces of the polygon's sides and the diagonals, as one array of corners and the
    offsets of each face: half-edges around each corner sorted by angle, each face walked
    with the face on its left."""
    m = len(xy)
    d = len(pairs)
    count = m + 2 * d
    origin = np.empty(count, np.int64)
    target = np.empty(count, np.int64)
    for e in range(m):
        origin[e], target[e] = e, (e + 1) % m
    for k in range(d):
        origin[m + 2 * k], target[m + 2 * k] = pairs[k, 0], pairs[k, 1]
        origin[m + 2 * k + 1], target[m + 2 * k + 1] = pairs[k, 1], pairs[k, 0]
    angle = np.empty(count)
    for h in range(count):
        angle[h] = np.arctan2(xy[target[h], 1] - xy[origin[h], 1],
                              xy[target[h], 0] - xy[origin[h], 0])
    by_angle = np.argsort(angle, kind="mergesort")
    around = by_angle[np.argsort(origin[by_angle], kind="mergesort")]  # by corner, then angle
    first = np.zeros(m + 1, np.int64)
    for h in range(count):
        first[origin[h] + 1] += 1
    for v in range(m):
        first[v + 1] += first[v]
    # next half-edge of each face: at the target v of h, the half-edge out of v next
    # clockwise from the direction back to h's origin
    following = np.empty(count, np.int64)
    for h in range(count):
        v = target[h]
        back = np.arctan2(xy[origin[h], 1] - xy[v, 1], xy[origin[h], 0] - xy[v, 0])
        lo, hi = first[v], first[v + 1]
        while lo < hi:  # the first of v's half-edges at an angle >= back
            mid = (lo + hi) // 2
            if angle[around[mid]] < back:
                lo = mid + 1
            else:
                hi = mid
        following[h] = around[lo - 1] if lo > first[v] else around[first[v + 1] - 1]
    corners = np.empty(count, np.int64)
    offsets = np.zeros(count + 1, np.int64)
    seen = np.zeros(count, np.bool_)
    n_pieces = 0
    c = 0
    for start in range(count):
        if seen[start]:
            continue
        h = start
        while not seen[h]:  # a face ends where it began (or, in a broken one, anywhere seen)
            seen[h] = True
            corners[c] = origin[h]
            c += 1
            h = following[h]
        n_pieces += 1
        offsets[n_pieces] = c
    return corners, offsets[:n_pieces + 1]


@kernel
def _emit(xy, triangles, t, a, b, c):
    """Write the triangle (a, b, c), turned counter-clockwise, into row t if there is room."""
    if t < len(triangles):
        if cross(xy, a, b, c) < 0.0:
            b, c = c, b
        triangles[t, 0], triangles[t, 1], triangles[t, 2] = a, b, c
    return t + 1


@kernel
def cut_piece(xy, rank, piece, triangles, t, stack, chain, merged):
    """Triangulate one y-monotone piece (corners in face order) into triangles from row t;
    returns the next free row."""
    k = len(piece)
    if k < 3:
        return t
    top = bottom = 0
    for q in range(k):
        if rank[piece[q]] < rank[piece[top]]:
            top = q
        if rank[piece[q]] > rank[piece[bottom]]:
            bottom = q
    # merge the left chain (forward from the top) and the right chain (backward) by rank
    a = top
    b = (top + k - 1) % k
    merged[0] = piece[top]
    chain[0] = 0
    for s in range(1, k):
        take_left = b == bottom or (a != bottom and rank[piece[(a + 1) % k]] < rank[piece[b]])
        if take_left and a != bottom:
            a = (a + 1) % k
            merged[s], chain[s] = piece[a], 0
        else:
            merged[s], chain[s] = piece[b], 1
            b = (b + k - 1) % k
    stack[0], stack[1] = 0, 1
    size = 2
    for s in range(2, k - 1):
        if chain[s] != chain[stack[size - 1]]:
            for q in range(size - 1):
                t = _emit(xy, triangles, t, merged[s], merged[stack[q]], merged[stack[q + 1]])
            stack[0], stack[1] = s - 1, s
            size = 2
        else:
            size -= 1
            last = stack[size]
            while size > 0:
                up = stack[size - 1]
                if chain[s] == 0:
                    inside = cross(xy, merged[up], merged[last], merged[s]) > 0.0
                else:
                    inside = cross(xy, merged[s], merged[last], merged[up]) > 0.0
                if not inside:
                    break
                t = _emit(xy, triangles, t, merged[s], merged[last], merged[up])
                last = up
                size -= 1
            stack[size] = last
            stack[size + 1] = s
            size += 2
    for q in range(size - 1):
        t = _emit(xy, triangles, t, merged[k - 1], merged[stack[q]], merged[stack[q + 1]])
    return t
