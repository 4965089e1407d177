"""Numba kernels for the normals of an OBJ file's Mesh: rows scaled to unit length, and the
sum of the corner normals at each vertex. Each works out what the NumPy expressions it
replaces would, bit for bit (``fastmath=False``, the operations in NumPy's order), in one
pass without temporaries.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["corner_normal_sums", "unit_rows"]

#: Rows whose largest component is beyond these are scaled towards 1 before their length is
#: taken, so that its squares neither overflow nor vanish.
_HUGE, _TINY = 1e150, 1e-150


@kernel(fastmath=False)
def unit_rows(a, out):
    """Write into ``out`` (N, 3) float64 the rows of ``a`` (N, 3) float64 scaled to length 1, NaN and infinite
    components taken as 0 (``np.nan_to_num``); rows of length 0 become 0. A row whose
    largest component (in size) is above 1e150 or below 1e-150 is divided by it first;
    the length is ``sqrt((x * x + y * y) + z * z)``, as ``np.linalg.norm`` sums along rows."""
    for r in range(a.shape[0]):
        x, y, z = a[r, 0], a[r, 1], a[r, 2]
        x = x if np.isfinite(x) else 0.0
        y = y if np.isfinite(y) else 0.0
        z = z if np.isfinite(z) else 0.0
        biggest = max(abs(x), abs(y), abs(z))
        if biggest > _HUGE or (biggest < _TINY and biggest > 0):
            x, y, z = x / biggest, y / biggest, z / biggest
        length = np.sqrt((x * x + y * y) + z * z)
        if length > 0:
            out[r, 0], out[r, 1], out[r, 2] = x / length, y / length, z / length
        else:
            out[r, 0] = out[r, 1] = out[r, 2] = 0.0


@kernel(fastmath=False)
def corner_normal_sums(vertex, normal, unit, n_vertices):
    """(n_vertices, 3) float64: for each vertex, the sum of ``unit[normal[c]]`` over the
    corners c with ``vertex[c]`` that vertex and a normal (``normal[c] >= 0``), added in
    corner order from 0 (as ``np.bincount`` adds its weights). Indices are in range: the
    caller's (vertex in [0, n_vertices), normal -1 or a row of unit)."""
    total = np.zeros((n_vertices, 3))
    for c in range(len(vertex)):
        k = normal[c]
        if k >= 0:
            v = vertex[c]
            total[v, 0] += unit[k, 0]
            total[v, 1] += unit[k, 1]
            total[v, 2] += unit[k, 2]
    return total
