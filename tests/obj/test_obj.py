"""load_obj on small OBJ texts written by the tests: every accepted form, every error with its
line, and the triangulation of concave polygons checked against geometry."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rasterkit.mesh import polygon_edges
from rasterkit.obj import DEFAULT_KD, ObjError, load_obj

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
# An arrow whose fan from vertex 1 would cover the notch between vertices 4 and 6.
ARROW = [(0, 0), (4, 2), (0, 4), (1, 2)]
# A comb: three teeth; concave at vertices 3, 4, 7, 8.
COMB = [(0, 0), (6, 0), (6, 3), (5, 3), (5, 1), (3.5, 1), (3.5, 3), (2.5, 3), (2.5, 1), (1, 1),
        (1, 3), (0, 3)]


def write(tmp_path, text, name="m.obj"):
    path = tmp_path / name
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return path


def load(tmp_path, text, name="m.obj"):
    return load_obj(write(tmp_path, text, name))


def polygon_text(points_2d, z=0.0):
    vertices = "".join(f"v {x} {y} {z}\n" for x, y in points_2d)
    return vertices + "f " + " ".join(str(i + 1) for i in range(len(points_2d))) + "\n"


# --- geometric references (slow and obvious) ---------------------------------------------------

def newell_normal(points):
    """Normal of a polygon (m, 3) whose length is twice its area (Newell's formula)."""
    p = np.asarray(points, float)
    q = np.roll(p, -1, axis=0)
    return np.array([np.sum((p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])),
                     np.sum((p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])),
                     np.sum((p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1]))])


def triangle_normals(mesh):
    a, b, c = (mesh.vertices[mesh.faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


def inside_polygon_2d(point, polygon):
    """Even-odd ray casting."""
    x, y = point
    inside = False
    for (x0, y0), (x1, y1) in zip(polygon, polygon[1:] + polygon[:1]):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def assert_exact_cover(mesh, polygon_2d):
    """The triangles of the planar (z = const) polygon cover it exactly: n - 2 triangles wound
    like the polygon, total area equal to its area, every triangle inside it."""
    normals = triangle_normals(mesh)
    polygon_normal = newell_normal([(x, y, 0.0) for x, y in polygon_2d])
    assert len(mesh.faces) == len(polygon_2d) - 2
    assert np.all(normals @ polygon_normal > 0)
    assert np.linalg.norm(normals, axis=1).sum() == pytest.approx(np.linalg.norm(polygon_normal))
    for triangle in mesh.vertices[mesh.faces][:, :, :2]:
        assert inside_polygon_2d(tuple(triangle.mean(axis=0)), list(polygon_2d))


# --- forms --------------------------------------------------------------------------------------

INDEX_FORMS = {
    "v": ("f 1 2 3", False, False),
    "v/vt": ("f 1/3 2/2 3/1", True, False),
    "v//vn": ("f 1//1 2//1 3//2", False, True),
    "v/vt/vn": ("f 1/3/1 2/2/1 3/1/2", True, True),
}


@pytest.mark.parametrize("form", INDEX_FORMS)
def test_every_index_form_gives_the_triangle_and_its_attributes(tmp_path, form):
    face, has_vt, has_vn = INDEX_FORMS[form]
    mesh = load(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.1 0.2\nvt 0.3 0.4\nvt 0.5 0.6\n"
                          "vn 0 0 1\nvn 0 0 -1\n" + face + "\n")
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])
    assert (mesh.texcoords is not None) == has_vt
    assert (mesh.normals is not None) == has_vn
    if has_vt:
        np.testing.assert_array_equal(mesh.texcoords, [[0.5, 0.6], [0.3, 0.4], [0.1, 0.2]])
    if has_vn:
        np.testing.assert_array_equal(mesh.normals, [[0, 0, 1], [0, 0, 1], [0, 0, -1]])
    assert mesh.warnings == ()


