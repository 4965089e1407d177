"""The images of a vision pipeline made from a render's face ids: camera-space normals and the
scene object seen at each pixel (rasterkit.vision).

Compiled only when a render asks for them: a plain render never loads this module.
"""

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.intrinsics import fetch_add

#: The rows are worked on in this many chunks, shared out among the threads.
N_CHUNKS = 64


@kernel(inline="always")
def _smooth_normal(f, px, py, faces, bary, vertex_normals):
    """Vertex normals of face ``f`` interpolated perspective-correctly at raster (px, py),
    unnormalised (the barycentrics of :func:`rasterkit.kernels.shade.bary_matrices`, which
    are known up to a factor: its sign is made positive)."""
    b0 = bary[f, 0] * px + bary[f, 1] * py + bary[f, 2]
    b1 = bary[f, 3] * px + bary[f, 4] * py + bary[f, 5]
    b2 = bary[f, 6] * px + bary[f, 7] * py + bary[f, 8]
    if b0 + b1 + b2 < 0.0:
        b0, b1, b2 = -b0, -b1, -b2
    v0, v1, v2 = faces[f, 0], faces[f, 1], faces[f, 2]
    x = b0 * vertex_normals[v0, 0] + b1 * vertex_normals[v1, 0] + b2 * vertex_normals[v2, 0]
    y = b0 * vertex_normals[v0, 1] + b1 * vertex_normals[v1, 1] + b2 * vertex_normals[v2, 1]
    z = b0 * vertex_normals[v0, 2] + b1 * vertex_normals[v1, 2] + b2 * vertex_normals[v2, 2]
    return x, y, z


@kernel
def surface_maps(slot, counter, ids, maps):
    """Per pixel of ``ids`` (H, W) int32 (the visible face, -1 for none): the unit camera-space
    normal and the scene object, as a :class:`rasterkit.kernels.records.Maps` asks.

    Normals (``maps.want_normals``) go into ``maps.normals`` (H, W, 3) float32, NaN where no
    face is seen: ``maps.face_normals[f]`` (M, 3) float32 when ``maps.smooth`` is false, else
    ``maps.vertex_normals`` (N, 3) float64 interpolated with ``maps.bary`` (M, 9) and
    ``maps.faces`` (M, 3) int64, normalised. Objects (``maps.want_objects``): the object of
    face ``f`` is ``maps.face_object[f]`` (M,) int32, written to ``maps.object_ids`` (H, W)
    int32 (-1 where none), and ``ids`` becomes the index within that object (minus
    ``maps.object_first[o]``, its first face). A worker of :func:`rasterkit._jit.run_workers`;
    face indices in ``ids`` must lie in 0..M-1 (a render's ids do).
    """
    height, width = ids.shape
    nan = np.float32(np.nan)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(height * ch // N_CHUNKS, height * (ch + 1) // N_CHUNKS):
            py = j + 0.5
            for i in range(width):
                f = ids[j, i]
                if maps.want_normals:
                    if f < 0:
                        maps.normals[j, i, 0] = maps.normals[j, i, 1] = maps.normals[j, i, 2] = nan
                    elif maps.smooth:
                        x, y, z = _smooth_normal(f, i + 0.5, py, maps.faces, maps.bary, maps.vertex_normals)
                        scale = 1.0 / np.sqrt(x * x + y * y + z * z)
                        maps.normals[j, i, 0] = x * scale
                        maps.normals[j, i, 1] = y * scale
                        maps.normals[j, i, 2] = z * scale
                    else:
                        maps.normals[j, i, 0] = maps.face_normals[f, 0]
                        maps.normals[j, i, 1] = maps.face_normals[f, 1]
                        maps.normals[j, i, 2] = maps.face_normals[f, 2]
                if maps.want_objects:
                    if f < 0:
                        maps.object_ids[j, i] = -1
                    else:
                        o = maps.face_object[f]
                        maps.object_ids[j, i] = o
                        ids[j, i] = f - maps.object_first[o]
    return 0
