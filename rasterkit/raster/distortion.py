"""Lens distortion: the image a calibrated camera with OpenCV's distortion model sees.

OpenCV's model moves an ideal (pinhole) image point, in normalised coordinates ``(x, y) =
(X/Z, Y/Z)``, to

    r² = x² + y²,   g = (1 + k1·r² + k2·r⁴ + k3·r⁶) / (1 + k4·r² + k5·r⁴ + k6·r⁶)
    x_d = x·g + 2·p1·x·y + p2·(r² + 2·x²)
    y_d = y·g + p1·(r² + 2·y²) + 2·p2·x·y

and the pixel is ``(fx·x_d + cx, fy·y_d + cy)``. A render with a distorted camera
(``Camera.from_opencv(..., dist=...)``) is made in two steps:

1. every pixel centre of the distorted image is mapped back to its ideal point, by Newton's
   method on the equations above (to 1e-12); pixels with no ideal point (beyond the fold of
   a strong barrel distortion, where the model turns back on itself) stay empty;
2. an undistorted pinhole image that covers all those points is rendered, at least as finely
   as the distortion stretches the image anywhere (up to :data:`MAX_OVERSAMPLING`). Each
   distorted pixel takes the colour at its ideal point interpolated **bilinearly** between
   the four ideal pixel centres around it (edges keep their sub-pixel position; with
   ``samples > 1`` they are also anti-aliased), and the depth, ids, object ids, normals and ambient occlusion
   of the **nearest** ideal pixel (never a mixture of two surfaces). An edge pixel's colour
   can therefore mix two faces while its id names one of them.

Straight lines therefore come out as the curves the model makes of them (barrel distortion,
``k1 < 0``, bows lines that miss the principal point outwards; pincushion, ``k1 > 0``,
inwards), correct to the nearest pixel of the oversampled ideal image everywhere along
them — not only at the vertices, as distorting the vertices of a mesh would be.

The map of a camera is computed once and kept (for the last two cameras).
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from rasterkit.raster.framebuffer import Framebuffer

__all__ = ["MAX_OVERSAMPLING", "Lens", "distort", "ideal_camera", "render_distorted", "undistort", "vector_plan"]

#: The ideal image is rendered at most this many times finer than the distorted one.
MAX_OVERSAMPLING = 3.0

#: The ideal image is at most this many times wider (and higher) than the distorted one.
MAX_WIDENING = 8.0


def _coefficients(dist):
    k = list(dist) + [0.0] * (8 - len(dist))
    k1, k2, p1, p2, k3, k4, k5, k6 = k
    return k1, k2, p1, p2, k3, k4, k5, k6


def distort(x: np.ndarray, y: np.ndarray, dist) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """OpenCV's distortion of normalised points: ``(x_d, y_d, jacobian)``, the Jacobian
    (..., 2, 2) of ``(x_d, y_d)`` with respect to ``(x, y)``."""
    k1, k2, p1, p2, k3, k4, k5, k6 = _coefficients(dist)
    r2 = x * x + y * y
    a = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    b = 1.0 + r2 * (k4 + r2 * (k5 + r2 * k6))
    g = a / b
    dg = ((k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3)) * b - a * (k4 + r2 * (2.0 * k5 + 3.0 * r2 * k6))) / (b * b)
    gx, gy = 2.0 * x * dg, 2.0 * y * dg
    xd = x * g + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x)
    yd = y * g + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y
    jac = np.empty(x.shape + (2, 2))
    jac[..., 0, 0] = g + x * gx + 2.0 * p1 * y + 6.0 * p2 * x
    jac[..., 0, 1] = x * gy + 2.0 * p1 * x + 2.0 * p2 * y
    jac[..., 1, 0] = y * gx + 2.0 * p1 * x + 2.0 * p2 * y
    jac[..., 1, 1] = g + y * gy + 6.0 * p1 * y + 2.0 * p2 * x
    return xd, yd, jac


def undistort(xd: np.ndarray, yd: np.ndarray, dist, iterations: int = 20):
    """The ideal normalised points ``(x, y)`` that :func:`distort` moves to ``(xd, yd)``, and
    where one was found (converged to 1e-12, on the side of the model's fold that contains
    the centre: positive Jacobian determinant, and not turned through the centre by a
    negative radial factor). Newton's method from ``(xd, yd)``."""
    x, y = xd.copy(), yd.copy()
    with np.errstate(all="ignore"):
        for _ in range(iterations):
            fx, fy, jac = distort(x, y, dist)
            ex, ey = xd - fx, yd - fy
            det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
            x = x + (jac[..., 1, 1] * ex - jac[..., 0, 1] * ey) / det
            y = y + (jac[..., 0, 0] * ey - jac[..., 1, 0] * ex) / det
        fx, fy, jac = distort(x, y, dist)
        det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
        ok = (np.abs(fx - xd) < 1e-12 * np.maximum(1.0, np.abs(xd))) & \
             (np.abs(fy - yd) < 1e-12 * np.maximum(1.0, np.abs(yd))) & (det > 0.0) & \
             (x * fx + y * fy >= 0.0)  # not turned through the centre (a negative radial factor)
    return x, y, ok


