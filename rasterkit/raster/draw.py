"""Pixel sets of simple shapes in raster space, returned as arrays of (x, y) pixels.

Public as :mod:`rasterkit.draw`. Thin validating wrappers over :mod:`rasterkit.raster.kernels`:
each function checks its arguments and raises ``TypeError`` / ``ValueError`` before any kernel runs. Pixels are ``(x, y)``
integer pairs, x to the right and y down; index an image with ``image[y, x]``.
"""

from __future__ import annotations

import numbers

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.raster.edge_pass import draw_edges, scratch_bytes
from rasterkit.limits import check_memory
from rasterkit.raster.kernels import line as _line
from rasterkit.raster.kernels.segments import SEGMENT_GUARD_BAND
from rasterkit.raster.kernels.edges import MODE_ANTIALIAS, MODE_PLAIN
from rasterkit.raster.kernels import triangle as _triangle
from rasterkit.raster.kernels.clip import GUARD_BAND as _TRIANGLE_LIMIT

__all__ = ["LINE_METHODS", "line", "lines", "triangle"]

LINE_METHODS = {
    "bresenham": _line.METHOD_BRESENHAM,
    "dda": _line.METHOD_DDA,
    "naive": _line.METHOD_NAIVE,
}
"""Names accepted by :func:`line`'s ``method``, mapped to the kernel's method codes."""

_COORD_LIMIT = 2**29

#: Bytes :func:`line` needs per pixel: the minor coordinates (8), the (x, y) pairs (16)
#: and, for a line drawn backwards, their reversed copy (16).
_LINE_BYTES_PER_PIXEL = 40
#: Bytes :func:`lines` needs per segment: its float64 row (32, and as much again for a
#: conversion), two homogeneous points (64), the edge (16) and the edge path's scratch
#: (:func:`rasterkit.raster.edge_pass.scratch_bytes`).
_LINES_BYTES_PER_SEGMENT = 32 * 2 + 64 + 16


