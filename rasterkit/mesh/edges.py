"""Edges of a mesh: the unique undirected edges of polygons or vertex pairs, and the face
across each side of a triangle."""

from __future__ import annotations

import numpy as np

from rasterkit.mesh.checks import sealed_empty
from rasterkit.mesh.kernels import sorted_edges, sorted_polygon_edges
from rasterkit.runtime.jit import readonly

__all__ = ["ALL_SIDES", "polygon_edges", "polygon_mesh_edges", "side_neighbours", "unique_edges"]

#: The ``sides`` of :func:`rasterkit.mesh.kernels.sorted_edges` that keep every side.
ALL_SIDES = readonly(np.zeros(0, np.uint8))


def polygon_edges(polygons) -> np.ndarray:
    """Unique undirected edges (E, 2) int64 of a list of polygons (sequences of vertex indices).

    Each polygon contributes its boundary ``p[0]-p[1], ..., p[-1]-p[0]``; an edge shared by
    two polygons appears once, as ``(min, max)``, sorted.
    """
    pairs = []
    for k, p in enumerate(polygons):
        p = np.asarray(p)
        if p.dtype.kind not in "iu" or p.ndim != 1:
            raise TypeError(f"polygons[{k}] must be a sequence of integer vertex indices, got dtype {p.dtype} "
                            f"and shape {p.shape}")
        p = p.astype(np.int64)
        pairs.append(np.stack([p, np.roll(p, -1)], axis=1))
    if not pairs:
        return np.zeros((0, 2), np.int64)
    # Any integers: numbered 0..n-1 in order first, which keeps the edges' order.
    values, compact = np.unique(np.concatenate(pairs), return_inverse=True)
    return values[unique_edges(compact.reshape(-1, 2), len(values))]


def unique_edges(pairs: np.ndarray, n_vertices: int, keys: np.ndarray | None = None) -> np.ndarray:
    """Sorted unique undirected edges (E, 2) int64, ``(lo, hi)`` with lo < hi.

    Parameters
    ----------
    pairs : (K, 2) int
        Vertex index pairs, either way round; a pair from a vertex to itself is left out.
    n_vertices : int
        N: every index is in 0..N-1.
    keys : (J,) int64, optional
        More edges, as keys ``lo * N + hi`` (lo < hi).
    """
    pairs = np.asarray(pairs)
    if pairs.dtype.kind not in "iu" and pairs.size:
        raise TypeError(f"pairs must hold integer vertex indices, got dtype {pairs.dtype}")
    pairs = pairs.astype(np.int64, copy=False).reshape(-1, 2)
    n = max(int(n_vertices), 1)
    if keys is not None and len(keys):
        keys = np.asarray(keys, np.int64)
        pairs = np.concatenate([pairs, np.stack([keys // n, keys % n], axis=1)])
    if len(pairs) and (pairs.min() < 0 or pairs.max() >= n_vertices):
        raise ValueError(f"pairs index out of range [0, {n_vertices})")
    return sorted_edges(readonly(np.zeros((0, 3), np.int64)), ALL_SIDES, readonly(np.ascontiguousarray(pairs)),
                        int(n_vertices))


def polygon_mesh_edges(corners: np.ndarray, offsets: np.ndarray, keep: np.ndarray, triangles: np.ndarray | None,
                       polygon: np.ndarray | None, lines: np.ndarray, n_vertices: int) -> tuple:
    """``(edges, polygon_sides)`` to give a Mesh whose faces a reader split from polygons,
    for the sorted unique sides of the kept polygons (``corners[offsets[p]:offsets[p + 1]]``
    (int64, in [0, n_vertices), checked by the reader), ``keep`` (P,) bool) and the segments
    ``lines`` (K, 2) int64. The faces are ``triangles`` (M, 3), indices into ``corners`` (None:
    ``3 m + c``), cut from the polygons ``polygon`` (M,) (None: face m from polygon m; both
    None: every polygon a triangle, kept, and made a face).

    - ``(None, None)`` when the triangles are the polygons themselves (every polygon a
      triangle, kept, and made one face): the Mesh works their sides out when first needed.
    - ``(None, sides)`` when every kept polygon of n corners became n - 2 triangles (as
      splitting it covers it): each triangle's sides that are polygon sides (corners next to
      each other in the polygon), as :attr:`rasterkit.Mesh.polygon_sides`; the Mesh works the
      same edges out from them when first needed (loading does not pay for them).
    - ``(edges, None)`` otherwise (triangles dropped for a repeated vertex, polygons of fewer
      than three corners): the edges, worked out now."""
    if triangles is None and polygon is None:  # each polygon a triangle, kept, and made a face
        return None, None
    sizes = np.diff(offsets)
    m = len(sizes) if triangles is None else len(triangles)
    if m == len(sizes) and keep.all() and (sizes == 3).all():
        return None, None
    polygon = np.arange(m) if polygon is None else polygon
    if (sizes[keep] >= 3).all() and np.array_equal(np.bincount(polygon, minlength=len(sizes)),
                                                   np.where(keep, sizes - 2, 0)):
        rows = np.arange(3 * m, dtype=np.int64).reshape(-1, 3) if triangles is None else triangles
        # a polygon's corners next to each other are 1 or n - 1 apart (int32: corners of one
        # polygon, fewer than a file's 2**31 bytes)
        last = sizes.astype(np.int32)[polygon]
        last -= 1
        sealed, sides = sealed_empty(m, np.uint8)  # zeros that the Mesh keeps without a copy
        step = np.empty(m, np.int32)
        for k in range(3):  # a column at a time, in place: few temporaries (the memory bound)
            np.subtract(rows[:, (k + 1) % 3], rows[:, k], out=step, casting="unsafe")
            np.abs(step, out=step)
            beside = step == 1
            beside |= step == last
            sides |= beside.view(np.uint8) << k
        return None, sealed
    return sorted_polygon_edges(readonly(corners), readonly(offsets), readonly(keep), readonly(lines),
                                int(n_vertices)), None


def side_neighbours(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(M, 3) int32: for side ``c`` of each face (corners ``c`` and ``c + 1``), the other
    face with the same two vertices when exactly two faces have that side, else -1 (an
    open border, a side of three faces or more, or a side whose corners are one vertex)."""
    m = len(faces)
    a = faces.reshape(-1)
    b = faces[:, [1, 2, 0]].reshape(-1)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    keys = lo * max(int(n_vertices), 1) + hi
    keys[lo == hi] = -1 - np.arange(np.count_nonzero(lo == hi))  # each its own: no neighbour
    order = np.argsort(keys, kind="stable")
    same = keys[order][1:] == keys[order][:-1]
    pair = same.copy()  # a run of exactly two equal keys
    pair[1:] &= ~same[:-1]
    pair[:-1] &= ~same[1:]
    i = np.flatnonzero(pair)
    out = np.full(3 * m, -1, np.int32)
    out[order[i]] = order[i + 1] // 3
    out[order[i + 1]] = order[i] // 3
    return out.reshape(m, 3)
