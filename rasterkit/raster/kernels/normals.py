"""Face and vertex normals.

Face normals follow the right-hand rule (counter-clockwise seen from outside points out); a
vertex normal is the sum of the unnormalised face normals around it (each ``2 * area * n``,
so bigger faces weigh more), normalised. Degenerate ones are zero. Both work in any space
(object, world or camera) as long as positions and the light are in the same one.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def cross(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@kernel(inline="always")
def _face_cross(positions, faces, f):
    """``(v1 - v0) x (v2 - v0)`` of face ``f``: twice its area times its unit normal."""
    a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
    return cross(
        positions[b, 0] - positions[a, 0],
        positions[b, 1] - positions[a, 1],
        positions[b, 2] - positions[a, 2],
        positions[c, 0] - positions[a, 0],
        positions[c, 1] - positions[a, 1],
        positions[c, 2] - positions[a, 2],
    )


@kernel(inline="always")
def _normalize_row(v, k):
    """Scale row ``k`` of ``v (K, 3)`` to unit length in place; a zero row stays zero."""
    length = np.sqrt(v[k, 0] ** 2 + v[k, 1] ** 2 + v[k, 2] ** 2)
    if length > 0.0:
        v[k, 0] /= length
        v[k, 1] /= length
        v[k, 2] /= length


@kernel
def face_normals(positions, faces):
    """Unit face normals.

    Parameters
    ----------
    positions : (N, 3) float64
        Vertex positions (any space).
    faces : (M, 3) int64
        Vertex indices, counter-clockwise seen from the outside.

    Returns
    -------
    (M, 3) float64
        Unit outward normals; zero for degenerate faces.
    """
    m = faces.shape[0]
    out = np.empty((m, 3))
    for f in range(m):
        out[f, 0], out[f, 1], out[f, 2] = _face_cross(positions, faces, f)
        _normalize_row(out, f)
    return out


@kernel
def vertex_normals(positions, faces):
    """Area-weighted unit vertex normals.

    Parameters
    ----------
    positions : (N, 3) float64
    faces : (M, 3) int64

    Returns
    -------
    (N, 3) float64
        For each vertex the normalised sum of ``(v1 - v0) x (v2 - v0)`` over its faces;
        zero for vertices used by no face (or whose normals cancel).
    """
    out = np.zeros((positions.shape[0], 3))
    for f in range(faces.shape[0]):
        nx, ny, nz = _face_cross(positions, faces, f)
        for k in range(3):
            v = faces[f, k]
            out[v, 0] += nx
            out[v, 1] += ny
            out[v, 2] += nz
    for v in range(out.shape[0]):
        _normalize_row(out, v)
    return out
