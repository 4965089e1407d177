"""glTF ``KHR_lights_punctual`` lights: the record of a light placed by a node
(:class:`GltfLight`, :func:`place_light`) and the :class:`rasterkit.Light` it gives
(:func:`light_of`).

The file lists its lights once (``extensions.KHR_lights_punctual.lights``, at the top
level); a node places one with ``extensions.KHR_lights_punctual.light``, an index of that
list. A light is read (and checked) once, when a node of the default scene first places it:

- ``type``: ``directional``, ``point`` or ``spot`` (required);
- ``color``: linear RGB, numbers >= 0 (default white), and ``intensity`` >= 0 (default 1):
  candela for point and spot lights, lux for directional ones; rasterkit lights each surface
  by ``intensity / d²`` (point, spot) or ``intensity`` (directional), so the intensity is
  kept as it is;
- ``range`` (point and spot lights; above 0; absent: infinite), the distance at which
  glTF's window ``clamp(1 - (d / range)⁴, 0, 1)`` brings the light to zero, as rasterkit's;
- ``spot``: ``innerConeAngle`` (default 0) and ``outerConeAngle`` (default pi/4), radians
  from the cone's axis, ``0 <= inner < outer <= pi/2``.

The node places it: its position is the node's world-space origin, its direction (where it
shines) the node's world-space -Z axis, normalised; a node whose matrix squashes that axis
to nothing leaves a directional or spot light out, with a warning.

rasterkit's lights have sRGB colours of 0-255 values: the linear colour is encoded to sRGB
(the nearest 8-bit code); a colour brighter than 1 (which glTF's schema does not allow,
but files have) gives its brightest component to the intensity first (``color / m``,
``intensity * m``). A spot's cone becomes rasterkit's full opening ``angle = 2 outer``
(degrees; just under 180 for an outer angle of pi/2) and ``blend = 1 - inner / outer``,
the fraction of the half-angle over which it fades: the same ramp between the cosines,
squared.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from rasterkit._arrays import unit
from rasterkit.gltf.document import Document, Obj, shown
from rasterkit.material.colorspace import encode_srgb8
from rasterkit.raster.lights import Light

__all__ = ["LIGHT_TYPES", "GltfLight", "light_of", "node_light", "place_light"]

#: The light types of KHR_lights_punctual.
LIGHT_TYPES = ("directional", "point", "spot")
_EXTENSION = "KHR_lights_punctual"
_TABLE = f"extensions.{_EXTENSION}.lights"
#: glTF's default outer cone angle (radians).
_OUTER = math.pi / 4
#: rasterkit's spot angle is below 180 degrees: an outer cone angle of pi/2 is drawn as this.
_WIDEST = math.nextafter(180.0, 0.0)


@dataclass(frozen=True, eq=False)
class GltfLight:
    """A ``KHR_lights_punctual`` light as its JSON says it, placed by a node.

    Attributes
    ----------
    kind : {"directional", "point", "spot"}
    color : (r, g, b) float
        Linear RGB, as in the file.
    intensity : float
        Candela (point, spot) or lux (directional).
    range : float or None
        Point and spot lights: where they fade out (None: infinite).
    inner_cone_angle, outer_cone_angle : float or None
        Spot lights: radians from the cone's axis.
    name : str or None
    index : int
        Its index in the file's list of lights.
    node : int or None
        The index of the node that places it (None: not placed).
    position : (3,) float64 or None
        World space: the node's origin.
    direction : (3,) float64 or None
        World space, unit: the node's -Z axis, the way the light shines (None when the
        node's matrix squashes it).
    """

    kind: str
    color: tuple
    intensity: float
    range: float | None
    inner_cone_angle: float | None
    outer_cone_angle: float | None
    name: str | None
    index: int
    node: int | None = None
    position: np.ndarray | None = None
    direction: np.ndarray | None = None


def node_light(node: Obj) -> Obj | None:
    """The ``extensions.KHR_lights_punctual`` object of ``node``, or None."""
    extensions = node.obj("extensions", None)
    return None if extensions is None else extensions.obj(_EXTENSION, None)


def place_light(doc: Document, ref: Obj, node: int, world: np.ndarray) -> tuple[GltfLight, Light] | None:
    """``(GltfLight, Light)`` of the light ``ref.light`` names, placed by the node ``node``
    of world matrix ``world``; None (after a warning) when the matrix leaves a directional or
    spot light no direction."""
    index, where = _light_index(doc, ref)
    light = _read_light(doc, index)
    d = -world[:3, 2] + 0.0  # + 0.0: no -0.0 components
    direction = unit(d, "direction") if np.isfinite(d).all() and d.any() else None
    if direction is None and light.kind != "point":
        doc.warn(doc.item("nodes", node).where, f"its {light.kind} light ({where}) is left out: the node's matrix "
                                                "squashes its -Z axis, the light's direction")
        return None
    placed = replace(light, node=node, position=world[:3, 3].copy(), direction=direction)
    try:
        return placed, light_of(placed)
    except (TypeError, ValueError) as e:  # numbers no rasterkit.Light takes (beyond float64)
        raise doc.error(where, " ".join(str(e).split())) from None


def light_of(light: GltfLight) -> Light:
    """The :class:`rasterkit.Light` of a placed :class:`GltfLight` (see the module
    documentation); ``ValueError`` when its intensity times its brightest colour component
    is beyond float64."""
    color, intensity = _srgb(light.color, light.intensity)
    position = None if light.position is None else tuple(float(c) for c in light.position)
    if light.kind == "directional":
        return Light.directional(light.direction, color=color, intensity=intensity)
    if light.kind == "point":
        return Light.point(position, color=color, intensity=intensity, range=light.range)
    outer, inner = light.outer_cone_angle, light.inner_cone_angle
    angle = min(math.degrees(2.0 * outer), _WIDEST)
    return Light.spot(position, light.direction, angle=angle, blend=1.0 - inner / outer, color=color,
                      intensity=intensity, range=light.range)


def _srgb(color: tuple, intensity: float) -> tuple[tuple, float]:
    """``(sRGB 0-255 ints, intensity)`` of a linear colour and its intensity: a component
    above 1 moves the brightest one into the intensity first."""
    linear = np.array(color, np.float64)
    brightest = float(linear.max())
    if brightest > 1.0:
        linear = linear / brightest
        intensity = intensity * brightest
        if not math.isfinite(intensity):
            raise ValueError(f"its intensity times its brightest colour component ({brightest:g}) is beyond float64")
    return tuple(int(c) for c in encode_srgb8(linear)), intensity


def _lights(doc: Document, ref: Obj) -> list:
    """The file's list of lights (each an :class:`Obj`), read once."""
    if "lights" not in doc.cache:
        root = doc.root.obj("extensions", None)
        table = None if root is None else root.obj(_EXTENSION, None)
        if table is None:
            raise doc.error(ref.path("light"), f"names a light, but the file defines none ({_TABLE} is missing)")
        doc.cache["lights"] = table.objects("lights")
    return doc.cache["lights"]


