"""read_off on OFF files made here: the keywords and where the counts are, comments, polygons
(concave ones covered exactly, their own sides as edges), colours per vertex and per face,
normals and texture coordinates, and the errors with their lines."""

import pickle

import numpy as np
import pytest

from rasterkit.limits import LimitError
from rasterkit.off import OffError, OffLimitError, read_off, sniff

CUBE = """OFF
8 6 12
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 1 2 6 5
4 2 3 7 6
4 3 0 4 7
"""
CUBE_EDGES = [[0, 1], [0, 3], [0, 4], [1, 2], [1, 5], [2, 3], [2, 6], [3, 7], [4, 5], [4, 7], [5, 6], [6, 7]]


def read(text, name="t.off"):
    return read_off(name, data=text.encode() if isinstance(text, str) else text)


def fails(text, line, words):
    with pytest.raises(OffError) as info:
        read(text)
    e = info.value
    assert (e.line, e.path) == (line, "t.off") and words in e.reason, str(e)
    assert str(e) == (f"t.off:{line}: {e.reason}" if line else f"t.off: {e.reason}") and "\n" not in str(e)


def area(mesh):
    v = mesh.vertices[mesh.faces]
    return 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum()


def test_a_cube_of_quads_is_twelve_triangles_with_the_quads_own_edges():
    mesh = read(CUBE)
    assert mesh.vertices.tolist()[:2] == [[0, 0, 0], [1, 0, 0]] and mesh.faces.shape == (12, 3)
    assert mesh.edges.tolist() == CUBE_EDGES and mesh.warnings == ()
    assert np.isclose(area(mesh), 6.0)
    # the winding of each quad is kept: the first one faces -z
    v = mesh.vertices[mesh.faces[0]]
    assert np.cross(v[1] - v[0], v[2] - v[0])[2] < 0


@pytest.mark.parametrize("header", ["OFF\n8 6 12\n", "OFF 8 6 12\n", "OFF8 6 12\n", "8 6 12\n", "OFF\n8 6\n",
                                    "# made by hand\n\nOFF # the keyword\n  \n# counts:\n8 6 0 # no edges\n",
                                    "\ufeffOFF\r\n8 6 12\r\n", "nOFF\n3\n8 6 12\n", "nOFF 3 8 6 12\n"])
def test_the_keyword_and_counts_wherever_they_are(header):
    mesh = read(header + CUBE.split("\n", 2)[2].replace("\n", "\r\n" if "\r" in header else "\n"))
    assert mesh.edges.tolist() == CUBE_EDGES and mesh.warnings == ()


def test_comments_and_blank_lines_anywhere():
    text = CUBE.replace("1 1 0\n", "1 1 0 # a comment\n\n# a line of its own\n").replace("4 1 2 6 5", "4 1 2 6 5#x")
    assert read(text).edges.tolist() == CUBE_EDGES


def test_a_concave_polygon_is_covered_exactly_and_keeps_its_sides():
    text = "OFF\n6 1 0\n0 0 0\n4 0 0\n4 4 0\n2 1 0\n0 4 0\n-1 2 0\n6 0 1 2 3 4 5\n"
    mesh = read(text)
    assert mesh.faces.shape == (4, 3) and np.isclose(area(mesh), 16 - 6 + 2)
    assert mesh.edges.tolist() == [[0, 1], [0, 5], [1, 2], [2, 3], [3, 4], [4, 5]]


def test_triangles_with_a_repeated_vertex_are_left_out():
    mesh = read("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n4 1 3 3 2\n")
    assert mesh.faces.tolist() == [[0, 1, 2], [1, 3, 2]]


@pytest.mark.parametrize("colour, rgb", [("255 0 0", [1, 0, 0]), ("1 0 0", [1 / 255, 0, 0]),
                                         ("1.0 0 0", [1, 0, 0]), ("0.5 0.25 1", [0.5, 0.25, 1]),
                                         ("0 128 255 255", [0, 128 / 255, 1]), ("1 0.5 0 0.7", [1, 0.5, 0]),
                                         ("2.0 0 0", [2 / 255, 0, 0])])
