"""Numba kernels of the STL reader's Mesh: the flaws of each facet, welding identical corners
into vertices, and the facet normals kept.

The weld runs in O(corners) on real meshes, with an open-addressing hash table over the
corners' bit patterns (each vertex numbered where it first appears, so the result does not
depend on the hash), and cannot be made slow by a file: it gives up after a fixed amount of
probing per corner (corners made to collide), for its caller to weld by sorting instead. The
Mesh works out its edges itself (:mod:`rasterkit.mesh.kernels`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["COLLIDING", "FULL", "M1", "M2", "M3", "PROBES_PER_CORNER", "NOT_FINITE", "SOUND", "TWO_EQUAL", "facet_flaws", "facet_normals", "weld"]

#: The multipliers of the hash of a row (MurmurHash3's and the golden ratio's).
M1 = np.uint64(0x9E3779B97F4A7C15)
M2 = np.uint64(0xC2B2AE3D27D4EB4F)
M3 = np.uint64(0x165667B19E3779F9)

#: Probes per corner, on average, before :func:`weld` gives up (a table at most half full
#: needs about 1.5 with a good hash).
PROBES_PER_CORNER = 8
FULL, COLLIDING = -1, -2


@kernel
def weld(keys, bits):
    """Number the distinct rows of ``keys`` (K, 3) uint32 or uint64 (bit patterns of
    coordinates) in order of first appearance.

    Returns ``inverse`` (K,) int64, the number of each row; ``first`` (n,) int64, the first
    row of each number; and ``n``; or :data:`FULL` when more than half of the table's
    ``2**bits`` slots would be needed (call again with more bits), or :data:`COLLIDING` when
    the probes exceed :data:`PROBES_PER_CORNER` per corner (``inverse`` and ``first`` then
    mean nothing). A slot of the table holds a row and its number + 1 (0: empty), so a probe
    reads one cache line."""
    k = keys.shape[0]
    size = np.int64(1) << bits
    mask = size - 1
    table = np.zeros((size, 4), keys.dtype)
    first = np.empty(k, np.int64)
    inverse = np.empty(k, np.int64)
    n = 0
    budget = PROBES_PER_CORNER * k + 64
    for i in range(k):
        a = keys[i, 0]
        b = keys[i, 1]
        c = keys[i, 2]
        h = (np.uint64(a) * M1) ^ (np.uint64(b) * M2) ^ (np.uint64(c) * M3)
        h ^= h >> np.uint64(33)  # MurmurHash3's finaliser: every bit moves every bit
        h *= M2
        h ^= h >> np.uint64(29)
        s = np.int64(h & np.uint64(mask))
        while True:
            t = np.int64(table[s, 3])
            if t == 0:
                table[s, 0] = a
                table[s, 1] = b
                table[s, 2] = c
                n += 1
                table[s, 3] = n
                first[n - 1] = i
                inverse[i] = n - 1
                break
            if table[s, 0] == a and table[s, 1] == b and table[s, 2] == c:
                inverse[i] = t - 1
                break
            s = (s + 1) & mask
            budget -= 1
            if budget < 0:
                return inverse, first[:0], COLLIDING
        if 2 * n > size:
            return inverse, first[:0], FULL
    return inverse, first[:n], n


#: What :func:`facet_flaws` finds in a facet: nothing; a NaN or infinite coordinate; two equal corners.
SOUND, NOT_FINITE, TWO_EQUAL = 0, 1, 2


@kernel
def facet_flaws(corners):
    """(F,) uint8: for each facet of ``corners`` (F, 3, 3), :data:`NOT_FINITE` when one of its
    numbers is NaN or infinite, else :data:`TWO_EQUAL` when two corners are equal (as numbers:
    ``-0.0 == 0.0``), else :data:`SOUND`."""
    out = np.zeros(corners.shape[0], np.uint8)
    for f in range(corners.shape[0]):
        for i in range(3):
            for j in range(3):
                if not np.isfinite(corners[f, i, j]):
                    out[f] = NOT_FINITE
        if out[f] == SOUND:
            for i in range(3):
                k = i + 1 if i < 2 else 0
                if corners[f, i, 0] == corners[f, k, 0] and corners[f, i, 1] == corners[f, k, 1] and \
                        corners[f, i, 2] == corners[f, k, 2]:
                    out[f] = TWO_EQUAL
    return out


@kernel(fastmath=False)  # IEEE division: a reciprocal of a subnormal length would be infinite
def facet_normals(given, vertices, faces, out):
    """Fill ``out`` (M, 3) float64 with a unit normal per facet: the file's normal ``given``
    (M, 3) float64 where it is finite, not zero and not pointing against the winding of the
    facet ``faces`` (M, 3) of ``vertices`` (N, 3) float64, else the normal of its corners
    (zero when they are on one line). Returns the counts (missing, backwards) of the file's
    normals not used: zero/NaN/infinite ones, and ones against the winding."""
    missing = 0
    backwards = 0
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
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
        nx, ny, nz = given[f, 0], given[f, 1], given[f, 2]
        if not (np.isfinite(nx) and np.isfinite(ny) and np.isfinite(nz)) or (nx == 0.0 and ny == 0.0 and nz == 0.0):
            missing += 1
            nx, ny, nz = ox, oy, oz
        elif nx * ox + ny * oy + nz * oz < 0.0:
            backwards += 1
            nx, ny, nz = ox, oy, oz
        largest = max(abs(nx), abs(ny), abs(nz))  # scaled first: no overflow in the squares
        if largest > 0.0 and np.isfinite(largest):
            nx, ny, nz = nx / largest, ny / largest, nz / largest
            length = np.sqrt(nx * nx + ny * ny + nz * nz)
            out[f, 0], out[f, 1], out[f, 2] = nx / length, ny / length, nz / length
        else:
            out[f, 0], out[f, 1], out[f, 2] = 0.0, 0.0, 0.0
    return missing, backwards
