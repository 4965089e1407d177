"""read_ply on small files written by the tests (tests/support/plyfiles.py, with struct and
repr: independent of the reader), in all three encodings: what each property becomes."""

import math
import struct

import numpy as np
import pytest

from rasterkit.mesh import Mesh
from rasterkit.ply import PointCloud, read_ply, sniff
from support.plyfiles import CODES, FACES, SQUARE, XYZ, body, header, ply_bytes, square, write_ply

ENCODINGS = ("ascii", "binary_little_endian", "binary_big_endian")

#: A value of each type at the edge of its range, and one inside it.
EXTREMES = {"char": (-128, 127), "uchar": (0, 255), "short": (-32768, 32767), "ushort": (0, 65535),
            "int": (-2**31, 2**31 - 1), "uint": (0, 2**32 - 1), "float": (-3.5, 1.25e-30),
            "double": (0.1, -1e300)}
NEW_NAMES = {"char": "int8", "uchar": "uint8", "short": "int16", "ushort": "uint16", "int": "int32",
             "uint": "uint32", "float": "float32", "double": "float64"}


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def stored(value, kind):
    """What the file holds for ``value`` of type ``kind``: float32 rounds (ASCII text too)."""
    return f32(value) if kind in ("float", "float32") else value


@pytest.mark.parametrize("encoding", ENCODINGS)
@pytest.mark.parametrize("kind", list(EXTREMES) + list(NEW_NAMES.values()))
def test_positions_of_every_scalar_type_by_both_names(tmp_path, encoding, kind):
    old = {v: k for k, v in NEW_NAMES.items()}.get(kind, kind)
    low, high = EXTREMES[old]
    rows = [(low, high, 0), (high, 0, low), (0, low, high)]
    # an unknown property of every other type between them, so that their sizes count
    others = [t for t in EXTREMES if t != old]
    props = [(kind, "x"), (others[0], "a"), (kind, "y"), (others[1], "b"), (kind, "z")] + [
        (t, f"extra_{t}") for t in others[2:]]
    fill = lambda t: EXTREMES[t][1]  # noqa: E731
    vertex_rows = [(r[0], fill(others[0]), r[1], fill(others[1]), r[2], *[fill(t) for t in others[2:]])
                   for r in rows]
    path = write_ply(tmp_path / "types.ply", encoding, [("vertex", props, vertex_rows)])
    cloud = read_ply(path)
    assert isinstance(cloud, PointCloud)
    want = [[stored(v, kind) for v in r] for r in rows]
    assert cloud.points.dtype == np.float64
    assert cloud.points.tolist() == want


