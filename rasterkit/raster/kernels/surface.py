"""What the pixels of one face share, for the resolves that colour them per pixel (textured
faces: :mod:`rasterkit.raster.kernels.texture_shade`; lit faces:
:mod:`rasterkit.raster.kernels.lit_shade`): the fields of the frame's
:class:`rasterkit.raster.kernels.records.Textured`, a face's barycentric planes and texture
coordinates with their screen-space derivatives, its normal (bent by a normal map), the
texture's linear colour, and the sRGB encoding by table.

The barycentric rows of a face (:func:`rasterkit.raster.kernels.shade.bary_matrices`) give at
raster point ``(x, y)`` ``b_k = a_k x + b_k y + c_k``, perspective-correct up to a common
factor ``s = b_0 + b_1 + b_2``; an attribute ``q`` of the corners is ``sum_k b_k q_k / s``,
whose plane (``sum_k q_k (a_k, b_k, c_k)``) :func:`plane` gives.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.kernels.sample import FILTER, FILTER_TRILINEAR, sample, texture_lod
from rasterkit.raster.kernels.cull import per_face
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
    k = np.uint64(k)  # unsigned: no wraparound of negative indices
    low = table[k]
    return low + (table[k + np.uint64(1)] - low) * frac


@kernel(inline="always")
def texture_fields(textures):
    """The record's fields as locals, unpacked once per row: an access through the record
    inside the pixel loop, or a call that passes it, costs the copy of a large structure.
    Fields 0-20 are the textures' and their lighting's, 21-34 a lit frame's
    (:func:`rasterkit.raster.kernels.lit_shade.lit_fields`)."""
    return (textures.texels, textures.levels, textures.samplers, textures.transforms, textures.decode,
            textures.face_texture, textures.corner_uv, textures.tint, textures.smooth, textures.intensity,
            textures.corners, textures.normals, textures.light, textures.ambient, textures.back, textures.encode,
            textures.face_normal_map, textures.face_bump, textures.tangents, textures.corner_normals,
            textures.face_normal_space, textures.lights, textures.eye, textures.perspective, textures.toward_viewer,
            textures.positions, textures.faces, textures.specular, textures.shininess, textures.emission,
            textures.phong, textures.shadow_maps, textures.shadow_matrices, textures.shadow_axes, textures.softness)


@kernel(inline="always")
def plane(rows, q0, q1, q2):
    """The affine function ``sum_k q_k (a_k x + b_k y + c_k)`` as (x, y, 1) coefficients, of
    the barycentric ``rows`` ``(a0, b0, c0, a1, b1, c1, a2, b2, c2)``."""
    a0, b0, c0, a1, b1, c1, a2, b2, c2 = rows
    return a0 * q0 + a1 * q1 + a2 * q2, b0 * q0 + b1 * q1 + b2 * q2, c0 * q0 + c1 * q1 + c2 * q2


@kernel(inline="always")
def lod(levels, samplers, transforms, t, derivatives):
    """OpenGL's level of detail of texture ``t`` for ``derivatives`` (du/dx, dv/dx, du/dy,
    dv/dy) where it is filtered with mipmaps, else 0."""
    if samplers[np.uint64(t), FILTER] != FILTER_TRILINEAR:
        return 0.0
    return texture_lod(levels, samplers, transforms, t, derivatives[0], derivatives[1], derivatives[2],
                       derivatives[3])


@kernel(inline="always")
def lambert_factor(x, y, z, light, ambient, back):
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
    corner_uv, tint, smooth, intensity, corners, normals = fields[6], fields[7], fields[8], fields[9], fields[10], fields[11]
    light, ambient, back = fields[12], fields[13], fields[14]
    a0, b0, c0 = bary[f, 0], bary[f, 1], bary[f, 2]
    a1, b1, c1 = bary[f, 3], bary[f, 4], bary[f, 5]
    a2, b2, c2 = bary[f, 6], bary[f, 7], bary[f, 8]
    rows = (a0, b0, c0, a1, b1, c1, a2, b2, c2)
    s_plane = (a0 + a1 + a2, b0 + b1 + b2, c0 + c1 + c2)
    u_plane = plane(rows, corner_uv[f, 0], corner_uv[f, 2], corner_uv[f, 4])
    v_plane = plane(rows, corner_uv[f, 1], corner_uv[f, 3], corner_uv[f, 5])
    shade = 0.0
    i_plane = (0.0, 0.0, 0.0)
    if smooth:
        i_plane = plane(rows, np.float64(intensity[corners[f, 0]]), np.float64(intensity[corners[f, 1]]),
                         np.float64(intensity[corners[f, 2]]))
    else:
        shade = lambert_factor(normals[f, 0], normals[f, 1], normals[f, 2], light, ambient, per_face(back, f))
    return rows, s_plane, u_plane, v_plane, i_plane, smooth, shade, (tint[f, 0], tint[f, 1], tint[f, 2])


@kernel(inline="always")
def normal_terms(f, rows, fields):
    """What the pixels of face ``f`` share for its normal map: ``(tangent, bitangent, normal
    planes, bump, object_space, back)``, the normal's planes those of the interpolated corner
    normals (smooth) or the face normal (flat: constant planes); none of the frame for a map
    in object space; ``back`` the face's two-sided factor (:func:`lambert_factor`)."""
    smooth, corners, normals, back = fields[8], fields[10], fields[11], fields[14]
    face_normal_map, face_bump, tangents, corner_normals, face_normal_space = (fields[16], fields[17], fields[18],
                                                                               fields[19], fields[20])
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
            planes = (plane(rows, corner_normals[c0, 0], corner_normals[c1, 0], corner_normals[c2, 0]),
                      plane(rows, corner_normals[c0, 1], corner_normals[c1, 1], corner_normals[c2, 1]),
                      plane(rows, corner_normals[c0, 2], corner_normals[c1, 2], corner_normals[c2, 2]))
        else:  # constant: the face normal times s, whose plane is the rows' sums
            sx, sy, s0 = rows[0] + rows[3] + rows[6], rows[1] + rows[4] + rows[7], rows[2] + rows[5] + rows[8]
            nx, ny, nz = np.float64(normals[f, 0]), np.float64(normals[f, 1]), np.float64(normals[f, 2])
            planes = ((sx * nx, sy * nx, s0 * nx), (sx * ny, sy * ny, s0 * ny), (sx * nz, sy * nz, s0 * nz))
    return tangent, bitangent, planes, bump, object_space, per_face(back, f)


