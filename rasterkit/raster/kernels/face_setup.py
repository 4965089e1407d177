"""Triangle setup: vertices to fixed point, faces to records (cull, bound, count into bands).

Fixed point
    Raster coordinates are snapped to 1/256 pixel (``SUBPIXEL_BITS = 8``, :func:`snap`);
    the rasterizer (:mod:`rasterkit.raster.kernels.triangle`) evaluates its edge functions
    exactly in int64 on these coordinates.

Passes
    :func:`setup_vertices` classifies and snaps every vertex once; :func:`setup_faces`
    turns every face that needs no cutting into its record, culls it by the sign of its
    area (the lecture's n·v test, :mod:`rasterkit.raster.kernels.cull`), clamps its bounding box
    to the image and counts it into the bands it spans (the counting pass of binning,
    :mod:`rasterkit.raster.kernels.bands`). Faces that cross a clipping plane are left to
    :mod:`rasterkit.raster.kernels.fans`. Every pass is a worker of
    :func:`rasterkit.runtime.threads.run_parallel` over N_CHUNKS chunks of vertices or faces.

Records    The setup stage turns face ``f`` into record ``f`` or, when clipping cut it, into a fan
    of records numbered from M up (``fan_face[t - M]`` is their face): ``tri_xy (T, 6)
    int32`` fixed-point ``X0, Y0, X1, Y1, X2, Y2``; ``tri_z (T, 3) float32`` depths;
    ``tri_box (T, 4) int32`` the clamped pixel bounding box ``i_lo, i_hi, j_lo, j_hi``
    (empty when ``j_lo > j_hi``: culled, empty, outside or cut).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.clip import (
    CUT_MASK,
    DEGENERATE_BIT,
    FACE_INSIDE,
    FACE_NEEDS_CUT,
    FACE_NONFINITE,
    MAX_POLYGON,
    NONFINITE_BIT,
    VIEW_BOTTOM,
    VIEW_LEFT,
    VIEW_RIGHT,
    VIEW_TOP,
    classify_face,
    project_vertex,
    vertex_code,
)
from rasterkit.raster.kernels.cull import is_culled, per_face
from rasterkit.runtime.intrinsics import fetch_add, prefetch_row
from rasterkit.raster.kernels.shade import flat_colors
from rasterkit.raster.kernels.vertex import transform_row

SUBPIXEL_BITS = 8
ONE = 1 << SUBPIXEL_BITS
HALF = ONE >> 1
#: Most triangles one cut face can become (a fan over a MAX_POLYGON-gon).
MAX_FAN = MAX_POLYGON - 2
# What happened to a face; the setup kernels count faces per outcome (their ``tally``).
STATUS_DRAWN = 0
STATUS_CULLED = 1
STATUS_EMPTY = 2  # zero area after snapping, or covers no pixel centre of the image
STATUS_OUTSIDE = 3
STATUS_NONFINITE = 4
N_STATUS = 5
#: The vertex code bits of the image's sides (:mod:`rasterkit.raster.kernels.clip`): a face wholly
#: beside one of them is rejected, unless the boxes are padded (:func:`setup_vertices`).
VIEW_MASK = (1 << VIEW_LEFT) | (1 << VIEW_RIGHT) | (1 << VIEW_TOP) | (1 << VIEW_BOTTOM)
#: Faces (and vertices) are processed in this many contiguous chunks, setup and binning
#: using the same ones. A constant, so that nothing depends on the thread count.
N_CHUNKS = 64


@kernel(inline="always")
def chunk_range(n, c):
    """Items ``[start, stop)`` of chunk ``c`` of ``N_CHUNKS`` chunks of ``n`` faces or vertices."""
    return (n * c) // N_CHUNKS, (n * (c + 1)) // N_CHUNKS


@kernel(inline="always")
def snap(v):
    """Raster coordinate ``v`` (pixels, float) -> fixed point (int64, 1/256 px), rounded."""
    return np.int64(np.floor(v * ONE + 0.5))


@kernel(inline="always")
def _ceil_div(a, b):
    """``ceil(a / b)`` for int64 ``a`` and ``b > 0``."""
    return -((-a) // b)


@kernel(inline="always")
def pixel_bounds(lo, hi):
    """Pixel indices whose centres ``256 k + 128`` lie in the fixed-point range [lo, hi]."""
    return _ceil_div(lo - HALF, ONE), (hi - HALF) // ONE


@kernel(inline="always")
def _padded_bounds(lo, hi, pad):
    """:func:`pixel_bounds` widened by ``pad`` pixels on each side (the sums' constant
    parts are loop-invariant: the face loop pays nothing for the padding)."""
    return _ceil_div(lo - (HALF + pad * ONE), ONE), (hi - (HALF - pad * ONE)) // ONE


@kernel(inline="always")
def signed_area2(x0, y0, x1, y1, x2, y2):
    """Twice the raster signed area of a fixed-point triangle (int64, exact)."""
    return (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)


@kernel(inline="always")
def _empty_box(t, tri_box):
    """Mark record ``t`` as not drawn (binning skips it)."""
    tri_box[t, 0], tri_box[t, 1], tri_box[t, 2], tri_box[t, 3] = 0, -1, 0, -1


@kernel(inline="always")
def setup_triangle(x0, y0, z0, x1, y1, z1, x2, y2, z2, width, height, cull_mode, pad, t, tri_xy, tri_z, tri_box):
    """Cull and bound a fixed-point triangle into record ``t``.

    Parameters
    ----------
    x0, y0, z0, x1, y1, z1, x2, y2, z2
        Vertices in the face's winding order: fixed-point raster ``x, y`` (:func:`snap`,
        within the guard band) and depth ``z``.
    width, height : int
        Image size; the bounding box is clamped to it.
    cull_mode : int
        A :mod:`rasterkit.raster.kernels.cull` mode.
    pad : int
        0, or 1 for records drawn at sample points other than the pixel centres: the box
        grows by a pixel on every side (before it is clamped to the image), so that it
        holds the pixels of every sample point up to a pixel from the centres (each
        sample point bounds the triangle again: :func:`rasterkit.raster.kernels.triangle_samples.moved_box`),
        and a triangle that covers no pixel centre is kept all the same.
    t : int
        Record to write.
    tri_xy, tri_z, tri_box
        Record arrays (see the module docstring). The box is left empty unless drawn.

    Returns
    -------
    int
        STATUS_DRAWN, STATUS_CULLED or STATUS_EMPTY.
    """
    _empty_box(t, tri_box)
    area2 = signed_area2(x0, y0, x1, y1, x2, y2)
    if area2 == 0:
        return STATUS_EMPTY
    if is_culled(area2, cull_mode):
        return STATUS_CULLED
    i_lo, i_hi = _padded_bounds(min(x0, x1, x2), max(x0, x1, x2), pad)
    j_lo, j_hi = _padded_bounds(min(y0, y1, y2), max(y0, y1, y2), pad)
    i_lo, i_hi = max(i_lo, 0), min(i_hi, width - 1)
    j_lo, j_hi = max(j_lo, 0), min(j_hi, height - 1)
    if i_lo > i_hi or j_lo > j_hi:
        return STATUS_EMPTY
    if area2 < 0:  # store clockwise on screen, so every edge function is positive inside
        x1, y1, z1, x2, y2, z2 = x2, y2, z2, x1, y1, z1
    tri_xy[t, 0], tri_xy[t, 1], tri_xy[t, 2] = x0, y0, x1
    tri_xy[t, 3], tri_xy[t, 4], tri_xy[t, 5] = y1, x2, y2
    tri_z[t, 0], tri_z[t, 1], tri_z[t, 2] = z0, z1, z2
    tri_box[t, 0], tri_box[t, 1], tri_box[t, 2], tri_box[t, 3] = i_lo, i_hi, j_lo, j_hi
    return STATUS_DRAWN


#: Columns of the per-vertex rows of :func:`setup_vertices` (z in the float32 view).
_V_CODE, _V_X, _V_Y, _V_Z = range(4)


@kernel(refcounts=False)
def _setup_vertex_chunk(ch, clip, width, height, keep, corners, depths, points, matrix):
    """:func:`setup_vertices` for the vertices of chunk ``ch``."""
    start, stop = chunk_range(clip.shape[0], ch)
    transform = points.shape[0] > 0
    for i in range(np.uint64(start), np.uint64(stop)):
        if transform:
            transform_row(points, matrix, clip, i)
        code = vertex_code(clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3], width, height) & keep
        corners[i, _V_CODE] = code
        if code & CUT_MASK or code & (NONFINITE_BIT | DEGENERATE_BIT):
            corners[i, _V_X], corners[i, _V_Y], depths[i, _V_Z] = 0, 0, 0.0
            continue
        x, y, z = project_vertex(clip, i)
        corners[i, _V_X], corners[i, _V_Y], depths[i, _V_Z] = snap(x), snap(y), z


@kernel
def setup_vertices(slot, counter, clip, width, height, pad, corners, depths, points, matrix):
    """Vertex pass: classify every vertex once and, where it is safe, project and snap it;
    with ``points``, transform them into ``clip`` first.

    A vertex is shared by about six faces of a closed mesh, so doing this per vertex and
    not per face corner saves most of the setup work.

    Parameters
    ----------
    clip : (N, 4) float64
        Homogeneous raster coordinates: in, or out when ``points`` are given.
    width, height : int
        Image size.
    pad : int
        1 for faces drawn at other sample points than the pixel centres
        (:func:`setup_triangle`): the codes get no bits of the image's sides (VIEW_MASK),
        so that no face is rejected for lying beside the image, as a moved face may not
        be (its box decides: empty, or within a pixel of the image); else 0.
    corners : (N, 4) int32
        Out, one 16-byte row per vertex (what a face reads of each corner, in one cache
        line): column ``_V_CODE`` the :func:`rasterkit.raster.kernels.clip.vertex_code`;
        ``_V_X, _V_Y`` the fixed-point raster ``x, y`` (:func:`snap`) of vertices whose code
        has no CUT_MASK, NONFINITE or DEGENERATE bit (0 otherwise).
    depths : (N, 4) float32
        The same memory as ``corners`` seen as float32: out, column ``_V_Z`` the depth
        ``zh / w`` of the same vertices.
    points, matrix : (N, 3) and (4, 4) float64
        Object-space points and the object -> raster matrix: ``clip[i]`` is made here as
        :func:`rasterkit.raster.kernels.vertex.transform_row` makes it (one pass over the
        vertices and one hand-off less than a transform of its own); ``points`` (0, 3):
        ``clip`` is given.

    A worker of :func:`rasterkit.runtime.threads.run_parallel`: ``slot`` is unused, the N_CHUNKS
    chunks are claimed through ``counter``.
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        _setup_vertex_chunk(ch, clip, width, height, ~VIEW_MASK if pad else ~0, corners, depths, points, matrix)


