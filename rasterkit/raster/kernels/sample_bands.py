"""Every sample of a pinhole multi-sample render drawn band by band, averaged on the way.

The samples of a pinhole render share one triangle setup (:mod:`rasterkit.raster.shared_samples`):
they differ only in where each pixel is sampled. :func:`draw_sample_bands` draws them all in
one pass over the bands: each band (claimed by one thread, as in
:func:`rasterkit.raster.kernels.bands.draw_bands`) is rasterized at each sample point in turn
(:func:`rasterkit.raster.kernels.triangle_samples.raster_band_at`), and each sample's colours are added at
once into a band of 16-bit sums (:mod:`rasterkit.raster.kernels.sample_rows`). The sums start
at the background times the number of samples, and a sample adds its colour minus the
background where a face won, visiting only the columns it may have written (which it also
resets for the next sample). After the last
sample the band's average, rounded as :func:`rasterkit.raster.kernels.accumulate.average_samples`
rounds it, is written into the image. The band's depth, visibility and sum rows stay in the
thread's cache from one sample to the next, where a frame per sample writes a whole image
and reads it back (:mod:`rasterkit.raster.accumulate`) for every sample. The sums are those of the
frames the samples draw one by one (:func:`rasterkit.raster.kernels.shade.resolve_row` at the same
points), so the image is the same, to the bit, and does not depend on the thread count.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.clear import fill_bytes
from rasterkit.raster.kernels.coverage import pixel_area
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.records import Sample
from rasterkit.raster.kernels.face_setup import ONE
from rasterkit.raster.kernels.shade import SHADE_SMOOTH, SHADE_TAGGED, smooth_rgba
from rasterkit.raster.kernels.bands import BAND_HEIGHT, PREFETCH_AHEAD, clear_depth, prefetch_record
from rasterkit.raster.kernels.lit_shade import lit_untextured_rgba
from rasterkit.raster.kernels.sample_rows import (
    ALL, EDGE, HITS, OTHER, add_row, add_textured_row, fill_sums, note_face)
from rasterkit.raster.kernels.texture_shade import texture_fields
from rasterkit.raster.kernels.triangle_samples import raster_band_at
from rasterkit.raster.kernels.cutout import cutout_band_at


@kernel(inline="always")
def _note_edge(xa, ya, xb, yb, t, y0, y1, width, first, state):
    """Note face ``t`` in every pixel of rows ``y0 .. y1 - 1`` that its edge from ``(xa,
    ya)`` to ``(xb, yb)`` (fixed point) passes through or within a fixed-point unit of: row
    by row, the columns between the edge's x where it enters and leaves the row."""
    if ya > yb:
        xa, ya, xb, yb = xb, yb, xa, ya
    for j in range(max(ya >> 8, y0), min(yb >> 8, y1 - 1) + 1):
        xs, xe = np.float64(xa), np.float64(xb)
        if yb > ya:
            slope = (xb - xa) / np.float64(yb - ya)
            xs = xa + slope * (max(ya, j << 8) - ya)
            xe = xa + slope * (min(yb, (j << 8) + 256) - ya)
        lo = max(np.int64(np.floor((min(xs, xe) - 1.0) / 256.0)), 0)
        hi = min(np.int64(np.floor((max(xs, xe) + 1.0) / 256.0)), width - 1)
        for i in range(lo, hi + 1):
            note_face(first, state, np.uint64(j - y0), np.uint64(i), t, 0)


@kernel(refcounts=False)
def _note_boundaries(items, start, end, n_faces, records, faces, corners, neighbours, y0, y1, width, first, state):
    """Note the band's uncut faces (record ``t`` < ``n_faces`` is face ``t``) in the pixels
    that their sides on an outline cross: a pixel that a face covers in part may hold none
    of the sample points (a corner or a sliver between them), or all of them. A side is on
    an outline unless another drawn uncut face shares it (``neighbours``, the faces'
    :func:`rasterkit.mesh.side_neighbours`): a pixel that two such faces share is theirs."""
    tri_xy, _, tri_box = records
    for k in range(start, end):
        t = items[k]
        if t >= n_faces:
            continue
        outline = 0  # the face's sides on an outline, a bit each
        for e in range(3):
            g = neighbours[t, e]
            if g < 0 or tri_box[g, 2] > tri_box[g, 3]:
                outline |= 1 << e
        if outline == 0:  # most faces of a closed mesh
            continue
        # the record's corners are the face's, 1 and 2 swapped when it is counter-clockwise
        # on screen (rasterkit.raster.kernels.face_setup.setup_triangle): its side c is the face's 2 - c
        v1 = faces[t, 1]
        swapped = corners[v1, 1] != tri_xy[t, 2] or corners[v1, 2] != tri_xy[t, 3]
        for c in range(3):
            if not outline & (1 << (2 - c if swapped else c)):
                continue
            d = (c + 1) % 3
            _note_edge(np.int64(tri_xy[t, 2 * c]), np.int64(tri_xy[t, 2 * c + 1]), np.int64(tri_xy[t, 2 * d]),
                       np.int64(tri_xy[t, 2 * d + 1]), t, y0, y1, width, first, state)


