"""Welding the corners of an STL file's facets into shared vertices (:func:`weld_facets`): rows
of coordinates that are equal as numbers become one vertex, numbered in order of first
appearance among the sound facets (those without a NaN or infinite number, and without two
equal corners), in the same pass that finds each facet's flaws and keeps its normal.

Equal as numbers: ``-0.0`` is ``0.0``. The hash table of
:func:`rasterkit.stl.kernels.mesh.assemble` does it in O(corners); corners made to collide in
it are numbered by sorting instead (:func:`weld_by_sorting`, O(n log n)), with the same result.
A large file is welded in chunks of facets on the threads, joined by
:func:`rasterkit.stl.kernels.merge.merge_chunks` into the same numbering.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.mesh.checks import sealed_empty
from rasterkit.runtime.threads import get_threads, in_parallel
from rasterkit.stl.kernels.merge import merge_chunks
from rasterkit.stl.kernels.mesh import COLLIDING, FULL, SOUND, assemble

__all__ = ["BYTES_PER_CORNER", "Welded", "facet_flaws", "weld_facets", "weld_by_sorting"]

#: Bytes per corner while welding, at most: its vertex (float64 coordinates) and its slot of
#: the hash table (8 bytes, a table at most a quarter full; twice that when it grows).
BYTES_PER_CORNER = 24 + 8 * 4

_NO_IDS = np.zeros(0, np.int64)
#: Facets at least that a file has before it is welded in chunks on the threads.
PARALLEL_FACETS = 1 << 16
#: Chunks of a weld on the threads per thread (each chunk's vertices are looked up again by
#: the join: one chunk per thread is the least work).
CHUNKS_PER_THREAD = 1


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
    # the faces and normals are the Mesh's own arrays (sealed: no copy); the vertices are
    # copied into a Mesh of their own size, from room for every corner
    sealed_faces, faces = sealed_empty((f, 3), np.int64)
    sealed_unit, unit = sealed_empty((f, 3), np.float64)
    vertices = np.empty((3 * f, 3))  # room for every corner; only the vertices' pages are touched
    bits = _table_bits(f)
    threads = get_threads()
    if f >= PARALLEL_FACETS and threads > 1:
        pieces = min(threads * CHUNKS_PER_THREAD, f // (PARALLEL_FACETS // 2))
        counts = _in_chunks(corners, normals, flaws, faces, vertices, unit, pieces, threads)
        if counts is not None:
            kept, n, missing, backwards = counts
            return Welded(flaws, sealed_faces[:kept], vertices[:n], sealed_unit[:kept], missing, backwards)
    ids = _NO_IDS
    while True:
        kept, n, missing, backwards = assemble(corners, normals, ids, np.zeros(1 << bits, np.uint64), flaws, faces,
                                               vertices, unit)
        if n >= 0:
            return Welded(flaws, sealed_faces[:kept], vertices[:n], sealed_unit[:kept], missing, backwards)
        if n == FULL:
            bits = max(bits + 2, int(6 * f).bit_length())  # room for every corner
        elif n == COLLIDING:
            sound = np.asarray(corners[flaws == SOUND], np.float64).reshape(-1, 3) + 0.0  # -0.0 is 0.0
            ids, _ = weld_by_sorting(sound.view(np.uint64))
            bits = 0


def _table_bits(facets: int) -> int:
    """log2 of the hash table's slots for ``facets``: room for 3f / 4 vertices (a closed mesh
    has 3f / 6)."""
    return max(10, int(3 * facets // 2).bit_length())


def _in_chunks(corners, normals, flaws, faces, vertices, unit, pieces: int, threads: int) -> tuple | None:
    """:func:`weld_facets` in ``pieces`` chunks of facets welded at once on ``threads``
    threads, then joined (:func:`rasterkit.stl.kernels.merge.merge_chunks`): ``(sound facets,
    vertices, missing, backwards)`` as :func:`rasterkit.stl.kernels.mesh.assemble` counts them;
    None when a chunk or the join finds the table too small or the corners colliding (then
    one pass does it all)."""
    f = len(corners)
    starts = np.array([f * k // pieces for k in range(pieces + 1)], np.int64)
    # the first chunk's table is the join's: large enough for the whole file, as one pass's
    tables = [np.zeros(1 << _table_bits(f if k == 0 else int(starts[k + 1] - starts[k])), np.uint64)
              for k in range(pieces)]

    def weld(k):
        lo, hi = int(starts[k]), int(starts[k + 1])
        return assemble(corners[lo:hi], normals[lo:hi], _NO_IDS, tables[k], flaws[lo:hi], faces[lo:hi],
                        vertices[3 * lo:3 * hi], unit[lo:hi])

    results = in_parallel(weld, pieces, threads)
    kept = np.array([r[0] for r in results], np.int64)
    counts = np.array([r[1] for r in results], np.int64)
    if counts.min() < 0:
        return None
    del tables[1:]
    numbers = np.empty(counts.max(), np.int64)  # the join's scratch: a chunk's vertex numbers
    kept_all, n = merge_chunks(starts, kept, counts, tables[0], faces, vertices, unit, numbers)
    if n < 0:
        return None
    return kept_all, n, sum(r[2] for r in results), sum(r[3] for r in results)


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
