"""Triangles set up once and drawn at every sample point of a pinhole multi-sample render.

The samples of a render through a pinhole (:mod:`rasterkit.raster.accumulate`) differ only by
where each pixel is sampled: ``P + s`` for the pixel centre ``P`` and a sub-pixel offset
``s``. When ``s`` is a multiple of 1/256 pixel (the fixed-point grid the vertices are
snapped to, :data:`rasterkit.raster.kernels.face_setup.SUBPIXEL_BITS`), sampling at ``P + s`` is the
same, to the bit, as drawing the scene moved by ``-s`` at the pixel centres: the snapped
vertices move by exactly ``-256 s`` fixed-point units, and nothing else of a triangle's
record changes (its depths, its winding, whether it is culled or of zero area, its face's
colour). So the vertex pass, the face pass (clipping, culling, snapping, flat colours),
the cut faces' fans, the binning, the polygon offset and the smooth colours'
perspective-correct terms are done once, with every box padded by a pixel, and each sample
only draws the bands: :meth:`SharedTriangles.draw` moves the records' vertices by
``-256 s`` and bounds them again (:func:`rasterkit.raster.kernels.triangle_samples.move_records`, a pass over
the records) and draws them as any draw (:func:`rasterkit.raster.kernels.bands.draw_bands`);
:meth:`SharedTriangles.draw_average` draws every sample of a band in turn, moving each
record as it draws it (:func:`rasterkit.raster.kernels.triangle_samples.raster_band_at`), and averages
them there (:mod:`rasterkit.raster.kernels.sample_bands`). The resolve interpolates smooth colours
at ``P + s``. Boxes are padded by a pixel, and faces beside the image are not rejected
(:func:`rasterkit.raster.kernels.face_setup.setup_vertices`), for offsets up to a pixel.

Exactly equal to a full draw of the moved vertices: every face that no clipping plane cuts
(the cut faces' fans are cut once, where the centre sample's vertices lie: the same
polygons, whose corners a moved draw would round differently). Smooth colours are
evaluated at the sample point from the centre's barycentric terms, which a moved draw would
round differently too (the same interpolation, to float64 rounding).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.triangle_pass import WORKSPACE, Prepared, clear_spec, draw_prepared, prepare, texture_arguments
from rasterkit.raster.kernels.records import Samples
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_TAGGED
from rasterkit.raster.kernels.bands import BAND_HEIGHT, SLOT_GUARD_BYTES, slot_rows
from rasterkit.mesh import side_neighbours
from rasterkit.raster.draw_checks import (check_buffer, check_cull, check_depth, check_depth_offset, check_geometry,
                                          thread_count)
from rasterkit.raster.triangles import background_bytes, check_corners, shading_mode

__all__ = ["SharedTriangles"]


class SharedTriangles:
    """Triangles set up once (as :func:`rasterkit.raster.triangles.rasterize_triangles` would draw
    them), for drawing at several sample points.

    Parameters
    ----------
    clip, faces, face_colors, vertex_colors, cull, depth_offset, threads
        As for :func:`rasterkit.raster.triangles.rasterize_triangles`.
    width, height : int
        The image size.
    color : bool
        Whether colours are drawn (then ``face_colors`` or ``vertex_colors`` is needed).
    neighbours : (M, 3) int32, optional
        :func:`rasterkit.mesh.side_neighbours` of ``faces`` (a Mesh keeps them), for
        :meth:`draw_average`; worked out there when not given.
    textures : Textured, optional
        A textured frame's (:func:`rasterkit.raster.texturing.frame_textures`, made for these
        faces).
    corners : (M, 3) int64, optional
        Each face corner's row of ``vertex_colors`` (K, 3), for colours per distinct corner
        (:func:`rasterkit.raster.shading.shade`); None: one per vertex.

    The setup lives in this thread's scratch memory (:mod:`rasterkit.raster.triangle_pass`): it can
    be drawn until the next draw of triangles of this thread (:meth:`draw` raises after that).
    """

    def __init__(self, clip, faces, *, width, height, color, face_colors=None, vertex_colors=None, cull="back",
                 depth_offset=(0.0, 0.0), threads=None, neighbours=None, textures=None, corners=None):
        check_depth(np.empty((height, width), np.float32))  # the size
        check_geometry(clip, faces)
        check_cull(cull, faces.shape[0])
        face_colors, vertex_colors, lighting = shading_mode(True if color else None, face_colors, vertex_colors, faces,
                                                        clip if corners is None else vertex_colors)
        if corners is not None:
            corners = check_corners(corners, faces, vertex_colors)
        self._threads = thread_count(threads)
        self._faces = faces
        if neighbours is not None and (not isinstance(neighbours, np.ndarray) or neighbours.dtype != np.int32
                                       or neighbours.shape != faces.shape or neighbours.size
                                       and not -1 <= neighbours.min() <= neighbours.max() < len(faces)):
            raise ValueError("neighbours must be the faces' side_neighbours: (M, 3) int32 in -1..M-1")
        self._neighbours = neighbours
        self._color = bool(color)
        self._prepared = prepare(clip, faces, face_colors, vertex_colors, cull, check_depth_offset(depth_offset),
                                 width=width, height=height, color=self._color, ids=False, threads=self._threads,
                                 lighting=lighting, padded=True, textures=textures,
                                 color_index=corners)

    def draw(self, color, depth, *, sample=(0, 0), clear=None) -> int:
        """Draw the triangles sampled at ``sample`` from each pixel centre, ``(x, y)``
        integers in 1/256 pixel, each in -256..256 (raster x right, y down); returns the
        fragments depth-tested.

        ``color`` (H, W, C) uint8 (None exactly when the setup was made without colours),
        ``depth`` (H, W) float32 or None and ``clear`` as for
        :func:`rasterkit.raster.triangles.rasterize_triangles`. The image is what that function
        draws of the vertices moved by ``-sample / 256`` pixel (see the module docstring).
        """
        prepared = self._prepared
        shape = (prepared.height, prepared.width)
        if (color is not None) != self._color:
            raise ValueError("color must be given exactly when the triangles were set up with colours")
        if color is not None:
            if not (isinstance(color, np.ndarray) and color.ndim == 3 and color.shape[2] in (3, 4)):
                raise ValueError("color must be an (H, W, 3 or 4) uint8 array")
            check_buffer("color", color, np.uint8, shape + (color.shape[2],))
        elif depth is None:
            raise ValueError("depth can be None only when color is given")
        if depth is not None:
            check_buffer("depth", depth, np.float32, shape)
        for name, buffer in (("color", color), ("depth", depth)):
            if buffer is not None and np.may_share_memory(self._faces, buffer):
                raise ValueError(f"faces must not share memory with {name}, the buffer drawn into")
        x, y = sample
        if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and -256 <= v <= 256 for v in (x, y)):
            raise ValueError(f"sample must be two integers in -256..256 (1/256 pixel), got {sample!r}")
        return draw_prepared(prepared, color, depth, None, background_bytes(clear, color), threads=self._threads,
                             sample=(int(x), int(y)))

    def draw_average(self, color, samples, *, clear, exact=True) -> int:
        """Draw the triangles at every sample point of ``samples`` ((n, 2) integers in
        -256..256, 1/256 pixel; 1 <= n <= 256) and write the average into ``color`` (H, W,
        3) uint8, cleared to ``clear`` (3 integers) first: what :meth:`draw` of each sample
        into an image cleared to ``clear``, the images summed and divided with rounding
        (:func:`rasterkit.raster.kernels.accumulate.average_samples`), gives, to the bit, in one pass
        over the bands (:mod:`rasterkit.raster.kernels.sample_bands`). Returns the fragments.

        With ``exact`` (the default), a pixel whose samples saw one face (not cut by a
        clipping plane) and the background, or that holds a corner of one face and
        nothing else, is instead the background plus the face's exact share of the pixel
        times the face's colour (the mean of its samples) minus the background: "which
        part of the pixel" (:mod:`rasterkit.raster.kernels.coverage`). Then ``color`` may also be
        (H, W, 4) with ``clear`` (0, 0, 0, 0): straight colours, the covered share as alpha
        (as :func:`rasterkit.raster.kernels.accumulate.average_samples_rgba` makes a transparent
        render's average, those pixels exact)."""
        prepared = self._prepared
        channels = 4 if exact else 3
        if not self._color or not isinstance(color, np.ndarray) or color.ndim != 3 or color.shape[2] not in (3, channels):
            raise ValueError("draw_average draws colours into an (H, W, 3) uint8 image (or, exact, (H, W, 4))")
        check_buffer("color", color, np.uint8, (prepared.height, prepared.width, color.shape[2]))
        if color.shape[2] == 4 and tuple(clear) != (0, 0, 0, 0):
            raise ValueError("an (H, W, 4) average is drawn on a transparent background: clear must be (0, 0, 0, 0)")
        if np.may_share_memory(self._faces, color):
            raise ValueError("faces must not share memory with color, the buffer drawn into")
        offsets = np.asarray(samples)
        if offsets.dtype.kind not in "iu" or offsets.ndim != 2 or offsets.shape[1] != 2 \
                or not 1 <= offsets.shape[0] <= 256 or offsets.size and np.abs(offsets).max() > 256:
            raise ValueError("samples must be (n, 2) integers in -256..256 (1/256 pixel), 1 <= n <= 256")
        return _average(prepared, color, background_bytes(clear, color), offsets.astype(np.int64), threads=self._threads,
                        exact=bool(exact), neighbours=self._neighbours)


_NO_NEIGHBOURS = readonly(np.zeros((0, 3), np.int32))


def _average(prepared: Prepared, color, background, offsets, *, threads, exact=True, neighbours=None) -> int:
    """Draw ``prepared`` (padded, flat or smooth colours) at every sample point ``offsets``
    (n, 2) int64 (1/256 pixel, each in -256..256) and write their average into ``color``
    (H, W, 3) uint8 on a ``background`` (3,) uint8 (or, with ``exact``, (H, W, 4) on a
    transparent black one, as :func:`rasterkit.raster.kernels.accumulate.average_samples_rgba`
    averages), as :func:`rasterkit.raster.triangle_pass.draw_prepared` of each sample,
    summed and divided by :func:`rasterkit.raster.kernels.accumulate.average_samples` would, to the
    bit (:mod:`rasterkit.raster.kernels.sample_bands`); returns the number of fragments. With
    ``exact``, the pixels whose samples saw one uncut face and the background (or that hold
    a corner of one face and nothing else) get instead the background plus the face's exact
    share of the pixel times its colour minus the background; ``neighbours``: the faces'
    :func:`rasterkit.mesh.side_neighbours` (made here when None), whose sides between two
    drawn faces cross no pixel of that kind and are not looked at."""
    from rasterkit.raster.kernels.sample_bands import draw_sample_bands  # multi-sample renders only

    ws = WORKSPACE
    if prepared.generation != ws.generation or not prepared.padded:
        raise RuntimeError("the triangles were not set up for samples, or before another draw of this thread")
    n, width = offsets.shape[0], prepared.width
    band_depth = ws.reserve("band_depth", (threads * slot_rows(width), width), np.float32)
    guard = -(-SLOT_GUARD_BYTES // (6 * width))  # rows of sums between two slots' bands
    sums = ws.reserve("sample_sums", (threads, BAND_HEIGHT + guard, width, 3), np.uint16)
    if color.shape[2] == 4 and not (exact and int(background[3]) == 0 and not background[:3].any()):
        raise ValueError("an RGBA average needs exact and a transparent black background")
    rgb = int(background[0]) | int(background[1]) << 8 | int(background[2]) << 16
    shading = prepared.shading
    if exact:  # each pixel's faces: the visibility rows hold faces, not colours
        first = ws.reserve("sample_first", (threads, slot_rows(width), width), np.int32)
        state = ws.reserve("sample_state", (threads, slot_rows(width), width), np.int32)
        if shading.mode == SHADE_TAGGED:
            shading = shading._replace(mode=SHADE_FLAT)
        if neighbours is None:
            neighbours = side_neighbours(shading.faces, prepared.corners.shape[0])
    else:
        first = state = np.zeros((threads, 0, 0), np.int32)
        neighbours = _NO_NEIGHBOURS
    samples = Samples(np.ascontiguousarray(offsets, np.int64), np.uint32(rgb), 1.0 / n, (n // 2 + 0.5) / n, sums,
                      bool(exact), first, state, prepared.corners, readonly(neighbours))
    spans = ws.reserve("spans", (threads, 2, BAND_HEIGHT), np.int64)
    textures, cutouts, mapped = texture_arguments(prepared.textures)
    if prepared.textures is not None and prepared.textures.lit_only:
        textures = None  # every face lit per pixel, none textured: the lighting alone is compiled
    return int(sum(run_workers(draw_sample_bands, prepared.band_start, prepared.items, prepared.records,
                               shading, band_depth, color, clear_spec(background, color), samples,
                               ws.visibility(threads, width), spans, textures, cutouts, mapped, threads=threads)))
