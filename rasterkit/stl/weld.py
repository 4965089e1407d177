"""Welding the corners of an STL file's facets into shared vertices: rows of coordinates that
are equal as numbers become one vertex, numbered in order of first appearance.

Equal as numbers: the bit patterns are compared after ``-0.0`` is made ``0.0``; the caller
drops corners that are NaN or infinite first. The hash table of
:func:`rasterkit.stl.kernels.mesh.weld` does it in O(corners); corners made to collide in it are
welded by sorting instead (:func:`weld_by_sorting`, O(n log n)), with the same result.
"""

from __future__ import annotations

import numpy as np

from rasterkit.stl.kernels.mesh import COLLIDING, weld

__all__ = ["BYTES_PER_CORNER", "weld_corners", "weld_by_sorting"]

#: Bytes per corner while welding: its number, the first corner of each number and the hash
#: table (half a slot per corner, of 4 keys of 8 bytes; a slot per corner when it grows).
BYTES_PER_CORNER = 8 + 8 + 32


def weld_corners(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``inverse`` (K,) int64, the vertex of each corner of ``corners`` (K, 3) float32 or
    float64 (finite, C-contiguous, changed in place: ``-0.0`` becomes ``0.0``), and ``first``
    (V,) int64, the first corner of each vertex: the vertices are ``corners[first]``."""
    corners += corners.dtype.type(0)  # -0.0 + 0.0 is 0.0: equal numbers, equal bits (no copy)
    keys = corners.view(np.uint32 if corners.dtype == np.float32 else np.uint64)
    k = len(keys)
    bits = max(10, int(k // 2).bit_length())  # room for k / 4 vertices: a closed mesh has k / 6
    while True:
        inverse, first, n = weld(keys, bits)
        if n >= 0:
            return inverse, first
        if n == COLLIDING:
            return weld_by_sorting(keys)
        bits = max(bits + 2, int(2 * k).bit_length())  # room for every corner


def weld_by_sorting(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`weld_corners` of ``keys`` (K, 3) unsigned integers by NumPy's sort."""
    rows = np.ascontiguousarray(keys).view(np.dtype((np.void, 3 * keys.dtype.itemsize))).ravel()
    _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")  # numbered by first appearance, as the hash numbers
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return rank[inverse.ravel()], first[order]