def test_index_forms_mixed_in_one_file_and_empty_fields(tmp_path):
    mesh = load(tmp_path, SQUARE + "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                "f 1 2 3\nf 1/1 3/3 4/2\nf 1//1 4//1 2//\nf 2/2/1 3/3/1 4/2/1\nf 1// 2// 3//\n")
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 2, 3],
                                               [0, 1, 2]])
    # texcoords from each vertex's first corner that has one; normals where given
    np.testing.assert_array_equal(mesh.texcoords, [[0, 0], [1, 0], [1, 1], [1, 0]])
    np.testing.assert_array_equal(mesh.normals, [[0, 0, 1]] * 4)


def test_negative_indices_count_back_from_the_line(tmp_path):
    relative = load(tmp_path, "v 9 9 9\n" + SQUARE + "vt 0 0\nvt 1 1\nvn 0 0 1\n"
                    "f -4/-2/-1 -3/-1/-1 -2/-2/-1 -1/-1/-1\nv 5 5 5\nf -2 -3 -6\n")
    absolute = load(tmp_path, "v 9 9 9\n" + SQUARE + "vt 0 0\nvt 1 1\nvn 0 0 1\n"
                    "f 2/1/1 3/2/1 4/1/1 5/2/1\nv 5 5 5\nf 5 4 1\n", "b.obj")
    np.testing.assert_array_equal(relative.faces, absolute.faces)
    np.testing.assert_array_equal(relative.faces, [[1, 2, 3], [1, 3, 4], [4, 3, 0]])
    np.testing.assert_array_equal(relative.texcoords, absolute.texcoords)
    np.testing.assert_array_equal(relative.normals, absolute.normals)


def test_positive_indices_may_point_below_the_line(tmp_path):
    mesh = load(tmp_path, "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n")
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])


def test_a_quad_gives_two_triangles_and_its_four_sides_not_the_diagonal(tmp_path):
    mesh = load_obj(str(write(tmp_path, SQUARE + "f 1 2 3 4\n")))
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(mesh.edges, [[0, 1], [0, 3], [1, 2], [2, 3]])
    np.testing.assert_array_equal(mesh.edges, polygon_edges([[0, 1, 2, 3]]))


def test_shared_sides_of_polygons_are_one_edge(tmp_path):
    mesh = load(tmp_path, SQUARE + "v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n")
    np.testing.assert_array_equal(mesh.edges, polygon_edges([[0, 1, 2, 3], [1, 4, 5, 2]]))
    assert len(mesh.edges) == 7


@pytest.mark.parametrize("polygon", [ARROW, COMB, COMB[::-1], ARROW[2:] + ARROW[:2]],
                         ids=["arrow", "comb", "comb-clockwise", "arrow-rotated"])
def test_concave_polygons_are_ear_clipped_not_fanned(tmp_path, polygon):
    assert_exact_cover(load(tmp_path, polygon_text(polygon)), polygon)


def test_a_concave_quad_is_split_along_its_inside_diagonal(tmp_path):
    mesh = load(tmp_path, polygon_text(ARROW))
    # the fan from vertex 0 would use the diagonal 0-2, which lies outside the arrow
    assert sorted(map(sorted, mesh.faces.tolist())) == [[0, 1, 3], [1, 2, 3]]


def rotation(angles):
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def assert_exact_cover_3d(mesh, points_3d):
    """Like assert_exact_cover for a planar polygon in any orientation."""
    normal = newell_normal(points_3d)
    normals = triangle_normals(mesh)
    assert len(mesh.faces) == len(points_3d) - 2
    assert np.all(normals @ normal >= -1e-9 * (normal @ normal))
    assert np.linalg.norm(normals, axis=1).sum() == pytest.approx(np.linalg.norm(normal))


@settings(deadline=None, max_examples=40)
@given(radii=st.lists(st.floats(0.2, 3.0), min_size=3, max_size=24),
       angles=st.tuples(*[st.floats(-math.pi, math.pi)] * 3),
       offset=st.tuples(*[st.floats(-1e3, 1e3)] * 3), clockwise=st.booleans())
