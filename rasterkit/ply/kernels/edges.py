"""The sides of polygons as sortable keys, and sorted keys back as unique pairs: the two
passes around one NumPy sort that make ``Mesh.edges`` (each pass one read of its input,
where NumPy would take a temporary array per operation).

A side from vertex ``a`` to ``b`` (``a != b``) is the key ``min << bits | max``: keys sort
as the pairs ``(min, max)`` do.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["pairs_of_keys", "side_keys"]


@kernel
def side_keys(corners, offsets, keep, bits):
    """(K,) int64 keys of the sides ``c[0]-c[1], ..., c[-1]-c[0]`` of each kept polygon
    (``corners[offsets[p]:offsets[p + 1]]``, ``keep`` (P,) bool), none from a vertex to
    itself."""
    keys = np.empty(len(corners), np.int64)
    k = 0
    for p in range(len(offsets) - 1):
        if not keep[p]:
            continue
        first, end = offsets[p], offsets[p + 1]
        for c in range(first, end):
            a = corners[c]
            b = corners[c + 1] if c + 1 < end else corners[first]
            if a != b:
                keys[k] = (min(a, b) << bits) | max(a, b)
                k += 1
    return keys[:k]


@kernel
def pairs_of_keys(keys, bits):
    """(E, 2) int64 ``(min, max)`` of the distinct keys of ``keys`` (sorted)."""
    out = np.empty((len(keys), 2), np.int64)
    mask = (np.int64(1) << bits) - 1
    e = 0
    for k in range(len(keys)):
        if k == 0 or keys[k] != keys[k - 1]:
            out[e, 0] = keys[k] >> bits
            out[e, 1] = keys[k] & mask
            e += 1
    return out[:e]
