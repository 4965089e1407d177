"""The band worker's record for an untextured frame lit per pixel: shaded ``"phong"``, or
under a light that casts shadows (:class:`rasterkit.raster.kernels.records.PixelLights`,
resolved by :mod:`rasterkit.raster.kernels.phong_rows`). A frame with textures is lit per
pixel through the textured resolve instead (:func:`rasterkit.raster.texturing.frame_textures`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.material.colorspace import DECODE, SRGB_ROW
from rasterkit.raster.kernels.records import PixelLights
from rasterkit.raster.kernels.surface import encode_table
from rasterkit.raster.shading import surface_terms
from rasterkit.runtime.jit import readonly

__all__ = ["pixel_lights"]

_ENCODE = encode_table()
_DECODE = readonly(np.ascontiguousarray(DECODE[SRGB_ROW], np.float64))
_NO_CORNERS = readonly(np.zeros((0, 3), np.int64))
_NO_NORMALS = readonly(np.zeros((0, 3)))


def pixel_lights(mesh, lit, two_sided, smooth: bool) -> PixelLights:
    """The record of ``mesh``'s frame under ``lit`` (its
    :class:`rasterkit.raster.lights.FrameLights`), faces lit on both sides as ``two_sided``
    says (a bool, or (M,) bool per face), the normals interpolated from the corners
    (``smooth``) or each face's own. Shadow maps are drawn here (once per frame and mesh:
    :meth:`~rasterkit.raster.lights.FrameLights.shadow_terms`)."""
    specular, shininess, emission = surface_terms(mesh, lit, 1)
    table, shadows = lit.shadow_terms(mesh)
    if smooth:
        corner_normals, normal_corners, _ = mesh.smooth_corners
    else:
        corner_normals, normal_corners = _NO_NORMALS, _NO_CORNERS
    if isinstance(two_sided, np.ndarray):
        two_sided = readonly(np.ascontiguousarray(two_sided, np.bool_))
    else:
        two_sided = bool(two_sided)
    fields = (table, lit.eye, bool(lit.perspective), lit.view, np.ascontiguousarray(mesh.vertices, np.float64),
              np.ascontiguousarray(mesh.faces, np.int64), specular, shininess, emission, bool(smooth),
              np.ascontiguousarray(corner_normals, np.float64), np.ascontiguousarray(normal_corners, np.int64),
              mesh.face_normals, two_sided, _ENCODE, _DECODE)
    # every array read-only: one record type (and one compiled band worker) for frames with
    # shadow maps, one for frames without
    shadows = tuple(readonly(v) if isinstance(v, np.ndarray) else v for v in shadows) if lit.shadowed else None
    # a spot's or point light's map (a perspective one, column 7 of its axes): another resolve
    perspective_maps = True if shadows is not None and bool(np.any(shadows[2][:, 7] > 0.0)) else None
    return PixelLights(*(readonly(v) if isinstance(v, np.ndarray) else v for v in fields), shadows, perspective_maps)
