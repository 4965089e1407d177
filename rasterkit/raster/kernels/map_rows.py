"""The rows of a vision pipeline's images, made from a render's face ids and depths: camera-space
normals, the scene object seen at each pixel, the metric depth (:mod:`rasterkit.raster.vision`).

The band worker (:func:`rasterkit.raster.kernels.bands.draw_bands`) makes them with
:func:`band_maps` right after it resolved a band, while the band is in its cache; the passes
of :mod:`rasterkit.raster.kernels.maps` make them for the other renders. A render that asks for none
compiles none of this: its band worker gets ``maps=None``, and Numba prunes the call.
"""

import numpy as np

from rasterkit.runtime.jit import kernel

#: Pixels tested at once for a face: a block that sees none (the background, most of many
#: frames) is written with vector stores, without a test per pixel.
BLOCK = 16


@kernel(inline="always")
def _smooth_normal(f, px, py, faces, bary, vertex_normals):
    """Vertex normals of face ``f`` interpolated perspective-correctly at raster (px, py),
    unnormalised (the barycentrics of :func:`rasterkit.raster.kernels.shade.bary_matrices`, which
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
def _normal_pixel(smooth, iflat, nflat, p, px, py, world_normals, r, faces, bary, vertex_normals, rotation, nan):
    """Pixel ``p`` (raster centre (px, py)) of smooth or flat normals."""
    if smooth:
        _smooth_pixel(iflat, nflat, p, px, py, faces, bary, vertex_normals, rotation, nan)
    else:
        _flat_pixel(iflat, nflat, p, world_normals, r, nan)


@kernel(inline="always")
def _normals_row(smooth, iflat, lo, hi, py, nflat, world_normals, r, faces, bary, vertex_normals, rotation, nan):
    """Pixels ``lo`` to ``hi`` (flat indices) of row ``py - 0.5`` of normals, smooth (the
    vertex normals interpolated at each pixel centre) or flat (each face's), in blocks of
    ``BLOCK``: a block that sees no face is one vectorised fill of NaN. (``smooth`` is the
    same for the whole row: LLVM takes the test out of the loop.)"""
    k = lo
    while k + np.uint64(BLOCK) <= hi:
        if _background(iflat, k):
            o = np.uint64(3) * k
            for q in range(3 * BLOCK):
                nflat[o + np.uint64(q)] = nan
        else:
            for q in range(BLOCK):
                p = k + np.uint64(q)
                _normal_pixel(smooth, iflat, nflat, p, np.float64(p - lo) + 0.5, py, world_normals, r, faces, bary,
                              vertex_normals, rotation, nan)
        k += np.uint64(BLOCK)
    for p in range(k, hi):
        _normal_pixel(smooth, iflat, nflat, p, np.float64(p - lo) + 0.5, py, world_normals, r, faces, bary,
                      vertex_normals, rotation, nan)


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
    """Pixels ``lo`` to ``hi`` of object ids, in blocks like :func:`_normals_row`."""
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


@kernel(inline="always")
def _uv_pixel(iflat, uflat, p, px, py, bary, corner_uv, nan):
    """Pixel ``p`` (raster centre (px, py)) of texture coordinates: its face's corner UVs
    interpolated perspective-correctly (the barycentrics of
    :func:`rasterkit.raster.kernels.shade.bary_matrices`, normalised to sum 1); NaN for no
    face or a face without UVs."""
    f = iflat[p]
    o = np.uint64(2) * p
    if f < 0:
        uflat[o] = uflat[o + np.uint64(1)] = nan
        return
    b0 = bary[f, 0] * px + bary[f, 1] * py + bary[f, 2]
    b1 = bary[f, 3] * px + bary[f, 4] * py + bary[f, 5]
    b2 = bary[f, 6] * px + bary[f, 7] * py + bary[f, 8]
    s = 1.0 / (b0 + b1 + b2)
    uflat[o] = (b0 * corner_uv[f, 0] + b1 * corner_uv[f, 2] + b2 * corner_uv[f, 4]) * s
    uflat[o + np.uint64(1)] = (b0 * corner_uv[f, 1] + b1 * corner_uv[f, 3] + b2 * corner_uv[f, 5]) * s


@kernel(inline="always")
def _uv_row(iflat, lo, hi, py, uflat, bary, corner_uv, nan):
    """Pixels ``lo`` to ``hi`` of texture coordinates, in blocks like :func:`_normals_row`."""
    k = lo
    while k + np.uint64(BLOCK) <= hi:
        if _background(iflat, k):
            o = np.uint64(2) * k
            for q in range(2 * BLOCK):
                uflat[o + np.uint64(q)] = nan
        else:
            for q in range(BLOCK):
                p = k + np.uint64(q)
                _uv_pixel(iflat, uflat, p, np.float64(p - lo) + 0.5, py, bary, corner_uv, nan)
        k += np.uint64(BLOCK)
    for p in range(k, hi):
        _uv_pixel(iflat, uflat, p, np.float64(p - lo) + 0.5, py, bary, corner_uv, nan)


@kernel(inline="always")
def map_fields(maps):
    """The record's fields as locals (every access through the record inside a loop would
    count a reference, an atomic operation, in a kernel with reference counts)."""
    return (maps.want_normals and not maps.smooth, maps.want_normals, maps.want_objects, maps.normals,
            maps.world_normals, maps.rotation, maps.faces, maps.bary, maps.vertex_normals, maps.object_ids,
            maps.face_object, maps.object_first, maps.want_uv, maps.uv, maps.corner_uv)


@kernel(inline="always")
def surface_row(iflat, j, w, fields, nan):
    """Row ``j`` (``w`` pixels) of the normals, object ids and texture coordinates that
    ``fields`` (:func:`map_fields`) ask for, from the face ids ``iflat`` (flat)."""
    (flat, want_normals, want_objects, normals, world_normals, rotation, faces, bary, vertex_normals,
     object_ids, face_object, object_first, want_uv, uv, corner_uv) = fields
    nflat, oflat = normals.reshape(normals.size), object_ids.reshape(object_ids.size)
    lo = w * j
    py = np.float64(j) + 0.5
    if want_normals:
        _normals_row(not flat, iflat, lo, lo + w, py, nflat, world_normals, rotation.reshape(9),
                     faces, bary, vertex_normals, rotation, nan)
    if want_uv:
        _uv_row(iflat, lo, lo + w, py, uv.reshape(uv.size), bary, corner_uv, nan)
    if want_objects:
        _object_row(iflat, lo, lo + w, oflat, face_object, object_first)


@kernel(refcounts=False)
def band_maps(ids, y0, y1, maps, band_depth, drawn):
    """The maps of image rows ``y0 .. y1 - 1``, made by the band worker
    (:func:`rasterkit.raster.kernels.bands.draw_bands`) right after it resolved them, while their
    ids and depths are in its cache: normals and object ids as
    :func:`rasterkit.raster.kernels.maps.surface_maps` makes them from ``ids`` (H, W) int32, and (``maps.want_depth``) the metric depth of the band's
    depths ``band_depth`` (its rows, first row ``y0``; not read unless ``drawn``: a band
    without faces is 0), as :func:`rasterkit.raster.kernels.maps.metric_depth` makes it."""
    nan = np.float32(np.nan)
    fields = map_fields(maps)
    want_depth, metric, near, far, perspective = maps.want_depth, maps.metric, maps.near, maps.far, maps.perspective
    surface = maps.want_normals or maps.want_objects or maps.want_uv
    iflat = ids.reshape(ids.size)
    w = np.uint64(band_depth.shape[1])
    for j in range(np.uint64(y0), np.uint64(y1)):
        if surface:
            surface_row(iflat, j, w, fields, nan)
        if want_depth:
            out = metric[j]
            if drawn:
                metric_run(band_depth[j - np.uint64(y0)], out, np.uint64(0), w, near, far, perspective)
            else:
                for i in range(w):
                    out[i] = 0.0


@kernel(inline="always")
def metric_of(depth, near, far, perspective):
    """The distance along the optical axis (float32) of the depth buffer's value ``depth``, in
    float64: ``f·n / (f - D·(f - n))`` for a perspective camera, ``n + D·(f - n)`` for a
    parallel one; 0 where ``D`` is +inf (nothing drawn)."""
    d = np.float64(depth)
    value = far * near / (far - d * (far - near)) if perspective else near + d * (far - near)  # noqa: FURB136
    return np.float32(value if d < np.inf else 0.0)  # noqa: FURB136


@kernel(inline="always")
def metric_run(dflat, oflat, lo, hi, near, far, perspective):
    """Elements ``lo .. hi - 1`` of :func:`rasterkit.raster.kernels.maps.metric_depth` (unsigned indices: no wraparound
    tests, vectorised)."""
    for k in range(lo, hi):
        oflat[k] = metric_of(dflat[k], near, far, perspective)
