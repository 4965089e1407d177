"""Ear clipping in NumPy: many polygons of one size at a time, in lock step.

The clipper of :func:`rasterkit.obj.kernels.ears.ear_clip`, step for step, for the polygons
of a real file that are neither triangles nor convex (concave quads, nearly flat corners,
concave polygons of a few corners): a handful per file, which would otherwise compile the
kernel for 8 to 10 seconds on a first run. Each step of the loop below is one step of the
kernel's loop for every polygon still being clipped; the arithmetic is the kernel's (a turn is
``(b - a) x (c - b)``), in plain IEEE double precision.
"""

from __future__ import annotations

import numpy as np

from rasterkit.obj.kernels.ears import WORK_PER_CORNER

__all__ = ["ear_clip"]


class _Clipper:
    """The state of the clipping of G polygons of m corners (CCW plane coordinates xy
    (G, m, 2), vertex indices ring (G, m)): each polygon's remaining corners as a cyclic
    list (prev, nxt), its current corner, work, failures and triangles so far."""

    def __init__(self, xy: np.ndarray, ring: np.ndarray):
        g, m = ring.shape
        self.xy, self.ring = xy, ring
        self.prev = np.tile((np.arange(m) + m - 1) % m, (g, 1))
        self.nxt = np.tile((np.arange(m) + 1) % m, (g, 1))
        self.corner = np.zeros(g, np.int64)
        self.remaining = np.full(g, m, np.int64)
        self.failures = np.zeros(g, np.int64)
        self.work = np.zeros(g, np.int64)
        self.budget = WORK_PER_CORNER * m
        self.out = np.full((g, m - 2, 3), -1, np.int64)
        self.t = np.zeros(g, np.int64)

    def turn(self, p, a, b, c):
        """z of (b - a) x (c - b) for corners a, b, c of polygons p (all (K,) arrays)."""
        xa, ya = self.xy[p, a, 0], self.xy[p, a, 1]
        xb, yb = self.xy[p, b, 0], self.xy[p, b, 1]
        xc, yc = self.xy[p, c, 0], self.xy[p, c, 1]
        return (xb - xa) * (yc - yb) - (yb - ya) * (xc - xb)

    def same_point(self, p, a, b):
        return (self.xy[p, a] == self.xy[p, b]).all(axis=1)

    def blocks(self, p, a, i, c, r):
        """Corner r, reflex or straight, lies in or on the triangle (a, i, c) and is not at
        the same place as one of its corners."""
        elsewhere = ~(self.same_point(p, r, a) | self.same_point(p, r, i) | self.same_point(p, r, c))
        return (elsewhere & (self.turn(p, a, i, r) >= 0.0) & (self.turn(p, i, c, r) >= 0.0)
                & (self.turn(p, c, a, r) >= 0.0)
                & (self.turn(p, self.prev[p, r], r, self.nxt[p, r]) <= 0.0))

    def is_ear(self, p):
        """Whether the current corner of each of polygons p is an ear (the work counted)."""
        i = self.corner[p]
        a, c = self.prev[p, i], self.nxt[p, i]
        ear = self.turn(p, a, i, c) > 0.0
        r = self.nxt[p, c]
        looking = ear & (r != a)
        while looking.any():
            k = np.flatnonzero(looking)
            q = p[k]
            ear[k] = ~self.blocks(q, a[k], i[k], c[k], r[k])
            r[k] = self.nxt[q, r[k]]
            self.work[q] += 1
            looking[k] = ear[k] & (r[k] != a[k])
        self.work[p] += 1
        return ear

    def most_convex(self, p):
        """Move the current corner of polygons p to their remaining corner with the largest
        left turn (the first such from the current one)."""
        best = self.corner[p].copy()
        best_turn = np.full(len(p), -np.inf)
        j = best.copy()
        for step in range(int(self.remaining[p].max(initial=0))):
            live = step < self.remaining[p]
            turn = self.turn(p, self.prev[p, j], j, self.nxt[p, j])
            better = live & (turn > best_turn)
            best[better], best_turn[better] = j[better], turn[better]
            j = self.nxt[p, j]
        self.corner[p] = best
        self.work[p] += self.remaining[p]

    def emit(self, p, apex, b, c):
        self.out[p, self.t[p]] = np.stack([self.ring[p, apex], self.ring[p, b], self.ring[p, c]], axis=1)
        self.t[p] += 1

    def cut(self, p):
        """Cut the current corner of polygons p off as a triangle; go on at the next."""
        i = self.corner[p]
        a, c = self.prev[p, i], self.nxt[p, i]
        self.emit(p, a, i, c)
        self.nxt[p, a] = c
        self.prev[p, c] = a
        self.corner[p] = c
        self.remaining[p] -= 1
        self.failures[p] = 0

    def step(self, p):
        """One step of the kernel's loop for polygons p."""
        stuck = self.failures[p] >= self.remaining[p]
        self.most_convex(p[stuck])
        self.cut(p[stuck])
        p = p[~stuck]
        ear = self.is_ear(p)
        missed = p[~ear]
        self.corner[missed] = self.nxt[missed, self.corner[missed]]
        self.failures[missed] += 1
        self.cut(p[ear])

    def finish(self) -> np.ndarray:
        """The last triangle, or where the work ran out the rest as a fan from the current
        corner; (G,) bool: exact (no fan)."""
        p = np.arange(len(self.ring))
        i = self.corner
        exact = self.remaining == 3
        last = p[exact]
        self.emit(last, self.prev[last, i[last]], i[last], self.nxt[last, i[last]])
        over = p[~exact]
        j = self.nxt[over, i[over]]
        for step in range(int(self.remaining[over].max(initial=0)) - 2):
            live = step < self.remaining[over] - 2
            q, jq = over[live], j[live]
            self.emit(q, i[q], jq, self.nxt[q, jq])
            j[live] = self.nxt[q, jq]
        return exact


def ear_clip(xy: np.ndarray, ring: np.ndarray):
    """Triangulate polygons ring (G, m) int64 whose plane coordinates xy (G, m, 2) wind
    counter-clockwise, as :func:`rasterkit.obj.kernels.ears.ear_clip` does each.

    Returns triangles (G, m - 2, 3) int64 (entries of ring, which are only copied: the
    polygons' corners or vertex indices; same winding) and
    exact (G,) bool: False where the work limit was reached and the rest split as a fan."""
    clipper = _Clipper(xy, ring)
    while True:
        going = np.flatnonzero((clipper.remaining > 3) & (clipper.work <= clipper.budget))
        if len(going) == 0:
            break
        clipper.step(going)
    return clipper.out, clipper.finish()
