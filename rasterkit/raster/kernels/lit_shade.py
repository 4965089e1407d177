"""Colours of visible pixels lit per pixel by Blinn-Phong (:mod:`rasterkit.raster.kernels.lights`):
every face of a frame shaded ``"phong"``, and the textured faces of any frame with lights.

At the pixel's sample point ``(px, py)``, from the face's perspective-correct barycentrics
(:mod:`rasterkit.raster.kernels.surface`): the surface point (its corners' world positions
interpolated), the unit normal (the corners' smooth normals interpolated, or the face normal
for flat shading; bent by the face's normal map where it has one), the base colour in linear
light (the texture's colour times the material's ``diffuse``; an untextured face's own colour,
per face or interpolated from its corners, decoded from sRGB), the viewer's direction; the
lights' sum plus the face's emission is encoded to sRGB by table.
"""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.cull import per_face
from rasterkit.raster.kernels.lights import decode, light_sum, toward_viewer
from rasterkit.raster.kernels.shade import SHADE_SMOOTH, put_rgba, to_u8
from rasterkit.raster.kernels.surface import bent_normal, diffuse, encode, face_terms, normal_terms, surface
from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def lit_fields(fields):
    """A lit frame's fields of :func:`rasterkit.raster.kernels.surface.texture_fields`:
    ``(lights, eye, perspective, view, positions, faces, specular, shininess, emission, phong)``."""
    return (fields[21], fields[22], fields[23], fields[24], fields[25], fields[26], fields[27], fields[28],
            fields[29], fields[30])


@kernel(inline="always")
def lit_face(fields, t):
    """Whether a face with texture ``t`` (-1: none) is lit per pixel in this frame."""
    return fields[21].shape[0] > 0 and (t >= 0 or fields[30])


@kernel(inline="always")
def _weights(bary, f, px, py):
    """Face ``f``'s barycentric weights (summing to 1) at raster point (px, py)."""
    w0 = bary[f, 0] * px + bary[f, 1] * py + bary[f, 2]
    w1 = bary[f, 3] * px + bary[f, 4] * py + bary[f, 5]
    w2 = bary[f, 6] * px + bary[f, 7] * py + bary[f, 8]
    total = w0 + w1 + w2
    if total != 0.0:
        return w0 / total, w1 / total, w2 / total
    return 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0


@kernel(inline="always")
def _mix(rows, table, w, c):
    """Column ``c`` of the rows ``rows`` (3 indices) of ``table``, weighted by ``w``."""
    return w[0] * table[rows[0], c] + w[1] * table[rows[1], c] + w[2] * table[rows[2], c]


@kernel(inline="always")
def _normal(f, w, fields):
    """The unit normal of face ``f`` at weights ``w``: its corners' interpolated (smooth) or its
    own; zero for a degenerate face."""
    if fields[8]:
        corners, corner_normals = fields[10], fields[19]
        rows = (corners[f, 0], corners[f, 1], corners[f, 2])
        nx, ny, nz = _mix(rows, corner_normals, w, 0), _mix(rows, corner_normals, w, 1), _mix(rows, corner_normals,
                                                                                              w, 2)
    else:
        normals = fields[11]
        nx, ny, nz = np.float64(normals[f, 0]), np.float64(normals[f, 1]), np.float64(normals[f, 2])
    length = np.sqrt(nx * nx + ny * ny + nz * nz)
    if not length > 0.0:  # degenerate, or NaN
        return 0.0, 0.0, 0.0
    return nx / length, ny / length, nz / length


@kernel(inline="always")
def _face_plane(positions, rows, fallback):
    """The unit normal of the face whose corners are ``positions[rows]`` (``fallback`` for a
    degenerate one)."""
    ax, ay, az = positions[rows[1], 0] - positions[rows[0], 0], positions[rows[1], 1] - positions[rows[0], 1], \
        positions[rows[1], 2] - positions[rows[0], 2]
    bx, by, bz = positions[rows[2], 0] - positions[rows[0], 0], positions[rows[2], 1] - positions[rows[0], 1], \
        positions[rows[2], 2] - positions[rows[0], 2]
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    length = np.sqrt(cx * cx + cy * cy + cz * cz)
    if not length > 0.0:
        return fallback
    return cx / length, cy / length, cz / length


@kernel(inline="always")
def _base(mode, f, t, w, px, py, packed, vertex_colors, corners, bary, fields):
    """``(base, normal)``: face ``f``'s linear base colour at weights ``w`` (texture ``t``, or its
    flat or interpolated own colour) and its unit normal there (bent by its normal map)."""
    normal = _normal(f, w, fields)
    if t >= 0:
        terms = face_terms(f, bary, fields)
        inv, u, v, derivatives = surface(terms, px, py)
        r, g, b = diffuse(t, u, v, derivatives, fields)
        tint = terms[7]
        m = fields[16][f]
        if m >= 0:
            normal = bent_normal(m, normal_terms(f, terms[0], fields), px, py, inv, u, v, derivatives, fields)
        return (r * decode(tint[0] / 255.0), g * decode(tint[1] / 255.0), b * decode(tint[2] / 255.0)), normal
    return _own_base(mode, f, w, packed, vertex_colors, corners, fields), normal


