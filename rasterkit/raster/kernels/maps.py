"""The vision pipeline's images in passes of their own (rasterkit.raster.vision): normals and scene
object ids from a render's face ids, for the renders whose band worker does not make them
(several samples, a wireframe), and the metric depth of a depth buffer when asked for.

The rows are :mod:`rasterkit.raster.kernels.map_rows`'. Compiled only when a render asks for them: a
plain render never loads this module.
"""

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.map_rows import map_fields, metric_run, surface_row

#: The rows are worked on in this many chunks, shared out among the threads.
N_CHUNKS = 64


@kernel(refcounts=False)
def surface_maps(slot, counter, ids, maps):
    """Per pixel of ``ids`` (H, W) int32 (the visible face, -1 for none): the unit camera-space
    normal and the scene object, as a :class:`rasterkit.raster.kernels.records.Maps` asks.

    Normals (``maps.want_normals``) go into ``maps.normals`` (H, W, 3) float32, NaN where no
    face is seen. Flat (``maps.smooth`` false): each pixel's face's world-space normal
    ``maps.world_normals[f]`` (M, 3) float32 turned into camera space by ``maps.rotation``
    (3, 3) float64 (world -> camera); per pixel rather than per face first: a frame sees a
    few of a large model's faces, and a pass over all of them cost more than the pixels'
    rotations. Smooth: ``maps.vertex_normals`` (N, 3) float64 (world space) interpolated
    with ``maps.bary`` (M, 9) and ``maps.faces`` (M, 3) int64, turned by ``maps.rotation``
    and normalised. Objects (``maps.want_objects``): the object of face ``f`` is
    ``maps.face_object[f]`` (M,) int32, written to ``maps.object_ids`` (H, W) int32 (-1
    where none), and ``ids`` becomes the index within that object (minus
    ``maps.object_first[o]``, its first face). ``maps.want_depth`` is not read here.

    A worker of :func:`rasterkit.runtime.threads.run_workers` over ``N_CHUNKS`` pieces of rows, for
    the renders whose band worker does not make the maps itself
    (:func:`rasterkit.raster.kernels.map_rows.band_maps`). Face
    indices in ``ids`` must lie in 0..M-1 (a render's ids do).
    """
    height, width = ids.shape
    nan = np.float32(np.nan)
    fields = map_fields(maps)
    iflat = ids.reshape(ids.size)
    w = np.uint64(width)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(np.uint64(height * ch // N_CHUNKS), np.uint64(height * (ch + 1) // N_CHUNKS)):
            surface_row(iflat, j, w, fields, nan)
    return 0


@kernel(refcounts=False)
def metric_depth(slot, counter, depth, out, near, far, perspective):
    """``out`` (H, W) float32: the distance along the optical axis of each depth ``D`` of
    ``depth`` (H, W) float32, in float64: ``f·n / (f - D·(f - n))`` for a perspective camera,
    ``n + D·(f - n)`` for a parallel one; 0 where ``D`` is +inf (nothing drawn). A worker
    like :func:`surface_maps`."""
    height, width = depth.shape
    dflat, oflat = depth.reshape(depth.size), out.reshape(out.size)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        metric_run(dflat, oflat, np.uint64(width * (height * ch // N_CHUNKS)),
                    np.uint64(width * (height * (ch + 1) // N_CHUNKS)), near, far, perspective)
    return 0
