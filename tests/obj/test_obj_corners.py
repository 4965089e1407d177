"""``load_obj`` keeps each face corner's own ``vt`` and ``vn`` (issue 27): a UV seam keeps both
coordinates, a hard edge both normals, polygons split into triangles (fans, NumPy's ear
clipping, the kernels for repeated corners and for more than 80 corners) carry their
corners' attributes exactly, against slow Python references; relative indices, faces with
and without ``vt``, bad references, ``usemtl`` -> ``face_materials``, and the real models."""

from __future__ import annotations

import re

import numpy as np
import pytest

from rasterkit.obj import load_obj
from rasterkit.obj.kernels.ears import EAR_CLIP_LIMIT


def load_text(tmp_path, text, name="m.obj"):
    path = tmp_path / name
    path.write_text(text)
    return load_obj(path)


def corner_uv(mesh):
    """(M, 3, 2) texture coordinates of each triangle corner."""
    return mesh.uv[mesh.uv_index]


# --- seams, hard edges, tables ---------------------------------------------------------------

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"


def test_a_seam_vertex_keeps_both_texture_coordinates(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.25\n"
                                        "f 1/1 2/2 3/3\nf 1/5 3/3 4/4\n")
    assert mesh.uv_index.tolist() == [[0, 1, 2], [4, 2, 3]]
    assert corner_uv(mesh)[:, 0].tolist() == [[0, 0], [0.5, 0.25]]  # vertex 0, two sides of a seam
    assert mesh.texcoords[0].tolist() == [0, 0]  # the per-vertex one: the first corner's, as before
    assert mesh.warnings == ()


def test_a_hard_edge_keeps_both_normals(tmp_path):
    # two faces folded along the edge 1-3, each with its own normal at the shared corners
    mesh = load_text(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 -1\nvn -1 0 0\n"
                               "f 1//1 3//1 2//1\nf 1//2 4//2 3//2\n")
    assert mesh.normal_index.tolist() == [[0, 0, 0], [1, 1, 1]]
    normals = mesh.corner_normals[mesh.normal_index]
    assert normals[0, 0].tolist() == [0, 0, -1] and normals[1, 0].tolist() == [-1, 0, 0]
    # the per-vertex normal of the shared vertex is still the average, as before
    assert np.allclose(mesh.normals[0], np.array([-1, 0, -1]) / np.sqrt(2))


def test_the_tables_hold_every_line_as_the_file_gives_it(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0.25\nvt 0.5 0.75 9\nvt nan inf\nvt -3 1e300\n"
                               "vn 0 0 2\nvn 0 0 0\nvn nan 0 1\nvn 3 4 0\n"
                               "f 1/1/1 2/2/2 3/3/3\nf 1/4/4 3/3/3 4/2/1\n")
    assert np.array_equal(mesh.uv, [[0.25, 0], [0.5, 0.75], [np.nan, np.inf], [-3, 1e300]], equal_nan=True)
    assert mesh.corner_normals.tolist() == [[0, 0, 1], [0, 0, 0], [0, 0, 0], [0.6, 0.8, 0]]  # unit, or 0
    assert mesh.uv_index.tolist() == [[0, 1, 2], [3, 2, 1]] and mesh.normal_index.tolist() == [[0, 1, 2], [3, 2, 0]]


def test_relative_indices_count_back_from_the_line(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                               "f -4/-3/-1 -3/-2/-1 -2/-1/-1\n"
                               "vt 0 1\nvn 0 0 -1\n"
                               "f 1/-4/1 3/-2/-1 -1/-1/-1\n")
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.uv_index.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.normal_index.tolist() == [[0, 0, 0], [0, 1, 1]]


def test_faces_without_texture_coordinates_have_rows_of_minus_one(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "f 1/1 2/2 3/3\nf 1 3 4\nf 4//  3// 1\n")
    assert mesh.uv_index.tolist() == [[0, 1, 2], [-1, -1, -1], [-1, -1, -1]]
    assert mesh.normal_index is None and mesh.corner_normals is None
    assert mesh.warnings == ()


def test_a_face_with_texture_coordinates_at_some_corners_only_has_none_with_a_warning(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "f 1/1 2/2 3/3\nf 1/1 3 4/4\n")
    assert mesh.uv_index.tolist() == [[0, 1, 2], [-1, -1, -1]]
    (warning,) = mesh.warnings
    assert warning.endswith("m.obj:10: 1 face with texture coordinates at some corners only: none kept for their "
                            "corners")


