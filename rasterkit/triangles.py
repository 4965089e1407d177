"""Validated entry point to the triangle pipeline: clip -> cull -> bin -> rasterize -> resolve.

:func:`rasterize_triangles` checks every input once and then runs the kernels of
:mod:`rasterkit.kernels` (``clip``, ``cull``, ``triangle``, ``tiles``, ``shade``); the
renderer calls it with the vertices already in homogeneous raster space.
"""

from __future__ import annotations

import functools
import math
import threading
from dataclasses import dataclass

import numpy as np

from rasterkit import _jit
from rasterkit._jit import readonly, run_parallel
from rasterkit.kernels.clear import PATTERN_BYTES
from rasterkit.kernels.clip import MAX_IMAGE_SIZE
from rasterkit.kernels.cull import CULL_BACK, CULL_FRONT, CULL_NONE
from rasterkit.kernels.shade import (
    SHADE_FLAT,
    SHADE_NONE,
    SHADE_SMOOTH,
    SHADE_TAGGED,
    all_finite,
    bary_matrices,
    pack_colors,
)
from rasterkit.kernels.tiles import (
    BAND_HEIGHT,
    BAND_SHIFT,
    bin_cursors,
    bin_records,
    draw_bands,
    n_bands,
    slot_rows,
)
from rasterkit.kernels.fans import count_fans, setup_cut_faces
from rasterkit.kernels.setup import (
    MAX_FAN,
    N_CHUNKS,
    N_STATUS,
    STATUS_CULLED,
    STATUS_DRAWN,
    STATUS_EMPTY,
    STATUS_NONFINITE,
    STATUS_OUTSIDE,
    setup_faces,
    setup_vertices,
)
from rasterkit.kernels.triangle import offset_depths

__all__ = ["FlatLambert", "TriangleStats", "rasterize_triangles"]

_CULL_MODES = {"none": CULL_NONE, "back": CULL_BACK, "front": CULL_FRONT}

# Record indices are int32 in the visibility buffer; a face becomes at most MAX_FAN records.
_MAX_FACES = (2**31 - 1) // (MAX_FAN + 1)


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


def _check_array(name, a, dtype, ndim):
    if not isinstance(a, np.ndarray):
        raise TypeError(f"{name} must be a numpy.ndarray, got {type(a).__name__}")
    if a.dtype != dtype:
        raise TypeError(f"{name} must have dtype {np.dtype(dtype).name}, got {a.dtype}")
    if a.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-dimensional, got shape {a.shape}")
    if not a.flags.c_contiguous:
        raise ValueError(f"{name} must be C-contiguous (use numpy.ascontiguousarray)")


def _check_buffer(name, a, dtype, shape):
    _check_array(name, a, dtype, len(shape))
    if a.shape != shape:
        raise ValueError(f"{name} has shape {a.shape}, expected {shape} to match depth")
    if not a.flags.writeable:
        raise ValueError(f"{name} must be writeable")


def _check_colors(name, colors, rows, what):
    _check_array(name, colors, np.float32, 2)
    if colors.shape != (rows, 3):
        raise ValueError(f"{name} must have shape ({rows}, 3) (one RGB per {what}), got {colors.shape}")
    if not all_finite(colors):
        raise ValueError(f"{name} must be finite")


def _check_geometry(clip, faces):
    _check_array("clip", clip, np.float64, 2)
    if clip.shape[1] != 4:
        raise ValueError(f"clip must have shape (N, 4) (xh, yh, zh, w), got {clip.shape}")
    _check_array("faces", faces, np.int64, 2)
    if faces.shape[1] != 3:
        raise ValueError(f"faces must have shape (M, 3), got {faces.shape}")
    if faces.shape[0] > _MAX_FACES:
        raise ValueError(f"at most {_MAX_FACES} faces per call, got {faces.shape[0]}")
    # The vertex indices are checked by the face pass (setup_faces), which reads them all
    # anyway, before anything is drawn or read through them.


def _check_depth(depth):
    _check_array("depth", depth, np.float32, 2)
    if not depth.flags.writeable:
        raise ValueError("depth must be writeable")
    _check_size(*depth.shape)


def _check_size(height, width):
    if not (1 <= width <= MAX_IMAGE_SIZE and 1 <= height <= MAX_IMAGE_SIZE):
        raise ValueError(f"image size must be 1..{MAX_IMAGE_SIZE} pixels a side, got {width}x{height}")