def test_star_shaped_polygons_in_any_plane_are_covered_exactly(tmp_path_factory, radii, angles,
                                                               offset, clockwise):
    n = len(radii)
    turns = np.arange(n) * 2 * math.pi / n
    flat = np.stack([np.cos(turns) * radii, np.sin(turns) * radii, np.zeros(n)], axis=1)
    if clockwise:
        flat = flat[::-1]
    points = flat @ rotation(angles).T + np.array(offset)
    text = "".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in points)
    text += "f " + " ".join(str(i + 1) for i in range(n)) + "\n"
    mesh = load_obj(write(tmp_path_factory.mktemp("star"), text))
    assert_exact_cover_3d(mesh, points)


def test_a_polygon_with_a_hole_joined_by_a_bridge_is_covered(tmp_path):
    outer = [(0, 0), (4, 0), (4, 4), (0, 4)]
    hole = [(1, 1), (1, 3), (3, 3), (3, 1)]  # clockwise
    # outer ring, bridge to the hole, around the hole, back over the same bridge
    ring = [0, 1, 2, 3, 0, 4, 5, 6, 7, 4]
    points = outer + hole
    text = "".join(f"v {x} {y} 0\n" for x, y in points)
    text += "f " + " ".join(str(i + 1) for i in ring) + "\n"
    mesh = load(tmp_path, text)
    areas = np.linalg.norm(triangle_normals(mesh), axis=1) / 2
    assert areas.sum() == pytest.approx(16 - 4)
    assert np.all(triangle_normals(mesh)[:, 2] >= 0)
    for triangle in mesh.vertices[mesh.faces][:, :, :2]:
        centre = tuple(triangle.mean(axis=0))
        assert inside_polygon_2d(centre, outer) and not inside_polygon_2d(centre, hole)


def test_repeated_vertices_in_a_face_leave_no_degenerate_triangle(tmp_path):
    mesh = load(tmp_path, SQUARE + "f 1 2 2 3\nf 1 3 3 4 4\n")
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(mesh.edges, [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]])


def test_polylines_give_consecutive_segments(tmp_path):
    mesh = load(tmp_path, SQUARE + "vt 0 0\nl 1 2 3\nl 4/1 1/1\nl -1 -2\n")
    np.testing.assert_array_equal(mesh.lines, [[0, 1], [1, 2], [3, 0], [3, 2]])
    np.testing.assert_array_equal(mesh.faces, np.zeros((0, 3)))
    np.testing.assert_array_equal(mesh.edges, [[0, 1], [0, 3], [1, 2], [2, 3]])


def test_points_are_counted_in_a_warning_and_not_drawn(tmp_path):
    mesh = load(tmp_path, SQUARE + "p 1 2\np 3\nf 1 2 3\n")
    assert len(mesh.faces) == 1
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}: 3 points in 2 p elements not drawn",)


# --- text layout: every variant reads like the plain file ---------------------------------------

PLAIN = SQUARE + "vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nl 1 3\n"
VARIANTS = {
    "crlf": PLAIN.replace("\n", "\r\n"),
    "cr": PLAIN.replace("\n", "\r"),
    "tabs": PLAIN.replace(" ", "\t"),
    "runs of blanks": PLAIN.replace(" ", " \t  ").replace("\n", "  \n"),
    "leading blanks": "".join("  \t" + line + "\n" for line in PLAIN.splitlines()),
    "utf-8 bom": "\ufeff" + PLAIN,
    "no final newline": PLAIN.rstrip("\n"),
    "crlf, no final newline": PLAIN.replace("\n", "\r\n").rstrip("\r\n"),
    "comments": "# header\n" + PLAIN.replace("\nf", "  # end of vertices\n#f 9 9 9\nf")
                + "#",
    "blank lines": "\n\n" + PLAIN.replace("\n", "\n\n   \n"),
    "continuation": PLAIN.replace("2/1/1 ", "2/1/1 \\\n    ").replace("v 1 1", "v 1 \\\n1"),
    "crlf continuation": PLAIN.replace("\n", "\r\n").replace("2/1/1 ", "2/1/1 \\\r\n"),
    "line-end comment": PLAIN.replace("\n", " # note\n"),
}


