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
   (:func:`encode`) and multiplied by the face's tint (its material's ``diffuse``, 0..255)
   and the Lambert factor: per face for flat shading, interpolated perspective-correctly
   from the corners for smooth shading, as an untextured face's colour is lit.

Faces without a texture (``face_texture[f] < 0``) are coloured as in
:func:`rasterkit.raster.kernels.shade.resolve_row`.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.kernels.sample import FILTER, FILTER_TRILINEAR, sample, texture_lod
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_SMOOTH, put_rgba, smooth_rgba, to_u8
from rasterkit.runtime.jit import kernel

#: Intervals of the sRGB encoding table (:func:`encode_table`): with linear interpolation
#: between its entries the encoded value is within 1e-5 of the exact transfer function
#: (0.003 of an 8-bit step), everywhere in [0, 1].
ENCODE_STEPS = 4096


def encode_table() -> np.ndarray:
    """(ENCODE_STEPS + 2,) float32: the sRGB encoding of ``k / ENCODE_STEPS``, with the last
    entry repeated (so that :func:`encode` of 1.0 reads inside the table). Read-only."""
    x = np.arange(ENCODE_STEPS + 1) / ENCODE_STEPS
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.maximum(x, 0.0031308) ** (1 / 2.4) - 0.055)
    table = np.append(s, s[-1]).astype(np.float32)
    table.flags.writeable = False
    return table


@kernel(inline="always")
def encode(table, x):
    """The sRGB encoding (0..1) of the linear value ``x`` (clamped to [0, 1]; NaN gives 0),
    interpolated in ``table`` (:func:`encode_table`)."""
    x = x if x > 0.0 else 0.0  # noqa: FURB136 - the select sends NaN to 0
    x = x if x < 1.0 else 1.0  # noqa: FURB136
    pos = x * ENCODE_STEPS
    k = np.int64(pos)
    frac = pos - k
    return table[k] + (table[k + 1] - table[k]) * frac


@kernel(inline="always")
def _flat_intensity(f, textures):
    """The Lambert factor of face ``f`` (flat shading), as the face pass lights an
    untextured face (:func:`rasterkit.raster.kernels.shade.flat_colors`)."""
    normals, light = textures.normals, textures.light
    cos = normals[f, 0] * light[0] + normals[f, 1] * light[1] + normals[f, 2] * light[2]
    cos = max(cos, -textures.back * cos)
    cos = cos if np.isfinite(cos) else 0.0
    return textures.ambient + (1.0 - textures.ambient) * cos


@kernel(refcounts=False)
def textured_rgba(f, t, px, py, bary, textures):
    """The packed colour of face ``f`` with texture ``t`` at raster point (px, py) (see the
    module documentation)."""
    a0, b0, c0 = bary[f, 0], bary[f, 1], bary[f, 2]
    a1, b1, c1 = bary[f, 3], bary[f, 4], bary[f, 5]
    a2, b2, c2 = bary[f, 6], bary[f, 7], bary[f, 8]
    w0 = a0 * px + b0 * py + c0
    w1 = a1 * px + b1 * py + c1
    w2 = a2 * px + b2 * py + c2
    inv = 1.0 / (w0 + w1 + w2)
    uv = textures.corner_uv
    u0, v0, u1, v1, u2, v2 = uv[f, 0], uv[f, 1], uv[f, 2], uv[f, 3], uv[f, 4], uv[f, 5]
    u = (w0 * u0 + w1 * u1 + w2 * u2) * inv
    v = (w0 * v0 + w1 * v1 + w2 * v2) * inv
    samplers = textures.samplers
    lod = 0.0
    if samplers[t, FILTER] == FILTER_TRILINEAR:
        sx, sy = a0 + a1 + a2, b0 + b1 + b2
        dudx = (a0 * u0 + a1 * u1 + a2 * u2 - u * sx) * inv
        dvdx = (a0 * v0 + a1 * v1 + a2 * v2 - v * sx) * inv
        dudy = (b0 * u0 + b1 * u1 + b2 * u2 - u * sy) * inv
        dvdy = (b0 * v0 + b1 * v1 + b2 * v2 - v * sy) * inv
        lod = texture_lod(textures.levels, samplers, textures.transforms, t, dudx, dvdx, dudy, dvdy)
    r, g, b, _ = sample(textures.texels, textures.levels, samplers, textures.transforms, textures.decode, t, u, v,
                        lod)
    if textures.smooth:
        corners, intensity = textures.corners, textures.intensity
        shade = (w0 * intensity[corners[f, 0]] + w1 * intensity[corners[f, 1]]
                 + w2 * intensity[corners[f, 2]]) * inv
    else:
        shade = _flat_intensity(f, textures)
    table, tint = textures.encode, textures.tint
    red = to_u8(encode(table, r) * tint[f, 0] * shade)
    green = to_u8(encode(table, g) * tint[f, 1] * shade)
    blue = to_u8(encode(table, b) * tint[f, 2] * shade)
    return np.uint32(red | green << 8 | blue << 16 | 255 << 24)


@kernel(inline="always")
def pixel_rgba(mode, f, px, py, packed, vertex_colors, faces, bary, textures):
    """The colour of face ``f`` at raster point (px, py): textured where it has a texture,
    else flat (``packed``) or smooth (``vertex_colors`` through ``faces``)."""
    t = textures.face_texture[f]
    if t >= 0:
        return textured_rgba(f, t, px, py, bary, textures)
    if mode == SHADE_SMOOTH:
        return smooth_rgba(f, px, py, vertex_colors, faces, bary)
    return packed[f]


@kernel(refcounts=False)
def resolve_textured_row(mode, lid, r, j, lo, hi, sample_x, sample_y, packed, vertex_colors, faces, bary, color,
                         write_ids, ids, textures):
    """:func:`rasterkit.raster.kernels.shade.resolve_row` of a textured frame (``mode``
    SHADE_FLAT or SHADE_SMOOTH: the visibility rows hold faces); ``textures`` a
    :class:`rasterkit.raster.kernels.records.Textured`."""
    ru, ju, base = np.uint64(r), np.uint64(j), np.uint64(lo)
    px, py = lo + 0.5 + sample_x, j + 0.5 + sample_y
    for k in range(hi - lo + 1):
        i = base + np.uint64(k)
        f = lid[ru, i]
        if f < 0:
            continue
        lid[ru, i] = -1
        if mode == SHADE_FLAT or mode == SHADE_SMOOTH:
            put_rgba(color, ju, i, pixel_rgba(mode, f, px + k, py, packed, vertex_colors, faces, bary, textures))
        if write_ids:
            ids[ju, i] = f