@dataclass(frozen=True, eq=False)
class FlatLambert:
    """Face colours for :func:`rasterize_triangles` that it computes itself: per face,
    Lambert's law under a distant light, for the faces that can be seen only.

    Equal, face for face, to ``face_colors=rasterkit.kernels.shade.flat_packed(...)`` of the
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
    two_sided : bool
        Light both sides of a face (``|cos|``), else only the front.
    scale : float
        Multiplies ``base`` (255 for colours in [0, 1]).
    """

    normals: np.ndarray
    base: np.ndarray
    light: np.ndarray
    ambient: float = 0.25
    two_sided: bool = False
    scale: float = 1.0

    def _lit(self, faces, packed):
        """The ``lit`` tuple of :func:`rasterkit.kernels.setup.setup_faces`, validated."""
        m = faces.shape[0]
        _check_array("normals", self.normals, np.float32, 2)
        if self.normals.shape != (m, 3):
            raise ValueError(f"normals must have shape ({m}, 3), got {self.normals.shape}")
        _check_array("base", self.base, np.float32, 2)
        if self.base.shape not in ((1, 3), (m, 3)):
            raise ValueError(f"base must have shape (1, 3) or ({m}, 3), got {self.base.shape}")
        light = readonly(np.ascontiguousarray(self.light, np.float64))
        if light.shape != (3,) or not np.all(np.isfinite(light)):
            raise ValueError(f"light must be 3 finite numbers, got {self.light!r}")
        ambient, scale = float(self.ambient), float(self.scale)
        if not (np.isfinite(ambient) and np.isfinite(scale)):
            raise ValueError("ambient and scale must be finite")
        return (True, readonly(self.normals), readonly(self.base), np.float32(scale), light, ambient,
                bool(self.two_sided), packed)


def _no_light(packed):
    """The ``lit`` tuple that computes nothing (same types as a FlatLambert's)."""
    return (False, _NO_NORMALS, _NO_BASE, np.float32(1.0), _NO_LIGHT, 0.0, False, packed)


_NO_NORMALS = readonly(np.zeros((0, 3), np.float32))
_NO_BASE = readonly(np.zeros((1, 3), np.float32))
_NO_LIGHT = readonly(np.zeros(3))


def _shading(color, face_colors, vertex_colors, faces, clip):
    """Pick the resolve mode once for the draw; returns (mode, face_colors, vertex_colors)."""
    if face_colors is not None and vertex_colors is not None:
        raise ValueError("give face_colors or vertex_colors, not both")
    if color is None:
        if face_colors is not None or vertex_colors is not None:
            raise ValueError("colours were given but color is None")
        return SHADE_NONE, np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32)
    if vertex_colors is not None:
        _check_colors("vertex_colors", vertex_colors, clip.shape[0], "vertex")
        return SHADE_SMOOTH, np.zeros((0, 3), np.float32), vertex_colors
    if face_colors is None:
        raise ValueError("color needs face_colors or vertex_colors (or pass color=None for depth only)")
    if isinstance(face_colors, FlatLambert):
        return SHADE_FLAT, face_colors, np.zeros((0, 3), np.float32)
    if isinstance(face_colors, np.ndarray) and face_colors.dtype == np.uint32:
        _check_array("face_colors", face_colors, np.uint32, 1)
        if face_colors.shape != (faces.shape[0],):
            raise ValueError(f"packed face_colors must have shape ({faces.shape[0]},), got {face_colors.shape}")
        return SHADE_FLAT, face_colors, np.zeros((0, 3), np.float32)
    _check_colors("face_colors", face_colors, faces.shape[0], "face")
    return SHADE_FLAT, face_colors, np.zeros((0, 3), np.float32)


def _background(clear, color):
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


