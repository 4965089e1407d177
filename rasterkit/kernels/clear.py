"""Clearing a framebuffer: colour to the background, depth to +inf, ids to -1, row-parallel."""

import numpy as np
from numba import prange

from .._jit import kernel


@kernel(parallel=True)
def clear(color, depth, ids, rgba):
    """Clear (H, W, C) uint8 ``color`` to ``rgba`` (C,), (H, W) float32 ``depth`` to +inf and
    (H, W) int32 ``ids`` to -1 (pass a (0, 0) array to leave ids alone).

    Each thread owns whole rows; writing rows at a time is several times faster than
    NumPy's broadcast fill of an (H, W, 3) array.
    """
    height, width, channels = color.shape
    with_ids = ids.shape[0] == height
    for y in prange(height):
        for x in range(width):
            for c in range(channels):
                color[y, x, c] = rgba[c]
            depth[y, x] = np.inf
            if with_ids:
                ids[y, x] = -1