@kernel(inline="always")
def count_bands(t, tri_box, band_shift, band_counts, ch):
    """Count drawn record ``t`` into the bands of ``1 << band_shift`` rows its box spans.

    This is the counting pass of binning (:mod:`rasterkit.raster.kernels.bands`), done here while
    the box is at hand: ``band_counts[ch, b]`` counts chunk ``ch``'s records in band ``b``.
    (A shift, not a division: the band height is a run-time value, and a 64-bit division
    costs tens of cycles per face.)
    """
    for b in range(tri_box[t, 2] >> band_shift, (tri_box[t, 3] >> band_shift) + 1):
        band_counts[ch, b] += 1


@kernel(inline="always")
def _setup_fast_face(faces, f, corners, depths, width, height, cull_mode, pad, tri_xy, tri_z, tri_box):
    """Set up face ``f`` (FACE_INSIDE) into record ``f`` from the vertex pass; its status."""
    a, b, c = np.uint64(faces[f, 0]), np.uint64(faces[f, 1]), np.uint64(faces[f, 2])
    return setup_triangle(
        np.int64(corners[a, _V_X]), np.int64(corners[a, _V_Y]), depths[a, _V_Z],
        np.int64(corners[b, _V_X]), np.int64(corners[b, _V_Y]), depths[b, _V_Z],
        np.int64(corners[c, _V_X]), np.int64(corners[c, _V_Y]), depths[c, _V_Z],
        width, height, per_face(cull_mode, f), pad, f, tri_xy, tri_z, tri_box,
    )