@kernel(inline="always")
def _own_base(mode, f, w, packed, vertex_colors, corners, fields):
    """The linear base colour of an untextured face ``f`` at weights ``w``: its flat or
    interpolated own colour."""
    if mode == SHADE_SMOOTH:
        rows = (corners[f, 0], corners[f, 1], corners[f, 2])
        return (decode(_mix(rows, vertex_colors, w, 0) / 255.0), decode(_mix(rows, vertex_colors, w, 1) / 255.0),
                decode(_mix(rows, vertex_colors, w, 2) / 255.0))
    table = fields[4]  # the 8-bit codes' linear values: row 1, sRGB
    rgba = packed[f]
    return table[1, rgba & 0xFF], table[1, (rgba >> 8) & 0xFF], table[1, (rgba >> 16) & 0xFF]


@kernel(inline="always")
def _lit_pixel(mode, f, t, px, py, packed, vertex_colors, corners, bary, fields):
    """:func:`lit_rgba`'s colour, inlined into it and into :func:`lit_run`."""
    w = _weights(bary, f, px, py)
    base, normal = _base(mode, f, t, w, px, py, packed, vertex_colors, corners, bary, fields)
    return _lit_point(f, w, base, normal, fields)


@kernel(inline="always")
def _lit_point(f, w, base, normal, fields):
    """The packed colour of face ``f`` at weights ``w`` with the linear colour ``base`` and
    the unit ``normal`` there, lit."""
    lights, eye, perspective, view, positions, faces, specular, shininess, emission, _ = lit_fields(fields)
    rows = (faces[f, 0], faces[f, 1], faces[f, 2])
    x, y, z = _mix(rows, positions, w, 0), _mix(rows, positions, w, 1), _mix(rows, positions, w, 2)
    vx, vy, vz = toward_viewer(x, y, z, eye, perspective, view)
    nx, ny, nz = normal
    if per_face(fields[14], f) > 0.0 and nx * vx + ny * vy + nz * vz < 0.0:  # two-sided, seen from behind
        nx, ny, nz = -nx, -ny, -nz
    s = 0 if specular.shape[0] == 1 else f
    r, g, b = light_sum(x, y, z, nx, ny, nz, vx, vy, vz, base, (specular[s, 0], specular[s, 1], specular[s, 2]),
                        shininess[s], lights, (fields[31], fields[32], fields[33], fields[34]),
                        _face_plane(positions, rows, (nx, ny, nz)) if fields[31].shape[0] else (nx, ny, nz))
    table = fields[15]
    rgba = 255 << 24
    rgba |= to_u8(encode(table, r + emission[s, 0]) * 255.0)
    rgba |= to_u8(encode(table, g + emission[s, 1]) * 255.0) << 8
    rgba |= to_u8(encode(table, b + emission[s, 2]) * 255.0) << 16
    return np.uint32(rgba)


@kernel(refcounts=False)
def lit_rgba(mode, f, t, px, py, packed, vertex_colors, corners, bary, fields):
    """The packed colour of face ``f`` (texture ``t``) at raster point (px, py), lit per pixel;
    ``mode`` SHADE_FLAT (its own colour ``packed[f]``) or SHADE_SMOOTH (``vertex_colors``
    through ``corners``) for an untextured face. Compiled once, called from the multi-sample
    resolves of textured frames (their rows and outlines), not inlined into each."""
    return _lit_pixel(mode, f, t, px, py, packed, vertex_colors, corners, bary, fields)


@kernel(refcounts=False)
def lit_untextured_rgba(mode, f, px, py, packed, vertex_colors, corners, bary, fields):
    """:func:`lit_rgba` of an untextured face, in a frame without textures (none of the
    textured faces' code compiled): the same colour, to the bit."""
    w = _weights(bary, f, px, py)
    return _lit_point(f, w, _own_base(mode, f, w, packed, vertex_colors, corners, fields), _normal(f, w, fields),
                      fields)


@kernel(refcounts=False)
def lit_run(color, j, i0, n, mode, f, t, x0, y, packed, vertex_colors, corners, bary, fields):
    """Colour ``n`` pixels of row ``j`` from column ``i0`` on, of face ``f`` (texture ``t``),
    lit per pixel (:func:`lit_rgba`), ``(x0, y)`` the first one's sample point: one call per
    run of a face's pixels in the single-sample resolve."""
    for q in range(n):
        put_rgba(color, j, i0 + np.uint64(q), _lit_pixel(mode, f, t, x0 + q, y, packed, vertex_colors, corners,
                                                          bary, fields))
