"""``Material``: how a surface looks, as an ``.mtl`` file describes it (the Phong model's
colours and exponent, opacity, emission and texture maps).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rasterkit import values
from rasterkit._arrays import describe
from rasterkit.material.texture import Texture

#: The spaces a normal map's vectors can be in (:attr:`Material.normal_space`).
NORMAL_SPACES = ("tangent", "object")

__all__ = ["NORMAL_SPACES", "DEFAULT_DIFFUSE", "MAPPED_DIFFUSE", "Material"]

DEFAULT_DIFFUSE = (0.8, 0.8, 0.8)
"""Diffuse colour (``Kd``) of a material that gives neither a colour nor a ``diffuse_map``,
and of faces without a material."""

MAPPED_DIFFUSE = (1.0, 1.0, 1.0)
"""Diffuse colour of a material that gives a ``diffuse_map`` but no colour: the texture as it
is (the renderer multiplies the texture by ``diffuse``)."""


def _rgb(high: float):
    """The check of an (r, g, b) colour of floats from 0 to ``high``."""

    def check(name: str, value) -> tuple[float, float, float]:
        if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
            raise TypeError(f"{name} must be (r, g, b), three numbers, got {describe(value)}")
        rgb = tuple(values.real(name, v) for v in value)
        if not all(0.0 <= c <= high for c in rgb):
            limit = "[0, 1]" if high == 1.0 else "[0, inf)"
            raise ValueError(f"{name} must lie in {limit}, got {rgb}")
        return rgb

    return check


def _texture(name: str, value):
    if value is not None and not isinstance(value, Texture):
        raise TypeError(f"{name} must be a rasterkit.Texture or None, got {type(value).__name__}")
    return value


def _name(name: str, value) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, got {type(value).__name__}")
    return value


def _shininess(name: str, value) -> float:
    value = values.real(name, value)
    if value < 0.0:
        raise ValueError(f"{name} must be at least 0, got {value!r}")
    return value


@dataclass(frozen=True)
class Material:
    """A surface's material, with the ``.mtl`` statement each field comes from. Immutable;
    textures are shared objects (compared by identity).

    Fields
    ------
    name : str
        The ``newmtl`` name.
    diffuse : (r, g, b) floats in [0, 1], or None
        ``Kd``, the Lambert colour, multiplied by ``diffuse_map`` where it has one. None (the
        default) is :data:`MAPPED_DIFFUSE` (1, 1, 1) when a ``diffuse_map`` is given, so that
        the texture is drawn as it is, and :data:`DEFAULT_DIFFUSE` (0.8, 0.8, 0.8), the colour
        of faces without a material, otherwise. Resolved when the Material is made: it is
        always a colour afterwards, and ``dataclasses.replace`` keeps it (pass
        ``diffuse=None`` with a new ``diffuse_map`` to have it chosen again).
    specular : (r, g, b) floats in [0, 1]
        ``Ks``, the Phong highlight's colour, multiplied by ``specular_map``. Default
        (0, 0, 0): no highlight unless the file asks for one.
    shininess : float >= 0
        ``Ns``, the Phong exponent. Default 32, a moderate highlight (the usual default of
        Phong shading examples): it is used only with a ``Ks``, and a file that gives ``Ks``
        without ``Ns`` means a highlight, which the MTL default of 0 (the whole lit side as
        bright as the highlight) is not. A file's ``Ns 0`` is kept as it is.
    opacity : float in [0, 1]
        ``d`` (dissolve): 1 opaque, 0 invisible; ``Tr`` is ``1 - d``. Default 1.
    emission : (r, g, b) floats >= 0
        ``Ke``, light the surface gives off whatever the lighting. Default (0, 0, 0).
    diffuse_map : Texture or None
        ``map_Kd``: sRGB colours; its alpha, when it has one, is a cut-out.
    opacity_map : Texture or None
        ``map_d``: opacity, from the texture's alpha when it has one, else its first channel
        (linear data: ``srgb=False``).
    specular_map : Texture or None
        ``map_Ks``: scales ``specular`` (linear data).
    normal_map : Texture or None
        ``map_Bump``, ``bump`` or ``norm`` (linear data): a normal map (an RGB image, each
        texel a unit vector ``2 * rgb - 1``), or a height map when the image is grey (as
        ``bump`` often is: heights 0 to 1, turned into normals by their slopes,
        :data:`rasterkit.raster.texturing.HEIGHT_SLOPE`).
    bump_scale : float
        ``-bm`` of the bump or normal map: how strongly it bends the normal (a tangent-space
        normal's x and y, a height map's slopes, are multiplied by it). Default 1.
    normal_space : {"tangent", "object"}
        The space of ``normal_map``'s vectors: ``tangent`` (the default; x along the texture's
        ``u``, y along ``v``, z the surface normal, as ``.mtl`` and glTF files mean them), or
        ``object``, the mesh's own coordinates (as tinyrenderer's ``african_head_nm.tga``):
        the map's vector is the normal, whatever the mesh's normals.
    double_sided : bool
        glTF's ``doubleSided``: the faces are meant to be seen from both sides (not culled,
        and lit on the back as on the front). Default False. :func:`rasterkit.render` draws
        such faces from both sides whatever ``RenderOptions.cull`` says, and lights their
        backs with the normal turned towards the viewer (``|n · l|``,
        :mod:`rasterkit.raster.sides`).
    """

    name: str = "default"
    diffuse: tuple | None = None
    specular: tuple = (0.0, 0.0, 0.0)
    shininess: float = 32.0
    opacity: float = 1.0
    emission: tuple = (0.0, 0.0, 0.0)
    diffuse_map: Texture | None = None
    opacity_map: Texture | None = None
    specular_map: Texture | None = None
    normal_map: Texture | None = None
    bump_scale: float = 1.0
    normal_space: str = "tangent"
    double_sided: bool = False

    def __post_init__(self):
        if self.diffuse is None:
            object.__setattr__(self, "diffuse", DEFAULT_DIFFUSE if self.diffuse_map is None else MAPPED_DIFFUSE)
        for name, check in _CHECKS.items():
            object.__setattr__(self, name, check(name, getattr(self, name)))

    @property
    def textures(self) -> tuple:
        """The maps it has, in field order (``diffuse_map``, ``opacity_map``, ...)."""
        return tuple(t for t in (self.diffuse_map, self.opacity_map, self.specular_map, self.normal_map)
                     if t is not None)


#: Each field's check, giving the value as it is stored.
_CHECKS = {
    "name": _name,
    "diffuse": _rgb(1.0), "specular": _rgb(1.0), "emission": _rgb(math.inf),
    "shininess": _shininess,
    "opacity": values.unit_interval,
    "diffuse_map": _texture, "opacity_map": _texture, "specular_map": _texture, "normal_map": _texture,
    "bump_scale": values.real,
    "normal_space": lambda name, value: values.choice(name, value, NORMAL_SPACES),
    "double_sided": values.flag,
}
