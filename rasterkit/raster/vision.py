"""The images a computer-vision pipeline reads from a render: metric depth, camera-space
normals, object ids, the visible faces, and their files.

:class:`rasterkit.Framebuffer`'s ``camera_depth``, ``visible_faces`` and ``save_*`` methods
and :func:`rasterkit.render`'s ``normals=True`` and scene ``ids=True`` come here.

Depth
    The depth buffer stores, for a perspective camera, ``D = f·(d - n) / (d·(f - n))`` (0 on
    the near plane ``n``, 1 on the far plane ``f``, +inf where nothing was drawn; OpenGL's
    window depth for the same matrices), with ``d`` the distance along the optical axis;
    a parallel camera stores ``D = (d - n)/(f - n)``. :func:`camera_depth` inverts this in
    float64, ``d = f·n / (f - D·(f - n))``, from the float32 ``D``: no further rounding than
    the depth buffer's own (relative error about ``d·(f - n)/(f·n)·6e-8``: 3e-6 at
    ``d = 5`` with ``n = 0.1``, ``f = 100``). In the modes that draw edges over faces
    (hidden, solid+wire) the faces were pushed back by the polygon offset.
"""

from __future__ import annotations

import math
import numbers
import os
import struct
from pathlib import Path

import numpy as np

from rasterkit.image import png as _png
from rasterkit.runtime import scratch as _memory
from rasterkit.image.atomic import atomic_write
from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers

__all__ = ["camera_depth", "fill_maps", "finish_maps", "maps_record", "save_depth", "save_ids", "save_normals",
           "visible_faces"]

#: Scale of a 16-bit depth PNG: the value is the depth times this, rounded (millimetres
#: when the world unit is the metre); 0 where nothing was drawn, 65535 at 65.535 m and beyond.
DEPTH_PNG_SCALE = 1000.0

#: Passes over fewer pixels (and faces) than this make the maps and the camera depth on the
#: calling thread alone: handing a pass to another thread costs about 15 microseconds (much
#: more on a busy machine), as much as this many pixels.
_PARALLEL_PIXELS = 32_768


def _threads(items: int):
    """The ``threads`` of a pass over ``items`` pixels and faces: 1 for a small one, else all."""
    return 1 if items < _PARALLEL_PIXELS else None


def camera_depth(depth: np.ndarray, camera) -> np.ndarray:
    """(H, W) float32 distance along the optical axis, world units, 0 where nothing was drawn
    (see the module docstring); ``depth`` the (H, W) float32 depth buffer of ``camera``."""
    from rasterkit.raster.kernels.maps import metric_depth

    out = _memory.take(depth.shape, np.float32)
    run_workers(metric_depth, np.ascontiguousarray(depth), out, float(camera.near), float(camera.far),
                camera.kind == "perspective", threads=_threads(depth.size))
    return out


