"""The lecture's ray-tracer camera: the world-space ray through a raster point.

Window coordinates of the raster point (x, y): ``a = 2x/W - 1`` (-1 at the left edge, +1 at
the right) and ``b = 1 - 2y/H`` (+1 at the top). With the camera frame (u, v, w) of
:meth:`rasterkit.Camera.basis`:

Perspective. Origin ``o = eye``; focal vector ``f = -w`` (the window lies at distance
1); half window sizes ``t = tan(fov_y/2)`` and ``s = t·W/H``, giving the scaled up
vector ``u' = t·v`` and right vector ``r' = s·u``; the window centre is
``f + s_x·r' + s_y·u'`` for the shift (s_x, s_y). The ray through any raster point is

    r(t) = o + t·d,   d = f + (a + s_x)·r' + (b + s_y)·u',

and through the centre of pixel (i, j): ``a = (2i + 1)/W - 1``, ``b = 1 - (2j + 1)/H``.

Parallel. All rays share the direction ``d = -w - k_x·u - k_y·v``, where
``(k_x, k_y) = ratio·(cos angle, sin angle)`` is the oblique offset per unit depth
(zero for orthographic cameras). A ray meets the target plane (distance D from the
eye) at the window point ``target + a·h_w·u + b·h_h·v`` (half sizes h_w, h_h in world
units); going back to the near plane gives the origin

    o = eye - near·w + (a·h_w + k_x·(D - near))·u + (b·h_h + k_y·(D - near))·v.

:meth:`rasterkit.Camera.ray` calls these functions. The conventions are in the docstring of
:mod:`rasterkit.camera`.
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.limits import check_memory

#: Bytes :meth:`rasterkit.Camera.ray` needs per ray: the window coordinates, origin and
#: direction, and the temporaries of the arithmetic (float64 each).
_BYTES_PER_RAY = 8 * 24


def window_coordinates(
    x: float | np.ndarray, y: float | np.ndarray, width: int, height: int,
) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) of raster points (x, y) in pixels, broadcast together, float64, shape (..., 1).

    ``TypeError`` unless x and y hold real numbers; ``LimitError`` when the rays of all the
    points would not fit in memory (:func:`rasterkit.limits.check_memory`)."""
    x, y = real_array(x, "x"), real_array(y, "y")
    try:
        n = math.prod(np.broadcast_shapes(x.shape, y.shape))
    except ValueError:
        raise ValueError(f"x and y must broadcast together, got shapes {x.shape} and {y.shape}") from None
    check_memory(n * _BYTES_PER_RAY, f"{n} rays")
    a = 2.0 * x / width - 1.0
    b = 1.0 - 2.0 * y / height
    a, b = np.broadcast_arrays(a, b)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ValueError("x and y must be finite")
    return a[..., None], b[..., None]


def perspective_ray(
    a: np.ndarray, b: np.ndarray, *, eye: np.ndarray,
    basis: tuple[np.ndarray, np.ndarray, np.ndarray], half_window: tuple[float, float],
    shift: tuple[float, float],
) -> tuple[np.ndarray, np.ndarray]:
    """Origin (a read-only broadcast of ``eye``) and direction d (not unit), shape (..., 3).

    ``half_window``: s and t, the half window sizes at distance 1.
    """
    u, v, w = basis
    half_w, half_h = half_window
    f, r_prime, u_prime = -w, half_w * u, half_h * v
    d = f + (a + shift[0]) * r_prime + (b + shift[1]) * u_prime
    return np.broadcast_to(eye, d.shape), d


def parallel_ray(
    a: np.ndarray, b: np.ndarray, *, eye: np.ndarray,
    basis: tuple[np.ndarray, np.ndarray, np.ndarray], half_window: tuple[float, float],
    oblique: tuple[float, float], near: float, target_distance: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Origin on the near plane and direction d (not unit, a read-only broadcast), (..., 3).

    ``half_window``: h_w and h_h, world units; ``oblique``: (k_x, k_y); ``target_distance``: D.
    """
    u, v, w = basis
    half_w, half_h = half_window
    k_x, k_y = oblique
    back = target_distance - near
    o = eye - near * w + (a * half_w + k_x * back) * u + (b * half_h + k_y * back) * v
    return o, np.broadcast_to(-w - k_x * u - k_y * v, o.shape)