@pytest.mark.parametrize("reference, words", [("9", "out of range"), ("0", "index 0"), ("-9", "before the first")])
def test_a_bad_texture_index_drops_that_faces_coordinates_with_one_warning(tmp_path, reference, words):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               f"f 1/1 2/2 3/3\nf 1/1 3/{reference} 4/4\n")
    assert mesh.uv_index.tolist() == [[0, 1, 2], [-1, -1, -1]]
    assert len(mesh.warnings) == 1 and words in mesh.warnings[0] and "texture coordinates ignored" in mesh.warnings[0]


def test_a_file_whose_faces_name_no_vt_has_no_uv(tmp_path):
    mesh = load_text(tmp_path, SQUARE + "vt 0 0\nf 1 2 3\nf 1 3 4\n")
    assert mesh.uv is None and mesh.uv_index is None


# --- materials ----------------------------------------------------------------------------

def test_usemtl_gives_each_triangle_its_material(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n")
    mesh = load_text(tmp_path, "mtllib m.mtl\n" + SQUARE + "v 2 0 0\nv 2 1 0\n"
                               "f 1 2 3\nusemtl blue\nf 1 2 3 4\nusemtl red\nf 2 5 6 3\n"
                               "usemtl missing\nf 1 3 4\nusemtl\nf 1 2 3\nusemtl blue\nf 2 5 6\n")
    assert mesh.material_names == ("blue", "red", "missing")
    assert mesh.face_materials.tolist() == [-1, 0, 0, 1, 1, 2, -1, 0]
    assert mesh.face_materials.dtype == np.int32
    # the same material as the face colours say
    kd = {0: [0, 0, 1], 1: [1, 0, 0]}
    for f, m in enumerate(mesh.face_materials.tolist()):
        if m in kd:
            assert mesh.face_colors[f].tolist() == kd[m]


def test_a_file_without_usemtl_has_no_face_materials(tmp_path):
    assert load_text(tmp_path, SQUARE + "f 1 2 3\n").face_materials is None


# --- polygons: every triangle corner is the polygon corner it was cut from --------------------

def write_polygons(tmp_path, points, polygons, relative=()):
    """An OBJ file of ``points`` (N, 3) and ``polygons`` (lists of vertex indices) whose every
    corner has its own ``vt`` and ``vn``: corner c of the file (counted over all polygons)
    has ``vt c 0`` and ``vn`` row c, so a triangle corner's texture coordinate names the
    polygon corner it came from. Polygons in ``relative`` are written with negative indices."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(points).tolist()]
    c = 0
    for k, polygon in enumerate(polygons):
        lines += [f"vt {c + j} 0\nvn 0 0 {c + j + 1}" for j in range(len(polygon))]
        corners = []
        for j, v in enumerate(polygon):
            if k in relative:  # back from the last line above: vt and vn c + j are -(m - j)
                back = len(polygon) - j
                corners.append(f"{v - len(points)}/{-back}/{-back}")
            else:
                corners.append(f"{v + 1}/{c + j + 1}/{c + j + 1}")
        lines.append("f " + " ".join(corners))
        c += len(polygon)
    path = tmp_path / "polygons.obj"
    path.write_text("\n".join(lines) + "\n")
    return load_obj(path)


def corners_of_triangles(mesh, polygons):
    """(polygon, positions (3,)) of each triangle from its texture coordinates, checking the
    three corners' texture coordinates and normals name the same corners, of one polygon."""
    offsets = np.cumsum([0] + [len(p) for p in polygons])
    out = []
    for t in range(len(mesh.faces)):
        c = [int(u) for u in mesh.uv[mesh.uv_index[t], 0]]
        assert mesh.normal_index[t].tolist() == c  # vn row c is the corner's too
        k = int(np.searchsorted(offsets, c[0], side="right")) - 1
        positions = [x - offsets[k] for x in c]
        assert all(0 <= p < len(polygons[k]) for p in positions), (t, c)
        out.append((k, positions))
    return out


def check_corners_by_vertex(mesh, polygons):
    """The slow reference for polygons whose vertices are all different: the corner of a
    triangle's vertex v is the one polygon corner with vertex v."""
    for t, (k, positions) in enumerate(corners_of_triangles(mesh, polygons)):
        expected = [polygons[k].index(v) for v in mesh.faces[t].tolist()]
        assert positions == expected, (t, k)


def check_triangulates_the_corner_cycle(mesh, polygons, kept=None):
    """In corner space: each triangle's vertices are its corners' vertices, each side of a
    polygon (corners j, j + 1) is the side of exactly one of its triangles, in the polygon's
    direction, every other side of a triangle is shared with another triangle the other way
    round, and a polygon of m corners has m - 2 triangles (``kept``: fewer corners)."""
    sides = {k: [] for k in range(len(polygons))}
    for t, (k, positions) in enumerate(corners_of_triangles(mesh, polygons)):
        assert [polygons[k][p] for p in positions] == mesh.faces[t].tolist()
        sides[k] += [(positions[i], positions[(i + 1) % 3]) for i in range(3)]
    for k, polygon in enumerate(polygons):
        ring = kept[k] if kept and k in kept else list(range(len(polygon)))
        border = {(ring[j], ring[(j + 1) % len(ring)]) for j in range(len(ring))}
        counted = {s: sides[k].count(s) for s in sides[k]}
        assert all(counted.get(s) == 1 for s in border), (k, sorted(border - set(counted)))
        assert all(counted[s] == 1 and (s in border or (s[1], s[0]) in counted) for s in counted), k
        assert len(sides[k]) == 3 * (len(ring) - 2), k


def star(n, inner=0.45, seed=0):
    """(n, 2) a star-shaped polygon with every other corner pulled in (concave), jittered."""
    rng = np.random.default_rng(seed)
    angles = np.sort(rng.uniform(0, 2 * np.pi, n)) if seed else np.linspace(0, 2 * np.pi, n, endpoint=False)
    radii = np.where(np.arange(n) % 2, inner, 1.0) * rng.uniform(0.9, 1.0, n)
    return np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)