def _light_index(doc: Document, ref: Obj) -> tuple[int, str]:
    """``(index, where)``: the light ``ref`` names, checked, and its place in the file."""
    lights = _lights(doc, ref)
    index = ref.int("light")
    if index >= len(lights):
        have = f"the file's {len(lights)} lights" if lights else f"{_TABLE}, which is empty"
        raise doc.error(ref.path("light"), f"must be an index of {have}, got {index}")
    return index, lights[index].where


def _read_light(doc: Document, index: int) -> GltfLight:
    """The :class:`GltfLight` (not placed) of light ``index`` (checked to be one), read once."""
    key = ("light", index)
    if key not in doc.cache:
        doc.cache[key] = _parse_light(doc, doc.cache["lights"][index], index)
    return doc.cache[key]


def _parse_light(doc: Document, light: Obj, index: int) -> GltfLight:
    """The :class:`GltfLight` of the JSON object ``light`` (checked), not placed."""
    kind = light.string("type")
    if kind not in LIGHT_TYPES:
        raise doc.error(light.path("type"), f"must be one of {', '.join(LIGHT_TYPES)}, got {shown(kind)}")
    color = light.numbers("color", (3,), (1.0, 1.0, 1.0))
    if min(color) < 0.0:
        raise doc.error(light.path("color"), f"must be 3 numbers >= 0 (linear RGB), got {list(color)}")
    intensity = light.number("intensity", 1.0, low=0.0)
    range_ = None
    if kind == "directional":
        if light.has("range"):
            doc.warn(light.path("range"), "a directional light has no range: ignored")
    else:
        range_ = light.number("range", None, low=0.0)
        if range_ == 0.0:
            raise doc.error(light.path("range"), "must be above 0 (absent: infinite), got 0")
    inner = outer = None
    if kind == "spot":
        inner, outer = _cone(doc, light)
    elif light.has("spot"):
        doc.warn(light.path("spot"), f"a {kind} light has no cone: ignored")
    return GltfLight(kind, color, intensity, range_, inner, outer, light.string("name", None), index)


def _cone(doc: Document, light: Obj) -> tuple[float, float]:
    """``(inner, outer)`` cone angles of a spot light (radians, checked)."""
    spot = light.obj("spot", None)
    if spot is None:
        doc.warn(light.where, "a spot light without 'spot': glTF's default cone (inner 0, outer pi/4)")
        return 0.0, _OUTER
    outer = spot.number("outerConeAngle", _OUTER, low=0.0, high=math.pi / 2)
    if outer == 0.0:
        raise doc.error(spot.path("outerConeAngle"), "must be above 0 (and at most pi/2), got 0")
    inner = spot.number("innerConeAngle", 0.0, low=0.0, high=math.pi / 2)
    if inner >= outer:
        raise doc.error(spot.path("innerConeAngle"), f"must be below outerConeAngle ({outer:g}), got {inner:g}")
    return inner, outer
