"""The textures of a frame: which faces are textured and with what, worked out once per mesh
(:func:`mesh_textures`), and the band worker's record for one frame (:func:`frame_textures`,
a :class:`rasterkit.raster.kernels.records.Textured`).

A face is drawn textured when its material (``Mesh.face_materials`` → ``Mesh.materials``) is
a :class:`rasterkit.Material` with a ``diffuse_map`` and the face has texture coordinates;
its colour is the map's, encoded to sRGB, times the material's ``diffuse`` and the Lambert
factor of the frame's shading (:mod:`rasterkit.raster.kernels.texture_shade`). Other faces
are drawn as in an untextured frame.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rasterkit.material import Material, Texture
from rasterkit.material.sampling import TextureArgs, texture_args, with_filter
from rasterkit.raster.kernels.records import PixelLights, Textured
from rasterkit.raster.kernels.surface import encode_table
from rasterkit.raster.normals import unit
from rasterkit.raster.lights import NO_SHADOWS, TABLE_WIDTH
from rasterkit.raster.shading import surface_terms
from rasterkit.raster.sides import corner_sides
from rasterkit.raster.vision import corner_uv
from rasterkit.runtime.jit import readonly

__all__ = ["FrameTextures", "MeshTextures", "face_tangents", "frame_textures", "mesh_textures"]

_ENCODE = encode_table()


#: A height map's slopes: a grey ``normal_map`` is a height map, heights ``h`` 0 to 1 (black
#: to white), whose normals are ``normalize(-HEIGHT_SLOPE * dh/di, -HEIGHT_SLOPE * dh/dj, 1)``
#: in tangent space, from central differences per texel (``i`` along ``u``, ``j`` along ``v``;
#: across the edges as the texture wraps): the full range of heights is as high as 16 texels
#: are wide (a step from black to white over 16 texels slopes at 45 degrees), times the
#: material's ``bump_scale``.
HEIGHT_SLOPE = 16.0

#: The diffuse map of a material that has other maps but none for its colour: white, so that
#: its faces take the textured path (its ``diffuse`` times the shading).
_WHITE = Texture(np.full((1, 1, 3), 255, np.uint8), filter="nearest")


@dataclass(frozen=True, eq=False)
class MeshTextures:
    """The textured faces of a mesh (:func:`mesh_textures`); per face, -1 for none."""

    textures: tuple  # the maps used, each once (rasterkit.Texture)
    face_texture: np.ndarray  # (M,) int32: the diffuse map's row of textures
    tint: np.ndarray  # (M, 3) float32: the material's diffuse colour times 255
    corner_uv: np.ndarray  # (M, 6) float64: (u, v) of each face's corners
    face_alpha: np.ndarray  # (M,) int32: the texture whose alpha cuts the face out
    face_opacity: np.ndarray  # (M,) float32: the material's opacity, times that alpha
    face_normal_map: np.ndarray  # (M,) int32: the tangent-space normal map
    face_bump: np.ndarray  # (M,) float32: how strongly the normal map bends the normal
    face_normal_space: np.ndarray  # (M,) int8: 0 tangent space, 1 object space
    tangents: np.ndarray  # (M, 6) float32: each face's tangent and bitangent (normal-mapped faces)
    cutout: bool  # some face is cut out where its alpha is below one half
    normal_mapped: bool  # some face has a normal map


class FrameTextures(NamedTuple):
    """A frame's :class:`~rasterkit.raster.kernels.records.Textured` (``textures``), and the
    same record as ``cutouts`` and ``mapped`` when some face is cut out or has a normal map
    (else None: the band worker then compiles none of that code); or, for an untextured
    frame lit per pixel, only ``lights`` (:func:`rasterkit.raster.pixel_lights.pixel_lights`)."""

    textures: Textured | None
    cutouts: Textured | None
    mapped: Textured | None
    lights: PixelLights | None = None
    lit_only: bool = False  # no face textured and every face lit per pixel (the record's lights and phong)


def mesh_textures(mesh) -> MeshTextures | None:
    """The textured faces of ``mesh`` (a checked :class:`rasterkit.Mesh`), or None when no face
    is textured. Read-only arrays; :attr:`rasterkit.Mesh.textured` keeps them with the mesh.

    A face is textured when its material is a :class:`rasterkit.Material` with a diffuse,
    opacity or normal map (``diffuse_map`` white where it has none) and the face has texture
    coordinates. Its alpha is its ``opacity_map`` (or the alpha of a ``diffuse_map`` with some
    alpha below 255); data maps (opacity, normals) are read as linear values."""
    if mesh.face_materials is None or not mesh.materials:
        return None
    rows = {}

    def row(texture):
        return -1 if texture is None else rows.setdefault(id(texture), (len(rows), texture))[0]

    n = len(mesh.materials)
    diffuse, alpha, normal = (np.full(n + 1, -1, np.int32) for _ in range(3))  # the last row: no material
    space = np.zeros(n + 1, np.int8)
    tint, opacity, bump = np.zeros((n + 1, 3), np.float32), np.ones(n + 1, np.float32), np.ones(n + 1, np.float32)
    for k, material in enumerate(mesh.materials):
        if not isinstance(material, Material):
            continue
        cut = material.opacity_map if material.opacity_map is not None else _with_alpha(material.diffuse_map)
        if material.diffuse_map is None and material.normal_map is None and cut is None:
            continue
        diffuse[k] = row(material.diffuse_map if material.diffuse_map is not None else _WHITE)
        tint[k] = np.asarray(material.diffuse, np.float32) * np.float32(255)
        alpha[k] = row(_linear(cut) if cut is material.opacity_map else cut)
        opacity[k] = material.opacity
        normal[k] = row(_normal_map(material.normal_map))
        bump[k] = material.bump_scale
        space[k] = material.normal_space == "object"
    if not rows:
        return None
    uv = corner_uv(mesh)
    untextured = ~np.isfinite(uv).all(axis=1)  # a face without texture coordinates
    index = np.where(untextured, n, mesh.face_materials)  # -1 reads the last row too
    face_normal_map = _sealed(normal[index])
    tangents = face_tangents(mesh.vertices, mesh.faces, uv) if (face_normal_map >= 0).any() \
        else np.zeros((0, 6), np.float32)
    textures = tuple(texture for _, texture in sorted(rows.values(), key=lambda item: item[0]))
    face_alpha = _sealed(alpha[index])
    return MeshTextures(textures, _sealed(diffuse[index]), _sealed(tint[index]), _sealed(uv), face_alpha,
                        _sealed(opacity[index]), face_normal_map, _sealed(bump[index]), _sealed(space[index]),
                        _sealed(tangents), bool((face_alpha >= 0).any()), bool(tangents.size))


def face_tangents(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(M, 6) float32: each face's tangent and bitangent, the directions in which ``u`` and
    ``v`` grow on it (``dP/du``, ``dP/dv`` from its edges and their texture-coordinate
    differences), unit length; zero for a face whose texture coordinates have no area."""
    p = vertices[faces]  # (M, 3 corners, 3)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    d1, d2 = uv[:, 2:4] - uv[:, 0:2], uv[:, 4:6] - uv[:, 0:2]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(det != 0.0, 1.0 / det, 0.0)[:, None]
        tangent = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r
        bitangent = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * r
    return np.ascontiguousarray(np.hstack([unit(tangent), unit(bitangent)]), np.float32)


