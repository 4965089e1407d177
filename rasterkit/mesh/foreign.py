"""What meshes of other libraries bring besides their geometry, as keyword arguments of a
:class:`rasterkit.mesh.Mesh`: trimesh's texture coordinates and material image
(``TextureVisuals``) and its vertex or face colours (``ColorVisuals``).

Nothing here imports trimesh or Pillow: the objects are read through the attributes they
have (``visual.kind``, ``visual.uv``, ``visual.material``, a Pillow image's ``convert``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.limits import check_memory
from rasterkit.mesh.checks import seal

__all__ = ["ImportedMaterial", "visual_fields"]


@dataclass(frozen=True, eq=False)
class ImportedMaterial:
    """A material as another library gives it, kept in ``Mesh.materials`` until rasterkit's
    own material record takes its place.

    Attributes
    ----------
    name : str
    diffuse : tuple of 4 floats in [0, 1]
        The base colour, RGBA (trimesh's ``diffuse`` or ``baseColorFactor``).
    diffuse_map : (H, W, 3) or (H, W, 4) uint8, or None
        The texture image, immutable, row 0 at the top of the image as image files store
        it (so ``uv`` v = 1 is row 0 and v = 0 the bottom row); RGBA when the image has
        transparency.
    """

    name: str
    diffuse: tuple = (1.0, 1.0, 1.0, 1.0)
    diffuse_map: np.ndarray | None = None


def visual_fields(obj) -> dict:
    """Keyword arguments of a Mesh for what ``obj.visual`` holds (nothing for an object
    without one, or with trimesh's default colours): ``uv`` per vertex and one material
    that every face uses for ``TextureVisuals``; ``vertex_colors`` or ``face_colors`` (RGB
    in [0, 1]) for ``ColorVisuals`` whose colours were set."""
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
    if material is not None:
        fields["materials"] = (_imported(material),)
        fields["material_names"] = (fields["materials"][0].name,)
        fields["face_materials"] = np.zeros(len(obj.faces), np.int32)
    return fields


def _imported(material) -> ImportedMaterial:
    """trimesh's ``SimpleMaterial`` (``image``, ``diffuse``) or ``PBRMaterial``
    (``baseColorTexture``, ``baseColorFactor``) as an :class:`ImportedMaterial`."""
    image = getattr(material, "image", None)
    if image is None:
        image = getattr(material, "baseColorTexture", None)
    colour = getattr(material, "diffuse", None)
    if colour is None:
        colour = getattr(material, "baseColorFactor", None)
    diffuse = (1.0, 1.0, 1.0, 1.0)
    if colour is not None:
        rgba = np.asarray(colour)
        rgba = rgba / 255.0 if rgba.dtype.kind in "iu" else rgba.astype(np.float64)
        if rgba.shape in ((3,), (4,)) and np.isfinite(rgba).all():
            diffuse = tuple(np.clip(np.append(rgba, 1.0)[:4], 0.0, 1.0).tolist())
    name = getattr(material, "name", None)
    return ImportedMaterial(str(name) if name is not None else "material", diffuse, _pixels(image))


def _pixels(image) -> np.ndarray | None:
    """A Pillow image (or an array) as an immutable (H, W, 3 | 4) uint8 array, or None."""
    if image is None:
        return None
    if hasattr(image, "convert") and hasattr(image, "getbands"):
        alpha = "A" in image.getbands() or "transparency" in getattr(image, "info", {})
        width, height = image.size
        check_memory(2 * 4 * width * height, f"a {width}x{height} texture image")
        image = image.convert("RGBA" if alpha else "RGB")
    pixels = np.asarray(image)
    if pixels.dtype != np.uint8 or pixels.ndim != 3 or pixels.shape[2] not in (3, 4):
        raise ValueError(f"a texture image must be (H, W, 3 or 4) uint8, got shape {pixels.shape} and dtype "
                         f"{pixels.dtype}")
    return seal(pixels)


def _unit_rgb(colors, name: str) -> np.ndarray:
    """(K, 3) float32 RGB in [0, 1] of trimesh colours (K, 3 | 4), uint8 0..255 or floats."""
    c = real_array(colors, name, None)
    if c.ndim != 2 or c.shape[1] not in (3, 4):
        raise ValueError(f"{name} must have shape (K, 3) or (K, 4), got {c.shape}")
    rgb = c[:, :3]
    return (rgb / 255.0 if c.dtype.kind in "iu" else rgb).astype(np.float32)
