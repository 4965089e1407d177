"""Mesh: validated, C-contiguous arrays of one polygonal model.

A Mesh never holds an index out of range, a face with repeated shape errors or arrays of the
wrong dtype: the constructor checks everything once (:mod:`rasterkit.mesh.checks`), so the
kernels can trust its arrays. They are the Mesh's own and immutable: read-only views of
``bytes`` objects the Mesh made (an array passed in is copied), which NumPy cannot make
writeable again nor resize, so what was checked stays true, and what is worked out from them
once (:attr:`Mesh.face_normals`) stays valid. What NumPy still lets anyone change in place,
an array's ``shape``, ``dtype`` and ``strides``, or an attribute replaced behind the frozen
dataclass's back, is caught by :meth:`Mesh.check_intact` (a few attribute reads), which the
renderer calls before any kernel runs. To move a mesh, make a new one
(``dataclasses.replace(mesh, vertices=...)`` keeps its edges and every attribute).

The package: the Mesh (here), the checks of its arrays (``checks``), edges of polygons and
the faces across each side (``edges``, sorted by the kernels in ``kernels``), and the
attributes of meshes from other libraries (``foreign``: trimesh's texture coordinates,
materials and colours).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from rasterkit._arrays import finite_bounds
from rasterkit.limits import check_memory
from rasterkit.mesh.checks import (
    check_unit_colors, checked_array, corner_attributes, face_labels, immutable, seal, side_flags, vertex_indices,
)
from rasterkit.mesh.edges import ALL_SIDES, polygon_edges, polygon_mesh_edges, side_neighbours, unique_edges
from rasterkit.mesh.kernels import repeated_corners, sorted_edges
from rasterkit.mesh.foreign import visual_fields

__all__ = ["Mesh", "as_mesh", "immutable", "mesh_bytes", "polygon_edges", "polygon_mesh_edges", "repeated_corners",
           "seal", "side_neighbours", "unique_edges"]


def mesh_bytes(n_vertices: int, n_faces: int, n_edges: int, n_uv: int = 0, n_corner_normals: int = 0,
               corner_indices: int = 0) -> int:
    """Bytes that making a Mesh needs, at most: per vertex its positions, colours, normals
    and texture coordinates, checked and then copied; per face its indices, colour, group
    and material; per edge given its pair, checked and copied (edges worked out later are
    checked then); the rows of the ``uv`` and
    ``corner_normals`` tables (``n_uv``, ``n_corner_normals``), checked and copied; and per
    face each of its ``corner_indices`` (M, 3) index arrays (``uv_index``, ``normal_index``:
    0 to 2), checked (with the temporaries of the check) and copied. For
    :func:`rasterkit.limits.check_memory`."""
    return (n_vertices * 2 * (24 + 12 + 24 + 16) + n_faces * 2 * (24 + 12 + 4 + 4 + 1)
            + n_edges * 2 * 16 + n_uv * 2 * 16 + n_corner_normals * 2 * 24 + corner_indices * n_faces * (2 * 24 + 32))


class _Edges:
    """The ``edges`` field of a Mesh: the array it was given, or, when it was given None, the
    sides of its faces and its lines, worked out on first use (:func:`sorted_edges`) and
    kept. Loading and solid renders never need them; the line modes do."""

    def __get__(self, mesh, owner=None):
        if mesh is None:
            return None  # the field's default
        edges = mesh.__dict__.get("edges")
        if edges is None:  # made without edges (``__set__`` noted it)
            faces, lines = mesh.faces, mesh.lines
            check_memory(24 * (3 * len(faces) + len(lines)) + 24 * len(mesh.vertices),
                         f"the edges of a Mesh of {len(faces)} faces")
            sides = ALL_SIDES if mesh.polygon_sides is None else mesh.polygon_sides
            edges = seal(sorted_edges(faces, sides, lines, len(mesh.vertices)))
            mesh.__dict__["edges"] = edges
            mesh._arrays["edges"] = (edges, edges.shape, edges.dtype)
        return edges

    def __set__(self, mesh, value):
        mesh.__dict__["edges"] = value
        mesh.__dict__["_derived_edges"] = value is None


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
        diagonal of its triangulation) and of ``lines``, each ``(lo, hi)`` with lo < hi, sorted.
        When omitted (None), the sides of ``faces`` (those ``polygon_sides`` flags) and
        ``lines``, worked out on first use.
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
        The names of the materials (OBJ ``usemtl``), each once.
    warnings : tuple of str
        What the loader noticed but accepted.
    uv : (U, 2) float64, or None
        A table of texture coordinates (u, v), read through ``uv_index``; v = 0 is the
        bottom row of a texture image, as in OBJ and OpenGL. Any float is kept, NaN and
        infinities too: a texture lookup wraps or clamps every value into the image.
    uv_index : (M, 3) int64, or None
        For each face corner (``faces[f, c]``), its row of ``uv``; a face without texture
        coordinates is ``-1, -1, -1`` (a face has them at all three corners or at none).
        Corners of one vertex may have different rows: a UV seam keeps both sides. When
        ``uv`` is given without ``uv_index`` it must have one row per vertex (N, as glTF and
        trimesh give texture coordinates), and ``uv_index`` is ``faces`` (so
        ``dataclasses.replace(mesh, faces=...)`` keeps the old corners' rows: pass
        ``uv_index=None`` with new faces of per-vertex ``uv``).
    corner_normals : (C, 3) float64, finite, or None
        A table of normals (object space), read through ``normal_index``: where the corners
        of a vertex have different normals (an authored hard edge) each face keeps its own.
        Not necessarily of unit length (``load_obj`` gives unit vectors, and zero where the
        file's normal is zero or not finite); shading normalises after interpolating.
    normal_index : (M, 3) int64, or None
        For each face corner its row of ``corner_normals``, as ``uv_index`` is for ``uv``
        (``-1, -1, -1``: none; ``corner_normals`` without ``normal_index``: one per vertex).
    face_materials : (M,) int32, or None
        For each face, its index into ``material_names`` (and ``materials``), -1 for none.
    materials : tuple
        Empty, or one material for each of ``material_names``, in that order: the readers
        and :func:`as_mesh` give :class:`rasterkit.Material` records (``load_obj`` with
        ``textures=True``, trimesh meshes with ``TextureVisuals``).
    polygon_sides : (M,) uint8 in 0..7, or None
        For faces cut from polygons (the readers give it): bit k of ``polygon_sides[f]`` is
        set when side k of face f (corner k to corner k + 1, mod 3) is a side of its polygon,
        clear for a diagonal of the polygon's triangulation (OpenGL's edge flags). The
        edges worked out when ``edges`` is omitted are the flagged sides. None: every side.

    ``normals`` and ``texcoords`` are one per vertex (an OBJ file's averaged over each
    vertex's corners, and the first corner's); ``corner_normals`` and ``uv`` keep every
    corner's own. The arrays are immutable (read-only views of ``bytes``); the Mesh shares
    them with no array it was made from, except another Mesh's (immutable too), and
    ``uv_index`` or ``normal_index`` may be the very array ``faces`` is.
    """

    vertices: np.ndarray
    faces: np.ndarray
    edges: np.ndarray | None = _Edges()
    lines: np.ndarray | None = None
    vertex_colors: np.ndarray | None = None
    normals: np.ndarray | None = None
    texcoords: np.ndarray | None = None
    face_colors: np.ndarray | None = None
    face_groups: np.ndarray | None = None
    group_names: tuple = ()
    material_names: tuple = ()
    warnings: tuple = field(default=())
    uv: np.ndarray | None = None
    uv_index: np.ndarray | None = None
    corner_normals: np.ndarray | None = None
    normal_index: np.ndarray | None = None
    face_materials: np.ndarray | None = None
    materials: tuple = ()
    polygon_sides: np.ndarray | None = None

    def __post_init__(self):
        v = checked_array(self.vertices, np.float64, (3,), "vertices")
        n = len(v)
        f = vertex_indices(self.faces, n, 3, "faces")
        lines = vertex_indices(self.lines if self.lines is not None else (), n, 2, "lines")
        given = self.__dict__.get("edges")
        edges = None if given is None else vertex_indices(given, n, 2, "edges")
        indexed = sum(i is not None for i in (self.uv_index, self.normal_index))
        check_memory(mesh_bytes(n, len(f), len(lines) + (0 if edges is None else len(edges)), _rows(self.uv),
                                _rows(self.corner_normals), indexed),
                     f"a Mesh of {n} vertices and {len(f)} faces")
        arrays = {"vertices": v, "faces": f, "lines": lines}
        if edges is not None:
            arrays["edges"] = edges
        optional = {
            "vertex_colors": (np.float32, (3,), n),
            "normals": (np.float64, (3,), n),
            "texcoords": (np.float64, (2,), n),
            "face_colors": (np.float32, (3,), len(f)),
        }
        for name, (dtype, tail, rows) in optional.items():
            value = getattr(self, name)
            if value is not None:
                arrays[name] = checked_array(value, dtype, tail, name, rows)
        for name in ("vertex_colors", "face_colors"):
            if name in arrays:
                check_unit_colors(arrays[name], name)
        if self.face_groups is not None:
            arrays["face_groups"] = face_labels(self.face_groups, len(f), len(self.group_names), "face_groups",
                                                "group_names", none=False)
        arrays.update(corner_attributes(self.uv, self.uv_index, self.corner_normals, self.normal_index, f, n))
        names = tuple(self.material_names)
        if self.polygon_sides is not None:
            arrays["polygon_sides"] = side_flags(self.polygon_sides, len(f))
        if self.face_materials is not None:
            arrays["face_materials"] = face_labels(self.face_materials, len(f), len(names), "face_materials",
                                                   "material_names", none=True)
        materials = () if self.materials is None else tuple(self.materials)
        if materials and len(materials) != len(names):
            raise ValueError(f"materials must be empty or one for each of material_names ({len(names)}), "
                             f"got {len(materials)}")
        self._seal(arrays)
        set_ = object.__setattr__
        set_(self, "group_names", tuple(self.group_names))
        set_(self, "material_names", names)
        set_(self, "warnings", tuple(self.warnings))
        set_(self, "materials", materials)

    def _seal(self, arrays: dict) -> None:
        """Make each array the Mesh's own and immutable (an array under two names, such as
        ``faces`` and a per-vertex ``uv_index``, stays one), and note what
        :meth:`check_intact` compares them with."""
        set_ = object.__setattr__
        record, sealed = {}, {}
        for name, arr in arrays.items():
            if id(arr) not in sealed:
                sealed[id(arr)] = seal(arr)
            arr = sealed[id(arr)]
            set_(self, name, arr)
            record[name] = (arr, arr.shape, arr.dtype)
        set_(self, "_arrays", record)

    @property
    def derives_edges(self) -> bool:
        """Whether :attr:`edges` are the sides of ``faces`` and ``lines`` (the Mesh was made
        without edges, and works them out on first use), rather than edges it was given."""
        return self.__dict__.get("_derived_edges", False)

    @property
    def nbytes(self) -> int:
        """Bytes of the arrays the Mesh was made with and of its :attr:`edges` once worked
        out (an array under two names counted once), not of what it works out later for
        drawing (:attr:`face_normals`, ...)."""
        return sum({id(arr): arr.nbytes for arr, _, _ in self._arrays.values()}.values())

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
        return (Mesh, tuple(self.__dict__.get(f.name) for f in fields(self)))

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

    @cached_property
    def textured(self):
        """Which faces are drawn textured, with which texture, tint and texture coordinates
        (:func:`rasterkit.raster.texturing.mesh_textures`), or None when none is; worked out
        on first use and kept: a turntable looks its textures up once."""
        from rasterkit.raster.texturing import mesh_textures
        self.check_intact()
        return mesh_textures(self)

    @cached_property
    def smooth_corners(self) -> tuple:
        """``(normals, corners, split)``: the unit normals smooth shading interpolates, each
        face corner's row of them and whether a vertex has corners with different normals
        (:func:`rasterkit.raster.normals.smooth_corners`: the corners' own normals where
        the mesh has them, so that an authored hard edge stays hard); worked out on first
        use and kept."""
        from rasterkit.raster.normals import smooth_corners
        self.check_intact()
        return smooth_corners(self)

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float64: minimum and maximum corner of the finite vertices' bounding box."""
        bounds = finite_bounds(self.vertices)
        return np.zeros((2, 3)) if bounds is None else np.stack(bounds)

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
        edges = self.__dict__.get("edges")  # not worked out for a repr
        return (f"Mesh({len(self.vertices)} vertices, {len(self.faces)} faces, "
                + ("" if edges is None else f"{len(edges)} edges, ") + f"{len(self.lines)} lines)")