def test_face_colours_are_0_255_when_written_as_integers_or_above_1(colour, rgb):
    mesh = read(CUBE.replace("4 0 3 2 1", f"4 0 3 2 1 {colour}").replace("4 1 2 6 5", f"4 1 2 6 5 {colour}"))
    assert mesh.face_colors.dtype == np.float32
    assert np.allclose(mesh.face_colors[[0, 1, 6, 7]], rgb)
    assert np.allclose(mesh.face_colors[2], 0.8) and "4 of 6 faces have no colour" in mesh.warnings[0]


def test_colours_out_of_range_are_clipped_and_nan_is_the_default_with_warnings():
    text = CUBE
    for k, colour in enumerate(["300 0 0", "-5 10 20", "nan 0 0", "0 0 0", "10 20 30", "1 2 3"]):
        text = text.replace(["4 0 3 2 1", "4 4 5 6 7", "4 0 1 5 4", "4 1 2 6 5", "4 2 3 7 6", "4 3 0 4 7"][k],
                            ["4 0 3 2 1", "4 4 5 6 7", "4 0 1 5 4", "4 1 2 6 5", "4 2 3 7 6", "4 3 0 4 7"][k] + " " + colour)
    mesh = read(text)
    assert np.allclose(mesh.face_colors[::2], [[1, 0, 0], [0, 10 / 255, 20 / 255], [0.8, 0.8, 0.8], [0, 0, 0],
                                               [10 / 255, 20 / 255, 30 / 255], [1 / 255, 2 / 255, 3 / 255]])
    assert [w.split(": ", 1)[1] for w in mesh.warnings] == [
        "2 face colours outside 0..255: clipped", "1 face colour with NaN or infinite values: drawn in the default colour"]


def test_a_colour_map_index_is_ignored_with_a_warning():
    mesh = read(CUBE.replace("4 0 3 2 1", "4 0 3 2 1 7"))
    assert mesh.face_colors is None and "1 face has 1 or 2 numbers after its vertex indices" in mesh.warnings[0]


def test_coff_vertex_colours_and_extra_numbers_on_plain_off_vertices():
    coff = CUBE.replace("OFF", "COFF")
    for k, line in enumerate(coff.splitlines()[2:10]):
        coff = coff.replace(f"\n{line}\n", f"\n{line} {k * 32} 0 255 255\n", 1)
    mesh = read(coff)
    assert np.allclose(mesh.vertex_colors[:, 0], np.arange(8) * 32 / 255) and np.all(mesh.vertex_colors[:, 2] == 1)
    plain = CUBE.replace("0 0 0\n1 0 0\n", "0 0 0 1.0 0 0\n1 0 0 0 1 0 1\n")  # one float: 0..1
    mesh = read(plain)
    assert mesh.vertex_colors[:2].tolist() == [[1, 0, 0], [0, 1, 0]]
    assert np.allclose(mesh.vertex_colors[2:], 0.8) and "6 of 8 vertices have no colour" in mesh.warnings[0]


def test_noff_normals_and_stoff_texture_coordinates():
    lines = CUBE.splitlines()
    vertices = [f"{v} 0 0 {2 * k - 7} {k / 8} {1 - k / 8}" for k, v in enumerate(lines[2:10])]
    mesh = read("\n".join(["STNOFF", lines[1], *vertices, *lines[10:]]) + "\n")
    assert np.allclose(mesh.normals, [[0, 0, np.sign(2 * k - 7)] for k in range(8)])
    assert np.allclose(mesh.texcoords, [[k / 8, 1 - k / 8] for k in range(8)]) and np.array_equal(mesh.uv, mesh.texcoords)
    assert mesh.edges.tolist() == CUBE_EDGES


def test_nan_vertices_drop_the_faces_that_use_them():
    mesh = read(CUBE.replace("1 1 1\n", "nan 1 1\n"))
    assert len(mesh.faces) == 6 and "1 vertex with NaN or infinite coordinates; 3 faces using it dropped" in \
        mesh.warnings[0]
    assert [6, 7] not in mesh.edges.tolist()


