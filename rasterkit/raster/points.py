"""Point clouds as primitives: ``render(..., points=...)`` draws each point as a depth-tested
square splat of ``point_size`` pixels, after the mesh's faces and edges (and in every sample
of a multi-sample render, so splats are anti-aliased too).

The kernel is :func:`rasterkit.raster.kernels.points.splat_points`; it is imported only when points
are drawn.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rasterkit._arrays import describe, real_array
from rasterkit.colors import parse_color
from rasterkit.options import MAX_POINT_SIZE

__all__ = ["Points", "check_points", "draw_points"]


class Points(NamedTuple):
    """Validated points: ``positions`` (N, 3) float64 world space, ``colors`` (1 or N, 4)
    uint8 RGBA, ``size`` pixels."""

    positions: np.ndarray
    colors: np.ndarray
    size: int


def check_points(points, colors, size) -> Points | None:
    """``render``'s ``points``, ``point_color`` and ``point_size``, checked (None: no points).

    ``colors``: one colour (a name, ``#rrggbb`` or an RGB tuple of 0-255) or an (N, 3|4)
    array of 0-255 per point."""
    if points is None:
        return None
    positions = np.ascontiguousarray(real_array(points, "points"), np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"points must be an (N, 3) array, got {describe(points)}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 1 <= size <= MAX_POINT_SIZE:
        raise ValueError(f"point_size must be a whole number of pixels from 1 to {MAX_POINT_SIZE}, "
                         f"got {describe(size)}")
    arr = None if isinstance(colors, str) else np.asarray(colors)
    if arr is not None and arr.ndim == 2:
        if arr.shape[0] != len(positions) or arr.shape[1] not in (3, 4):
            raise ValueError(f"point_color must be one colour or ({len(positions)}, 3|4) values, "
                             f"got {describe(colors)}")
        values = real_array(arr, "point_color")
        if not np.all((values >= 0) & (values <= 255)):
            raise ValueError("point_color values must lie in 0..255")
        rgba = np.full((len(positions), 4), 255, np.uint8)
        rgba[:, : arr.shape[1]] = np.rint(values)
    else:
        rgba = parse_color(colors)[None, :]
    return Points(positions, np.ascontiguousarray(rgba), int(size))


def draw_points(fb, points: Points, matrix: np.ndarray) -> int:
    """Splat ``points`` into ``fb``'s colour and depth through the world -> raster ``matrix``;
    returns how many were drawn."""
    from rasterkit.raster.vertex import transform_points
    from rasterkit.raster.kernels.points import splat_points

    clip = transform_points(points.positions, np.ascontiguousarray(matrix, np.float64))
    colors = np.ascontiguousarray(points.colors[:, : fb.color.shape[2]])
    return int(splat_points(clip, colors, points.size, fb.color, fb.depth))
