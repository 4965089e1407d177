"""A sample's colours added into a band of sums (:mod:`rasterkit.raster.kernels.sample_bands`):
the sums start at the background times the number of samples, and each sample adds its
colour minus the background where a face won, visiting only the columns it may have written
(which it also resets for the next sample); with exact outlines, each pixel's first face and
the samples that saw it are noted (:func:`note_face`)."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.lit_shade import lit_untextured_rgba
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_TAGGED, smooth_rgba
from rasterkit.raster.kernels.texture_shade import mapped_rgba, pixel_rgba, texture_fields
from rasterkit.runtime.jit import kernel

__all__ = ["ALL", "EDGE", "HITS", "OTHER", "add_row", "add_textured_row", "fill_sums", "note_face"]


#: A pixel's ``state`` (:func:`note_face`): the samples that saw its first face (bits 0-8),
#: the samples that saw any face (bits 9-17); a sample saw another face, or another face's
#: edge crosses the pixel; an edge of its first face crosses the pixel.
HITS, ALL, OTHER, EDGE = 0x1FF, 9, 1 << 18, 1 << 19


@kernel(inline="always")
def note_face(first, state, ru, iu, f, hit):
    """Note face ``f`` at a pixel: seen by a sample (``hit`` 1) or crossed by an edge (0).
    The first face noted is kept in ``first``; ``state`` counts the samples and flags."""
    g = first[ru, iu]
    if g < 0:
        first[ru, iu] = f
        g = f
    if hit:
        state[ru, iu] += (1 << ALL) + (f == g)
    if f != g:
        state[ru, iu] |= OTHER
    elif not hit:
        state[ru, iu] |= EDGE


@kernel(inline="always")
def fill_sums(sums, rows, n, background):
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
def _add(sums, ru, iu, rgb, background):
    """Pixel ``iu`` of row ``ru`` of ``sums`` plus the packed colour ``rgb`` minus the background."""
    sums[ru, iu, 0] = _channel(sums[ru, iu, 0], rgb, 0, background)
    sums[ru, iu, 1] = _channel(sums[ru, iu, 1], rgb, 8, background)
    sums[ru, iu, 2] = _channel(sums[ru, iu, 2], rgb, 16, background)


@kernel(inline="always")
def _taken(lid, depth, ru, iu, exact, first, state):
    """The face at pixel ``iu`` of band row ``ru`` (-1: none); where there is one, the
    visibility and depth there reset for the next sample, and the face noted with
    ``exact``."""
    f = lid[ru, iu]
    if f >= 0:
        lid[ru, iu] = -1
        depth[ru, iu] = np.inf
        if exact:
            note_face(first, state, ru, iu, f, 1)
    return f


@kernel(inline="always")
def add_row(lid, depth, r, y, lo, hi, sample_x, sample_y, shading, background, sums, exact, first, state):
    """Add one sample's colours minus the background at the pixels ``lo .. hi`` of band row
    ``r`` (image row ``y``) into ``sums[r]``, resetting the visibility row to -1 and the
    depth row to +inf there (nothing else of them was written): ready for the next sample.
    With ``exact``, also note each pixel's faces (:func:`note_face`; ``lid`` holds faces).

    The sums start at ``n`` backgrounds (:func:`fill_sums`): a pixel no face covers adds
    nothing, and the loop visits only the columns the sample may have written. Flat colours
    without branches (LLVM vectorises the tagged loop)."""
    mode, _, _, packed, vertex_colors, _, bary, corners = shading
    ru = np.uint64(r)
    px, py = lo + 0.5 + sample_x, y + 0.5 + sample_y
    for k in range(hi - lo + 1):
        iu = np.uint64(lo) + np.uint64(k)
        f = lid[ru, iu]
        lid[ru, iu] = -1
        depth[ru, iu] = np.inf
        if exact and f >= 0:
            note_face(first, state, ru, iu, f, 1)
        if mode == SHADE_TAGGED:
            rgb = np.uint32(f)
        elif mode == SHADE_FLAT:
            rgb = packed[np.uint64(max(f, 0))]  # packed has a row: a band with records has faces
        elif f >= 0:
            rgb = smooth_rgba(f, px + k, py, vertex_colors, corners, bary)
        else:
            rgb = background
        _add(sums, ru, iu, rgb if f >= 0 else background, background)


@kernel(refcounts=False)
def add_textured_row(lid, depth, r, y, lo, hi, sample_x, sample_y, shading, background, sums, exact, first, state,
                      textures, mapped):
    """:func:`add_row` of a textured frame (``shading.mode`` SHADE_FLAT or SHADE_SMOOTH),
    each face's colour by :func:`rasterkit.raster.kernels.texture_shade.pixel_rgba` (``mapped``
    None) or ``mapped_rgba``; or, ``textures`` None, of a frame without textures whose every
    face is lit per pixel (``mapped``: its record, lights and ``phong`` set), by
    :func:`rasterkit.raster.kernels.lit_shade.lit_untextured_rgba`: the colour ``mapped_rgba``
    gives such a face, to the bit, without compiling the textured faces' code (Numba drops the
    branches of an argument typed None)."""
    mode, _, _, packed, vertex_colors, _, bary, corners = shading
    fields = texture_fields(mapped if textures is None else textures)
    ru = np.uint64(r)
    px, py = lo + 0.5 + sample_x, y + 0.5 + sample_y
    for k in range(hi - lo + 1):
        iu = np.uint64(lo) + np.uint64(k)
        f = _taken(lid, depth, ru, iu, exact, first, state)
        if f < 0:
            continue
        if textures is None:
            rgb = lit_untextured_rgba(mode, f, px + k, py, packed, vertex_colors, corners, bary, fields)
        elif mapped is None:
            rgb = pixel_rgba(mode, f, px + k, py, packed, vertex_colors, corners, bary, fields)
        else:
            rgb = mapped_rgba(mode, f, px + k, py, packed, vertex_colors, corners, bary, fields)
        _add(sums, ru, iu, rgb, background)