def in_space(flat, seed):
    """(n, 3) points of the plane polygon flat (n, 2) turned into a random plane."""
    rng = np.random.default_rng(seed)
    basis = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    return np.column_stack([flat, np.zeros(len(flat))]) @ basis.T + rng.uniform(-2, 2, 3)


def test_a_quad_and_concave_polygons_carry_their_corners(tmp_path):
    flat = np.concatenate([[[0, 0], [1, 0], [1, 1], [0, 1]],  # convex quad: a fan
                           [[2, 0], [3, 0], [2.2, 0.2], [2, 1]],  # a dart: ear clipped
                           [[4, 0], [6, 0], [6, 1], [5, 1], [5, 2], [4, 2]],  # an L
                           star(12) + [8, 0]])  # a star of 12
    polygons = [[0, 1, 2, 3], [4, 5, 6, 7], list(range(8, 14)), list(range(14, 26))]
    mesh = write_polygons(tmp_path, in_space(flat, 1), polygons)
    assert mesh.warnings == () and len(mesh.faces) == 2 + 2 + 4 + 10
    check_corners_by_vertex(mesh, polygons)
    check_triangulates_the_corner_cycle(mesh, polygons)


@pytest.mark.parametrize("n", [EAR_CLIP_LIMIT + 10, 3 * EAR_CLIP_LIMIT])
def test_polygons_of_more_than_80_corners_carry_their_corners(tmp_path, n):
    """The kernels' splitter: a convex polygon (a fan from its last corner) and a concave one
    (the monotone sweep)."""
    convex = star(n, inner=1.0)
    concave = star(n, seed=n) + [3, 0]
    polygons = [list(range(n)), list(range(n, 2 * n))]
    mesh = write_polygons(tmp_path, in_space(np.concatenate([convex, concave]), n), polygons)
    assert mesh.warnings == () and len(mesh.faces) == 2 * (n - 2)
    check_corners_by_vertex(mesh, polygons)
    check_triangulates_the_corner_cycle(mesh, polygons)


def bridged(outer: int, hole: int):
    """Points and the polygon of a regular polygon of ``outer`` corners with a hole of
    ``hole`` corners joined by a bridge walked both ways: vertices 0 and ``outer`` are
    visited twice."""
    a = np.linspace(0, 2 * np.pi, outer, endpoint=False)
    b = -np.linspace(0, 2 * np.pi, hole, endpoint=False)  # the hole clockwise
    points = np.concatenate([np.stack([4 * np.cos(a), 4 * np.sin(a)], 1), np.stack([np.cos(b), np.sin(b)], 1)])
    polygon = list(range(outer)) + [0] + list(range(outer, outer + hole)) + [outer]
    return points, polygon


@pytest.mark.parametrize("outer, hole", [(4, 4), (6, 5), (60, 30)])
def test_a_hole_joined_by_a_bridge_keeps_each_visits_own_corner(tmp_path, outer, hole):
    """Vertices visited twice (the kernels' ear clipping up to 80 corners, the sweep beyond)
    take the attributes of the visit whose triangle it is, not those of the first visit."""
    points, polygon = bridged(outer, hole)
    mesh = write_polygons(tmp_path, in_space(points, outer), [polygon])
    assert mesh.warnings == ()
    check_triangulates_the_corner_cycle(mesh, [polygon])
    second = len(polygon) - 1  # the second visit of the hole's first vertex
    assert second in {p for _, positions in corners_of_triangles(mesh, [polygon]) for p in positions}


