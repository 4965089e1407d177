"""Triangulation of large polygons in O(m log m): split into y-monotone pieces by a plane sweep,
then each piece in linear time (de Berg, Cheong, van Kreveld, Overmars, *Computational
Geometry*, chapter 3). For :mod:`rasterkit.obj.kernels.polygons`, on polygons too large for
ear clipping.

Corners at the same place as the one before them are left out first (their sides have no
direction). The sweep goes down the plane coordinates in the order of :func:`_sweep_order`
(y, then x, then position: no two corners tie). It keeps the polygon's left sides that cross
the sweep line in a treap (a binary search tree balanced by random priorities), compared at
the sweep line (sides through one place, as bridges to holes make, by their direction below
it), and adds a diagonal at each split and merge corner. The faces of sides and diagonals are
then walked, and each piece is cut by the usual stack walk down its two chains
(:mod:`rasterkit.obj.kernels.pieces`).

The result covers a simple polygon exactly. A self-intersecting polygon gets *some* m - 2
triangles; :func:`triangulate_monotone` checks, in O(m), that every triangle turns left and
that their areas add up to the polygon's, and returns False when they do not (or when its
work limit, for a treap made deep by bad luck, was reached), so that the caller can warn.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.ears import covers, cross, distinct_places
from rasterkit.obj.kernels.pieces import cut_piece, faces

# Corner kinds of the sweep.
_START, _END, _SPLIT, _MERGE, _REGULAR = 0, 1, 2, 3, 4

#: Treap steps allowed per corner and per level of a balanced tree (log2 m).
WORK_PER_LEVEL = 64


@kernel
def _sweep_order(xy):
    """The corners by descending y, then ascending x, then position (rank 0 goes first)."""
    by_x = np.argsort(xy[:, 0], kind="mergesort")
    order = by_x[np.argsort(-xy[by_x, 1], kind="mergesort")]
    rank = np.empty(len(xy), np.int64)
    for k in range(len(xy)):
        rank[order[k]] = k
    return order, rank


@kernel(inline="always")
def _x_at(xy, e, f, x, y):
    """x of side e -> f (e above f) at the sweep line through (x, y); a horizontal side is
    cut where the (slightly tilted) sweep line meets it."""
    if xy[e, 1] == xy[f, 1]:
        return min(max(x, min(xy[e, 0], xy[f, 0])), max(xy[e, 0], xy[f, 0]))
    t = (y - xy[e, 1]) / (xy[f, 1] - xy[e, 1])
    return xy[e, 0] + t * (xy[f, 0] - xy[e, 0])


@kernel(inline="always")
def _goes_left_of(xy, e, f, s, t):
    """True when side e -> f runs left of side s -> t just below a point that both pass
    through (both run down the sweep order): the one whose x grows less per unit of descent."""
    return (xy[f, 0] - xy[e, 0]) * (xy[t, 1] - xy[s, 1]) > (xy[t, 0] - xy[s, 0]) * (xy[f, 1] -
                                                                                   xy[e, 1])


@kernel(inline="always")
def _side_left_of(xy, s, t, x, y):
    """True when side s -> t runs left of the point (x, y) on the sweep line; a side through
    the point counts as left of it when it runs down to the left or straight down (a corner
    at the same place as another, as bridges to holes make, is then on the right side of it)."""
    at = _x_at(xy, s, t, x, y)
    if at != x:
        return at < x
    return xy[t, 0] - xy[s, 0] <= 0.0 and xy[t, 1] != xy[s, 1]


@kernel
def _rotate_up(c, left, right, parent, root):
    """Rotate node c above its parent; returns the (new) root."""
    p = parent[c]
    g = parent[p]
    if left[p] == c:
        b = right[c]
        left[p] = b
        right[c] = p
    else:
        b = left[c]
        right[p] = b
        left[c] = p
    if b >= 0:
        parent[b] = p
    parent[p] = c
    parent[c] = g
    if g < 0:
        return c
    if left[g] == p:
        left[g] = c
    else:
        right[g] = c
    return root


@kernel
def _insert(xy, side_end, e, x, y, left, right, parent, priority, root):
    """Insert side e, whose top is (x, y) on the sweep line, into the treap; returns (root,
    steps). The treap is the arrays left, right, parent (-1: none) and priority, one node per
    side (node e is the side from corner e to side_end[e]), and its root."""
    steps = 0
    node = root
    last = -1
    go_left = False
    f = side_end[e]
    while node >= 0:
        steps += 1
        last = node
        at = _x_at(xy, node, side_end[node], x, y)
        go_left = x < at or (x == at and _goes_left_of(xy, e, f, node, side_end[node]))
        node = left[node] if go_left else right[node]
    left[e] = right[e] = -1
    parent[e] = last
    if last < 0:
        return e, steps
    if go_left:
        left[last] = e
    else:
        right[last] = e
    while parent[e] >= 0 and priority[e] > priority[parent[e]]:
        root = _rotate_up(e, left, right, parent, root)
        steps += 1
    return root, steps


@kernel
def _delete(e, left, right, parent, priority, root):
    """Remove side e from the treap; returns (root, steps)."""
    steps = 0
    while left[e] >= 0 and right[e] >= 0:
        child = left[e] if priority[left[e]] > priority[right[e]] else right[e]
        root = _rotate_up(child, left, right, parent, root)
        steps += 1
    child = left[e] if left[e] >= 0 else right[e]
    p = parent[e]
    if child >= 0:
        parent[child] = p
    if p < 0:
        root = child
    elif left[p] == e:
        left[p] = child
    else:
        right[p] = child
    parent[e] = left[e] = right[e] = -1
    return root, steps


@kernel
def _left_of(xy, side_end, x, y, left, right, root):
    """The side in the treap directly left of (x, y) (-1 when none), and the steps taken."""
    found = -1
    steps = 0
    node = root
    while node >= 0:
        steps += 1
        if _side_left_of(xy, node, side_end[node], x, y):
            found = node
            node = right[node]
        else:
            node = left[node]
    return found, steps


@kernel
def _diagonals(xy, rank, order, budget):
    """The diagonals (D, 2) that split the polygon into y-monotone pieces, and whether the
    sweep stayed within budget steps."""
    m = len(xy)
    kind = np.empty(m, np.int64)
    for v in range(m):
        u = (v + m - 1) % m
        w = (v + 1) % m
        turn = cross(xy, u, v, w)
        if rank[u] > rank[v] and rank[w] > rank[v]:
            kind[v] = _START if turn > 0.0 else _SPLIT
        elif rank[u] < rank[v] and rank[w] < rank[v]:
            kind[v] = _END if turn > 0.0 else _MERGE
        else:
            kind[v] = _REGULAR
    side_end = np.empty(m, np.int64)  # side e runs from corner e to corner e + 1
    for e in range(m):
        side_end[e] = (e + 1) % m
    left = np.full(m, -1, np.int64)
    right = np.full(m, -1, np.int64)
    parent = np.full(m, -1, np.int64)
    priority = np.empty(m, np.uint64)
    state = np.uint64(0x9E3779B97F4A7C15)
    for e in range(m):  # xorshift64: a fixed sequence, so results never vary between runs
        state ^= state << np.uint64(13)
        state ^= state >> np.uint64(7)
        state ^= state << np.uint64(17)
        priority[e] = state
    helper = np.full(m, -1, np.int64)
    pairs = np.empty((2 * m, 2), np.int64)
    d = 0
    root = -1
    work = 0
    for k in range(m):
        if work > budget:
            return pairs[:d], False
        v = order[k]
        x, y = xy[v, 0], xy[v, 1]
        before = (v + m - 1) % m
        what = kind[v]
        if what == _START:
            root, steps = _insert(xy, side_end, v, x, y, left, right, parent, priority, root)
            helper[v] = v
            work += steps
            continue
        if what == _END or what == _MERGE or (what == _REGULAR and rank[before] < rank[v]):
            # the side above v ends here (for a regular corner: v is on a left chain)
            h = helper[before]
            if h >= 0 and kind[h] == _MERGE:
                pairs[d, 0], pairs[d, 1] = v, h
                d += 1
            root, steps = _delete(before, left, right, parent, priority, root)
            work += steps
            if what == _REGULAR:
                root, steps = _insert(xy, side_end, v, x, y, left, right, parent, priority,
                                      root)
                helper[v] = v
                work += steps
                continue
            if what == _END:
                continue
        # split, merge and right-chain regular corners: the side directly left of v
        j, steps = _left_of(xy, side_end, x, y, left, right, root)
        work += steps
        if j >= 0:
            h = helper[j]
            if what == _SPLIT or (h >= 0 and kind[h] == _MERGE):
                pairs[d, 0], pairs[d, 1] = v, h
                d += 1
            helper[j] = v
        if what == _SPLIT:
            root, steps = _insert(xy, side_end, v, x, y, left, right, parent, priority, root)
            helper[v] = v
            work += steps
    return pairs[:d], True


@kernel
def triangulate_monotone(xy, ring, out):
    """Triangulate the polygon ring (m,) whose plane coordinates xy (m, 2) wind CCW into out
    (m - 2 rows, vertex indices from ring). Corners at the same place as the one before them
    are left out, and with them the flat triangles they would make: their rows stay as they
    are. Returns True when the triangles cover the polygon (see the module documentation)."""
    places = distinct_places(xy)
    if len(places) < 3:  # flat: nothing to cover
        return True
    if len(places) < len(xy):
        xy = np.ascontiguousarray(xy[places])
        ring = ring[places]
    m = len(ring)
    order, rank = _sweep_order(xy)
    levels = 1
    while (1 << levels) < m:
        levels += 1
    pairs, within = _diagonals(xy, rank, order, WORK_PER_LEVEL * levels * m)
    triangles = np.zeros((m - 2, 3), np.int64)
    t = 0
    exact = False
    if within:
        corners, offsets = faces(xy, pairs)
        stack = np.empty(len(corners) + 2, np.int64)
        chain = np.empty(len(corners) + 2, np.int64)
        merged = np.empty(len(corners) + 2, np.int64)
        for p in range(len(offsets) - 1):
            t = cut_piece(xy, rank, corners[offsets[p]:offsets[p + 1]], triangles, t, stack,
                           chain, merged)
        exact = t == m - 2 and covers(xy, triangles)
    if not within or t < m - 2:  # a fan: every row must be filled
        for q in range(m - 2):
            triangles[q, 0], triangles[q, 1], triangles[q, 2] = 0, q + 1, q + 2
        exact = False
    for q in range(m - 2):
        out[q, 0], out[q, 1], out[q, 2] = (ring[triangles[q, 0]], ring[triangles[q, 1]],
                                           ring[triangles[q, 2]])
    return exact
