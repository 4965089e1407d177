"""The node hierarchy of the default scene (:func:`walk`): each node with its world matrix.

The default scene is ``scenes[scene]``, else ``scenes[0]``, else (a file without scenes)
every root node (a node no other node names as a child), in index order. From its root
nodes the children are walked depth first, in the order each node lists them; a node's world
matrix is its parent's times its own local matrix (object -> parent):

- ``matrix``: 16 numbers, column-major (glTF's order), affine (last row ``0 0 0 1``);
- else ``translation`` (x, y, z), ``rotation`` (a quaternion x, y, z, w; normalised here, a
  zero one is an error) and ``scale``: ``T · R · S``.

A node that is reached twice (a cycle, a node with two parents, a root that is also a child)
is an error: glTF's nodes form disjoint trees, and walking a graph that is not one could take
forever or exponentially long. The walk is a loop with its own stack (a chain of a million
nodes does not touch Python's recursion limit).
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.gltf.document import Document, Obj

__all__ = ["local_matrix", "quaternion_matrix", "roots", "walk"]


def quaternion_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    """The 3x3 rotation of the unit quaternion ``(x, y, z, w)``."""
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def local_matrix(doc: Document, node: Obj) -> np.ndarray:
    """The (4, 4) float64 local matrix of ``node`` (see the module documentation)."""
    if node.has("matrix"):
        if any(node.has(k) for k in ("translation", "rotation", "scale")):
            doc.warn(node.where, "has both a matrix and translation/rotation/scale: the matrix is used")
        m = np.array(node.numbers("matrix", (16,))).reshape(4, 4).T
        if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
            raise doc.error(node.path("matrix"), "must be affine (its last row 0, 0, 0, 1; glTF's order is "
                                                 "column-major)")
        return m
    t = node.numbers("translation", (3,), (0.0, 0.0, 0.0))
    q = node.numbers("rotation", (4,), (0.0, 0.0, 0.0, 1.0))
    s = node.numbers("scale", (3,), (1.0, 1.0, 1.0))
    length = math.sqrt(sum(c * c for c in q))
    if not 0.0 < length < math.inf:
        raise doc.error(node.path("rotation"), f"{list(q)} is not a rotation (a unit quaternion x, y, z, w)")
    m = np.eye(4)
    m[:3, :3] = quaternion_matrix(*(c / length for c in q)) * np.array(s)
    m[:3, 3] = t
    return m


def roots(doc: Document) -> tuple[list, str]:
    """``(node indices, where)``: the root nodes of the default scene and where they are listed."""
    scenes = doc.table("scenes")
    chosen = doc.root.ref("scene", "scenes", None)
    if chosen is None and scenes:
        chosen = 0
    if chosen is not None:
        scene = doc.item("scenes", chosen)
        return scene.refs("nodes", "nodes"), scene.path("nodes")
    children = set()
    for k in range(len(doc.table("nodes"))):
        children.update(doc.item("nodes", k).refs("children", "nodes"))
    return [k for k in range(len(doc.table("nodes"))) if k not in children], "nodes"


def walk(doc: Document):
    """Yield ``(index, node, world)`` for each node of the default scene, depth first:
    ``node`` its :class:`Obj`, ``world`` its (4, 4) object -> world matrix."""
    start, where = roots(doc)
    stack = [(k, np.eye(4), where) for k in reversed(start)]
    seen = set()
    while stack:
        index, parent, named = stack.pop()
        if index in seen:
            raise doc.error(named, f"nodes[{index}] is reached a second time (a cycle, or a node with two parents: "
                                   "glTF's nodes form trees)")
        seen.add(index)
        node = doc.item("nodes", index)
        with np.errstate(all="ignore"):
            world = parent @ local_matrix(doc, node)
        if not np.isfinite(world).all():
            raise doc.error(node.where, "its world matrix is beyond float64 (huge scales or translations)")
        yield index, node, world
        stack.extend((k, world, f"{node.path('children')}") for k in reversed(node.refs("children", "nodes")))