@kernel
def _unseen_rgb(f, i, j, background, records, shading, textures, mapped):
    """Face ``f``'s packed colour in pixel ``(i, j)`` that no sample saw (a corner or a sliver
    between the sample points): its flat colour, or its smooth, textured or lit-per-pixel
    colour at its corner in the pixel (else at the pixel's centre)."""
    mode, _, _, packed, vertex_colors, _, bary, corners = shading
    per_pixel = mapped is not None and mapped.lights.shape[0] > 0 and mapped.phong  # every face lit per pixel
    if mode != SHADE_SMOOTH and not per_pixel and (textures is None or textures.face_texture[f] < 0):
        return packed[np.uint64(f)]
    tri_xy = records[0]
    cx, cy = (i << 8) + 128, (j << 8) + 128
    for k in range(3):
        x, y = np.int64(tri_xy[f, 2 * k]), np.int64(tri_xy[f, 2 * k + 1])
        if (x >> 8) == i and (y >> 8) == j:
            cx, cy = x, y
    if textures is None and mapped is not None:  # every face lit per pixel, none textured
        return lit_untextured_rgba(mode, f, cx / 256.0, cy / 256.0, packed, vertex_colors, corners, bary,
                                   texture_fields(mapped))
    if textures is None:
        return smooth_rgba(f, cx / 256.0, cy / 256.0, vertex_colors, corners, bary)
    return _textured_point(f, cx / 256.0, cy / 256.0, background, shading, textures, mapped)


@kernel(inline="always")
def _textured_point(f, x, y, background, shading, textures, mapped):
    """The packed colour of face ``f`` of a textured frame at raster point ``(x, y)``, worked
    out by :func:`add_textured_row` on a band of one pixel (its sample point placed at ``(x,
    y)``: exact, the offsets are multiples of 1/256): the band rows' own compiled kernel, not
    a second copy of the texture and lighting code (it took 13 s to compile). The scratch
    arrays are made and sliced as :func:`draw_sample_bands` makes its bands, so that the call
    has the band rows' argument types and compiles nothing more."""
    lid = np.full((1, 1, 1), f, np.int32)
    depth = np.full((1, 1), np.inf, np.float32)
    sums = np.empty((1, 1, 1, 3), np.uint16)
    for c in range(3):  # the background: the row adds the colour minus the background
        sums[0, 0, 0, c] = (background >> (8 * c)) & 0xFF
    marks = np.zeros((1, 1, 1), np.int32)
    band_sums = sums[0, 0:]
    zero = np.int64(0)
    add_textured_row(lid[0, 0:], depth[0:1], zero, zero, zero, zero, x - 0.5, y - 0.5, shading, background,
                      band_sums, marks.shape[0] < 0, marks[0, 0:], marks[0, 0:], textures, mapped)
    return np.uint32(255 << 24) | np.uint32(band_sums[0, 0, 0]) | (np.uint32(band_sums[0, 0, 1]) << 8) | \
        (np.uint32(band_sums[0, 0, 2]) << 16)


