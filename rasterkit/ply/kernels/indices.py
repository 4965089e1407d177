"""Widening a binary PLY file's vertex indices: one pass over the list items where they lie in
the file's bytes (a strided view, often unaligned: a count byte before each face's indices),
into int64, with their smallest and largest value for the range check. NumPy's conversion of
unaligned values takes a slow path (about four times as long)."""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["widen"]


@kernel
def widen(src, out):
    """``out`` (n, k) int64 = ``src`` (n, k) integers of the machine's byte order (any
    strides, aligned or not); returns ``(smallest, largest)`` of ``out`` (0, -1 when empty)."""
    lo = np.int64(0)
    hi = np.int64(-1)
    if src.shape[0] * src.shape[1] > 0:
        lo = hi = np.int64(src[0, 0])
    for i in range(src.shape[0]):
        for k in range(src.shape[1]):
            x = np.int64(src[i, k])
            out[i, k] = x
            lo = min(lo, x)
            hi = max(hi, x)
    return lo, hi
