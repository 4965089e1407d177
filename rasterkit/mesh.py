"""Mesh: validated, C-contiguous arrays of one polygonal model.

A Mesh never holds an index out of range, a face with repeated shape errors or arrays of the
wrong dtype: the constructor checks everything once, so the kernels can trust its arrays.
They are the Mesh's own and immutable: read-only views of ``bytes`` objects the Mesh made
(an array passed in is copied), which NumPy cannot make writeable again nor resize, so what
was checked stays true, and what is worked out from them once (:attr:`Mesh.face_normals`)
stays valid. What NumPy still lets anyone change in place, an array's ``shape``, ``dtype``
and ``strides``, or an attribute replaced behind the frozen dataclass's back, is caught by
:meth:`Mesh.check_intact` (a few attribute reads), which the renderer calls before any
kernel runs. To move a mesh, make a new one (``dataclasses.replace(mesh, vertices=...)``
keeps its edges).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from rasterkit._arrays import real_array
from rasterkit.limits import check_memory

__all__ = ["Mesh", "as_mesh", "mesh_bytes", "polygon_edges", "unique_edges"]


def polygon_edges(polygons) -> np.ndarray:
    """Unique undirected edges (E, 2) int64 of a list of polygons (sequences of vertex indices).

    Each polygon contributes its boundary ``p[0]-p[1], ..., p[-1]-p[0]``; an edge shared by
    two polygons appears once, as ``(min, max)``, sorted.
    """
    pairs = []
    for k, p in enumerate(polygons):
        p = np.asarray(p)
        if p.dtype.kind not in "iu" or p.ndim != 1:
            raise TypeError(f"polygons[{k}] must be a sequence of integer vertex indices, got dtype {p.dtype} "
                            f"and shape {p.shape}")
        p = p.astype(np.int64)
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
        :func:`rasterkit.obj.assemble.polygon_sides` makes them.
    """
    pairs = np.asarray(pairs)
    if pairs.dtype.kind not in "iu" and pairs.size:
        raise TypeError(f"pairs must hold integer vertex indices, got dtype {pairs.dtype}")
    pairs = np.sort(pairs.astype(np.int64).reshape(-1, 2), axis=1)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    n = max(int(n_vertices), 1)
    codes = pairs[:, 0] * n + pairs[:, 1]
    if keys is not None:
        codes = np.concatenate([keys, codes])
    codes = np.sort(codes)
    codes = codes[np.diff(codes, prepend=-1) != 0]
    return np.stack([codes // n, codes % n], axis=1)


def side_neighbours(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(M, 3) int32: for side ``c`` of each face (corners ``c`` and ``c + 1``), the other
    face with the same two vertices when exactly two faces have that side, else -1 (an
    open border, a side of three faces or more, or a side whose corners are one vertex)."""
    m = len(faces)
    a = faces.reshape(-1)
    b = faces[:, [1, 2, 0]].reshape(-1)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    keys = lo * max(int(n_vertices), 1) + hi
    keys[lo == hi] = -1 - np.arange(np.count_nonzero(lo == hi))  # each its own: no neighbour
    order = np.argsort(keys, kind="stable")
    same = keys[order][1:] == keys[order][:-1]
    pair = same.copy()  # a run of exactly two equal keys
    pair[1:] &= ~same[:-1]
    pair[:-1] &= ~same[1:]
    i = np.flatnonzero(pair)
    out = np.full(3 * m, -1, np.int32)
    out[order[i]] = order[i + 1] // 3
    out[order[i + 1]] = order[i] // 3
    return out.reshape(m, 3)


def _array(a, dtype, shape_tail, name, n_rows=None):
    arr = np.ascontiguousarray(real_array(a, name, dtype))
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        want = ", ".join(["N", *map(str, shape_tail)])
        raise ValueError(f"{name} must have shape ({want}), got {arr.shape}")
    if n_rows is not None and len(arr) != n_rows:
        raise ValueError(f"{name} must have {n_rows} rows, got {len(arr)}")
    return arr


def _check_unit_colors(colors: np.ndarray, name: str) -> None:
    """ValueError unless every value of ``colors`` (float32) is finite and in [0, 1]."""
    if not colors.size:
        return
    finite = np.isfinite(colors)
    if not finite.all():
        row = int(np.argmin(finite.all(axis=1)))
        raise ValueError(f"{name}[{row}] is {colors[row].tolist()}: colours must be finite numbers in [0, 1]")
    low, high = float(colors.min()), float(colors.max())
    if low < 0.0 or high > 1.0:
        row = int(np.argmax(((colors < 0.0) | (colors > 1.0)).any(axis=1)))
        hint = " (divide 0-255 colours by 255)" if high > 1.0 else ""
        raise ValueError(f"{name}[{row}] is {colors[row].tolist()}: colours must lie in [0, 1]{hint}")


def immutable(arr) -> bool:
    """Whether ``arr`` is a read-only, C-contiguous, aligned view of a ``bytes`` object:
    memory that NumPy offers no way to write to (its ``WRITEABLE`` flag cannot be set
    again, on it or on any array made from it, and it cannot be resized)."""
    if not isinstance(arr, np.ndarray) or arr.flags.writeable or not (arr.flags.c_contiguous and arr.flags.aligned):
        return False
    base = arr
    while isinstance(base, np.ndarray):
        base = base.base
    return type(base) is bytes


def seal(arr: np.ndarray) -> np.ndarray:
    """``arr`` as an immutable array (:func:`immutable`): itself when it is one already,
    else a copy over a new ``bytes`` object (``arr`` stays as it was)."""
    if immutable(arr):
        return arr
    return np.frombuffer(np.ascontiguousarray(arr).tobytes(), dtype=arr.dtype).reshape(arr.shape)


def _indices(a, n_vertices, width, name):
    if a is None:
        raise TypeError(f"{name} must be an array of integers, got None")
    a = np.asarray(a)
    if a.size == 0 and a.dtype.kind in "iufO":  # [] is float64 to NumPy
        a = np.zeros((0, width), np.int64)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must hold integers, got dtype {a.dtype}")
    arr = _array(a, np.int64, (width,), name)
    if len(arr) and (arr.min() < 0 or arr.max() >= n_vertices):
        raise ValueError(f"{name} index out of range [0, {n_vertices})")
    return arr


def mesh_bytes(n_vertices: int, n_faces: int, n_edges: int) -> int:
    """Bytes that making a Mesh needs, at most: per vertex its positions, colours, normals
    and texture coordinates, checked and then copied; per face its indices, colour and
    group, and the temporaries of working out the edges (6 arrays of 3 pairs per face);
    per edge its pair, checked and copied. For :func:`rasterkit.limits.check_memory`."""
    return n_vertices * 2 * (24 + 12 + 24 + 16) + n_faces * (2 * (24 + 12 + 4) + 3 * 16 * 6) + n_edges * 2 * 16


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
        Per-vertex colours: a value outside [0, 1], NaN or infinite is refused
        (``ValueError``), never clamped.
    normals : (N, 3) float64, or None
        Per-vertex normals (object space).
    texcoords : (N, 2) float64, or None
    face_colors : (M, 3) float32 in [0, 1], or None
        Per-face colours (for example the ``Kd`` of the face's material); refused as
        ``vertex_colors`` are when not finite or outside [0, 1].
    face_groups : (M,) int32, or None
        Index into ``group_names`` for each face.
    group_names : tuple of str
    material_names : tuple of str
    warnings : tuple of str
        What the loader noticed but accepted.

    The arrays are immutable (read-only views of ``bytes``); the Mesh shares them with no
    array it was made from, except another Mesh's (immutable too).
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
        edges = None if self.edges is None else _indices(self.edges, n, 2, "edges")
        n_edges = 3 * len(f) + len(lines) if edges is None else len(edges)
        check_memory(mesh_bytes(n, len(f), len(lines) + n_edges), f"a Mesh of {n} vertices and {len(f)} faces")
        if edges is None:
            edges = unique_edges(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]], lines]), n)
        arrays = {"vertices": v, "faces": f, "lines": lines, "edges": edges}
        optional = {
            "vertex_colors": (np.float32, (3,), n),
            "normals": (np.float64, (3,), n),
            "texcoords": (np.float64, (2,), n),
            "face_colors": (np.float32, (3,), len(f)),
        }
        for name, (dtype, tail, rows) in optional.items():
            value = getattr(self, name)
            if value is not None:
                arrays[name] = _array(value, dtype, tail, name, rows)
        for name in ("vertex_colors", "face_colors"):
            if name in arrays:
                _check_unit_colors(arrays[name], name)
        if self.face_groups is not None:
            g = _groups(self.face_groups, len(f), len(self.group_names))
            arrays["face_groups"] = g
        # Each array the Mesh's own and immutable; what check_intact compares them with.
        set_ = object.__setattr__
        record = {}
        for name, arr in arrays.items():
            arr = seal(arr)
            set_(self, name, arr)
            record[name] = (arr, arr.shape, arr.dtype)
        set_(self, "_arrays", record)
        set_(self, "group_names", tuple(self.group_names))
        set_(self, "material_names", tuple(self.material_names))
        set_(self, "warnings", tuple(self.warnings))

    def check_intact(self) -> "Mesh":
        """Raise ``ValueError`` unless every array of the Mesh is still the one it was made
        with, with its shape, dtype and layout; returns the Mesh.

        The arrays' contents cannot change (they are immutable), but NumPy lets anyone set
        an array's ``shape``, ``dtype`` or ``strides`` in place, and an attribute of the
        frozen dataclass can be replaced with ``object.__setattr__``: kernels reading such
        an array would read outside it. A few attribute reads: the renderer calls it on
        every draw.
        """
        for name, (arr, shape, dtype) in self._arrays.items():
            now = getattr(self, name)
            if now is not arr or now.shape != shape or now.dtype != dtype or not now.flags.c_contiguous:
                raise ValueError(f"Mesh.{name} was changed after the Mesh was made (a Mesh's arrays are fixed: "
                                 f"make a new Mesh, e.g. with dataclasses.replace)")
        return self

    def __reduce__(self):
        """Pickled and copied through the constructor: the copy checks and seals its own
        arrays (a plain copy of the instance's state would hold writeable ones)."""
        return (Mesh, tuple(getattr(self, f.name) for f in fields(self)))

    @cached_property
    def _feature_sides(self) -> tuple:
        """The camera-independent part of the feature edges (:func:`rasterkit.raster.features.sides`:
        the face sides sorted into edges, their dihedral angles and material changes), worked
        out on first use and kept: a turntable or an animation of ``edges="feature"`` sorts
        the 3M face sides once, not once a frame."""
        from rasterkit.raster.features import sides
        self.check_intact()
        return sides(self)

    @cached_property
    def spatial_edges(self) -> np.ndarray:
        """The edges in a spatial order (:func:`rasterkit.raster.edge_pass.spatial_edges`), in which
        the plain wireframe draws them (the same pixels); worked out on first use and kept."""
        from rasterkit.raster.edge_pass import spatial_edges
        self.check_intact()
        return spatial_edges(self.vertices, self.edges)

    @cached_property
    def side_neighbours(self) -> np.ndarray:
        """:func:`side_neighbours` of the faces, worked out on first use and kept (a
        multi-sample render finds the sides on the outline with them)."""
        self.check_intact()
        return seal(side_neighbours(self.faces, len(self.vertices)))

    @cached_property
    def face_normals(self) -> np.ndarray:
        """(M, 3) float32, immutable: unit face normals (right-hand rule: counter-clockwise
        seen from the front points out), zero for a degenerate face, NaN for a face with a
        non-finite corner. Worked out on first use and kept: flat shading needs them in every
        frame, and they do not depend on the camera."""
        from rasterkit.raster.normals import face_normals
        self.check_intact()
        return seal(face_normals(self.vertices, self.faces))

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float64: minimum and maximum corner of the finite vertices' bounding box."""
        finite = self.vertices[np.all(np.isfinite(self.vertices), axis=1)]
        if len(finite) == 0:
            return np.zeros((2, 3))
        return np.stack([finite.min(axis=0), finite.max(axis=0)])

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """Centre (3,) and radius of a sphere holding every finite vertex (box centre based).

        A mesh without vertices gives the origin and radius 0. Raises ``ValueError`` when
        every vertex is NaN or infinite, or when the radius is beyond float64 (coordinates
        near 1e308 of both signs)."""
        finite = self.vertices[np.all(np.isfinite(self.vertices), axis=1)]
        if len(finite) == 0:
            if len(self.vertices):
                raise ValueError(f"all {len(self.vertices)} vertices are NaN or infinite: the model has no extent")
            return np.zeros(3), 0.0
        lo, hi = finite.min(axis=0), finite.max(axis=0)
        centre = lo / 2.0 + hi / 2.0  # (lo + hi) / 2 to the bit, without overflowing
        offsets = finite - centre
        with np.errstate(over="ignore", under="ignore"):
            radius = float(np.linalg.norm(offsets, axis=1).max())
            if not 0.0 < radius < np.inf and np.any(offsets):
                # squares overflowed or underflowed: the same length, in units of the largest offset
                largest = float(np.abs(offsets).max())
                radius = largest * float(np.linalg.norm(offsets / largest, axis=1).max())
        if not np.isfinite(radius):
            raise ValueError(f"the model's extent overflows float64 (coordinates from {lo.min():.3g} "
                             f"to {hi.max():.3g}): scale it down")
        return centre, radius

    def __repr__(self) -> str:
        return (f"Mesh({len(self.vertices)} vertices, {len(self.faces)} faces, "
                f"{len(self.edges)} edges, {len(self.lines)} lines)")


def _groups(value, n_faces, n_groups) -> np.ndarray:
    g = np.asarray(value)
    if g.dtype.kind not in "iu" and not (g.size == 0 and g.dtype.kind == "f"):
        raise TypeError(f"face_groups must hold integers, got dtype {g.dtype}")
    if g.shape != (n_faces,) or (len(g) and (g.min() < 0 or g.max() >= n_groups)):
        raise ValueError("face_groups must be (M,) indices into group_names")
    return np.ascontiguousarray(g, dtype=np.int32)


def as_mesh(mesh) -> Mesh:
    """A :class:`Mesh` from a Mesh, a ``(vertices, faces)`` pair or an object with
    ``.vertices`` and ``.faces`` (a trimesh mesh, for example). A Mesh is checked with
    :meth:`Mesh.check_intact`."""
    if isinstance(mesh, Mesh):
        return mesh.check_intact()
    if isinstance(mesh, tuple) and len(mesh) == 2:
        return Mesh(*mesh)
    if hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        return Mesh(mesh.vertices, mesh.faces)
    raise TypeError("mesh must be a rasterkit.Mesh, a (vertices, faces) tuple, "
                    "or an object with .vertices and .faces")
