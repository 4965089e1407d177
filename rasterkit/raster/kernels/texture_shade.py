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

A face with a normal map is lit per pixel instead (:func:`normal_terms`): its normal (the
face's, or its corners' interpolated) bent by the map in the frame of its tangent and
bitangent (the directions of growing ``u`` and ``v``), Lambert's law of that normal.

Faces without a texture (``face_texture[f] < 0``) are coloured as in
:func:`rasterkit.raster.kernels.shade.resolve_row`.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.kernels.sample import FILTER, FILTER_TRILINEAR, lookup, sample, texture_lod
from rasterkit.raster.kernels.shade import SHADE_FLAT, SHADE_NONE, SHADE_SMOOTH, put_rgba, smooth_rgba, to_u8
from rasterkit.raster.kernels.cull import per_face
from rasterkit.runtime.intrinsics import stack_floats
from rasterkit.runtime.jit import kernel

#: Intervals of the sRGB encoding table (:func:`encode_table`): with linear interpolation
#: between its entries the encoded value is within 1e-5 of the exact transfer function
#: (0.003 of an 8-bit step), everywhere in [0, 1].
ENCODE_STEPS = 4096

#: Pixels of a run that :func:`textured_run` prepares at a time (its scratch: 4 floats each).
RUN_CHUNK = 32
_RUN_SCRATCH = 4 * RUN_CHUNK


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
    k = np.uint64(k)  # unsigned: no wraparound of negative indices
    low = table[k]
    return low + (table[k + np.uint64(1)] - low) * frac


@kernel(inline="always")
def texture_fields(textures):
    """The record's fields as locals, unpacked once per row: an access through the record
    inside the pixel loop, or a call that passes it, costs the copy of a large structure."""
    return (textures.texels, textures.levels, textures.samplers, textures.transforms, textures.decode,
            textures.face_texture, textures.corner_uv, textures.tint, textures.smooth, textures.intensity,
            textures.corners, textures.normals, textures.light, textures.ambient, textures.back, textures.encode,
            textures.face_normal_map, textures.face_bump, textures.tangents, textures.corner_normals,
            textures.face_normal_space)


@kernel(inline="always")
def _plane(rows, q0, q1, q2):
    """The affine function ``sum_k q_k (a_k x + b_k y + c_k)`` as (x, y, 1) coefficients, of
    the barycentric ``rows`` ``(a0, b0, c0, a1, b1, c1, a2, b2, c2)``."""
    a0, b0, c0, a1, b1, c1, a2, b2, c2 = rows
    return a0 * q0 + a1 * q1 + a2 * q2, b0 * q0 + b1 * q1 + b2 * q2, c0 * q0 + c1 * q1 + c2 * q2


@kernel(inline="always")
def _lod(levels, samplers, transforms, t, derivatives):
    """OpenGL's level of detail of texture ``t`` for ``derivatives`` (du/dx, dv/dx, du/dy,
    dv/dy) where it is filtered with mipmaps, else 0."""
    if samplers[np.uint64(t), FILTER] != FILTER_TRILINEAR:
        return 0.0
    return texture_lod(levels, samplers, transforms, t, derivatives[0], derivatives[1], derivatives[2],
                       derivatives[3])


@kernel(inline="always")
def _lambert(x, y, z, light, ambient, back):
    """The Lambert factor of the unit normal (x, y, z), as the face pass lights an untextured
    face: ``ambient + (1 - ambient) max(cos, -back cos)``; a non-finite normal gets the
    ambient term."""
    cos = x * light[0] + y * light[1] + z * light[2]
    cos = max(cos, -back * cos)
    cos = cos if np.isfinite(cos) else 0.0
    return ambient + (1.0 - ambient) * cos


@kernel(inline="always")
def face_terms(f, bary, fields):
    """What the pixels of face ``f`` share: its barycentric rows, the planes of ``s``, ``U``,
    ``V`` and (smooth) the Lambert factor times ``s`` (see the module documentation), the flat
    Lambert factor and the tint."""
    (_, _, _, _, _, _, corner_uv, tint, smooth, intensity, corners, normals, light, ambient, back, _, _, _, _, _,
     _) = fields
    a0, b0, c0 = bary[f, 0], bary[f, 1], bary[f, 2]
    a1, b1, c1 = bary[f, 3], bary[f, 4], bary[f, 5]
    a2, b2, c2 = bary[f, 6], bary[f, 7], bary[f, 8]
    rows = (a0, b0, c0, a1, b1, c1, a2, b2, c2)
    s_plane = (a0 + a1 + a2, b0 + b1 + b2, c0 + c1 + c2)
    u_plane = _plane(rows, corner_uv[f, 0], corner_uv[f, 2], corner_uv[f, 4])
    v_plane = _plane(rows, corner_uv[f, 1], corner_uv[f, 3], corner_uv[f, 5])
    shade = 0.0
    i_plane = (0.0, 0.0, 0.0)
    if smooth:
        i_plane = _plane(rows, np.float64(intensity[corners[f, 0]]), np.float64(intensity[corners[f, 1]]),
                         np.float64(intensity[corners[f, 2]]))
    else:
        shade = _lambert(normals[f, 0], normals[f, 1], normals[f, 2], light, ambient, per_face(back, f))
    return rows, s_plane, u_plane, v_plane, i_plane, smooth, shade, (tint[f, 0], tint[f, 1], tint[f, 2])