def _check_coordinate(name: str, value) -> int:
    """Return ``value`` as an int; reject bools, floats and values the kernel can't handle."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer pixel coordinate, got {type(value).__name__} {value!r}")
    value = int(value)
    if abs(value) > _COORD_LIMIT:
        raise ValueError(f"{name} must lie in [-2**29, 2**29], got {value}")
    return value


def line(x0: int, y0: int, x1: int, y1: int, method: str = "bresenham") -> np.ndarray:
    """Pixels of the line segment from pixel (x0, y0) to pixel (x1, y1).

    The line is stepped along its major axis (the one with the larger extent, x when they
    are equal), one pixel per step; at each step the minor coordinate is the ideal line's,
    rounded half up: where the ideal line passes exactly half-way between two pixels, the one
    with the larger minor coordinate is chosen (+y, down, for a shallow line; +x for a steep
    one). The rule depends on the ideal line only, so a reversed line has the same pixels in
    reverse order and swapping x and y transposes the pixel set.

    Parameters
    ----------
    x0, y0, x1, y1 : int
        Endpoint pixels in raster space (x right, y down), each in ``[-2**29, 2**29]``.
    method : {"bresenham", "dda", "naive"}, optional
        ``"bresenham"``: the midpoint algorithm in integer arithmetic; exact.
        ``"dda"``: the minor coordinate grows by the slope ``m`` per step, in floating point.
        ``"naive"``: ``v = m u + b`` evaluated at every major coordinate ``u``, in floating
        point. The two floating-point methods give Bresenham's pixels except where rounding
        error decides a tie; they agree with it exactly for horizontal, vertical and
        diagonal lines, when the major extent is a power of two, and whenever the ideal line
        never passes exactly half-way between two pixels (for coordinates of moderate size).

    Returns
    -------
    pixels : (max(|x1 - x0|, |y1 - y0|) + 1, 2) int64
        ``(x, y)`` pixels from (x0, y0) to (x1, y1), both included; consecutive pixels
        differ by at most 1 in each coordinate (8-connected).

    Raises
    ------
    TypeError
        If a coordinate is not an integer (bools and floats are rejected).
    ValueError
        If a coordinate is out of range or ``method`` is unknown.
    rasterkit.limits.LimitError
        If the pixels would need more than :func:`rasterkit.limits.memory_limit` (40 bytes
        a pixel: a line 2**29 pixels long needs 20 GiB).

    Examples
    --------
    >>> import numpy as np
    >>> from rasterkit.draw import line
    >>> line(0, 0, 4, 2)
    array([[0, 0],
           [1, 1],
           [2, 1],
           [3, 2],
           [4, 2]])
    >>> img = np.zeros((5, 8), dtype=np.uint8)
    >>> xy = line(1, 4, 7, 0)
    >>> img[xy[:, 1], xy[:, 0]] = 1
    >>> img
    array([[0, 0, 0, 0, 0, 0, 0, 1],
           [0, 0, 0, 0, 0, 1, 1, 0],
           [0, 0, 0, 0, 1, 0, 0, 0],
           [0, 0, 1, 1, 0, 0, 0, 0],
           [0, 1, 0, 0, 0, 0, 0, 0]], dtype=uint8)

    Ties go to the larger minor coordinate whatever the direction (here x is minor):

    >>> img[:] = 0
    >>> for x0, y0, x1, y1 in [(1, 0, 2, 4), (6, 4, 5, 0)]:
    ...     xy = line(x0, y0, x1, y1)
    ...     img[xy[:, 1], xy[:, 0]] = 1
    >>> img
    array([[0, 1, 0, 0, 0, 1, 0, 0],
           [0, 1, 0, 0, 0, 1, 0, 0],
           [0, 0, 1, 0, 0, 0, 1, 0],
           [0, 0, 1, 0, 0, 0, 1, 0],
           [0, 0, 1, 0, 0, 0, 1, 0]], dtype=uint8)
    """
    coords = [_check_coordinate(name, value) for name, value in zip(("x0", "y0", "x1", "y1"), (x0, y0, x1, y1))]
    if not isinstance(method, str) or method not in LINE_METHODS:
        raise ValueError(f"method must be one of {sorted(LINE_METHODS)}, got {method!r}")
    n = max(abs(coords[2] - coords[0]), abs(coords[3] - coords[1])) + 1
    check_memory(n * _LINE_BYTES_PER_PIXEL, f"a line of {n} pixels")
    return _line.line_pixels(*coords, LINE_METHODS[method])


def lines(image: np.ndarray, segments, color=(0, 0, 0), aa: bool = False) -> np.ndarray:
    """Draw many 2D segments into an image, in place, and return it.

    The batch form of :func:`line`: each segment is drawn with the same Bresenham pixels
    (or with Xiaolin Wu's anti-aliasing when ``aa``), clipped to the image before any
    stepping, in parallel over horizontal bands of the image.

    Parameters
    ----------
    image : (H, W, 3) or (H, W, 4) uint8, C-contiguous
        Drawn into in place.
    segments : (K, 4) or (K, 2, 2) array of int or float
        ``x0, y0, x1, y1`` in raster pixels (x right, y down). Integers name pixels; a float
        point lies in the pixel that contains it (``floor``). Any finite value is accepted:
        parts outside the image are clipped away; rows with NaN or inf are skipped.
    color : colour
        A name, ``'#rrggbb'`` or an ``(r, g, b[, a])`` tuple.
    aa : bool
        Anti-aliased lines, blended into the image.

    Returns
    -------
    image : the same array

    Raises
    ------
    TypeError
        If ``segments`` holds anything but real numbers (bools, strings, objects).
    ValueError
        If ``image`` is not a writeable C-contiguous (H, W, 3|4) uint8 array, or
        ``segments`` has another shape.
    rasterkit.limits.LimitError
        If the segments would need more than :func:`rasterkit.limits.memory_limit`.

    Examples
    --------
    >>> import numpy as np
    >>> from rasterkit.draw import lines
    >>> img = np.zeros((4, 6, 3), np.uint8)
    >>> _ = lines(img, [[0, 0, 5, 3], [0, 3, 2, 3]], color="white")
    >>> img[..., 0] // 255
    array([[1, 0, 0, 0, 0, 0],
           [0, 1, 1, 0, 0, 0],
           [0, 0, 0, 1, 1, 0],
           [1, 1, 1, 0, 0, 1]], dtype=uint8)
    """
    from rasterkit.colors import parse_color

    if not isinstance(image, np.ndarray) or image.dtype != np.uint8 or image.ndim != 3 \
            or image.shape[2] not in (3, 4) or not image.flags.c_contiguous:
        raise ValueError("image must be a C-contiguous uint8 array of shape (H, W, 3) or (H, W, 4)")
    if not image.flags.writeable:
        raise ValueError("image must be writeable")
    if max(image.shape[:2]) >= SEGMENT_GUARD_BAND:
        raise ValueError("image is too large")
    given = real_array(segments, "segments", dtype=None)
    if given.size == 0:
        return image
    if given.ndim == 3 and given.shape[1:] == (2, 2):
        given = given.reshape(-1, 4)
    if given.ndim != 2 or given.shape[1] != 4:
        raise ValueError(f"segments must have shape (K, 4) or (K, 2, 2), got {np.shape(segments)}")
    count = len(given)
    check_memory(count * _LINES_BYTES_PER_SEGMENT
                 + scratch_bytes(2 * count, count, 0, MODE_ANTIALIAS if aa else MODE_PLAIN),
                 f"drawing {count} segments")
    if min(image.shape[:2]) == 0:
        return image
    seg = given.astype(np.float64)
    if given.dtype.kind in "iu":
        seg = seg + 0.5  # pixel centres: the kernel takes the pixel containing each point
    points = np.empty((2 * count, 4))
    points[:, :2] = seg.reshape(-1, 2)
    points[:, 2] = 0.0  # depth 0: inside the near and far planes
    points[:, 3] = 1.0
    edges = np.arange(2 * count, dtype=np.int64).reshape(count, 2)
    rgba = np.ascontiguousarray(parse_color(color)[: image.shape[2]])
    mode = MODE_ANTIALIAS if aa else MODE_PLAIN
    draw_edges(image, None, points, edges, rgba, mode)
    return image


_TRIANGLE_MAX_BOX = 2**26  # pixels in the bounding box: keeps the result under 1 GiB


def _check_vertex_coordinate(name: str, value) -> float:
    """Return ``value`` as a float; reject bools, non-numbers, NaN/inf and huge values."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real raster coordinate, got {type(value).__name__} {value!r}")
    value = float(value)
    if not abs(value) <= _TRIANGLE_LIMIT:
        raise ValueError(f"{name} must be finite and within [-2**20, 2**20], got {value}")
    return value


