"""Ambient occlusion of a rendered frame, from its depth buffer (``render(..., ao=True)``).

Definition
    The ambient occlusion of a surface point ``P`` with normal ``N`` is the cosine-weighted
    share of the hemisphere around ``N`` whose rays from ``P`` meet geometry within the
    radius ``R``: ``AO(P) = (1/pi) integral V_R(P, w) (w . N) dw``, ``V_R`` 1 where the ray
    meets a surface closer than ``R``. A frame's ``ao`` map holds ``1 - AO``, the light an
    ambient sky lets through (1 in the open, 0 fully enclosed; glTF's occlusion maps use the
    same sense), and the colour of each drawn pixel is multiplied by it in linear light.

Estimate (screen space)
    :mod:`rasterkit.raster.kernels.ao` works it out from the frame's depth buffer alone:
    ``P`` from the pixel's ray and axial depth, ``N`` from the neighbouring depths (the geometric
    normal), ``samples`` rays in cosine-weighted directions (a Fibonacci spiral, turned per
    pixel within a 4x4 tile), each marched in four steps up to ``R`` and blocked where a step
    falls behind the surface the depth buffer holds there by less than ``R``; then each
    pixel's share is averaged over its tile on the same surface. What the camera does not see
    (the back of a model, surfaces hidden by others) cannot occlude, and every surface is taken
    to be at most ``R`` thick: the estimate's differences from the ray-traced definition.
    Everything is a function of the depth buffer, so the result is the same at any thread count.
"""

from __future__ import annotations

import math
from functools import lru_cache, partial

import numpy as np

from rasterkit._arrays import finite_bounds
from rasterkit.material.colorspace import DECODE, SRGB_ROW, encode_srgb8
from rasterkit.runtime import scratch as _memory
from rasterkit.runtime.threads import MAX_THREADS, run_workers

__all__ = ["DEFAULT_RADIUS", "ambient_occlusion", "default_radius", "directions"]

#: The radius, as a share of the model's bounding-box diagonal, when none is given.
DEFAULT_RADIUS = 0.1

#: Pixels below this many go on one thread.
_SMALL = 1 << 15


def default_radius(vertices: np.ndarray) -> float:
    """:data:`DEFAULT_RADIUS` times the diagonal of the finite ``vertices``' bounding box
    (1 for none)."""
    bounds = finite_bounds(vertices)
    if bounds is None:
        return 1.0
    low, high = bounds
    diagonal = float(np.linalg.norm(high - low))
    return DEFAULT_RADIUS * diagonal if diagonal > 0 else 1.0


@lru_cache(maxsize=8)
def directions(count: int) -> np.ndarray:
    """(count, 3) unit directions about +z, cosine-weighted: a Fibonacci spiral over the unit
    disk (equal areas) lifted onto the hemisphere (Malley's method)."""
    k = np.arange(count, dtype=np.float64)
    r = np.sqrt((k + 0.5) / count)
    phi = k * (math.pi * (3.0 - math.sqrt(5.0)))
    return _frozen(np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1.0 - r * r)], axis=1))


