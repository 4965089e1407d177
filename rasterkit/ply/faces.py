"""The face element: polygons of any size as triangles, their edges, and what faces carry
(colours, MeshLab's per-corner ``texcoord`` list, ``texnumber``); and the edge element as
line segments.

Faces are the list ``vertex_indices`` (or ``vertex_index``) of integers, 0-based. Polygons
are split as the OBJ reader splits them (:func:`rasterkit.obj.assemble.split_polygons`:
fans where that covers them exactly, ear clipping for concave ones); the triangles keep the
file's winding, and ``Mesh.edges`` holds the polygons' own sides (a quad's four, not its
diagonal). As in OBJ files: a face of fewer than 3 vertices, or an index outside the
vertices, is an error naming the row; faces with a NaN or infinite vertex are dropped (one
warning), and triangles that a repeated index makes degenerate are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.mesh import mesh_bytes, repeated_corners
from rasterkit.mesh.checks import sealed_empty
from rasterkit.obj.assemble import split_polygons
from rasterkit.ply.errors import Notes, PlyError, check_limit, count
from rasterkit.ply.kernels.indices import widen
from rasterkit.ply.header import Element, Header

__all__ = ["FACE_INDICES", "MAX_VERTICES", "Polygons", "Triangles", "check_face_element", "read_lines",
           "read_polygons",
           "triangulate"]

FACE_INDICES = ("vertex_indices", "vertex_index")

#: The most vertices a mesh may have: two indices make one int64 key of the edges.
MAX_VERTICES = 2**31

#: Bytes per polygon corner while faces are split and their sides sorted (indices, the
#: sides' keys and their sorting, the triangles' corners), besides the Mesh's own arrays.
BYTES_PER_CORNER = 96


def check_face_element(header: Header, name: str) -> Element | None:
    """The face element (None without one); an error naming the line when it has no list of
    integers ``vertex_indices`` (or ``vertex_index``)."""
    element = header.element("face")
    if element is None:
        return None
    prop = element.find(*FACE_INDICES)
    if prop is None:
        raise PlyError(name, element.line, "element 'face' has no property 'vertex_indices' (or 'vertex_index')")
    if not prop.is_list or prop.dtype.kind not in "iu":
        raise PlyError(name, prop.line, f"property {prop.name!r} of element 'face' must be a list of integers")
    return element


@dataclass(frozen=True)
class Polygons:
    """The faces as read: ``corners`` (C,) int64 vertex indices, polygon p at
    ``offsets[p]:offsets[p + 1]``."""

    corners: np.ndarray
    offsets: np.ndarray

    @property
    def sizes(self) -> np.ndarray:
        return np.diff(self.offsets)


@dataclass(frozen=True)
class Triangles:
    """The triangles of the kept polygons: ``faces`` (M, 3) int64 vertex indices, ``corners``
    (M, 3) int64 the polygon corners they were cut from (None: corner ``3 m + c``, every
    polygon a triangle and all kept), ``polygon`` (M,) int64 each one's polygon (None: the
    identity) and ``keep`` (P,) bool the polygons whose vertices are finite."""

    faces: np.ndarray
    corners: np.ndarray | None
    polygon: np.ndarray | None
    keep: np.ndarray

    def per_polygon(self, values: np.ndarray) -> np.ndarray:
        """values (P, ...) of each polygon, as values of each triangle."""
        return values if self.polygon is None else values[self.polygon]

    def corner_rows(self) -> np.ndarray:
        return np.arange(3 * len(self.faces), dtype=np.int64).reshape(-1, 3) if self.corners is None else self.corners


def read_polygons(rows, element: Element, n_vertices: int, corner_uv: bool) -> Polygons:
    """The polygons of the face element's rows; checks the memory that making the Mesh
    will take first (with a per-corner texture coordinate table when ``corner_uv``)."""
    prop = element.find(*FACE_INDICES)
    j = rows.layout.lists.index(prop)
    sizes = np.atleast_1d(rows.list_counts(j))  # one count for all rows, or one each
    polygons = rows.n
    corners = int(sizes[0]) * polygons if len(sizes) == 1 else int(sizes.sum())
    triangles = corners - 2 * polygons
    check_limit(rows.source.name, BYTES_PER_CORNER * corners + mesh_bytes(
        n_vertices, max(triangles, polygons), corners, corners if corner_uv else 0, 0, int(corner_uv)),
        f"reading its {count(polygons, 'face')} of {count(corners, 'corner')}")
    small = sizes < 3
    if small.any():
        row = int(np.argmax(small))
        raise rows.error(row, f"a face needs at least 3 vertices, got {int(sizes[row])}", prop)
    values, offsets = rows.items(prop)
    values, lo, hi = _int64(values)
    if len(values) and (lo < 0 or hi >= n_vertices):
        k = int(np.argmax((values < 0) | (values >= n_vertices)))
        row = rows.row_of_item(offsets, k)
        raise rows.error(row, f"vertex index {int(values[k])} is out of range (the file has "
                              f"{count(n_vertices, 'vertex', 'vertices')})", prop, k - int(offsets[row]))
    return Polygons(values, offsets)


def _int64(values) -> tuple:
    """``(items, smallest, largest)``: the list items ``values`` as (C,) int64, as they are
    when they are that already (an ASCII file's), else converted in one copy into sealed
    memory (:func:`rasterkit.mesh.checks.sealed_empty`), which the Mesh keeps as its faces when
    the polygons are its triangles (a binary file's strided view of its bytes: by
    :func:`rasterkit.ply.kernels.indices.widen` where the bytes are in the machine's order)."""
    values = np.asarray(values)
    if values.dtype == np.int64 and values.flags.c_contiguous:
        flat = values.reshape(-1)
        return (flat, int(flat.min()), int(flat.max())) if len(flat) else (flat, 0, -1)
    sealed, fill = sealed_empty((values.size,), np.int64)
    if values.dtype.isnative and values.dtype.kind in "iu" and values.ndim == 2:
        lo, hi = widen(values, fill.reshape(values.shape))
        return sealed, int(lo), int(hi)
    np.copyto(fill.reshape(values.shape), values, casting="unsafe")
    return (sealed, int(sealed.min()), int(sealed.max())) if len(sealed) else (sealed, 0, -1)


def triangulate(polygons: Polygons, positions: np.ndarray, notes: Notes, line: int) -> Triangles:
    """The triangles of ``polygons`` over ``positions`` (N, 3); warns (naming the header
    ``line`` of the face element) about dropped and inexactly split faces."""
    corners, offsets = polygons.corners, polygons.offsets
    p = len(offsets) - 1
    keep = np.ones(p, bool)
    if not np.isfinite(positions).all() and p:
        finite = np.isfinite(positions).all(axis=1)
        keep = np.logical_and.reduceat(finite[corners], offsets[:-1])
        notes.warn(line, f"{count(np.count_nonzero(~finite), 'vertex', 'vertices')} with NaN or infinite "
                         f"coordinates; {count(p - np.count_nonzero(keep), 'face')} using them dropped")
    if len(corners) == 3 * p:  # every polygon a triangle (each has 3 corners or more)
        tri = corners.reshape(-1, 3)
        kept = keep & ~repeated_corners(tri)
        if kept.all():
            return Triangles(tri, None, None, keep)
        index = np.flatnonzero(kept)
        return Triangles(tri[index], 3 * index[:, None] + np.arange(3), index, keep)
    split, counts, inexact = split_polygons(positions, corners, offsets, keep)
    if inexact.any():
        notes.warn(line, f"{count(np.count_nonzero(inexact), 'face')} too irregular to split exactly "
                         "(self-intersecting?): split as a fan")
    return Triangles(corners[split], split, np.repeat(np.arange(p), counts), keep)


def read_lines(rows, element: Element, n_vertices: int, finite: np.ndarray, notes: Notes) -> np.ndarray | None:
    """(K, 2) int64 segments of the edge element (``vertex1``, ``vertex2``), without those at
    a NaN or infinite vertex; None when it has no such integer scalars (a warning)."""
    props = (element.find("vertex1"), element.find("vertex2"))
    if any(p is None or p.is_list or p.dtype.kind not in "iu" for p in props):
        notes.warn(element.line, "element 'edge' has no integer properties 'vertex1' and 'vertex2': skipped")
        return None
    pairs = np.stack([np.asarray(rows.scalar(p)).astype(np.int64) for p in props], axis=1)
    bad = (pairs < 0) | (pairs >= n_vertices)
    if bad.any():
        row, column = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise rows.error(int(row), f"vertex index {int(pairs[row, column])} is out of range (the file has "
                                   f"{count(n_vertices, 'vertex', 'vertices')})", props[column])
    usable = finite[pairs].all(axis=1)
    return pairs if usable.all() else pairs[usable]