def _threads(threads):
    if threads is None:
        return _jit.get_threads()
    limit = _jit.MAX_THREADS
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= limit:
        raise ValueError(f"threads must be an int in 1..{limit} or None, got {threads!r}")
    return int(threads)


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
    cull : {"back", "front", "none"}
        Which faces to remove; front faces wind counter-clockwise on screen.
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
        disagree, non-finite colours, or an unknown ``cull`` or ``clear``.

    Notes
    -----
    Pixels are covered when their centre is inside the triangle, centres on an edge by the
    top-left rule, after snapping vertices to 1/256 pixel; equal depths keep the face
    drawn first (less-than test, faces in order). The image is bit-identical for any
    thread count. Per-face scratch arrays are kept between calls (per Python thread), so
    that repeated draws do not pay for fresh memory.
    """
    if depth is not None:
        _check_depth(depth)
        height, width = depth.shape
    elif color is None:
        raise ValueError("depth can be None only when color is given")
    if color is not None:
        _check_array("color", color, np.uint8, 3)
        if color.shape[2] not in (3, 4):
            raise ValueError(f"color must have 3 or 4 channels, got shape {color.shape}")
        if depth is None:  # the image size comes from the colour buffer
            height, width = color.shape[:2]
            _check_size(height, width)
        _check_buffer("color", color, np.uint8, (height, width, color.shape[2]))
    if ids is not None:
        _check_buffer("ids", ids, np.int32, (height, width))
    _check_geometry(clip, faces)
    faces = readonly(faces)  # as a Mesh's: one compiled kernel for both
    if cull not in _CULL_MODES:
        raise ValueError(f"cull must be one of {sorted(_CULL_MODES)}, got {cull!r}")
    mode, face_colors, vertex_colors = _shading(color, face_colors, vertex_colors, faces, clip)
    offset = _depth_offset(depth_offset)
    background = _background(clear, color)
    return _run(color, depth, clip, faces, mode, face_colors, vertex_colors, ids, _CULL_MODES[cull], background,
                offset, _threads(threads))


class _Workspace(threading.local):
    """Scratch arrays kept between calls, one set per Python thread.

    A draw of a few hundred thousand faces needs tens of megabytes of per-face records;
    allocated afresh each time, the operating system would zero every page again, which
    costs as much as the setup itself. Buffers only grow.
    """

    def __init__(self):
        self._buffers = {}

    def take(self, name, shape, dtype, keep=0):
        """A C-contiguous ``shape`` array of ``dtype``; its first ``keep`` rows are kept
        from the previous ``take`` of the same name (when the buffer has to grow)."""
        size = math.prod(shape)
        buffer = self._buffers.get(name)
        if buffer is None or buffer.dtype != dtype or buffer.size < size:
            grown = np.empty(size + size // 4, dtype)
            if keep and buffer is not None:
                row = size // shape[0]
                grown[: keep * row] = buffer[: keep * row]
            self._buffers[name] = buffer = grown
        return buffer[:size].reshape(shape)

    def visibility(self, slots, width):
        """(slots, slot_rows(width), width) int32, all -1 (draw_bands leaves it so). A
        buffer of more slots is kept, and its first ``slots`` handed out: a caller that
        changes the thread count between draws does not fill a new one each time."""
        rows = slot_rows(width)
        lid = self._buffers.get("lid")
        if lid is None or lid.shape[0] < slots or lid.shape[1:] != (rows, width):
            self._buffers["lid"] = lid = np.full((slots, rows, width), -1, np.int32)
        return lid[:slots]


_WORKSPACE = _Workspace()

#: Draws of fewer faces run their setup passes on the calling thread alone.
_PARALLEL_FACES = 4096


def _records(ws, rows, keep=0):
    """Record arrays ``tri_xy, tri_z, tri_box`` of ``rows`` records, the first ``keep`` kept."""
    return (
        ws.take("tri_xy", (rows, 6), np.int32, keep),
        ws.take("tri_z", (rows, 3), np.float32, keep),
        ws.take("tri_box", (rows, 4), np.int32, keep),
    )


def _clear_spec(background, color):
    """``(clear, color_bytes, pattern)`` as draw_bands takes it."""
    if background is None or color is None:
        return background is not None, _NO_BYTES, _NO_PATTERN
    return True, color.reshape(-1), _pattern(background.tobytes())


_NO_BYTES = np.empty(0, np.uint8)
_NO_PATTERN = readonly(np.empty(0, np.uint8))


@functools.lru_cache(maxsize=64)
def _pattern(background: bytes) -> np.ndarray:
    """The background colour repeated over PATTERN_BYTES bytes (read-only, kept per colour)."""
    pattern = np.tile(np.frombuffer(background, np.uint8), PATTERN_BYTES // len(background))
    pattern.flags.writeable = False
    return pattern


def _parallel(worker, *args, threads):
    """``worker`` on ``threads`` threads, with a fresh work counter."""
    return run_parallel(worker, np.zeros(1, np.int64), *args, threads=threads)


def _set_up(ws, clip, faces, width, height, cull_mode, lit, threads):
    """Vertex pass, face pass and (when needed) the cut faces' fans; binning counted.

    Returns ``(records, n_fan, fan_start, fan_face, band_counts, counts, listed)`` for
    :func:`rasterkit.kernels.tiles.bin_records` and the resolve; ``counts`` (N_STATUS + 1,)
    are the faces per STATUS_* and, last, the faces cut with something left.
    """
    n, m = clip.shape[0], faces.shape[0]
    corners = ws.take("corners", (n, 4), np.int32)
    depths = corners.view(np.float32)  # the same rows: z as float32
    _parallel(setup_vertices, clip, width, height, corners, depths, threads=threads)
    tri_xy, tri_z, tri_box = _records(ws, m)
    cut_mask, n_fan = ws.take("cut_mask", (m,), np.int8), ws.take("n_fan", (m,), np.int8)
    band_counts = np.zeros((N_CHUNKS, n_bands(height)), np.int64)
    tally = np.zeros((N_CHUNKS, N_STATUS + 1), np.int64)
    listed = (ws.take("listed", (m,), np.int32), np.zeros(N_CHUNKS, np.int64))
    cut = np.zeros(N_CHUNKS, np.int64)
    face_pass = (tri_xy, tri_z, tri_box, cut_mask, n_fan, BAND_SHIFT, band_counts, tally, lit, listed, cut)
    _parallel(setup_faces, faces, corners, depths, width, height, cull_mode, *face_pass, threads=threads)
    if cut.min() < 0:
        raise ValueError(f"faces must index vertices 0..{n - 1}")
    n_cut = int(cut.sum())
    fan_start = np.full(N_CHUNKS, m, np.int64)
    fan_face = np.empty(0, np.int32)
    if n_cut:
        fans = np.zeros(N_CHUNKS, np.int64)
        _parallel(count_fans, clip, faces, width, height, cut_mask, n_fan, fans, threads=threads)
        fan_start += np.cumsum(fans) - fans
        tri_xy, tri_z, tri_box = _records(ws, m + int(fans.sum()), keep=m)
        fan_face = ws.take("fan_face", (int(fans.sum()),), np.int32)
        fan_pass = (fan_start, fan_face, tri_xy, tri_z, tri_box, cut_mask, BAND_SHIFT, band_counts, tally)
        _parallel(setup_cut_faces, clip, faces, width, height, cull_mode, *fan_pass, threads=threads)
    return (tri_xy, tri_z, tri_box), n_fan, fan_start, fan_face, band_counts, tally.sum(axis=0), listed


def _depth_offset(value):
    """``(factor, units)`` as two finite floats (glPolygonOffset's arguments)."""
    try:
        factor, units = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"depth_offset must be (factor, units), got {value!r}") from None
    if not (math.isfinite(factor) and math.isfinite(units)):
        raise ValueError(f"depth_offset must be finite, got {value!r}")
    return factor, units


