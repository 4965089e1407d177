"""The images of a vision pipeline made from a render's face ids: camera-space normals and the
scene object seen at each pixel (rasterkit.vision).

Compiled only when a render asks for them: a plain render never loads this module.
"""

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.intrinsics import fetch_add

#: The rows are worked on in this many chunks, shared out among the threads.
N_CHUNKS = 64

#: Pixels tested at once for a face: a block that sees none (the background, most of many
#: frames) is written with vector stores, without a test per pixel.
BLOCK = 16


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
def _to_camera(rotation, x, y, z):
    """The world-space vector (x, y, z) turned into camera space by ``rotation`` (3, 3) and
    scaled to unit length (NaN for a zero vector)."""
    cx = rotation[0, 0] * x + rotation[0, 1] * y + rotation[0, 2] * z
    cy = rotation[1, 0] * x + rotation[1, 1] * y + rotation[1, 2] * z
    cz = rotation[2, 0] * x + rotation[2, 1] * y + rotation[2, 2] * z
    scale = 1.0 / np.sqrt(cx * cx + cy * cy + cz * cz)
    return cx * scale, cy * scale, cz * scale


@kernel(inline="always")
def _background(iflat, k):
    """Whether the ``BLOCK`` pixels from ``k`` of ``iflat`` (the ids, flat) all see no face:
    a maximum the compiler vectorises."""
    top = iflat[k]
    for q in range(1, BLOCK):
        v = iflat[k + np.uint64(q)]
        top = v if v > top else top
    return top < 0


@kernel(inline="always")
def _flat_pixel(iflat, nflat, p, world_normals, r, nan):
    """Pixel ``p`` (flat index) of flat normals: its face's unit world-space normal (a
    Mesh's ``face_normals``, zero for a face without area) turned into camera space by the
    rotation ``r`` (9,) float64, row by row (a rotation keeps the length: no square root);
    NaN for no face or a zero normal."""
    f = iflat[p]
    o = np.uint64(3) * p
    if f >= 0:
        x, y, z = np.float64(world_normals[f, 0]), np.float64(world_normals[f, 1]), np.float64(world_normals[f, 2])
        zero = (x == 0.0) & (y == 0.0) & (z == 0.0)
        cx = r[0] * x + r[1] * y + r[2] * z
        cy = r[3] * x + r[4] * y + r[5] * z
        cz = r[6] * x + r[7] * y + r[8] * z
        nflat[o] = nan if zero else cx
        nflat[o + np.uint64(1)] = nan if zero else cy
        nflat[o + np.uint64(2)] = nan if zero else cz
    else:
        nflat[o] = nflat[o + np.uint64(1)] = nflat[o + np.uint64(2)] = nan


@kernel(inline="always")
def _flat_row(iflat, lo, hi, nflat, world_normals, r, nan):
    """Pixels ``lo`` to ``hi`` (flat indices, one row) of flat normals, in blocks of
    ``BLOCK``: a block that sees no face is one vectorised fill of NaN."""
    k = lo
    while k + np.uint64(BLOCK) <= hi:
        if _background(iflat, k):
            o = np.uint64(3) * k
            for q in range(3 * BLOCK):
                nflat[o + np.uint64(q)] = nan
        else:
            for q in range(BLOCK):
                _flat_pixel(iflat, nflat, k + np.uint64(q), world_normals, r, nan)
        k += np.uint64(BLOCK)
    for p in range(k, hi):
        _flat_pixel(iflat, nflat, p, world_normals, r, nan)


@kernel(inline="always")
def _smooth_pixel(iflat, nflat, p, px, py, faces, bary, vertex_normals, rotation, nan):
    """Pixel ``p`` (flat index; raster centre (px, py)) of smooth normals."""
    f = iflat[p]
    o = np.uint64(3) * p
    if f >= 0:
        x, y, z = _smooth_normal(f, px, py, faces, bary, vertex_normals)
        cx, cy, cz = _to_camera(rotation, x, y, z)
        nflat[o], nflat[o + np.uint64(1)], nflat[o + np.uint64(2)] = cx, cy, cz
    else:
        nflat[o] = nflat[o + np.uint64(1)] = nflat[o + np.uint64(2)] = nan


