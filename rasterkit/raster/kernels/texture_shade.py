"""Textured colours of visible pixels: the band worker's resolve for a frame whose faces have
texture maps (:class:`rasterkit.raster.kernels.records.Textured`).

Per pixel of a textured face, at its sample point ``(px, py)`` (raster pixels):

1. The perspective-correct barycentrics ``b_k = a_k px + b_k py + c_k`` from the face's rows
   (:func:`rasterkit.raster.kernels.shade.bary_matrices`), known up to a common factor ``s =
   b_0 + b_1 + b_2``; the texture coordinates ``u = U / s`` with ``U = sum_k b_k u_k`` (and
   ``v`` alike).
2. Their exact screen-space derivatives, the quotient rule on those affine functions:
   ``du/dx = (sum_k a_k u_k - u sum_k a_k) / s`` (``d/dy`` with the ``b_k``), which give
   OpenGL's level of detail (:func:`rasterkit.material.kernels.sample.texture_lod`) when
   the texture is filtered with mipmaps.
3. The texture's colour at (u, v) in linear light
   (:func:`rasterkit.material.kernels.sample.sample`), encoded to sRGB once
   (:func:`rasterkit.raster.kernels.surface.encode`) and multiplied by the face's tint (its material's ``diffuse``, 0..255)
   and the Lambert factor: per face for flat shading, interpolated perspective-correctly
   from the corners for smooth shading, as an untextured face's colour is lit.

A face with a normal map is lit per pixel instead (:func:`rasterkit.raster.kernels.surface.normal_terms`): its normal (the
face's, or its corners' interpolated) bent by the map in the frame of its tangent and
bitangent (the directions of growing ``u`` and ``v``), Lambert's law of that normal.

Faces without a texture (``face_texture[f] < 0``) are coloured as in
:func:`rasterkit.raster.kernels.shade.resolve_row`.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.kernels.sample import lookup, texture_lod
from rasterkit.raster.kernels.lit_shade import lit_face, lit_rgba, lit_run
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_NONE, SHADE_SMOOTH, put_rgba, smooth_rgba, to_u8
from rasterkit.raster.kernels.surface import (
    diffuse, encode, face_terms, mapped_shade, normal_terms, surface, texture_fields,
)
from rasterkit.runtime.intrinsics import stack_floats
from rasterkit.runtime.jit import kernel

#: Pixels of a run that :func:`textured_run` prepares at a time (its scratch: 4 floats each).
RUN_CHUNK = 32
_RUN_SCRATCH = 4 * RUN_CHUNK

@kernel(inline="always")
def _packed(r, g, b, tint, shade, table):
    """The linear colour (r, g, b) encoded to sRGB, times ``tint`` (0..255) and ``shade``, packed
    (a loop over the channels: one copy of the encoding to compile, not three)."""
    rgb = (r, g, b)
    packed = 255 << 24
    for c in range(3):
        packed |= to_u8(encode(table, rgb[c]) * tint[c] * shade) << (8 * c)
    return np.uint32(packed)


@kernel(inline="always")
def _gouraud(terms, x, y, inv):
    """The Lambert factor of a face without a normal map: its own (flat) or its corners'
    interpolated (smooth)."""
    i_plane, smooth, shade = terms[4], terms[5], terms[6]
    return (i_plane[0] * x + i_plane[1] * y + i_plane[2]) * inv if smooth else shade


@kernel(inline="always")
def face_pixel(t, terms, x, y, fields):
    """The packed colour at raster point (x, y) of a face with texture ``t`` and no normal
    map, whose :func:`~rasterkit.raster.kernels.surface.face_terms` are ``terms``."""
    inv, u, v, derivatives = surface(terms, x, y)
    r, g, b = diffuse(t, u, v, derivatives, fields)
    return _packed(r, g, b, terms[7], _gouraud(terms, x, y, inv), fields[15])


@kernel(refcounts=False)
def textured_run(color, j, i0, n, t, terms, x0, y, texels, levels, samplers, transforms, decode, table):
    """Colour ``n`` pixels of row ``j`` from column ``i0`` on, of a face with texture ``t`` and
    no normal map whose :func:`~rasterkit.raster.kernels.surface.face_terms` are ``terms``; ``(x0, y)`` the first one's sample
    point. :func:`face_pixel` in two passes over up to :data:`RUN_CHUNK` pixels at a time:
    the texture coordinates, level of detail and Lambert factor of each pixel into scratch
    on the stack (a loop of independent arithmetic without branches, which LLVM vectorises),
    then the lookups (inlined: a kernel of its own, called once per run, compiles the lookup
    in one place). The level of detail is worked out for every filter (only trilinear reads
    it), and the texture's settings are read per pixel inside the lookup (see
    :func:`rasterkit.material.kernels.sample.lookup`): no branch on a setting in the loops."""
    scratch = stack_floats(_RUN_SCRATCH)
    chunk = np.uint64(RUN_CHUNK)
    tint = terms[7]
    for start in range(0, n, RUN_CHUNK):
        m = np.uint64(min(RUN_CHUNK, n - start))
        for q in range(m):
            x = x0 + np.float64(start + q)
            inv, u, v, d = surface(terms, x, y)
            scratch[q] = u
            scratch[chunk + q] = v
            scratch[2 * chunk + q] = texture_lod(levels, samplers, transforms, t, d[0], d[1], d[2], d[3])
            scratch[3 * chunk + q] = _gouraud(terms, x, y, inv)
        for q in range(m):  # the linear colour in place of (u, v, lod)
            r, g, b, _ = lookup(texels, levels, samplers, transforms, decode, t, scratch[q], scratch[chunk + q],
                                scratch[2 * chunk + q])
            scratch[q], scratch[chunk + q], scratch[2 * chunk + q] = r, g, b
        for q in range(m):
            put_rgba(color, j, i0 + np.uint64(start) + q, _packed(scratch[q], scratch[chunk + q],
                                                                  scratch[2 * chunk + q], tint, scratch[3 * chunk + q],
                                                                  table))


@kernel(inline="always")
def mapped_pixel(f, t, terms, normal, x, y, fields):
    """:func:`face_pixel` of a frame with normal maps: face ``f``'s (whose
    :func:`~rasterkit.raster.kernels.surface.normal_terms` are ``normal``) bends its normal where it has one."""
    inv, u, v, derivatives = surface(terms, x, y)
    r, g, b = diffuse(t, u, v, derivatives, fields)
    m = fields[16][f]  # read here, not once per face: see rasterkit.material.kernels.sample.lookup
    shade = mapped_shade(m, normal, x, y, inv, u, v, derivatives, fields) if m >= 0 else _gouraud(terms, x, y, inv)
    return _packed(r, g, b, terms[7], shade, fields[15])


@kernel(inline="always")
def pixel_rgba(mode, f, px, py, packed, vertex_colors, corners, bary, fields):
    """The colour of face ``f`` at raster point (px, py): textured where it has a texture,
    else flat (``packed``) or smooth (``vertex_colors`` through ``corners``); ``fields``:
    :func:`~rasterkit.raster.kernels.surface.texture_fields` of a frame without normal maps."""
    t = fields[5][f]
    if t >= 0:
        return face_pixel(t, face_terms(f, bary, fields), px, py, fields)
    if mode == SHADE_SMOOTH:
        return smooth_rgba(f, px, py, vertex_colors, corners, bary)
    return packed[f]


@kernel(inline="always")
def mapped_rgba(mode, f, px, py, packed, vertex_colors, corners, bary, fields):
    """:func:`pixel_rgba` of a frame with normal maps or lights (then
    :func:`~rasterkit.raster.kernels.lit_shade.lit_rgba` where the face is lit per pixel)."""
    t = fields[5][f]
    if lit_face(fields, t):
        return lit_rgba(mode, f, t, px, py, packed, vertex_colors, corners, bary, fields)
    if t >= 0:
        terms = face_terms(f, bary, fields)
        return mapped_pixel(f, t, terms, normal_terms(f, terms[0], fields), px, py, fields)
    if mode == SHADE_SMOOTH:
        return smooth_rgba(f, px, py, vertex_colors, corners, bary)
    return packed[f]


@kernel(refcounts=False)
def resolve_textured_row(mode, lid, r, j, lo, hi, sample_x, sample_y, packed, vertex_colors, corners, bary, color,
                         write_ids, ids, textures, mapped):
    """:func:`rasterkit.raster.kernels.shade.resolve_row` of a textured frame (``mode``
    SHADE_FLAT or SHADE_SMOOTH, or SHADE_NONE for a depth pass with cut-out faces: the
    visibility rows hold faces); ``textures`` a :class:`rasterkit.raster.kernels.records.Textured`,
    and again as ``mapped`` when some face has a normal map or the frame has lights (else
    None: that code is not compiled; a face lit per pixel is coloured by
    :func:`~rasterkit.raster.kernels.lit_shade.lit_rgba`). A run of pixels of one face shares
    its :func:`~rasterkit.raster.kernels.surface.face_terms`; without normal maps
    :func:`textured_run` colours the run."""
    fields = texture_fields(textures)
    face_texture = fields[5]
    ru, ju, base = np.uint64(r), np.uint64(j), np.uint64(lo)
    px, py = lo + 0.5 + sample_x, j + 0.5 + sample_y
    n = hi - lo + 1
    k = 0
    while k < n:
        f = lid[ru, base + np.uint64(k)]
        if f < 0:
            k += 1
            continue
        end = k + 1
        while end < n and lid[ru, base + np.uint64(end)] == f:
            end += 1
        t = face_texture[f]
        if mode == SHADE_NONE:
            pass
        elif mapped is not None and lit_face(fields, t):
            lit_run(color, ju, base + np.uint64(k), np.int64(end - k), mode, f, t, px + k, py, packed, vertex_colors,
                    corners, bary, fields)
        elif t >= 0:
            terms = face_terms(f, bary, fields)
            if mapped is None:
                textured_run(color, ju, base + np.uint64(k), np.int64(end - k), t, terms, px + k, py, fields[0],
                             fields[1], fields[2], fields[3], fields[4], fields[15])
            else:
                normal = normal_terms(f, terms[0], fields)
                for q in range(k, end):
                    put_rgba(color, ju, base + np.uint64(q), mapped_pixel(f, t, terms, normal, px + q, py, fields))
        elif mode == SHADE_SMOOTH:
            for q in range(k, end):
                put_rgba(color, ju, base + np.uint64(q), smooth_rgba(f, px + q, py, vertex_colors, corners, bary))
        elif mode == SHADE_FLAT:
            for q in range(k, end):
                put_rgba(color, ju, base + np.uint64(q), packed[f])
        for q in range(k, end):
            i = base + np.uint64(q)
            lid[ru, i] = -1
            if write_ids:
                ids[ju, i] = f
        k = end