def _with_alpha(texture):
    """``texture`` when it has an alpha channel with some value below 255, else None."""
    if texture is None or texture.channels != 4 or texture.image[..., 3].min() == 255:
        return None
    return texture


def _normal_map(texture):
    """``texture`` as a normal map read as data: a grey one (a height map) turned into normals
    (:data:`HEIGHT_SLOPE`), once per texture."""
    if texture is None:
        return None
    image = texture.image
    if np.array_equal(image[..., 0], image[..., 1]) and np.array_equal(image[..., 0], image[..., 2]):
        return _from_heights(texture)
    return _linear(texture)


@functools.lru_cache(maxsize=8)
def _from_heights(texture):
    """The tangent-space normal map (a Texture with ``texture``'s settings) of the height map
    ``texture`` (see :data:`HEIGHT_SLOPE`)."""
    heights = texture.image[::-1, :, 0].astype(np.float64) / 255.0  # rows bottom first: j grows with v
    mode = "edge" if texture.wrap == "clamp" else ("symmetric" if texture.wrap == "mirror" else "wrap")
    padded = np.pad(heights, 1, mode=mode)
    di = (padded[1:-1, 2:] - padded[1:-1, :-2]) / 2.0
    dj = (padded[2:, 1:-1] - padded[:-2, 1:-1]) / 2.0
    normals = np.stack([-HEIGHT_SLOPE * di, -HEIGHT_SLOPE * dj, np.ones_like(di)], axis=2)
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    image = np.floor((normals[::-1] + 1.0) / 2.0 * 255.0 + 0.5).astype(np.uint8)
    return Texture(image, filter=texture.filter, wrap=texture.wrap, scale=texture.scale, offset=texture.offset,
                   srgb=False, name=texture.name)


def _back(two_sided):
    """The band worker's ``back``: 1.0 (two-sided) or 0.0, or (M,) float64 of those per face."""
    if isinstance(two_sided, np.ndarray):
        return _sealed(two_sided.astype(np.float64))
    return 1.0 if two_sided else 0.0


@functools.lru_cache(maxsize=64)
def _linear(texture):
    """``texture`` read as data (linear values), not sRGB colours: one copy per texture (kept),
    so that materials sharing a map share its row of the band worker's arrays."""
    return texture.replace(srgb=False) if texture is not None and texture.srgb else texture