@pytest.mark.parametrize("variant", VARIANTS)
def test_text_layout_variants_read_like_the_plain_file(tmp_path, variant):
    plain = load(tmp_path, PLAIN, "plain.obj")
    mesh = load(tmp_path, VARIANTS[variant])
    for field in ("vertices", "faces", "edges", "lines", "normals", "texcoords"):
        np.testing.assert_array_equal(getattr(mesh, field), getattr(plain, field), err_msg=field)
    assert mesh.warnings == ()


def test_line_numbers_count_physical_lines_across_continuations(tmp_path):
    with pytest.raises(ObjError) as caught:
        load(tmp_path, SQUARE + "f 1 2 \\\n 3 4\n\nf 1 2 0\n")
    assert caught.value.line == 8


# --- numbers ------------------------------------------------------------------------------------

@pytest.mark.parametrize("text, value", [
    ("1", 1.0), ("-2.", -2.0), (".5", 0.5), ("-.7e+2", -70.0), ("+1e-3", 1e-3), ("1E+02", 100.0),
    ("2.e1", 20.0), (".8e-001", 0.08), ("0.000", 0.0), ("-0", -0.0), ("007", 7.0),
    ("123456789012345678901234567890", 1.2345678901234568e29), ("1e-400", 0.0),
    ("0.70710676908493042", 0.70710676908493042), ("4.9406564584124654e-324", 5e-324),
])
def test_numbers_are_read_exactly(tmp_path, text, value):
    mesh = load(tmp_path, f"v {text} 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert mesh.vertices[0, 0] == value
    assert math.copysign(1.0, mesh.vertices[0, 0]) == math.copysign(1.0, value)


decimal_text = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
    st.tuples(st.floats(-1e6, 1e6), st.integers(0, 25)).map(lambda t: f"{t[0]:.{t[1]}f}"),
    st.tuples(st.floats(-1e300, 1e300), st.integers(0, 25)).map(lambda t: f"{t[0]:.{t[1]}e}"),
    st.tuples(st.sampled_from(["", "-", "+"]), st.text("0123456789", min_size=1, max_size=30),
              st.integers(0, 30), st.sampled_from(["", "e7", "E-12", "e+300", "e-320"]))
      .map(lambda t: t[0] + t[1][:t[2]] + "." + t[1][t[2]:] + t[3]),
)


@settings(deadline=None, max_examples=60)
@given(numbers=st.lists(decimal_text, min_size=3, max_size=30))
def test_any_decimal_text_reads_as_pythons_float(tmp_path_factory, numbers):
    numbers = numbers[:len(numbers) // 3 * 3]
    text = "".join(f"v {a} {b} {c}\n" for a, b, c in zip(*[iter(numbers)] * 3)) + "l 1 1\n"
    mesh = load_obj(write(tmp_path_factory.mktemp("num"), text))
    np.testing.assert_array_equal(mesh.vertices.ravel(), [float(t) for t in numbers])


number_like = st.one_of(
    decimal_text, st.sampled_from(["nan", "-NaN", "+inf", "-Infinity", "INF", "1.#IND", "-12.#inf", "+1.#QNAN",
                                   "7.#snan", "1.#", "--1.#INF", ".#IND", "1.#INDx", "1_0", "nanx", "1e", "\u0661"]),
    st.text("0123456789+-.eE#nafiINDQS_", min_size=1, max_size=8),
)


@settings(deadline=None, max_examples=150)
@given(tokens=st.lists(number_like, min_size=1, max_size=12), long=st.booleans())
def test_numbers_left_to_python_are_read_at_once_as_one_by_one(tokens, long):
    from rasterkit.obj.statements import _number, _numbers

    raw = [t.encode() for t in tokens] + ([b"1" * 80] if long else [])  # a long token: one by one
    values, ok = _numbers(raw)
    one_by_one = [_number(t) for t in raw]
    assert ok.tolist() == [v is not None for v in one_by_one]
    np.testing.assert_array_equal(values[ok], [v for v in one_by_one if v is not None])


@pytest.mark.parametrize("text", ["nan", "-nan", "NaN", "inf", "-Infinity", "1.#IND", "-1.#IND",
                                  "1.#INF", "-1.#INF", "1.#QNAN", "1e999"])
def test_nan_and_infinity_spellings_are_read_and_their_faces_dropped(tmp_path, text):
    mesh = load(tmp_path, f"v 0 0 0\nv {text} 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 4 3\n"
                          "l 1 2\nl 3 4\n")
    expected = float(text.replace("1.#IND", "nan").replace("1.#QNAN", "nan")
                     .replace("1.#INF", "inf"))
    assert np.isnan(mesh.vertices[1, 0]) == math.isnan(expected)
    if not math.isnan(expected):
        assert mesh.vertices[1, 0] == expected
    np.testing.assert_array_equal(mesh.faces, [[0, 3, 2]])
    np.testing.assert_array_equal(mesh.lines, [[2, 3]])
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}:2: 1 vertex with NaN or infinite "
                             "coordinates; 1 face and 1 line using them dropped",)


