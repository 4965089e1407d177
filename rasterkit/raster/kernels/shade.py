"""Shading: Lambert lighting, and writing the colour of visible pixels (the normals they
use: :mod:`rasterkit.raster.kernels.normals`).

Lighting
    ``intensity = ambient + (1 - ambient) * max(0, n · l)`` with unit normal ``n`` and unit
    direction ``l`` from the surface towards the light; the colour is ``base * intensity``.
    A *headlight* (the renderer's default) is ``l`` pointing towards the camera:
    ``(0, 0, 1)`` for camera-space normals, as the camera looks down -Z. With ``two_sided=True`` the term is
    ``|n · l|``: a face seen from behind is lit as if its normal were flipped towards the
    viewer (OpenGL's two-sided lighting). Use it when back faces are drawn (``cull="none"``),
    otherwise their inside shows up flat at the ambient level.

Resolve
    The rasterizer leaves, per band, the index of the visible face at each pixel it wrote
    (:mod:`rasterkit.raster.kernels.triangle`); :func:`resolve_row` then writes each such pixel's
    colour once, so hidden fragments never cost a colour computation. Smooth
    (Gouraud) colours are interpolated perspective-correctly from the face's *unclipped*
    homogeneous vertices (see :func:`bary_matrices`), so clipping never needs to carry
    attributes.
"""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.cull import per_face
from rasterkit.raster.kernels.normals import cross, face_normals
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.runtime.jit import kernel

# How resolve_row colours a pixel; chosen once per draw.
SHADE_NONE = 0  # depth (and ids) only
SHADE_FLAT = 1  # per-face colour
SHADE_SMOOTH = 2  # per-vertex colour, perspective-correct
SHADE_TAGGED = 3  # per-face colour carried in the visibility buffer itself (no ids wanted)


@kernel
def lambert(normals, base, light, points, positional, ambient, two_sided):
    """Lambert colours ``base * (ambient + (1 - ambient) * max(0, n · l))``.

    Parameters
    ----------
    normals : (K, 3) float64
        Unit normals (zero normals get the ambient term only).
    base : (B, 3) float32
        Colour(s) 0..255: one per normal (``B == K``) or one for all (``B == 1``).
    light : (3,) float64
        Unit direction towards the light, or the light's position when ``positional``.
    points : (K, 3) float64
        Surface points (face centroids or vertices); read only when ``positional``.
    positional : bool
        True: ``l = normalize(light - points[k])`` (a point light, e.g. at the eye);
        False: ``l = light`` everywhere.
    ambient : float
        In [0, 1].
    two_sided : bool or (K,) bool
        Use ``|n · l|`` instead of ``max(0, n · l)`` (see the module docstring), for every
        normal or for each.

    Returns
    -------
    (K, 3) float32
        Colours 0..255, in the same space-independent units as ``base``.
    """
    k_count = normals.shape[0]
    out = np.empty((k_count, 3), np.float32)
    single = base.shape[0] == 1
    for k in range(k_count):
        lx, ly, lz = light[0], light[1], light[2]
        if positional:
            lx, ly, lz = lx - points[k, 0], ly - points[k, 1], lz - points[k, 2]
            length = np.sqrt(lx * lx + ly * ly + lz * lz)
            if length > 0.0:
                lx, ly, lz = lx / length, ly / length, lz / length
        cos = normals[k, 0] * lx + normals[k, 1] * ly + normals[k, 2] * lz
        cos = abs(cos) if per_face(two_sided, k) else max(cos, 0.0)
        intensity = ambient + (1.0 - ambient) * cos
        src = 0 if single else np.int64(k)
        for c in range(3):
            out[k, c] = base[src, c] * intensity
    return out


