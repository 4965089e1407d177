"""Welding the corners of an STL file's facets into shared vertices (:func:`weld_facets`): rows
of coordinates that are equal as numbers become one vertex, numbered in order of first
appearance among the sound facets (those without a NaN or infinite number, and without two
equal corners), in the same pass that finds each facet's flaws and keeps its normal.

Equal as numbers: ``-0.0`` is ``0.0``. The hash table of
:func:`rasterkit.stl.kernels.mesh.assemble` does it in O(corners); corners made to collide in
it are numbered by sorting instead (:func:`weld_by_sorting`, O(n log n)), with the same result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.stl.kernels.mesh import COLLIDING, FULL, SOUND, assemble

__all__ = ["BYTES_PER_CORNER", "Welded", "facet_flaws", "weld_facets", "weld_by_sorting"]

#: Bytes per corner while welding, at most: its vertex (float64 coordinates) and its slot of
#: the hash table (8 bytes, a table at most a quarter full; twice that when it grows).
BYTES_PER_CORNER = 24 + 8 * 4

_NO_IDS = np.zeros(0, np.int64)


@dataclass(frozen=True)
class Welded:
    """The facets welded (see :func:`weld_facets`)."""

    flaws: np.ndarray  # (F,) uint8: SOUND, NOT_FINITE or TWO_EQUAL, each facet's
    faces: np.ndarray  # (M, 3) int64: the sound facets' vertices
    vertices: np.ndarray  # (N, 3) float64, without -0.0
    normals: np.ndarray  # (M, 3) float64: each sound facet's unit normal
    missing: int  # file normals zero, NaN or infinite (replaced by their corners')
    backwards: int  # file normals against their facet's winding (likewise)


def weld_facets(corners: np.ndarray, normals: np.ndarray) -> Welded:
    """:class:`Welded` of the facets ``corners`` (F, 3, 3) float32 or float64 (any strides)
    whose file normals are ``normals`` (F, 3), by :func:`rasterkit.stl.kernels.mesh.assemble`."""
    f = len(corners)
    flaws = np.empty(f, np.uint8)
    faces = np.empty((f, 3), np.int64)
    unit = np.empty((f, 3))
    vertices = np.empty((3 * f, 3))  # room for every corner; only the vertices' pages are touched
    bits = max(10, int(3 * f // 2).bit_length())  # room for 3f / 4 vertices: a closed mesh has 3f / 6
    ids = _NO_IDS
    while True:
        kept, n, missing, backwards = assemble(corners, normals, ids, np.zeros(1 << bits, np.uint64), flaws, faces,
                                               vertices, unit)
        if n >= 0:
            return Welded(flaws, faces[:kept], vertices[:n], unit[:kept], missing, backwards)
        if n == FULL:
            bits = max(bits + 2, int(6 * f).bit_length())  # room for every corner
        elif n == COLLIDING:
            sound = np.asarray(corners[flaws == SOUND], np.float64).reshape(-1, 3) + 0.0  # -0.0 is 0.0
            ids, _ = weld_by_sorting(sound.view(np.uint64))
            bits = 0


def facet_flaws(corners: np.ndarray) -> np.ndarray:
    """(F,) uint8: the flaw of each facet of ``corners`` (F, 3, 3) (``SOUND``, ``NOT_FINITE`` or
    ``TWO_EQUAL``), by the same kernel without welding (an empty table)."""
    f = len(corners)
    flaws = np.empty(f, np.uint8)
    empty = np.zeros((0, 3))
    assemble(corners, empty, _NO_IDS, np.zeros(0, np.uint64), flaws, np.zeros((0, 3), np.int64), empty, empty)
    return flaws


def weld_by_sorting(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``inverse`` (K,) int64, the vertex of each row of ``keys`` (K, 3) unsigned integers
    (bit patterns of coordinates), numbered in order of first appearance, and ``first`` (V,)
    int64, the first row of each vertex, by NumPy's sort."""
    rows = np.ascontiguousarray(keys).view(np.dtype((np.void, 3 * keys.dtype.itemsize))).ravel()
    _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")  # numbered by first appearance, as the hash numbers
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return rank[inverse.ravel()], first[order]
