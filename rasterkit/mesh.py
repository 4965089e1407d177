"""Mesh: validated, C-contiguous arrays of one polygonal model.

A Mesh never holds an index out of range, a face with repeated shape errors or arrays of the
wrong dtype: the constructor checks everything once, so the kernels can trust its arrays.
They are the Mesh's own and read-only (an array passed in is copied when the Mesh would
otherwise share it), so what was checked stays true, and what is worked out from them once
(:attr:`Mesh.face_normals`) stays valid. To move a mesh, make a new one
(``dataclasses.replace(mesh, vertices=...)`` keeps its edges).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

__all__ = ["Mesh", "as_mesh", "polygon_edges", "unique_edges"]


def polygon_edges(polygons) -> np.ndarray:
    """Unique undirected edges (E, 2) int64 of a list of polygons (sequences of vertex indices).

    Each polygon contributes its boundary ``p[0]-p[1], ..., p[-1]-p[0]``; an edge shared by
    two polygons appears once, as ``(min, max)``, sorted.
    """
    pairs = []
    for p in polygons:
        p = np.asarray(p, dtype=np.int64)
        pairs.append(np.stack([p, np.roll(p, -1)], axis=1))
    if not pairs:
        return np.zeros((0, 2), np.int64)
    # Any integers: numbered 0..n-1 in order first, which keeps the edges' order.
    values, compact = np.unique(np.concatenate(pairs), return_inverse=True)
    return values[unique_edges(compact.reshape(-1, 2), len(values))]


def unique_edges(pairs: np.ndarray, n_vertices: int, keys: np.ndarray | None = None) -> np.ndarray:
    """Sorted unique undirected edges (E, 2) int64, ``(lo, hi)`` with lo < hi.

    Parameters
    ----------
    pairs : (K, 2) int
        Vertex index pairs, either way round; a pair from a vertex to itself is left out.
    n_vertices : int
        N: every index is in 0..N-1.
    keys : (J,) int64, optional
        More edges, as keys ``lo * N + hi`` (lo < hi), as
        :func:`rasterkit.kernels.obj_polygons.side_keys` makes them.
    """
    pairs = np.sort(np.asarray(pairs, dtype=np.int64).reshape(-1, 2), axis=1)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    n = max(int(n_vertices), 1)
    codes = pairs[:, 0] * n + pairs[:, 1]
    if keys is not None:
        codes = np.concatenate([keys, codes])
    codes = np.sort(codes)
    codes = codes[np.diff(codes, prepend=-1) != 0]
    return np.stack([codes // n, codes % n], axis=1)


def _array(a, dtype, shape_tail, name, n_rows=None):
    arr = np.ascontiguousarray(np.asarray(a, dtype=dtype))
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        want = ", ".join(["N", *map(str, shape_tail)])
        raise ValueError(f"{name} must have shape ({want}), got {arr.shape}")
    if n_rows is not None and len(arr) != n_rows:
        raise ValueError(f"{name} must have {n_rows} rows, got {len(arr)}")
    return arr


def _own(arr, source) -> np.ndarray:
    """``arr`` (made from ``source``, what the caller passed) made read-only; copied first
    unless it is a fresh array or ``source`` itself already frozen (another Mesh's array):
    the caller's arrays stay writeable, and writing to them cannot change the Mesh."""
    fresh = arr is not source and arr.base is None
    frozen = arr is source and not arr.flags.writeable and arr.flags.owndata
    if not (fresh or frozen):
        arr = arr.copy()
    arr.flags.writeable = False
    return arr


def _indices(a, n_vertices, width, name):
    a = np.asarray(a)
    if a.size == 0:
        a = np.zeros((0, width), np.int64)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must hold integers, got {a.dtype}")
    arr = _array(a, np.int64, (width,), name)
    if len(arr) and (arr.min() < 0 or arr.max() >= n_vertices):
        raise ValueError(f"{name} index out of range [0, {n_vertices})")
    return arr


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh with the edges of its original polygons.

    Attributes
    ----------
    vertices : (N, 3) float64
        Positions in object space.
    faces : (M, 3) int64
        Triangles (indices into ``vertices``), counter-clockwise seen from the front.
    edges : (E, 2) int64
        Unique undirected edges of the original polygons (a quad gives its four sides, not the
        diagonal of its triangulation) and of ``lines``. Computed from ``faces`` when omitted.
    lines : (K, 2) int64
        Segments from OBJ ``l`` elements.
    vertex_colors : (N, 3) float32 in [0, 1], or None
    normals : (N, 3) float64, or None
        Per-vertex normals (object space).
    texcoords : (N, 2) float64, or None
    face_colors : (M, 3) float32 in [0, 1], or None
        Per-face colours (for example the ``Kd`` of the face's material).
    face_groups : (M,) int32, or None
        Index into ``group_names`` for each face.
    group_names : tuple of str
    material_names : tuple of str
    warnings : tuple of str
        What the loader noticed but accepted.

    The arrays are read-only; the Mesh does not share them with the arrays it was made from.
    """

    vertices: np.ndarray
    faces: np.ndarray
    edges: np.ndarray | None = None
    lines: np.ndarray | None = None
    vertex_colors: np.ndarray | None = None
    normals: np.ndarray | None = None
    texcoords: np.ndarray | None = None
    face_colors: np.ndarray | None = None
    face_groups: np.ndarray | None = None
    group_names: tuple = ()
    material_names: tuple = ()
    warnings: tuple = field(default=())

    def __post_init__(self):
        v = _array(self.vertices, np.float64, (3,), "vertices")
        n = len(v)
        f = _indices(self.faces, n, 3, "faces")
        lines = _indices(self.lines if self.lines is not None else (), n, 2, "lines")
        if self.edges is None:
            edges = unique_edges(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]], lines]), n)
        else:
            edges = _indices(self.edges, n, 2, "edges")
        set_ = object.__setattr__
        # each array the Mesh's own and read-only (self.<name> is still what was passed)
        set_(self, "vertices", _own(v, self.vertices))
        set_(self, "faces", _own(f, self.faces))
        set_(self, "lines", _own(lines, self.lines))
        set_(self, "edges", _own(edges, self.edges))
        optional = {
            "vertex_colors": (np.float32, (3,), n),
            "normals": (np.float64, (3,), n),
            "texcoords": (np.float64, (2,), n),
            "face_colors": (np.float32, (3,), len(f)),
        }
        for name, (dtype, tail, rows) in optional.items():
            value = getattr(self, name)
            if value is not None:
                set_(self, name, _own(_array(value, dtype, tail, name, rows), value))
        if self.face_groups is not None:
            g = np.ascontiguousarray(np.asarray(self.face_groups, dtype=np.int32))
            if g.shape != (len(f),) or (len(g) and (g.min() < 0 or g.max() >= len(self.group_names))):
                raise ValueError("face_groups must be (M,) indices into group_names")
            set_(self, "face_groups", _own(g, self.face_groups))
        set_(self, "group_names", tuple(self.group_names))
        set_(self, "material_names", tuple(self.material_names))
        set_(self, "warnings", tuple(self.warnings))

    @cached_property
    def face_normals(self) -> np.ndarray:
        """(M, 3) float32, read-only: unit face normals (right-hand rule: counter-clockwise
        seen from the front points out), zero for a degenerate face, NaN for a face with a
        non-finite corner. Worked out on first use and kept: flat shading needs them in every
        frame, and they do not depend on the camera."""
        from .kernels.shade import face_normals
        normals = face_normals(self.vertices, self.faces).astype(np.float32)
        normals.flags.writeable = False
        return normals

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float64: minimum and maximum corner of the finite vertices' bounding box."""
        finite = self.vertices[np.all(np.isfinite(self.vertices), axis=1)]
        if len(finite) == 0:
            return np.zeros((2, 3))
        return np.stack([finite.min(axis=0), finite.max(axis=0)])

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """Centre (3,) and radius of a sphere holding every finite vertex (box centre based)."""
        lo, hi = self.bounds
        centre = (lo + hi) / 2.0
        finite = self.vertices[np.all(np.isfinite(self.vertices), axis=1)]
        radius = float(np.linalg.norm(finite - centre, axis=1).max()) if len(finite) else 0.0
        return centre, radius

    def __repr__(self) -> str:
        return (f"Mesh({len(self.vertices)} vertices, {len(self.faces)} faces, "
                f"{len(self.edges)} edges, {len(self.lines)} lines)")


def as_mesh(mesh) -> Mesh:
    """A :class:`Mesh` from a Mesh, a ``(vertices, faces)`` pair or an object with
    ``.vertices`` and ``.faces`` (a trimesh mesh, for example)."""
    if isinstance(mesh, Mesh):
        return mesh
    if isinstance(mesh, tuple) and len(mesh) == 2:
        return Mesh(*mesh)
    if hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        return Mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces))
    raise TypeError("mesh must be a rasterkit.Mesh, a (vertices, faces) tuple, "
                    "or an object with .vertices and .faces")