@functools.lru_cache(maxsize=2)
def _plan(camera):
    """(ideal camera, :class:`_Map` from the distorted pixels to the ideal image)."""
    k, r, t = camera.to_opencv()
    fx, fy, cx, cy = k[0, 0], k[1, 1], k[0, 2], k[1, 2]
    width, height = camera.width, camera.height
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)  # OpenCV's pixel centres
    x, y, ok = undistort((u - cx) / fx, (v - cy) / fy, camera.distortion)
    if not ok.any():
        raise ValueError("the distortion coefficients map no pixel of the image to a point in view")
    _, _, jac = distort(x[ok], y[ok], camera.distortion)
    # how much finer than the distorted image the ideal one must be: the largest stretch
    jac_px = jac * np.array([[1.0, fx / fy], [fy / fx, 1.0]])
    scale = float(np.clip(np.max(np.linalg.norm(jac_px, ord=2, axis=(1, 2))), 1.0, MAX_OVERSAMPLING))
    fx2, fy2 = scale * fx, scale * fy
    x0, y0 = x[ok].min(), y[ok].min()
    w2 = math.ceil(fx2 * (x[ok].max() - x0)) + 2
    h2 = math.ceil(fy2 * (y[ok].max() - y0)) + 2
    if w2 > MAX_WIDENING * scale * width or h2 > MAX_WIDENING * scale * height:
        raise ValueError(f"the distortion coefficients widen the view too far to render ({w2}x{h2} "
                         f"undistorted pixels for a {width}x{height} image)")
    cx2, cy2 = 0.5 - fx2 * x0, 0.5 - fy2 * y0  # x0, y0 at raster 1.0 (OpenCV's 0.5)
    ideal = type(camera).from_opencv([[fx2, 0.0, cx2], [0.0, fy2, cy2], [0.0, 0.0, 1.0]], r, t, w2, h2,
                                     near=camera.near, far=camera.far)
    x, y = np.where(ok, x, 0.0), np.where(ok, y, 0.0)  # beyond the fold: no point (NaN) to cast
    xr, yr = fx2 * x + cx2 + 0.5, fy2 * y + cy2 + 0.5  # ideal raster coordinates
    i, j = np.floor(xr).astype(np.int64), np.floor(yr).astype(np.int64)
    ok &= (i >= 0) & (i < w2) & (j >= 0) & (j < h2)
    nearest = np.where(ok, j * w2 + i, -1).reshape(-1)
    # bilinear: the four pixel centres around (xr, yr), clamped to the image
    i0 = np.clip(np.floor(xr - 0.5), 0, w2 - 2).astype(np.int64)
    j0 = np.clip(np.floor(yr - 0.5), 0, h2 - 2).astype(np.int64)
    weights = np.stack([np.clip(xr - 0.5 - i0, 0.0, 1.0), np.clip(yr - 0.5 - j0, 0.0, 1.0)]).reshape(2, -1)
    corner = np.where(ok, j0 * w2 + i0, 0).reshape(-1)
    for a in (nearest, corner, weights):
        a.flags.writeable = False
    return ideal, _Map(nearest, corner, weights.astype(np.float32), w2)


