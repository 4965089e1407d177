"""Every sample of a pinhole multi-sample render drawn band by band, averaged on the way.

The samples of a pinhole render share one triangle setup (:mod:`rasterkit._shared_triangles`):
they differ only in where each pixel is sampled. :func:`draw_sample_bands` draws them all in
one pass over the bands: each band (claimed by one thread, as in
:func:`rasterkit.kernels.tiles.draw_bands`) is rasterized at each sample point in turn
(:func:`rasterkit.kernels.triangle_samples.raster_band_at`), and each sample's colours are added at
once into a band of 16-bit sums. The sums start at the background times the number of
samples, and a sample adds its colour minus the background where a face won, visiting only
the columns it may have written (which it also resets for the next sample). After the last
sample the band's average, rounded as :func:`rasterkit.kernels.accumulate.average_samples`
rounds it, is written into the image. The band's depth, visibility and sum rows stay in the
thread's cache from one sample to the next, where a frame per sample writes a whole image
and reads it back (:mod:`rasterkit._accumulate`) for every sample. The sums are those of the
frames the samples draw one by one (:func:`rasterkit.kernels.shade.resolve_row` at the same
points), so the image is the same, to the bit, and does not depend on the thread count.
"""

from __future__ import annotations

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.clear import fill_bytes
from rasterkit.kernels.intrinsics import fetch_add
from rasterkit.kernels.records import Sample
from rasterkit.kernels.setup import ONE
from rasterkit.kernels.shade import SHADE_FLAT, SHADE_TAGGED, _smooth_rgba
from rasterkit.kernels.tiles import BAND_HEIGHT, PREFETCH_AHEAD, _clear_depth, _prefetch_record
from rasterkit.kernels.triangle_samples import raster_band_at


@kernel(inline="always")
def _fill_sums(sums, rows, n, background):
    """The first ``rows`` rows of ``sums`` to ``n`` times the background, channel by
    channel: what ``n`` samples that no face covers add up to."""
    for c in range(3):
        value = np.uint16(n * ((background >> (8 * c)) & 0xFF))
        for r in range(rows):
            ru = np.uint64(r)
            for i in range(sums.shape[1]):
                sums[ru, np.uint64(i), c] = value


@kernel(inline="always")
def _channel(sum_value, rgb, shift, background):
    """``sum_value`` plus channel ``shift`` of ``rgb`` minus that of ``background``, modulo
    2**16 (the sums end in 0 .. 256 * 255, whatever the order of the terms)."""
    change = np.int64((rgb >> shift) & 0xFF) - np.int64((background >> shift) & 0xFF)
    return np.uint16((np.int64(sum_value) + change) & 0xFFFF)


@kernel(inline="always")
def _add_row(lid, depth, r, y, lo, hi, sample_x, sample_y, shading, background, sums):
    """Add one sample's colours minus the background at the pixels ``lo .. hi`` of band row
    ``r`` (image row ``y``) into ``sums[r]``, resetting the visibility row to -1 and the
    depth row to +inf there (nothing else of them was written): ready for the next sample.

    The sums start at ``n`` backgrounds (:func:`_fill_sums`): a pixel no face covers adds
    nothing, and the loop visits only the columns the sample may have written. Flat colours
    without branches (LLVM vectorises the tagged loop)."""
    mode, _, _, packed, vertex_colors, faces, bary = shading
    ru = np.uint64(r)
    px, py = lo + 0.5 + sample_x, y + 0.5 + sample_y
    for k in range(hi - lo + 1):
        iu = np.uint64(lo) + np.uint64(k)
        f = lid[ru, iu]
        lid[ru, iu] = -1
        depth[ru, iu] = np.inf
        if mode == SHADE_TAGGED:
            rgb = np.uint32(f)
        elif mode == SHADE_FLAT:
            rgb = packed[np.uint64(max(f, 0))]  # packed has a row: a band with records has faces
        elif f >= 0:
            rgb = _smooth_rgba(f, px + k, py, vertex_colors, faces, bary)
        else:
            rgb = background
        rgb = rgb if f >= 0 else background
        sums[ru, iu, 0] = _channel(sums[ru, iu, 0], rgb, 0, background)
        sums[ru, iu, 1] = _channel(sums[ru, iu, 1], rgb, 8, background)
        sums[ru, iu, 2] = _channel(sums[ru, iu, 2], rgb, 16, background)


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
def draw_sample_bands(slot, counter, band_start, items, records, shading, depth, color, clear, samples, lid, spans):
    """Draw the averaged samples into ``color``, band by band, each band the next one no
    slot has claimed (through ``counter``). A worker of :func:`rasterkit._jit.run_parallel`.

    Parameters
    ----------
    band_start, items, records, shading
        As for :func:`rasterkit.kernels.tiles.draw_bands`, from a setup with padded boxes
        (``shading.mode`` SHADE_FLAT, SHADE_TAGGED or SHADE_SMOOTH).
    depth : (n_slots * slot_rows(W), W) float32
        The depth scratch, ``BAND_HEIGHT`` rows per slot as in ``draw_bands``.
    color : (H, W, 3) uint8
        Out: the average of the samples.
    clear : Clear
        :class:`rasterkit.kernels.records.Clear` (on): fills the bands no face reaches.
    samples : Samples
        :class:`rasterkit.kernels.records.Samples`: the sample points, the background, the
        rounding of the average, and the sums scratch.
    lid, spans
        As for ``draw_bands`` (``lid`` all -1 on entry and on return).
    """
    offsets, background, scale, bias, sums = samples
    tri_xy, tri_z, _ = records
    mode, n_faces, fan_face, packed, _, _, _ = shading
    width = lid.shape[2]
    guard = lid.shape[1] - BAND_HEIGHT
    band_lid = lid[slot, guard:]
    band_sums = sums[slot, sums.shape[1] - BAND_HEIGHT:]
    scratch_row = np.int64(slot) * lid.shape[1] + guard
    row_lo, row_hi = spans[slot, 0], spans[slot, 1]
    height = color.shape[0]
    row_bytes = color.shape[1] * 3
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
        _fill_sums(band_sums, y1 - y0, offsets.shape[0], background)
        _clear_depth(band_depth)  # once: each sample resets what it wrote (_add_row)
        for s in range(offsets.shape[0]):
            sample = Sample(offsets[s, 0], offsets[s, 1])
            for r in range(BAND_HEIGHT):
                row_lo[r], row_hi[r] = width, -1
            for k in range(band_start[b], end):  # as draw_bands, each record moved to the sample
                if k + PREFETCH_AHEAD < end:
                    _prefetch_record(items[k + PREFETCH_AHEAD], records, shading)
                t = items[k]
                face = t if t < n_faces else fan_face[t - n_faces]
                tag = (packed[face] & 0xFFFFFF) if mode == SHADE_TAGGED else face
                fragments += raster_band_at(t, tag, tri_xy, tri_z, sample, y0, y1, band_depth, band_lid, row_lo,
                                            row_hi)
            sample_x, sample_y = offsets[s, 0] / ONE, offsets[s, 1] / ONE
            for r in range(y1 - y0):
                _add_row(band_lid, band_depth, r, y0 + r, row_lo[r], row_hi[r], sample_x, sample_y, shading,
                         background, band_sums)
        _average_rows(band_sums, y0, y1, color, scale, bias)
    return fragments