@kernel(inline="always")
def normal_terms(f, rows, fields):
    """What the pixels of face ``f`` share for its normal map: ``(tangent, bitangent, normal
    planes, bump, object_space, back)``, the normal's planes those of the interpolated corner
    normals (smooth) or the face normal (flat: constant planes); none of the frame for a map
    in object space; ``back`` the face's two-sided factor (:func:`_lambert`)."""
    (_, _, _, _, _, _, _, _, smooth, _, corners, normals, _, _, back, _, face_normal_map, face_bump, tangents,
     corner_normals, face_normal_space) = fields
    m = face_normal_map[f]
    zero = (0.0, 0.0, 0.0)
    tangent, bitangent, planes, bump = zero, zero, (zero, zero, zero), 1.0
    object_space = m >= 0 and face_normal_space[f] == 1  # the map's vector is the normal
    if m >= 0 and not object_space:
        tangent = (np.float64(tangents[f, 0]), np.float64(tangents[f, 1]), np.float64(tangents[f, 2]))
        bitangent = (np.float64(tangents[f, 3]), np.float64(tangents[f, 4]), np.float64(tangents[f, 5]))
        bump = np.float64(face_bump[f])
        if smooth:
            c0, c1, c2 = corners[f, 0], corners[f, 1], corners[f, 2]
            planes = (_plane(rows, corner_normals[c0, 0], corner_normals[c1, 0], corner_normals[c2, 0]),
                      _plane(rows, corner_normals[c0, 1], corner_normals[c1, 1], corner_normals[c2, 1]),
                      _plane(rows, corner_normals[c0, 2], corner_normals[c1, 2], corner_normals[c2, 2]))
        else:  # constant: the face normal times s, whose plane is the rows' sums
            sx, sy, s0 = rows[0] + rows[3] + rows[6], rows[1] + rows[4] + rows[7], rows[2] + rows[5] + rows[8]
            nx, ny, nz = np.float64(normals[f, 0]), np.float64(normals[f, 1]), np.float64(normals[f, 2])
            planes = ((sx * nx, sy * nx, s0 * nx), (sx * ny, sy * ny, s0 * ny), (sx * nz, sy * nz, s0 * nz))
    return tangent, bitangent, planes, bump, object_space, per_face(back, f)


@kernel(inline="always")
def _mapped_shade(m, terms, x, y, inv, u, v, derivatives, fields):
    """The Lambert factor at (x, y) with the normal bent by the face's normal map (see
    :func:`normal_terms`): the surface normal ``n``, the tangent made perpendicular to it and
    the bitangent to both (Gram-Schmidt), the map's ``(2r - 1, 2g - 1, 2b - 1)`` with its
    first two components times ``bump``, in that frame."""
    tangent, bitangent, planes, bump, object_space, back = terms
    texels, levels, samplers, transforms, decode, light, ambient = (fields[0], fields[1], fields[2], fields[3],
                                                                   fields[4], fields[12], fields[13])
    r, g, b, _ = sample(texels, levels, samplers, transforms, decode, m, u, v,
                        _lod(levels, samplers, transforms, m, derivatives))
    if object_space:
        x, y, z = 2.0 * r - 1.0, 2.0 * g - 1.0, 2.0 * b - 1.0
        scale = 1.0 / np.sqrt(x * x + y * y + z * z)
        return _lambert(x * scale, y * scale, z * scale, light, ambient, back)
    nx = (planes[0][0] * x + planes[0][1] * y + planes[0][2]) * inv
    ny = (planes[1][0] * x + planes[1][1] * y + planes[1][2]) * inv
    nz = (planes[2][0] * x + planes[2][1] * y + planes[2][2]) * inv
    scale = 1.0 / np.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx * scale, ny * scale, nz * scale
    tx, ty, tz = tangent
    d = tx * nx + ty * ny + tz * nz
    tx, ty, tz = tx - d * nx, ty - d * ny, tz - d * nz
    scale = 1.0 / np.sqrt(tx * tx + ty * ty + tz * tz)
    tx, ty, tz = tx * scale, ty * scale, tz * scale
    bx, by, bz = bitangent
    d, e = bx * nx + by * ny + bz * nz, bx * tx + by * ty + bz * tz
    bx, by, bz = bx - d * nx - e * tx, by - d * ny - e * ty, bz - d * nz - e * tz
    scale = 1.0 / np.sqrt(bx * bx + by * by + bz * bz)
    bx, by, bz = bx * scale, by * scale, bz * scale
    mx, my, mz = (2.0 * r - 1.0) * bump, (2.0 * g - 1.0) * bump, 2.0 * b - 1.0
    x, y, z = tx * mx + bx * my + nx * mz, ty * mx + by * my + ny * mz, tz * mx + bz * my + nz * mz
    scale = 1.0 / np.sqrt(x * x + y * y + z * z)
    return _lambert(x * scale, y * scale, z * scale, light, ambient, back)


