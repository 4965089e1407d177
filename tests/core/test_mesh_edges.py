"""A Mesh's edges: the kernel that sorts them against a set of sorted pairs, the edges a
reader gives for polygons, and the Mesh working them out on first use."""

import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rasterkit.mesh import Mesh, polygon_mesh_edges, unique_edges
from rasterkit.mesh.edges import ALL_SIDES
from rasterkit.mesh.kernels import sorted_edges, sorted_polygon_edges


def reference(faces, pairs=()):
    """The unique undirected sides as a sorted list of (lo, hi), from Python sets."""
    sides = [(f[c], f[(c + 1) % 3]) for f in np.asarray(faces).tolist() for c in range(3)]
    sides += [tuple(p) for p in np.asarray(pairs).tolist()]
    return [list(e) for e in sorted({(min(a, b), max(a, b)) for a, b in sides if a != b})]


@pytest.mark.parametrize("n", [1, 5, 60, 2000])
def test_sorted_edges_are_the_set_of_sides(n):
    rng = np.random.default_rng(n)
    faces = rng.integers(0, n, (3000, 3))  # repeated corners: sides from a vertex to itself
    pairs = rng.integers(0, n, (200, 2))
    edges = sorted_edges(faces, ALL_SIDES, pairs, n)
    assert edges.dtype == np.int64 and edges.shape[1] == 2
    assert edges.tolist() == reference(faces, pairs)


def test_a_vertex_of_a_hundred_thousand_sides_is_sorted_too():
    m = 100_000  # a fan: vertex 0 has 2m sides, beyond the lists sorted by insertion
    rng = np.random.default_rng(0)
    faces = np.stack([np.zeros(m, np.int64), np.arange(1, m + 1), np.arange(2, m + 2)], axis=1)[rng.permutation(m)]
    assert sorted_edges(faces, ALL_SIDES, np.zeros((0, 2), np.int64), m + 2).tolist() == reference(faces)


def test_no_vertices_no_edges():
    assert sorted_edges(np.zeros((0, 3), np.int64), ALL_SIDES, np.zeros((0, 2), np.int64), 0).shape == (0, 2)


def test_unique_edges_takes_pairs_and_keys_and_refuses_indices_out_of_range():
    keys = np.array([1 * 10 + 7, 2 * 10 + 3])
    assert unique_edges([[4, 2], [2, 4], [5, 5]], 10, keys=keys).tolist() == [[1, 7], [2, 3], [2, 4]]
    with pytest.raises(ValueError, match="out of range"):
        unique_edges([[0, 10]], 10)
    with pytest.raises(ValueError, match="out of range"):
        unique_edges(np.array([[0, 2**63 + 1]], np.uint64), 10)


def test_sorted_polygon_edges_of_kept_polygons_and_pairs():
    corners = np.array([0, 1, 2, 3, 4, 4, 5, 6, 7, 8])
    offsets = np.array([0, 4, 7, 10])
    keep = np.array([True, True, False])
    edges = sorted_polygon_edges(corners, offsets, keep, np.array([[8, 2], [3, 3]]), 9)
    assert edges.tolist() == [[0, 1], [0, 3], [1, 2], [2, 3], [2, 8], [4, 5]]


def test_polygon_mesh_edges_leave_a_mesh_of_triangles_to_work_its_own():
    tri = np.array([0, 1, 2, 2, 1, 3])
    offsets = np.array([0, 3, 6])
    none = np.zeros((0, 2), np.int64)
    assert polygon_mesh_edges(tri, offsets, np.ones(2, bool), None, None, none, 4) == (None, None)
    # one triangle dropped with its polygon: the triangles' own sides, flagged
    edges, sides = polygon_mesh_edges(tri, offsets, np.array([True, False]), np.array([[0, 1, 2]]), np.array([0]),
                                      none, 4)
    assert edges is None and sides.tolist() == [7]
    # one triangle made no face (a repeated vertex), its polygon kept: its sides are still edges
    edges, sides = polygon_mesh_edges(tri, offsets, np.ones(2, bool), np.array([[0, 1, 2]]), np.array([0]), none, 4)
    assert sides is None and edges.tolist() == reference([[0, 1, 2], [2, 1, 3]])
    # a quad split in two: its four sides flagged, not the diagonal
    quad = np.array([0, 1, 2, 3])
    edges, sides = polygon_mesh_edges(quad, np.array([0, 4]), np.ones(1, bool), np.array([[0, 1, 2], [0, 2, 3]]),
                                      np.array([0, 0]), np.array([[3, 5]]), 6)
    assert edges is None and sides.tolist() == [0b011, 0b110]
    mesh = Mesh(np.zeros((6, 3)), quad[[[0, 1, 2], [0, 2, 3]]], lines=[[3, 5]], polygon_sides=sides)
    assert mesh.derives_edges and mesh.edges.tolist() == [[0, 1], [0, 3], [1, 2], [2, 3], [3, 5]]


