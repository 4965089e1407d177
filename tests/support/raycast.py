"""Exact ray casting for the lighting tests: the surface point seen at each pixel (the ray
through its centre meeting the face the render says is there) and whether a ray from a point
towards a light meets any triangle (Moller-Trumbore against every triangle: slow, simple,
independent of the renderer)."""

from __future__ import annotations

import numba
import numpy as np

from support.unchecked import as_written


def surface_points(mesh, camera, ids):
    """(points (K, 3), weights (K, 3)) where the ray through the centre of each pixel with a
    face in ``ids`` meets that face's plane, for the pixels ``np.nonzero(ids >= 0)``."""
    j, i = np.nonzero(ids >= 0)
    origin, direction = camera.ray(i + 0.5, j + 0.5)
    a, b, c = (mesh.vertices[mesh.faces[ids[j, i], k]] for k in range(3))
    e1, e2 = b - a, c - a
    p = np.cross(direction, e2)
    det = (e1 * p).sum(axis=1)
    s = origin - a
    u = (s * p).sum(axis=1) / det
    q = np.cross(s, e1)
    v = (direction * q).sum(axis=1) / det
    t = (e2 * q).sum(axis=1) / det
    return origin + t[:, None] * direction, np.stack([1 - u - v, u, v], axis=1)


@numba.njit(cache=False)
def ray_hits(ox, oy, oz, dx, dy, dz, f, a, e1, e2):
    """The distance along the ray (o, d) at which it meets triangle ``f`` (corner ``a[f]``,
    edges ``e1[f]``, ``e2[f]``; Moller-Trumbore), or -1 where it does not."""
    px = dy * e2[f, 2] - dz * e2[f, 1]
    py = dz * e2[f, 0] - dx * e2[f, 2]
    pz = dx * e2[f, 1] - dy * e2[f, 0]
    det = e1[f, 0] * px + e1[f, 1] * py + e1[f, 2] * pz
    if abs(det) < 1e-14:
        return -1.0
    inv = 1.0 / det
    sx, sy, sz = ox - a[f, 0], oy - a[f, 1], oz - a[f, 2]
    u = (sx * px + sy * py + sz * pz) * inv
    if u < 0.0 or u > 1.0:
        return -1.0
    qx = sy * e1[f, 2] - sz * e1[f, 1]
    qy = sz * e1[f, 0] - sx * e1[f, 2]
    qz = sx * e1[f, 1] - sy * e1[f, 0]
    v = (dx * qx + dy * qy + dz * qz) * inv
    if v < 0.0 or u + v > 1.0:
        return -1.0
    return (e2[f, 0] * qx + e2[f, 1] * qy + e2[f, 2] * qz) * inv


@numba.njit(cache=False)
def _blocked(origins, directions, lengths, a, e1, e2):
    out = np.zeros(len(origins), np.bool_)
    for r in range(len(origins)):
        for f in range(len(a)):
            t = ray_hits(origins[r, 0], origins[r, 1], origins[r, 2], directions[r, 0], directions[r, 1],
                         directions[r, 2], f, a, e1, e2)
            if t > 0.0 and t < lengths[r]:
                out[r] = True
                break
    return out


def in_shadow(mesh, points, normals, towards_light, lengths):
    """(K,) bool: whether the segment from each point (moved off its surface by a hair along
    its normal) along the unit ``towards_light`` (K, 3), ``lengths`` (K,) long (inf for a
    distant light), meets a triangle of ``mesh``."""
    scale = float(np.abs(mesh.vertices).max())
    origins = points + normals * (1e-6 * scale)
    a = mesh.vertices[mesh.faces[:, 0]]
    e1 = mesh.vertices[mesh.faces[:, 1]] - a
    e2 = mesh.vertices[mesh.faces[:, 2]] - a
    with as_written():
        return _blocked(np.ascontiguousarray(origins), np.ascontiguousarray(towards_light, np.float64),
                        np.ascontiguousarray(lengths, np.float64), np.ascontiguousarray(a),
                        np.ascontiguousarray(e1), np.ascontiguousarray(e2))
