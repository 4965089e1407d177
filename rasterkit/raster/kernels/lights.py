"""Blinn-Phong lighting of surface points under a render's lights
(:func:`rasterkit.raster.lights.light_table`), in linear light.

At a point ``p`` with unit normal ``n``, seen along the unit ``v`` (towards the viewer), each
light gives its linear colour ``C`` (colour times intensity) times its attenuation ``a`` and
the direction ``l`` towards it:

    ambient:  base · C
    others:   a · C · (base · max(n · l, 0) + specular · max(n · h, 0)^shininess)  where n · l > 0,
              h = normalize(l + v)

(directional and headlight: ``a = 1``; point and spot: ``a = 1 / d²`` times glTF's range
window ``clamp(1 - (d / range)⁴, 0, 1)``, and for a spot the cone's
``clamp(cos · scale + offset, 0, 1)²``; times the light's shadow factor where it has a shadow
map, :func:`shadow_factor`). The sum, plus ``emission``, is clamped to [0, 1] per
channel and encoded to sRGB. A two-sided surface seen from behind (``n · v < 0``) is lit with
its normal turned towards the viewer.
"""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.cull import per_face
from rasterkit.runtime.jit import kernel

# the kind codes of rasterkit.raster.lights.KINDS
_AMBIENT, _DIRECTIONAL, _POINT, _SPOT, _HEADLIGHT = 0, 1, 2, 3, 4


@kernel(inline="always")
def decode(c):
    """Linear light of the sRGB value ``c`` in [0, 1]."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


@kernel(inline="always")
def encode255(x):
    """The sRGB encoding of linear ``x`` (clamped to [0, 1]; NaN gives 0), times 255."""
    x = x if x > 0.0 else 0.0  # noqa: FURB136 - the select sends NaN to 0
    x = x if x < 1.0 else 1.0  # noqa: FURB136
    return 255.0 * (12.92 * x if x <= 0.0031308 else 1.055 * x ** (1.0 / 2.4) - 0.055)


@kernel(inline="always")
def _map_texel(maps, m, i, j):
    """Texel (i, j) of map ``m``, the nearest inside it."""
    size = maps.shape[1]
    i = min(max(i, 0), size - 1)
    j = min(max(j, 0), size - 1)
    return maps[np.uint64(m), np.uint64(j), np.uint64(i)]


@kernel(inline="always")
def _cube_face(k, table, first, px, py, pz):
    """The map of light ``k``'s cube (its six from ``first``) that the point is seen in: the
    face of the largest component of the direction from the light."""
    dx, dy, dz = px - table[k, 1], py - table[k, 2], pz - table[k, 3]
    ax, ay, az = abs(dx), abs(dy), abs(dz)
    if ax >= ay and ax >= az:
        return first + (0 if dx >= 0.0 else 1)
    if ay >= az:
        return first + (2 if dy >= 0.0 else 3)
    return first + (4 if dz >= 0.0 else 5)


@kernel(inline="always")
def _plane_gradient(axes, mu, nx, ny, nz, ex, ey, ez, depth):
    """How the map depth (the depth buffer's, :mod:`rasterkit.raster.shadows`) at which the
    texels' rays meet the plane through the point ``e`` (from map ``mu``'s eye) with normal
    (nx, ny, nz) changes per texel along the map's x and y: ``(gi, gj, scale)``, ``scale`` the
    map depth per unit of distance along the axis at the point's ``depth``. Affine in the
    texel for both kinds of camera: a parallel map stores ``(d - n) / (f - n)``, and the
    plane's ``d`` is affine across its texels; a perspective map stores
    ``f / (f - n) - (f n / (f - n)) / d``, and the plane's ``1 / d`` is affine across them.
    (0, 0) when the texels' rays run along the plane."""
    near, far, step = axes[mu, 8], axes[mu, 9], axes[mu, 6]
    nr = nx * axes[mu, 10] + ny * axes[mu, 11] + nz * axes[mu, 12]  # the normal along the map's x, y
    nu = nx * axes[mu, 13] + ny * axes[mu, 14] + nz * axes[mu, 15]
    if axes[mu, 7] > 0.0:  # perspective: 1/d(i, j) = 1/depth + s (di n.r + dj n.u) / n.e
        k = far * near / (far - near)
        ne = nx * ex + ny * ey + nz * ez
        if not abs(ne) > 1e-12 * depth:
            return 0.0, 0.0, k / (depth * depth)
        g = -k * step / ne
        return g * nr, g * nu, k / (depth * depth)
    scale = 1.0 / (far - near)  # parallel: d(i, j) = depth - s (di n.r + dj n.u) / n.f
    nf = nx * axes[mu, 3] + ny * axes[mu, 4] + nz * axes[mu, 5]
    if not abs(nf) > 1e-6:
        return 0.0, 0.0, scale
    g = -step * scale / nf
    return g * nr, g * nu, scale