def test_the_w_of_four_number_vertices_is_ignored(tmp_path):
    mesh = load(tmp_path, "v 0 0 0 2\nv 1 0 0 0.5\nv 0 1 0 0\nf 1 2 3\n")
    np.testing.assert_array_equal(mesh.vertices, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert mesh.vertex_colors is None


def test_vt_may_have_one_to_three_numbers(tmp_path):
    mesh = load(tmp_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5\nvt 0.25 0.75\nvt 0.1 0.2 0.3\n"
                          "f 1/1 2/2 3/3\n")
    np.testing.assert_array_equal(mesh.texcoords, [[0.5, 0], [0.25, 0.75], [0.1, 0.2]])


# --- colours, normals, groups, materials --------------------------------------------------------

def test_vertex_colors_between_0_and_1(tmp_path):
    mesh = load(tmp_path, "v 0 0 0 1 0 0\nv 1 0 0 0 0.5 0\nv 0 1 0 0 0 0.25\nf 1 2 3\n")
    assert mesh.vertex_colors.dtype == np.float32
    np.testing.assert_array_equal(mesh.vertex_colors, [[1, 0, 0], [0, 0.5, 0], [0, 0, 0.25]])


def test_vertex_colors_above_1_are_taken_as_0_to_255(tmp_path):
    mesh = load(tmp_path, "v 0 0 0 255 0 0\nv 1 0 0 0 51 0\nv 0 1 0\nf 1 2 3\n")
    np.testing.assert_allclose(mesh.vertex_colors, [[1, 0, 0], [0, 0.2, 0], [1, 1, 1]],
                               rtol=1e-6)
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}:3: 1 of 3 vertices have no colour while "
                             "others have one: white",)


def test_normals_are_the_normalised_sum_over_the_corners(tmp_path):
    mesh = load(tmp_path, SQUARE + "v 0 0 1\nvn 0 0 2\nvn 1 0 0\n"
                          "f 1//1 2//1 3//1\nf 1//2 2//2 5//2\n")
    s = math.sqrt(0.5)
    np.testing.assert_allclose(mesh.normals, [[s, 0, s], [s, 0, s], [0, 0, 1], [0, 0, 0],
                                              [1, 0, 0]])


def test_groups_and_objects_name_the_faces(tmp_path):
    mesh = load(tmp_path, SQUARE + "f 1 2 3\ng wall  left\nf 1 3 4\no thing\nf 2 3 4\n"
                          "g\nf 1 2 4\ng wall left\nf 4 3 2 1\n")
    assert mesh.group_names == ("default", "wall left", "thing")
    np.testing.assert_array_equal(mesh.face_groups, [0, 1, 2, 0, 1, 1])


def test_without_group_statements_there_are_no_groups(tmp_path):
    mesh = load(tmp_path, SQUARE + "f 1 2 3\n")
    assert mesh.face_groups is None and mesh.group_names == ()


MTL = """# two colours and one without Kd
newmtl red
Ka 0 0 0
Kd 1 0 0
newmtl grey
Kd 0.5
newmtl plain
Ns 10
"""


