"""The checks of the triangle pipeline's inputs (:func:`rasterkit.raster.triangles.rasterize_triangles`
and :class:`rasterkit.raster.shared_samples.SharedTriangles`): buffers, geometry, colours,
cull choice, polygon offset and thread count, each a clear ``TypeError`` or ``ValueError``
before any kernel runs."""

from __future__ import annotations

import math

import numpy as np

from rasterkit.options import CULL, MAX_IMAGE_SIZE
from rasterkit.raster.kernels.shade import all_finite
from rasterkit.raster.triangle_pass import CULL_CODES, MAX_FACES
from rasterkit.runtime import threads as _pool

__all__ = ["check_array", "check_buffer", "check_colors", "check_cull", "check_depth", "check_depth_offset",
           "check_geometry", "check_size", "thread_count"]


def check_array(name, a, dtype, ndim):
    if not isinstance(a, np.ndarray):
        raise TypeError(f"{name} must be a numpy.ndarray, got {type(a).__name__}")
    if a.dtype != dtype:
        raise TypeError(f"{name} must have dtype {np.dtype(dtype).name}, got {a.dtype}")
    if a.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-dimensional, got shape {a.shape}")
    if not a.flags.c_contiguous:
        raise ValueError(f"{name} must be C-contiguous (use numpy.ascontiguousarray)")


def check_buffer(name, a, dtype, shape):
    check_array(name, a, dtype, len(shape))
    if a.shape != shape:
        raise ValueError(f"{name} has shape {a.shape}, expected {shape} to match depth")
    if not a.flags.writeable:
        raise ValueError(f"{name} must be writeable")


def check_colors(name, colors, rows, what):
    check_array(name, colors, np.float32, 2)
    if colors.shape != (rows, 3):
        raise ValueError(f"{name} must have shape ({rows}, 3) (one RGB per {what}), got {colors.shape}")
    if not all_finite(colors):
        raise ValueError(f"{name} must be finite")


def check_geometry(clip, faces):
    check_array("clip", clip, np.float64, 2)
    if clip.shape[1] != 4:
        raise ValueError(f"clip must have shape (N, 4) (xh, yh, zh, w), got {clip.shape}")
    check_array("faces", faces, np.int64, 2)
    if faces.shape[1] != 3:
        raise ValueError(f"faces must have shape (M, 3), got {faces.shape}")
    if faces.shape[0] > MAX_FACES:
        raise ValueError(f"at most {MAX_FACES} faces per call, got {faces.shape[0]}")
    # The vertex indices are checked by the face pass (setup_faces), which reads them all
    # anyway, before anything is drawn or read through them.


def check_depth(depth):
    check_array("depth", depth, np.float32, 2)
    if not depth.flags.writeable:
        raise ValueError("depth must be writeable")
    check_size(*depth.shape)


def check_size(height, width):
    if not (1 <= width <= MAX_IMAGE_SIZE and 1 <= height <= MAX_IMAGE_SIZE):
        raise ValueError(f"image size must be 1..{MAX_IMAGE_SIZE} pixels a side, got {width}x{height}")


def check_cull(cull, m: int) -> None:
    """``cull``: a name of :data:`rasterkit.options.CULL`, or (M,) uint8 codes of
    :data:`rasterkit.raster.triangle_pass.CULL_CODES`, one per face."""
    if isinstance(cull, np.ndarray):
        if cull.dtype != np.uint8 or cull.shape != (m,) or (m and int(cull.max()) > max(CULL_CODES.values())):
            raise ValueError(f"cull must be a name or ({m},) uint8 cull codes, got {cull.dtype} {cull.shape}")
    elif cull not in CULL:
        raise ValueError(f"cull must be one of {sorted(CULL)}, got {cull!r}")


def check_depth_offset(value):
    """``(factor, units)`` as two finite floats (glPolygonOffset's arguments)."""
    try:
        factor, units = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"depth_offset must be (factor, units), got {value!r}") from None
    if not (math.isfinite(factor) and math.isfinite(units)):
        raise ValueError(f"depth_offset must be finite, got {value!r}")
    return factor, units


def thread_count(threads):
    if threads is None:
        return _pool.get_threads()
    limit = _pool.MAX_THREADS
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= limit:
        raise ValueError(f"threads must be an int in 1..{limit} or None, got {threads!r}")
    return int(threads)
