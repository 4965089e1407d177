"""Binning triangle records into bands and drawing the bands in parallel.

The image is cut into *bands* (tiles the width of the image, ``BAND_HEIGHT`` rows tall);
full-width tiles compute each row's span once, where square tiles would redo it in every
tile the row crosses. Each band is owned by exactly one thread, which rasterizes every
triangle of its bin into it and then resolves its colours, so no two threads ever write
the same pixel and no locks are needed.

Order
    A bin lists its records in submission order (face order; a cut face's fan in fan
    order), so equal depths resolve the same way whatever the thread count: the image is
    bit-identical for 1 and N threads. Binning is a stable counting sort over the same
    face chunks as the setup stage (:data:`triangle.N_CHUNKS`), whose counting pass the
    setup does (:func:`rasterkit.raster.kernels.face_setup.count_bands`).

Scheduling
    :func:`draw_bands` runs once per thread *slot*; each slot takes the next band that no
    slot has claimed yet (an atomic counter, :func:`rasterkit.runtime.intrinsics.fetch_add`)
    until none are left, so a thread that is given more work, or less of the machine,
    does not hold up the others, and each slot reuses one band-sized visibility buffer.

Slot buffers apart
    A slot's band buffers (visibility rows and depth scratch) begin ``SLOT_GUARD_BYTES``
    after the previous slot's end: two threads' band buffers that touch slow the thread
    whose buffers come second (see :data:`SLOT_GUARD_BYTES`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.clear import fill_bytes
from rasterkit.runtime.intrinsics import fetch_add, prefetch_row
from rasterkit.raster.kernels.map_rows import band_maps
from rasterkit.raster.kernels.phong_rows import resolve_lit_rows
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_TAGGED, resolve_row
from rasterkit.raster.kernels.texture_shade import resolve_textured_row
from rasterkit.raster.kernels.face_setup import N_CHUNKS, ONE, chunk_range
from rasterkit.raster.kernels.triangle import raster_band
from rasterkit.raster.kernels.cutout import cutout_band

#: Rows per band, ``1 << BAND_SHIFT`` (a shift: the face pass counts bands per face, and a
#: division there cost 10 %). 32 rows of a 1920-pixel image keep the band's depth and
#: visibility rows (2 x 240 KiB) in the L2 cache while its triangles are drawn; taller bands
#: mean fewer triangles set up twice (once per band they cross) but coarser load balance.
BAND_SHIFT = 5
BAND_HEIGHT = 1 << BAND_SHIFT

#: Unused memory before each slot's rows in the visibility buffer and in the depth scratch
#: (:func:`slot_rows`), so that no two threads' band buffers are within 128 KiB of each
#: other. Measured on the fill scene with 2 threads: when the worker's buffers directly
#: followed the main thread's, in phases of minutes every band the worker drew took 1.2-1.35x
#: as long as the same band on one thread (the main thread's 1.01x), and 2 threads ran only
#: 1.65-1.7x faster than 1; swapping the buffers moved the slowness to the main thread, and
#: buffers 1, 2, 3, 8 and 16 rows (7.5 KiB each) apart cut it to 1.18, 1.14, 1.10, 1.05 and
#: 1.0x. Most likely one core's hardware prefetchers running past the end of its buffers
#: into the next ones, taking lines away from the core that is writing them.
SLOT_GUARD_BYTES = 128 * 1024


def slot_rows(width):
    """Rows per slot of the visibility buffer and the depth scratch (4-byte elements) of an
    image ``width`` pixels wide: guard rows (at least ``SLOT_GUARD_BYTES``), then the
    ``BAND_HEIGHT`` rows a band is drawn in."""
    return BAND_HEIGHT + -(-SLOT_GUARD_BYTES // (4 * width))


#: How many records ahead a band asks for the next record's rows to be fetched
#: (:func:`rasterkit.runtime.intrinsics.prefetch_row`): a triangle takes some 60 ns, a miss
#: to memory about 100, and 4-16 measured the same.
PREFETCH_AHEAD = 8


@kernel(inline="always")
def n_bands(height):
    """Number of bands of an image ``height`` rows tall."""
    return (height + BAND_HEIGHT - 1) // BAND_HEIGHT


@kernel(inline="always")
def _bin_record(t, ch, tri_box, cursor, items):
    """Put record ``t`` into the bins of the bands its box spans; 1 if drawn, else 0."""
    j_lo, j_hi = tri_box[t, 2], tri_box[t, 3]
    if j_lo > j_hi:
        return 0
    for b in range(j_lo // BAND_HEIGHT, j_hi // BAND_HEIGHT + 1):
        items[cursor[ch, b]] = t
        cursor[ch, b] += 1
    return 1


@kernel(refcounts=False)
def _bin_chunk(ch, n_faces, n_fan, fan_start, tri_box, cursor, items, listed):
    """Bin the records of face chunk ``ch`` in submission order; returns how many are drawn.

    Record ``f`` is face ``f``'s, except for a cut face, whose ``n_fan[f]`` fan records
    come next in the chunk's run of fan records from ``fan_start[ch]``. Only the faces the
    setup listed (drawn or cut, in order) are visited.
    """
    faces_listed, n_listed = listed
    start = chunk_range(n_faces, ch)[0]
    t_fan = fan_start[ch]
    drawn = 0
    for k in range(np.uint64(start), np.uint64(start + n_listed[ch])):
        f = faces_listed[k]
        if n_fan[f] == 0:
            drawn += _bin_record(f, ch, tri_box, cursor, items)
        else:
            for t in range(t_fan, t_fan + n_fan[f]):
                drawn += _bin_record(t, ch, tri_box, cursor, items)
            t_fan += n_fan[f]
    return drawn


def bin_cursors(band_counts):
    """Turn the counts of :func:`rasterkit.raster.kernels.face_setup.count_bands` into cursors, in
    place (band-major, then chunk, that is face, order), for :func:`bin_records`; returns
    ``band_start`` (n_bands + 1,) int64: bin ``b`` will be ``items[band_start[b]:
    band_start[b + 1]]``. NumPy (a few thousand counts: microseconds), so that no process
    compiles it."""
    counts = band_counts.T.ravel()  # band-major, then chunk: a copy
    ends = np.cumsum(counts)
    band_counts[...] = (ends - counts).reshape(band_counts.shape[::-1]).T
    band_start = np.empty(band_counts.shape[1] + 1, np.int64)
    band_start[0] = 0
    band_start[1:] = ends[N_CHUNKS - 1::N_CHUNKS]
    return band_start


@kernel
def bin_records(slot, counter, n_faces, n_fan, fan_start, tri_box, band_counts, listed, items, drawn):
    """Bin the records into bands, in submission order (a stable counting sort).

    Parameters
    ----------
    n_faces : int
        M; record ``f < M`` is face ``f``'s uncut triangle.
    n_fan : (M,) int8
        Records of each cut face (0 for the others).
    fan_start : (N_CHUNKS,) int64
        First fan record of each chunk (the fans of a chunk are consecutive).
    tri_box : (T, 4) int32
        Pixel boxes ``i_lo, i_hi, j_lo, j_hi``; empty ones are skipped.
    band_counts : (N_CHUNKS, n_bands) int64
        The cursors of :func:`bin_cursors`; used up.
    listed : tuple
        ``(faces_listed, n_listed)`` from :func:`rasterkit.raster.kernels.face_setup.setup_faces`:
        the faces that can have records; the others are skipped without being read.
    items : (band_start[-1],) int32
        Out: the record indices, bin after bin.
    drawn : (N_CHUNKS,) int64
        Out: records drawn (non-empty) per chunk, each counted once however many bands it
        spans.

    A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused, chunks claimed
    through ``counter``).
    """
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        drawn[ch] = _bin_chunk(ch, n_faces, n_fan, fan_start, tri_box, band_counts, items, listed)


@kernel(refcounts=False)
def clear_depth(band_depth):
    """Every depth of a band's rows to +inf (a plain loop with unsigned indices: Numba's
    slice assignment is ten times slower here)."""
    for r in range(band_depth.shape[0]):
        ru = np.uint64(r)
        for i in range(band_depth.shape[1]):
            band_depth[ru, np.uint64(i)] = np.inf


@kernel(refcounts=False)
def _clear_band(y0, y1, target, clear):
    """Clear image rows ``y0 .. y1 - 1`` of the ids (-1) and the colour (background)."""
    _, _, height, _, write_ids, ids = target
    _, color_bytes, pattern = clear
    if write_ids:
        for j in range(y0, y1):
            ju = np.uint64(j)
            for i in range(ids.shape[1]):
                ids[ju, np.uint64(i)] = -1
    if color_bytes.size:
        row_bytes = color_bytes.size // height
        fill_bytes(color_bytes, y0 * row_bytes, y1 * row_bytes, pattern)


@kernel(inline="always")
def prefetch_record(t, records, shading):
    """Ask for record ``t``'s rows and (flat shading, an uncut face) its face colour."""
    tri_xy, tri_z, tri_box = records
    mode, n_faces, _, packed, _, _, _, _ = shading
    prefetch_row(tri_box, t)
    prefetch_row(tri_xy, t)
    prefetch_row(tri_z, t)
    if (mode == SHADE_FLAT or mode == SHADE_TAGGED) and t < n_faces:
        prefetch_row(packed, t)