def test_no_faces_is_a_point_cloud_and_lines_after_the_faces_are_a_warning():
    mesh = read("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n")
    assert mesh.faces.shape == (0, 3) and len(mesh.vertices) == 3 and "a point cloud" in mesh.warnings[0]
    mesh = read(CUBE + "1 2 3\n4 5 6\n")
    assert "2 lines after the 6 faces ignored (the first: line 17)" in mesh.warnings[0]


@pytest.mark.parametrize("text, line, words", [
    ("OFF BINARY\n8 6 12\n", 1, "binary OFF (OFF BINARY) is not supported"),
    ("4OFF\n8 6 12\n", 1, "4OFF (homogeneous 4D vertices) is not supported"),
    ("nOFF\n4\n8 6 12\n", 2, "nOFF with vertices of 4 dimensions is not supported"),
    ("XOFF\n8 6 12\n", 1, "expected the keyword OFF (or COFF, NOFF, STOFF...) or the counts, got 'XOFF'"),
    ("OFFx 6 12\n", 1, "unknown keyword 'OFFx'"),
    ("OFF\n8\n", 2, "expected the counts NVertices NFaces [NEdges], got 1 numbers"),
    ("OFF\n8 6 12 5\n", 2, "got 4 numbers"),
    ("OFF\n8 -6 12\n", 2, "expected a count, got '-6'"),
    ("OFF\n", 1, "got the end of the file"),
    ("OFF\n80 6 12\n0 0 0\n", 2, "the header says 80 vertices and 6 faces, but only 1 lines of numbers follow it"),
    (CUBE.replace("1 1 0\n", "1 1\n"), 5, "a vertex line has 2 numbers; the vertices of this OFF file have 3 (x y z), "
                                           "or 3 or 4 more with a colour"),
    (CUBE.replace("1 1 0\n", "1 1 x\n"), 5, "expected a number, got 'x'"),
    (CUBE.replace("4 1 2 6 5", "4 1 2 6 8"), 14, "vertex index 8 is out of range: the file has 8 vertices"),
    (CUBE.replace("4 1 2 6 5", "4 1 2 -1 5"), 14, "vertex index -1 is out of range"),
    (CUBE.replace("4 1 2 6 5", "4 1 2 6.0 5"), 14, "expected a vertex index, got '6.0'"),
    (CUBE.replace("4 1 2 6 5", "2 1 2"), 14, "a face of 2 vertices (at least 3)"),
    (CUBE.replace("4 1 2 6 5", "5 1 2 6 5"), 14, "a face of 5 vertices, but only 4 numbers follow"),
    (CUBE.replace("4 1 2 6 5", "999999999999999999 1 2 6 5"), 14, "a face of 999999999999999999 vertices"),
    (CUBE.replace("4 1 2 6 5", "99999999999999999999 1 2 6 5"), 14, "expected the number of vertices of a face"),
    (CUBE.replace("4 1 2 6 5", "4 1 2 6 5 1 2 3 4 5"), 14, "5 numbers after the 4 vertex indices of a face"),
    (CUBE.replace("4 1 2 6 5", "4 1 2 6 5 1 0 x"), 14, "expected a number, got 'x'"),
    ("", None, "an empty file"),
    ("# only a comment\n\n", None, "an empty file"),
])
def test_errors_name_their_line(text, line, words):
    fails(text, line, words)


def test_errors_pickle_and_limit_errors_are_limit_errors():
    for error in (OffError("a.off", 3, "bad"), OffError("a.off", None, "bad"), OffLimitError("a.off", None, "big")):
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is type(error) and str(again) == str(error) and again.line == error.line
    assert isinstance(OffLimitError("a", None, "x"), LimitError)


@pytest.mark.parametrize("head, expected", [(b"OFF\n8 6 12\n", True), (b"COFF\n", True), (b"OFF1234 56 0\n", True),
                                            (b"# c\nSTCNOFF 8 6 0\n", True), (b"8 6 12\n0 0 0\n", True),
                                            (b"solid x\n", False), (b"ply\n", False), (b"v 0 0 0\n", False),
                                            (b"OFFICE 1 2\n", False), (b"8 6\nfoo\n", False), (b"", False)])
def test_sniff(head, expected):
    assert sniff(head) == expected
