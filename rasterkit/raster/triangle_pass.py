"""Driver of the triangle path (solid faces, the depth pass of hidden-line renders):
vertex pass -> face pass (and cut faces' fans) -> bins -> draw the bands (raster, z-test,
resolve).

The kernels are in :mod:`rasterkit.raster.kernels.face_setup`, :mod:`rasterkit.raster.kernels.fans`,
:mod:`rasterkit.raster.kernels.bands`, :mod:`rasterkit.raster.kernels.triangle` and
:mod:`rasterkit.raster.kernels.shade`; this module picks the resolve mode once per draw, the scratch
memory and the threads, and runs the passes in order. Its callers
(:func:`rasterkit.raster.triangles.rasterize_triangles`, :mod:`rasterkit.raster.shared_samples`) have
validated the inputs.

A draw is :func:`prepare` (everything up to the bins) then :func:`draw_prepared` (the bands);
the samples of a pinhole multi-sample render share one :func:`prepare` with padded boxes,
each drawn by :func:`draw_prepared` at its sample point (the records moved there first,
:func:`rasterkit.raster.kernels.triangle_samples.move_records`), or all averaged in one pass over the
bands (:mod:`rasterkit.raster.shared_samples`).
"""

from __future__ import annotations

import functools
import math
import threading
from typing import NamedTuple

import numpy as np