def _polygons(rng, count, n_vertices):
    """Random polygons of 3 to 8 corners (vertices distinct within each): corners, offsets."""
    sizes = rng.integers(3, 9, count)
    corners = np.concatenate([rng.choice(n_vertices, k, replace=False) for k in sizes])
    return corners, np.concatenate([[0], np.cumsum(sizes)])


@pytest.mark.parametrize("seed", range(4))
def test_flagged_sides_give_the_edges_of_the_polygons(seed):
    """Polygons split by the readers' splitter (fans, ear clipping, a sweep): the Mesh's edges
    from the flags are the polygons' sides (as sorted_polygon_edges and Python sets give
    them), in every split a reader makes."""
    from rasterkit.obj.assemble import split_polygons

    rng = np.random.default_rng(seed)
    n = 40
    corners, offsets = _polygons(rng, 300, n)
    angles = rng.random(n) * 2 * np.pi  # on a circle: each polygon a simple (if crossing) shape
    vertices = np.stack([np.cos(angles), np.sin(angles), np.zeros(n)], axis=1)
    keep = rng.random(300) < 0.9
    triangles, counts, _ = split_polygons(vertices, corners, offsets, keep)
    polygon = np.repeat(np.arange(300), counts)
    pairs = rng.integers(0, n, (10, 2))
    edges, sides = polygon_mesh_edges(corners, offsets, keep, triangles, polygon, pairs, n)
    expected = sorted_polygon_edges(corners, offsets, keep, pairs, n).tolist()
    kept_sides = [(corners[o + c], corners[o + (c + 1) % (e - o)])
                  for p, (o, e) in enumerate(zip(offsets[:-1], offsets[1:])) if keep[p] for c in range(e - o)]
    assert expected == reference(np.zeros((0, 3), np.int64), kept_sides + pairs.tolist())
    if sides is None:  # a triangle dropped: the edges now
        assert edges.tolist() == expected
    else:
        mesh = Mesh(vertices, corners[triangles], lines=pairs, polygon_sides=sides)
        assert mesh.edges.tolist() == expected
        assert sorted_edges(corners[triangles], sides, pairs, n).tolist() == expected


def test_polygon_sides_are_checked_and_kept_by_the_scene():
    from rasterkit import Scene

    v, faces = np.zeros((4, 3)), [[0, 1, 2], [0, 2, 3]]
    with pytest.raises(ValueError, match="polygon_sides must be"):
        Mesh(v, faces, polygon_sides=[1, 8])
    with pytest.raises(ValueError, match="polygon_sides must be"):
        Mesh(v, faces, polygon_sides=[1])
    with pytest.raises(TypeError, match="polygon_sides must hold integers"):
        Mesh(v, faces, polygon_sides=[1.0, 2.0])
    quad = Mesh(v, faces, polygon_sides=np.array([0b011, 0b110], np.uint8))
    scene = Scene()
    scene.add(quad)
    scene.add(Mesh(v, faces))  # two triangles: every side
    world = scene.world_mesh()
    assert world.derives_edges and world.polygon_sides.tolist() == [3, 6, 7, 7]
    assert world.edges.tolist() == [[0, 1], [0, 3], [1, 2], [2, 3], [4, 5], [4, 6], [4, 7], [5, 6], [6, 7]]