def test_material_kd_colours_become_face_colours(tmp_path):
    write(tmp_path, MTL, "colors.mtl")
    mesh = load(tmp_path, "mtllib colors.mtl\n" + SQUARE + "f 1 2 3\nusemtl red\nf 1 2 3 4\n"
                          "usemtl grey\nf 2 3 4\nusemtl plain\nf 1 3 4\nusemtl red\nf 1 2 4\n")
    assert mesh.face_colors.dtype == np.float32
    expected = np.array([DEFAULT_KD, [1, 0, 0], [1, 0, 0], [0.5] * 3, DEFAULT_KD, [1, 0, 0]],
                        np.float32)
    np.testing.assert_array_equal(mesh.face_colors, expected)
    assert mesh.material_names == ("red", "grey", "plain")
    assert mesh.warnings == ()


def test_a_material_missing_from_the_library_is_a_warning(tmp_path):
    write(tmp_path, MTL, "colors.mtl")
    mesh = load(tmp_path, "mtllib colors.mtl\n" + SQUARE + "usemtl blue\nf 1 2 3\n")
    np.testing.assert_array_equal(mesh.face_colors, np.array([DEFAULT_KD], np.float32))
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}:6: 1 material not in the material "
                             "libraries: 'blue'",)


def test_a_missing_mtl_file_is_a_warning_not_an_error(tmp_path):
    mesh = load(tmp_path, "# no library here\nmtllib absent.mtl\n" + SQUARE +
                "usemtl red\nf 1 2 3\n")
    assert mesh.face_colors is None
    assert mesh.material_names == ("red",)
    assert len(mesh.warnings) == 1
    assert mesh.warnings[0].startswith(f"{tmp_path / 'm.obj'}:2: material library 'absent.mtl' "
                                       "cannot be read: ")


def test_unknown_keywords_are_skipped_and_counted(tmp_path):
    mesh = load(tmp_path, SQUARE + "vp 0.5 0.5\ncstype bspline\nvp 1 1\nf 1 2 3\ncurv 0 1 1 2\n"
                          "s off\n")
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}: 4 unknown keyword lines skipped "
                             "(vp, cstype, curv)",)


def test_warnings_are_returned_not_printed(tmp_path, capsys):
    mesh = load(tmp_path, "mtllib absent.mtl\nvp 1\n" + SQUARE + "f 1 2 3\n")
    assert len(mesh.warnings) == 2
    assert capsys.readouterr() == ("", "")


# --- errors -------------------------------------------------------------------------------------

ERRORS = {
    "index 0": (SQUARE + "f 1 2 3\nf 1 0 3\n", 6, "vertex index 0 in '0'"),
    "index out of range": (SQUARE + "f 1 2 5\n", 5, "vertex index 5 in '5' is out of range"),
    "relative before first": ("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", 3,
                              "relative vertex index -3"),
    "texture index 0 with a bad vertex": (SQUARE + "vt 0 0\nf 1/0 2/1 9/1\n", 6, "index 9"),
    "face with 2 vertices": (SQUARE + "f 1 2\n", 5, "face with 2 vertices"),
    "face with 1 vertex": (SQUARE + "\n\nf 3\n", 7, "face with 1 vertex"),
    "bare f": (SQUARE + "f\n", 5, "face with no vertices"),
    "line with 1 vertex": (SQUARE + "l 1\n", 5, "line with 1 vertex"),
    "malformed number": ("v 0 0 0\nv 1 x 0\n", 2, "malformed number 'x'"),
    "number with a sign after digits": ("v 0 0 3.1+e2\n", 1, "malformed number '3.1+e2'"),
    "two points": (SQUARE + "vn 1.2.3 0 0\n", 5, "malformed number '1.2.3'"),
    "empty exponent": (SQUARE + "vt 1e 0\n", 5, "malformed number '1e'"),
    "malformed index": (SQUARE + "f 1 2 3a\n", 5, "malformed vertex reference '3a'"),
    "four fields": (SQUARE + "f 1/1/1/1 2 3\n", 5, "malformed vertex reference '1/1/1/1'"),
    "empty vertex field": (SQUARE + "f /1 2 3\n", 5, "malformed vertex reference '/1'"),
    "sign without digits": (SQUARE + "f 1 - 3\n", 5, "malformed vertex reference '-'"),
    "v with two numbers": ("v 0 0\n", 1, "v needs 3 (x y z), 4 (x y z w) or 6"),
    "v with five numbers": (SQUARE + "v 1 2 3 4 5\n", 5, "got 5"),
    "vn with two numbers": ("vn 0 1\n", 1, "vn needs 3 (x y z) numbers, got 2"),
    "vt with four numbers": ("vt 0 1 2 3\n", 1, "vt needs 1 to 3 (u v w) numbers, got 4"),
    "the first of several errors": (SQUARE + "f 1 2 9\nv 1 2\nf 0 1 2\n", 5, "index 9"),
    "the first error even when a later line is worse": ("v 0 0\nv 1 x 0\n", 1, "v needs"),
}


