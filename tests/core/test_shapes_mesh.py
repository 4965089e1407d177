"""Shapes are closed, outward-facing and have the edges of their polygons; Mesh validates."""

import numpy as np
import pytest

from rasterkit import shapes
from rasterkit.mesh import Mesh, polygon_edges

CLOSED = ["cube", "tetrahedron", "octahedron", "icosahedron", "icosphere", "torus"]


def _face_normals(mesh):
    v = mesh.vertices[mesh.faces]
    return np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v


@pytest.mark.parametrize("name", CLOSED)
def test_closed_shapes_are_watertight_and_wound_outward(name):
    mesh = getattr(shapes, name)()
    # watertight: every directed triangle edge has its reverse exactly once
    f = mesh.faces
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    forward = {tuple(e) for e in directed}
    assert len(forward) == len(directed)
    assert all((b, a) in forward for a, b in directed)
    # outward: divergence theorem gives a positive volume
    n, v = _face_normals(mesh)
    assert np.einsum("ij,ij->i", v[:, 0], n).sum() / 6.0 > 0


@pytest.mark.parametrize("name", ["cube", "tetrahedron", "octahedron", "icosahedron", "icosphere"])
def test_convex_shapes_face_away_from_the_centre(name):
    n, v = _face_normals(getattr(shapes, name)())
    assert np.all(np.einsum("ij,ij->i", n, v.mean(axis=1)) > 0)


def test_cube_has_volume_size_cubed_and_twelve_polygon_edges():
    mesh = shapes.cube(2.0)
    n, v = _face_normals(mesh)
    assert np.einsum("ij,ij->i", v[:, 0], n).sum() / 6.0 == pytest.approx(8.0)
    assert len(mesh.edges) == 12  # the quads' sides, not their diagonals
    lengths = np.linalg.norm(mesh.vertices[mesh.edges[:, 0]] - mesh.vertices[mesh.edges[:, 1]], axis=1)
    assert np.allclose(lengths, 2.0)


def test_icosphere_counts_and_radius():
    for k in range(4):
        mesh = shapes.icosphere(k, radius=2.5)
        assert len(mesh.vertices) == 10 * 4**k + 2
        assert len(mesh.faces) == 20 * 4**k
        assert np.allclose(np.linalg.norm(mesh.vertices, axis=1), 2.5)
        # Euler characteristic of a sphere: V - E + F = 2
        assert len(mesh.vertices) - len(mesh.edges) + len(mesh.faces) == 2


def test_torus_is_genus_one_and_edges_are_the_quads_sides():
    mesh = shapes.torus(1.0, 0.3, rings=12, sides=8)
    assert len(mesh.faces) == 2 * 12 * 8
    assert len(mesh.edges) == 2 * 12 * 8  # V - E + F(quads) = 0
    assert len(mesh.vertices) - len(mesh.edges) + 12 * 8 == 0


def test_grid_faces_up():
    n, _ = _face_normals(shapes.grid(3, 4))
    assert np.all(n[:, 1] > 0) and len(n) == 24


def test_polygon_edges_are_unique_and_undirected():
    edges = polygon_edges([[0, 1, 2, 3], [3, 2, 4]])
    assert edges.tolist() == [[0, 1], [0, 3], [1, 2], [2, 3], [2, 4], [3, 4]]


def test_unique_edges_match_a_set_of_sorted_pairs():
    """Random pairs (repeats, both directions, self pairs, unsigned ints, extra keys): the sorted
    set of (min, max) without self pairs."""
    from rasterkit.mesh import unique_edges

    rng = np.random.default_rng(7)
    for n, k in [(1, 5), (6, 40), (300, 2000)]:
        pairs = rng.integers(0, n, (k, 2)).astype(np.uint32)
        keys = np.array([0 * n + n - 1] if n > 1 else [], np.int64)
        expected = sorted({(min(a, b), max(a, b)) for a, b in pairs.tolist() if a != b} |
                          ({(0, n - 1)} if n > 1 else set()))
        assert unique_edges(pairs, n, keys).tolist() == [list(e) for e in expected]


def test_mesh_derives_edges_and_validates():
    mesh = Mesh(np.zeros((4, 3)), [[0, 1, 2], [0, 2, 3]])
    assert mesh.edges.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    assert mesh.vertices.flags.c_contiguous and mesh.faces.dtype == np.int64
    with pytest.raises(ValueError, match="out of range"):
        Mesh(np.zeros((3, 3)), [[0, 1, 3]])
    with pytest.raises(ValueError, match="out of range"):
        Mesh(np.zeros((3, 3)), [[0, 1, -1]])
    with pytest.raises(ValueError, match="shape"):
        Mesh(np.zeros((4, 3)), [[0, 1, 2, 3]])
    with pytest.raises(ValueError, match="shape"):
        Mesh(np.zeros((4, 2)), [[0, 1, 2]])
    with pytest.raises(TypeError, match="integers"):
        Mesh(np.zeros((3, 3)), [[0.0, 1.0, 2.0]])
    with pytest.raises(ValueError, match="rows"):
        Mesh(np.zeros((3, 3)), [[0, 1, 2]], vertex_colors=np.zeros((2, 3)))


def test_bounding_sphere_holds_every_vertex_and_ignores_nan():
    v = np.array([[0, 0, 0], [2, 0, 0], [0, 4, 0], [np.nan, 0, 0]], float)
    mesh = Mesh(v, [[0, 1, 2]])
    centre, radius = mesh.bounding_sphere()
    assert np.allclose(centre, [1, 2, 0])
    assert np.all(np.linalg.norm(v[:3] - centre, axis=1) <= radius + 1e-12)


def test_side_neighbours_pair_the_faces_of_each_side_shared_by_exactly_two():
    """Against a brute-force count of the faces of each undirected side: a closed mesh's
    sides all pair up (each face's neighbour has the side back); an open border, a side of
    three faces and a side whose two corners are one vertex have none."""
    from rasterkit.mesh import side_neighbours

    def brute(faces):
        sides = {}
        for f, face in enumerate(faces.tolist()):
            for c in range(3):
                a, b = face[c], face[(c + 1) % 3]
                if a != b:
                    sides.setdefault(frozenset((a, b)), []).append(f)
        out = np.full(faces.shape, -1)
        for f, face in enumerate(faces.tolist()):
            for c in range(3):
                a, b = face[c], face[(c + 1) % 3]
                owners = sides.get(frozenset((a, b)), [])
                if a != b and len(owners) == 2:
                    out[f, c] = owners[0] if owners[1] == f else owners[1]
        return out

    sphere = shapes.icosphere(2)
    assert np.array_equal(side_neighbours(sphere.faces, len(sphere.vertices)), brute(sphere.faces))
    assert (sphere.side_neighbours >= 0).all() and not sphere.side_neighbours.flags.writeable
    fan = np.array([[0, 1, 2], [0, 2, 3], [0, 2, 4], [5, 5, 6], [2, 1, 7]])  # side 0-2 thrice
    assert np.array_equal(side_neighbours(fan, 8), brute(fan))
    rng = np.random.default_rng(3)
    for _ in range(20):
        faces = rng.integers(0, 7, (12, 3))
        assert np.array_equal(side_neighbours(faces, 7), brute(faces))