@lru_cache(maxsize=8)
def camera_geometry(camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(rays (6, 3), matrix (4, 4), axis (4,))`` of :func:`rasterkit.raster.kernels.ao.ao_raw`
    for ``camera``: the point at raster (x, y) with axial depth d is ``O0 + x Ox + y Oy + d
    (V0 + x Vx + y Vy)`` (exact for perspective and parallel cameras, sheared or shifted), found
    by inverting the world -> raster matrix; the axial depth of a world point ``q`` is
    ``axis[:3] . q + axis[3]``."""
    matrix = np.asarray(camera.world_to_raster(), np.float64)
    inverse = np.linalg.inv(matrix)
    near, far, perspective = float(camera.near), float(camera.far), camera.kind == "perspective"

    def point(x, y, d):
        window = far * (d - near) / (d * (far - near)) if perspective else (d - near) / (far - near)
        h = inverse @ np.array([x, y, window, 1.0])
        return h[:3] / h[3]

    d1, d2 = near * 2.0, (near + far) / 2.0
    o, v = {}, {}
    for x, y in ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0)):
        a, b = point(x, y, d1), point(x, y, d2)
        v[x, y] = (b - a) / (d2 - d1)
        o[x, y] = a - d1 * v[x, y]
    rays = np.array([o[0, 0], o[1, 0] - o[0, 0], o[0, 1] - o[0, 0], v[0, 0], v[1, 0] - v[0, 0], v[0, 1] - v[0, 0]])
    # the axial depth is affine in the world point: fitted to points of known depth
    samples = [(x, y, d) for x in (0.0, 100.0) for y in (0.0, 100.0) for d in (d1, d2)]
    points = np.array([np.append(point(x, y, d), 1.0) for x, y, d in samples])
    axis = np.linalg.lstsq(points, np.array([d for _, _, d in samples]), rcond=None)[0]
    return _frozen(rays), _frozen(matrix), _frozen(axis)  # (kept for the camera's next frames)


def ambient_occlusion(depth: np.ndarray, camera, radius: float, samples: int, color: np.ndarray):
    """Multiplies the RGB of ``color`` (H, W, 3|4) uint8 sRGB, in place and in linear light,
    by ``1 - AO`` (see the module) of the frame whose depth buffer is ``depth`` (H, W) float32
    and camera ``camera``; returns a function that makes the (H, W) float32 map of ``1 - AO``
    (NaN where nothing was drawn) from the same depths, for :attr:`rasterkit.Framebuffer.ao`
    (only the pixels near a blocked ray are darkened here, and a render whose map nobody
    reads does not fill one)."""
    from rasterkit.raster.kernels.ao import STEPS, ao_blur, ao_grid, ao_raw, ao_shade

    height, width = depth.shape
    view = (np.ascontiguousarray(depth, np.float32), float(camera.near), float(camera.far),
            camera.kind == "perspective")
    rays, matrix, axis = camera_geometry(camera)
    s = stride(width, height)
    rows, columns = -(-height // s), -(-width // s)
    flat = np.zeros(rows * columns + 1, np.float32)  # the grid's depths, then 0 for what is off it
    grid = flat[:-1].reshape(rows, columns)
    threads = 1 if depth.size < _SMALL else None
    run_workers(ao_grid, view, s, grid, threads=threads)
    raw, shares, some = np.empty_like(grid), np.empty_like(grid), np.empty(rows, np.uint8)
    where = np.empty((MAX_THREADS, STEPS * samples), np.int32)
    along = np.empty((MAX_THREADS, STEPS * samples), np.float32)
    run_workers(ao_raw, view, flat, columns, rays, matrix, axis, tile_steps(samples), float(radius), s, where,
                along, raw, some, threads=threads)
    run_workers(ao_blur, grid, raw, some, float(radius), shares, threads=threads)
    fractions, starts = _interpolation(height, width, s)
    marks = np.empty((MAX_THREADS, columns), np.uint8)
    run_workers(ao_shade, view, grid, shares, float(radius), fractions, starts, marks,
                np.empty((MAX_THREADS, width), np.float32), color, _DECODE, _ENCODE, threads=threads)
    return partial(_fill, view, grid, shares, float(radius), fractions, starts, threads)


def _fill(view, grid, shares, radius, fractions, starts, threads) -> np.ndarray:
    """The map of :func:`ambient_occlusion` (:func:`rasterkit.raster.kernels.ao.ao_fill`)."""
    from rasterkit.raster.kernels.ao import ao_fill

    out = _memory.take(view[0].shape, np.float32)
    run_workers(ao_fill, view, grid, shares, radius, fractions, starts,
                np.empty((MAX_THREADS, grid.shape[1]), np.uint8), out, threads=threads)
    return out


@lru_cache(maxsize=8)
def tile_steps(samples: int) -> np.ndarray:
    """(16, 3, STEPS K) float32 of :func:`rasterkit.raster.kernels.ao.ao_raw`: for each rank of a
    4x4 tile, the K :func:`directions` turned about the normal (z) by ``2 pi rank / 16``, and
    along each the points at ``(j + shift) / STEPS`` (j = 0 .. STEPS - 1) with the rank's
    shift ``((7 rank) % 16 + 0.5) / 16`` (so that the ranks' steps interleave), as rows x, y,
    z; step j of ray k at ``j K + k``."""
    from rasterkit.raster.kernels.ao import STEPS

    a, b, c = directions(samples).T
    rank = np.arange(16)[:, None]
    cos, sin = np.cos(rank * (2.0 * math.pi / 16.0)), np.sin(rank * (2.0 * math.pi / 16.0))
    turned = np.stack([a * cos - b * sin, a * sin + b * cos, np.broadcast_to(c, (16, samples))], axis=1)
    along = (np.arange(STEPS)[None, :] + ((rank * 7) % 16 + 0.5) / 16.0) / STEPS  # (16, STEPS)
    steps = turned[:, :, None, :] * along[:, None, :, None]  # (16, 3, STEPS, K)
    return _frozen(steps.reshape(16, 3, STEPS * samples).astype(np.float32))


def _grid_pixels(size: int, s: int) -> np.ndarray:
    """The pixels (along one axis of ``size``) where rays are sent: the middle of every ``s``."""
    return np.minimum(np.arange(-(-size // s)) * s + s // 2, size - 1)


@lru_cache(maxsize=8)
def _interpolation(height: int, width: int, s: int) -> tuple[np.ndarray, np.ndarray]:
    """(fractions (H + W,), starts (Hg + 1 + Wg + 1,)) of
    :func:`rasterkit.raster.kernels.ao.ao_map`: the rows' then the columns' weights of the
    grid point after them (:func:`_between`), and the first row after each grid row (then H),
    then the same for columns (then W)."""
    parts = []
    for size in (height, width):
        low, fraction = _between(size, s)
        parts.append((fraction, np.searchsorted(low, np.arange(-(-size // s) + 1), side="left")))
    (row_fractions, row_starts), (column_fractions, column_starts) = parts
    return (_frozen(np.concatenate([row_fractions, column_fractions])),
            _frozen(np.concatenate([row_starts, column_starts]).astype(np.int64)))


def _between(size: int, s: int) -> tuple[np.ndarray, np.ndarray]:
    """For each pixel along an axis of ``size``: the grid point before it (int64) and the
    weight of the one after it (float32, 0 to 1), for bilinear interpolation."""
    points = _grid_pixels(size, s)
    at = np.arange(size)
    low = np.clip(np.searchsorted(points, at, side="right") - 1, 0, len(points) - 1)
    high = np.minimum(low + 1, len(points) - 1)
    span = np.maximum(points[high] - points[low], 1)
    fraction = np.clip((at - points[low]) / span, 0.0, 1.0)
    return low.astype(np.int64), fraction.astype(np.float32)


def _frozen(a: np.ndarray) -> np.ndarray:
    """A read-only C-contiguous copy of ``a`` (for the caches here)."""
    a = np.array(a, order="C")
    a.flags.writeable = False
    return a


def stride(width: int, height: int) -> int:
    """Every how many pixels (across and down) the rays are sent: one per 180 pixels of the
    shorter side up to 720, beyond that growing with its square (the grid's points then stay
    about as many as at 720: 1920x1080 has every 8th pixel's), rounded, 1 to 8 (1280x720:
    every 4th; 480p: every 3rd; below 270: each)."""
    side = min(width, height)
    return max(1, min(8, round(side / 180 * max(1.0, side / 720))))


#: Entries of the linear -> sRGB table (linear steps of 1/4095: within one level of 255).
_ENCODE_SIZE = 4096
# read-only, as every table kept between frames: a warm helper's compile-only run zeroes the
# writable arrays it is handed (rasterkit.runtime.warm), and a test that runs that hook in its
# own process left these zeroed for its later renders (AO then blackened whole grid cells)
_DECODE = _frozen(DECODE[SRGB_ROW].astype(np.float32))
_ENCODE = _frozen(encode_srgb8(np.arange(_ENCODE_SIZE) / (_ENCODE_SIZE - 1)))
