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

import numpy as np

from rasterkit.material import Material
from rasterkit.material.sampling import TextureArgs, texture_args, with_filter
from rasterkit.raster.kernels.records import Textured
from rasterkit.raster.kernels.texture_shade import encode_table
from rasterkit.raster.vision import corner_uv

__all__ = ["MeshTextures", "frame_textures", "mesh_textures"]

_ENCODE = encode_table()


@dataclass(frozen=True, eq=False)
class MeshTextures:
    """The textured faces of a mesh (:func:`mesh_textures`)."""

    textures: tuple  # the diffuse maps used, each once (rasterkit.Texture)
    face_texture: np.ndarray  # (M,) int32: row of textures, -1 for an untextured face
    tint: np.ndarray  # (M, 3) float32: the material's diffuse colour times 255
    corner_uv: np.ndarray  # (M, 6) float64: (u, v) of each face's corners

    @property
    def nbytes(self) -> int:
        return self.face_texture.nbytes + self.tint.nbytes + self.corner_uv.nbytes


def mesh_textures(mesh) -> MeshTextures | None:
    """The textured faces of ``mesh`` (a checked :class:`rasterkit.Mesh`), or None when no face
    is textured. Read-only arrays; :attr:`rasterkit.Mesh.textured` keeps them with the mesh."""
    if mesh.face_materials is None or not mesh.materials:
        return None
    maps, rows = {}, []
    tints = np.zeros((len(mesh.materials) + 1, 3), np.float32)  # the last row: faces without a material
    for k, material in enumerate(mesh.materials):
        texture = material.diffuse_map if isinstance(material, Material) else None
        rows.append(-1 if texture is None else maps.setdefault(id(texture), (len(maps), texture))[0])
        if texture is not None:
            tints[k] = np.asarray(material.diffuse, np.float32) * np.float32(255)
    if not maps:
        return None
    material_texture = np.array(rows + [-1], np.int32)
    face_texture = material_texture[mesh.face_materials]  # -1 (no material) reads the last row
    uv = corner_uv(mesh)
    face_texture[~np.isfinite(uv).all(axis=1)] = -1  # a face without texture coordinates
    textures = tuple(texture for _, texture in sorted(maps.values(), key=lambda item: item[0]))
    return MeshTextures(textures, _sealed(face_texture), _sealed(tints[mesh.face_materials]), _sealed(uv))


def frame_textures(mesh, light: np.ndarray, ambient: float, two_sided: bool, smooth: bool,
                   texture_filter: str | None) -> Textured | None:
    """The band worker's :class:`~rasterkit.raster.kernels.records.Textured` for a frame of
    ``mesh`` lit from the unit direction ``light`` (world space) with ``ambient``, lit on both
    sides or not, flat or ``smooth``, every texture filtered with ``texture_filter`` (a name of
    :data:`rasterkit.material.sampling.FILTER_CODES`, or None for each texture's own); None
    when no face of ``mesh`` is textured."""
    layout = mesh.textured
    if layout is None:
        return None
    args = _arguments(layout.textures, texture_filter)
    light = np.ascontiguousarray(light, np.float64)
    if smooth:
        normals, corners, _ = mesh.smooth_corners
        cos = normals @ light
        cos = np.abs(cos) if two_sided else np.maximum(cos, 0.0)
        intensity = (ambient + (1.0 - ambient) * np.nan_to_num(cos, nan=0.0)).astype(np.float32)
        face_normals = np.zeros((0, 3), np.float32)
    else:
        intensity, corners, face_normals = np.zeros(0, np.float32), np.zeros((0, 3), np.int64), mesh.face_normals
    return Textured(*args, layout.face_texture, layout.corner_uv, layout.tint, smooth, intensity, corners,
                    face_normals, light, float(ambient), 1.0 if two_sided else 0.0, _ENCODE)


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
