"""What a render draws, decided from its :class:`~rasterkit.RenderOptions` before anything is
allocated: the mesh in world space, the camera, the options resolved for this frame
(:class:`Style`), which maps the band worker makes, and the memory it needs."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rasterkit.camera import Camera
from rasterkit.colors import parse_color
from rasterkit.mesh import Mesh, as_mesh
from rasterkit.options import SHADOW_GROUND, RenderOptions
from rasterkit.raster import accumulate as _accumulate
from rasterkit.raster.ao import default_radius
from rasterkit.raster.memory import ao_bytes, frame_bytes, maps_bytes
from rasterkit.raster.lights import PHONG_LIGHTS, check_lights, frame_lights
from rasterkit.raster.modes import Mode, mode
from rasterkit.raster.shading import light_direction
from rasterkit.raster.vertex import transform_points
from rasterkit.scene import Scene

__all__ = ["FramePlan", "Style", "plan_frame"]


@dataclass(frozen=True)
class Style:
    """A render's options resolved for one frame, as the passes read them."""

    mode: Mode  # the row of the mode table
    cull: str
    shading: str
    color: np.ndarray  # (4,) uint8 RGBA
    line_color: np.ndarray  # (4,) uint8 RGBA
    aa: bool
    light: np.ndarray  # (3,) unit world-space direction towards the light
    keep_depth: bool = False  # solid: draw the depth buffer in the colour pass, not when read
    points: object = None  # rasterkit.raster.points.Points, drawn last as depth-tested splats
    maps: object = None  # a vision render's Maps (rasterkit.raster.vision.maps_record), made by the band worker
    textures: bool = False  # textured faces drawn textured, cut-out faces cut out (rasterkit.raster.texturing)
    texture_filter: str | None = "trilinear"  # every texture's filter, or None: each one's own
    lights: object = None  # rasterkit.raster.lights.FrameLights, or None: the classic headlight


@dataclass(frozen=True)
class FramePlan:
    """What :func:`rasterkit.render` draws."""

    mesh: Mesh
    camera: Camera
    style: Style
    background: object
    options: RenderOptions
    one_sample: bool  # one sample at the pixel centres, no vignette
    in_bands: bool  # the maps made by the band worker
    object_faces: list | None  # a scene's faces per object, when ids are asked for
    need: int  # bytes, for check_memory
    ao_radius: float | None = None  # ambient occlusion's radius (rasterkit.raster.ao), None: no AO
    catcher: int | None = None  # ground="shadow": the ground's first face (rasterkit.raster.ground)

    @property
    def metric(self) -> bool:
        """Whether the frame's metric depth is made (asked for, or read by the shadow
        catcher; the AO reads the depth buffer)."""
        return self.options.camera_depth or self.catcher is not None

    @property
    def with_ids(self) -> bool:
        """Whether the frame draws face ids (asked for, or to find the shadow catcher)."""
        return self.options.ids or self.options.normals or self.options.uv or self.catcher is not None