@kernel(inline="always")
def shadow_factor(k, table, px, py, pz, nx, ny, nz, sx, sy, sz, shadows):
    """The fraction (0 to 1) of light ``k`` of ``table`` that reaches the point (px, py, pz)
    of a face with unit normal (nx, ny, nz), lit on the side of its shading normal (sx, sy,
    sz): 1 for a light without a shadow map (column 13 of its row -1); 0 when the light is
    behind the face's plane as seen from that side (an opaque face shadows its own back: a
    shading normal bent towards the light near a curved surface's terminator does not let
    light through the face); else the share of the map's texels around the point's (a square
    of ``2 r + 1`` a side, ``r = ceil(softness)``: percentage-closer filtering) that see
    nothing nearer the light than the point's surface there. The depth of each texel is
    compared with the depth at which its ray meets the plane of the point's face (a
    receiver-plane bias, so that a lit face does not shadow itself at any slope; at most 100
    texels beyond the point: a plane seen almost edge-on runs far from the surface, and what
    the texel sees short of that still shadows the point), less a leeway of a texel plus the
    depth the plane slopes over a quarter texel and over the filter's reach (its slope
    ``tan`` of the angle between the face's normal and the light, at most 20): a curved
    surface leaves its face's plane across the filter, by more the more it slopes away from
    the light. The comparisons are in the map's own depth units, where the plane's depth is
    affine across the texels (:func:`_plane_gradient`): a few divisions per point, none per
    texel. ``shadows``: ``(maps, matrices, axes, softness)`` of
    :class:`rasterkit.raster.shadows.ShadowMaps`."""
    first = np.int64(table[k, 13])
    if first < 0:
        return 1.0
    kind = np.int64(table[k, 0])
    if kind == _DIRECTIONAL or kind == _HEADLIGHT:
        lx, ly, lz = -table[k, 4], -table[k, 5], -table[k, 6]
    else:
        lx, ly, lz = table[k, 1] - px, table[k, 2] - py, table[k, 3] - pz
    if nx * sx + ny * sy + nz * sz < 0.0:  # the face's normal on the side that is lit
        nx, ny, nz = -nx, -ny, -nz
    towards = nx * lx + ny * ly + nz * lz
    if not towards > 0.0:
        return 0.0  # the light is behind the face
    across = max(lx * lx + ly * ly + lz * lz - towards * towards, 0.0)  # (|l| sin θ)², θ from the normal
    maps, matrices, axes, softness = shadows
    m = first if table[k, 14] < 2.0 else _cube_face(k, table, first, px, py, pz)
    mu = np.uint64(m)
    w = matrices[mu, 3, 0] * px + matrices[mu, 3, 1] * py + matrices[mu, 3, 2] * pz + matrices[mu, 3, 3]
    if not w > 0.0:
        return 1.0
    inverse = 1.0 / w if axes[mu, 7] > 0.0 else 1.0  # a parallel map's w is 1
    x = (matrices[mu, 0, 0] * px + matrices[mu, 0, 1] * py + matrices[mu, 0, 2] * pz + matrices[mu, 0, 3]) * inverse
    y = (matrices[mu, 1, 0] * px + matrices[mu, 1, 1] * py + matrices[mu, 1, 2] * pz + matrices[mu, 1, 3]) * inverse
    size = maps.shape[1]
    if not (x >= 0.0 and y >= 0.0 and x < size and y < size):
        return 1.0  # outside the map: nothing there casts a shadow
    z = (matrices[mu, 2, 0] * px + matrices[mu, 2, 1] * py + matrices[mu, 2, 2] * pz + matrices[mu, 2, 3]) * inverse
    ex, ey, ez = px - axes[mu, 0], py - axes[mu, 1], pz - axes[mu, 2]
    depth = ex * axes[mu, 3] + ey * axes[mu, 4] + ez * axes[mu, 5]
    gi, gj, scale = _plane_gradient(axes, mu, nx, ny, nz, ex, ey, ez, depth)
    texel = axes[mu, 6] * (depth if axes[mu, 7] > 0.0 else 1.0)
    reach = np.int64(np.ceil(softness))
    slope = min(np.sqrt(across) / towards, 20.0)
    leeway = texel * (1.0 + slope * (0.25 + reach)) * scale
    cap = z + 100.0 * texel * scale
    return filtered(maps, m, x, y, z, gi, gj, cap, leeway, reach)