from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers
from rasterkit.limits import check_memory
from rasterkit.raster.kernels.clear import PATTERN_BYTES
from rasterkit.raster.kernels.cull import CULL_BACK, CULL_FRONT, CULL_NONE
from rasterkit.raster.kernels.fans import count_fans, setup_cut_faces
from rasterkit.raster.kernels.records import Clear, Counts, Cuts, Lit, Records, Sample, Shading, Target
from rasterkit.raster.kernels.face_setup import (
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
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_NONE, SHADE_SMOOTH, SHADE_TAGGED, bary_chunks, pack_colors
from rasterkit.raster.kernels.bands import (
    BAND_HEIGHT,
    BAND_SHIFT,
    bin_cursors,
    bin_records,
    draw_bands,
    n_bands,
    slot_rows,
)
from rasterkit.raster.kernels.triangle import offset_depths
from rasterkit.raster.kernels.triangle_samples import move_records

CULL_CODES = {"none": CULL_NONE, "back": CULL_BACK, "front": CULL_FRONT}
"""The cull kernel's code of each name of :data:`rasterkit.options.CULL`."""


def cull_code(cull):
    """The kernels' cull argument: the code of a name of :data:`CULL_CODES`, or a per-face
    (M,) uint8 array of codes as it is (:func:`rasterkit.raster.sides.face_sides`)."""
    return cull if isinstance(cull, np.ndarray) else CULL_CODES[cull]

MAX_FACES = (2**31 - 1) // (MAX_FAN + 1)
"""Faces per draw at most: record indices are int32 in the visibility buffer, and a face
becomes at most MAX_FAN records."""

#: Draws of fewer faces run their setup passes on the calling thread alone: handing work to
#: a thread costs about 15 microseconds a pass.
_PARALLEL_FACES = 4096


class Lighting(NamedTuple):
    """Validated terms of :class:`rasterkit.raster.triangles.FlatLambert`, as the face pass
    (:func:`rasterkit.raster.kernels.face_setup.setup_faces`) takes them."""

    normals: np.ndarray  # (M, 3) float32, read-only
    base: np.ndarray  # (1, 3) or (M, 3) float32, read-only
    scale: np.float32
    light: np.ndarray  # (3,) float64, read-only
    ambient: float
    two_sided: bool | np.ndarray  # or (M,) bool, read-only: per face


#: Bytes of per-face scratch of a draw, each record array grown by a quarter: the records
#: (xy 24, z 12, box 16), the cut mask and fan count (2), the face list (4), the packed
#: colour (4) and at least one bin entry (4).
_BYTES_PER_FACE = (24 + 12 + 16 + 2 + 4 + 4 + 4) * 5 // 4
#: Bytes of the perspective-correct colour terms of smooth shading, per face.
_BYTES_PER_SMOOTH_FACE = 72


def scratch_bytes(n_vertices, n_faces, width, threads, smooth=False, band_depth=False) -> int:
    """Bytes of the scratch memory of a :func:`draw_triangles` call before its cut faces
    and bins are counted: per vertex, per face, and per thread (the visibility buffer and,
    with ``band_depth``, the band-sized depth buffer). For
    :func:`rasterkit.limits.check_memory`; the workspace checks its own growth again once
    the fans and the bins are counted (:meth:`_Workspace.reserve`)."""
    per_face = _BYTES_PER_FACE + (_BYTES_PER_SMOOTH_FACE if smooth else 0)
    per_thread = slot_rows(width) * width * 4 * (2 if band_depth else 1)
    return n_vertices * 16 * 5 // 4 + n_faces * per_face + threads * per_thread


class _Workspace(threading.local):
    """Named scratch arrays kept between draws, one set per Python thread; they only grow.

    Not :func:`rasterkit.runtime.scratch.take`, which hands out blocks of exactly the size asked
    for, 1 MiB and more, uninitialised, and takes them back when nothing refers to them
    (memory that leaves the call: framebuffers). Here the arrays never leave the draw, so
    one per name per thread is enough, whatever its size: no reference counting, no lock.
    A draw of a few hundred thousand faces needs tens of megabytes of per-face records
    whose number changes from frame to frame (the cut faces' fans): a buffer that grows by
    a quarter is reused for all of them, where exact sizes need fresh memory (zero-filled
    by the operating system page by page) each time: a 1080p turntable of a 300k-face model
    with the camera inside its bounding sphere took 4-19 % longer a frame on
    ``_memory.take``. Two needs only this one meets: records grown while keeping their
    first rows (:meth:`reserve`'s ``keep``), and the visibility buffer, whose contents
    (all -1) are kept between draws.
    """

    def __init__(self):
        self._buffers = {}
        self.generation = 0  # draws set up (rasterkit.raster.triangle_pass.prepare) by this thread

    def reserve(self, name, shape, dtype, keep=0):
        """A C-contiguous ``shape`` array of ``dtype``; its first ``keep`` rows are kept
        from the previous ``reserve`` of the same name (when the buffer has to grow).

        Growing checks the workspace's total against :func:`rasterkit.limits.memory_limit`
        first (``LimitError``): the number of cut faces' fans and of bin entries is known
        only here."""
        size = math.prod(shape)
        buffer = self._buffers.get(name)
        if buffer is None or buffer.dtype != dtype or buffer.size < size:
            new_bytes = (size + size // 4) * np.dtype(dtype).itemsize
            held = sum(b.nbytes for n, b in self._buffers.items() if n != name)
            check_memory(held + new_bytes, f"the triangle path's scratch memory (kept between draws; {name} "
                                           f"grown to {size} entries)")
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

    def held(self, name):
        """The whole buffer kept under ``name`` (for tests), or None."""
        return self._buffers.get(name)


WORKSPACE = _Workspace()
"""This module's scratch arrays (the calling thread's)."""

_NO_NORMALS = readonly(np.zeros((0, 3), np.float32))
_NO_BASE = readonly(np.zeros((1, 3), np.float32))
_NO_LIGHT = readonly(np.zeros(3))
_NO_BYTES = np.empty(0, np.uint8)
#: The vertex pass's (points, matrix) when ``clip`` is given (read-only, as a Mesh's
#: vertices: one compiled signature for both)
_NO_TRANSFORM = (readonly(np.zeros((0, 3))), readonly(np.zeros((4, 4))))
_NO_PATTERN = readonly(np.empty(0, np.uint8))


def _lit(lighting, packed):
    """The ``lit`` tuple of :func:`rasterkit.raster.kernels.face_setup.setup_faces` (the same types
    with and without lighting: one compiled kernel)."""
    if lighting is None:
        return Lit(False, _NO_NORMALS, _NO_BASE, np.float32(1.0), _NO_LIGHT, 0.0, False, packed)
    return Lit(True, lighting.normals, lighting.base, lighting.scale, lighting.light, lighting.ambient,
               lighting.two_sided, packed)


def _records(ws, rows, keep=0):
    """Record arrays ``tri_xy, tri_z, tri_box`` of ``rows`` records, the first ``keep`` kept."""
    return (
        ws.reserve("tri_xy", (rows, 6), np.int32, keep),
        ws.reserve("tri_z", (rows, 3), np.float32, keep),
        ws.reserve("tri_box", (rows, 4), np.int32, keep),
    )


def clear_spec(background, color):
    """The :class:`rasterkit.raster.kernels.records.Clear` of a draw."""
    if background is None or color is None:
        return Clear(background is not None, _NO_BYTES, _NO_PATTERN)
    return Clear(True, color.reshape(-1), _pattern(background.tobytes()))


@functools.lru_cache(maxsize=64)
def _pattern(background: bytes) -> np.ndarray:
    """The background colour repeated over PATTERN_BYTES bytes (read-only, kept per colour)."""
    pattern = np.tile(np.frombuffer(background, np.uint8), PATTERN_BYTES // len(background))
    pattern.flags.writeable = False
    return pattern



def _set_up(ws, clip, faces, width, height, cull_mode, pad, lit, threads, transform=None):
    """Vertex pass, face pass and (when needed) the cut faces' fans; binning counted.
    ``pad``: the boxes' padding (:func:`rasterkit.raster.kernels.face_setup.setup_triangle`);
    ``transform``: None, or ``(points, matrix)`` that the vertex pass makes ``clip`` from.

    Returns ``(records, n_fan, fan_start, fan_face, band_counts, counts, listed, corners)``
    for :func:`rasterkit.raster.kernels.bands.bin_records` and the resolve; ``counts`` (N_STATUS + 1,)
    are the faces per STATUS_* and, last, the faces cut with something left; ``corners``
    the vertex pass's rows.
    """
    n, m = clip.shape[0], faces.shape[0]
    corners = ws.reserve("corners", (n, 4), np.int32)
    depths = corners.view(np.float32)  # the same rows: z as float32
    points, matrix = _NO_TRANSFORM if transform is None else (readonly(transform[0]), readonly(transform[1]))
    if transform is not None and (points.shape != (n, 3) or matrix.shape != (4, 4)):  # the pass reads row i of both
        raise ValueError(f"transform must be (N, 3) points for the {n} clip rows and a 4x4 matrix")
    run_workers(setup_vertices, clip, width, height, pad, corners, depths, points, matrix, threads=threads)
    tri_xy, tri_z, tri_box = _records(ws, m)
    cut_mask, n_fan = ws.reserve("cut_mask", (m,), np.int8), ws.reserve("n_fan", (m,), np.int8)
    band_counts = np.zeros((N_CHUNKS, n_bands.py_func(height)), np.int64)  # no compile for it
    # a row of 128 bytes per chunk: the threads count faces into rows of their own cache
    # lines (rows of 48 bytes cost ogre's face pass 10 % at 2 threads: false sharing)
    tally = np.zeros((N_CHUNKS, 16), np.int64)
    listed = (ws.reserve("listed", (m,), np.int32), np.zeros(N_CHUNKS, np.int64))
    cut = np.zeros(N_CHUNKS, np.int64)
    cuts, counts = Cuts(cut_mask, n_fan), Counts(BAND_SHIFT, band_counts, tally)
    run_workers(setup_faces, faces, corners, depths, width, height, cull_mode, pad, Records(tri_xy, tri_z, tri_box),
                cuts, counts, lit, listed, cut, threads=threads)
    if cut.min() < 0:
        raise ValueError(f"faces must index vertices 0..{n - 1}")
    n_cut = int(cut.sum())
    fan_start = np.full(N_CHUNKS, m, np.int64)
    fan_face = np.empty(0, np.int32)
    if n_cut:
        fans = np.zeros(N_CHUNKS, np.int64)
        run_workers(count_fans, clip, faces, width, height, cut_mask, n_fan, fans, threads=threads)
        fan_start += np.cumsum(fans) - fans
        tri_xy, tri_z, tri_box = _records(ws, m + int(fans.sum()), keep=m)
        fan_face = ws.reserve("fan_face", (int(fans.sum()),), np.int32)
        run_workers(setup_cut_faces, clip, faces, width, height, cull_mode, pad, fan_start, fan_face,
                    Records(tri_xy, tri_z, tri_box), cuts, counts, threads=threads)
    counts = tally[:, :N_STATUS + 1].sum(axis=0)
    return Records(tri_xy, tri_z, tri_box), n_fan, fan_start, fan_face, band_counts, counts, listed, corners


def _flat_colors(ws, m, face_colors, lighting):
    """Packed RGBA (M,) uint32 per face: made by the face pass when ``lighting`` is given
    (for the faces drawn only), else ``face_colors`` packed."""
    if lighting is not None:
        return ws.reserve("packed", (m,), np.uint32)
    return face_colors if face_colors.dtype == np.uint32 else pack_colors(face_colors)


class Prepared(NamedTuple):
    """A draw's triangles set up and binned (:func:`prepare`), ready to be drawn
    (:func:`draw_prepared`) once, or at each sample point of a multi-sample render. Its
    arrays are the workspace's: valid until the next :func:`prepare` of this thread."""

    records: Records
    band_start: np.ndarray
    items: np.ndarray
    shading: Shading
    width: int
    height: int
    padded: bool
    generation: int  # the workspace's at prepare: checked by draw_prepared
    stats: dict  # the counts of rasterkit.raster.triangles.TriangleStats but fragments
    corners: np.ndarray  # the vertex pass's (rasterkit.raster.kernels.face_setup.setup_vertices)
    textures: object = None  # a textured frame's rasterkit.raster.texturing.FrameTextures


def prepare(clip, faces, face_colors, vertex_colors, cull, offset, *, width, height, color, ids, threads,
            lighting=None, padded=False, transform=None, textures=None, color_index=None) -> Prepared:
    """Vertex pass, face pass, fans, bins, polygon offset and the smooth colours' terms of
    a :func:`draw_triangles` (its arguments; ``color`` and ``ids``: whether colours and
    face ids will be drawn). ``padded``: boxes padded by a pixel, for drawing at sample
    points other than the pixel centres. ``transform``: None, or ``(points, matrix)``
    ((N, 3) and (4, 4) float64, C-contiguous) that the vertex pass turns into ``clip``
    (N, 4), written here. ``textures``: a textured frame's
    :class:`rasterkit.raster.texturing.FrameTextures` (checked against the faces by its maker).
    ``color_index``: with ``vertex_colors`` (K, 3), each face corner's row of them (M, 3) int64
    (checked by the caller); None: ``faces`` (a colour per vertex)."""
    ws = WORKSPACE
    faces = readonly(faces)  # as a Mesh's: one compiled kernel for both
    m = faces.shape[0]
    if not color:
        mode, packed = SHADE_NONE, np.empty(0, np.uint32)
    elif vertex_colors is not None:
        mode, packed = SHADE_SMOOTH, np.empty(0, np.uint32)
    else:
        mode, packed = SHADE_FLAT, _flat_colors(ws, m, face_colors, lighting)
    lit = _lit(lighting, packed if lighting is not None else np.empty(0, np.uint32))
    setup_threads = 1 if m < _PARALLEL_FACES else threads
    ws.generation += 1
    records, n_fan, fan_start, fan_face, band_counts, counts, listed, corners = _set_up(
        ws, clip, faces, width, height, cull_code(cull), int(padded), lit, setup_threads, transform
    )
    band_start = bin_cursors(band_counts)
    items = ws.reserve("items", (int(band_start[-1]),), np.int32)
    drawn = np.zeros(N_CHUNKS, np.int64)
    run_workers(bin_records, m, n_fan, fan_start, records.box, band_counts, listed, items, drawn,
                threads=setup_threads)
    if offset != (0.0, 0.0):
        run_workers(offset_depths, *records, records.xy.shape[0], *offset, threads=setup_threads)
    bary = np.empty((0, 9))
    if mode == SHADE_SMOOTH or textures is not None:
        bary = ws.reserve("bary", (m, 9), np.float64)
        run_workers(bary_chunks, clip, faces, bary, threads=setup_threads)
    # Flat colours without ids or textures: the visibility buffer carries the colour itself.
    resolve = SHADE_TAGGED if mode == SHADE_FLAT and not ids and textures is None else mode
    colors = vertex_colors if vertex_colors is not None else np.zeros((0, 3), np.float32)
    # every row table read-only, as faces are: one compiled band worker whoever made them
    shading = Shading(resolve, m, fan_face, packed, colors, faces, bary, faces if color_index is None else readonly(color_index))
    stats = dict(
        faces=m,
        drawn=int(counts[STATUS_DRAWN]),
        culled=int(counts[STATUS_CULLED]),
        empty=int(counts[STATUS_EMPTY]),
        outside=int(counts[STATUS_OUTSIDE]),
        dropped_nonfinite=int(counts[STATUS_NONFINITE]),
        clipped=int(counts[N_STATUS]),
        triangles=int(drawn.sum()),
    )
    return Prepared(records, band_start, items, shading, width, height, bool(padded), ws.generation, stats, corners,
                    textures)


def draw_prepared(prepared: Prepared, color, depth, ids, background, *, threads, sample=(0, 0), maps=None) -> int:
    """Draw ``prepared`` into ``color``, ``depth`` and ``ids`` (as :func:`draw_triangles`,
    which made the draw's ``prepared`` with the same ones wanted), sampling each pixel at
    ``sample``, an offset from its centre in 1/256 pixel (``(0, 0)`` unless padded), and
    make a vision render's ``maps`` (a :class:`rasterkit.raster.kernels.records.Maps`, or None)
    band by band; returns the number of fragments."""
    ws = WORKSPACE
    if prepared.generation != ws.generation:
        raise RuntimeError("the triangles were set up before another draw of this thread (or in another thread)")
    sample = Sample(int(sample[0]), int(sample[1]))
    records = prepared.records
    if prepared.padded:  # the records moved to the sample point
        n = records.xy.shape[0]
        moved = Records(ws.reserve("moved_xy", (n, 6), np.int32), records.z,
                        ws.reserve("moved_box", (n, 4), np.int32))
        run_workers(move_records, records, moved, n, sample, prepared.width, prepared.height,
                    threads=1 if n < _PARALLEL_FACES else threads)
        records = moved
    elif sample != (0, 0):
        raise ValueError("a draw prepared without padded boxes is sampled at the pixel centres only")
    width, height = prepared.width, prepared.height
    color_target = color if color is not None else np.empty((0, 0, 3), np.uint8)
    ids_target = ids if ids is not None else np.empty((0, 0), np.int32)
    if depth is None:  # a band-sized depth scratch per thread, never written to memory whole
        band_depth = ws.reserve("band_depth", (threads * slot_rows(width), width), np.float32)
        target = Target(band_depth, False, height, color_target, ids is not None, ids_target)
    else:
        target = Target(depth, True, height, color_target, ids is not None, ids_target)
    clear = clear_spec(background, color)
    spans = ws.reserve("spans", (threads, 2, BAND_HEIGHT), np.int64)
    return int(sum(run_workers(draw_bands, prepared.band_start, prepared.items, records, prepared.shading,
                               target, clear, sample, ws.visibility(threads, width), spans, maps,
                               *texture_arguments(prepared.textures),
                               None if prepared.textures is None else prepared.textures.lights, threads=threads)))


def texture_arguments(textures):
    """The band workers' ``textures, cutouts, mapped`` of a frame's FrameTextures (or None)."""
    return (None, None, None) if textures is None else tuple(textures)[:3]


def draw_triangles(color, depth, clip, faces, face_colors, vertex_colors, ids, cull, background, offset, *,
                   threads, lighting=None, maps=None, transform=None, textures=None, color_index=None) -> dict:
    """Draw the triangles ``faces`` (M, 3) int64 of the vertices ``clip`` (N, 4) float64
    (homogeneous raster space) as :func:`rasterkit.raster.triangles.rasterize_triangles` describes.

    The resolve mode follows from the colours: none without ``color``; smooth with
    ``vertex_colors`` (N, 3) float32; else flat, by ``face_colors`` ((M, 3) float32 or
    packed (M,) uint32) or ``lighting`` (a :class:`Lighting`, colours made by the face
    pass). ``cull`` is a name of :data:`CULL_CODES`, ``background`` (C,) uint8 or None,
    ``offset`` ``(factor, units)`` floats; ``threads`` draw the bands (the setup passes of
    a few faces run on one); ``maps``: as :func:`draw_prepared`; ``transform``: as
    :func:`prepare`; ``textures``, ``color_index``: as :func:`prepare`. Returns the counts of
    :class:`rasterkit.raster.triangles.TriangleStats`, by field name.
    """
    height, width = (depth if depth is not None else color).shape[:2]
    prepared = prepare(clip, faces, face_colors, vertex_colors, cull, offset, width=width, height=height,
                       color=color is not None, ids=ids is not None, threads=threads, lighting=lighting,
                       transform=transform, textures=textures, color_index=color_index)
    fragments = draw_prepared(prepared, color, depth, ids, background, threads=threads, maps=maps)
    return dict(prepared.stats, fragments=fragments)
