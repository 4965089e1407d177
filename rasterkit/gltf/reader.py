"""``read_gltf(path) -> GltfScene``: the default scene of a glTF or GLB file, each mesh node one
object of a :class:`rasterkit.Scene` lit by the file's lights, with its first camera recorded.

The steps: the container and its JSON (:mod:`.container`), the extensions (:mod:`.extensions`),
the GLB's binary buffer checked against its declared length, then the walk of the default
scene's nodes (:mod:`.nodes`): a node with a ``mesh`` adds that mesh (:mod:`.meshes`, read
once however many nodes use it) with the node's world matrix as its model matrix; the first
node with a ``camera`` is recorded (:mod:`.cameras`); a node with a ``KHR_lights_punctual``
light adds it to the Scene's lights as a :class:`rasterkit.Light` (:mod:`.lights`), its record
to :attr:`GltfScene.gltf_lights`. Skins are not applied (a skinned mesh is drawn
where its node puts it, in its bind shape), with a warning; animations are not played.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rasterkit.gltf.buffers import buffer
from rasterkit.gltf.cameras import GltfCamera, read_camera
from rasterkit.gltf.container import open_document
from rasterkit.gltf.document import Document, Obj
from rasterkit.gltf.errors import readable
from rasterkit.gltf.extensions import check_extensions
from rasterkit.gltf.lights import node_light, place_light
from rasterkit.gltf.meshes import read_mesh
from rasterkit.gltf.nodes import walk
from rasterkit.scene import Scene
from rasterkit.transform import apply_points

__all__ = ["GltfScene", "read_gltf"]


@dataclass
class GltfScene(Scene):
    """A :class:`rasterkit.Scene` read from a glTF file, with what the file adds.

    Attributes (besides the Scene's)
    --------------------------------
    path : str or None
        The file.
    gltf_camera : GltfCamera or None
        The default scene's first camera node (depth first, in the order nodes list their
        children): :func:`rasterkit.gltf.camera_of` makes a :class:`rasterkit.Camera` of it.
        ``Scene.camera`` is left None (the file's camera is not imposed).
    lights : list of rasterkit.Light
        (The Scene's.) The ``KHR_lights_punctual`` lights placed by the default scene's
        nodes, in world space (:mod:`rasterkit.gltf.lights`): ``render(scene)`` uses them.
    gltf_lights : list of GltfLight
        The same lights as the file gives them (type, linear colour, intensity, range, cone
        angles in radians, name), with their node and world position and direction.
    points : (K, 3) float64 or None
        World-space positions of the points primitives (mode 0), for ``render(...,
        points=...)``; their vertices are in the objects' meshes too (no face draws them).
    point_colors : (K, 3) uint8 or None
        Their sRGB colours (0-255), when their meshes have vertex colours.
    warnings : tuple of str
        What the reader noticed but accepted, one line each, starting with the file's name.
    """

    path: str | None = None
    gltf_camera: GltfCamera | None = None
    gltf_lights: list = field(default_factory=list)
    points: np.ndarray | None = None
    point_colors: np.ndarray | None = None
    warnings: tuple = ()


def read_gltf(path, *, textures: bool = True) -> GltfScene:
    """The default scene of the ``.gltf`` or ``.glb`` file ``path`` (see
    :mod:`rasterkit.gltf`); ``textures=False`` reads no image (materials keep their colours).

    Raises
    ------
    GltfError
        One line ``FILE: WHERE: reason``: the file or a buffer it names cannot be read, its
        JSON or GLB structure is broken, a value has the wrong type or range, an accessor
        or index reaches past its data, the node graph is not a set of trees, it requires an
        extension that changes the geometry, or its default scene draws nothing. Over the
        file size or memory limit, :class:`GltfLimitError`.
    """
    doc = open_document(path)
    doc.textures = textures
    check_extensions(doc)
    if doc.binary is not None and doc.table("buffers") and not doc.item("buffers", 0).has("uri"):
        buffer(doc, 0)  # the binary chunk's declared length, checked whether or not it is used
    scene = GltfScene(path=doc.path)
    points, colors = [], []
    for index, node, world in walk(doc):
        _node_contents(doc, scene, index, node, world, points, colors)
    if points:
        scene.points = np.concatenate(points)
        if all(c is not None for c in colors):
            scene.point_colors = np.concatenate(colors)
    if not scene.objects:
        noticed = f"; {len(doc.warnings)} warnings, the first: {doc.warnings[0]}" if doc.warnings else ""
        raise doc.error(None, "the default scene draws nothing (no node with a mesh of triangles, lines or "
                              f"points{noticed})")
    if doc.dropped:
        doc.warnings.append(f"{doc.dropped} more warnings not shown")
    scene.warnings = tuple(f"{readable(doc.path)}: {w}" for w in doc.warnings)
    return scene


def _node_contents(doc: Document, scene: GltfScene, index: int, node: Obj, world: np.ndarray, points: list,
                   colors: list) -> None:
    """Add what ``node`` holds to ``scene``: its mesh, camera, light."""
    mesh_index = node.ref("mesh", "meshes", None)
    if mesh_index is not None:
        if node.has("skin"):
            doc.warn(node.where, "its skin is not applied (drawn in its bind shape)")
        parts = read_mesh(doc, mesh_index)
        mesh = parts.mesh
        if len(mesh.faces) or len(mesh.lines) or len(parts.points):
            scene.add(mesh, world)
        if len(parts.points):
            points.append(apply_points(world, mesh.vertices[parts.points]))
            colors.append(None if mesh.vertex_colors is None else
                          np.floor(mesh.vertex_colors[parts.points] * 255.0 + 0.5).astype(np.uint8))
    camera = node.ref("camera", "cameras", None)
    if camera is not None and scene.gltf_camera is None:
        scene.gltf_camera = read_camera(doc, camera, index, world)
    ref = node_light(node)
    if ref is not None:
        placed = place_light(doc, ref, index, world)
        if placed is not None:
            scene.gltf_lights.append(placed[0])
            scene.add_light(placed[1])