#: Faces ahead whose corners the face pass asks to be fetched: meshes whose vertices are
#: not in surface order (the bunny) gather each corner from anywhere in memory.
PREFETCH_AHEAD = 8
#: Mean jump between the first corners of consecutive faces (vertex rows) above which the
#: face pass prefetches; below it the rows come in order and the hardware fetches them.
SCATTERED_JUMP = 64


@kernel(inline="always")
def _scattered(faces, start, stop):
    """Whether the faces ``start .. stop - 1`` read their corners from scattered rows,
    judged on the first 32: the prefetches pay off only then."""
    n = min(stop - start, 33)
    jump = 0
    for f in range(start + 1, start + n):
        jump += abs(faces[f, 0] - faces[f - 1, 0])
    return jump > SCATTERED_JUMP * (n - 1)


@kernel(inline="always")
def _prefetch_corners(faces, f, corners):
    for k in range(3):
        prefetch_row(corners, faces[f, k])


@kernel(refcounts=False)
def _setup_chunk(
    ch,
    faces,
    corners,
    depths,
    width,
    height,
    cull_mode,
    pad,
    records,
    cuts,
    counts,
    lit,
    listed,
):
    """:func:`setup_faces` for the faces of chunk ``ch``; returns how many need cutting,
    or -1 (and stops) at a vertex index out of range.

    A face to cut only gets its mask here (and counts as STATUS_OUTSIDE until
    :func:`setup_cut_faces` has cut it).
    """
    start, stop = chunk_range(faces.shape[0], ch)
    tri_xy, tri_z, tri_box = records
    cut_mask, n_fan = cuts
    band_shift, band_counts, tally = counts
    on, normals, base, scale, light, ambient, two_sided, packed = lit
    seen, n_listed = listed
    cut = 0
    n_seen = np.int64(0)  # not a literal 0: flat_colors would compile for Literal[int](0) too
    n_vertices = np.uint64(corners.shape[0])
    scattered = _scattered(faces, start, stop)
    for f in range(np.uint64(start), np.uint64(stop)):
        if scattered and f + PREFETCH_AHEAD < stop:
            _prefetch_corners(faces, f + PREFETCH_AHEAD, corners)  # never faults, even out of range
        a, b, c = np.uint64(faces[f, 0]), np.uint64(faces[f, 1]), np.uint64(faces[f, 2])
        if a >= n_vertices or b >= n_vertices or c >= n_vertices:  # a negative index too
            return -1  # the caller raises before anything is drawn
        cls, mask = classify_face(corners[a, _V_CODE], corners[b, _V_CODE], corners[c, _V_CODE])
        cut_mask[f] = mask
        n_fan[f] = 0
        if cls == FACE_INSIDE:
            outcome = _setup_fast_face(faces, f, corners, depths, width, height, cull_mode, pad, tri_xy, tri_z,
                                       tri_box)
            if outcome == STATUS_DRAWN:
                count_bands(f, tri_box, band_shift, band_counts, ch)
                seen[start + n_seen] = f
                n_seen += 1
        else:
            _empty_box(f, tri_box)
            outcome = STATUS_NONFINITE if cls == FACE_NONFINITE else STATUS_OUTSIDE
            if cls == FACE_NEEDS_CUT:
                cut += 1
                seen[start + n_seen] = f
                n_seen += 1
        tally[ch, outcome] += 1
    n_listed[ch] = n_seen
    # The colours in a loop of their own: inside the branches above they would wait on
    # every mispredicted drawn / culled decision.
    if on:
        flat_colors(normals, seen, start, n_seen, base, scale, light, ambient, two_sided, packed)
    return cut


