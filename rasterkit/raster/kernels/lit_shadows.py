"""Shadow lookups for a chunk of pixels lit per pixel (:mod:`rasterkit.raster.kernels.phong_rows`):
each light's shadow factor of each pixel, into the scratch's SHADE column
(:mod:`rasterkit.raster.kernels.lit_columns`), from the shadow maps
(:func:`~rasterkit.raster.kernels.lights.shadow_factor`)."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.lights import filtered, parallel_map, parallel_terms, shadow_at
from rasterkit.raster.kernels.lit_columns import (
    ABOVE, DIRECTIONAL, GI, GJ, HEADLIGHT, LEEWAY, NDH, NDL, NX, NY, NZ, POWER, PX, PY, PZ, SHADE, X, Y, Z, unit)
from rasterkit.runtime.intrinsics import prefetch_texel
from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def _face_terms(s, n, k, table, shadows):
    """Pass 1 of :func:`_parallel_shadows`: each pixel's factor where it needs no lookup (0:
    its shading normal or its face turned from the light), else -1 and its face's
    :func:`~rasterkit.raster.kernels.lights.parallel_terms` (made once for each run of pixels
    with the same plane: the chunk's pixels come run by run) into columns GI .. ABOVE. A
    degenerate face (no plane) is looked up in the plane of each pixel's shading normal, as
    :func:`~rasterkit.raster.kernels.lights.shadow_factor` does."""
    lx, ly, lz = -table[k, 4], -table[k, 5], -table[k, 6]
    last_x, last_y, last_z = np.nan, np.nan, np.nan
    fx, fy, fz = 0.0, 0.0, 0.0
    terms = (0.0, 0.0, 0.0, 0.0, 0.0)
    for q in range(n):
        u = np.uint64(q)
        nx, ny, nz = s[NX + u], s[NY + u], s[NZ + u]
        factor = 0.0
        if nx * lx + ny * ly + nz * lz > 0.0:
            ax, ay, az = s[PX + u], s[PY + u], s[PZ + u]
            if not (ax == last_x and ay == last_y and az == last_z):
                last_x, last_y, last_z = ax, ay, az
                fx, fy, fz = unit(ax, ay, az)
                if fx == 0.0 and fy == 0.0 and fz == 0.0:  # made again for the next pixel
                    fx, fy, fz, last_x = nx, ny, nz, np.nan
                terms = parallel_terms(k, table, fx, fy, fz, shadows)
            if (-terms[0] if fx * nx + fy * ny + fz * nz < 0.0 else terms[0]) > 0.0:  # noqa: FURB136
                factor = -1.0  # the light is in front of the face: look it up
                s[GI + u], s[GJ + u], s[LEEWAY + u], s[ABOVE + u] = terms[1], terms[2], terms[3], terms[4]
        s[SHADE + u] = factor


@kernel(inline="always")
def _map_points(s, n, k, table, shadows):
    """Pass 2 of :func:`_parallel_shadows`, for every pixel (a loop without branches: vector
    instructions): its point in the map's raster, into columns NDL, NDH, POWER (free until
    the light's share is added), x NaN where w is not positive (the point is then outside
    the map); then the map's texels around each point that pass 1 will look up are asked
    for, before any is read: the lookups then wait on their cache misses together."""
    maps, matrices = shadows[0], shadows[1]
    m = np.int64(table[k, 13])
    mu = np.uint64(m)
    m00, m01, m02, m03 = matrices[mu, 0, 0], matrices[mu, 0, 1], matrices[mu, 0, 2], matrices[mu, 0, 3]
    m10, m11, m12, m13 = matrices[mu, 1, 0], matrices[mu, 1, 1], matrices[mu, 1, 2], matrices[mu, 1, 3]
    m20, m21, m22, m23 = matrices[mu, 2, 0], matrices[mu, 2, 1], matrices[mu, 2, 2], matrices[mu, 2, 3]
    m30, m31, m32, m33 = matrices[mu, 3, 0], matrices[mu, 3, 1], matrices[mu, 3, 2], matrices[mu, 3, 3]
    for q in range(n):
        u = np.uint64(q)
        x, y, z = s[X + u], s[Y + u], s[Z + u]
        w = m30 * x + m31 * y + m32 * z + m33
        i = m00 * x + m01 * y + m02 * z + m03
        s[NDL + u] = i if w > 0.0 else np.nan  # noqa: FURB136
        s[NDH + u] = m10 * x + m11 * y + m12 * z + m13
        s[POWER + u] = m20 * x + m21 * y + m22 * z + m23
    edge = maps.shape[1] - 1.0
    for q in range(n):
        u = np.uint64(q)
        i, j = s[NDL + u], s[NDH + u]
        if s[SHADE + u] < 0.0 and i >= 1.0 and j >= 1.0 and i < edge and j < edge:
            column, row = np.int64(i) - 1, np.int64(j)
            prefetch_texel(maps, m, row - 1, column)
            prefetch_texel(maps, m, row, column)
            prefetch_texel(maps, m, row + 1, column)


@kernel(inline="always")
def _parallel_shadows(s, n, k, table, shadows):
    """:func:`_chunk_shadows` of a directional light with a parallel map, in three passes
    over the chunk: the face's terms (:func:`_face_terms`), the points in the map
    (:func:`_map_points`), and the lookups
    (:func:`~rasterkit.raster.kernels.lights.filtered`; a point outside the map is lit).
    The same arithmetic as :func:`~rasterkit.raster.kernels.lights.shadow_factor`."""
    _face_terms(s, n, k, table, shadows)
    _map_points(s, n, k, table, shadows)
    maps, softness = shadows[0], shadows[3]
    m = np.int64(table[k, 13])
    size = maps.shape[1]
    reach = np.int64(np.ceil(softness))
    for q in range(n):
        u = np.uint64(q)
        if not s[SHADE + u] < 0.0:
            continue
        x, y, z = s[NDL + u], s[NDH + u], s[POWER + u]
        factor = 1.0  # outside the map: nothing there casts a shadow
        if x >= 0.0 and y >= 0.0 and x < size and y < size:
            factor = filtered(maps, m, x, y, z, s[GI + u], s[GJ + u], z + s[ABOVE + u], s[LEEWAY + u], reach)
        s[SHADE + u] = factor


@kernel(inline="always")
def _chunk_shadows(s, n, k, table, shadows):
    """Light ``k``'s shadow factor of each pixel that faces it (0 for the others), into the
    scratch."""
    if parallel_map(k, table, shadows):
        _parallel_shadows(s, n, k, table, shadows)
        return
    directional = table[k, 0] == DIRECTIONAL or table[k, 0] == HEADLIGHT
    for q in range(n):
        x, y, z = s[X + np.uint64(q)], s[Y + np.uint64(q)], s[Z + np.uint64(q)]
        nx, ny, nz = s[NX + np.uint64(q)], s[NY + np.uint64(q)], s[NZ + np.uint64(q)]
        if directional:
            lx, ly, lz = -table[k, 4], -table[k, 5], -table[k, 6]
        else:
            lx, ly, lz = table[k, 1] - x, table[k, 2] - y, table[k, 3] - z
        factor = 0.0
        if nx * lx + ny * ly + nz * lz > 0.0:
            fx, fy, fz = unit(s[PX + np.uint64(q)], s[PY + np.uint64(q)], s[PZ + np.uint64(q)])
            if fx == 0.0 and fy == 0.0 and fz == 0.0:
                fx, fy, fz = nx, ny, nz
            factor = shadow_at(k, table, x, y, z, fx, fy, fz, nx, ny, nz, shadows)
        s[SHADE + np.uint64(q)] = factor


@kernel(inline="always")
def _unshadowed(s, n):
    """A light without a shadow map reaches every pixel."""
    for q in range(n):
        s[SHADE + np.uint64(q)] = 1.0


@kernel(refcounts=False)
def light_reaches(s, n, k, table, shadows, perspective_maps):
    """Light ``k``'s share of each of the chunk's ``n`` pixels that it reaches, into column
    SHADE: its shadow factors where it has a shadow map, else 1. Compiled on its own, once
    for each kind of frame: without shadow maps (``shadows`` None: none of the lookups is
    compiled), with parallel maps only (``perspective_maps`` None: directional lights, whose
    lookups run in passes, :func:`_parallel_shadows`) and with a spot's or a point light's
    maps too (:func:`_chunk_shadows`, which looks up the others one point at a time through
    :func:`~rasterkit.raster.kernels.lights.shadow_at`)."""
    if shadows is None:
        _unshadowed(s, n)
    elif table[k, 13] < 0.0:
        _unshadowed(s, n)
    elif perspective_maps is None:
        _parallel_shadows(s, n, k, table, shadows)
    else:
        _chunk_shadows(s, n, k, table, shadows)
