"""Validated entry point to the triangle pipeline: clip -> cull -> bin -> rasterize -> resolve.

:func:`rasterize_triangles` checks every input once and then hands the draw to the triangle
path's driver (:mod:`rasterkit.raster.triangle_pass`), which runs the kernels; the renderer calls it
with the vertices already in homogeneous raster space.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.runtime.jit import readonly
from rasterkit.raster.draw_checks import (check_array, check_buffer, check_colors, check_cull, check_depth,
                                          check_depth_offset, check_geometry, check_size, thread_count)
from rasterkit.raster.triangle_pass import Lighting, draw_triangles

__all__ = ["FlatLambert", "TriangleStats", "rasterize_triangles"]


@dataclass(frozen=True)
class TriangleStats:
    """What happened to the faces of one :func:`rasterize_triangles` call.

    Every face is counted in exactly one of ``drawn``, ``culled``, ``empty``, ``outside``
    and ``dropped_nonfinite`` (they add up to ``faces``); ``clipped`` counts the faces,
    among those, that were cut by the near, far or guard-band planes with something left.

    Attributes
    ----------
    faces : int
        Faces submitted.
    drawn : int
        Faces with at least one triangle sent to the rasterizer (it may still lose every
        depth test).
    culled : int
        Faces removed by backface culling.
    empty : int
        Faces of zero area after snapping to 1/256 pixel, or covering no pixel centre.
    outside : int
        Faces wholly outside the view volume (beside the image, before near, beyond far).
    dropped_nonfinite : int
        Faces with a NaN or infinite vertex coordinate.
    clipped : int
        Faces cut by a clipping plane (and not wholly removed).
    triangles : int
        Triangles rasterized (a cut face can become up to 7).
    fragments : int
        Covered pixel centres that reached the depth test.
    """

    faces: int
    drawn: int
    culled: int
    empty: int
    outside: int
    dropped_nonfinite: int
    clipped: int
    triangles: int
    fragments: int


@dataclass(frozen=True, eq=False)
class FlatLambert:
    """Face colours for :func:`rasterize_triangles` that it computes itself: per face,
    Lambert's law under a distant light, for the faces that can be seen only.

    Equal, face for face, to ``face_colors=rasterkit.raster.kernels.shade.flat_packed(...)`` of the
    positions the normals come from, but worked out during the face setup and skipped for
    the faces culled, outside or empty (half of a closed mesh is back-facing): a renderer
    saves a pass over every face. The normals depend on the mesh only, not on the camera:
    :attr:`rasterkit.Mesh.face_normals` works them out once per mesh.

    Attributes
    ----------
    normals : (M, 3) float32
        Unit face normals in the space of ``light`` (world space), one per face
        (:attr:`rasterkit.Mesh.face_normals`); a zero or non-finite one gets the ambient
        term only.
    base : (1, 3) or (M, 3) float32
        Surface colour(s), times ``scale`` in 0..255.
    light : (3,) float64
        Unit direction towards the light.
    ambient : float
        Fraction of the colour that unlit faces keep.
    two_sided : bool or (M,) bool
        Light both sides of a face (``|cos|``), else only the front; for every face or each.
    scale : float
        Multiplies ``base`` (255 for colours in [0, 1]).
    """

    normals: np.ndarray
    base: np.ndarray
    light: np.ndarray
    ambient: float = 0.25
    two_sided: bool = False
    scale: float = 1.0


def _lighting(flat: FlatLambert, faces, trusted=False) -> Lighting:
    """The terms of ``flat``, validated against the ``faces`` (M, 3); ``trusted``: made by
    render() from a checked light, only its arrays are checked."""
    m = faces.shape[0]
    check_array("normals", flat.normals, np.float32, 2)
    if flat.normals.shape != (m, 3):
        raise ValueError(f"normals must have shape ({m}, 3), got {flat.normals.shape}")
    check_array("base", flat.base, np.float32, 2)
    if flat.base.shape not in ((1, 3), (m, 3)):
        raise ValueError(f"base must have shape (1, 3) or ({m}, 3), got {flat.base.shape}")
    if trusted:
        return Lighting(readonly(flat.normals), readonly(flat.base), np.float32(flat.scale), readonly(flat.light),
                        float(flat.ambient), _two_sided(flat.two_sided, m))
    light = readonly(np.ascontiguousarray(flat.light, np.float64))
    if light.shape != (3,) or not np.all(np.isfinite(light)):
        raise ValueError(f"light must be 3 finite numbers, got {flat.light!r}")
    ambient, scale = float(flat.ambient), float(flat.scale)
    if not (np.isfinite(ambient) and np.isfinite(scale)):
        raise ValueError("ambient and scale must be finite")
    return Lighting(readonly(flat.normals), readonly(flat.base), np.float32(scale), light, ambient,
                    _two_sided(flat.two_sided, m))


def _two_sided(value, m: int):
    """``FlatLambert.two_sided`` as the face pass takes it: a bool, or (M,) bool per face."""
    if not isinstance(value, np.ndarray):
        return bool(value)
    if value.shape != (m,):
        raise ValueError(f"two_sided must be a bool or ({m},) bools, got shape {value.shape}")
    return readonly(np.ascontiguousarray(value, bool))


def shading_mode(color, face_colors, vertex_colors, faces, clip):
    """The colours checked: ``(face_colors, vertex_colors, lighting)``, None for each that
    the draw does not use (all three without ``color``)."""
    if face_colors is not None and vertex_colors is not None:
        raise ValueError("give face_colors or vertex_colors, not both")
    if color is None:
        if face_colors is not None or vertex_colors is not None:
            raise ValueError("colours were given but color is None")
        return None, None, None
    if vertex_colors is not None:
        check_colors("vertex_colors", vertex_colors, clip.shape[0], "vertex")
        return None, vertex_colors, None
    if face_colors is None:
        raise ValueError("color needs face_colors or vertex_colors (or pass color=None for depth only)")
    if isinstance(face_colors, FlatLambert):
        return None, None, _lighting(face_colors, faces)
    if isinstance(face_colors, np.ndarray) and face_colors.dtype == np.uint32:
        check_array("face_colors", face_colors, np.uint32, 1)
        if face_colors.shape != (faces.shape[0],):
            raise ValueError(f"packed face_colors must have shape ({faces.shape[0]},), got {face_colors.shape}")
        return face_colors, None, None
    check_colors("face_colors", face_colors, faces.shape[0], "face")
    return face_colors, None, None


def check_corners(corners, faces, vertex_colors):
    """``corners`` as (M, 3) int64 rows of ``vertex_colors`` (K, 3), one per face corner."""
    check_array("corners", corners, np.int64, 2)
    if corners.shape != faces.shape:
        raise ValueError(f"corners must have the faces' shape {faces.shape}, got {corners.shape}")
    if vertex_colors is None:
        raise ValueError("corners index vertex_colors: give both")
    if corners.size and not 0 <= corners.min() <= corners.max() < len(vertex_colors):
        raise ValueError(f"corners must be rows 0..{len(vertex_colors) - 1} of vertex_colors")
    return corners


def background_bytes(clear, color):
    """The clear colour as a (C,) uint8 array (empty without a colour buffer), or None."""
    if clear is None:
        return None
    channels = 0 if color is None else color.shape[2]
    if isinstance(clear, (tuple, list)):  # the common case, without a NumPy round trip
        values = tuple(clear)
    elif np.ndim(clear) == 1:
        values = tuple(np.asarray(clear))
    else:
        values = None
    if values is None or len(values) != channels \
            or not all(isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_)) for v in values):
        raise ValueError(f"clear must be {channels} integers 0..255 (one per colour channel), got {clear!r}")
    if not all(0 <= v <= 255 for v in values):
        raise ValueError(f"clear values must be in 0..255, got {clear!r}")
    return np.array(values, np.uint8)


def rasterize_triangles(
    color,
    depth,
    clip,
    faces,
    *,
    face_colors=None,
    vertex_colors=None,
    ids=None,
    cull="back",
    clear=None,
    depth_offset=(0.0, 0.0),
    threads=None,
):
    """Draw triangles into colour, depth and (optionally) id buffers.

    Runs clip (near/far planes, guard band) -> backface cull -> bin into bands ->
    rasterize (top-left rule, 8 sub-pixel bits, less-than depth test) -> colour.

    Parameters
    ----------
    color : (H, W, C) uint8 or None
        Colour buffer, C = 3 (RGB) or 4 (RGBA: drawn pixels get alpha 255). None draws
        depth (and ids) only.
    depth : (H, W) float32 or None
        Depth buffer (cleared to +inf); a pixel is drawn when its depth ``z = zh / w`` is
        less than the stored one, which it then replaces. None (with ``color``): the depth
        test runs in a band-sized buffer per thread and no depth is kept, which saves
        writing an image-sized buffer to memory; the colours are the same.
    clip : (N, 4) float64
        Vertices in homogeneous raster space ``(xh, yh, zh, w)``: ``xh / w, yh / w`` are
        raster pixels, ``zh / w`` is the depth; inside the view volume ``0 <= zh <= w``.
        Faces using a NaN or infinite vertex are dropped (and counted).
    faces : (M, 3) int64
        Vertex indices, counter-clockwise seen from the front (right-handed world).
    face_colors : (M, 3) float32, (M,) uint32 or FlatLambert, optional
        Flat shading: RGB 0..255 per face (rounded, clamped to 0..255), or packed opaque
        RGBA per face, R in the low byte (``R | G << 8 | B << 16 | A << 24``; A is written
        only to an RGBA buffer), or a :class:`FlatLambert` to have the Lambert colours
        computed during the setup, for the visible faces only.
    vertex_colors : (N, 3) float32, optional
        Smooth (Gouraud) shading: RGB 0..255 per vertex, interpolated perspective-correctly.
        Exactly one of ``face_colors`` and ``vertex_colors`` is needed when ``color`` is
        given.
    ids : (H, W) int32, optional
        Receives the index of the face visible at each drawn pixel.
    cull : {"back", "front", "none"} or (M,) uint8
        Which faces to remove; front faces wind counter-clockwise on screen. Or a choice
        per face, as codes of :data:`rasterkit.raster.triangle_pass.CULL_CODES` (the faces
        of double-sided materials: :mod:`rasterkit.raster.sides`).
    clear : sequence of int, optional
        Clear the buffers first: colour to this value (C integers 0..255; ``()`` when
        ``color`` is None), depth to +inf, ids to -1. Done band by band in the drawing
        threads, it costs far less than clearing before the call.
    depth_offset : (float, float)
        ``(factor, units)``: every triangle is pushed back by
        ``factor * max(|dz/dx|, |dz/dy|) + units`` (depth units, slopes per pixel) before the
        depth test, like OpenGL's polygon offset, so that lines drawn over the faces
        afterwards survive the depth test. Default no offset.
    threads : int, optional
        Threads to use (default: :func:`rasterkit.set_threads`'s setting). The result does
        not depend on it.

    Returns
    -------
    TriangleStats
        Per-face accounting of the call (drawn, culled, clipped, dropped_nonfinite, ...).

    Raises
    ------
    TypeError, ValueError
        For a wrong type, dtype, shape or layout, an index out of range, buffers whose sizes
        disagree, ``faces`` in the memory of a buffer drawn into, non-finite colours, or an
        unknown ``cull`` or ``clear``.
    rasterkit.limits.LimitError
        When the per-face scratch memory would grow beyond
        :func:`rasterkit.limits.memory_limit`.

    Notes
    -----
    Pixels are covered when their centre is inside the triangle, centres on an edge by the
    top-left rule, after snapping vertices to 1/256 pixel; equal depths keep the face
    drawn first (less-than test, faces in order). The image is bit-identical for any
    thread count. Per-face scratch arrays are kept between calls (per Python thread), so
    that repeated draws do not pay for fresh memory.
    """
    return TriangleStats(**rasterize_checked(color, depth, clip, faces, face_colors, vertex_colors, ids, cull, clear,
                                      depth_offset, threads))


def rasterize_checked(color, depth, clip, faces, face_colors, vertex_colors, ids, cull, clear, depth_offset, threads,
               maps=None, transform=None, trusted=False, textures=None, corners=None) -> dict:
    """:func:`rasterize_triangles`'s checks and draw, returning its counts by name, for
    :func:`rasterkit.render`: ``maps``, a vision render's
    (:func:`rasterkit.raster.triangle_pass.draw_prepared`); ``transform``, ``(points, matrix)``
    that the vertex pass makes ``clip`` from (:func:`rasterkit.raster.triangle_pass.prepare`);
    ``trusted``: the buffers are render()'s own, the faces a Mesh's and the colours made by
    render() (checked where they were made): the checks are skipped. Each NumPy call of them
    costs microseconds after a frame has gone through the caches, about 0.1 ms a frame.
    ``textures``: a textured frame's (:func:`rasterkit.raster.texturing.frame_textures`, made
    for these faces); ``corners``: each face corner's row of ``vertex_colors`` (M, 3) int64,
    render()'s own (``trusted``), for a mesh whose corners have their own normals."""
    if trusted:
        lighting = None
        if isinstance(face_colors, FlatLambert):  # its arrays' shapes still checked: a Mesh's
            lighting, face_colors = _lighting(face_colors, faces, trusted=True), None  # normals can be swapped
    else:
        _check_draw(color, depth, ids, clip, faces, cull)
        face_colors, vertex_colors, lighting = shading_mode(color, face_colors, vertex_colors, faces, clip)
        depth_offset = check_depth_offset(depth_offset)
    return draw_triangles(color, depth, clip, faces, face_colors, vertex_colors, ids, cull, background_bytes(clear, color),
                          depth_offset, threads=thread_count(threads), lighting=lighting, maps=maps, transform=transform,
                          textures=textures, color_index=corners if trusted else None)


def _check_draw(color, depth, ids, clip, faces, cull):
    """The buffers, geometry and cull choice of a :func:`rasterize_triangles` call."""
    if depth is not None:
        check_depth(depth)
        height, width = depth.shape
    elif color is None:
        raise ValueError("depth can be None only when color is given")
    if color is not None:
        check_array("color", color, np.uint8, 3)
        if color.shape[2] not in (3, 4):
            raise ValueError(f"color must have 3 or 4 channels, got shape {color.shape}")
        if depth is None:  # the image size comes from the colour buffer
            height, width = color.shape[:2]
            check_size(height, width)
        check_buffer("color", color, np.uint8, (height, width, color.shape[2]))
    if ids is not None:
        check_buffer("ids", ids, np.int32, (height, width))
    check_geometry(clip, faces)
    for name, buffer in (("color", color), ("depth", depth), ("ids", ids)):
        # faces are read again after the draw has written into its buffers: never through them
        if buffer is not None and np.may_share_memory(faces, buffer):
            raise ValueError(f"faces must not share memory with {name}, the buffer drawn into")
    check_cull(cull, faces.shape[0])