def triangle(x0: float, y0: float, x1: float, y1: float, x2: float, y2: float) -> np.ndarray:
    """Pixels covered by the triangle with vertices (x0, y0), (x1, y1), (x2, y2).

    A pixel (x, y) is covered when its centre (x + 0.5, y + 0.5) lies inside the triangle;
    centres exactly on an edge count only for a *top* edge (horizontal, the triangle below
    it) or a *left* edge (the triangle to its right): the top-left rule of Direct3D and
    OpenGL, the one the renderer uses. So triangles sharing an edge never share a pixel and
    leave no gap between them, and a mesh covers each pixel centre exactly once. Vertices are
    first rounded to 1/256 pixel, like the renderer's fixed point.

    Parameters
    ----------
    x0, y0, x1, y1, x2, y2 : float
        Vertices in raster space (x right, y down; pixel (x, y) is the square
        [x, x + 1) x [y, y + 1)), each finite and within ``[-2**20, 2**20]``. Either
        winding gives the same pixels.

    Returns
    -------
    pixels : (N, 2) int64
        ``(x, y)`` of the covered pixels, row by row (y ascending), x ascending in a row;
        empty for a triangle of zero area or one that covers no pixel centre. Not clipped
        to any image: coordinates may be negative.

    Raises
    ------
    TypeError
        If a coordinate is not a real number (bools are rejected).
    ValueError
        If a coordinate is NaN, infinite or out of range, or the bounding box has more
        than 2**26 pixels.
    rasterkit.limits.LimitError
        If the pixels could need more than :func:`rasterkit.limits.memory_limit` (16
        bytes a pixel of the bounding box).

    Examples
    --------
    >>> import numpy as np
    >>> from rasterkit.draw import triangle
    >>> triangle(0, 0, 4, 0, 0, 4)
    array([[0, 0],
           [1, 0],
           [2, 0],
           [0, 1],
           [1, 1],
           [0, 2]])

    The top and left edges below run through pixel centres, which are drawn; so does the
    diagonal, whose centres are left to the neighbouring triangle:

    >>> img = np.zeros((6, 7), dtype=np.uint8)
    >>> xy = triangle(0.5, 0.5, 5.5, 0.5, 0.5, 5.5)
    >>> img[xy[:, 1], xy[:, 0]] = 1
    >>> xy = triangle(5.5, 0.5, 5.5, 5.5, 0.5, 5.5)
    >>> img[xy[:, 1], xy[:, 0]] += 2
    >>> img
    array([[1, 1, 1, 1, 1, 0, 0],
           [1, 1, 1, 1, 2, 0, 0],
           [1, 1, 1, 2, 2, 0, 0],
           [1, 1, 2, 2, 2, 0, 0],
           [1, 2, 2, 2, 2, 0, 0],
           [0, 0, 0, 0, 0, 0, 0]], dtype=uint8)
    """
    names = ("x0", "y0", "x1", "y1", "x2", "y2")
    xs = [_check_vertex_coordinate(n, v) for n, v in zip(names, (x0, y0, x1, y1, x2, y2))]
    width = np.ceil(max(xs[0::2])) - np.floor(min(xs[0::2])) + 1
    height = np.ceil(max(xs[1::2])) - np.floor(min(xs[1::2])) + 1
    if width * height > _TRIANGLE_MAX_BOX:
        raise ValueError(f"the triangle's bounding box has {width * height:.0f} pixels, more than 2**26")
    check_memory(int(width * height) * 16, f"the pixels of a triangle with a {width:.0f}x{height:.0f} bounding box")
    return _triangle.triangle_pixels(*xs)
