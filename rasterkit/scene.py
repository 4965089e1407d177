"""Scene: meshes placed in the world by model matrices, a camera, a light and a background.

No kernels here: :func:`rasterkit.render` turns a scene into one world-space mesh with
:meth:`Scene.world_mesh` and draws it through the same pipeline as a single mesh.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from rasterkit.camera import Camera
from rasterkit.colors import ColorLike, parse_color
from rasterkit._arrays import real_array
from rasterkit.limits import check_memory
from rasterkit.material import Material
from rasterkit.mesh import Mesh, as_mesh, mesh_bytes
from rasterkit.transform import apply_normals, apply_points

__all__ = ["Scene", "SceneObject"]


@dataclass(frozen=True)
class SceneObject:
    """One mesh in a scene: its model matrix (object -> world) and optional colour."""

    mesh: Mesh
    matrix: np.ndarray
    color: np.ndarray | None = None


@dataclass
class Scene:
    """Meshes with their own model matrices and colours, a camera, a light, a background.

    Parameters
    ----------
    camera : Camera, optional
        Used by ``render(scene)`` unless a camera is passed there.
    light : (3,) float, optional
        World-space direction *towards* a distant light. None is a headlight (the light
        shines along the viewing direction).
    background : colour
        Background of ``render(scene)`` unless one is passed there.
    lights : list of rasterkit.Light
        The scene's lights (:meth:`add_light`), used by ``render(scene)`` unless lights are
        passed there; none: the classic headlight (or ``light``).

    Examples
    --------
    >>> from rasterkit import Scene, shapes, transform
    >>> scene = Scene().add(shapes.cube(), transform.translate(-1, 0, 0), color="red")
    >>> scene = scene.add(shapes.icosphere(1), transform.translate(1, 0, 0))
    >>> len(scene.objects), len(scene.world_mesh().faces)
    (2, 92)
    """

    camera: Camera | None = None
    light: Sequence[float] | None = None
    background: ColorLike = "white"
    objects: list[SceneObject] = field(default_factory=list)
    lights: list = field(default_factory=list)

    def add(self, mesh: Mesh, matrix: np.ndarray | None = None,
            color: ColorLike | None = None) -> "Scene":
        """Place ``mesh`` in the world by ``matrix`` (4x4, default identity); returns self."""
        m = np.eye(4) if matrix is None else _model_matrix(matrix)
        rgb = None if color is None else parse_color(color)[:3].astype(np.float32) / 255.0
        self.objects.append(SceneObject(as_mesh(mesh), m, rgb))
        return self

    def add_light(self, light) -> "Scene":
        """Add a :class:`rasterkit.Light` to the scene's lights; returns self."""
        from rasterkit.raster.lights import check_lights

        self.lights.extend(check_lights("light", [light]))
        return self

    def world_mesh(self, default_color: ColorLike = "lightgray") -> Mesh:
        """All objects in world space as one mesh.

        Faces carry colours when any object has a colour of its own (``color``, face colours,
        or vertex colours averaged over each face); faces without one get ``default_color``.
        Vertex colours survive only when every object has them and none has a ``color``.

        The per-corner tables are joined, each object's indices offset into them: ``uv``
        as they are, ``corner_normals`` in world space (the inverse transpose of the linear
        part of the object's model matrix, normalised; zero rows stay zero). The faces of
        an object without a table, or whose matrix cannot carry normals (a singular linear
        part), get ``-1, -1, -1``; a table is None when no object has one. The materials
        are one table too (``material_names``, ``materials``), each object's
        ``face_materials`` offset into it (-1 stays -1; an object without them: -1). A name
        may appear more than once (objects whose materials share a name stay apart).
        ``materials`` is empty when no object has any; otherwise an object that names
        materials without having them gets a default :class:`~rasterkit.Material` of each
        name (as ``load_obj`` gives a material no library defines).
        """
        if not self.objects:
            raise ValueError("the scene is empty: add a mesh first")
        for o in self.objects:  # Scene.objects is a plain list: what was appended to it is checked here
            if not isinstance(o, SceneObject):
                raise TypeError(f"Scene.objects must hold SceneObjects (use Scene.add), got {type(o).__name__}")
            as_mesh(o.mesh)
            _model_matrix(o.matrix)
        n = sum(len(o.mesh.vertices) for o in self.objects)
        m = sum(len(o.mesh.faces) for o in self.objects)
        # objects of triangles alone (no edges given, no lines): the world Mesh works out their sides itself
        derived = all(o.mesh.derives_edges and not len(o.mesh.lines) for o in self.objects)
        e = 0 if derived else sum(len(o.mesh.edges) for o in self.objects)
        n_uv = sum(_rows(o.mesh.uv) for o in self.objects)
        n_normals = sum(_rows(o.mesh.corner_normals) for o in self.objects)
        indexed = (n_uv > 0) + (n_normals > 0)
        # world-space copies (and their homogeneous temporaries), the joined corner tables (the
        # normals' scaled and transformed temporaries), then the Mesh made of them
        check_memory(n * (24 * 4 + 32 + 12 + 16) + m * (24 + 12 + 8) + e * 16 + n_uv * 16 + n_normals * 24 * 5
                     + indexed * m * 48 + mesh_bytes(n, m, e, n_uv, n_normals, indexed),
                     f"the world mesh of a scene of {len(self.objects)} objects ({n} vertices, {m} faces)")
        offsets = np.cumsum([0] + [len(o.mesh.vertices) for o in self.objects])
        vertices = np.concatenate([apply_points(o.matrix, o.mesh.vertices) for o in self.objects])
        faces = np.concatenate([o.mesh.faces + k for o, k in zip(self.objects, offsets)])
        edges = None if derived else np.concatenate([o.mesh.edges + k for o, k in zip(self.objects, offsets)])
        sides = None  # worked out edges: the sides each object's own flags keep
        if derived and any(o.mesh.polygon_sides is not None for o in self.objects):
            sides = np.concatenate([np.full(len(o.mesh.faces), 7, np.uint8) if o.mesh.polygon_sides is None
                                    else o.mesh.polygon_sides for o in self.objects])
        vertex_colors = self._vertex_colors()
        face_colors = None if vertex_colors is not None else \
            self._face_colors(parse_color(default_color)[:3] / 255.0)
        uv, uv_index = self._join_corners([None if o.mesh.uv is None else (o.mesh.uv, o.mesh.uv_index)
                                           for o in self.objects])
        corner_normals, normal_index = self._join_corners([_world_corner_normals(o) for o in self.objects])
        names, face_materials, materials = self._materials()
        return Mesh(vertices, faces, edges=edges, normals=self._normals(), texcoords=self._texcoords(),
                    vertex_colors=vertex_colors, face_colors=face_colors, uv=uv, uv_index=uv_index,
                    corner_normals=corner_normals, normal_index=normal_index, material_names=names,
                    face_materials=face_materials, materials=materials, polygon_sides=sides)

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """Centre and radius of a sphere holding every object's world-space vertices."""
        return self.world_mesh().bounding_sphere()

    def _normals(self):
        """The objects' normals in world space, when every object has normals and a model
        matrix whose linear part can be inverted (normals need its inverse transpose)."""
        if all(o.mesh.normals is not None and _invertible(o.matrix) for o in self.objects):
            return np.concatenate([apply_normals(o.matrix, o.mesh.normals) for o in self.objects])
        return None

    def _join_corners(self, tables: list):
        """``(table, index)`` of one table of per-corner rows from each object's
        ``(table, index)`` (None: its faces get -1), or ``(None, None)`` when no object has
        one."""
        if all(t is None for t in tables):
            return None, None
        rows, indices, start = [], [], 0
        for o, t in zip(self.objects, tables):
            if t is None:
                indices.append(np.full((len(o.mesh.faces), 3), -1, np.int64))
                continue
            rows.append(t[0])
            indices.append(np.where(t[1] >= 0, t[1] + start, -1))
            start += len(t[0])
        return np.concatenate(rows), np.concatenate(indices)

    def _materials(self):
        """``(material_names, face_materials, materials)`` of the objects in one table (see
        :meth:`world_mesh`)."""
        names, labels, materials = [], [], []
        whole = any(o.mesh.materials for o in self.objects)
        for o in self.objects:
            mesh = o.mesh
            if mesh.face_materials is None:
                labels.append(np.full(len(mesh.faces), -1, np.int32))
            else:
                labels.append(np.where(mesh.face_materials >= 0, mesh.face_materials + len(names), -1).astype(np.int32))
            if whole:
                materials.extend(mesh.materials or [Material(name) for name in mesh.material_names])
            names.extend(mesh.material_names)
        labelled = any(o.mesh.face_materials is not None for o in self.objects)
        return tuple(names), np.concatenate(labels) if labelled else None, tuple(materials)

    def _texcoords(self):
        """The objects' texture coordinates, when every object has them."""
        if all(o.mesh.texcoords is not None for o in self.objects):
            return np.concatenate([o.mesh.texcoords for o in self.objects])
        return None

    def _vertex_colors(self):
        if all(o.mesh.vertex_colors is not None and o.color is None for o in self.objects):
            return np.concatenate([o.mesh.vertex_colors for o in self.objects])
        return None

    def _face_colors(self, default_rgb: np.ndarray):
        own = [_own_face_colors(o) for o in self.objects]
        if all(c is None for c in own):
            return None
        return np.concatenate([
            c if c is not None else np.tile(default_rgb, (len(o.mesh.faces), 1))
            for c, o in zip(own, self.objects)
        ]).astype(np.float32)


