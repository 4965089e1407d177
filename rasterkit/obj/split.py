"""Polygons split in NumPy, the way the polygon kernels split them.

Almost every polygon of a real OBJ file is a triangle, a convex quad, a concave quad or a small
polygon, and the few files with other ones have a handful. This module splits all of those
with NumPy, a group of polygons of one size at a time, so that a first run does not compile
the general splitter of :mod:`rasterkit.obj.kernels.polygons` (8-10 s; its monotone sweep for
large polygons 17 s more). It follows that kernel's steps:

- triangles as they are (one with a repeated corner is dropped later, as by the kernels);
- quads that turn the way of their Newell normal at every corner (convex in 3D): the fan
  from corner 0;
- in the polygon's plane (the kernels' basis): a polygon whose every corner turns left, and
  every triangle of the fan from its last corner too, is that fan; any other is ear clipped
  (:func:`rasterkit.obj.ears.ear_clip`, the kernel's clipper step for step).

Quads with one vertex repeated on neighbouring corners are the triangle of the other three;
a polygon with no normal (its corners on one line) is the fan from corner 0. Polygons the
kernels treat specially are left to them: other repeated vertex indices (a cycle walked
twice), two neighbouring corners at one place in the plane, or more corners than ear clipping
takes (:data:`~rasterkit.obj.kernels.ears.EAR_CLIP_LIMIT`). The arithmetic is the kernels' in plain
IEEE double precision where the kernels use fast-math (fused multiply-adds): a corner that is
straight to the last bit may be taken as turning the other way, which splits the polygon
differently but covers it all the same.
"""

from __future__ import annotations

import numpy as np

from rasterkit.obj.ears import ear_clip
from rasterkit.obj.kernels.ears import EAR_CLIP_LIMIT

__all__ = ["CHUNK", "split_in_numpy"]

#: Polygons of more than three corners split at once: the arrays of a chunk take about
#: ``CHUNK * m * 100`` bytes.
CHUNK = 1 << 15


def split_in_numpy(vertices: np.ndarray, corners: np.ndarray, offsets: np.ndarray,
                   keep: np.ndarray):
    """Split the kept polygons that need no kernel.

    ``vertices`` (N, 3) float64; ``corners`` (C,) int64 vertex indices of all polygons, one
    run after another, polygon p at ``offsets[p]:offsets[p + 1]`` (at least 3 corners, every
    index in [0, N)); ``keep`` (P,) bool.

    Returns ``parts``, a list of (polygons (K,) ascending, triangles (K, m - 2, 3) int64 as
    corners, indices into ``corners`` (the vertex of corner c is ``corners[c]``), with rows
    of -1 where none), ``inexact`` (P,) bool and ``left`` (P,) bool, the kept polygons left
    to the kernels."""
    sizes = np.diff(offsets)
    inexact = np.zeros(len(sizes), bool)
    left = keep & (sizes > EAR_CLIP_LIMIT)
    parts = []
    for m in np.unique(sizes[keep & (sizes <= EAR_CLIP_LIMIT)]):
        group = np.flatnonzero(keep & (sizes == m))
        if m == 3:
            parts.append((group, (offsets[group][:, None] + np.arange(3))[:, None, :]))
            continue
        for first in range(0, len(group), CHUNK):  # bounded memory: (chunk, m, 3) arrays
            chunk = group[first:first + CHUNK]
            at = offsets[chunk][:, None] + np.arange(m)
            ring = corners[at]
            with np.errstate(all="ignore"):  # huge or tiny coordinates are the kernels' too
                triangles, exact, done = _split(vertices, ring, at)
            if m == 4:
                triangles[~done], done[~done] = _quads_with_a_repeat(ring[~done], at[~done])
            parts.append((chunk[done], triangles[done]))
            inexact[chunk[done]] = ~exact[done]
            left[chunk[~done]] = True
    return parts, inexact, left


def _split(vertices: np.ndarray, ring: np.ndarray, at: np.ndarray):
    """Triangles (G, m - 2, 3) as the corners at (G, m) of the polygons, exact (G,) and
    done (G,) of polygons ring (G, m) (vertex indices), m > 3."""
    g, m = ring.shape
    triangles = np.full((g, m - 2, 3), -1, np.int64)
    exact = np.ones(g, bool)
    done = _distinct(ring)
    if m == 4:  # most quads are a fan from corner 0: decided on columns, without the plane
        first = done & _quad_fans(vertices, ring)
        triangles[first] = _fans(at[first], 0)
        rest = np.flatnonzero(done & ~first)
    else:
        rest = np.flatnonzero(done)
    points = vertices[ring[rest]]
    rel = points - points[:, :1]
    normal = _newell(rel)
    flat = ~((normal * normal).sum(axis=1) > 0.0)  # no normal: on one line
    triangles[rest[flat]] = _fans(at[rest[flat]], 0)
    plane = np.flatnonzero(~flat)
    xy = _plane(rel[plane], normal[plane])
    usable = np.isfinite(xy).all(axis=(1, 2)) & (xy != np.roll(xy, -1, axis=1)).any(axis=2).all(axis=1)
    done[rest[plane[~usable]]] = False
    plane, xy = rest[plane[usable]], xy[usable]
    convex = _fans_like_ear_clipping(xy)
    triangles[plane[convex]] = _fans(at[plane[convex]], m - 1)
    clip = plane[~convex]
    if len(clip):
        triangles[clip], exact[clip] = ear_clip(np.ascontiguousarray(xy[~convex]), at[clip])
    return triangles, exact, done