class _Map(NamedTuple):
    """Where each distorted pixel (flattened) reads the ideal image: ``nearest`` (P,) the
    flat index of the ideal pixel holding its ideal point (-1: none), ``corner`` (P,) the
    top-left of the four ideal pixel centres around it and ``weights`` (2, P) its position
    between them (x, y in [0, 1]); ``width`` of the ideal image."""

    nearest: np.ndarray
    corner: np.ndarray
    weights: np.ndarray
    width: int


def _bilinear(color: np.ndarray, where: _Map, valid: np.ndarray) -> np.ndarray:
    """(P, C) uint8: the colour at each distorted pixel's ideal point, interpolated
    bilinearly between the four ideal pixel centres around it."""
    flat = color.reshape(-1, color.shape[2])
    wx, wy = where.weights[0][:, None], where.weights[1][:, None]
    c = where.corner
    top = flat[c] * (1 - wx) + flat[c + 1] * wx
    bottom = flat[c + where.width] * (1 - wx) + flat[c + where.width + 1] * wx
    mixed = top * (1 - wy) + bottom * wy
    return (mixed + 0.5).astype(np.uint8)


def ideal_camera(camera):
    """The undistorted camera whose render :func:`render_distorted` resamples."""
    return _plan(camera)[0]


def render_distorted(camera, render_ideal) -> Framebuffer:
    """The distorted image of ``camera``: ``render_ideal(ideal_camera)`` resampled (module
    docstring). ``render_ideal`` returns a :class:`Framebuffer`."""
    ideal, where = _plan(camera)
    src = render_ideal(ideal)
    valid = where.nearest >= 0
    safe = np.where(valid, where.nearest, 0)

    def gather(image, empty):
        flat = image.reshape((-1,) + image.shape[2:])
        out = flat[safe]
        out[~valid] = empty
        return out.reshape((camera.height, camera.width) + image.shape[2:])

    fb = Framebuffer(camera.width, camera.height, alpha=src.alpha, background=src.background,
                     ids=src.ids is not None, cleared=False)
    color = _bilinear(src.color, where, valid)
    color[~valid] = src.background[: src.color.shape[2]]
    fb.color[...] = color.reshape(fb.color.shape)
    if src.ids is not None:
        fb.ids[...] = gather(src.ids, -1)
    fb.defer_depth(lambda depth: np.copyto(depth, gather(src.depth, np.inf)))
    if src.object_ids is not None:
        fb.object_ids, fb.object_first = gather(src.object_ids, -1), src.object_first
    if src.normals is not None:
        fb.normals = gather(src.normals, np.nan)
    if src.uv is not None:
        fb.uv = gather(src.uv, np.nan)
    if src.ao is not None:
        fb.ao = gather(src.ao, np.nan)
    fb.camera = camera
    return fb


class Lens(NamedTuple):
    """The map from the raster of an undistorted camera (``ideal``, :func:`vector_plan`) to
    the raster of the distorted one: the focal lengths and principal points (OpenCV's:
    pixel centres at integers) of the ideal camera (``ideal_f``, ``ideal_c``) and of the
    distorted one (``f``, ``c``), and the distortion coefficients ``dist``."""

    ideal_f: tuple[float, float]
    ideal_c: tuple[float, float]
    f: tuple[float, float]
    c: tuple[float, float]
    dist: tuple[float, ...]

    def __call__(self, px: np.ndarray, py: np.ndarray):
        """Distorted raster ``(u, v)`` of the ideal raster points ``(px, py)`` and whether each
        is on the side of the model's fold that the image shows (``valid``: where
        :func:`undistort` of ``(u, v)`` finds it again)."""
        x = (px - 0.5 - self.ideal_c[0]) / self.ideal_f[0]
        y = (py - 0.5 - self.ideal_c[1]) / self.ideal_f[1]
        with np.errstate(all="ignore"):
            xd, yd, jac = distort(x, y, self.dist)
            det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
            u, v = self.f[0] * xd + self.c[0] + 0.5, self.f[1] * yd + self.c[1] + 0.5
            valid = (det > 0.0) & (x * xd + y * yd >= 0.0) & np.isfinite(u) & np.isfinite(v)
        return u, v, valid