def _rows(value) -> int:
    """Rows of an array argument, for the memory estimate (0 for None or a scalar: its check
    refuses it later)."""
    try:
        return 0 if value is None else len(value)
    except TypeError:
        return 0


def as_mesh(mesh) -> Mesh:
    """A :class:`Mesh` from a Mesh, a ``(vertices, faces)`` pair or an object with
    ``.vertices`` and ``.faces``. A Mesh is checked with :meth:`Mesh.check_intact`.

    A trimesh mesh brings what its ``visual`` holds (:func:`rasterkit.mesh.foreign.visual_fields`):
    ``TextureVisuals`` their per-vertex ``uv`` (``uv_index`` is then ``faces``; v up, as
    rasterkit's) and their material as a :class:`rasterkit.Material` that every face uses
    (``materials[0]``; the image, or ``baseColorTexture``, as its ``diffuse_map``);
    ``ColorVisuals`` their vertex or face colours (RGB; alpha is dropped)."""
    if isinstance(mesh, Mesh):
        return mesh.check_intact()
    if isinstance(mesh, tuple) and len(mesh) == 2:
        return Mesh(*mesh)
    if hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        return Mesh(mesh.vertices, mesh.faces, **visual_fields(mesh))
    raise TypeError("mesh must be a rasterkit.Mesh, a (vertices, faces) tuple, "
                    "or an object with .vertices and .faces")
