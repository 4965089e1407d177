"""A glTF mesh as one :class:`rasterkit.Mesh` (:func:`read_mesh`): its primitives' vertices
one after the other, their triangles and lines offset into them, each triangle labelled with
its primitive's material; made once, shared by every node that uses the mesh.

- Primitives that read the same attribute accessors share one copy of their vertices (a mesh
  whose primitives index one vertex buffer keeps it once).
- ``NORMAL`` becomes the Mesh's ``normals`` (per vertex) and ``corner_normals``: per vertex
  too when every primitive with triangles has normals, else through ``normal_index`` with
  ``-1`` rows for the faces without.
- ``TEXCOORD_<n>`` (the set the material's texture reads) becomes ``uv``, likewise.
- Colours (sRGB, as rasterkit's colours are): ``COLOR_0`` times the material's
  ``baseColorFactor``, encoded, as ``vertex_colors`` when some primitive has ``COLOR_0``
  (the others: their factor; without a material
  :data:`~rasterkit.material.DEFAULT_DIFFUSE`); otherwise ``face_colors`` from the factors
  when some primitive has a material, else none (the render's colour).
- Points primitives' vertices are in the Mesh, with no face: :class:`MeshParts` lists them.
- Morph targets are not applied (the base shape is drawn), with a warning.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.gltf.document import Document
from rasterkit.gltf.errors import GltfError, GltfLimitError, readable
from rasterkit.gltf.materials import look
from rasterkit.gltf.primitives import attribute_accessors, read_topology, read_vertices
from rasterkit.limits import LimitError
from rasterkit.material import DEFAULT_DIFFUSE
from rasterkit.material.colorspace import encode_srgb
from rasterkit.mesh import Mesh, mesh_bytes
from rasterkit.mesh.checks import sealed_empty

__all__ = ["MeshParts", "read_mesh"]


@dataclass(frozen=True)
class MeshParts:
    """A glTF mesh read: its ``mesh`` and the ``points`` (P,) int64 of its points
    primitives (vertex indices of ``mesh``)."""

    mesh: Mesh
    points: np.ndarray


@dataclass
class _Part:
    """One primitive: its vertex block, what it draws and its material's slot."""

    block: int
    faces: np.ndarray
    lines: np.ndarray
    points: np.ndarray
    slot: int  # index into the mesh's materials, -1 for none
    color: tuple | None  # its material's sRGB colour


def read_mesh(doc: Document, index: int) -> MeshParts:
    """The :class:`MeshParts` of ``meshes[index]`` (an index already checked), made once."""
    key = ("mesh", index)
    if key not in doc.cache:
        before = len(doc.warnings)
        doc.cache[key] = _read(doc, index, before)
    return doc.cache[key]


def _read(doc: Document, index: int, before: int) -> MeshParts:
    m = doc.item("meshes", index)
    blocks, keys, parts, slots, materials = [], {}, [], {}, []
    primitives = m.objects("primitives")
    for prim in primitives:
        material = prim.ref("material", "materials", None)
        lk = look(doc, material)
        if lk is not None and lk.hidden:
            continue
        if prim.has("targets"):
            doc.warn(prim.where, "morph targets are not applied")
        accessors = attribute_accessors(prim, None if lk is None else lk.uv_set)
        if "POSITION" not in accessors:
            doc.warn(prim.where, "has no POSITION: not drawn")
            continue
        if lk is not None and lk.uv_set is not None and f"TEXCOORD_{lk.uv_set}" not in accessors:
            doc.warn(prim.where, f"has no TEXCOORD_{lk.uv_set}: drawn without its texture")
        block_key = (tuple(sorted(accessors.items())), material if "COLOR_0" in accessors else None)
        if block_key not in keys:
            keys[block_key] = len(blocks)
            blocks.append((read_vertices(doc, prim, accessors), lk))
        b = keys[block_key]
        topology = read_topology(doc, prim, len(blocks[b][0].positions))
        slot = -1
        if lk is not None:
            if material not in slots:
                slots[material] = len(materials)
                materials.append(lk.material)
            slot = slots[material]
        parts.append(_Part(b, topology.faces, topology.lines, topology.points, slot, None if lk is None else lk.color))
    warnings = tuple(doc.warnings[before:])
    return _assemble(doc, m.where, [v for v, _ in blocks], [lk for _, lk in blocks], parts, materials, warnings)