@kernel
def _exact_pixel(color, sums, ru, i, y, f, hits, n, background, records, shading, textures, mapped):
    """Pixel ``(i, y)`` (band row ``ru``) of face ``f``, seen by ``hits`` of the ``n`` samples
    and by the background otherwise: the background plus the face's exact share of the
    pixel (:func:`rasterkit.raster.kernels.coverage.pixel_area`) times its colour (the mean of its
    samples, or :func:`_unseen_rgb`) minus the background. Into an RGBA ``color`` (a
    transparent background: ``background`` 0), the colour straight and the share as alpha."""
    tri_xy = records[0]
    area = pixel_area(np.int64(tri_xy[f, 0]), np.int64(tri_xy[f, 1]), np.int64(tri_xy[f, 2]), np.int64(tri_xy[f, 3]),
                      np.int64(tri_xy[f, 4]), np.int64(tri_xy[f, 5]), i, y)
    rgb = _unseen_rgb(f, i, y, background, records, shading, textures, mapped) if hits == 0 else np.uint32(0)
    rgba = color.shape[2] == 4
    alpha = np.uint8(255.0 * area + 0.5)
    yu, iu = np.uint64(y), np.uint64(i)
    for c in range(3):
        back = np.float64((background >> (8 * c)) & 0xFF)
        if hits > 0:
            face = (np.float64(sums[ru, iu, c]) - (n - hits) * back) / hits
        else:
            face = np.float64((rgb >> (8 * c)) & 0xFF)
        value = (face if alpha else 0.0) if rgba else back + area * (face - back)
        color[yu, iu, c] = np.uint8(min(max(value + 0.5, 0.0), 255.0))
    if rgba:
        color[yu, iu, 3] = alpha