def test_merged_repeats_keep_the_first_corner_of_each(tmp_path):
    points = in_space(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), 5)
    polygons = [[0, 1, 1, 2], [0, 1, 2, 3, 0, 1, 2, 3], [3, 0, 1, 2, 3]]
    mesh = write_polygons(tmp_path, points, polygons)
    check_triangulates_the_corner_cycle(mesh, polygons, kept={0: [0, 1, 3], 1: [0, 1, 2, 3], 2: [0, 1, 2, 3]})


def test_random_polygons_carry_their_corners_exactly(tmp_path):
    """Hundreds of triangles, quads and star polygons (convex and concave, 4 to 12 corners,
    a few of 81 to 120) in random planes, some written with relative indices, against the
    slow reference."""
    rng = np.random.default_rng(27)
    points, polygons, n = [], [], 0
    for k in range(400):
        m = int(rng.choice([3, 4, 4, 5, 7, 12])) if k % 50 else int(rng.integers(81, 121))
        flat = star(m, inner=float(rng.choice([1.0, 0.5])), seed=int(rng.integers(1, 1 << 30)))
        polygons.append(list(range(n, n + m)))
        points.append(in_space(flat, k))
        n += m
    relative = set(rng.choice(len(polygons), 100, replace=False).tolist())
    mesh = write_polygons(tmp_path, np.concatenate(points), polygons, relative=relative)
    assert len(mesh.faces) == sum(len(p) - 2 for p in polygons)
    check_corners_by_vertex(mesh, polygons)
    check_triangulates_the_corner_cycle(mesh, polygons)


# --- the real models ------------------------------------------------------------------------

def reference_corners(path):
    """The faces of an OBJ file of ``f`` lines with absolute ``v/vt[/vn]`` corners, read by a
    plain Python loop: a list of polygons, each a list of (v, vt, vn) 0-based (-1: none)."""
    polygons = []
    for line in path.read_text().splitlines():
        if line.startswith("f "):
            corner = []
            for token in line.split()[1:]:
                fields = (token.split("/") + ["", ""])[:3]
                corner.append(tuple(int(x) - 1 if x else -1 for x in fields))
            polygons.append(corner)
    return polygons


def check_against_reference(mesh, polygons):
    """Each triangle, of the polygons in order, against its polygon's corners found by vertex."""
    assert len(mesh.faces) == sum(len(p) - 2 for p in polygons)  # no degenerate triangle in these
    polygon_of = np.repeat(np.arange(len(polygons)), [len(p) - 2 for p in polygons])
    for t, face in enumerate(mesh.faces.tolist()):
        corner = {v: (vt, vn) for v, vt, vn in polygons[polygon_of[t]]}
        assert mesh.uv_index[t].tolist() == [corner[v][0] for v in face]
        if mesh.normal_index is not None:
            assert mesh.normal_index[t].tolist() == [corner[v][1] for v in face]


@pytest.mark.parametrize("name, n_vt, n_vn", [
    ("spot.obj", 3225, 0), ("spot_quadrangulated.obj", 3225, 0), ("spot_control_mesh.obj", 267, 0),
    ("formats/obj/fuze/fuze.obj", 664, 502), ("formats/obj/african_head/african_head.obj", 1339, 1258),
])
def test_the_real_models_keep_every_corner(models_dir, name, n_vt, n_vn):
    path = models_dir / name
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    mesh = load_obj(path)
    assert mesh.uv.shape == (n_vt, 2) and (mesh.uv_index >= 0).all()
    assert (mesh.corner_normals is None) == (n_vn == 0)
    if n_vn:
        assert mesh.corner_normals.shape == (n_vn, 3) and (mesh.normal_index >= 0).all()
    check_against_reference(mesh, reference_corners(path))
    text = path.read_text()
    vt = [[float(x) for x in line.split()[1:3]] for line in re.findall(r"^vt .*$", text, re.M)]
    assert np.array_equal(mesh.uv, vt)


def test_spot_has_seams_and_uses_every_texture_coordinate(models_dir):
    path = models_dir / "spot.obj"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    mesh = load_obj(path)
    pairs = np.unique(np.stack([mesh.faces.ravel(), mesh.uv_index.ravel()], axis=1), axis=0)
    expected = {(v, vt) for polygon in reference_corners(path) for v, vt, _ in polygon}
    assert set(map(tuple, pairs.tolist())) == expected
    assert len(np.unique(pairs[:, 1])) == 3225  # every vt is some corner's
    seams = np.flatnonzero(np.bincount(pairs[:, 0]) > 1)  # vertices with two or more vt
    assert len(seams) == len({v for v, _ in expected if len({vt for w, vt in expected if w == v}) > 1}) > 100
    # a seam vertex's corners differ in texture coordinates, not only in vt row
    vertex = seams[0]
    assert len({tuple(mesh.uv[vt]) for v, vt in pairs.tolist() if v == vertex}) > 1
