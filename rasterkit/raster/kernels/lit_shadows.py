"""Shadow lookups for a chunk of pixels lit per pixel (:mod:`rasterkit.raster.kernels.phong_rows`):
each light's shadow factor of each pixel, into the scratch's SHADE column
(:mod:`rasterkit.raster.kernels.lit_columns`), from the shadow maps
(:func:`~rasterkit.raster.kernels.lights.shadow_factor`)."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.lights import parallel_map, parallel_shadow, parallel_terms, shadow_at
from rasterkit.raster.kernels.lit_columns import (
    DIRECTIONAL, HEADLIGHT, NX, NY, NZ, PX, PY, PZ, SHADE, X, Y, Z, unit)
from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def _parallel_shadows(s, n, k, table, shadows):
    """:func:`_chunk_shadows` of a directional light with a parallel map: the terms of a face
    (:func:`~rasterkit.raster.kernels.lights.parallel_terms`) made once for each run of
    pixels with the same plane (the chunk's pixels come run by run), only the point's own
    lookup per pixel; a degenerate face's pixels through
    :func:`~rasterkit.raster.kernels.lights.shadow_at`."""
    lx, ly, lz = -table[k, 4], -table[k, 5], -table[k, 6]
    last_x, last_y, last_z = np.nan, np.nan, np.nan
    fx, fy, fz = 0.0, 0.0, 0.0
    terms = (0.0, 0.0, 0.0, 0.0, 0.0)
    for q in range(n):
        nx, ny, nz = s[NX + np.uint64(q)], s[NY + np.uint64(q)], s[NZ + np.uint64(q)]
        factor = 0.0
        if nx * lx + ny * ly + nz * lz > 0.0:
            x, y, z = s[X + np.uint64(q)], s[Y + np.uint64(q)], s[Z + np.uint64(q)]
            ax, ay, az = s[PX + np.uint64(q)], s[PY + np.uint64(q)], s[PZ + np.uint64(q)]
            if not (ax == last_x and ay == last_y and az == last_z):
                last_x, last_y, last_z = ax, ay, az
                fx, fy, fz = unit(ax, ay, az)
                terms = parallel_terms(k, table, fx, fy, fz, shadows)
            if fx == 0.0 and fy == 0.0 and fz == 0.0:
                factor = shadow_at(k, table, x, y, z, nx, ny, nz, nx, ny, nz, shadows)
            else:
                towards = -terms[0] if fx * nx + fy * ny + fz * nz < 0.0 else terms[0]  # noqa: FURB136
                factor = parallel_shadow(k, table, x, y, z, towards, terms, shadows)
        s[SHADE + np.uint64(q)] = factor


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
def light_reaches(s, n, k, table, shadows):
    """Light ``k``'s share of each of the chunk's ``n`` pixels that it reaches, into column
    SHADE: its shadow factors where it has a shadow map (:func:`_chunk_shadows`), else 1.
    Compiled on its own, once for frames with shadow maps and once for frames without
    (``shadows`` None: none of the lookups is compiled)."""
    if shadows is None:
        _unshadowed(s, n)
    elif table[k, 13] >= 0.0:
        _chunk_shadows(s, n, k, table, shadows)
    else:
        _unshadowed(s, n)
