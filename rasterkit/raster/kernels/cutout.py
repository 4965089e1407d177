"""Cut-out faces: the raster of a face whose material's alpha (a ``map_d`` opacity map, or the
alpha of its diffuse map, times its ``opacity``) is below one half somewhere. Such a fragment
is not drawn at all: it neither passes the depth test nor writes the depth, the visible face
(the id map) or a colour, so what lies behind shows through (OpenGL's ``discard``; glTF's
``alphaMode: MASK`` with a cut-off of 0.5).

A covered pixel whose depth passes the test looks its alpha up at its sample point, as the
resolve looks the colour up (:mod:`rasterkit.raster.kernels.texture_shade`), and is kept when
the alpha is at least :data:`CUTOFF`. Only the records of cut-out faces come here; the others
keep the vectorised raster of :mod:`rasterkit.raster.kernels.triangle`.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.kernels.sample import CHANNELS, FILTER, FILTER_TRILINEAR, sample, texture_lod
from rasterkit.raster.kernels.face_setup import ONE
from rasterkit.raster.kernels.triangle import depth_plane, next_row, row_bounds, row_span, triangle_edges
from rasterkit.raster.kernels.triangle_samples import moved_box
from rasterkit.runtime.jit import kernel

#: Fragments whose alpha is below this are not drawn.
CUTOFF = 0.5


@kernel(inline="always")
def _alpha(face, x, y, bary, textures):
    """The alpha of ``face`` at raster point (x, y): its alpha texture's alpha channel (or,
    for a texture without one, its first channel) times the face's opacity."""
    t = textures.face_alpha[face]
    a0, b0, c0 = bary[face, 0], bary[face, 1], bary[face, 2]
    a1, b1, c1 = bary[face, 3], bary[face, 4], bary[face, 5]
    a2, b2, c2 = bary[face, 6], bary[face, 7], bary[face, 8]
    w0 = a0 * x + b0 * y + c0
    w1 = a1 * x + b1 * y + c1
    w2 = a2 * x + b2 * y + c2
    inv = 1.0 / (w0 + w1 + w2)
    uv = textures.corner_uv
    u0, v0, u1, v1, u2, v2 = uv[face, 0], uv[face, 1], uv[face, 2], uv[face, 3], uv[face, 4], uv[face, 5]
    u = (w0 * u0 + w1 * u1 + w2 * u2) * inv
    v = (w0 * v0 + w1 * v1 + w2 * v2) * inv
    levels, samplers, transforms = textures.levels, textures.samplers, textures.transforms
    lod = 0.0
    if samplers[t, FILTER] == FILTER_TRILINEAR:
        sx, sy = a0 + a1 + a2, b0 + b1 + b2
        lod = texture_lod(levels, samplers, transforms, t, (a0 * u0 + a1 * u1 + a2 * u2 - u * sx) * inv,
                          (a0 * v0 + a1 * v1 + a2 * v2 - v * sx) * inv, (b0 * u0 + b1 * u1 + b2 * u2 - u * sy) * inv,
                          (b0 * v0 + b1 * v1 + b2 * v2 - v * sy) * inv)
    r, _, _, a = sample(textures.texels, levels, samplers, transforms, textures.decode, t, u, v, lod)
    return (a if samplers[t, CHANNELS] == 4 else r) * textures.face_opacity[face]


@kernel(refcounts=False)
def raster_cutout(x0, y0_, x1, y1_, x2, y2, tri_z, t, i_lo, i_hi, j_lo, j_hi, tag, y0, depth, lid, row_lo, row_hi,
                  face, sample_x, sample_y, bary, textures):
    """:func:`rasterkit.raster.kernels.triangle.raster_vertices` of a cut-out face: the same
    spans and depths, a fragment kept only where :func:`_alpha` at its sample point (pixel
    centre plus ``sample_x, sample_y`` pixels) is at least :data:`CUTOFF`. Returns the
    fragments depth-tested."""
    e0, e1, e2 = triangle_edges(x0, y0_, x1, y1_, x2, y2)
    zc, gx, gy = depth_plane(x0, y0_, x1, y1_, x2, y2, float(tri_z[t, 0]), float(tri_z[t, 1]), float(tri_z[t, 2]))
    tag = np.int32(tag)
    bounds = row_bounds(j_lo, e0, e1, e2)
    covered = 0
    for j in range(j_lo, j_hi + 1):
        lo, hi = row_span(bounds, i_lo, i_hi)
        bounds = next_row(bounds)
        if lo > hi:
            continue
        r = j - y0
        ru = np.uint64(r)
        for i in range(lo, hi + 1):
            iu = np.uint64(i)
            z = np.float32(zc + gx * i + gy * j)
            if z < depth[ru, iu] and _alpha(face, i + 0.5 + sample_x, j + 0.5 + sample_y, bary, textures) >= CUTOFF:
                depth[ru, iu] = z
                lid[ru, iu] = tag
        covered += hi - lo + 1
        row_lo[r] = min(row_lo[r], lo)
        row_hi[r] = max(row_hi[r], hi)
    return covered


@kernel(inline="always")
def cutout_band(t, tag, face, tri_xy, tri_z, tri_box, y0, y1, sample, depth, lid, row_lo, row_hi, bary, textures):
    """:func:`rasterkit.raster.kernels.triangle.raster_band` of record ``t`` of the cut-out
    ``face`` (its records drawn at ``sample``, a Sample, already moved there)."""
    j_lo, j_hi = max(tri_box[t, 2], y0), min(tri_box[t, 3], y1 - 1)
    if j_lo > j_hi:
        return 0
    return raster_cutout(np.int64(tri_xy[t, 0]), np.int64(tri_xy[t, 1]), np.int64(tri_xy[t, 2]),
                         np.int64(tri_xy[t, 3]), np.int64(tri_xy[t, 4]), np.int64(tri_xy[t, 5]), tri_z, t,
                         np.int64(tri_box[t, 0]), np.int64(tri_box[t, 1]), j_lo, j_hi, tag, y0, depth, lid, row_lo,
                         row_hi, face, sample.x / ONE, sample.y / ONE, bary, textures)


@kernel(inline="always")
def cutout_band_at(t, tag, face, tri_xy, tri_z, sample, y0, y1, depth, lid, row_lo, row_hi, bary, textures):
    """:func:`rasterkit.raster.kernels.triangle_samples.raster_band_at` of record ``t`` of the
    cut-out ``face``: the record moved to ``sample`` here."""
    sx, sy = sample
    x0, y0_, x1 = np.int64(tri_xy[t, 0]) - sx, np.int64(tri_xy[t, 1]) - sy, np.int64(tri_xy[t, 2]) - sx
    y1_, x2, y2 = np.int64(tri_xy[t, 3]) - sy, np.int64(tri_xy[t, 4]) - sx, np.int64(tri_xy[t, 5]) - sy
    i_lo, i_hi, j_lo, j_hi = moved_box(x0, y0_, x1, y1_, x2, y2, np.int64(depth.shape[1]), np.int64(y0),
                                       np.int64(y1) - 1)
    if j_lo > j_hi:
        return 0
    return raster_cutout(x0, y0_, x1, y1_, x2, y2, tri_z, t, i_lo, i_hi, j_lo, j_hi, tag, y0, depth, lid, row_lo,
                         row_hi, face, sx / ONE, sy / ONE, bary, textures)
