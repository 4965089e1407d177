"""How a frame is drawn: :class:`RenderOptions`, the lists of choices and the size limits.

One home, shared by the command line and the API. Pure Python: importing this module imports
neither NumPy nor Numba, so the command line builds its parser, answers ``--help`` and
rejects bad arguments without loading the kernels (checking a colour or a light loads NumPy).
"""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass

from rasterkit import values
from rasterkit.raster.kernels.limits import MAX_IMAGE_SIZE

__all__ = ["CULL", "EDGES", "FIELDS", "HIDDEN", "MAX_IMAGE_SIZE", "MAX_POINT_SIZE", "MAX_SAMPLES", "MODEL_CAMERAS",
           "MAX_SHADOW_MAP", "MODES", "PROJECTIONS", "RenderOptions", "SHADING", "SVG_MODES", "TEXTURE_FILTERS",
           "check_choice"]

#: What ``View(camera=...)`` and ``--camera`` may name: a camera the model file brings (a glTF
#: file's first camera node).
MODEL_CAMERAS = ("gltf",)

#: The side of a shadow map, texels, at most.
MAX_SHADOW_MAP = 8192
#: Samples per pixel of a render, at most.
MAX_SAMPLES = 256

#: ``ground=`` for a ground that shows only the shadows it catches.
SHADOW_GROUND = "shadow"

#: Ambient occlusion's rays per pixel, at most.
MAX_AO_SAMPLES = 256

#: The side of a drawn point, in pixels, at most.
MAX_POINT_SIZE = 64

#: What :func:`rasterkit.render` draws: every edge; only the visible parts of the edges;
#: shaded triangles; shaded triangles with their visible edges on top.
MODES = ("wire", "hidden", "solid", "solid+wire")

#: Which edges are drawn: those of the original polygons, or the feature edges (silhouettes,
#: boundaries, creases, material boundaries: :mod:`rasterkit.raster.features`).
EDGES = ("all", "feature")

#: What :func:`rasterkit.render_svg` draws: every edge, or only their visible parts.
SVG_MODES = ("wire", "hidden")

#: What a vector drawing does with the hidden parts of the edges: leaves them out (None) or
#: draws them dashed.
HIDDEN = (None, "dashed")

#: Which triangles are removed before rasterization: those facing away from the camera,
#: those facing it, or none.
CULL = ("back", "front", "none")

#: Shading per face, per vertex (Gouraud), or per pixel (Phong: Blinn-Phong under the lights).
SHADING = ("flat", "smooth", "phong")

#: How textures are filtered: mipmaps blended between two levels (GL_LINEAR_MIPMAP_LINEAR),
#: the 4 nearest texels of the image (GL_LINEAR), or the one texel under the point (GL_NEAREST).
TEXTURE_FILTERS = ("trilinear", "bilinear", "nearest")

PROJECTIONS = ("perspective", "orthographic", "isometric", "dimetric", "trimetric", "cavalier",
               "cabinet", "1-point", "2-point", "3-point")
"""Names accepted by :meth:`Camera.preset` (and the command line's ``--projection``)."""