@kernel
def flat_packed(positions, faces, base, scale, light, ambient, two_sided):
    """Per-face Lambert colours under a distant light, packed.

    The same as :func:`lambert` (not positional) of the face normals
    ``face_normals(positions, faces)`` rounded to float32 (as :attr:`rasterkit.Mesh.face_normals`
    keeps them) on ``base * scale``, then :func:`pack_colors`, to the bit, except that a face
    whose normal is not finite (a NaN or infinite corner) gets the ambient term only, like a
    degenerate face.

    Parameters
    ----------
    positions : (N, 3) float64
    faces : (M, 3) int64
    base : (B, 3) float32
        Colour(s), one per face (``B == M``) or one for all (``B == 1``), in units that
        ``scale`` turns into 0..255 (255 for colours in [0, 1]).
    scale : float32
    light : (3,) float64
        Unit direction towards the light.
    ambient : float
    two_sided : bool or (M,) bool
        For every face or for each (:func:`rasterkit.raster.kernels.cull.per_face`).

    Returns
    -------
    (M,) uint32
        Opaque RGBA, R in the low byte (as :func:`pack_colors`).
    """
    m = faces.shape[0]
    normals = face_normals(positions, faces).astype(np.float32)
    out = np.empty(m, np.uint32)
    everyone = np.empty(0, np.int32)
    for ch in range(_COLOR_CHUNKS):
        start, stop = m * ch // _COLOR_CHUNKS, m * (ch + 1) // _COLOR_CHUNKS
        flat_colors(normals, everyone, start, stop - start, base, scale, light, ambient, two_sided, out)
    return out


_COLOR_CHUNKS = 64


#: Faces per block of :func:`flat_colors`.
COLOR_BLOCK = 256


@kernel
def flat_colors(normals, listed, start, count, base, scale, light, ambient, two_sided, packed):
    """The packed Lambert colours of ``count`` faces (as :func:`flat_packed`), into
    ``packed[f]``: the faces ``listed[start: start + count]``, or
    ``start .. start + count - 1`` when ``listed`` is empty.

    ``normals`` (M, 3) float32 are the faces' unit normals (:attr:`rasterkit.Mesh.face_normals`).
    In blocks of COLOR_BLOCK faces: gather each face's cosine and base colour, then light and
    pack the block in a loop without branches (LLVM turns it into vector instructions; a
    face costs about 2.5 ns), then scatter the colours. Written with selects and a 0/1
    factor where ``if`` or a loop-invariant choice of row made the loop three times slower."""
    lx, ly, lz = light[0], light[1], light[2]
    base_step = np.uint64(base.shape[0] != 1)  # base row = face * base_step
    cosines = np.empty(COLOR_BLOCK)
    backs = np.empty(COLOR_BLOCK)  # max(cos, -back * cos): |cos| (1.0) or max(cos, 0) (0.0)
    colours = np.empty(3 * COLOR_BLOCK, np.float32)
    out = np.empty(COLOR_BLOCK, np.uint32)
    for first in range(start, start + count, COLOR_BLOCK):
        n = min(COLOR_BLOCK, start + count - first)
        for k in range(n):
            f = _face_at(listed, first + k)
            cosines[k] = normals[f, 0] * lx + normals[f, 1] * ly + normals[f, 2] * lz
            backs[k] = 1.0 if per_face(two_sided, f) else 0.0
            for c in range(3):
                colours[c * COLOR_BLOCK + k] = base[f * base_step, c] * scale
        for k in range(n):
            intensity = _intensity(cosines[k], backs[k], ambient)
            red = to_u8(np.float32(colours[k] * intensity))
            green = to_u8(np.float32(colours[COLOR_BLOCK + k] * intensity))
            blue = to_u8(np.float32(colours[2 * COLOR_BLOCK + k] * intensity))
            out[k] = np.uint32(red | green << 8 | blue << 16 | 255 << 24)
        for k in range(n):
            packed[_face_at(listed, first + k)] = out[k]


@kernel(inline="always")
def _face_at(listed, k):
    """Face ``listed[k]``, or ``k`` itself when ``listed`` is empty (every face)."""
    return np.uint64(listed[k]) if listed.size else np.uint64(k)


@kernel(inline="always")
def _intensity(cos, back, ambient):
    """Lambert factor ``ambient + (1 - ambient) c`` of a face whose unit normal makes
    ``cos`` with the light: ``c = max(cos, -back * cos)`` (``back`` 1: two-sided, ``|cos|``;
    0: ``max(cos, 0)``); a non-finite ``cos`` (a NaN or infinite corner) counts as 0."""
    cos = max(cos, -back * cos)
    # checked after max: the other way round, LLVM's fast-math folds (reassoc, nsz) merged
    # the two selects and let a NaN through (tested)
    cos = cos if np.isfinite(cos) else 0.0
    return ambient + (1.0 - ambient) * cos


