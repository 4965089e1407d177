"""The ground under a model (``RenderOptions(ground=COLOUR)``, ``--ground``): a square plane of
that colour just under the model's lowest point along the camera's up direction, many times
wider than the model, which catches its shadows as product renders do."""

from __future__ import annotations

import numpy as np

from rasterkit.mesh import Mesh
from rasterkit.scene import Scene
from rasterkit.transform import apply_points

__all__ = ["GROUND_SCALE", "catch_shadows", "with_ground"]

#: The ground's half side, in radii of the model's bounding sphere.
GROUND_SCALE = 12.0


def with_ground(model, color, up) -> Scene:
    """A :class:`rasterkit.Scene` of ``model`` (a Mesh or a Scene: its objects, lights, camera
    and background) standing on a square of ground of colour ``color``, perpendicular to
    ``up`` (world space), at the model's lowest point along it."""
    scene = Scene(camera=model.camera, light=model.light, background=model.background, objects=list(model.objects),
                  lights=list(model.lights)) if isinstance(model, Scene) else Scene().add(model)
    vertices = np.concatenate([apply_points(o.matrix, o.mesh.vertices) for o in scene.objects])
    vertices = vertices[np.isfinite(vertices).all(axis=1)]
    if len(vertices) == 0:
        return scene
    up = np.asarray(up, np.float64) / np.linalg.norm(up)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, radius = (lo + hi) / 2.0, max(float(np.linalg.norm(hi - lo)) / 2.0, 1e-9)
    height = float((vertices @ up).min())
    # the plane's axes: two directions perpendicular to up
    side = np.eye(3)[int(np.argmin(np.abs(up)))]
    a = np.cross(up, side)
    a /= np.linalg.norm(a)
    b = np.cross(a, up)
    middle = centre + (height - centre @ up) * up
    half = GROUND_SCALE * radius
    corners = np.array([middle + half * (sa * a + sb * b) for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    if np.cross(corners[1] - corners[0], corners[2] - corners[0]) @ up < 0:  # wound to face up
        faces = faces[:, ::-1].copy()
    return scene.add(Mesh(corners, faces), color=color)


def catch_shadows(fb, seen, camera, lights, normal) -> None:
    """``ground="shadow"``: turn the ground's pixels (``seen`` (H, W) bool) of ``fb`` into
    black of the opacity of the light they miss over the background.

    The ground was drawn white, with the frame's shadows and ambient occlusion; its colour
    unshadowed is worked out again at each of its pixels (its point from the metric depth, its
    normal ``normal``) under ``lights`` (the frame's, lit per pixel) without shadows. A frame
    not lit per pixel has no shadows: the share of ambient light ``fb.ao`` is then all there
    is to miss. The
    opacity is one minus the ratio of the two in linear light (summed over red, green and
    blue), composited over the background's colour and opacity."""
    from rasterkit.material.colorspace import decode_srgb
    from rasterkit.raster.ao import camera_geometry
    from rasterkit.raster.shading import lit_rows

    j, i = np.nonzero(seen)
    if lights is not None:
        d = fb.camera_depth()[j, i].astype(np.float64)
        rays, _, _ = camera_geometry(camera)
        x, y = (i + 0.5)[:, None], (j + 0.5)[:, None]
        points = rays[0] + x * rays[1] + y * rays[2] + d[:, None] * (rays[3] + x * rays[4] + y * rays[5])
        normals = np.broadcast_to(np.asarray(normal, np.float64) / np.linalg.norm(normal), points.shape)
        plain = (np.full((1, 3), lights.specular), np.array([lights.shininess]), np.zeros((1, 3)))
        white = np.full((1, 3), 255.0, np.float32)
        unshadowed = decode_srgb(lit_rows(points, normals, white, plain, lights, False) / 255.0).sum(axis=1)
        drawn = decode_srgb(fb.color[j, i, :3] / 255.0).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            light = np.where(unshadowed > 1e-6, drawn / unshadowed, 1.0)
    else:
        light = fb.ao[j, i].astype(np.float64) if fb.ao is not None else np.ones(len(j))
    opacity = 1.0 - np.clip(light, 0.0, 1.0)
    under = fb.background[3] / 255.0 * (1.0 - opacity)  # the background's share of the result
    alpha = opacity + under
    with np.errstate(divide="ignore", invalid="ignore"):
        rgb = np.where(alpha[:, None] > 0, fb.background[None, :3] * (under / np.maximum(alpha, 1e-12))[:, None], 0.0)
    fb.color[j, i, :3] = np.rint(rgb).astype(np.uint8)
    if fb.color.shape[2] == 4:
        fb.color[j, i, 3] = np.rint(255.0 * alpha).astype(np.uint8)