@kernel(refcounts=False)
def draw_bands(slot, counter, band_start, items, records, shading, target, clear, sample, lid, spans, maps, textures,
               cutouts, mapped, lights):
    """Rasterize and resolve bands, each the next one no slot has claimed yet (through
    ``counter``), until none are left; returns the number of fragments this slot
    depth-tested. A worker of :func:`rasterkit.runtime.threads.run_parallel`: slot ``slot`` draws in
    its own rows of ``lid`` and of a depth scratch.

    Parameters
    ----------
    slot : int
        This worker's slot, ``0 .. n_slots - 1``.
    counter : (1,) int64
        0 on entry; the bands are handed out from it.
    band_start, items
        From :func:`bin_records`.
    records : Records
        The triangle records (:class:`rasterkit.raster.kernels.records.Records`).
    shading : Shading
        How to colour a visible pixel (:class:`rasterkit.raster.kernels.records.Shading`,
        :func:`rasterkit.raster.kernels.shade.resolve_row`). In SHADE_TAGGED (flat colours, no
        ids) the visibility buffer holds the face's colour instead of its index.
    target : Target
        Where to draw (:class:`rasterkit.raster.kernels.records.Target`): the depth buffer
        (less-than test), the whole (H, W) float32 buffer when ``keep_depth``, else a
        scratch of ``BAND_HEIGHT`` rows per slot, (n_slots * slot_rows(W), W) float32 (slot
        ``s`` draws in the last ``BAND_HEIGHT`` of rows ``s * slot_rows(W)`` onwards),
        cleared per band, so that a draw whose depth nobody reads never writes an
        image-sized depth buffer to memory.
    clear : Clear
        :class:`rasterkit.raster.kernels.records.Clear`: when on, each band is cleared right
        before it is drawn, while its rows are in this thread's cache anyway. A depth
        scratch (not ``keep_depth``) is cleared in any case.
    sample : Sample
        :class:`rasterkit.raster.kernels.records.Sample`: where in each pixel smooth colours are
        interpolated, ``Sample(0, 0)`` at the centre. The records are those of the same
        sample point (:func:`rasterkit.raster.kernels.triangle_samples.move_records` moves a setup shared
        by the samples of a multi-sample render to each).
    lid : (n_slots, slot_rows(W), W) int32
        One visibility buffer per parallel slot (its last ``BAND_HEIGHT`` rows; the rows
        before them keep the slots apart, :data:`SLOT_GUARD_BYTES`), all -1 on entry, all
        -1 again on return (the resolve resets what it reads). The number of slots
        (normally the thread count) does not change the image, nor does the number of
        them that run.
    spans : (n_slots, 2, BAND_HEIGHT) int64
        Scratch: per slot, the columns each band row may have been written in.
    maps : Maps or None
        A vision render's maps (:class:`rasterkit.raster.kernels.records.Maps`): normals, object
        ids and metric depth of each band's rows, made right after its resolve while the
        band is in this thread's cache (:func:`rasterkit.raster.kernels.map_rows.band_maps`). None
        for other renders, which compile without that call (Numba prunes the branches of
        an argument typed None).
    textures, cutouts, mapped : Textured or None
        A textured frame's textures (:class:`rasterkit.raster.kernels.records.Textured`):
        the resolve is :func:`rasterkit.raster.kernels.texture_shade.resolve_textured_row`;
        the same record again as ``cutouts`` when some face is cut out
        (:mod:`rasterkit.raster.kernels.cutout`), as ``mapped`` when some face has a normal
        map. None for frames without them, which compile none of that code.
    lights : PixelLights or None
        An untextured frame lit per pixel (:class:`rasterkit.raster.kernels.records.PixelLights`):
        the resolve is :func:`rasterkit.raster.kernels.phong_rows.resolve_lit_rows`. None for
        other frames.

    Compiled without reference counting (nothing is allocated here, and the counts cost
    atomic operations in the per-record loop).
    """
    depth, keep_depth, height, _, _, ids = target
    do_clear = clear.on
    guard = lid.shape[1] - BAND_HEIGHT  # unused rows before each slot's band rows
    band_lid = lid[slot, guard:]
    scratch_row = np.int64(slot) * lid.shape[1] + guard  # this slot's depth scratch rows
    row_lo, row_hi = spans[slot, 0], spans[slot, 1]
    fragments = 0
    while True:  # claim the next piece until none is left
        b = fetch_add(counter, 0, 1)
        if b >= band_start.size - 1:
            break
        y0 = b * BAND_HEIGHT
        y1 = min(y0 + BAND_HEIGHT, height)
        first_row = y0 if keep_depth else scratch_row
        band_depth = depth[first_row: first_row + y1 - y0]
        if do_clear:
            if keep_depth:
                clear_depth(band_depth)
            _clear_band(y0, y1, target, clear)
        drawn = band_start[b] != band_start[b + 1]
        if drawn:
            if not keep_depth:
                clear_depth(band_depth)
            fragments += _draw_band(b, y0, y1, band_start, items, records, shading, target, sample, band_lid,
                                    band_depth, row_lo, row_hi, cutouts, textures is None and lights is None)
            if textures is not None:
                resolve_textured_rows(y0, y1, shading, target, sample, band_lid, row_lo, row_hi, textures, mapped)
            elif lights is not None:
                resolve_lit_rows(y0, y1, shading, target, sample, band_lid, row_lo, row_hi, lights)
        if maps is not None:
            band_maps(ids, y0, y1, maps, band_depth, drawn)
    return fragments


