"""The resolve of a frame lit per pixel whose faces have no textures
(:class:`rasterkit.raster.kernels.records.PixelLights`): every visible pixel's colour by
Blinn-Phong under the frame's lights (the formulas: :mod:`rasterkit.raster.kernels.lights`).

A row's visible pixels are lit :data:`CHUNK` at a time, across faces, in passes over scratch
on the stack, one value per pixel in each of its columns
(:mod:`rasterkit.raster.kernels.lit_columns`):

1. gather (one pixel at a time: what it reads depends on its face): the face's
   perspective-correct barycentrics at the pixel's sample point, the surface point and the
   normal (the corners' smooth normals or the face's) interpolated, the linear base colour
   (the face's own, or its corners' interpolated and decoded), the face's specular colour,
   shininess and emission, and for shadow lookups the normal of the face's plane;
2. the unit normal and the direction towards the viewer (the normal turned towards the
   viewer on a two-sided face seen from behind);
3. per light, its share added to every pixel's sum: loops without branches (selects), so
   LLVM turns them into vector instructions; the highlight's power by squarings when the
   chunk's pixels share one whole shininess (the default 32 and most materials'), else by
   :func:`rasterkit.raster.kernels.powers.power` (no library call either way). A light with a shadow
   map first looks up each pixel that faces it (:mod:`rasterkit.raster.kernels.lit_shadows`);
4. the sums encoded to sRGB by table and written.

The same arithmetic as :func:`rasterkit.raster.kernels.lit_shade.lit_rgba` (which lights the
textured faces and the multi-sample resolves); the results agree to the rounding.
"""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.cull import per_face
from rasterkit.raster.kernels.face_setup import ONE
from rasterkit.raster.kernels.shade import SHADE_SMOOTH, put_rgba
from rasterkit.raster.kernels.lit_columns import (
    AB, AG, AMBIENT, AR, BB, BG, BR, CHUNK, COLUMN, CONSTANT, DIRECTIONAL, HEADLIGHT, INTERPOLATED, NDH, NDL, NX,
    NY, NZ, POWER, SB, SCRATCH, SG, SHADE, SPOT, SR, TWO, VX, VY, VZ, X, Y, Z, encode_chunk, highlights, unit,
    whole_exponent)
from rasterkit.raster.kernels.lit_shadows import light_reaches
from rasterkit.runtime.intrinsics import prefetch_item, stack_floats
from rasterkit.runtime.jit import kernel

#: What a run's gather keeps: a line (3 values) per interpolated value, and the constants.
_LINES = 3 * INTERPOLATED + CONSTANT


@kernel(inline="always")
def _decoded(decode, c):
    """Linear light of the sRGB value ``c`` (0..255, fractional), interpolated between the
    8-bit codes of ``decode`` (256,)."""
    c = min(max(c, 0.0), 255.0)
    k = min(np.int64(c), 254)
    low = decode[np.uint64(k)]
    return low + (decode[np.uint64(k + 1)] - low) * (c - k)


@kernel(inline="always")
def _line(lines, row, table, ra, rb, rc, a0, a1, a2, d0, d1, d2, column):
    """Row ``row`` of ``lines``: ``(slope, intercept, mean)`` of column ``column`` of
    ``table``'s rows ``ra, rb, rc`` weighted along the pixel row by ``b_k = a_k px + d_k``
    (divided by their sum at each pixel), and their plain mean (where the sum is 0)."""
    qa, qb, qc = table[ra, column], table[rb, column], table[rc, column]
    at = np.uint64(3 * row)
    lines[at] = a0 * qa + a1 * qb + a2 * qc
    lines[at + np.uint64(1)] = d0 * qa + d1 * qb + d2 * qc
    lines[at + np.uint64(2)] = (qa + qb + qc) / 3.0


