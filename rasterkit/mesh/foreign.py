"""What meshes of other libraries bring besides their geometry, as keyword arguments of a
:class:`rasterkit.mesh.Mesh`: trimesh's texture coordinates and materials
(``TextureVisuals``) and its vertex or face colours (``ColorVisuals``).

Nothing here imports trimesh or Pillow: the objects are read through the attributes they
have (``visual.kind``, ``visual.uv``, ``visual.material``, a Pillow image's ``convert``).
trimesh's texture coordinates are OpenGL's (``v`` up, ``v = 0`` the bottom row of the image),
as rasterkit's are: they are taken as they are.
"""

from __future__ import annotations

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.limits import check_memory
from rasterkit.material import Material, Texture

__all__ = ["TRIMESH_UNSET_DIFFUSE", "visual_fields"]

TRIMESH_UNSET_DIFFUSE = (102, 102, 102, 255)
"""What trimesh's ``SimpleMaterial`` stores as ``diffuse`` when it is given none
(``trimesh.visual.color.DEFAULT_COLOR``): read as no colour, so that a material with an image
gets :class:`~rasterkit.Material`'s default under a map, white, and its image is drawn as it
is (as trimesh's own viewer draws it), not at 40 % brightness."""


def visual_fields(obj) -> dict:
    """Keyword arguments of a Mesh for what ``obj.visual`` holds (nothing for an object
    without one, or with trimesh's default colours): ``uv`` per vertex and its material
    (:func:`_material`) for every face for ``TextureVisuals`` (a ``MultiMaterial``'s
    materials, by ``visual.face_materials``); ``vertex_colors`` or ``face_colors`` (RGB in
    [0, 1]) for ``ColorVisuals`` whose colours were set."""
    visual = getattr(obj, "visual", None)
    kind = getattr(visual, "kind", None)
    if kind == "texture":
        return _texture_fields(visual, obj)
    if kind == "vertex":
        return {"vertex_colors": _unit_rgb(visual.vertex_colors, "visual.vertex_colors")}
    if kind == "face":
        return {"face_colors": _unit_rgb(visual.face_colors, "visual.face_colors")}
    return {}


def _texture_fields(visual, obj) -> dict:
    fields = {}
    if getattr(visual, "uv", None) is not None:
        fields["uv"] = real_array(visual.uv, "visual.uv")[:, :2]
    material = getattr(visual, "material", None)
    if material is None:
        return fields
    parts = getattr(material, "materials", None)  # a MultiMaterial
    if parts is None:
        materials = (_material(material, "material"),)
        face_materials = np.zeros(len(obj.faces), np.int32)
    else:
        materials = tuple(_material(m, f"material_{k}") for k, m in enumerate(parts))
        chosen = getattr(visual, "face_materials", None)
        face_materials = np.zeros(len(obj.faces), np.int32) if chosen is None else chosen
    fields.update(materials=materials, material_names=tuple(m.name for m in materials), face_materials=face_materials)
    return fields


def _material(material, default_name: str = "material") -> Material:
    """A :class:`rasterkit.Material` of trimesh's ``SimpleMaterial`` (``image``,
    ``diffuse``) or ``PBRMaterial`` (``baseColorTexture``, ``baseColorFactor``): the image as
    its ``diffuse_map`` (an sRGB :class:`~rasterkit.Texture`, RGBA when the image has
    transparency), the colour's RGB as ``diffuse`` and its alpha as ``opacity``. A colour
    that is absent or not finite, and a ``SimpleMaterial``'s :data:`TRIMESH_UNSET_DIFFUSE`
    under an image, leave Material's defaults: white under a map, else (0.8, 0.8, 0.8)."""
    image = getattr(material, "image", None)
    if image is None:
        image = getattr(material, "baseColorTexture", None)
    colour = getattr(material, "diffuse", None)
    if colour is None:
        colour = getattr(material, "baseColorFactor", None)
    elif image is not None and np.array_equal(colour, TRIMESH_UNSET_DIFFUSE):
        colour = None
    values = {}
    if colour is not None:
        rgba = np.asarray(colour)
        rgba = rgba / 255.0 if rgba.dtype.kind in "iu" else rgba.astype(np.float64)
        if rgba.shape in ((3,), (4,)) and np.isfinite(rgba).all():
            rgba = np.clip(np.append(rgba, 1.0)[:4], 0.0, 1.0).tolist()
            values.update(diffuse=tuple(rgba[:3]), opacity=rgba[3])
    name = getattr(material, "name", None)
    return Material(str(name) if name is not None else default_name, diffuse_map=_texture(image), **values)


def _texture(image) -> Texture | None:
    """A Pillow image (or an array) as a :class:`~rasterkit.Texture`, or None."""
    if image is None:
        return None
    name = None
    if hasattr(image, "convert") and hasattr(image, "getbands"):
        info = getattr(image, "info", {})
        alpha = "A" in image.getbands() or "transparency" in info
        width, height = image.size
        check_memory(2 * 4 * width * height, f"a {width}x{height} texture image")
        name = info.get("file_path") or getattr(image, "filename", None) or None
        image = image.convert("RGBA" if alpha else "RGB")
    return Texture(np.asarray(image), name=None if name is None else str(name))


def _unit_rgb(colors, name: str) -> np.ndarray:
    """(K, 3) float32 RGB in [0, 1] of trimesh colours (K, 3 | 4), uint8 0..255 or floats."""
    c = real_array(colors, name, None)
    if c.ndim != 2 or c.shape[1] not in (3, 4):
        raise ValueError(f"{name} must have shape (K, 3) or (K, 4), got {c.shape}")
    rgb = c[:, :3]
    return (rgb / 255.0 if c.dtype.kind in "iu" else rgb).astype(np.float32)