@kernel(inline="always")
def _bary_rows(clip, faces, out, start, stop):
    """Rows ``start .. stop - 1`` of :func:`bary_matrices` into ``out`` (M, 9) float64."""
    for f in range(start, stop):
        scale = 0.0
        for k in range(3):
            v = faces[f, k]
            scale = max(scale, abs(clip[v, 0]), abs(clip[v, 1]), abs(clip[v, 3]))
        if not (scale > 0.0 and np.isfinite(scale)):
            for k in range(9):
                out[f, k] = 0.0
            continue
        for k in range(3):
            p, q = faces[f, (k + 1) % 3], faces[f, (k + 2) % 3]
            out[f, 3 * k], out[f, 3 * k + 1], out[f, 3 * k + 2] = cross(
                clip[p, 0] / scale,
                clip[p, 1] / scale,
                clip[p, 3] / scale,
                clip[q, 0] / scale,
                clip[q, 1] / scale,
                clip[q, 3] / scale,
            )


@kernel
def bary_matrices(clip, faces):
    """Per face, the rows that turn a pixel into perspective-correct barycentrics.

    With ``h_k = (xh, yh, w)`` of vertex ``k`` (homogeneous raster space), a pixel
    ``q = (x, y, 1)`` sees the surface point ``sum_k b_k h_k`` (true 3D barycentrics
    ``b``, since ``h`` is linear in the 3D point) with ``M b ∝ q`` for ``M = [h0 h1 h2]``,
    hence ``b ∝ adj(M) q``: row ``k`` of ``adj(M)`` is ``h_{k+1} x h_{k+2}``. This holds for
    any part of the face that is visible, even when other vertices are behind the eye.
    The ``h`` are scaled by their largest magnitude first (the ratios do not change), so
    huge coordinates do not overflow; a face without a finite, non-zero one gets zeros.

    Parameters
    ----------
    clip : (N, 4) float64
    faces : (M, 3) int64

    Returns
    -------
    (M, 9) float64
        ``[a0, b0, c0, a1, b1, c1, a2, b2, c2]``: ``b_k ∝ a_k x + b_k y + c_k``.
    """
    out = np.empty((faces.shape[0], 9))
    _bary_rows(clip, faces, out, 0, faces.shape[0])
    return out


#: The pieces :func:`bary_chunks` claims.
BARY_CHUNKS = 64