def maps_record(height: int, width: int, mesh, camera, matrix, normals: str | None, object_faces,
                want_depth: bool = False, want_uv: bool = False):
    """The :class:`rasterkit.raster.kernels.records.Maps` of an (H, W) render of ``mesh`` (world
    space) seen through ``matrix`` (world -> raster) by ``camera``, with its output arrays:
    normals (``normals``: 'flat' per face, 'smooth' interpolated, None: not), object ids for
    a scene (``object_faces``: the number of faces of each object, in order; None: not),
    (``want_depth``) the metric depth and (``want_uv``) the texture coordinates."""
    from rasterkit.raster.kernels.records import Maps
    from rasterkit.raster.normals import vertex_normals
    from rasterkit.raster.kernels.shade import bary_matrices
    from rasterkit.raster.vertex import transform_points

    rotation = np.ascontiguousarray(camera.rotation())  # rows u, v, w: world -> camera
    smooth = normals in ("smooth", "phong")
    world_normals, vertex, bary = readonly(np.zeros((0, 3), np.float32)), np.zeros((0, 3)), np.zeros((0, 9))
    if smooth or want_uv:
        bary = bary_matrices(transform_points(mesh.vertices, matrix), mesh.faces)
    if smooth:
        world = mesh.normals if mesh.normals is not None else vertex_normals(mesh.vertices, mesh.faces)
        vertex = np.ascontiguousarray(world, np.float64)
    elif normals:  # turned into camera space per pixel by the kernel
        world_normals = readonly(mesh.face_normals)  # one compiled kernel: read-only either way
    out_normals = _memory.take((height, width, 3), np.float32) if normals else np.empty((0, 0, 3), np.float32)
    objects = object_faces is not None
    if objects:
        counts = np.asarray(object_faces, np.int64)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        face_object = np.repeat(np.arange(len(counts), dtype=np.int32), counts)
    else:
        first, face_object = np.zeros(0, np.int64), np.zeros(0, np.int32)
    object_ids = _memory.take((height, width), np.int32) if objects else np.empty((0, 0), np.int32)
    metric = _memory.take((height, width), np.float32) if want_depth else np.empty((0, 0), np.float32)
    uv = _memory.take((height, width, 2), np.float32) if want_uv else np.empty((0, 0, 2), np.float32)
    corners = corner_uv(mesh) if want_uv else np.zeros((0, 6))
    return Maps(normals is not None, out_normals, smooth, world_normals, vertex, bary, mesh.faces, rotation,
                objects, object_ids, face_object, first, bool(want_depth), metric, float(camera.near),
                float(camera.far), camera.kind == "perspective", bool(want_uv), uv, corners)


def corner_uv(mesh) -> np.ndarray:
    """(M, 6) float64: the texture coordinates (u0, v0, u1, v1, u2, v2) of each face's corners,
    NaN for a face without: per corner where the mesh has them (``uv`` and ``uv_index``), else
    its per-vertex ``texcoords``, else NaN everywhere."""
    m = len(mesh.faces)
    table, index = mesh.uv, mesh.uv_index
    if table is None:
        if mesh.texcoords is None:
            return np.full((m, 6), np.nan)
        table, index = mesh.texcoords[:, :2], mesh.faces
    table = np.asarray(table, np.float64)
    rows = np.concatenate([table, np.full((1, 2), np.nan)])  # index -1: the last row, NaN
    return np.ascontiguousarray(rows[np.asarray(index)].reshape(m, 6))


def finish_maps(fb, maps) -> None:
    """Hand ``maps`` (:func:`maps_record`, made) to ``fb``: ``fb.normals``, for a scene
    ``fb.object_ids`` (``fb.ids`` are indices within each object by now), and the metric
    depth that :meth:`rasterkit.Framebuffer.camera_depth` returns."""
    fb.normals = maps.normals if maps.want_normals else None
    fb.uv = maps.uv if maps.want_uv else None
    if maps.want_objects:
        fb.object_ids, fb.object_first = maps.object_ids, maps.object_first
    if maps.want_depth:
        fb.keep_camera_depth(maps.metric)


def fill_maps(fb, mesh, camera, matrix, normals: str | None, object_faces, want_uv: bool = False) -> None:
    """Fill ``fb.normals`` (``normals``: 'flat' per face, 'smooth' interpolated, None: not)
    and, for a scene (``object_faces``: the number of faces of each object, in order),
    ``fb.object_ids``, turning ``fb.ids`` into indices within each object; from ``fb.ids``,
    the faces of ``mesh`` (world space) seen through ``matrix``: a pass of its own, for the
    renders whose band worker does not make them (:func:`rasterkit.raster.kernels.maps.band_maps`)."""
    from rasterkit.raster.kernels.maps import surface_maps

    height, width = fb.ids.shape
    maps = maps_record(height, width, mesh, camera, matrix, normals, object_faces, want_uv=want_uv)
    run_workers(surface_maps, fb.ids, maps, threads=_threads(height * width))
    finish_maps(fb, maps)