def _quad_fans(vertices: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """(G,) bool: quads ring (G, 4) split as the fan from corner 0: no normal (corners on one
    line), or turning the way of their Newell normal at every corner (convex in 3D); the
    arithmetic on columns, the kernels' formulas (normal relative to corner 0, sides from
    the coordinates)."""
    corner = [vertices[ring[:, k]] for k in range(4)]
    rel = [np.zeros_like(corner[0])] + [p - corner[0] for p in corner[1:]]
    nx = ny = nz = 0.0
    for k in range(4):
        p, q = rel[k], rel[(k + 1) % 4]
        nx = nx + (p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])
        ny = ny + (p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])
        nz = nz + (p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1])
    side = [corner[(k + 1) % 4] - corner[k] for k in range(4)]
    fan = np.ones(len(ring), bool)
    for k in range(4):
        s, t = side[k], side[(k + 1) % 4]
        turn = ((s[:, 1] * t[:, 2] - s[:, 2] * t[:, 1]) * nx + (s[:, 2] * t[:, 0] - s[:, 0] * t[:, 2]) * ny
                + (s[:, 0] * t[:, 1] - s[:, 1] * t[:, 0]) * nz)
        fan &= turn > 0.0
    return fan | ~(nx * nx + ny * ny + nz * nz > 0.0)


def _quads_with_a_repeat(ring: np.ndarray, at: np.ndarray):
    """Triangles (G, 2, 3), as the corners at (G, 4), and done (G,) of quads ring (G, 4)
    whose one repeated vertex is on neighbouring corners (``f 1 2 2 3``, ``f 1 2 3 1``):
    the triangle of the other three corners in order (the kernels merge the repeat and
    keep its first corner); the others are not done."""
    same = ring == np.roll(ring, -1, axis=1)  # corner k repeats corner k + 1
    ordered = np.sort(ring, axis=1)
    done = (same.sum(axis=1) == 1) & ((ordered[:, 1:] != ordered[:, :-1]).sum(axis=1) == 2)
    k = np.argmax(same, axis=1)
    drop = np.where(k == 3, 3, k + 1)  # the kernels keep the first of the two (corner 0 of 3, 0)
    order = np.sort((drop[:, None] + np.arange(1, 4)) % 4, axis=1)
    triangles = np.full((len(ring), 2, 3), -1, np.int64)
    triangles[done, 0] = np.take_along_axis(at, order, axis=1)[done]
    return triangles, done


def _fans(ring: np.ndarray, apex: int) -> np.ndarray:
    """(G, m - 2, 3): the fans of polygons ring (G, m) (their corners) from corner apex."""
    m = ring.shape[1]
    step = np.arange(m - 2)
    return np.stack([np.broadcast_to(ring[:, apex:apex + 1], (len(ring), m - 2)),
                     ring[:, (apex + 1 + step) % m], ring[:, (apex + 2 + step) % m]], axis=2)


def _newell(rel: np.ndarray) -> np.ndarray:
    """(G, 3) Newell normals of polygons rel (G, m, 3), coordinates relative to the first."""
    p, q = rel, np.roll(rel, -1, axis=1)
    return np.stack([((p[..., 1] - q[..., 1]) * (p[..., 2] + q[..., 2])).sum(axis=1),
                     ((p[..., 2] - q[..., 2]) * (p[..., 0] + q[..., 0])).sum(axis=1),
                     ((p[..., 0] - q[..., 0]) * (p[..., 1] + q[..., 1])).sum(axis=1)], axis=1)


def _distinct(ring: np.ndarray) -> np.ndarray:
    """(G,) bool: polygons whose vertex indices are all different."""
    if ring.shape[1] == 4:
        a, b, c, d = ring.T
        return (a != b) & (a != c) & (a != d) & (b != c) & (b != d) & (c != d)
    ordered = np.sort(ring, axis=1)
    return (ordered[:, 1:] != ordered[:, :-1]).all(axis=1)


def _plane(rel: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """(G, m, 2) coordinates in each polygon's plane, wound counter-clockwise around its
    normal, in the basis of :func:`rasterkit.obj.kernels.polygons._plane_coordinates`."""
    n = normal / np.linalg.norm(normal, axis=1, keepdims=True)
    a = np.abs(n)
    x_least = (a[:, 0] <= a[:, 1]) & (a[:, 0] <= a[:, 2])
    y_least = ~x_least & (a[:, 1] <= a[:, 2])
    zero = np.zeros(len(n))
    u = np.where(x_least[:, None], np.stack([zero, n[:, 2], -n[:, 1]], axis=1),
                 np.where(y_least[:, None], np.stack([-n[:, 2], zero, n[:, 0]], axis=1),
                          np.stack([n[:, 1], -n[:, 0], zero], axis=1)))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = np.cross(n, u)
    return np.stack([np.einsum("gmk,gk->gm", rel, u), np.einsum("gmk,gk->gm", rel, w)], axis=2)


def _fans_like_ear_clipping(xy: np.ndarray) -> np.ndarray:
    """(G,) bool: every corner turns left, and so does every triangle of the fan from the
    last corner but the last (then ear clipping would cut that fan)."""
    m = xy.shape[1]
    before, after = np.roll(xy, 1, axis=1), np.roll(xy, -1, axis=1)
    corner = _turns(before, xy, after)
    last = np.broadcast_to(xy[:, m - 1:], xy[:, :m - 3].shape)
    fan = _turns(last, xy[:, :m - 3], xy[:, 1:m - 2])
    return (corner > 0.0).all(axis=1) & (fan > 0.0).all(axis=1)


def _turns(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """z of (b - a) x (c - b), element-wise over (..., 2) points."""
    return ((b[..., 0] - a[..., 0]) * (c[..., 1] - b[..., 1])
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - b[..., 0]))
