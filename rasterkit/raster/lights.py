"""Lights: :class:`Light`, the record a render's ``lights`` hold, and :func:`light_table`, the
lights of one frame as the lighting kernel reads them (:mod:`rasterkit.raster.kernels.lights`).

Every position and direction is in world space. A light's colour is an sRGB colour (a name,
``'#rrggbb'`` or 0-255 values) that the lighting turns into linear light and multiplies by
``intensity``; the lights add up in linear light (:mod:`rasterkit.raster.lighting`).

- ``directional``: parallel rays along ``direction`` (from the light towards the scene): the
  sun; ``n · l`` with ``l = -direction``.
- ``point``: from ``position`` in every direction, falling off with the inverse square of the
  distance ``d`` (``intensity / d²``); with a ``range``, glTF's window
  ``clamp(1 - (d / range)⁴, 0, 1)`` brings it to zero at that distance.
- ``spot``: a point light limited to a cone around ``direction`` of full opening ``angle``
  (degrees), whose edge fades over the outer ``blend`` fraction of its half-angle: glTF's
  ``KHR_lights_punctual`` spot (outer cone ``angle / 2``, inner ``(1 - blend) angle / 2``,
  the square of the linear ramp between their cosines).
- ``ambient``: light from everywhere, ``base · colour · intensity`` whatever the normal.
- ``headlight``: a directional light along the camera's viewing direction, resolved per frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np

from rasterkit import values

__all__ = ["KINDS", "NO_SHADOWS", "PHONG_LIGHTS", "TABLE_WIDTH", "FrameLights", "Light", "check_lights", "frame_lights", "moved",
           "light_table"]

#: The kinds of :class:`Light`, in the order of their codes in :func:`light_table`.
KINDS = ("ambient", "directional", "point", "spot", "headlight")
AMBIENT, DIRECTIONAL, POINT, SPOT, HEADLIGHT = range(len(KINDS))

#: Columns of a :func:`light_table` row.
TABLE_WIDTH = 15


@dataclass(frozen=True)
class Light:
    """One light of a render (``render(..., lights=[...])``, :meth:`rasterkit.Scene.add_light`).
    Make it with the constructors (:meth:`directional`, :meth:`point`, :meth:`spot`,
    :meth:`ambient`, :meth:`headlight`); the record is immutable, compares by value and
    pickles, so it travels in :class:`rasterkit.RenderOptions` to batch workers.

    Fields
    ------
    kind : {"ambient", "directional", "point", "spot", "headlight"}
    color : colour
        sRGB, as given (a name, ``'#rrggbb'``, or an (r, g, b) tuple of 0-255).
    intensity : float >= 0
        Multiplies the colour (in linear light).
    position : (x, y, z) or None
        World space: point and spot lights.
    direction : (x, y, z) or None
        World space, from the light towards the scene (unit length): directional and spot lights.
    range : float or None
        Point and spot lights: the distance at which they fade out (None: never).
    angle : float
        Spot lights: the cone's full opening, degrees in (0, 180).
    blend : float
        Spot lights: the fraction of the cone's half-angle, from its edge, over which the light fades, in [0, 1].
    shadows : bool
        Whether the light casts shadows.

    Examples
    --------
    >>> key = Light.directional((-1, -2, -1), color="white", intensity=2.5)
    >>> key.kind, key.direction == tuple(np.array((-1, -2, -1)) / np.sqrt(6))
    ('directional', True)
    >>> Light.point((0, 3, 0), intensity=20, range=10).range
    10.0
    """

    kind: str
    color: object = "white"
    intensity: float = 1.0
    position: tuple | None = None
    direction: tuple | None = None
    range: float | None = None
    angle: float = 45.0
    blend: float = 0.15
    shadows: bool = False

    def __post_init__(self):
        values.choice("kind", self.kind, KINDS)
        set_ = object.__setattr__
        set_(self, "color", values.colour("color", self.color))
        set_(self, "intensity", values.non_negative("intensity", self.intensity))
        placed = self.kind in ("point", "spot")
        aimed = self.kind in ("directional", "spot")
        set_(self, "position", values.point("position", self.position) if placed else _absent("position", self))
        set_(self, "direction", _unit("direction", self.direction) if aimed else _absent("direction", self))
        if self.range is not None:
            if not placed:
                raise ValueError(f"range: only point and spot lights have one, not a {self.kind} light")
            set_(self, "range", values.positive("range", self.range))
        set_(self, "angle", _angle(self.angle))
        set_(self, "blend", values.unit_interval("blend", self.blend))
        set_(self, "shadows", values.flag("shadows", self.shadows))
        if self.shadows and self.kind == "ambient":
            raise ValueError("shadows: an ambient light has no direction to cast them")

    @classmethod
    def directional(cls, direction, color="white", intensity: float = 1.0, shadows: bool = False) -> Light:
        """A distant light shining along ``direction`` (world space, towards the scene)."""
        return cls("directional", color, intensity, direction=direction, shadows=shadows)

    @classmethod
    def point(cls, position, color="white", intensity: float = 1.0, range: float | None = None,
              shadows: bool = False) -> Light:
        """A light at ``position`` shining every way, ``intensity / d²`` at distance ``d``."""
        return cls("point", color, intensity, position=position, range=range, shadows=shadows)

    @classmethod
    def spot(cls, position, direction, angle: float = 45.0, blend: float = 0.15, color="white",
             intensity: float = 1.0, range: float | None = None, shadows: bool = False) -> Light:
        """A point light limited to a cone of full opening ``angle`` degrees around ``direction``."""
        return cls("spot", color, intensity, position=position, direction=direction, range=range, angle=angle,
                   blend=blend, shadows=shadows)

    @classmethod
    def ambient(cls, color="white", intensity: float = 0.1) -> Light:
        """Light from everywhere: every surface gets ``base · colour · intensity``."""
        return cls("ambient", color, intensity)

    @classmethod
    def headlight(cls, color="white", intensity: float = 1.0, shadows: bool = False) -> Light:
        """A directional light that follows the camera: it shines along the viewing direction."""
        return cls("headlight", color, intensity, shadows=shadows)


@dataclass(frozen=True)
class FrameLights:
    """A frame's lights as the shading reads them (:func:`frame_lights`)."""

    table: np.ndarray  # (L, TABLE_WIDTH) float64, light_table's
    eye: np.ndarray  # (3,) float64 the camera's eye, world space
    perspective: bool  # the viewer is at the eye (else along ``view``)
    view: np.ndarray  # (3,) float64 unit direction towards the viewer of a parallel camera
    camera: object  # the frame's rasterkit.Camera (the shadow maps of directional lights fit its view)
    specular: float  # RenderOptions.specular: the highlight of faces without a material
    shininess: float  # RenderOptions.shininess
    lights: tuple = ()  # the Light records (those that cast shadows marked so)
    map_size: int = 0  # the side of each shadow map, texels
    softness: float = 1.0  # RenderOptions.shadow_softness
    casters: tuple | None = None  # (vertices, faces): the mesh's first ones cast shadows (None: all)
    _made: dict = field(default_factory=dict, compare=False, repr=False)  # shadow_terms' maps, per mesh

    @property
    def shadowed(self) -> bool:
        """Whether some light casts shadows (then every face is lit per pixel)."""
        return any(light.shadows for light in self.lights)

    def shadow_bytes(self) -> int:
        """Memory the shadow maps take while they are made and used: per map (six for a point
        light) its float32 texels (the depth buffer as drawn), and one drawing at a time a
        quarter of its side (the fit of a directional light's map, the near plane of a
        perspective one)."""
        maps = sum(6 if light.kind == "point" else 1 for light in self.lights if light.shadows)
        if not maps:
            return 0
        quarter = max(16, self.map_size // 4)
        return maps * self.map_size * self.map_size * 4 + quarter * quarter * 4

    def shadow_terms(self, mesh) -> tuple:
        """``(table, shadows)`` for the kernels: the light table with each light's first
        shadow map and their count (columns 13, 14), and ``(maps, matrices, axes, softness)``
        of :class:`rasterkit.raster.shadows.ShadowMaps`, drawn for ``mesh`` (world space) on
        first use and kept (the samples of a render share them); empty without shadows."""
        if not self.shadowed:
            return self.table, NO_SHADOWS
        made = self._made.get(id(mesh))
        if made is None or made[0] is not mesh:
            from rasterkit.raster.shadows import shadow_maps

            maps = shadow_maps(mesh, self.lights, self.camera, self.map_size, self.softness, self.casters)
            table = self.table.copy()
            table[:, 13] = maps.first
            table[:, 14] = [6 if light.kind == "point" else 1 for light in self.lights]
            table.flags.writeable = False
            made = self._made[id(mesh)] = (mesh, table, (maps.maps, maps.matrices, maps.axes, float(self.softness)))
        return made[1], made[2]


#: The kernels' ``shadows`` of a frame without shadow maps.
NO_SHADOWS = (np.zeros((0, 1, 1), np.float32), np.zeros((0, 4, 4)), np.zeros((0, 16)), 0.0)


def frame_lights(lights: tuple, camera, specular: float, shininess: float, shadows: bool = False,
                 map_size: int | None = None, softness: float = 1.0, casters=None) -> FrameLights | None:
    """The :class:`FrameLights` of ``lights`` seen by ``camera`` (a rasterkit.Camera), or
    None without lights (the frame is lit by the classic headlight); ``shadows``: every light
    but the ambient ones casts shadows, in maps ``map_size`` texels a side (None: by the image
    size, :func:`rasterkit.raster.shadows.default_map_size`) filtered over ``softness``
    texels; ``casters``: :attr:`FrameLights.casters`."""
    if not lights:
        return None
    if shadows:
        lights = tuple(light if light.kind == "ambient" else replace(light, shadows=True) for light in lights)
    if map_size is None:
        from rasterkit.raster.shadows import default_map_size

        map_size = default_map_size(camera.width, camera.height)
    view = np.asarray(camera.backward(), np.float64)
    return FrameLights(light_table(lights, -view), np.asarray(camera.eye, np.float64),
                       camera.kind == "perspective", view, camera, specular, shininess, lights, map_size, softness,
                       casters)


def moved(light: Light, matrix) -> Light:
    """``light`` carried by the affine world transform ``matrix`` (4, 4) (a turntable's turn):
    its position transformed, its direction turned (and made unit again); ambient lights and
    headlights (which follow the camera) as they are."""
    if light.kind in ("ambient", "headlight"):
        return light
    m = np.asarray(matrix, np.float64)
    position = None if light.position is None else tuple(float(v) for v in m[:3, :3] @ light.position + m[:3, 3])
    direction = None if light.direction is None else tuple(float(v) for v in m[:3, :3] @ light.direction)
    return replace(light, position=position, direction=direction)


def check_lights(name: str, value) -> tuple:
    """A render's lights as they are stored: a tuple of :class:`Light` (``TypeError`` for anything else)."""
    if isinstance(value, (str, bytes, Light)) or not hasattr(value, "__iter__"):
        raise TypeError(f"{name} must be a list of rasterkit.Light, got {type(value).__name__}")
    lights = tuple(value)
    for k, light in enumerate(lights):
        if not isinstance(light, Light):
            raise TypeError(f"{name}[{k}] must be a rasterkit.Light, got {type(light).__name__}")
    return lights


def light_table(lights: tuple, view_direction: np.ndarray) -> np.ndarray:
    """(L, TABLE_WIDTH) float64, read-only: one row per light for the kernels: its kind code,
    position (3), unit direction towards the scene (3; a headlight's is ``view_direction``,
    the camera's), linear colour times intensity (3), range (0: none) and the spot cone's
    ``scale, offset`` (its factor is ``clamp(cos · scale + offset, 0, 1)²``, cos the angle's
    between the cone's axis and the direction to the point), its first shadow map (-1: none)
    and their count. Kept for the next frames of the same lights and view."""
    return _light_table(tuple(lights), tuple(float(v) for v in view_direction))


@lru_cache(maxsize=32)
def _light_table(lights: tuple, view_direction: tuple) -> np.ndarray:
    from rasterkit.colors import parse_color
    from rasterkit.material.colorspace import decode_srgb

    table = np.zeros((len(lights), TABLE_WIDTH))
    for row, light in zip(table, lights):
        row[0] = KINDS.index(light.kind)
        if light.position is not None:
            row[1:4] = light.position
        if light.kind == "headlight":
            row[4:7] = view_direction
        elif light.direction is not None:
            row[4:7] = light.direction
        row[7:10] = decode_srgb(parse_color(light.color)[:3] / 255.0) * light.intensity
        row[10] = light.range or 0.0
        outer = math.cos(math.radians(light.angle / 2))
        inner = math.cos(math.radians(light.angle / 2 * (1.0 - light.blend)))
        row[11] = 1.0 / max(1e-3, inner - outer)
        row[12] = -outer * row[11]
        row[13] = -1.0  # no shadow map (FrameLights.shadow_terms)
    table.flags.writeable = False
    return table


def _unit(name: str, value) -> tuple:
    from rasterkit._arrays import unit_vector

    return tuple(float(c) for c in unit_vector(value, name))


def _angle(value) -> float:
    value = values.real("angle", value)
    if not 0.0 < value < 180.0:
        raise ValueError(f"angle must be between 0 and 180 degrees (the cone's full opening), got {value!r}")
    return float(value)


def _absent(name: str, light: Light):
    if getattr(light, name) is not None:
        raise ValueError(f"{name}: a {light.kind} light has none")
    return None


#: The lights of a phong frame that brings none: a headlight, and the ambient light that
#: leaves the classic headlight's 25 % (sRGB) on faces turned away.
PHONG_LIGHTS = (Light.headlight(), Light.ambient(intensity=0.05))