@kernel(refcounts=False)
def _draw_band(b, y0, y1, band_start, items, records, shading, target, sample, band_lid, band_depth, row_lo, row_hi,
               cutouts, resolve):
    """Rasterize the records of bin ``b`` into rows ``y0 .. y1 - 1`` (``band_lid``,
    ``band_depth``: the band's visibility and depth rows, the depth cleared) and, when
    ``resolve``, resolve them (:func:`draw_bands`' arguments); returns the number of
    fragments depth-tested. Compiled on its own: :func:`draw_bands` with and without a
    vision render's maps or textures is a small loop around this one function, so they do
    not compile the band's drawing again (cut-out faces do)."""
    tri_xy, tri_z, tri_box = records
    mode, n_faces, fan_face, packed, vertex_colors, _, bary, corners = shading
    _, _, _, color, write_ids, ids = target
    sample_x, sample_y = sample.x / ONE, sample.y / ONE  # pixels, for the smooth colours
    width = band_lid.shape[1]
    for r in range(BAND_HEIGHT):
        row_lo[r], row_hi[r] = width, -1
    fragments = 0
    end = band_start[b + 1]
    for k in range(band_start[b], end):
        if k + PREFETCH_AHEAD < end:
            prefetch_record(items[k + PREFETCH_AHEAD], records, shading)
        t = items[k]
        face = t if t < n_faces else fan_face[t - n_faces]
        # what the visibility buffer holds: the face, or (SHADE_TAGGED) its colour, so
        # the resolve need not look each pixel's colour up
        tag = (packed[face] & 0xFFFFFF) if mode == SHADE_TAGGED else face
        if cutouts is not None and cutouts.face_alpha[face] >= 0:  # a cut-out face: its alpha decides
            fragments += cutout_band(t, tag, face, tri_xy, tri_z, tri_box, y0, y1, sample, band_depth, band_lid,
                                     row_lo, row_hi, bary, cutouts)
        else:
            fragments += raster_band(t, tag, tri_xy, tri_z, tri_box, y0, y1, band_depth, band_lid, row_lo, row_hi)
    if resolve:
        for r in range(y1 - y0):
            resolve_row(mode, band_lid, r, y0 + r, row_lo[r], row_hi[r], sample_x, sample_y, packed, vertex_colors,
                        corners, bary, color, write_ids, ids)
    return fragments


@kernel(refcounts=False)
def resolve_textured_rows(y0, y1, shading, target, sample, band_lid, row_lo, row_hi, textures, mapped):
    """Resolve rows ``y0 .. y1 - 1`` of a textured frame
    (:func:`rasterkit.raster.kernels.texture_shade.resolve_textured_row`)."""
    mode, _, _, packed, vertex_colors, _, bary, corners = shading
    _, _, _, color, write_ids, ids = target
    sample_x, sample_y = sample.x / ONE, sample.y / ONE
    for r in range(y1 - y0):
        resolve_textured_row(mode, band_lid, r, y0 + r, row_lo[r], row_hi[r], sample_x, sample_y, packed,
                             vertex_colors, corners, bary, color, write_ids, ids, textures, mapped)
