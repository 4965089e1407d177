"""The Numba kernel of the STL reader's Mesh: one pass over the facets as the file gives them
(:func:`assemble`) that finds each facet's flaws, welds the corners of the sound ones into
vertices and keeps their normals.

The weld numbers the distinct corners in order of first appearance with an open-addressing
hash table over their coordinates, so the result does not depend on the hash. It runs in
O(corners) on real meshes and cannot be made slow by a file: it gives up after a fixed amount
of probing per corner (corners made to collide), and its caller then numbers the corners by
sorting (:func:`rasterkit.stl.weld.weld_by_sorting`) and hands the numbers to the same kernel.
The table's slots are looked up a few facets ahead of their use (a software prefetch: a slot is
at a random place of a table larger than the caches). The Mesh works out its edges itself
(:mod:`rasterkit.mesh.kernels`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.intrinsics import float_bits, prefetch_row
from rasterkit.runtime.jit import kernel

__all__ = ["AHEAD", "COLLIDING", "FULL", "ID", "ID_BITS", "M1", "M2", "M3", "NOT_FINITE", "PROBES_PER_CORNER", "SOUND",
           "TWO_EQUAL", "assemble", "corner_hash", "find_vertex", "slot_entry"]

#: The multipliers of the hash of a corner (MurmurHash3's and the golden ratio's).
M1 = np.uint64(0x9E3779B97F4A7C15)
M2 = np.uint64(0xC2B2AE3D27D4EB4F)
M3 = np.uint64(0x165667B19E3779F9)

#: Probes per corner, on average, before :func:`assemble` gives up (a table at most half full
#: needs about 1.5 with a good hash).
PROBES_PER_CORNER = 8
#: How many facets ahead the table's slots are prefetched.
AHEAD = 8
#: What :func:`assemble` returns instead of a vertex count: the table is too small; corners collide.
FULL, COLLIDING = -1, -2
#: A facet's flaw: none; a NaN or infinite coordinate; two equal corners.
SOUND, NOT_FINITE, TWO_EQUAL = 0, 1, 2

#: A slot of the table: a vertex number + 1 in its low 40 bits (more than any file can have),
#: the high 24 bits of its hash above them (a probe of another vertex seldom reads it).
ID_BITS = np.uint64(40)
ID = np.uint64((1 << 40) - 1)
#: Which normal a facet keeps: the file's; its corners', the file's being zero, NaN or
#: infinite; its corners', the file's pointing against their winding.
_GIVEN, _MISSING, _BACKWARDS = 0, 1, 2


@kernel(inline="always")
def corner_hash(x, y, z):
    """The 64-bit hash of a corner (x, y, z), float64 numbers without ``-0.0``."""
    h = (np.uint64(float_bits(x)) * M1) ^ (np.uint64(float_bits(y)) * M2) ^ (np.uint64(float_bits(z)) * M3)
    h ^= h >> np.uint64(33)  # MurmurHash3's finaliser: every bit moves every bit
    h *= M2
    h ^= h >> np.uint64(29)
    return h


@kernel(inline="always")
def find_vertex(table, mask, h, vertices, n, x, y, z):
    """``(slot, vertex, probes)``: where the vertex (x, y, z) of hash ``h`` is in ``table``
    (``mask``: its size - 1; ``vertices``: the first n numbered) and its number, or the empty
    slot where it goes and ``n`` when it is not there; ``probes``: the slots passed over."""
    tag = h >> ID_BITS
    s = h & mask
    probes = 0
    while True:
        t = table[s]
        if t == 0:
            return s, n, probes
        v = np.int64(t & ID) - 1
        if t >> ID_BITS == tag and vertices[v, 0] == x and vertices[v, 1] == y and vertices[v, 2] == z:
            return s, v, probes
        s = (s + np.uint64(1)) & mask
        probes += 1


@kernel(inline="always")
def slot_entry(h, v):
    """What a slot of the table holds for vertex ``v`` of hash ``h`` (see :data:`ID_BITS`)."""
    return (h >> ID_BITS << ID_BITS) | np.uint64(v + 1)


@kernel(fastmath=False)  # IEEE arithmetic: the normals' divisions, and x + 0.0 making -0.0 0.0
def assemble(corners, given, ids, table, flaws, faces, vertices, unit):
    """Number the corners of the sound facets of ``corners`` (F, 3, 3) float32 or float64, in
    order of first appearance (numbers equal as numbers are one vertex: ``-0.0`` is ``0.0``).

    - ``flaws`` (F,) uint8 gets each facet's flaw: :data:`NOT_FINITE` when one of its numbers
      is NaN or infinite, else :data:`TWO_EQUAL` when two corners are equal, else :data:`SOUND`.
    - The k-th sound facet becomes ``faces[k]`` (vertex numbers, int64), and ``unit[k]``
      (float64) its unit normal: the file's normal ``given[f]`` where it is finite, not zero
      and not against the winding of the facet's corners, else the normal of its corners
      (zero when they are on one line).
    - Vertex v is ``vertices[v]`` (float64; ``vertices`` has room for every corner).
    - The numbers come from ``table`` ((2**bits,) uint64, zeros) when ``ids`` is empty, else
      ``ids`` gives the number of each corner of the sound facets (from the sort, in order of
      first appearance). With both empty, only ``flaws`` are found (the rest is 0).

    Returns ``(sound facets, vertices, missing, backwards)``: the counts of the file's normals
    not used (zero, NaN or infinite ones, and ones against the winding). The vertex count is
    :data:`FULL` when more than half of the table's slots would be needed (call again with a
    larger table), :data:`COLLIDING` when the probes exceed :data:`PROBES_PER_CORNER` per corner;
    ``flaws`` are complete then, the rest means nothing."""
    n_facets = corners.shape[0]
    hashing = ids.shape[0] == 0
    size = table.shape[0]
    mask = np.uint64(size - 1)
    budget = PROBES_PER_CORNER * 3 * n_facets + 64
    kept = 0
    n = 0
    missing = 0
    backwards = 0
    welding = size > 0 or not hashing  # an empty table: the flaws only
    for f in range(n_facets):
        if hashing and welding and f + AHEAD < n_facets:
            g = f + AHEAD
            for i in range(3):
                h = corner_hash(corners[g, i, 0] + 0.0, corners[g, i, 1] + 0.0, corners[g, i, 2] + 0.0)
                prefetch_row(table, np.int64(h & mask))
        flaw = SOUND
        for i in range(3):
            for j in range(3):
                if not np.isfinite(corners[f, i, j]):
                    flaw = NOT_FINITE
        if flaw == SOUND:
            for i in range(3):
                k = i + 1 if i < 2 else 0
                if corners[f, i, 0] == corners[f, k, 0] and corners[f, i, 1] == corners[f, k, 1] and \
                        corners[f, i, 2] == corners[f, k, 2]:
                    flaw = TWO_EQUAL
        flaws[f] = flaw
        if flaw != SOUND or not welding:
            continue
        for i in range(3):
            x = np.float64(corners[f, i, 0]) + 0.0
            y = np.float64(corners[f, i, 1]) + 0.0
            z = np.float64(corners[f, i, 2]) + 0.0
            if hashing:
                h = corner_hash(x, y, z)
                s, v, probes = find_vertex(table, mask, h, vertices, n, x, y, z)
                budget -= probes
                if budget < 0:
                    welding = False
                    n = COLLIDING
                    break
                if v == n:
                    if 2 * (n + 1) > size:
                        welding = False
                        n = FULL
                        break
                    table[s] = slot_entry(h, n)
            else:
                v = ids[3 * kept + i]
            if v == n:
                vertices[n, 0], vertices[n, 1], vertices[n, 2] = x, y, z
                n += 1
            faces[kept, i] = v
        if not welding:
            continue
        use, nx, ny, nz = _normal(vertices, faces[kept, 0], faces[kept, 1], faces[kept, 2], np.float64(given[f, 0]),
                                  np.float64(given[f, 1]), np.float64(given[f, 2]))
        missing += use == _MISSING
        backwards += use == _BACKWARDS
        unit[kept, 0], unit[kept, 1], unit[kept, 2] = nx, ny, nz
        kept += 1
    return kept, n, missing, backwards


@kernel(inline="always", fastmath=False)
def _normal(vertices, a, b, c, nx, ny, nz):
    """``(use, x, y, z)``: the unit normal of the facet of ``vertices`` a, b, c whose file
    normal is (nx, ny, nz): that one (``use`` :data:`_GIVEN`), or the corners' where it is zero,
    NaN or infinite (:data:`_MISSING`) or points against their winding (:data:`_BACKWARDS`)."""
    ux = vertices[b, 0] - vertices[a, 0]
    uy = vertices[b, 1] - vertices[a, 1]
    uz = vertices[b, 2] - vertices[a, 2]
    vx = vertices[c, 0] - vertices[a, 0]
    vy = vertices[c, 1] - vertices[a, 1]
    vz = vertices[c, 2] - vertices[a, 2]
    su = max(abs(ux), abs(uy), abs(uz))  # the sides scaled first: no overflow or underflow
    sv = max(abs(vx), abs(vy), abs(vz))
    if su > 0.0 and sv > 0.0:
        ux, uy, uz, vx, vy, vz = ux / su, uy / su, uz / su, vx / sv, vy / sv, vz / sv
    ox, oy, oz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    use = _GIVEN
    if not (np.isfinite(nx) and np.isfinite(ny) and np.isfinite(nz)) or (nx == 0.0 and ny == 0.0 and nz == 0.0):
        use = _MISSING
        nx, ny, nz = ox, oy, oz
    elif nx * ox + ny * oy + nz * oz < 0.0:
        use = _BACKWARDS
        nx, ny, nz = ox, oy, oz
    largest = max(abs(nx), abs(ny), abs(nz))  # scaled first: no overflow in the squares
    if largest > 0.0 and np.isfinite(largest):
        nx, ny, nz = nx / largest, ny / largest, nz / largest
        length = np.sqrt(nx * nx + ny * ny + nz * nz)
        return use, nx / length, ny / length, nz / length
    return use, 0.0, 0.0, 0.0