def test_a_mesh_works_out_its_edges_when_asked_and_keeps_them():
    v = np.zeros((5, 3))
    faces, lines = [[0, 1, 2], [0, 2, 3]], [[3, 4]]
    mesh = Mesh(v, faces, lines=lines)
    assert "edges" not in repr(mesh)  # not worked out by making the Mesh or showing it
    first = mesh.edges
    assert first.tolist() == reference(faces, lines)
    assert mesh.edges is first and not first.flags.writeable
    assert "6 edges" in repr(mesh) and mesh.nbytes >= first.nbytes
    mesh.check_intact()
    object.__setattr__(mesh, "edges", np.array([[0, 1]]))
    with pytest.raises(ValueError, match="edges was changed"):
        mesh.check_intact()


def test_given_edges_are_kept_and_survive_pickling():
    v = np.zeros((4, 3))
    given = Mesh(v, [[0, 1, 2], [0, 2, 3]], edges=[[0, 1], [1, 2], [2, 3], [0, 3]])
    assert given.edges.tolist() == [[0, 1], [1, 2], [2, 3], [0, 3]]  # as given: no diagonal added
    again = pickle.loads(pickle.dumps(given))
    assert again.edges.tolist() == given.edges.tolist()
    lazy = pickle.loads(pickle.dumps(Mesh(v, [[0, 1, 2], [0, 2, 3]])))
    assert lazy.edges.tolist() == reference([[0, 1, 2], [0, 2, 3]])


@settings(max_examples=200, deadline=None)
@given(st.lists(st.lists(st.integers(0, 9), min_size=3, max_size=7), max_size=12), st.data())
def test_polygon_mesh_edges_are_the_sides_of_the_kept_polygons_and_the_lines(polygons, data):
    keep = np.array(data.draw(st.lists(st.booleans(), min_size=len(polygons), max_size=len(polygons))), bool)
    lines = np.array(data.draw(st.lists(st.tuples(st.integers(0, 9), st.integers(0, 9)), max_size=4)),
                     np.int64).reshape(-1, 2)
    offsets = np.concatenate([[0], np.cumsum([len(p) for p in polygons])]).astype(np.int64)
    corners = np.array(sum(polygons, []), np.int64)
    # no triangles given: the edges now, unless no polygon is kept (then the lines' alone, later)
    ours, sides = polygon_mesh_edges(corners, offsets, keep, np.zeros((0, 3), np.int64), np.zeros(0, np.int64),
                                     lines, 10)
    if ours is None:
        assert not keep.any() and (sides is None or len(sides) == 0)
        ours = sorted_edges(np.zeros((0, 3), np.int64), ALL_SIDES, lines, 10)
    sides = {(min(p[c], p[c - 1]), max(p[c], p[c - 1])) for p, k in zip(polygons, keep) if k for c in range(len(p))}
    sides |= {(min(a, b), max(a, b)) for a, b in lines.tolist()}
    assert ours.tolist() == [list(e) for e in sorted(sides) if e[0] != e[1]]


def test_a_scene_of_meshes_without_edges_gives_a_world_mesh_with_the_same_edges():
    from rasterkit import Camera, Scene, shapes, transform

    sphere = shapes.icosphere(1)
    plain = Mesh(sphere.vertices, sphere.faces)
    scene = Scene(Camera.frame(*sphere.bounding_sphere(), width=8, height=8))
    scene.add(plain, transform.translate(3, 0, 0))
    scene.add(Mesh(sphere.vertices, sphere.faces), transform.translate(-3, 0, 0))
    world = scene.world_mesh()
    assert plain.derives_edges and world.derives_edges
    assert world.edges.tolist() == reference(world.faces)
    scene.add(shapes.cube())  # given edges (the quads' sides): joined as they are
    world = scene.world_mesh()
    assert not world.derives_edges
    n = len(sphere.vertices)
    assert world.edges.tolist() == reference(plain.faces) + (np.array(reference(plain.faces)) + n).tolist() + \
        (shapes.cube().edges + 2 * n).tolist()


def test_repeated_corners():
    from rasterkit.mesh.kernels import repeated_corners

    faces = np.array([[0, 1, 2], [0, 0, 1], [1, 2, 2], [3, 1, 3], [4, 4, 4], [2, 1, 0]])
    want = [len({int(x) for x in f}) < 3 for f in faces]
    assert repeated_corners(faces).tolist() == want
    assert repeated_corners(np.zeros((0, 3), np.int64)).shape == (0,)