@pytest.mark.parametrize("encoding", ENCODINGS)
@pytest.mark.parametrize("count_type", ["uchar", "char", "ushort", "short", "uint", "int", "uint8", "int32"])
@pytest.mark.parametrize("item_type", ["uchar", "ushort", "short", "uint", "int", "int16", "uint32"])
def test_face_lists_of_every_count_and_index_type(tmp_path, encoding, count_type, item_type):
    elements = [("vertex", XYZ, SQUARE),
                ("face", [("list", count_type, item_type, "vertex_indices")], [([0, 1, 2],), ([0, 2, 3],)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.vertices.tolist() == [list(map(float, v)) for v in SQUARE]


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_the_three_encodings_read_the_same(tmp_path, encoding):
    elements = [("vertex", XYZ + [("uchar", "red"), ("uchar", "green"), ("uchar", "blue")],
                 [(0.5, -1.0, 2.0, 255, 0, 51), (1.0, 0.0, 0.0, 0, 128, 0), (0.0, 1.0, 0.25, 1, 2, 3)]),
                ("face", FACES, [([0, 1, 2],)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert mesh.vertices.tolist() == [[0.5, -1, 2], [1, 0, 0], [0, 1, 0.25]]
    np.testing.assert_array_equal(mesh.vertex_colors, np.float32([[255, 0, 51], [0, 128, 0], [1, 2, 3]]) / 255)
    assert mesh.vertex_colors.dtype == np.float32
    assert mesh.warnings == ()


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_unknown_elements_and_properties_are_skipped_wherever_they_are(tmp_path, encoding):
    """Elements before, between and after, unknown lists of varying length in the vertex
    and face rows (before and after the indices): the rows of every element are walked."""
    elements = [
        ("material", [("float", "ambient"), ("list", "uchar", "double", "name")], [(0.5, [1.0, 2.0]), (1.5, [])]),
        ("vertex", [("list", "ushort", "float", "junk"), ("float", "x"), ("double", "y"), ("float", "z"),
                    ("list", "uchar", "uchar", "more")],
         [([], 0, 0, 0, [1]), ([1.0, 2.0, 3.0], 1, 0, 0, []), ([9.0], 1, 1, 0, [2, 3]), ([], 0, 1, 0, [4])]),
        ("between", [("int", "a")], [(7,)]),
        ("face", [("list", "int", "float", "before"), ("uchar", "flags"), ("list", "uchar", "int", "vertex_indices"),
                  ("list", "uint", "short", "after"), ("float", "quality")],
         [([1.0], 3, [0, 1, 2], [], 0.5), ([], 4, [0, 2, 3], [5, 6, 7], 1.5)]),
        ("after", [("list", "uchar", "int", "x")], [([1, 2],)]),
    ]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert mesh.vertices.tolist() == [list(map(float, v)) for v in SQUARE]
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert len(mesh.warnings) == 1
    assert mesh.warnings[0] == (f"{tmp_path / 't.ply'}:3: skipped 3 elements the reader does not know: 'material' "
                                "(2 rows), 'between' (1 row), 'after' (1 row)")


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_faces_of_mixed_sizes_are_split_and_keep_their_sides(tmp_path, encoding):
    vertices = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (1, 1, 0), (0, 2, 0), (3, 0, 0), (3, 1, 0)]
    # a concave pentagon (an arrow head: corner 3 points in), a triangle, a degenerate triangle
    faces = [([0, 1, 2, 3, 4],), ([1, 5, 6],), ([1, 1, 5],), ([1, 5, 6, 2],)]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, [("vertex", XYZ, vertices), ("face", FACES, faces)]))
    v = mesh.vertices[:, :2]
    tri = v[mesh.faces]
    signed = 0.5 * ((tri[:, 1, 0] - tri[:, 0, 0]) * (tri[:, 2, 1] - tri[:, 0, 1])
                    - (tri[:, 1, 1] - tri[:, 0, 1]) * (tri[:, 2, 0] - tri[:, 0, 0]))
    assert (signed > 0).all()  # the file's winding (counter-clockwise), no sliver flipped
    # pentagon: 3 triangles covering its area exactly (shoelace: 3); triangle: 0.5; quad 1-5-6-2: 2 triangles
    assert len(mesh.faces) == 3 + 1 + 2
    assert math.isclose(signed[:3].sum(), 3.0) and math.isclose(signed[3], 0.5)
    assert math.isclose(signed[4:].sum(), 1.5)  # the quad (2, 0) (3, 0) (3, 1) (2, 2), by the shoelace formula
    sides = {tuple(sorted(p)) for f, in faces for p in zip(f, f[1:] + f[:1]) if p[0] != p[1]}
    assert sorted(map(tuple, mesh.edges.tolist())) == sorted(sides)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_a_quad_mesh_is_split_into_fans(tmp_path, encoding):
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, square(encoding, [(0, 1, 2, 3)] * 3)))
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]] * 3
    assert mesh.edges.tolist() == [[0, 1], [0, 3], [1, 2], [2, 3]]


