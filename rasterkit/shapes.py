"""Meshes made in code: the built-in demo models and geometry for tests.

Every shape is centred on the origin, its faces wind counter-clockwise seen from outside
(right-handed), and its ``edges`` are those of its polygons (a cube shows 12 edges, not the
diagonals of its triangulated quads).
"""

from __future__ import annotations

import numpy as np

from rasterkit._arrays import real_number
from rasterkit.limits import check_memory
from rasterkit.mesh import Mesh, mesh_bytes, polygon_edges

__all__ = ["cube", "tetrahedron", "octahedron", "icosahedron", "icosphere", "torus", "grid", "demo"]


def _count(value, name: str) -> int:
    """A whole number of rings, sides, cells or subdivisions (bools, floats and strings are
    refused with ``TypeError``)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    return int(value)


def _check_quads(n_vertices: int, n_quads: int, what: str) -> None:
    """Refuse a shape of quads whose arrays would not fit in memory: the grids of
    coordinates and indices (about 200 bytes a vertex), the polygon lists (about 400
    bytes a quad, Python objects) and the Mesh made of them."""
    check_memory(n_vertices * 200 + n_quads * 400 + mesh_bytes(n_vertices, 2 * n_quads, 4 * n_quads), what)


def _from_polygons(vertices, polygons) -> Mesh:
    """Mesh of convex polygons: fan triangulation, polygon edges."""
    triangles = [(p[0], p[i], p[i + 1]) for p in polygons for i in range(1, len(p) - 1)]
    return Mesh(np.asarray(vertices, np.float64), np.asarray(triangles, np.int64).reshape(-1, 3),
                edges=polygon_edges(polygons))


def cube(size: float = 1.0) -> Mesh:
    """Axis-aligned cube with edge length ``size``: 8 vertices, 6 quads (12 triangles), 12 edges."""
    h = real_number(size, "size") / 2.0
    v = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]  # index = 4x + 2y + z
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return _from_polygons(v, quads)


def tetrahedron(radius: float = 1.0) -> Mesh:
    """Regular tetrahedron inscribed in a sphere of ``radius``."""
    v = np.array([(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)], np.float64)
    v *= real_number(radius, "radius") / np.sqrt(3.0)
    return _from_polygons(v, [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)])


def octahedron(radius: float = 1.0) -> Mesh:
    """Regular octahedron with vertices on the axes at distance ``radius``."""
    v = real_number(radius, "radius") * np.array([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)],
                          np.float64)
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return _from_polygons(v, faces)


def _icosahedron_arrays():
    """The vertices (12, 3) of a regular icosahedron (at distance ``|v[0]|`` from its centre)
    and its faces (20, 3), as a list of index triples."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    v = np.array([(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                  (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)],
                 np.float64)
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return v, faces


def icosahedron(radius: float = 1.0) -> Mesh:
    """Regular icosahedron inscribed in a sphere of ``radius``: 12 vertices, 20 faces."""
    v, faces = _icosahedron_arrays()
    v *= real_number(radius, "radius") / np.linalg.norm(v[0])
    return _from_polygons(v, faces)


def icosphere(subdivisions: int = 2, radius: float = 1.0) -> Mesh:
    """Sphere made by splitting each icosahedron triangle into four, ``subdivisions`` times.

    Vertices: ``10 * 4**subdivisions + 2``; faces: ``20 * 4**subdivisions``.
    """
    if not 0 <= _count(subdivisions, "subdivisions") <= 7:
        raise ValueError(f"subdivisions must be between 0 and 7, got {subdivisions}")
    vertices, faces = _icosahedron_arrays()  # (no Mesh: its polygon edges would go unused)
    vertices *= 1.0 / np.linalg.norm(vertices[0])
    faces = np.asarray(faces, np.int64)
    for _ in range(int(subdivisions)):
        vertices, faces = _subdivide(vertices, faces)
    vertices = real_number(radius, "radius") * vertices / np.linalg.norm(vertices, axis=1, keepdims=True)
    return Mesh(vertices, faces)


def _subdivide(vertices: np.ndarray, faces: np.ndarray):
    """Split every triangle into four through its edge midpoints (shared midpoints once)."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(vertices) + inverse.reshape(3, -1).T  # (M, 3): midpoints of edges 01, 12, 20
    new_vertices = np.concatenate([vertices, vertices[unique].mean(axis=1)])
    a, b, c = faces.T
    ab, bc, ca = mid.T
    new_faces = np.concatenate([np.stack(t, axis=1) for t in
                                ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))])
    return new_vertices, new_faces


def torus(major: float = 1.0, minor: float = 0.35, rings: int = 32, sides: int = 16) -> Mesh:
    """Torus around the y axis: ``rings`` quads around, ``sides`` quads across the tube."""
    rings, sides = _count(rings, "rings"), _count(sides, "sides")
    major, minor = real_number(major, "major"), real_number(minor, "minor")
    if rings < 3 or sides < 3 or not 0 < minor < major < np.inf:
        raise ValueError("torus needs rings >= 3, sides >= 3 and 0 < minor < major (finite)")
    _check_quads(rings * sides, rings * sides, f"a torus of {rings}x{sides} quads")
    u = 2 * np.pi * np.arange(rings) / rings
    v = 2 * np.pi * np.arange(sides) / sides
    uu, vv = np.meshgrid(u, v, indexing="ij")
    r = major + minor * np.cos(vv)
    vertices = np.stack([r * np.cos(uu), minor * np.sin(vv), -r * np.sin(uu)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(rings), np.arange(sides), indexing="ij")
    i1, j1 = (i + 1) % rings, (j + 1) % sides
    quads = np.stack([i * sides + j, i1 * sides + j, i1 * sides + j1, i * sides + j1],
                     axis=-1).reshape(-1, 4)
    return _from_polygons(vertices, quads)


def grid(nx: int = 10, nz: int = 10, size: float = 2.0) -> Mesh:
    """Flat square grid in the xz plane facing +y: ``nx`` by ``nz`` quads."""
    nx, nz = _count(nx, "nx"), _count(nz, "nz")
    size = real_number(size, "size")
    if nx < 1 or nz < 1:
        raise ValueError("grid needs nx >= 1 and nz >= 1")
    _check_quads((nx + 1) * (nz + 1), nx * nz, f"a grid of {nx}x{nz} quads")
    xs = np.linspace(-size / 2, size / 2, nx + 1)
    zs = np.linspace(-size / 2, size / 2, nz + 1)
    xx, zz = np.meshgrid(xs, zs, indexing="ij")
    vertices = np.stack([xx, np.zeros_like(xx), zz], axis=-1).reshape(-1, 3)
    i, k = np.meshgrid(np.arange(nx), np.arange(nz), indexing="ij")
    n = nz + 1
    quads = np.stack([i * n + k, i * n + k + 1, (i + 1) * n + k + 1, (i + 1) * n + k],
                     axis=-1).reshape(-1, 4)
    return _from_polygons(vertices, quads)


def demo() -> Mesh:
    """The built-in demo model (``rasterkit render --demo``): a torus."""
    return torus(1.0, 0.4, 36, 18)
