"""Joining STL facets welded in chunks on several threads into the numbering one pass gives.

:func:`rasterkit.stl.kernels.mesh.assemble` welds each chunk of facets on its own thread, with
a hash table of its own and its vertices numbered from 0 in the chunk's own stretch of the
vertex array. :func:`merge_chunks` then takes the chunks after the first in file order and
looks each of their vertices up in the first chunk's table (made large enough for the whole
file): a vertex seen before gets the number it has there, a new one the next number. Vertices
seen first in an earlier chunk come before those seen first in a later one, and each chunk
keeps its own order, so the numbers are those of first appearance in the file: the same
vertices and faces as one pass over every facet, bit for bit.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.intrinsics import prefetch_row
from rasterkit.runtime.jit import kernel
from rasterkit.stl.kernels.mesh import AHEAD, COLLIDING, FULL, PROBES_PER_CORNER, corner_hash, find_vertex, slot_entry

__all__ = ["merge_chunks"]


@kernel(fastmath=False)
def merge_chunks(starts, kept, counts, table, faces, vertices, unit, numbers):
    """Join the chunks of facets ``starts[k] .. starts[k + 1] - 1`` welded apart.

    Chunk k's ``kept[k]`` sound facets are rows ``starts[k] ..`` of ``faces`` (numbers of its
    own vertices) and ``unit``; its ``counts[k]`` vertices are rows ``3 starts[k] ..`` of
    ``vertices``. ``table`` is chunk 0's hash table (its vertices are numbered already);
    ``numbers`` is scratch of at least ``max(counts)`` int64. Afterwards the sound facets of
    every chunk are the first rows of ``faces`` and ``unit``, in file order, and the vertices
    the first rows of ``vertices``, numbered in order of first appearance (each new vertex
    moves down to its number, never over a row still to be read: a chunk has at most as many
    vertices as corners).

    Returns ``(sound facets, vertices)``, or ``(0, FULL)`` when the table would be more than
    half full and ``(0, COLLIDING)`` when the probes exceed :data:`PROBES_PER_CORNER` per
    vertex looked up: the caller then welds in one pass."""
    size = table.shape[0]
    mask = np.uint64(size - 1)
    budget = PROBES_PER_CORNER * np.int64(counts.sum()) + 64
    n = counts[0]
    row = kept[0]
    for k in range(1, starts.shape[0] - 1):
        base = 3 * starts[k]
        count = counts[k]
        for j in range(count):
            if j + AHEAD < count:
                g = base + j + AHEAD
                h = corner_hash(vertices[g, 0], vertices[g, 1], vertices[g, 2])
                prefetch_row(table, np.int64(h & mask))
            x, y, z = vertices[base + j, 0], vertices[base + j, 1], vertices[base + j, 2]
            h = corner_hash(x, y, z)
            s, v, probes = find_vertex(table, mask, h, vertices, n, x, y, z)
            budget -= probes
            if budget < 0:
                return 0, COLLIDING
            if v == n:
                if 2 * (n + 1) > size:
                    return 0, FULL
                table[s] = slot_entry(h, n)
                vertices[n, 0], vertices[n, 1], vertices[n, 2] = x, y, z
                n += 1
            numbers[j] = v
        first = starts[k]
        for r in range(kept[k]):
            for i in range(3):
                faces[row + r, i] = numbers[faces[first + r, i]]
                unit[row + r, i] = unit[first + r, i]
        row += kept[k]
    return row, n