@kernel(inline="always")
def _gather(s, lines, q0, count, f, column0, px0, py, mode, packed, vertex_colors, corners, bary, lit):
    """Step 1 for ``count`` pixels of face ``f`` from scratch slot ``q0`` on: image columns
    ``column0 ...``, sample points ``(px0, py), (px0 + 1, py) ...``. The face's barycentrics
    are affine along the row, ``b_k = a_k px + d_k``; so are their sums weighted by the
    corners' values: each interpolated value is one such line divided by ``sum_k b_k``
    (:func:`_line`; a value of the face's own is a line too: ``v t1``, ``v t0``). The lines
    and constants go into ``lines`` once per run, then one loop without branches fills every
    column."""
    positions, faces, smooth, corner_normals, normal_corners, face_normals = lit[4], lit[5], lit[9], lit[10], \
        lit[11], lit[12]
    a0, a1, a2 = bary[f, 0], bary[f, 3], bary[f, 6]
    d0, d1, d2 = bary[f, 1] * py + bary[f, 2], bary[f, 4] * py + bary[f, 5], bary[f, 7] * py + bary[f, 8]
    t1, t0 = a0 + a1 + a2, d0 + d1 + d2
    a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
    for axis in range(3):
        _line(lines, axis, positions, a, b, c, a0, a1, a2, d0, d1, d2, axis)
    if smooth:
        na, nb, nc = normal_corners[f, 0], normal_corners[f, 1], normal_corners[f, 2]
        for axis in range(3):
            _line(lines, 3 + axis, corner_normals, na, nb, nc, a0, a1, a2, d0, d1, d2, axis)
    if mode == SHADE_SMOOTH:  # sRGB interpolated here, decoded below
        ca, cb, cc = corners[f, 0], corners[f, 1], corners[f, 2]
        for channel in range(3):
            _line(lines, 6 + channel, vertex_colors, ca, cb, cc, a0, a1, a2, d0, d1, d2, channel)
    decode, specular, shininess, emission = lit[15], lit[6], lit[7], lit[8]
    m = 0 if shininess.shape[0] == 1 else f
    rgba = packed[f] if mode != SHADE_SMOOTH else 0
    ux, uy, uz = positions[b, 0] - positions[a, 0], positions[b, 1] - positions[a, 1], \
        positions[b, 2] - positions[a, 2]
    wx, wy, wz = positions[c, 0] - positions[a, 0], positions[c, 1] - positions[a, 1], \
        positions[c, 2] - positions[a, 2]
    constants = (specular[m, 0], specular[m, 1], specular[m, 2], shininess[m], emission[m, 0], emission[m, 1],
                 emission[m, 2], uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx,
                 1.0 if per_face(lit[13], f) else 0.0)
    for k in range(3):  # the face's own normal and colour
        own_normal = np.float64(face_normals[f, k])
        own_colour = decode[np.uint64((rgba >> (8 * k)) & 0xFF)]
        for row, value, own in ((3 + k, own_normal, not smooth), (6 + k, own_colour, mode != SHADE_SMOOTH)):
            if own:
                at = np.uint64(3 * row)
                lines[at], lines[at + np.uint64(1)], lines[at + np.uint64(2)] = value * t1, value * t0, value
    for k in range(CONSTANT):
        lines[np.uint64(3 * INTERPOLATED + k)] = constants[k]
    for q in range(count):
        px = px0 + q
        total = t1 * px + t0
        inside = total != 0.0
        inv = 1.0 / total if inside else 0.0  # noqa: FURB136 - a select
        u = np.uint64(q0 + q)
        for k in range(INTERPOLATED):
            at = np.uint64(3 * k)
            value = (lines[at] * px + lines[at + np.uint64(1)]) * inv
            s[np.uint64(k * CHUNK) + u] = value if inside else lines[at + np.uint64(2)]  # noqa: FURB136
        for k in range(CONSTANT):
            s[np.uint64((INTERPOLATED + k) * CHUNK) + u] = lines[np.uint64(3 * INTERPOLATED + k)]
        s[COLUMN + u] = column0 + q
    if mode == SHADE_SMOOTH:
        for q in range(q0, q0 + count):
            for channel in range(3):
                at = BR + np.uint64(channel * CHUNK + q)
                s[at] = _decoded(decode, s[at])


@kernel(inline="always")
def _orient(s, n, eye, perspective, view):
    """Step 2 over the chunk's ``n`` pixels."""
    ex, ey, ez = eye[0], eye[1], eye[2]  # locals: the loop stores to the scratch
    wx, wy, wz = view[0], view[1], view[2]
    for q in range(n):
        vx, vy, vz = unit(ex - s[X + np.uint64(q)], ey - s[Y + np.uint64(q)], ez - s[Z + np.uint64(q)])
        vx, vy, vz = (vx, vy, vz) if perspective else (wx, wy, wz)
        nx, ny, nz = unit(s[NX + np.uint64(q)], s[NY + np.uint64(q)], s[NZ + np.uint64(q)])
        flip = -1.0 if s[TWO + np.uint64(q)] > 0.0 and nx * vx + ny * vy + nz * vz < 0.0 else 1.0
        s[NX + np.uint64(q)], s[NY + np.uint64(q)], s[NZ + np.uint64(q)] = nx * flip, ny * flip, nz * flip
        s[VX + np.uint64(q)], s[VY + np.uint64(q)], s[VZ + np.uint64(q)] = vx, vy, vz