@kernel(inline="always")
def _average_exact_rows(sums, y0, y1, color, scale, bias, n, background, first, state, records, shading, textures,
                        mapped):
    """:func:`_average_rows`, with the pixels whose samples saw one uncut face and the
    background (or that one face's edges cross and nothing else) made exact
    (:func:`_exact_pixel`). Into an RGBA ``color``, the other pixels as
    :func:`rasterkit.raster.kernels.accumulate.average_samples_rgba` makes them of opaque faces."""
    tri_box = records[2]
    rgba = color.shape[2] == 4
    for r in range(y1 - y0):
        ru, yu = np.uint64(r), np.uint64(y0 + r)
        for i in range(color.shape[1]):
            iu = np.uint64(i)
            f, st = first[ru, iu], state[ru, iu]
            hits, seen = st & HITS, (st >> ALL) & HITS
            if f >= 0 and not st & OTHER and (hits < n or st & EDGE) and tri_box[f, 2] <= tri_box[f, 3]:
                _exact_pixel(color, sums, ru, np.int64(i), np.int64(y0 + r), f, hits, n, background, records,
                             shading, textures, mapped)
            elif rgba:
                a = np.uint32(255 * seen)
                for c in range(3):
                    color[yu, iu, c] = (np.uint32(sums[ru, iu, c]) * 255 + a // 2) // a if a > 0 else 0
                color[yu, iu, 3] = (a + n // 2) // n
            else:
                for c in range(3):
                    color[yu, iu, c] = int(sums[ru, iu, c] * scale + bias)


@kernel(refcounts=False)
def _finish_exact(items, start, end, records, shading, corners, neighbours, y0, y1, first, state, sums, color,
                  scale, bias, n, background, textures, mapped):
    """A band's outlines noted (:func:`_note_boundaries`) and its average written
    (:func:`_average_exact_rows`): kernels of their own, compiled once (inlined into the
    band loop, they made the first multi-sample render compile 6 s longer)."""
    _note_boundaries(items, start, end, shading.n_faces, records, shading.faces, corners, neighbours, y0, y1,
                     color.shape[1], first, state)
    _average_exact_rows(sums, y0, y1, color, scale, bias, n, background, first, state, records, shading, textures,
                        mapped)


@kernel(inline="always")
def _average_rows(sums, y0, y1, color, scale, bias):
    """Image rows ``y0 .. y1 - 1`` of ``color`` (H, W, 3) from their band of sums."""
    for r in range(y1 - y0):
        ru, yu = np.uint64(r), np.uint64(y0 + r)
        for i in range(color.shape[1]):
            iu = np.uint64(i)
            for c in range(3):
                color[yu, iu, c] = int(sums[ru, iu, c] * scale + bias)


@kernel(refcounts=False)
def draw_sample_bands(slot, counter, band_start, items, records, shading, depth, color, clear, samples, lid, spans,
                      textures, cutouts, mapped):
    """Draw the averaged samples into ``color``, band by band, each band the next one no
    slot has claimed (through ``counter``). A worker of :func:`rasterkit.runtime.threads.run_parallel`.

    Parameters
    ----------
    band_start, items, records, shading
        As for :func:`rasterkit.raster.kernels.bands.draw_bands`, from a setup with padded boxes
        (``shading.mode`` SHADE_FLAT, SHADE_TAGGED or SHADE_SMOOTH).
    depth : (n_slots * slot_rows(W), W) float32
        The depth scratch, ``BAND_HEIGHT`` rows per slot as in ``draw_bands``.
    color : (H, W, 3) uint8
        Out: the average of the samples; (H, W, 4) with ``exact`` over a transparent black
        background (``samples.background`` 0): straight colour and alpha.
    clear : Clear
        :class:`rasterkit.raster.kernels.records.Clear` (on): fills the bands no face reaches.
    samples : Samples
        :class:`rasterkit.raster.kernels.records.Samples`: the sample points, the background, the
        rounding of the average, the sums scratch, and whether (``exact``) the pixels where
        the samples saw one face and the background get that face's exact share of the
        pixel (``shading.mode`` then not SHADE_TAGGED: the visibility rows hold faces).
    lid, spans, textures, cutouts, mapped
        As for ``draw_bands`` (``lid`` all -1 on entry and on return; None for a frame without
        textures, cut-outs or normal maps, which compiles none of that code). ``mapped``
        without ``textures``: a frame without textures whose every face is lit per pixel
        (:func:`~rasterkit.raster.kernels.sample_rows.add_textured_row`).
    """
    offsets, background, scale, bias, sums, exact, first, state, corners, neighbours = samples
    tri_xy, tri_z, _ = records
    mode, n_faces, fan_face, packed, _, _, _, _ = shading
    width = lid.shape[2]
    guard = lid.shape[1] - BAND_HEIGHT
    band_lid = lid[slot, guard:]
    band_sums = sums[slot, sums.shape[1] - BAND_HEIGHT:]
    band_first, band_state = first[slot, first.shape[1] - BAND_HEIGHT:], state[slot, state.shape[1] - BAND_HEIGHT:]
    n = offsets.shape[0]
    scratch_row = np.int64(slot) * lid.shape[1] + guard
    row_lo, row_hi = spans[slot, 0], spans[slot, 1]
    height = color.shape[0]
    row_bytes = color.shape[1] * color.shape[2]
    fragments = 0
    while True:  # claim the next piece until none is left
        b = fetch_add(counter, 0, 1)
        if b >= band_start.size - 1:
            break
        y0 = b * BAND_HEIGHT
        y1 = min(y0 + BAND_HEIGHT, height)
        if band_start[b] == band_start[b + 1]:  # every sample is the background
            fill_bytes(clear.color_bytes, y0 * row_bytes, y1 * row_bytes, clear.pattern)
            continue
        band_depth = depth[scratch_row: scratch_row + y1 - y0]
        end = band_start[b + 1]
        fill_sums(band_sums, y1 - y0, n, background)
        clear_depth(band_depth)  # once: each sample resets what it wrote (add_row)
        if exact:
            band_first[: y1 - y0] = -1
            band_state[: y1 - y0] = 0
        for s in range(n):
            sample = Sample(offsets[s, 0], offsets[s, 1])
            for r in range(BAND_HEIGHT):
                row_lo[r], row_hi[r] = width, -1
            for k in range(band_start[b], end):  # as draw_bands, each record moved to the sample
                if k + PREFETCH_AHEAD < end:
                    prefetch_record(items[k + PREFETCH_AHEAD], records, shading)
                t = items[k]
                face = t if t < n_faces else fan_face[t - n_faces]
                tag = (packed[face] & 0xFFFFFF) if mode == SHADE_TAGGED else face
                if cutouts is not None and cutouts.face_alpha[face] >= 0:  # a cut-out face
                    fragments += cutout_band_at(t, tag, face, tri_xy, tri_z, sample, y0, y1, band_depth, band_lid,
                                                row_lo, row_hi, shading.bary, cutouts)
                else:
                    fragments += raster_band_at(t, tag, tri_xy, tri_z, sample, y0, y1, band_depth, band_lid, row_lo,
                                                row_hi)
            sample_x, sample_y = offsets[s, 0] / ONE, offsets[s, 1] / ONE
            for r in range(y1 - y0):
                if textures is None and mapped is None:
                    add_row(band_lid, band_depth, r, y0 + r, row_lo[r], row_hi[r], sample_x, sample_y, shading,
                             background, band_sums, exact, band_first, band_state)
                else:
                    add_textured_row(band_lid, band_depth, r, y0 + r, row_lo[r], row_hi[r], sample_x, sample_y,
                                      shading, background, band_sums, exact, band_first, band_state, textures,
                                      mapped)
        if exact:
            _finish_exact(items, band_start[b], end, records, shading, corners, neighbours, y0, y1, band_first,
                          band_state, band_sums, color, scale, bias, n, background, textures, mapped)
        else:
            _average_rows(band_sums, y0, y1, color, scale, bias)
    return fragments