def plan_frame(mesh, camera, options: RenderOptions, points=None, point_colors=None,
               feature_edges: bool = True) -> FramePlan:
    """Check ``mesh`` and ``camera`` (an undistorted one, or a scene's) and decide what
    ``options`` draw; ``point_colors``: the points' own colours (else ``options.point_color``);
    ``feature_edges``: work out the feature edges (else counted as all edges)."""
    if points is not None:  # imported here, as the other extras: a plain render loads none
        from rasterkit.raster.points import check_points

        points = check_points(points, options.point_color if point_colors is None else point_colors,
                              options.point_size)
        if mesh is None:
            mesh = Mesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64))
    object_faces, background, light, lights = None, options.background, options.light, options.lights
    ground = None
    if options.ground is not None and isinstance(camera if camera is not None else getattr(mesh, "camera", None),
                                                 Camera):
        from rasterkit.raster.ground import with_ground

        seen_by = camera if camera is not None else mesh.camera
        catches_only = options.ground == SHADOW_GROUND
        if catches_only and background is None:
            background = "transparent"  # the shadow alone, for compositing (a scene's background aside)
        mesh = with_ground(mesh if isinstance(mesh, Scene) else as_mesh(mesh),
                           "white" if catches_only else options.ground, seen_by.up)
        ground = mesh.objects[-1].mesh  # the last object: it only receives shadows
    if isinstance(mesh, Scene):
        camera = camera if camera is not None else mesh.camera
        background = background if background is not None else mesh.background
        light = light if light is not None else mesh.light
        lights = lights or check_lights("Scene.lights", mesh.lights)
        if options.ids:
            object_faces = [len(o.mesh.faces) for o in mesh.objects]
        mesh = mesh.world_mesh(options.color)
    mesh = as_mesh(mesh)
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a rasterkit.Camera, got {type(camera).__name__}")
    if not lights and options.shading == "phong":
        lights = PHONG_LIGHTS
    row = mode(options.mode)
    if feature_edges and options.edges == "feature" and row.edges:
        mesh = _with_feature_edges(mesh, camera, options.crease_angle)
    background = "white" if background is None else background
    casters = None if ground is None else (len(mesh.vertices) - len(ground.vertices), len(mesh.faces) - len(ground.faces))
    ao_radius = None
    if options.ao and row.faces:
        ao_radius = options.ao_radius or default_radius(mesh.vertices[:None if casters is None else casters[0]])
    catcher = len(mesh.faces) - len(ground.faces) if ground is not None and options.ground == SHADOW_GROUND else None
    metric = options.camera_depth or catcher is not None
    style = Style(row, options.cull, options.shading, parse_color(options.color), parse_color(options.line_color),
                  options.aa, light_direction(light, camera), textures=options.textures,
                  texture_filter=options.texture_filter,
                  lights=frame_lights(lights, camera, options.specular, options.shininess, options.shadows,
                                      options.shadow_map_size, options.shadow_softness, casters))
    one_sample = options.samples == 1 and options.vignette == 0.0
    normals, wanted_ids = options.normals, options.ids or options.normals or options.uv or catcher is not None
    # the maps made by the band worker: a one-sample render of faces, nothing drawn after
    in_bands = (normals or options.uv or object_faces is not None or metric) and one_sample \
        and row.faces and points is None
    if wanted_ids and one_sample and not (metric and in_bands) or points is not None:
        # a vision frame (its depth is wanted too), or points to test against the depth: a
        # deferred depth pass would draw again
        style = replace(style, keep_depth=True, points=points)
    if ao_radius is not None and one_sample:  # the AO reads the whole depth buffer: drawn into it
        style = replace(style, keep_depth=True)
    width, height = camera.width, camera.height
    alpha = parse_color(background)[3] < 255
    need = (frame_bytes(mesh, width, height, style, alpha, wanted_ids)
            + _accumulate.extra_bytes(width, height, alpha, options.samples, options.vignette,
                                      len(mesh.faces) if row.faces else 0)
            + maps_bytes(mesh, width * height, normals, object_faces is not None, metric and in_bands, options.uv)
            + (0 if style.lights is None else style.lights.shadow_bytes())
            + (0 if ao_radius is None else ao_bytes(width, height, row.depth_kept or style.keep_depth)))
    return FramePlan(mesh, camera, style, background, options, one_sample, in_bands, object_faces, need, ao_radius, catcher)


def _with_feature_edges(mesh: Mesh, camera: Camera, crease_angle: float) -> Mesh:
    """A Mesh whose edges are ``mesh``'s feature edges seen by ``camera`` (silhouettes depend
    on the eye)."""
    from rasterkit.raster import features as _features

    clip = transform_points(mesh.vertices, np.ascontiguousarray(camera.world_to_raster()))
    feature, _ = _features.feature_edges(mesh, clip, crease_angle)
    return replace(mesh, edges=feature)
