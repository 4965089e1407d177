"""The frame's visible surface that a directional light's shadow map is fitted to
(:func:`rasterkit.raster.shadows.shadow_maps`), from a small drawing of it: one point per
pixel that a face covers."""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel


@kernel(fastmath=False)
def visible_points(depth, ids, inverse, normals, eye, backward, perspective, tangent, view_height, out):
    """The points of the pixels of a drawing (``depth`` (H, W) float32, its depth buffer;
    ``ids`` (H, W) int32, the face seen, -1 for none) that a face covers with a finite depth,
    row by row, into the columns of ``out`` (7, >= that many) float64: x, y, z (world space:
    the pixel centre's raster point through ``inverse``, the drawing camera's raster -> world
    (4, 4) matrix, divided by w), the unit normal of its face (``normals`` (M, 3) float32)
    turned towards the camera, and the radius (world units) of the patch its pixel stands
    for: ``view_height / H`` for a parallel camera, for a ``perspective`` one the distance
    along its axis (unit ``backward``, from ``eye``) times ``2 tangent / H`` (``tangent`` the
    tangent of half its vertical field of view). Points with a value that is not finite are
    left out. Returns how many points were written.

    Compiled without fast-math: the arithmetic is NumPy's, in the same order (no fused
    multiply-adds), so the fit is what the array expressions it replaces gave."""
    height, width = depth.shape
    n = 0
    for j in range(height):
        y = j + 0.5
        for i in range(width):
            f = ids[j, i]
            d = depth[j, i]
            if f < 0 or not np.isfinite(d):
                continue
            x, z = i + 0.5, np.float64(d)
            w = inverse[3, 0] * x + inverse[3, 1] * y + inverse[3, 2] * z + inverse[3, 3]
            px = (inverse[0, 0] * x + inverse[0, 1] * y + inverse[0, 2] * z + inverse[0, 3]) / w
            py = (inverse[1, 0] * x + inverse[1, 1] * y + inverse[1, 2] * z + inverse[1, 3]) / w
            pz = (inverse[2, 0] * x + inverse[2, 1] * y + inverse[2, 2] * z + inverse[2, 3]) / w
            nx, ny, nz = np.float64(normals[f, 0]), np.float64(normals[f, 1]), np.float64(normals[f, 2])
            if perspective:
                tx, ty, tz = eye[0] - px, eye[1] - py, eye[2] - pz
                radius = (backward[0] * tx + backward[1] * ty + backward[2] * tz) * 2.0 * tangent / height
            else:
                tx, ty, tz = backward[0], backward[1], backward[2]
                radius = view_height / height
            if nx * tx + ny * ty + nz * tz < 0.0:
                nx, ny, nz = nx * -1.0, ny * -1.0, nz * -1.0
            values = (px, py, pz, nx, ny, nz, radius)
            finite = True
            for value in values:
                finite &= np.isfinite(value)
            if finite:
                for k in range(7):
                    out[k, n] = values[k]
                n += 1
    return n