@kernel(refcounts=False)
def shadow_at(k, table, px, py, pz, nx, ny, nz, sx, sy, sz, shadows):
    """:func:`shadow_factor`, compiled once on its own: not into each kernel that lights
    pixels (:func:`light_sum` calls it for a light with a shadow map)."""
    return shadow_factor(k, table, px, py, pz, nx, ny, nz, sx, sy, sz, shadows)


@kernel(inline="always")
def parallel_map(k, table, shadows):
    """Whether light ``k`` (with a shadow map) is directional and its map parallel: then
    :func:`shadow_factor` splits into terms of the face (:func:`parallel_terms`) and a
    lookup of the point (:func:`filtered`; its map position by the map's matrix alone: a
    parallel map's w is 1)."""
    kind = np.int64(table[k, 0])
    if not (kind == _DIRECTIONAL or kind == _HEADLIGHT) or table[k, 14] >= 2.0:
        return False
    return shadows[2][np.uint64(np.int64(table[k, 13])), 7] <= 0.0


@kernel(inline="always")
def parallel_terms(k, table, nx, ny, nz, shadows):
    """What :func:`shadow_factor` of light ``k`` under a parallel map (:func:`parallel_map`)
    works out from a face's unit normal (nx, ny, nz) alone: ``(towards, gi, gj, leeway,
    above)``, the light's cosine on that side of the face, the plane's depth gradient across
    the map, the leeway, and how far above the point's depth the plane is cut off. The same
    on the face's other side but for the sign of ``towards`` (the normal turned: its products
    with the light and the map's axes change sign in pairs)."""
    lx, ly, lz = -table[k, 4], -table[k, 5], -table[k, 6]
    towards = nx * lx + ny * ly + nz * lz
    lit = abs(towards)
    across = max(lx * lx + ly * ly + lz * lz - lit * lit, 0.0)
    maps, matrices, axes, softness = shadows
    mu = np.uint64(np.int64(table[k, 13]))
    gi, gj, scale = _plane_gradient(axes, mu, nx, ny, nz, 0.0, 0.0, 0.0, 1.0)  # parallel: no e, depth
    texel = axes[mu, 6] * 1.0
    reach = np.int64(np.ceil(softness))
    slope = min(np.sqrt(across) / lit, 20.0) if lit > 0.0 else 0.0  # noqa: FURB136
    leeway = texel * (1.0 + slope * (0.25 + reach)) * scale
    return towards, gi, gj, leeway, 100.0 * texel * scale