@pytest.mark.parametrize("case", ERRORS)
def test_errors_name_the_file_and_the_line(tmp_path, case):
    text, line, words = ERRORS[case]
    path = write(tmp_path, text)
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    error = caught.value
    assert isinstance(error, ValueError)
    assert (error.path, error.line) == (str(path), line)
    assert str(error).startswith(f"{path}:{line}: ")
    assert words in str(error)
    assert "\n" not in str(error)


def test_bad_texture_and_normal_references_only_drop_those_attributes(tmp_path):
    mesh = load(tmp_path, SQUARE + "vt 0 0\nvn 0 0 1\nf 1/1/1 2/5/1 3/1/1\nf 1/1/-3 3/1/1 4/1/1\n")
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    path = tmp_path / "m.obj"
    assert mesh.warnings == (
        f"{path}:7: texture coordinate index 5 in '2/5/1' is out of range: the file has 1 vt "
        "line; texture coordinates ignored in 1 face",
        f"{path}:8: relative normal index -3 in '1/1/-3' points before the first vn (only 1 "
        "above this line); normals ignored in 1 face",
    )
    np.testing.assert_array_equal(mesh.texcoords, [[0, 0], [0, 0], [0, 0], [0, 0]])


@pytest.mark.parametrize("text", ["", "# only a comment\n\n", "v 0 0 0\nv 1 1 1\nvn 0 0 1\n",
                                  SQUARE + "p 1 2 3\n", "g group\ns 1\nusemtl x\n"],
                         ids=["empty", "comments", "point cloud", "points", "names only"])
def test_a_file_without_faces_or_lines_is_an_error(tmp_path, text):
    path = write(tmp_path, text)
    with pytest.raises(ObjError, match="no faces or lines") as caught:
        load_obj(path)
    assert caught.value.line is None
    assert str(caught.value).startswith(f"{path}: no faces or lines")


def test_a_missing_file_cannot_be_read(tmp_path):
    path = tmp_path / "nowhere.obj"
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert str(caught.value) == f"{path}: cannot read: No such file or directory"
    assert (caught.value.path, caught.value.line) == (str(path), None)


def test_a_directory_cannot_be_read(tmp_path):
    with pytest.raises(ObjError) as caught:
        load_obj(tmp_path)
    assert str(caught.value) == f"{tmp_path}: not a regular file (a directory)"


@pytest.mark.parametrize("data, line, words", [
    (SQUARE.encode() + b"f 1 2\x00 3\n", 5, "NUL byte"),
    (("\ufeff" + SQUARE + "f 1 2 3\n").encode("utf-16-le"), 1, "UTF-16"),
    ((SQUARE + "f 1 2 3\n").encode("utf-16-be"), 1, "NUL byte"),
    (("\ufeff" + SQUARE).encode("utf-32"), 1, "UTF-32"),
    (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", 3, "binary data"),
], ids=["nul", "utf-16 le", "utf-16 be without bom", "utf-32", "png"])
def test_binary_or_wide_text_is_an_error(tmp_path, data, line, words):
    path = write(tmp_path, data)
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert caught.value.line == line and words in str(caught.value)


def test_a_file_whose_every_polygon_has_a_nan_corner_loads_with_no_triangles(tmp_path):
    """Found by the long fuzz run: every quad dropped left nothing to merge into polygon order."""
    mesh = load(tmp_path, "v 0 0 0\nv 1 nan 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nl 1 3\n")
    assert mesh.faces.shape == (0, 3)
    assert any("NaN or infinite" in w for w in mesh.warnings)