@kernel(inline="always")
def _smooth_row(iflat, lo, hi, py, nflat, faces, bary, vertex_normals, rotation, nan):
    """Pixels ``lo`` to ``hi`` (flat indices) of row ``py - 0.5``: vertex normals interpolated
    at each pixel centre, in blocks like :func:`_flat_row`."""
    k = lo
    while k + np.uint64(BLOCK) <= hi:
        if _background(iflat, k):
            o = np.uint64(3) * k
            for q in range(3 * BLOCK):
                nflat[o + np.uint64(q)] = nan
        else:
            for q in range(BLOCK):
                p = k + np.uint64(q)
                _smooth_pixel(iflat, nflat, p, np.float64(p - lo) + 0.5, py, faces, bary, vertex_normals,
                              rotation, nan)
        k += np.uint64(BLOCK)
    for p in range(k, hi):
        _smooth_pixel(iflat, nflat, p, np.float64(p - lo) + 0.5, py, faces, bary, vertex_normals, rotation, nan)


@kernel(inline="always")
def _object_pixel(iflat, oflat, p, face_object, object_first):
    """Pixel ``p``'s object id, and its id made the index within that object."""
    f = iflat[p]
    if f < 0:
        oflat[p] = -1
    else:
        o = face_object[f]
        oflat[p] = o
        iflat[p] = f - object_first[o]


@kernel(inline="always")
def _object_row(iflat, lo, hi, oflat, face_object, object_first):
    """Pixels ``lo`` to ``hi`` of object ids, in blocks like :func:`_flat_row`."""
    k = lo
    while k + np.uint64(BLOCK) <= hi:
        if _background(iflat, k):
            for q in range(BLOCK):
                oflat[k + np.uint64(q)] = -1
        else:
            for q in range(BLOCK):
                _object_pixel(iflat, oflat, k + np.uint64(q), face_object, object_first)
        k += np.uint64(BLOCK)
    for p in range(k, hi):
        _object_pixel(iflat, oflat, p, face_object, object_first)


@kernel(refcounts=False)
def surface_maps(slot, counter, ids, maps):
    """Per pixel of ``ids`` (H, W) int32 (the visible face, -1 for none): the unit camera-space
    normal and the scene object, as a :class:`rasterkit.kernels.records.Maps` asks.

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
    ``maps.object_first[o]``, its first face).

    A worker of :func:`rasterkit._jit.run_workers` over ``N_CHUNKS`` pieces of rows. Face
    indices in ``ids`` must lie in 0..M-1 (a render's ids do).
    """
    height, width = ids.shape
    nan = np.float32(np.nan)
    # the record's fields as locals: read through the record inside the loop, every access
    # would count a reference (an atomic operation) on the array
    want_normals, smooth, want_objects = maps.want_normals, maps.smooth, maps.want_objects
    normals, faces, bary = maps.normals, maps.faces, maps.bary
    vertex_normals, world_normals, rotation = maps.vertex_normals, maps.world_normals, maps.rotation
    object_ids, face_object, object_first = maps.object_ids, maps.face_object, maps.object_first
    iflat, nflat, oflat = ids.reshape(ids.size), normals.reshape(normals.size), object_ids.reshape(object_ids.size)
    r = rotation.reshape(9)
    flat = want_normals and not smooth
    w = np.uint64(width)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(np.uint64(height * ch // N_CHUNKS), np.uint64(height * (ch + 1) // N_CHUNKS)):
            lo = w * j
            # one loop per case: no test of the choices per pixel
            if flat:
                _flat_row(iflat, lo, lo + w, nflat, world_normals, r, nan)
            elif want_normals:
                _smooth_row(iflat, lo, lo + w, np.float64(j) + 0.5, nflat, faces, bary, vertex_normals,
                            rotation, nan)
            if want_objects:
                _object_row(iflat, lo, lo + w, oflat, face_object, object_first)
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