@kernel(inline="always")
def filtered(maps, m, x, y, z, gi, gj, cap, leeway, reach):
    """The share of the ``2 reach + 1`` texels square of map ``m`` around the point's (x, y)
    (raster, its depth ``z``) whose depth is at least the plane's there (``z`` stepped by
    ``gi``, ``gj`` per texel; at most ``cap``) less ``leeway``, all in the map's units. The
    sums have no branch (a texel's outcome is hard to predict near a shadow's edge), and a
    square within the map needs no clamping."""
    size = maps.shape[1]
    i0, j0 = np.int64(x), np.int64(y)
    row = z + gi * (i0 - reach + 0.5 - x) + gj * (j0 - reach + 0.5 - y)  # the plane at the square's first texel
    seen = 0
    if i0 >= reach and j0 >= reach and i0 + reach < size and j0 + reach < size:
        mu = np.uint64(m)
        if reach == 1:  # 3 x 3, the same sums with fixed trip counts: unrolled, no loop branches
            for dj in range(3):
                expected, ju = row, np.uint64(j0 + dj - 1)
                for di in range(3):
                    seen += maps[mu, ju, np.uint64(i0 + di - 1)] >= min(expected, cap) - leeway
                    expected += gi
                row += gj
            return seen / 9
        for dj in range(-reach, reach + 1):
            expected, ju = row, np.uint64(j0 + dj)
            for di in range(-reach, reach + 1):
                seen += maps[mu, ju, np.uint64(i0 + di)] >= min(expected, cap) - leeway
                expected += gi
            row += gj
    else:
        for dj in range(-reach, reach + 1):
            expected = row
            for di in range(-reach, reach + 1):
                seen += _map_texel(maps, m, i0 + di, j0 + dj) >= min(expected, cap) - leeway
                expected += gi
            row += gj
    side = 2 * reach + 1
    return seen / (side * side)


@kernel(inline="always")
def toward_viewer(px, py, pz, eye, perspective, view):
    """The unit direction from the point (px, py, pz) towards the viewer: the ``eye`` of a
    ``perspective`` camera, else along the parallel camera's ``view``."""
    if not perspective:
        return view[0], view[1], view[2]
    vx, vy, vz = eye[0] - px, eye[1] - py, eye[2] - pz
    length = np.sqrt(vx * vx + vy * vy + vz * vz)
    if length > 0.0:
        return vx / length, vy / length, vz / length
    return vx, vy, vz