def _assemble(doc: Document, where: str, blocks: list, looks: list, parts: list, materials: list,
              warnings: tuple) -> MeshParts:
    starts = np.cumsum([0] + [len(b.positions) for b in blocks])
    n = int(starts[-1])
    m = sum(len(p.faces) for p in parts)
    e = sum(len(p.lines) for p in parts)
    with_faces = {p.block for p in parts if len(p.faces)}
    has_uv = any(blocks[b].uv is not None for b in with_faces)
    has_normals = any(blocks[b].normals is not None for b in with_faces)
    indexed = sum(has and not all(getattr(blocks[b], name) is not None for b in with_faces)
                  for has, name in ((has_uv, "uv"), (has_normals, "normals")))
    doc.check_memory(n * 24 * 4 + m * 24 * 3 + mesh_bytes(n, m, 3 * m + e, n if has_uv else 0,
                                                           n if has_normals else 0, indexed),
                     f"a mesh of {n} vertices and {m} faces", where)

    def joined(arrays, width):
        arrays = [a for a in arrays if len(a)]
        if len(arrays) == 1:
            return arrays[0]
        return np.concatenate(arrays) if arrays else np.zeros((0, width), np.int64)

    def offset(a, block):
        return a + starts[block] if starts[block] else a

    faces = joined([offset(p.faces, p.block) for p in parts], 3)
    lines = joined([offset(p.lines, p.block) for p in parts], 2)
    points = joined([offset(p.points, p.block) for p in parts], 1).reshape(-1)
    fields = dict(vertices=joined([b.positions for b in blocks], 3).astype(np.float64, copy=False),
                  faces=faces, lines=lines)
    if has_uv:
        fields.update(_table(blocks, parts, starts, faces, "uv", 2, "uv_index"))
    if has_normals:
        fields.update(_table(blocks, parts, starts, faces, "normals", 3, "normal_index", "corner_normals"))
        if fields["normal_index"] is None and all(b.normals is not None for b in blocks):
            fields["normals"] = fields["corner_normals"]
    fields.update(_colors(blocks, looks, parts, m))
    if materials:
        fields.update(materials=tuple(materials), material_names=tuple(x.name for x in materials),
                      face_materials=_per_face(parts, m, (), np.int32, lambda p: p.slot))
    try:
        mesh = Mesh(**fields, warnings=tuple(f"{readable(doc.path)}: {w}" for w in warnings))
    except LimitError as e:
        raise GltfLimitError(doc.path, where, str(e)) from None
    except ValueError as e:  # the reader's checks should leave nothing for the Mesh's own to find
        raise GltfError(doc.path, where, str(e)) from None
    doc.spent += mesh.nbytes
    return MeshParts(mesh, points)


def _table(blocks, parts, starts, faces, name: str, width: int, index_name: str, table_name: str | None = None):
    """``{table_name: (N, width) rows, index_name: (M, 3) rows or None}`` of the blocks'
    attribute ``name`` (zeros for a block without it; -1 rows for its faces)."""
    rows = _joined([getattr(b, name) if getattr(b, name) is not None else np.zeros((len(b.positions), width))
                    for b in blocks])
    if all(getattr(blocks[p.block], name) is not None for p in parts if len(p.faces)):
        return {table_name or name: rows, index_name: None}
    given = np.concatenate([np.full(len(p.faces), getattr(blocks[p.block], name) is not None) for p in parts])
    index = np.where(given[:, None], faces, -1)
    return {table_name or name: rows, index_name: index}


def _colors(blocks, looks, parts, m: int) -> dict:
    """``vertex_colors`` or ``face_colors`` (sRGB, float32), see the module documentation."""
    if any(b.colors is not None for b in blocks):
        rows = []
        for b, lk in zip(blocks, looks):
            factor = np.ones(3) if lk is None else np.asarray(lk.factor)
            if b.colors is not None:
                rows.append(encode_srgb(b.colors * factor))
            else:
                colour = DEFAULT_DIFFUSE if lk is None else lk.color
                rows.append(np.tile(np.asarray(colour, np.float64), (len(b.positions), 1)))
        return {"vertex_colors": np.clip(np.concatenate(rows), 0.0, 1.0).astype(np.float32)}
    if m and any(p.color is not None for p in parts):
        return {"face_colors": _per_face(parts, m, (3,), np.float32,
                                         lambda p: p.color if p.color is not None else DEFAULT_DIFFUSE)}
    return {}


def _joined(arrays: list) -> np.ndarray:
    """``arrays`` one after the other (the one array itself, not a copy, when there is one)."""
    return arrays[0] if len(arrays) == 1 else np.concatenate(arrays)


def _per_face(parts, m: int, shape: tuple, dtype, value) -> np.ndarray:
    """(m, *shape) of ``dtype``: ``value(part)`` for each face of each part, in order (in
    sealed memory: the Mesh keeps it without a copy)."""
    sealed, out = sealed_empty((m, *shape), dtype)
    start = 0
    for p in parts:
        out[start:start + len(p.faces)] = value(p)
        start += len(p.faces)
    return sealed
