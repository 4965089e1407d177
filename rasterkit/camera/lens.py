"""The thin-lens camera and the samples of a multi-sample render: one matrix per sample.

:func:`rasterkit.render` with ``samples = n > 1`` draws the scene ``n`` times, each time
through the matrix :func:`sample_matrices` gives, and averages the images. Sample ``s`` has
a sub-pixel offset ``(j_x, j_y)`` (pixels, raster x right, y down) and a point
``(l_x, l_y)`` on the unit lens disc (:mod:`rasterkit.raster.samples`).

Sub-pixel jitter (every camera). To see the scene at the raster point ``p + j`` in the
pixel whose centre is ``p``, every point's image must move by ``-j``: ``x' = x - j_x``,
``y' = y - j_y``. A window shift ``(s_x, s_y)`` (in half window sizes) moves the images by
``-s_x·W/2`` in x and ``+s_y·H/2`` in y (the window moves right and up; raster y points
down), so the jitter is the shift change ``Δs = (2·j_x/W, -2·j_y/H)``. A parallel camera has
no shift; its images move by the raster translation ``(-j_x, -j_y)`` put before ``K``.

Thin lens (perspective cameras with ``aperture A > 0``). The lens is the disc of diameter
``A`` around the eye in the plane spanned by the camera's right and up axes ``u``, ``v``.
Sample ``s`` looks through the lens point ``e = (A/2)·(l_x·u + l_y·v)``: eye *and* target
move by ``e``, so the viewing direction, the frame (u, v, w), the near and far planes (as
distances along w) and every depth stay as they are. In the moved camera's space a point
at camera coordinates ``(x, y, -d)`` has ``x - e_x``; its window coordinate (at distance 1)
is ``(x - e_x)/d``. The plane in focus, at distance ``F`` (``focus_distance``, default the
distance to the target), must keep its image: its points moved by ``-e_x/F`` in window
units, so the window moves by the same amount, its centre going to ``c_x = -e_x/F``: the
shift changes by

    Δs_x = -e_x / (F·tan(fov_y/2)·W/H),   Δs_y = -e_y / (F·tan(fov_y/2)),

``e`` divided by the half window size at the focus distance. The window is now off centre,
so the lecture's shear ``H`` (``x' = x + c_x·z``, :func:`rasterkit.camera.chain._H`) is a
real shear: it carries the lens point's window centre back onto the -z axis before
``S_xy`` and the perspective divide. Relative to the new window centre a point at distance
``d`` lies at ``x/d - e_x/d + e_x/F = x/d + e_x·(1/F - 1/d)``, in pixels times the focal
length in pixels ``f_px = (H/2)/tan(fov_y/2)``: it moves by ``f_px·e·(1/F - 1/d)``. Over the
lens (``|e| <= A/2``) its image sweeps a disc, the circle of confusion, of diameter

    b = f_px·A·|1/F - 1/d| = A·|d - F| / d · f_px / F   pixels,

zero on the focus plane (sharp), growing in front of it (d < F) and behind it (d > F).

Vignetting (:func:`vignette_factor`). A pixel whose ray makes the angle θ with the optical
axis receives ``cos⁴θ`` of the light of the axis's (the natural falloff of a lens: the
ray's obliquity on the lens and the image plane, cos² of the inverse-square distance).
With the principal point ``(c_x, c_y)``, where the axis meets the image
(``((1 - s_x)·W/2, (1 + s_y)·H/2)`` for the camera's own shift), ``cos θ = f_px /
sqrt(f_px² + (x - c_x)² + (y - c_y)²)`` at the pixel centre (x, y). ``vignette = v`` scales
each pixel by ``1 - v·(1 - cos⁴θ)``. A parallel camera's rays are all parallel to the axis:
no falloff.
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.transform import compose, translate
from rasterkit.camera.chain import perspective_chain

__all__ = ["focus_distance", "sample_matrices", "vignette_factor"]


def focus_distance(camera) -> float:
    """The distance of the plane in focus: ``camera.focus_distance``, or the distance from
    the eye to the target when that is None."""
    if camera.focus_distance is not None:
        return camera.focus_distance
    return float(np.linalg.norm(np.subtract(camera.target, camera.eye)))


def sample_matrices(camera, offsets: np.ndarray, lens: np.ndarray) -> list[np.ndarray]:
    """The world -> homogeneous raster matrix of each sample, (4, 4) float64 each.

    Parameters
    ----------
    camera : Camera
    offsets : (n, 2) float64
        Sub-pixel offsets in pixels (raster x right, y down).
    lens : (n, 2) float64
        Points on the unit disc (x right, y up); unused when ``camera.aperture`` is 0.

    An offset (0, 0) at the lens centre gives ``camera.world_to_raster()`` itself.
    """
    width, height = camera.width, camera.height
    if camera.kind != "perspective":
        k = camera.world_to_raster()
        return [k if (jx, jy) == (0.0, 0.0) else compose(k, translate(-jx, -jy, 0.0))
                for jx, jy in offsets.tolist()]
    basis = camera.basis()
    half_w, half_h = camera._half_window()
    radius = camera.aperture / 2.0
    focus = focus_distance(camera)
    eye = np.asarray(camera.eye, np.float64)
    matrices = []
    for (jx, jy), (lx, ly) in zip(offsets.tolist(), lens.tolist()):
        if (jx, jy, lx * radius, ly * radius) == (0.0, 0.0, 0.0, 0.0):
            matrices.append(camera.world_to_raster())
            continue
        ex, ey = radius * lx, radius * ly
        shift = (camera.shift[0] + 2.0 * jx / width - ex / (focus * half_w),
                 camera.shift[1] - 2.0 * jy / height - ey / (focus * half_h))
        chain = perspective_chain(eye=eye + ex * basis[0] + ey * basis[1], basis=basis,
                                  half_window=(half_w, half_h), shift=shift, near=camera.near,
                                  far=camera.far, width=width, height=height)
        matrices.append(compose(*(m for _, m in chain)))
    return matrices


def vignette_factor(camera, strength: float) -> np.ndarray | None:
    """``1 - strength·(1 - cos⁴θ)`` at every pixel centre, (H, W) float32; None when there
    is nothing to darken (``strength`` 0, or a parallel camera)."""
    if strength == 0.0 or camera.kind != "perspective":
        return None
    width, height = camera.width, camera.height
    f_px = (height / 2.0) / math.tan(math.radians(camera.fov_y) / 2.0)
    cx = (1.0 - camera.shift[0]) * width / 2.0
    cy = (1.0 + camera.shift[1]) * height / 2.0
    dx = (np.arange(width) + 0.5 - cx) * camera.pixel_aspect / f_px
    dy = (np.arange(height) + 0.5 - cy) / f_px
    cos2 = 1.0 / (1.0 + dx[None, :] ** 2 + dy[:, None] ** 2)
    return (1.0 - strength * (1.0 - cos2 * cos2)).astype(np.float32)