def _model_matrix(matrix) -> np.ndarray:
    """A model matrix checked: a finite, affine 4x4 array of real numbers (a new array)."""
    m = np.array(real_array(matrix, "a model matrix"), dtype=np.float64)
    if m.shape != (4, 4) or not np.all(np.isfinite(m)):
        raise ValueError(f"a model matrix must be a finite 4x4 array, got shape {m.shape}")
    if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise ValueError("a model matrix must be affine (last row 0, 0, 0, 1)")
    return m


def _invertible(matrix: np.ndarray) -> bool:
    """Whether the linear part of ``matrix`` has an inverse that is finite in float64."""
    with np.errstate(all="ignore"):
        try:
            return bool(np.all(np.isfinite(np.linalg.inv(matrix[:3, :3]))))
        except np.linalg.LinAlgError:
            return False


def _world_corner_normals(obj: SceneObject):
    """``(corner_normals, normal_index)`` of an object in world space, or None when it has
    none or its model matrix cannot carry normals (a singular linear part, or rows beyond
    float64 on the way)."""
    mesh = obj.mesh
    if mesh.corner_normals is None or not _invertible(obj.matrix):
        return None
    # each row scaled by a power of two (exact) to at most 1 first: only its direction counts
    _, exponent = np.frexp(np.abs(mesh.corner_normals).max(axis=1, keepdims=True))
    world = apply_normals(obj.matrix, np.ldexp(mesh.corner_normals, -exponent))
    return (world, mesh.normal_index) if np.isfinite(world).all() else None


def _rows(table) -> int:
    return 0 if table is None else len(table)


def _own_face_colors(obj: SceneObject) -> np.ndarray | None:
    """(M, 3) colours 0..1 an object brings itself, or None."""
    mesh = obj.mesh
    if obj.color is not None:
        return np.tile(obj.color, (len(mesh.faces), 1))
    if mesh.face_colors is not None:
        return mesh.face_colors
    if mesh.vertex_colors is not None:
        return mesh.vertex_colors[mesh.faces].mean(axis=1)
    return None
