"""glTF cameras: the record of the default scene's first camera node (:class:`GltfCamera`,
:func:`read_camera`) and the :class:`rasterkit.Camera` it gives (:func:`camera_of`).

A glTF camera looks down its node's -Z axis with +Y up, as rasterkit's camera space does
(OpenGL's), so its node's world matrix is its pose: the eye is the matrix's translation, the
view direction its -Z column, up its +Y column (a scale in the node's matrix is ignored, as
glTF says). ``perspective``: ``yfov`` (radians) is the vertical field of view; the image keeps
the size asked for (``aspectRatio`` is recorded, not imposed); ``zfar`` absent means an
infinite far plane, which rasterkit's depth cannot hold: the far plane is then put just past
the scene's bounding sphere. ``orthographic``: ``ymag`` is half the view's height (the width
follows the image's aspect, ``xmag`` is recorded); a ``znear`` of 0 becomes a small fraction
of ``zfar`` (rasterkit's near plane is in front of the eye).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from rasterkit.camera import Camera
from rasterkit.camera.checks import image_size
from rasterkit.gltf.document import Document
from rasterkit.gltf.errors import GltfError

__all__ = ["GltfCamera", "camera_of", "read_camera"]

#: How far past the bounding sphere the far plane goes (a camera without ``zfar``), and the
#: near plane of an orthographic camera with ``znear`` 0, as a fraction of ``zfar``.
_FAR_MARGIN = 1.05
_ORTHO_NEAR = 1e-6


@dataclass(frozen=True, eq=False)
class GltfCamera:
    """A camera of a glTF file as its JSON says it, placed by its node.

    Attributes
    ----------
    kind : {"perspective", "orthographic"}
    pose : (4, 4) float64
        The camera node's world matrix (camera -> world; the camera looks down its -Z).
    yfov : float or None
        Perspective: vertical field of view, radians.
    aspect_ratio : float or None
        Perspective: the width / height the file suggests, if it does.
    znear, zfar : float, float or None
        Near and far plane distances; ``zfar`` None: infinite (perspective only).
    xmag, ymag : float or None
        Orthographic: half the width and height of the view, world units.
    name : str or None
    node : int
        The index of its node.
    """

    kind: str
    pose: np.ndarray
    yfov: float | None
    aspect_ratio: float | None
    znear: float
    zfar: float | None
    xmag: float | None
    ymag: float | None
    name: str | None
    node: int


def read_camera(doc: Document, index: int, node: int, world: np.ndarray) -> GltfCamera:
    """The :class:`GltfCamera` of ``cameras[index]`` at the node ``node`` of world matrix ``world``."""
    c = doc.item("cameras", index)
    kind = c.string("type")
    if kind not in ("perspective", "orthographic"):
        raise doc.error(c.path("type"), f"must be 'perspective' or 'orthographic', got {kind!r}")
    p = c.obj(kind)
    name = c.string("name", None)
    if kind == "perspective":
        znear = p.number("znear", low=0.0)
        zfar = p.number("zfar", None, low=0.0)
        yfov = p.number("yfov", low=0.0, high=math.pi)
        if znear == 0.0 or yfov in (0.0, math.pi) or (zfar is not None and zfar <= znear):
            raise doc.error(p.where, "needs 0 < znear < zfar and 0 < yfov < pi")
        return GltfCamera(kind, world, yfov, p.number("aspectRatio", None, low=0.0), znear, zfar, None, None,
                          name, node)
    znear, zfar = p.number("znear", low=0.0), p.number("zfar", low=0.0)
    xmag, ymag = p.number("xmag"), p.number("ymag")
    if zfar <= znear or xmag == 0.0 or ymag == 0.0:
        raise doc.error(p.where, "needs 0 <= znear < zfar and non-zero xmag and ymag")
    return GltfCamera(kind, world, None, None, znear, zfar, xmag, ymag, name, node)


def camera_of(scene_or_path, width: int, height: int) -> Camera:
    """The :class:`rasterkit.Camera` of a glTF file's first camera (see the module
    documentation), ``width`` x ``height`` pixels.

    Parameters
    ----------
    scene_or_path : GltfScene, str or path
        A scene :func:`rasterkit.gltf.read_gltf` gave, or a file to read.
    width, height : int
        The image size.

    Raises
    ------
    GltfError
        The file cannot be read, or its default scene has no camera node, or the camera's
        pose cannot be a camera's (its node's matrix squashes a direction to nothing).
    """
    from rasterkit.gltf.reader import GltfScene, read_gltf

    width, height = image_size(width, "width"), image_size(height, "height")
    scene = scene_or_path if isinstance(scene_or_path, GltfScene) else read_gltf(scene_or_path)
    found = scene.gltf_camera
    path = os.fspath(scene.path) if scene.path is not None else "scene"
    if found is None:
        raise GltfError(path, None, "the default scene has no camera node")
    pose = found.pose
    eye = pose[:3, 3]
    ahead, up = -pose[:3, 2], pose[:3, 1]
    if not (np.linalg.norm(ahead) > 0.0 and np.linalg.norm(np.cross(ahead, up)) > 0.0):
        raise GltfError(path, f"nodes[{found.node}]", "the camera node's matrix leaves no view direction and up")
    ahead = ahead / np.linalg.norm(ahead)
    target = eye + ahead * max(1.0, float(np.abs(eye).max()))
    where = f"cameras of nodes[{found.node}]"
    try:
        if found.kind == "perspective":
            far = found.zfar if found.zfar is not None else _far(scene, eye, found.znear)
            return Camera.look_at(eye, target, up, fov_y=math.degrees(found.yfov), width=width, height=height,
                                  near=found.znear, far=far)
        near = found.znear if found.znear > 0.0 else found.zfar * _ORTHO_NEAR
        return Camera.orthographic(eye, target, up, view_height=2.0 * abs(found.ymag), width=width, height=height,
                                   near=near, far=found.zfar)
    except ValueError as e:  # the file's numbers make no valid camera (too large, too small)
        if isinstance(e, GltfError):
            raise
        raise GltfError(path, where, " ".join(str(e).split())) from None


def _far(scene, eye: np.ndarray, near: float) -> float:
    """A far plane just past the scene's bounding sphere, seen from ``eye``."""
    center, radius = scene.bounding_sphere()
    return max((float(np.linalg.norm(center - eye)) + radius) * _FAR_MARGIN, 2.0 * near)