@kernel(inline="always")
def _add_light(s, n, k, table, whole):
    """Step 3 for light ``k`` (not ambient) over the chunk's ``n`` pixels; ``whole``: the
    chunk's :func:`whole_exponent`."""
    kind = table[k, 0]
    directional = kind == DIRECTIONAL or kind == HEADLIGHT
    spot = kind == SPOT
    cr, cg, cb = table[k, 7], table[k, 8], table[k, 9]
    ox, oy, oz = table[k, 1], table[k, 2], table[k, 3]
    dx, dy, dz = table[k, 4], table[k, 5], table[k, 6]
    reach = table[k, 10]
    inv_reach4 = 1.0 / (reach * reach * reach * reach) if reach > 0.0 else 0.0
    scale, offset = table[k, 11], table[k, 12]
    for q in range(n):
        x, y, z = s[X + np.uint64(q)], s[Y + np.uint64(q)], s[Z + np.uint64(q)]
        nx, ny, nz = s[NX + np.uint64(q)], s[NY + np.uint64(q)], s[NZ + np.uint64(q)]
        if directional:
            lx, ly, lz, a = -dx, -dy, -dz, 1.0
        else:
            lx, ly, lz = ox - x, oy - y, oz - z
            d2 = lx * lx + ly * ly + lz * lz
            inv = 1.0 / np.sqrt(d2)
            lx, ly, lz = lx * inv, ly * inv, lz * inv
            window = min(max(1.0 - d2 * d2 * inv_reach4, 0.0), 1.0)
            cone = min(max(-(lx * dx + ly * dy + lz * dz) * scale + offset, 0.0), 1.0)
            cone = cone * cone if spot else 1.0  # noqa: FURB136
            a = window * cone / d2 if d2 > 0.0 else 0.0  # noqa: FURB136
        a *= s[SHADE + np.uint64(q)]
        ndl = nx * lx + ny * ly + nz * lz
        hx, hy, hz = lx + s[VX + np.uint64(q)], ly + s[VY + np.uint64(q)], lz + s[VZ + np.uint64(q)]
        hl = np.sqrt(hx * hx + hy * hy + hz * hz)
        ndh = (nx * hx + ny * hy + nz * hz) / hl if hl > 0.0 else 0.0  # noqa: FURB136
        lit = ndl > 0.0 and a > 0.0  # else nothing (a NaN from a point at the light included)
        s[SHADE + np.uint64(q)] = a if lit else 0.0  # noqa: FURB136
        s[NDL + np.uint64(q)] = ndl
        s[NDH + np.uint64(q)] = max(ndh, 0.0)
    highlights(s, n, whole)
    for q in range(n):
        a, ndl, highlight = s[SHADE + np.uint64(q)], s[NDL + np.uint64(q)], s[POWER + np.uint64(q)]
        red = a * cr * (s[BR + np.uint64(q)] * ndl + s[SR + np.uint64(q)] * highlight)
        green = a * cg * (s[BG + np.uint64(q)] * ndl + s[SG + np.uint64(q)] * highlight)
        blue = a * cb * (s[BB + np.uint64(q)] * ndl + s[SB + np.uint64(q)] * highlight)
        lit = a > 0.0
        s[AR + np.uint64(q)] += red if lit else 0.0  # noqa: FURB136
        s[AG + np.uint64(q)] += green if lit else 0.0  # noqa: FURB136
        s[AB + np.uint64(q)] += blue if lit else 0.0  # noqa: FURB136


@kernel(inline="always")
def _shade_chunk(s, n, color, j, lit, shadows, perspective_maps):
    """Steps 2-4 for the chunk's ``n`` pixels of image row ``j``; ``shadows`` and
    ``perspective_maps`` the record's (None: no light has a shadow map; only parallel ones)."""
    table, eye, perspective, view, encode_table = lit[0], lit[1], lit[2], lit[3], lit[14]
    _orient(s, n, eye, perspective, view)
    whole = whole_exponent(s, n)
    for k in range(table.shape[0]):
        if table[k, 0] == AMBIENT:
            cr, cg, cb = table[k, 7], table[k, 8], table[k, 9]
            for q in range(n):
                s[AR + np.uint64(q)] += s[BR + np.uint64(q)] * cr
                s[AG + np.uint64(q)] += s[BG + np.uint64(q)] * cg
                s[AB + np.uint64(q)] += s[BB + np.uint64(q)] * cb
            continue
        light_reaches(s, n, k, table, shadows, perspective_maps)
        _add_light(s, n, k, table, whole)
    encode_chunk(s, n, encode_table)
    ju = np.uint64(j)
    for q in range(n):
        put_rgba(color, ju, np.uint64(np.int64(s[COLUMN + np.uint64(q)])), np.uint32(np.int64(s[SHADE + np.uint64(q)])))


