"""One mesh primitive: its vertex attributes (:func:`read_vertices`) and what it draws with
them (:func:`read_topology`): triangles, line segments or points, as vertex indices.

Topology, by ``mode`` (glTF's rules, so that each triangle keeps the winding it is meant to
have: counter-clockwise seen from the front):

- 4 triangles: indices ``3k, 3k+1, 3k+2`` (a remainder of 1 or 2 indices is left out, with a
  warning); 5 strip: triangle ``i`` is ``(i, i+1, i+2)`` for even ``i`` and ``(i, i+2,
  i+1)`` for odd ``i`` (the alternating winding fixed); 6 fan: ``(i+1, i+2, 0)``.
- 1 lines (pairs), 2 line loop, 3 line strip: segments, drawn as the mesh's ``lines``.
- 0 points: the vertices drawn as points (``GltfScene.points``).

Indices come from the ``indices`` accessor, or are ``0 .. count-1`` without one; an index
at or above the vertex count is an error (never a read out of bounds).

Attributes: ``POSITION`` (VEC3), ``NORMAL`` (VEC3), ``TEXCOORD_n`` (VEC2; ``v`` flipped to
rasterkit's, ``v' = 1 - v``: glTF's ``v`` runs down the image), ``COLOR_0`` (VEC3 or VEC4,
linear light, clipped to [0, 1]; its alpha is not used), any component type, normalized or
not (which makes ``KHR_mesh_quantization`` files readable as they are). Every attribute must
have POSITION's count. A normal with a component that is not finite becomes zero, such a
colour white, each with a warning.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.gltf.accessors import floats, indices as read_indices
from rasterkit.gltf.document import Document, Obj

__all__ = ["MODES", "Topology", "Vertices", "read_topology", "read_vertices"]

#: glTF's primitive modes.
MODES = {0: "points", 1: "lines", 2: "line loop", 3: "line strip", 4: "triangles", 5: "triangle strip",
         6: "triangle fan"}


@dataclass(frozen=True)
class Vertices:
    """The attributes of a primitive's vertices: (N, 3) ``positions``, and (N, 3) ``normals``,
    (N, 2) ``uv`` (v up), (N, 3) linear ``colors`` in [0, 1], each or None; float64."""

    positions: np.ndarray
    normals: np.ndarray | None
    uv: np.ndarray | None
    colors: np.ndarray | None


@dataclass(frozen=True)
class Topology:
    """What a primitive draws: ``faces`` (M, 3), ``lines`` (K, 2) and ``points`` (P,), int64
    indices of its vertices."""

    faces: np.ndarray
    lines: np.ndarray
    points: np.ndarray


def attribute_accessors(prim: Obj, uv_set: int | None) -> dict:
    """``{name: accessor index}`` of the attributes read: POSITION, NORMAL, COLOR_0 and
    ``TEXCOORD_<uv_set>`` (none when ``uv_set`` is None), those the primitive has."""
    attributes = prim.obj("attributes")
    names = ["POSITION", "NORMAL", "COLOR_0"] + ([] if uv_set is None else [f"TEXCOORD_{uv_set}"])
    return {name: attributes.ref(name, "accessors") for name in names if attributes.has(name)}


def read_vertices(doc: Document, prim: Obj, accessors: dict) -> Vertices:
    """The attributes named by ``accessors`` (:func:`attribute_accessors`) of ``prim``."""
    at = f"{prim.where}.attributes"
    positions, acc = floats(doc, accessors["POSITION"], f"{at}.POSITION", ("VEC3",), sealed=True)
    n = acc.count
    normals = uv = colors = None
    for name, index in accessors.items():
        if name == "POSITION":
            continue
        types = ("VEC2",) if name.startswith("TEXCOORD") else ("VEC3", "VEC4") if name == "COLOR_0" else ("VEC3",)
        # normals and texture coordinates as the Mesh keeps them (sealed), colours not yet
        values, other = floats(doc, index, f"{at}.{name}", types, sealed=name != "COLOR_0",
                               flip_v=name.startswith("TEXCOORD"))
        if other.count != n:
            raise doc.error(f"{at}.{name}", f"{other.where} has {other.count} elements, POSITION has {n}")
        if name == "NORMAL":
            normals = _finite(doc, values, 0.0, f"{at}.NORMAL", "normals that are not finite are zero")
        elif name == "COLOR_0":
            colors = np.clip(_finite(doc, values[:, :3], 1.0, f"{at}.COLOR_0", "colours that are not finite are "
                                     "white"), 0.0, 1.0)
        else:
            uv = values
    return Vertices(positions, normals, uv, colors)


def _finite(doc: Document, values: np.ndarray, fill: float, where: str, message: str) -> np.ndarray:
    if np.isfinite(values).all():  # the usual case, without the slow reduction along rows
        return values
    bad = ~np.isfinite(values).all(axis=1)
    if bad.any():
        doc.warn(where, message)
        values = np.where(bad[:, None], fill, values)
    return values


def read_topology(doc: Document, prim: Obj, n_vertices: int) -> Topology:
    """The faces, lines or points of ``prim`` over its ``n_vertices`` vertices."""
    mode = prim.int("mode", 4, high=6)
    index = prim.ref("indices", "accessors", None)
    if index is None:
        doc.check_memory(n_vertices * 8 * 4, f"the {n_vertices} vertices of {prim.where}", prim.where)
        order = np.arange(n_vertices, dtype=np.int64)
    else:
        order = read_indices(doc, index, prim.path("indices"), n_vertices)
    doc.check_memory(len(order) * 8 * 8, f"the {MODES[mode]} of {prim.where}", prim.where)
    empty = np.zeros((0, 3), np.int64)
    no_lines, no_points = np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    if mode == 0:
        return Topology(empty, no_lines, order)
    if mode in (1, 2, 3):
        return Topology(empty, _segments(doc, prim, mode, order), no_points)
    return Topology(_triangles(doc, prim, mode, order), no_lines, no_points)


def _triangles(doc: Document, prim: Obj, mode: int, order: np.ndarray) -> np.ndarray:
    n = len(order)
    if mode == 4:
        if n % 3:
            doc.warn(prim.where, f"{n} indices are not whole triangles: the last {n % 3} left out")
        return order[: n - n % 3].reshape(-1, 3)
    if n < 3:
        doc.warn(prim.where, f"a {MODES[mode]} of {n} vertices draws no triangle")
        return np.zeros((0, 3), np.int64)
    if mode == 5:
        i = np.arange(n - 2)
        odd = i % 2
        return np.stack([order[i], order[i + 1 + odd], order[i + 2 - odd]], axis=1)
    return np.stack([order[1:-1], order[2:], np.full(n - 2, order[0])], axis=1)


def _segments(doc: Document, prim: Obj, mode: int, order: np.ndarray) -> np.ndarray:
    n = len(order)
    if mode == 1:
        if n % 2:
            doc.warn(prim.where, f"{n} indices are not whole lines: the last one left out")
        return order[: n - n % 2].reshape(-1, 2)
    if n < 2:
        doc.warn(prim.where, f"a {MODES[mode]} of {n} vertices draws no line")
        return np.zeros((0, 2), np.int64)
    ends = np.roll(order, -1) if mode == 2 else order[1:]
    return np.stack([order[: len(ends)], ends], axis=1)