#: :func:`vector_plan` finds its view from the ideal points of a grid of this many
#: points across the distorted image (and its edges).
_COVER_STEP = 128
#: The most an ideal pixel of the margin of :func:`vector_plan` may shrink to in the image.
_MAX_SPREAD = 16.0


@functools.lru_cache(maxsize=2)
def vector_plan(camera):
    """(ideal camera, :class:`Lens`) for vector lines of the distorted ``camera``: an
    undistorted camera with the same focal lengths (no oversampling: lines stay vectors)
    whose image covers the ideal point of every point of the distorted image that has one
    (its pixel edges included), with a margin; lines drawn by it in its raster and moved
    through the :class:`Lens` are the lines of the distorted image."""
    k, r, t = camera.to_opencv()
    fx, fy, cx, cy = k[0, 0], k[1, 1], k[0, 2], k[1, 2]
    width, height = camera.width, camera.height
    step = max(1, math.ceil(max(width, height) / _COVER_STEP))  # pixels between the grid's points
    us = np.unique(np.r_[np.arange(-0.5, width, step), width - 0.5])  # OpenCV: edges at -0.5, W-0.5
    vs = np.unique(np.r_[np.arange(-0.5, height, step), height - 0.5])
    u, v = np.meshgrid(us, vs)
    x, y, ok = undistort((u - cx) / fx, (v - cy) / fy, camera.distortion)
    if not ok.any():
        raise ValueError("the distortion coefficients map no pixel of the image to a point in view")
    x, y = x[ok], y[ok]
    _, _, jac = distort(x, y, camera.distortion)
    # a margin of the grid's step (and 2 pixels) in ideal pixels, where the image shrinks most
    # (up to _MAX_SPREAD times: next to a fold, where it shrinks without bound, the lines end
    # within about a step of the fold)
    jac_px = jac * np.array([[1.0, fx / fy], [fy / fx, 1.0]])
    least = float(np.min(np.linalg.svd(jac_px, compute_uv=False)[:, -1]))
    margin = 2.0 + step * min(1.0 / max(least, 1e-300), _MAX_SPREAD)
    x0, x1 = x.min() - margin / fx, x.max() + margin / fx
    y0, y1 = y.min() - margin / fy, y.max() + margin / fy
    w2, h2 = math.ceil(fx * (x1 - x0)), math.ceil(fy * (y1 - y0))
    if w2 > MAX_WIDENING * MAX_OVERSAMPLING * width or h2 > MAX_WIDENING * MAX_OVERSAMPLING * height:
        raise ValueError(f"the distortion coefficients widen the view too far to draw ({w2}x{h2} "
                         f"undistorted pixels for a {width}x{height} image)")
    cx2, cy2 = -0.5 - fx * x0, -0.5 - fy * y0  # x0, y0 at raster 0 (OpenCV's -0.5)
    ideal = type(camera).from_opencv([[fx, 0.0, cx2], [0.0, fy, cy2], [0.0, 0.0, 1.0]], r, t, w2, h2,
                                     near=camera.near, far=camera.far)
    k2 = ideal.to_opencv()[0]  # the ideal camera's own numbers (a round trip through its fields)
    return ideal, Lens((float(k2[0, 0]), float(k2[1, 1])), (float(k2[0, 2]), float(k2[1, 2])),
                       (float(fx), float(fy)), (float(cx), float(cy)), camera.distortion)