def check_choice(name: str, value, allowed: tuple):
    """``value`` when it is one of ``allowed``, else ``ValueError`` naming ``name`` and the choices."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value


@dataclass(frozen=True)
class RenderOptions:
    """Everything that decides how :func:`rasterkit.render` draws a frame, checked once.

    Make one with keywords (every field has a default) and derive others with
    :meth:`replace`; ``render(mesh, camera, options=opts, **changes)`` draws with ``opts``
    and then ``changes`` (``render(mesh, camera, "solid", cull="none")`` is
    ``render(mesh, camera, options=RenderOptions(mode="solid", cull="none"))``). The command
    line, :func:`rasterkit.render_many`, a batch's workers and the distorted-camera path
    all pass one of these whole. Values are stored in one form (tuples, floats, bools), so
    two records that draw alike compare equal, and a record pickles and hashes.

    Fields
    ------
    mode : {"wire", "hidden", "solid", "solid+wire"}
        ``wire``: every edge, no depth test. ``hidden``: hidden-line removal: a depth pass of
        the triangles, then only the visible parts of the edges. ``solid``: shaded triangles.
        ``solid+wire``: shaded triangles with the visible edges on top.
    cull : {"back", "front", "none"}
        Faces removed before rasterization (the lecture's n·v test, as the sign of the
        screen-space area).
    shading : {"flat", "smooth", "phong"}
        Lighting per face, per vertex (Gouraud, interpolated across the faces) or per pixel
        (Phong: the normals interpolated, Blinn-Phong under ``lights``; without lights, a
        headlight with a little ambient light, :data:`rasterkit.raster.lights.PHONG_LIGHTS`).
        Flat and smooth shading are Lambert's under the classic headlight (or ``light``),
        or Blinn-Phong under ``lights``.
    color, line_color : colour
        ``'#rrggbb'``, a name, or an ``(r, g, b)`` tuple of 0-255. Vertex or face colours of
        the mesh take the place of ``color``.
    background : colour or None
        ``'transparent'`` gives an RGBA framebuffer; None: a scene's background, else white.
    light : (3,) float or None
        World-space direction towards a distant light; None: a scene's light, else a
        headlight shining along the viewing direction.
    aa : bool
        Anti-aliased (Xiaolin Wu) lines.
    edges : {"all", "feature"}
        The edges the wire, hidden and solid+wire modes draw: those of the original polygons,
        or the feature edges seen from the camera (silhouettes, boundaries, creases,
        material boundaries: :mod:`rasterkit.raster.features`).
    crease_angle : float
        Degrees (0 to 180) between two faces' normals from which their shared edge is a
        crease (``edges="feature"``).
    samples : int
        Samples per pixel, 1 to 256, averaged (:mod:`rasterkit.raster.accumulate`): anti-aliasing
        of faces, edges and lines, and depth of field for a camera with an ``aperture``.
    vignette : float
        In [0, 1]: 1 darkens each pixel by the natural cos⁴θ falloff of a lens camera, 0 none.
    ids, normals, camera_depth, uv : bool
        The maps made with the frame: the visible face's index (``fb.ids``, and a scene's
        ``fb.object_ids``), camera-space unit normals (``fb.normals``), the metric depth of
        ``fb.camera_depth()`` made while drawing (the same values as when made on request),
        the texture coordinates (``fb.uv``, (H, W, 2) float32, interpolated perspective-correctly,
        NaN where no face or a face without texture coordinates is seen).
    point_size : int
        Side in pixels (1 to 64) of the squares that ``points`` are drawn as.
    point_color : colour
        The points' colour (per-point colours go to :func:`rasterkit.render` as an array).
    textures : bool
        Draw the faces whose material has a ``diffuse_map`` textured (the map's colour times
        the material's ``diffuse`` and the shading); False draws every face untextured.
    lights : list of rasterkit.Light
        The lights of the frame (:class:`rasterkit.Light`: directional, point, spot, ambient,
        headlight), Blinn-Phong shading summed in linear light (:mod:`rasterkit.raster.lighting`);
        empty (the default): a scene's lights, else the classic Lambert headlight (or ``light``).
    specular : float
        In [0, 1]: the strength of the white highlight of faces without a material (linear
        light), under ``lights``. Default 0.25.
    shininess : float
        The Blinn-Phong exponent of faces without a material, >= 0. Default 32.
    shadows : bool
        Every light (but ambient ones) casts shadows, as ``Light(shadows=True)`` does: shadow
        maps (:mod:`rasterkit.raster.shadows`), and every face lit per pixel.
    shadow_map_size : int or None
        The side of each shadow map in texels, 16 to 8192; None: the power of two at least as
        large as the image's longer side, 512 to 4096.
    shadow_softness : float
        The shadow maps' filter (percentage-closer filtering): the square of
        ``2 ceil(s) + 1`` texels around each lookup, 0 (hard) to 8. Default 1 (3 x 3).
    ground : colour, "shadow" or None
        A square of ground of this colour under the model (:mod:`rasterkit.raster.ground`),
        which catches its shadows; ``"shadow"``: only the shadows (and the ambient occlusion)
        the ground catches, as black of their darkness' opacity over the background (a
        transparent one unless ``background`` is given; a scene's own is not used), for
        compositing; None (the default): none. The
        frame is then a scene's: with ``ids``, ``fb.object_ids`` tells the model's objects from
        the ground (the last).
    ao : bool
        Ambient occlusion (:mod:`rasterkit.raster.ao`): the darkening of creases and contacts,
        estimated in screen space from the frame's depth, each drawn face pixel's colour
        multiplied by the share of ambient light reaching it (``fb.ao``), in the modes that
        draw faces.
    ao_radius : float or None
        How far (world units) a surface occludes; None: a tenth of the model's bounding-box
        diagonal.
    ao_samples : int
        Rays per pixel, 1 to 256. Default 8 (each pixel's are turned against its
        neighbours': 128 directions over each 4x4 tile).
    texture_filter : {"trilinear", "bilinear", "nearest"} or None
        How every texture is filtered (:data:`TEXTURE_FILTERS`): ``trilinear`` uses the
        mipmaps with OpenGL's level of detail, ``bilinear`` the 4 texels around the point,
        ``nearest`` the one under it; None: each texture's own ``filter``.
    """

    mode: str = "wire"
    cull: str = "back"
    shading: str = "flat"
    color: object = "lightgray"
    line_color: object = "black"
    background: object = None
    light: tuple | None = None
    aa: bool = False
    edges: str = "all"
    crease_angle: float = 30.0
    samples: int = 1
    vignette: float = 0.0
    ids: bool = False
    normals: bool = False
    camera_depth: bool = False
    uv: bool = False
    point_size: int = 1
    point_color: object = "black"
    textures: bool = True
    texture_filter: str | None = "trilinear"
    lights: tuple = ()
    specular: float = 0.25
    shininess: float = 32.0
    shadows: bool = False
    shadow_map_size: int | None = None
    shadow_softness: float = 1.0
    ground: object = None
    ao: bool = False
    ao_radius: float | None = None
    ao_samples: int = 8

    def __post_init__(self):
        for name, check in _CHECKS.items():
            object.__setattr__(self, name, check(name, getattr(self, name)))

    def replace(self, **changes) -> RenderOptions:
        """A copy with ``changes``, each checked (``TypeError`` naming a field that does not
        exist). The other fields were checked when this record was made."""
        if not changes:
            return self
        unknown = set(changes) - FIELDS
        if unknown:
            raise TypeError(f"unknown render option {sorted(unknown)[0]!r} (the options are: {', '.join(sorted(FIELDS))})")
        copy = object.__new__(RenderOptions)
        copy.__dict__.update(self.__dict__)
        for name, value in changes.items():
            object.__setattr__(copy, name, _CHECKS[name](name, value))
        return copy


#: The names of :class:`RenderOptions`' fields.
FIELDS = frozenset(f.name for f in dataclasses.fields(RenderOptions))


def _direction(name: str, value) -> tuple[float, float, float]:
    """Three finite numbers, not all zero, as they were given (scaled to unit length when drawn)."""
    from rasterkit._arrays import real_array, unit_vector

    unit_vector(value, name)
    return tuple(float(v) for v in real_array(value, name))


def _crease_angle(name: str, value) -> float:
    if values._is_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError(f"crease_angle must be a number of degrees, got {type(value).__name__}")
    if not 0.0 <= value <= 180.0:
        raise ValueError(f"crease_angle must be between 0 and 180 degrees, got {value!r}")
    return float(value)


def _lights(name: str, value) -> tuple:
    """A tuple of rasterkit.Light (none: no import of the lights module)."""
    if isinstance(value, (tuple, list)) and not value:
        return ()
    from rasterkit.raster.lights import check_lights

    return check_lights(name, value)


def _at_most(name: str, value: float, high: float) -> float:
    if value > high:
        raise ValueError(f"{name} must be at most {high:g}, got {value!r}")
    return value


def _optional(check):
    return lambda name, value: None if value is None else check(name, value)


#: Each field's check, giving the value as it is stored.
_CHECKS = {
    "mode": lambda name, value: values.choice(name, value, MODES),
    "cull": lambda name, value: values.choice(name, value, CULL),
    "shading": lambda name, value: values.choice(name, value, SHADING),
    "color": values.colour, "line_color": values.colour, "background": _optional(values.colour), "light": _optional(_direction),
    "aa": values.flag,
    "edges": lambda name, value: values.choice(name, value, EDGES),
    "crease_angle": _crease_angle,
    "samples": lambda name, value: values.whole(name, value, 1, MAX_SAMPLES),
    "vignette": values.unit_interval,
    "ids": values.flag, "normals": values.flag, "camera_depth": values.flag, "uv": values.flag,
    "point_size": lambda name, value: values.whole(name, value, 1, MAX_POINT_SIZE),
    "point_color": values.colour,
    "textures": values.flag,
    "texture_filter": _optional(lambda name, value: values.choice(name, value, TEXTURE_FILTERS)),
    "lights": lambda name, value: _lights(name, value),
    "specular": values.unit_interval,
    "shininess": values.non_negative,
    "shadows": values.flag,
    "shadow_map_size": _optional(lambda name, value: values.whole(name, value, 16, MAX_SHADOW_MAP)),
    "shadow_softness": lambda name, value: _at_most(name, values.non_negative(name, value), 8.0),
    "ground": _optional(lambda name, value: value if value == SHADOW_GROUND else values.colour(name, value)),
    "ao": values.flag,
    "ao_radius": _optional(values.positive),
    "ao_samples": lambda name, value: values.whole(name, value, 1, MAX_AO_SAMPLES),
}
assert set(_CHECKS) == FIELDS