def _run(color, depth, clip, faces, mode, face_colors, vertex_colors, ids, cull_mode, background, offset, n_threads):
    """The pipeline itself, on validated inputs."""
    ws = _WORKSPACE
    height, width = (depth if depth is not None else color).shape[:2]
    m = faces.shape[0]
    if isinstance(face_colors, FlatLambert):  # colours made by the face setup
        packed = ws.take("packed", (m,), np.uint32)
        lit = face_colors._lit(faces, packed)
    else:
        lit = _no_light(np.empty(0, np.uint32))
        if mode != SHADE_FLAT:
            packed = np.empty(0, np.uint32)
        else:
            packed = face_colors if face_colors.dtype == np.uint32 else pack_colors(face_colors)
    # Small draws on the calling thread alone: handing work to a thread costs ~15 us a pass.
    threads = 1 if m < _PARALLEL_FACES else n_threads
    records, n_fan, fan_start, fan_face, band_counts, counts, listed = _set_up(
        ws, clip, faces, width, height, cull_mode, lit, threads
    )
    band_start = bin_cursors(band_counts)
    items = ws.take("items", (int(band_start[-1]),), np.int32)
    drawn = np.zeros(N_CHUNKS, np.int64)
    _parallel(bin_records, m, n_fan, fan_start, records[2], band_counts, listed, items, drawn, threads=threads)
    n_records = int(drawn.sum())
    if offset != (0.0, 0.0):
        _parallel(offset_depths, *records, records[0].shape[0], *offset, threads=threads)
    bary = bary_matrices(clip, faces) if mode == SHADE_SMOOTH else np.empty((0, 9))
    # Flat colours without ids: the visibility buffer carries the colour itself.
    resolve = SHADE_TAGGED if mode == SHADE_FLAT and ids is None else mode
    shading = (resolve, m, fan_face, packed, vertex_colors, faces, bary)
    color_target = color if color is not None else np.empty((0, 0, 3), np.uint8)
    ids_target = ids if ids is not None else np.empty((0, 0), np.int32)
    if depth is None:  # a band-sized depth scratch per thread, never written to memory whole
        target = (ws.take("band_depth", (n_threads * slot_rows(width), width), np.float32), False, height, color_target,
                  ids is not None, ids_target)
    else:
        target = (depth, True, height, color_target, ids is not None, ids_target)
    clear = _clear_spec(background, color)
    spans = ws.take("spans", (n_threads, 2, BAND_HEIGHT), np.int64)
    fragments = sum(_parallel(draw_bands, band_start, items, records, shading, target, clear,
                              ws.visibility(n_threads, width), spans, threads=n_threads))
    return TriangleStats(
        faces=m,
        drawn=int(counts[STATUS_DRAWN]),
        culled=int(counts[STATUS_CULLED]),
        empty=int(counts[STATUS_EMPTY]),
        outside=int(counts[STATUS_OUTSIDE]),
        dropped_nonfinite=int(counts[STATUS_NONFINITE]),
        clipped=int(counts[N_STATUS]),
        triangles=int(n_records),
        fragments=int(fragments),
    )
