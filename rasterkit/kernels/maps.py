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


@kernel(inline="always")
def _put_normal(normals, j, i, rotation, x, y, z):
    """``normals[j, i]``: the world-space vector (x, y, z) turned into camera space by
    ``rotation`` (3, 3) and scaled to unit length (NaN for a zero vector)."""
    cx = rotation[0, 0] * x + rotation[0, 1] * y + rotation[0, 2] * z
    cy = rotation[1, 0] * x + rotation[1, 1] * y + rotation[1, 2] * z
    cz = rotation[2, 0] * x + rotation[2, 1] * y + rotation[2, 2] * z
    scale = 1.0 / np.sqrt(cx * cx + cy * cy + cz * cz)
    normals[j, i, 0] = cx * scale
    normals[j, i, 1] = cy * scale
    normals[j, i, 2] = cz * scale


@kernel(refcounts=False)
def camera_normals(slot, counter, world, rotation, out):
    """``out`` (M, 3) float32: the unit world-space normals ``world`` (M, 3) float32 (a
    Mesh's ``face_normals``: unit, zero for a degenerate face, NaN for a non-finite one)
    turned by ``rotation`` (3, 3) float64 into camera space: a rotation keeps their length,
    so no square root is needed; zero ones become NaN. A worker of
    :func:`rasterkit._jit.run_workers`, in ``N_CHUNKS`` pieces."""
    m = world.shape[0]
    r00, r01, r02 = rotation[0, 0], rotation[0, 1], rotation[0, 2]
    r10, r11, r12 = rotation[1, 0], rotation[1, 1], rotation[1, 2]
    r20, r21, r22 = rotation[2, 0], rotation[2, 1], rotation[2, 2]
    nan = np.float32(np.nan)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for f in range(np.uint64(m * ch // N_CHUNKS), np.uint64(m * (ch + 1) // N_CHUNKS)):
            x, y, z = np.float64(world[f, 0]), np.float64(world[f, 1]), np.float64(world[f, 2])
            if x == 0.0 and y == 0.0 and z == 0.0:
                out[f, 0] = out[f, 1] = out[f, 2] = nan
            else:
                out[f, 0] = r00 * x + r01 * y + r02 * z
                out[f, 1] = r10 * x + r11 * y + r12 * z
                out[f, 2] = r20 * x + r21 * y + r22 * z
    return 0


@kernel(inline="always")
def _nan_row(nflat, j, width, nan):
    """Row ``j`` of the normals (``nflat``: the (H, W, 3) array, flat) set to NaN: a plain
    fill the compiler vectorises; the pixels that see a face are written over next."""
    for k in range(np.uint64(3 * width * j), np.uint64(3 * width * (j + 1))):
        nflat[k] = nan  # unsigned: no wraparound test, a vectorised fill


@kernel(inline="always")
def _flat_row(ids, j, width, normals, nflat, face_normals, nan):
    """Row ``j`` of flat normals: the camera-space normal of each pixel's face, NaN for none."""
    _nan_row(nflat, j, width, nan)
    for i in range(np.uint64(width)):  # unsigned indices: no wraparound tests
        f = ids[j, i]
        if f >= 0:
            normals[j, i, 0] = face_normals[f, 0]
            normals[j, i, 1] = face_normals[f, 1]
            normals[j, i, 2] = face_normals[f, 2]


@kernel(inline="always")
def _smooth_row(ids, j, width, normals, nflat, faces, bary, vertex_normals, rotation, nan):
    """Row ``j`` of smooth normals: vertex normals interpolated at each pixel centre."""
    _nan_row(nflat, j, width, nan)
    py = j + 0.5
    for i in range(width):
        f = ids[j, i]
        if f >= 0:
            x, y, z = _smooth_normal(f, i + 0.5, py, faces, bary, vertex_normals)
            _put_normal(normals, j, i, rotation, x, y, z)


@kernel(inline="always")
def _object_row(ids, j, width, object_ids, face_object, object_first):
    """Row ``j`` of object ids, and ``ids`` made indices within their object."""
    for i in range(width):
        f = ids[j, i]
        if f < 0:
            object_ids[j, i] = -1
        else:
            o = face_object[f]
            object_ids[j, i] = o
            ids[j, i] = f - object_first[o]


@kernel(refcounts=False)
def surface_maps(slot, counter, ids, maps):
    """Per pixel of ``ids`` (H, W) int32 (the visible face, -1 for none): the unit camera-space
    normal and the scene object, as a :class:`rasterkit.kernels.records.Maps` asks.

    Normals (``maps.want_normals``) go into ``maps.normals`` (H, W, 3) float32, NaN where no
    face is seen: ``maps.face_normals[f]`` (M, 3) float32 (camera space, unit:
    :func:`camera_normals`) when ``maps.smooth`` is false, else ``maps.vertex_normals`` (N, 3)
    float64 (world space) interpolated with ``maps.bary`` (M, 9) and ``maps.faces`` (M, 3)
    int64, turned by ``maps.rotation`` (3, 3) float64 (world -> camera) and normalised. Objects (``maps.want_objects``): the object of
    face ``f`` is ``maps.face_object[f]`` (M,) int32, written to ``maps.object_ids`` (H, W)
    int32 (-1 where none), and ``ids`` becomes the index within that object (minus
    ``maps.object_first[o]``, its first face). A worker of :func:`rasterkit._jit.run_workers`;
    face indices in ``ids`` must lie in 0..M-1 (a render's ids do).
    """
    height, width = ids.shape
    nan = np.float32(np.nan)
    # the record's fields as locals: read through the record inside the loop, every access
    # would count a reference (an atomic operation) on the array
    want_normals, smooth, want_objects = maps.want_normals, maps.smooth, maps.want_objects
    normals, faces, bary = maps.normals, maps.faces, maps.bary
    vertex_normals, face_normals, rotation = maps.vertex_normals, maps.face_normals, maps.rotation
    object_ids, face_object, object_first = maps.object_ids, maps.face_object, maps.object_first
    nflat = normals.reshape(normals.size)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(height * ch // N_CHUNKS, height * (ch + 1) // N_CHUNKS):
            # one loop per case: no test of the choices per pixel
            if want_normals and not smooth:
                _flat_row(ids, j, width, normals, nflat, face_normals, nan)
            elif want_normals:
                _smooth_row(ids, j, width, normals, nflat, faces, bary, vertex_normals, rotation, nan)
            if want_objects:
                _object_row(ids, j, width, object_ids, face_object, object_first)
    return 0


@kernel(refcounts=False)
def metric_depth(slot, counter, depth, out, near, far, perspective):
    """``out`` (H, W) float32: the distance along the optical axis of each depth ``D`` of
    ``depth`` (H, W) float32, in float64: ``f·n / (f - D·(f - n))`` for a perspective camera,
    ``n + D·(f - n)`` for a parallel one; 0 where ``D`` is +inf (nothing drawn). A worker
    like :func:`surface_maps`."""
    height, width = depth.shape
    span = far - near
    product = far * near
    dflat, oflat = depth.reshape(depth.size), out.reshape(out.size)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        lo = np.uint64(width * (height * ch // N_CHUNKS))
        hi = np.uint64(width * (height * (ch + 1) // N_CHUNKS))
        for k in range(lo, hi):  # unsigned: no wraparound tests, vectorised
            d = np.float64(dflat[k])
            if perspective:
                value = product / (far - d * span)
            else:
                value = near + d * span
            oflat[k] = value if d < np.inf else 0.0
    return 0