@kernel(inline="always")
def light_sum(px, py, pz, nx, ny, nz, vx, vy, vz, base, specular, shininess, table, shadows, plane):
    """The linear (r, g, b) that the lights of ``table`` send back from the point (px, py, pz)
    with unit normal (nx, ny, nz), seen along the unit (vx, vy, vz); ``base`` and
    ``specular`` linear (r, g, b) tuples (see the module documentation); ``shadows`` the
    frame's shadow maps (:func:`shadow_factor`), looked up with ``plane``, the unit normal
    of the face the point is on (its shading normal may be interpolated or bent)."""
    r = g = b = 0.0
    for k in range(table.shape[0]):
        kind = np.int64(table[k, 0])
        cr, cg, cb = table[k, 7], table[k, 8], table[k, 9]
        if kind == _AMBIENT:
            r, g, b = r + base[0] * cr, g + base[1] * cg, b + base[2] * cb
            continue
        if kind == _DIRECTIONAL or kind == _HEADLIGHT:
            lx, ly, lz, a = -table[k, 4], -table[k, 5], -table[k, 6], 1.0
        else:
            lx, ly, lz = table[k, 1] - px, table[k, 2] - py, table[k, 3] - pz
            d2 = lx * lx + ly * ly + lz * lz
            if not d2 > 0.0:
                continue
            d = np.sqrt(d2)
            lx, ly, lz, a = lx / d, ly / d, lz / d, 1.0 / d2
            reach = table[k, 10]
            if reach > 0.0:
                q = d / reach
                w = min(max(1.0 - q * q * q * q, 0.0), 1.0)
                a *= w
            if kind == _SPOT:
                cos = -(lx * table[k, 4] + ly * table[k, 5] + lz * table[k, 6])
                t = min(max(cos * table[k, 11] + table[k, 12], 0.0), 1.0)
                a *= t * t
        ndl = nx * lx + ny * ly + nz * lz
        if not ndl > 0.0 or a == 0.0:
            continue
        if table[k, 13] >= 0.0:  # the light has a shadow map
            a *= shadow_at(k, table, px, py, pz, plane[0], plane[1], plane[2], nx, ny, nz, shadows)
            if a == 0.0:
                continue
        hx, hy, hz = lx + vx, ly + vy, lz + vz
        hl = np.sqrt(hx * hx + hy * hy + hz * hz)
        highlight = 0.0
        if hl > 0.0:
            ndh = (nx * hx + ny * hy + nz * hz) / hl
            highlight = max(ndh, 0.0) ** shininess
        r += a * cr * (base[0] * ndl + specular[0] * highlight)
        g += a * cg * (base[1] * ndl + specular[1] * highlight)
        b += a * cb * (base[2] * ndl + specular[2] * highlight)
    return r, g, b


@kernel(fastmath=False)
def lit_colors(points, normals, base, specular, shininess, emission, table, eye, perspective, view, two_sided,
               shadows):
    """Blinn-Phong colours of K surface points.

    Parameters
    ----------
    points, normals : (K, 3) float64
        World space; the normals unit length (a zero normal gets the ambient light only).
    base : (B, 3) float32
        sRGB colours 0..255, one per point (``B == K``) or one for all (``B == 1``).
    specular : (S, 3) float64, shininess : (S,) float64, emission : (S, 3) float64
        Linear light, one per point (``S == K``) or one for all (``S == 1``).
    table : (L, 14) float64
        :func:`rasterkit.raster.lights.light_table`.
    eye : (3,) float64
        The camera's eye, world space: the viewer of a ``perspective`` camera.
    perspective : bool
    view : (3,) float64
        Unit direction towards the viewer of a parallel camera.
    two_sided : bool or (K,) bool
        Points lit on both sides (:func:`rasterkit.raster.kernels.cull.per_face`).
    shadows : tuple
        The frame's shadow maps (:func:`shadow_factor`; none: empty arrays).

    Returns
    -------
    (K, 3) float32
        sRGB colours 0..255 (not rounded).
    """
    k_count = points.shape[0]
    out = np.empty((k_count, 3), np.float32)
    one_base, one_spec = base.shape[0] == 1, specular.shape[0] == 1
    for k in range(k_count):
        px, py, pz = points[k, 0], points[k, 1], points[k, 2]
        vx, vy, vz = toward_viewer(px, py, pz, eye, perspective, view)
        nx, ny, nz = normals[k, 0], normals[k, 1], normals[k, 2]
        if per_face(two_sided, k) and nx * vx + ny * vy + nz * vz < 0.0:
            nx, ny, nz = -nx, -ny, -nz
        kb = 0 if one_base else k
        ks = 0 if one_spec else k
        albedo = (decode(base[kb, 0] / 255.0), decode(base[kb, 1] / 255.0), decode(base[kb, 2] / 255.0))
        r, g, b = light_sum(px, py, pz, nx, ny, nz, vx, vy, vz, albedo,
                            (specular[ks, 0], specular[ks, 1], specular[ks, 2]), shininess[ks], table, shadows,
                            (nx, ny, nz))
        out[k, 0] = encode255(r + emission[ks, 0])
        out[k, 1] = encode255(g + emission[ks, 1])
        out[k, 2] = encode255(b + emission[ks, 2])
    return out