def test_degenerate_triangles_are_left_out_as_in_obj_files(tmp_path):
    faces = [(0, 1, 2), (0, 0, 1), (2, 3, 3), (0, 2, 3)]
    mesh = read_ply(write_ply(tmp_path / "t.ply", "ascii", square("ascii", faces)))
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.edges.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_faces_at_a_nan_vertex_are_dropped_with_a_warning(tmp_path, encoding):
    vertices = SQUARE + [(math.nan, 0.0, math.inf)]
    elements = [("vertex", XYZ, vertices), ("face", FACES, [([0, 1, 2],), ([0, 4, 2],), ([0, 2, 3],)])]
    path = write_ply(tmp_path / "t.ply", encoding, elements)
    mesh = read_ply(path)
    assert len(mesh.vertices) == 5 and np.isnan(mesh.vertices[4, 0]) and mesh.vertices[4, 2] == math.inf
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.edges.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    assert mesh.warnings == (f"{path}:7: 1 vertex with NaN or infinite coordinates; 1 face using them dropped",)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_colours_of_every_type_become_0_to_1(tmp_path, encoding):
    props = XYZ + [("ushort", "red"), ("float", "green"), ("char", "blue")]
    rows = [(0, 0, 0, 65535, 0.25, 127), (1, 0, 0, 0, 1.0, 0), (0, 1, 0, 13107, 0.0, 64)]
    elements = [("vertex", props, rows), ("face", FACES + [("uchar", "red"), ("uchar", "green"), ("uchar", "blue")],
                                          [([0, 1, 2], 255, 0, 102)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    np.testing.assert_allclose(mesh.vertex_colors, [[1, 0.25, 1], [0, 1, 0], [0.2, 0, 64 / 127]], rtol=1e-6)
    np.testing.assert_allclose(mesh.face_colors, [[1, 0, 0.4]], rtol=1e-6)
    assert mesh.warnings == ()


def test_float_colours_above_1_are_0_to_255_and_others_are_clamped(tmp_path):
    props = XYZ + [("float", "diffuse_red"), ("float", "diffuse_green"), ("float", "diffuse_blue")]
    path = write_ply(tmp_path / "t.ply", "ascii", [("vertex", props, [(0, 0, 0, 255, 51, 0), (1, 0, 0, -5, 0, 0)])])
    cloud = read_ply(path)
    np.testing.assert_allclose(cloud.colors, [[1, 0.2, 0], [0, 0, 0]], rtol=1e-6)
    assert cloud.warnings == (f"{path}:7: colours of element 'vertex' above 1: all taken as 0 to 255",
                              f"{path}:7: 1 colour of element 'vertex' outside 0 to 1 (or NaN): clamped, NaN "
                              "taken as 1")


@pytest.mark.parametrize("names", [("u", "v"), ("s", "t"), ("texture_u", "texture_v"), ("texture_s", "texture_t")])
def test_vertex_normals_and_texture_coordinates(tmp_path, names):
    props = XYZ + [("float", "nx"), ("float", "ny"), ("float", "nz"), ("float", names[0]), ("double", names[1])]
    rows = [(0, 0, 0, 0, 0, 2, 0.25, 0.5), (1, 0, 0, 3, 4, 0, 1.0, -0.5), (0, 1, 0, 0, 0, 0, 0.5, 0.125)]
    mesh = read_ply(write_ply(tmp_path / "t.ply", "binary_big_endian", [("vertex", props, rows),
                                                                        ("face", FACES, [([0, 1, 2],)])]))
    np.testing.assert_allclose(mesh.normals, [[0, 0, 1], [0.6, 0.8, 0], [0, 0, 0]])
    assert mesh.texcoords.tolist() == [[0.25, 0.5], [1.0, -0.5], [0.5, 0.125]]
    assert mesh.uv.tolist() == mesh.texcoords.tolist() and mesh.uv_index.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize("props", [[("float", "vertex1"), ("int", "vertex2")], [("int", "vertex1")],
                                   [("list", "uchar", "int", "vertex1"), ("int", "vertex2")]])
def test_an_edge_element_without_integer_vertex1_and_vertex2_is_skipped(tmp_path, props):
    rows = [tuple([0] if p[0] == "list" else 0 for p in props)]
    path = write_ply(tmp_path / "t.ply", "ascii", [("vertex", XYZ, SQUARE), ("edge", props, rows)])
    cloud = read_ply(path)
    assert isinstance(cloud, PointCloud) and len(cloud.points) == 4
    assert cloud.warnings == (f"{path}:7: element 'edge' has no integer properties 'vertex1' and 'vertex2': "
                              "skipped",)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_an_edge_element_gives_lines(tmp_path, encoding):
    elements = [("vertex", XYZ, SQUARE), ("edge", [("int", "vertex1"), ("int", "vertex2"), ("uchar", "red")],
                                          [(0, 2, 1), (3, 1, 2)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert isinstance(mesh, Mesh) and len(mesh.faces) == 0
    assert mesh.lines.tolist() == [[0, 2], [3, 1]]
    assert mesh.edges.tolist() == [[0, 2], [1, 3]]


@pytest.mark.parametrize("encoding", ENCODINGS)
@pytest.mark.parametrize("faces", [None, []])
def test_a_file_without_faces_is_a_point_cloud(tmp_path, encoding, faces):
    elements = [("vertex", XYZ + [("uchar", "red"), ("uchar", "green"), ("uchar", "blue"), ("uchar", "alpha"),
                                  ("float", "nx"), ("float", "ny"), ("float", "nz")],
                 [(0, 0, 0, 255, 0, 0, 9, 0, 0, 2), (1, 2, 3, 0, 0, 255, 9, 1, 0, 0)])]
    if faces is not None:
        elements.append(("face", FACES, faces))
    cloud = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert isinstance(cloud, PointCloud)
    assert cloud.points.tolist() == [[0, 0, 0], [1, 2, 3]]
    assert cloud.colors.tolist() == [[1, 0, 0], [0, 0, 1]]
    assert cloud.normals.tolist() == [[0, 0, 1], [1, 0, 0]]
    assert not cloud.points.flags.writeable
    assert repr(cloud) == "PointCloud(2 points, colors, normals)"


def test_a_point_cloud_renders_as_coloured_points(tmp_path):
    import rasterkit

    props = XYZ + [("uchar", "red"), ("uchar", "green"), ("uchar", "blue")]
    cloud = read_ply(write_ply(tmp_path / "t.ply", "binary_little_endian",
                               [("vertex", props, [(-1, 0, 0, 255, 0, 0), (1, 0, 0, 0, 0, 255)])]))
    centre, radius = cloud.bounding_sphere()
    assert centre.tolist() == [0, 0, 0] and radius == 1
    camera = rasterkit.Camera.frame(centre, radius, width=40, height=20)
    fb = rasterkit.render(None, camera, background="black", point_size=3, **cloud.render_arguments())
    colours = {tuple(c) for c in fb.color.reshape(-1, 3).tolist()}
    assert colours == {(0, 0, 0), (255, 0, 0), (0, 0, 255)}
    red = np.argwhere((fb.color == (255, 0, 0)).all(axis=2))
    blue = np.argwhere((fb.color == (0, 0, 255)).all(axis=2))
    assert red[:, 1].max() < blue[:, 1].min()  # x = -1 on the left


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_header_line_breaks_comments_and_blank_lines(tmp_path, encoding):
    elements = square(encoding)
    text = header(encoding, elements, comments=["made by hand", "TextureFile none.png"]).decode()
    text = text.replace("element face", "obj_info anything\n\ncomment é\nelement face").replace("\n", "\r\n")
    text = text.replace("end_header", "end_header  ")
    path = tmp_path / "t.ply"
    path.write_bytes(text.encode() + body(encoding, elements))
    mesh = read_ply(path)
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]
    # TextureFile without texture coordinates: a warning, no material
    assert mesh.warnings == (f"{path}:4: TextureFile given, but no texture coordinates: no texture drawn",)
    assert mesh.materials == ()


def test_ascii_rows_are_a_stream_of_values(tmp_path):
    """Rows split over lines, several rows on a line, tabs and form feeds: the values count."""
    elements = square("ascii", [(0, 1, 2), (0, 2, 3)])
    text = header("ascii", elements) + b"0 0 0 1 0\n0\t1 1 0\r\n0 1\x0c0 3 0 1 2\n3\n0 2 3"
    path = tmp_path / "t.ply"
    path.write_bytes(text)
    mesh = read_ply(path)
    assert mesh.vertices.tolist() == [list(map(float, v)) for v in SQUARE]
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize("text", ["1e-30", "-2.5e+22", "1234567890123456789012", "0.30000000000000004",
                                  "4.9e-324", "1.7976931348623157e308", "1e400", "-1e400", ".5", "5.", "+7", "-0",
                                  "nan", "-inf", "Infinity", "0.1e1", "00012", "1E5", "-NaN", "INF",
                                  "0.000000000000000000000000000001", "123456789012345678.5"])
def test_ascii_numbers_read_as_pythons_float(tmp_path, text):
    path = tmp_path / "t.ply"
    path.write_bytes(header("ascii", [("vertex", [("double", "x"), ("float", "y"), ("float", "z")], [(0, 0, 0)])])
                     + f"{text} 1 {text}\n".encode())
    point = read_ply(path).points[0]
    want = float(text)
    with np.errstate(over="ignore"):
        want32 = float(np.float32(want))  # z is a float: rounded as in a binary file
    assert (np.isnan(point[0]) and math.isnan(want)) or (point[0] == want and math.copysign(1, point[0])
                                                          == math.copysign(1, want))
    assert point[1] == 1
    assert (np.isnan(point[2]) and math.isnan(want)) or (point[2] == want32 and math.copysign(1, point[2])
                                                          == math.copysign(1, want32))


def test_sniff():
    assert sniff(b"ply\nformat ascii 1.0\n") and sniff(b"ply\r\nformat")
    assert not sniff(b"plyx\n") and not sniff(b"PLY\n") and not sniff(b"ply") and not sniff(b"solid ply\n")


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_the_codes_of_the_test_writer_round_trip(encoding):
    """The test writer itself: struct's codes are the types' sizes."""
    sizes = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}
    for old, new in NEW_NAMES.items():
        assert struct.calcsize("<" + CODES[old]) == struct.calcsize("<" + CODES[new]) == sizes[old]
    data = ply_bytes(encoding, square(encoding))
    assert data.startswith(b"ply\nformat " + encoding.encode() + b" 1.0\n")


@pytest.mark.parametrize("encoding", ["binary_little_endian", "binary_big_endian"])
def test_signalling_nans_and_infinities_read_without_a_numpy_warning(tmp_path, encoding):
    """A float32 signalling NaN (found by the fuzzer) sets the invalid flag when converted."""
    import warnings

    order = "<" if encoding == "binary_little_endian" else ">"
    elements = [("vertex", XYZ + [("float", "red"), ("float", "green"), ("float", "blue")], [(0, 0, 0, 0, 0, 0)])]
    data = ply_bytes(encoding, elements)
    snan, inf = struct.pack(order + "I", 0x7F800001), struct.pack(order + "f", math.inf)
    path = tmp_path / "t.ply"
    path.write_bytes(data[:-24] + snan + inf + snan + snan + inf + snan)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cloud = read_ply(path)
    assert np.isnan(cloud.points[0, 0]) and cloud.points[0, 1] == math.inf
    assert cloud.colors.tolist() == [[1, 1, 1]]  # NaN and inf colours: white, with a warning
    assert len(cloud.warnings) == 2


@pytest.mark.parametrize("text, value", [("1.#IND", math.nan), ("-1.#IND00", math.nan), ("1.#QNAN", math.nan),
                                         ("1.#INF", math.inf), ("-1.#INF", -math.inf), ("1.#SNAN", math.nan)])
def test_msvcs_nan_and_infinity(tmp_path, text, value):
    path = tmp_path / "t.ply"
    path.write_bytes(header("ascii", [("vertex", [("double", "x"), ("double", "y"), ("double", "z")], [(0, 0, 0)])])
                     + f"{text} 1 2\n".encode())
    x = read_ply(path).points[0, 0]
    assert (math.isnan(x) and math.isnan(value)) or x == value


def test_many_unusual_numbers_are_read_at_once(tmp_path):
    """Tokens the kernel leaves to NumPy (long, large exponents, nan): one conversion of all."""
    rng = np.random.default_rng(5)
    values = rng.standard_normal(3000) * 10.0 ** rng.integers(-300, 300, 3000)
    values[::7] = np.nan
    texts = [repr(float(v)) for v in values]
    path = tmp_path / "t.ply"
    path.write_bytes(header("ascii", [("vertex", [("double", "x"), ("double", "y"), ("double", "z")], [(0, 0, 0)] *
                                       1000)]) + " ".join(texts).encode())
    points = read_ply(path).points.reshape(-1)
    np.testing.assert_array_equal(points, values)


def test_optional_properties_that_are_lists_are_skipped_with_a_warning(tmp_path):
    props = XYZ + [("list", "uchar", "uchar", "red"), ("uchar", "green"), ("uchar", "blue"), ("float", "u"),
                   ("float", "v")]
    path = write_ply(tmp_path / "t.ply", "binary_little_endian", [("vertex", props, [(0, 1, 2, [9], 3, 4, 0.5, 1)])])
    cloud = read_ply(path)
    assert cloud.points.tolist() == [[0, 1, 2]] and cloud.colors is None
    assert cloud.warnings == (f"{path}:7: property 'red' of element 'vertex' must be a scalar, not a list: skipped",)


@pytest.mark.parametrize("module", ["rasterkit.ply", "rasterkit.ply.cloud"])
def test_docstring_examples(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0 and result.failed == 0


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_faces_before_the_vertices_and_a_property_named_twice(tmp_path, encoding):
    """Elements are read in the header's order, whatever it is; the first of two properties
    of one name is the one read."""
    elements = [("face", FACES, [([0, 1, 2],)]),
                ("vertex", [("float", "x"), ("float", "y"), ("double", "x"), ("float", "z")],
                 [(0, 0, 9, 0), (1, 0, 9, 0), (0, 1, 9, 0)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", encoding, elements))
    assert mesh.faces.tolist() == [[0, 1, 2]]
    assert mesh.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


@pytest.mark.parametrize("encoding, corners", [(e, 3) for e in ENCODINGS] + [("binary_little_endian", 4)])
def test_memory_peaks_below_three_times_the_meshs_arrays(tmp_path, encoding, corners):
    """Issue 28's bound, besides the file's bytes: reading (the body's values, the polygons,
    the sorted edges of quads) and the Mesh's own copies stay within 3x the Mesh's arrays
    (a Mesh of triangles has no edges yet: it works them out on first use). (Not for ASCII
    quads of this size, 3.4x: the OBJ splitter's chunks of 32768 quads and the body's numbers
    together; 2.7x at 500k quads.)"""
    import tracemalloc

    from rasterkit.ply import _read

    side = 300
    u, v = np.meshgrid(np.arange(side), np.arange(side))
    vertices = [(float(x), float(y), 0.0) for x, y in zip(u.ravel(), v.ravel())]
    a = (np.arange(side - 1)[:, None] * side + np.arange(side - 1)).ravel()
    quads = np.stack([a, a + 1, a + side + 1, a + side], axis=1).tolist()
    faces = quads if corners == 4 else [q[:3] for q in quads] + [[q[0], q[2], q[3]] for q in quads]
    elements = [("vertex", XYZ, vertices), ("face", FACES, [(f,) for f in faces])]
    path = write_ply(tmp_path / "grid.ply", encoding, elements)
    data = path.read_bytes()
    _read(str(path), data, True)  # kernels compiled or loaded outside the measurement
    tracemalloc.start()
    try:
        mesh = _read(str(path), data, True)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= 3 * mesh.nbytes, (peak, mesh.nbytes)
