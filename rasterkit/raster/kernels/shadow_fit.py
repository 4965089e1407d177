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


@kernel(fastmath=False)
def shadowed_extent(visible, matrix, basis, offset, depth, texel, near, span, margin):
    """Where across a directional light the frame's ``visible`` points (:func:`visible_points`'
    rows) may be in shadow, from a first map of the light (``depth`` (S, S) float32, its
    camera's world -> raster ``matrix`` (4, 4) and axes ``basis`` (3, 3): right, up,
    forward; ``offset`` the forward axis' product with its eye; ``texel`` its texel's size,
    ``near``, ``span`` its depth range): the points in the map facing the light with
    something nearer to it than their face's plane (by two texels and the slope's share) in
    their texel or the next ones. Returns ``(count, low0, low1, high0, high1)``: how many,
    and the extent along the right and up axes of those points widened by their footprint
    (row 6) plus ``margin``.

    Compiled without fast-math: NumPy's arithmetic in the same order, so the fit is what the
    array expressions it replaces gave."""
    size = depth.shape[0]
    count = 0
    low0, low1, high0, high1 = np.inf, np.inf, -np.inf, -np.inf
    for p in range(visible.shape[1]):
        px, py, pz = visible[0, p], visible[1, p], visible[2, p]
        x = matrix[0, 0] * px + matrix[0, 1] * py + matrix[0, 2] * pz + matrix[0, 3]
        y = matrix[1, 0] * px + matrix[1, 1] * py + matrix[1, 2] * pz + matrix[1, 3]
        facing = -(basis[2, 0] * visible[3, p] + basis[2, 1] * visible[4, p] + basis[2, 2] * visible[5, p])
        if not (x >= 0 and y >= 0 and x < size and y < size and facing > 0.0):
            continue
        i, j = np.int64(x), np.int64(y)
        along = basis[2, 0] * px + basis[2, 1] * py + basis[2, 2] * pz - offset
        slope = min(np.sqrt(max(1.0 - facing * facing, 0.0)) / facing, 20.0)
        nearest = np.float32(np.inf)
        for dj in range(-1, 2):
            row = min(max(j + dj, 0), size - 1)
            for di in range(-1, 2):
                nearest = min(nearest, depth[row, min(max(i + di, 0), size - 1)])
        if not np.float64(nearest) < (along - texel * (2.0 + 1.5 * slope) - near) / span:
            continue
        count += 1
        reach = visible[6, p] + margin
        a = basis[0, 0] * px + basis[0, 1] * py + basis[0, 2] * pz
        b = basis[1, 0] * px + basis[1, 1] * py + basis[1, 2] * pz
        low0, high0 = min(low0, a - reach), max(high0, a + reach)
        low1, high1 = min(low1, b - reach), max(high1, b + reach)
    return count, low0, low1, high0, high1