def visible_faces(ids: np.ndarray, object_ids, object_first) -> tuple[np.ndarray, np.ndarray]:
    """(face_ids, pixel_counts), int64 each, face ids ascending: the faces seen and their
    pixels. For a scene, a face's index is its index in the scene's world mesh (the objects'
    faces one after another)."""
    faces = ids.reshape(-1).astype(np.int64)
    if object_ids is not None:
        objects = object_ids.reshape(-1)
        faces = np.where(objects >= 0, faces + object_first[np.maximum(objects, 0)], -1)
    counts = np.bincount(faces[faces >= 0])
    seen = np.flatnonzero(counts)
    return seen, counts[seen]


def _png16(gray: np.ndarray) -> bytes:
    """A 16-bit greyscale PNG of a uint16 (H, W) array."""
    height, width = gray.shape
    rows = np.ascontiguousarray(gray.astype(">u2")).view(np.uint8).reshape(height, width, 2)
    ihdr = _png.chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0))
    idat = b"".join(_png.chunk(b"IDAT", p) for p in _png.pieces(_png.compressed(rows)))
    return _png.SIGNATURE + ihdr + idat + _png.chunk(b"IEND", b"")


def _write(path, array: np.ndarray, png) -> None:
    """``array`` to ``.npy``, or ``png()``'s bytes to ``.png``, atomically."""
    suffix = Path(path).suffix  # ``path`` itself goes on: "d.npy/" names a folder, not d.npy
    ext = suffix.lower()
    if ext not in (".npy", ".png"):
        raise ValueError(f"{os.fspath(path)}: unsupported extension {suffix!r} (use .png or .npy)")
    if ext == ".npy":
        from rasterkit.image.files import save_npy

        save_npy(array, path)
        return
    data = png()
    with atomic_write(path) as tmp:
        tmp.write_bytes(data)


def save_depth(depth: np.ndarray, path: str | os.PathLike, scale: float = DEPTH_PNG_SCALE) -> None:
    """Metric depth ``(H, W) float32`` (0: nothing drawn) to ``.npy`` as it is, or to a 16-bit
    greyscale ``.png`` of ``round(depth·scale)`` (millimetres for metres by default) clipped
    to 65535. ``scale`` is a finite number above 0 (ValueError otherwise)."""
    if isinstance(scale, bool) or not isinstance(scale, numbers.Real) or not math.isfinite(scale) or scale <= 0:
        raise ValueError(f"scale must be a finite number above 0, got {scale!r}")
    _write(path, depth, lambda: _png16(np.clip(np.rint(depth.astype(np.float64) * scale), 0, 65535)
                                        .astype(np.uint16)))


def save_normals(normals: np.ndarray, path: str | os.PathLike) -> None:
    """Unit normals (H, W, 3) float32 (NaN: nothing drawn) to ``.npy`` as they are, or to an
    RGB ``.png`` of ``(n + 1)/2·255`` rounded (nothing drawn: black)."""
    from rasterkit.image.files import encode_png

    def png():
        rgb = np.rint((np.nan_to_num(normals, nan=-1.0) + 1.0) * 127.5)
        return encode_png(np.clip(rgb, 0, 255).astype(np.uint8))

    _write(path, normals, png)


def save_ids(ids: np.ndarray, path: str | os.PathLike) -> None:
    """Ids (H, W) int32 (-1: none) to ``.npy`` as they are, or to a 16-bit greyscale ``.png``
    of ``id + 1`` (0: none; ids up to 65534, ValueError beyond)."""
    def png():
        if ids.size and int(ids.max()) > 65534:
            raise ValueError(f"{path}: ids up to {int(ids.max())} do not fit a 16-bit PNG (use .npy)")
        return _png16((ids.astype(np.int64) + 1).astype(np.uint16))

    _write(path, ids, png)
