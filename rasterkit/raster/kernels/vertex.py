"""Vertex stage: object space -> homogeneous raster space, by one 4x4 matrix."""

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add

#: The points are transformed in this many contiguous chunks, shared out among the threads.
N_CHUNKS = 16


@kernel
def transform_chunks(slot, counter, points, matrix, out):
    """(N, 3) float64 points times a 4x4 float64 matrix into ``out`` (N, 4) float64.

    ``out[i] = matrix @ (x, y, z, 1)``; no divide: clipping needs w. A worker of
    :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused; chunks claimed through
    ``counter``).
    """
    n = points.shape[0]
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for i in range(n * ch // N_CHUNKS, n * (ch + 1) // N_CHUNKS):
            transform_row(points, matrix, out, i)


@kernel(inline="always")
def transform_row(points, matrix, out, i):
    """``out[i] = matrix @ (points[i], 1)``."""
    x, y, z = points[i, 0], points[i, 1], points[i, 2]
    for r in range(4):
        out[i, r] = matrix[r, 0] * x + matrix[r, 1] * y + matrix[r, 2] * z + matrix[r, 3]