@kernel
def setup_faces(slot, counter, faces, corners, depths, width, height, cull_mode, pad, records, cuts, counts, lit,
                listed, cut):
    """Face pass: classify every face; set up the ones that need no cutting.

    Record ``f`` belongs to face ``f`` (empty unless the face is drawn uncut). Faces that
    cross a NEAR/FAR/guard-band plane get ``cut_mask[f]`` (the planes);
    :func:`count_fans` and :func:`setup_cut_faces` handle those.

    Parameters
    ----------
    faces : (M, 3) int64
        Vertex indices (a face out of range makes the call return -1).
    corners, depths
        From :func:`setup_vertices`.
    width, height : int
    cull_mode : int or (M,) uint8
        A :mod:`rasterkit.raster.kernels.cull` mode, or one per face (:func:`~rasterkit.raster.kernels.cull.per_face`).
    pad : int
        0, or 1 to pad every box by a pixel (:func:`setup_triangle`).
    records : Records
        :class:`rasterkit.raster.kernels.records.Records` with at least M records.
    cuts : Cuts
        :class:`rasterkit.raster.kernels.records.Cuts`; out: the planes cutting each face (0:
        none) in ``mask``, 0 in ``n_fan`` (filled in by :func:`count_fans`).
    counts : Counts
        :class:`rasterkit.raster.kernels.records.Counts`: ``shift`` is log2 of the rows per band
        of the binning (:data:`rasterkit.raster.kernels.bands.BAND_SHIFT`); ``bands`` and
        ``tally`` zeros in; out: drawn records per chunk and band (:func:`count_bands`), and
        faces per chunk and STATUS_* (column N_STATUS: faces cut with something left,
        counted by :func:`setup_cut_faces`).
    lit : Lit
        :class:`rasterkit.raster.kernels.records.Lit`: when on, each face that is drawn uncut or
        is to be cut gets its flat Lambert colour in ``lit.packed``; the other entries are
        left as they were.
    listed : tuple
        ``(faces_listed, n_listed)``: out, the faces drawn uncut or to be cut, in order,
        chunk ``ch``'s from ``chunk_range(M, ch)[0]`` in ``faces_listed`` (M,) int32, their
        number in ``n_listed`` (N_CHUNKS,) int64. Binning and shading visit only these.
    cut : (N_CHUNKS,) int64
        Out: per chunk, the number of faces to cut, or -1 when a face has a vertex index
        outside ``0 .. N - 1`` (checked here, where every index is read anyway, instead of
        in a pass of its own; nothing is read through such an index, and the records are
        then incomplete: the caller must not go on).

    A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused, chunks claimed
    through ``counter``).
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        cut[ch] = _setup_chunk(ch, faces, corners, depths, width, height, cull_mode, pad, records, cuts, counts,
                               lit, listed)
