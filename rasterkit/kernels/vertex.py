"""Vertex stage: object space -> homogeneous raster space, by one 4x4 matrix."""

import numpy as np
from numba import prange

from .._jit import kernel


@kernel(parallel=True)
def transform_points(points, matrix):
    """(N, 3) float64 points times a 4x4 float64 matrix -> (N, 4) float64 homogeneous.

    ``out[i] = matrix @ (x, y, z, 1)``; no divide: clipping needs w.
    """
    n = points.shape[0]
    out = np.empty((n, 4), np.float64)
    for i in prange(n):
        x, y, z = points[i, 0], points[i, 1], points[i, 2]
        for r in range(4):
            out[i, r] = matrix[r, 0] * x + matrix[r, 1] * y + matrix[r, 2] * z + matrix[r, 3]
    return out
