"""Driver of the vertex stage: points through a 4x4 matrix, on all threads."""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.kernels.vertex import transform_chunks

#: Fewer points than this are transformed on the calling thread alone (handing work to
#: another thread costs about as much as transforming this many).
_PARALLEL_POINTS = 20_000


def transform_points(points: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """(N, 3) float64 C-contiguous points -> (N, 4) float64 homogeneous ``matrix @ (x, y, z, 1)``.

    ``matrix`` is (4, 4) float64, C-contiguous. The caller validates both."""
    out = np.empty((points.shape[0], 4), np.float64)
    threads = 1 if points.shape[0] < _PARALLEL_POINTS else None
    run_workers(transform_chunks, readonly(points), readonly(matrix), out, threads=threads)
    return out
