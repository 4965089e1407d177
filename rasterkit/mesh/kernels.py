"""The Numba kernels behind a Mesh's edges: the unique undirected sides of triangles or
polygons and of vertex pairs, sorted, in two passes over the sides; and the triangles with a
repeated corner, which the readers leave out.

Each side's upper vertex is put in the list of its lower one (a counting sort by lower
vertex: one pass to count, one to place), then each list is sorted and its repeats dropped:
by insertion for the short lists of real meshes, by a heap sort (O(d log d)) for a vertex
of many sides, so that no mesh makes it quadratic. Memory: 8 bytes a side and 16 a vertex
besides the result.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["repeated_corners", "sorted_edges", "sorted_polygon_edges"]

#: Neighbour lists up to this long are sorted by insertion, longer ones by a heap sort.
SHORT = 24


@kernel(inline="always")
def _tally(start, a, b):
    """Count side a-b in the list of its lower vertex (``start[lo + 1]``); none for a == b."""
    if a != b:
        start[(a if a < b else b) + 1] += 1


@kernel(inline="always")
def _place(uppers, fill, a, b):
    """Put side a-b's upper vertex at the next free place of its lower vertex's list."""
    if a != b:
        lo = a if a < b else b
        uppers[fill[lo]] = b if a < b else a
        fill[lo] += 1


@kernel(inline="always")
def _open_lists(start, pairs, n_vertices):
    """Count ``pairs`` (K, 2) into ``start`` too, turn the counts into the lists' starts
    (prefix sums) and return the lists' storage and each list's next free place."""
    for p in range(pairs.shape[0]):
        _tally(start, pairs[p, 0], pairs[p, 1])
    for v in range(n_vertices):
        start[v + 1] += start[v]
    return np.empty(start[n_vertices], np.int64), start[:n_vertices].copy()


@kernel(inline="always")
def _close_lists(start, uppers, fill, pairs, n_vertices):
    """Place ``pairs`` in the lists too and return :func:`_unique_lists` of them."""
    for p in range(pairs.shape[0]):
        _place(uppers, fill, pairs[p, 0], pairs[p, 1])
    return _unique_lists(start, uppers, n_vertices)


@kernel
def _heap_sort(a, first, end):
    """Sort ``a[first:end]`` in place in O(d log d) (a heap sort: a few lines to compile,
    where NumPy's sort in a kernel compiles for seconds)."""
    n = end - first
    for root in range(n // 2 - 1, -1, -1):
        _sift(a, first, root, n)
    for last in range(n - 1, 0, -1):
        a[first], a[first + last] = a[first + last], a[first]
        _sift(a, first, 0, last)


@kernel(inline="always")
def _sift(a, first, root, n):
    """Move ``a[first + root]`` down the max-heap ``a[first:first + n]`` to its place."""
    while True:
        child = 2 * root + 1
        if child >= n:
            return
        if child + 1 < n and a[first + child + 1] > a[first + child]:
            child += 1
        if a[first + root] >= a[first + child]:
            return
        a[first + root], a[first + child] = a[first + child], a[first + root]
        root = child


@kernel(inline="always")
def _unique_lists(start, uppers, n_vertices):
    """(E, 2) int64 ``(lo, hi)`` of the lists ``uppers[start[lo]:start[lo + 1]]`` (prefix
    sums in ``start``), each sorted and without repeats."""
    kept = np.empty(n_vertices, np.int64)
    e = 0
    for lo in range(n_vertices):
        first, end = start[lo], start[lo + 1]
        if end - first > SHORT:
            _heap_sort(uppers, first, end)
        else:
            for i in range(first + 1, end):
                x = uppers[i]
                j = i - 1
                while j >= first and uppers[j] > x:
                    uppers[j + 1] = uppers[j]
                    j -= 1
                uppers[j + 1] = x
        u = first
        for i in range(first, end):
            if i == first or uppers[i] != uppers[u - 1]:
                uppers[u] = uppers[i]
                u += 1
        kept[lo] = u - first
        e += u - first
    out = np.empty((e, 2), np.int64)
    e = 0
    for lo in range(n_vertices):
        for i in range(start[lo], start[lo] + kept[lo]):
            out[e, 0] = lo
            out[e, 1] = uppers[i]
            e += 1
    return out


@kernel
def sorted_edges(faces, sides, pairs, n_vertices):
    """The unique undirected edges (E, 2) int64 ``(lo, hi)``, lo < hi, sorted by lo then hi,
    of the sides of the triangles ``faces`` (M, 3) and of the pairs ``pairs`` (K, 2) (int64
    indices in [0, n_vertices), which the caller has checked); a side or pair from a vertex
    to itself is left out. ``sides`` (M,) uint8, or empty for every side: bit k of
    ``sides[f]`` keeps side k of face f (corner k to corner k + 1, mod 3), as
    :attr:`rasterkit.Mesh.polygon_sides` says."""
    every = sides.shape[0] == 0
    start = np.zeros(n_vertices + 1, np.int64)
    for f in range(faces.shape[0]):
        keep = 7 if every else sides[f]
        for k in range(3):
            if keep >> k & 1:
                _tally(start, faces[f, k], faces[f, k + 1 if k < 2 else 0])
    uppers, fill = _open_lists(start, pairs, n_vertices)
    for f in range(faces.shape[0]):
        keep = 7 if every else sides[f]
        for k in range(3):
            if keep >> k & 1:
                _place(uppers, fill, faces[f, k], faces[f, k + 1 if k < 2 else 0])
    return _close_lists(start, uppers, fill, pairs, n_vertices)


@kernel
def sorted_polygon_edges(corners, offsets, keep, pairs, n_vertices):
    """:func:`sorted_edges` of the sides ``c[0]-c[1], ..., c[-1]-c[0]`` of each kept polygon
    ``c = corners[offsets[p]:offsets[p + 1]]`` (``offsets`` (P + 1,) rising from 0 to
    ``len(corners)``, ``keep`` (P,) bool; indices checked by the caller) and of ``pairs``."""
    start = np.zeros(n_vertices + 1, np.int64)
    for p in range(len(offsets) - 1):
        if keep[p]:
            first, end = offsets[p], offsets[p + 1]
            for c in range(first, end):
                _tally(start, corners[c], corners[c + 1] if c + 1 < end else corners[first])
    uppers, fill = _open_lists(start, pairs, n_vertices)
    for p in range(len(offsets) - 1):
        if keep[p]:
            first, end = offsets[p], offsets[p + 1]
            for c in range(first, end):
                _place(uppers, fill, corners[c], corners[c + 1] if c + 1 < end else corners[first])
    return _close_lists(start, uppers, fill, pairs, n_vertices)


@kernel
def repeated_corners(faces):
    """(M,) bool: whether triangle ``faces[f]`` (M, 3) has a vertex at two corners (one pass
    over the rows, where NumPy compares strided columns into three temporaries)."""
    out = np.empty(faces.shape[0], np.bool_)
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        out[f] = a == b or b == c or c == a
    return out