@kernel(refcounts=False)
def bary_chunks(slot, counter, clip, faces, out):
    """:func:`bary_matrices` into ``out`` (M, 9) float64, a worker of
    :func:`rasterkit.runtime.threads.run_workers` (``slot`` unused; chunks of faces claimed
    through ``counter``)."""
    m = faces.shape[0]
    while True:
        chunk = fetch_add(counter, 0, 1)
        if chunk >= BARY_CHUNKS:
            break
        _bary_rows(clip, faces, out, (m * chunk) // BARY_CHUNKS, (m * (chunk + 1)) // BARY_CHUNKS)


@kernel
def all_finite(values):
    """True when no entry of ``values (K, 3) float32`` is NaN or infinite."""
    flat = values.reshape(values.size)
    bad = 0
    for k in range(flat.size):
        bad += not np.isfinite(flat[np.uint64(k)])
    return bad == 0


@kernel(inline="always")
def to_u8(v):
    """A colour value 0..255 (float) -> 0..255 (int), rounded half up, clamped; NaN -> 0.

    Written with selects, not branches, so that loops over colours vectorise.
    """
    v = v if v > 0.0 else 0.0  # noqa: FURB136 - the select sends NaN to 0, max() might not
    return np.int64((v if v < 255.0 else 255.0) + 0.5)  # noqa: FURB136


@kernel
def pack_colors(colors):
    """RGB 0..255 floats -> opaque RGBA packed in uint32 (R in the low byte).

    Parameters
    ----------
    colors : (K, 3) float32
        Rounded half up and clamped to 0..255.

    Returns
    -------
    (K,) uint32
        ``R | G << 8 | B << 16 | 255 << 24``.
    """
    out = np.empty(colors.shape[0], np.uint32)
    for k in range(colors.shape[0]):
        rgb = to_u8(colors[k, 0]) | to_u8(colors[k, 1]) << 8 | to_u8(colors[k, 2]) << 16
        out[k] = np.uint32(rgb | 255 << 24)
    return out


@kernel(inline="always")
def put_rgba(color, j, i, rgba):
    """Write a packed RGBA colour into pixel (j, i) of an (H, W, 3 or 4) uint8 image.

    Spelled out per channel (no loop) so that LLVM merges the four byte stores of RGBA
    into one.
    """
    color[j, i, 0] = rgba & 0xFF
    color[j, i, 1] = (rgba >> 8) & 0xFF
    color[j, i, 2] = (rgba >> 16) & 0xFF
    if color.shape[2] == 4:
        color[j, i, 3] = rgba >> 24


@kernel(inline="always")
def smooth_rgba(f, px, py, vertex_colors, corners, bary):
    """Perspective-correct colour of face ``f`` at raster point (px, py), packed: its corners'
    rows ``corners[f]`` of ``vertex_colors`` interpolated."""
    b0 = bary[f, 0] * px + bary[f, 1] * py + bary[f, 2]
    b1 = bary[f, 3] * px + bary[f, 4] * py + bary[f, 5]
    b2 = bary[f, 6] * px + bary[f, 7] * py + bary[f, 8]
    total = b0 + b1 + b2
    if total != 0.0:
        b0, b1, b2 = b0 / total, b1 / total, b2 / total
    else:
        b0 = b1 = b2 = 1.0 / 3.0
    v0, v1, v2 = corners[f, 0], corners[f, 1], corners[f, 2]
    rgba = 255 << 24
    for c in range(3):
        value = b0 * vertex_colors[v0, c] + b1 * vertex_colors[v1, c] + b2 * vertex_colors[v2, c]
        rgba |= to_u8(value) << (8 * c)
    return np.uint32(rgba)


@kernel(refcounts=False)
def resolve_row(mode, lid, r, j, lo, hi, sample_x, sample_y, packed, vertex_colors, corners, bary, color, write_ids,
                ids):
    """Colour (and id) the pixels ``lo..hi`` of image row ``j`` that a triangle won.

    Reads the band's visibility buffer row ``lid[r]`` (the visible face, -1 for none; in
    SHADE_TAGGED the visible face's RGB colour, ``R | G << 8 | B << 16``) and resets what
    it reads to -1 for the next band.

    Parameters
    ----------
    mode : int
        SHADE_NONE, SHADE_FLAT, SHADE_TAGGED or SHADE_SMOOTH (a loop-invariant branch).
    lid : (BAND_HEIGHT, W) int32
        The band's visibility buffer.
    r, j : int
        Its row, and the image row.
    lo, hi : int
        Columns to look at.
    sample_x, sample_y : float
        Where in its pixel a pixel was sampled, from the centre (pixels): SHADE_SMOOTH
        interpolates the colour at that point, ``(i + 0.5 + sample_x, j + 0.5 + sample_y)``.
    packed : (M,) uint32
        SHADE_FLAT: each face's colour (:func:`pack_colors`).
    vertex_colors : (K, 3) float32
        SHADE_SMOOTH: 0..255 per row, each face corner's row in ``corners`` (M, 3) int64
        (the faces, for a colour per vertex), interpolated with ``bary`` (:func:`bary_matrices`).
    color : (H, W, C) uint8
        The image, C = 3 (RGB) or 4 (RGBA, alpha 255); untouched in SHADE_NONE.
    write_ids : bool
        Whether to write the face index into ``ids (H, W) int32``.
    """
    ru, ju, base = np.uint64(r), np.uint64(j), np.uint64(lo)
    if mode == SHADE_NONE and not write_ids:  # a depth pass: only the reset, every column
        for k in range(hi - lo + 1):  # (a full store: LLVM would mask one for f >= 0 only)
            lid[ru, base + np.uint64(k)] = -1
        return
    px, py = lo + 0.5 + sample_x, j + 0.5 + sample_y
    for k in range(hi - lo + 1):
        i = base + np.uint64(k)
        f = lid[ru, i]
        if f < 0:
            continue
        lid[ru, i] = -1
        if mode == SHADE_FLAT:
            put_rgba(color, ju, i, packed[f])
        elif mode == SHADE_TAGGED:
            put_rgba(color, ju, i, np.int64(f) | 0xFF000000)
        elif mode == SHADE_SMOOTH:
            put_rgba(color, ju, i, smooth_rgba(f, px + k, py, vertex_colors, corners, bary))
        if write_ids:
            ids[ju, i] = f