@kernel(inline="always")
def _surface(terms, x, y):
    """``(inv, u, v, derivatives)`` at raster point (x, y) of the face whose :func:`face_terms`
    are ``terms``: ``1 / s``, the texture coordinates and their screen-space derivatives
    (du/dx, dv/dx, du/dy, dv/dy), by the quotient rule: du/dx = (U_x - u s_x) / s, and so on."""
    _, s_plane, u_plane, v_plane = terms[0], terms[1], terms[2], terms[3]
    inv = 1.0 / (s_plane[0] * x + s_plane[1] * y + s_plane[2])
    u = (u_plane[0] * x + u_plane[1] * y + u_plane[2]) * inv
    v = (v_plane[0] * x + v_plane[1] * y + v_plane[2]) * inv
    return inv, u, v, ((u_plane[0] - u * s_plane[0]) * inv, (v_plane[0] - v * s_plane[0]) * inv,
                       (u_plane[1] - u * s_plane[1]) * inv, (v_plane[1] - v * s_plane[1]) * inv)


@kernel(inline="always")
def _diffuse(t, u, v, derivatives, fields):
    """Texture ``t``'s linear colour (r, g, b) at (u, v)."""
    texels, levels, samplers, transforms, decode = fields[0], fields[1], fields[2], fields[3], fields[4]
    r, g, b, _ = sample(texels, levels, samplers, transforms, decode, t, u, v,
                        _lod(levels, samplers, transforms, t, derivatives))
    return r, g, b


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
    map, whose :func:`face_terms` are ``terms``."""
    inv, u, v, derivatives = _surface(terms, x, y)
    r, g, b = _diffuse(t, u, v, derivatives, fields)
    return _packed(r, g, b, terms[7], _gouraud(terms, x, y, inv), fields[15])


@kernel(refcounts=False)
def textured_run(color, j, i0, n, t, terms, x0, y, texels, levels, samplers, transforms, decode, table):
    """Colour ``n`` pixels of row ``j`` from column ``i0`` on, of a face with texture ``t`` and
    no normal map whose :func:`face_terms` are ``terms``; ``(x0, y)`` the first one's sample
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
            inv, u, v, d = _surface(terms, x, y)
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
    :func:`normal_terms` are ``normal``) bends its normal where it has one."""
    inv, u, v, derivatives = _surface(terms, x, y)
    r, g, b = _diffuse(t, u, v, derivatives, fields)
    m = fields[16][f]  # read here, not once per face: see rasterkit.material.kernels.sample.lookup
    shade = _mapped_shade(m, normal, x, y, inv, u, v, derivatives, fields) if m >= 0 else _gouraud(terms, x, y, inv)
    return _packed(r, g, b, terms[7], shade, fields[15])


@kernel(inline="always")
def pixel_rgba(mode, f, px, py, packed, vertex_colors, corners, bary, fields):
    """The colour of face ``f`` at raster point (px, py): textured where it has a texture,
    else flat (``packed``) or smooth (``vertex_colors`` through ``corners``); ``fields``:
    :func:`texture_fields` of a frame without normal maps."""
    t = fields[5][f]
    if t >= 0:
        return face_pixel(t, face_terms(f, bary, fields), px, py, fields)
    if mode == SHADE_SMOOTH:
        return smooth_rgba(f, px, py, vertex_colors, corners, bary)
    return packed[f]


@kernel(inline="always")
def mapped_rgba(mode, f, px, py, packed, vertex_colors, corners, bary, fields):
    """:func:`pixel_rgba` of a frame with normal maps."""
    t = fields[5][f]
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
    and again as ``mapped`` when some face has a normal map (else None: that code is not
    compiled). A run of pixels of one face shares its :func:`face_terms`; without normal
    maps :func:`textured_run` colours the run."""
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
