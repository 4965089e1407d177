"""The ground under a model (``RenderOptions(ground=COLOUR)``, ``--ground``): a square plane of
that colour just under the model's lowest point along the camera's up direction, many times
wider than the model, which catches its shadows as product renders do."""

from __future__ import annotations

import numpy as np

from rasterkit.mesh import Mesh
from rasterkit.scene import Scene
from rasterkit.transform import apply_points

__all__ = ["GROUND_SCALE", "with_ground"]

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