def frame_textures(mesh, light: np.ndarray, ambient: float, two_sided, smooth: bool,
                   texture_filter: str | None, lit=None, phong: bool = False,
                   textured: bool = True) -> FrameTextures | None:
    """The band worker's :class:`FrameTextures` for a frame of
    ``mesh`` lit from the unit direction ``light`` (world space) with ``ambient``, lit on both
    sides or not (``two_sided``: a bool, or (M,) bool per face), flat or ``smooth``, every texture filtered with ``texture_filter`` (a name of
    :data:`rasterkit.material.sampling.FILTER_CODES`, or None for each texture's own); None
    when no face of ``mesh`` is textured. With ``lit`` (the frame's
    :class:`rasterkit.raster.lights.FrameLights`) the textured faces are lit per pixel by
    Blinn-Phong instead, and with ``phong`` every face (a mesh without textures too);
    ``textured`` False draws no face textured."""
    layout = mesh.textured if textured else None
    if layout is None and not (phong and lit is not None):
        return None
    untextured = layout is None
    layout = layout or _untextured(len(mesh.faces))
    args = _arguments(layout.textures, texture_filter)
    light = np.ascontiguousarray(light, np.float64)
    no_normals = np.zeros((0, 3))
    if smooth and lit is not None:  # the corners' normals, interpolated per pixel
        corner_normals, corners, _ = mesh.smooth_corners
        intensity, face_normals = np.ones(len(corner_normals), np.float32), np.zeros((0, 3), np.float32)
    elif smooth:
        normals, corners, _ = mesh.smooth_corners
        cos = normals @ light
        both = corner_sides(two_sided, corners, len(normals))
        cos = np.where(both, np.abs(cos), np.maximum(cos, 0.0))
        intensity = (ambient + (1.0 - ambient) * np.nan_to_num(cos, nan=0.0)).astype(np.float32)
        face_normals, corner_normals = np.zeros((0, 3), np.float32), normals if layout.tangents.size else no_normals
    else:
        intensity, corners, face_normals = np.zeros(0, np.float32), np.zeros((0, 3), np.int64), mesh.face_normals
        corner_normals = no_normals
    fields = (*args, layout.face_texture, layout.corner_uv, layout.tint, smooth, intensity, corners, face_normals,
              light, float(ambient), _back(two_sided), _ENCODE, layout.face_alpha, layout.face_opacity,
              layout.face_normal_map, layout.face_bump, layout.face_normal_space, layout.tangents, corner_normals,
              *_lighting(mesh, lit, phong))
    # every array read-only: one record type (and one compiled band worker) whatever the frame
    record = Textured(*(readonly(v) if isinstance(v, np.ndarray) else v for v in fields))
    mapped = layout.normal_mapped or lit is not None
    lit_only = untextured and bool(record.phong) and record.lights.shape[0] > 0
    return FrameTextures(record, record if layout.cutout else None, record if mapped else None, lit_only=lit_only)


def _lighting(mesh, lit, phong: bool) -> tuple:
    """The lit frame's fields of the record (:class:`rasterkit.raster.kernels.records.Textured`),
    empty without lights."""
    if lit is None:
        return (np.zeros((0, TABLE_WIDTH)), np.zeros(3), False, np.zeros(3), np.zeros((0, 3)),
                np.zeros((0, 3), np.int64), np.zeros((1, 3)), np.zeros(1), np.zeros((1, 3)), False, *NO_SHADOWS)
    specular, shininess, emission = surface_terms(mesh, lit, 1)
    table, shadows = lit.shadow_terms(mesh)
    return (table, lit.eye, lit.perspective, lit.view, np.ascontiguousarray(mesh.vertices, np.float64),
            np.ascontiguousarray(mesh.faces, np.int64), specular, shininess, emission, phong, *shadows)


def _untextured(m: int) -> MeshTextures:
    """The layout of a mesh of ``m`` faces none of which is textured (a phong frame's): no
    texture is read, only ``face_texture`` (all -1)."""
    empty = np.zeros(0, np.int32)
    return MeshTextures((_WHITE,), _sealed(np.full(m, -1, np.int32)), np.zeros((0, 3), np.float32),
                        np.zeros((0, 6)), empty, np.zeros(0, np.float32), empty, np.zeros(0, np.float32),
                        np.zeros(0, np.int8), np.zeros((0, 6), np.float32), False, False)


@functools.lru_cache(maxsize=16)
def _arguments(textures: tuple, texture_filter: str | None) -> TextureArgs:
    """:func:`rasterkit.material.sampling.texture_args` of ``textures`` (kept: the mipmaps of
    several textures are copied into one buffer once, not once a frame), their filters set to
    ``texture_filter`` unless it is None. Textures are hashed by identity."""
    args = texture_args(textures)
    return args if texture_filter is None else with_filter(args, texture_filter)


def _sealed(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a