@kernel(inline="always")
def _prefetch_faces(lid, r, lo, hi, bary, lit):
    """Ask for what the gather will read of each face seen in row ``r`` of ``lid`` (columns
    ``lo .. hi``): its barycentric rows, corners, their positions and normals. Called a row
    ahead: a face's first run would otherwise wait on these misses one after another (the
    corners' positions only once its corners have come)."""
    positions, faces, smooth, corner_normals, normal_corners = lit[4], lit[5], lit[9], lit[10], lit[11]
    ru = np.uint64(r)
    last = -1
    for i in range(lo, hi + 1):
        f = lid[ru, np.uint64(i)]
        if f >= 0 and f != last:
            last = f
            prefetch_item(bary, f, 0)
            prefetch_item(bary, f, 8)
            prefetch_item(faces, f, 0)
            if smooth:
                prefetch_item(normal_corners, f, 0)
    last = -1
    for i in range(lo, hi + 1):
        f = lid[ru, np.uint64(i)]
        if f >= 0 and f != last:
            last = f
            for k in range(3):
                prefetch_item(positions, faces[f, k], 0)
                if smooth:
                    prefetch_item(corner_normals, normal_corners[f, k], 0)


@kernel(inline="always")
def lit_fields(lit):
    """The record's fields as a tuple, unpacked once per band."""
    return (lit.lights, lit.eye, lit.perspective, lit.toward_viewer, lit.positions, lit.faces, lit.specular,
            lit.shininess, lit.emission, lit.smooth, lit.corner_normals, lit.normal_corners, lit.face_normals,
            lit.two_sided, lit.encode, lit.decode, lit.shadows, lit.perspective_maps)


@kernel(refcounts=False)
def resolve_lit_rows(y0, y1, shading, target, sample, lid, row_lo, row_hi, lighting):
    """:func:`rasterkit.raster.kernels.shade.resolve_row` for rows ``y0 .. y1 - 1`` of a frame
    lit per pixel (:func:`rasterkit.raster.kernels.bands.draw_bands`' arguments; ``lid`` the
    band's rows of the visibility buffer, ``row_lo``, ``row_hi`` the columns each may have
    been written in): shading mode SHADE_FLAT (each face's own colour ``packed``) or
    SHADE_SMOOTH (``vertex_colors`` through ``corners``); ``lighting`` the frame's
    :class:`~rasterkit.raster.kernels.records.PixelLights`.

    One function, the chunk's shading at one place in it: each kernel a caller calls is
    compiled again into the caller's code, so a chain of them would compile the lighting
    once per link."""
    mode, _, _, packed, vertex_colors, _, bary, corners = shading
    _, _, _, color, write_ids, ids = target
    lit = lit_fields(lighting)
    sample_x, sample_y = sample.x / ONE, sample.y / ONE
    s = stack_floats(SCRATCH)
    lines = stack_floats(_LINES)
    for r in range(y1 - y0):
        if r + 1 < y1 - y0:
            _prefetch_faces(lid, r + 1, row_lo[r + 1], row_hi[r + 1], bary, lit)
        j, lo, hi = y0 + r, row_lo[r], row_hi[r]
        ru, ju, base = np.uint64(r), np.uint64(j), np.uint64(lo)
        px, py = lo + 0.5 + sample_x, j + 0.5 + sample_y
        width = hi - lo + 1
        n = 0  # pixels in the chunk
        k = 0  # the next column of the row to gather
        end = 0  # the end of the current run of one face's pixels
        f = -1
        while True:
            while n < CHUNK:  # fill the chunk, run by run, a run in pieces where it does not fit
                if k >= end:
                    while k < width and lid[ru, base + np.uint64(k)] < 0:
                        k += 1
                    if k >= width:
                        break
                    f = lid[ru, base + np.uint64(k)]
                    end = k + 1
                    while end < width and lid[ru, base + np.uint64(end)] == f:
                        end += 1
                    for q in range(k, end):
                        i = base + np.uint64(q)
                        lid[ru, i] = -1
                        if write_ids:
                            ids[ju, i] = f
                count = min(end - k, CHUNK - n)
                _gather(s, lines, n, count, f, lo + k, px + k, py, mode, packed, vertex_colors, corners, bary, lit)
                n += count
                k += count
            if n == 0:
                break
            _shade_chunk(s, n, color, j, lit, lit[16], lit[17])
            n = 0