@kernel(inline="always")
def bent_normal(m, terms, x, y, inv, u, v, derivatives, fields):
    """The unit normal at (x, y) bent by the face's normal map ``m`` (see
    :func:`normal_terms`): the surface normal ``n``, the tangent made perpendicular to it and
    the bitangent to both (Gram-Schmidt), the map's ``(2r - 1, 2g - 1, 2b - 1)`` with its
    first two components times ``bump``, in that frame; in object space, the map's vector."""
    tangent, bitangent, planes, bump, object_space, _ = terms
    texels, levels, samplers, transforms, decode = fields[0], fields[1], fields[2], fields[3], fields[4]
    r, g, b, _ = sample(texels, levels, samplers, transforms, decode, m, u, v,
                        lod(levels, samplers, transforms, m, derivatives))
    if object_space:
        x, y, z = 2.0 * r - 1.0, 2.0 * g - 1.0, 2.0 * b - 1.0
        scale = 1.0 / np.sqrt(x * x + y * y + z * z)
        return x * scale, y * scale, z * scale
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
    return x * scale, y * scale, z * scale


@kernel(inline="always")
def mapped_shade(m, terms, x, y, inv, u, v, derivatives, fields):
    """The Lambert factor at (x, y) of the normal bent by the face's normal map ``m``
    (:func:`bent_normal`)."""
    nx, ny, nz = bent_normal(m, terms, x, y, inv, u, v, derivatives, fields)
    return lambert_factor(nx, ny, nz, fields[12], fields[13], terms[5])


@kernel(inline="always")
def surface(terms, x, y):
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
def diffuse(t, u, v, derivatives, fields):
    """Texture ``t``'s linear colour (r, g, b) at (u, v)."""
    texels, levels, samplers, transforms, decode = fields[0], fields[1], fields[2], fields[3], fields[4]
    r, g, b, _ = sample(texels, levels, samplers, transforms, decode, t, u, v,
                        lod(levels, samplers, transforms, t, derivatives))
    return r, g, b
