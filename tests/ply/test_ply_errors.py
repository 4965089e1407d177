"""read_ply on broken and hostile files: each ends in one PlyError of one line that starts
with the file's name and says where (header line, ASCII line and row, binary row and byte),
raised before anything is allocated for counts the file cannot hold."""

import os
import pickle
import socket
import stat
import struct

import pytest

from rasterkit import limits
from rasterkit.limits import LimitError
from rasterkit.ply import PlyError, PlyLimitError, read_ply
from support.hostile import run_python
from support.plyfiles import FACES, XYZ, header, ply_bytes, square

ENCODINGS = ("ascii", "binary_little_endian", "binary_big_endian")


def fails(tmp_path, data: bytes, name="bad.ply") -> PlyError:
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(PlyError) as caught:
        read_ply(path)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(f"{path}")
    return caught.value


def message(tmp_path, data: bytes) -> str:
    """The error's text after the file's name."""
    error = fails(tmp_path, data)
    return str(error)[len(str(tmp_path / "bad.ply")):]


def two_faces(encoding):
    return square(encoding, [(0, 1, 2, 3), (0, 1, 2)])


# --- the header --------------------------------------------------------------------------------

@pytest.mark.parametrize("data, expected", [
    (b"", ":1: not a PLY file: it starts with b'', not 'ply' and a line break"),
    (b"solid cube\n", ":1: not a PLY file: it starts with b'solid cube', not 'ply' and a line break"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
     ": the header has no 'end_header' line (not a PLY file, or cut short)"),
    (b"ply\nformat ascii 2.0\nend_header\n", ":2: version '2.0' is not read (only 1.0)"),
    (b"ply\nformat text 1.0\nend_header\n",
     ":2: unknown format 'text' (expected ascii, binary_little_endian, binary_big_endian)"),
    (b"ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n", ":3: a second 'format' line"),
    (b"ply\nelement vertex 1\nend_header\n", ":2: no 'format' line"),
    (b"ply\nformat ascii 1.0\nproperty float x\nend_header\n", ":3: a property before any element"),
    (b"ply\nformat ascii 1.0\nelement vertex -4\nend_header\n",
     ":3: the count of element 'vertex' must be a whole number >= 0, got '-4'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1e3\nend_header\n",
     ":3: the count of element 'vertex' must be a whole number >= 0, got '1e3'"),
    (b"ply\nformat ascii 1.0\nelement vertex " + b"9" * 5000 + b"\nend_header\n",
     ":3: the count of element 'vertex' is too large (5000 digits)"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n",
     ":4: element 'vertex' is declared twice"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float32 x y\nend_header\n",
     ":4: expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty int64 x\nend_header\n",
     ":4: unknown type 'int64' (expected one of char, int8, uchar, uint8, short, int16, ushort, uint16, int, int32, "
     "uint, uint32, float, float32, double, float64)"),
    (b"ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
     ":4: the count type of list 'vertex_indices' must be an integer type, got 'float'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float \xff\nend_header\n",
     ":4: the header line b'property float \\xff' is not UTF-8 text"),
    (b"ply\nformat ascii 1.0\nvertex 1\nend_header\n",
     ":3: unknown header line 'vertex 1' (expected format, element, property, comment, obj_info or end_header)"),
    (b"ply\nformat ascii 1.0\nend_header\n", ": no element 'vertex'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
     ":3: element 'vertex' has no property 'z'"),
    (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty list uchar float z\n"
     b"end_header\n0 0 1 0\n", ":6: property 'z' of element 'vertex' must be a scalar, not a list"),
    (header("ascii", [("vertex", XYZ, []), ("face", [("list", "uchar", "float", "vertex_indices")], [])]),
     ":8: property 'vertex_indices' of element 'face' must be a list of integers"),
    (header("ascii", [("vertex", XYZ, []), ("face", [("list", "uchar", "int", "corners")], [])]),
     ":7: element 'face' has no property 'vertex_indices' (or 'vertex_index')"),
    (header("ascii", [("vertex", XYZ, [])]), ":3: no vertices: nothing to draw"),
])
def test_header_errors_name_the_line(tmp_path, data, expected):
    assert message(tmp_path, data) == expected


def test_non_utf8_comments_are_fine(tmp_path):
    path = tmp_path / "c.ply"
    path.write_bytes(ply_bytes("ascii", square("ascii")).replace(b"element vertex", b"comment caf\xe9 \xff\nobj_info "
                                                                                    b"\x00\x80\nelement vertex"))
    assert len(read_ply(path).faces) == 2


# --- the body: counts against the bytes left ------------------------------------------------------

@pytest.mark.parametrize("encoding, expected", [
    ("ascii", ":10: element 'vertex' declares 4000000000000 rows of at least 3 values: more than the 21 values left "
              "in the file"),
    ("binary_little_endian", ": byte 169: element 'vertex' declares 4000000000000 rows of at least 12 bytes: more "
                             "than the 78 bytes left in the file"),
])
def test_a_count_larger_than_the_file_fails_before_anything_is_allocated(tmp_path, encoding, expected):
    data = ply_bytes(encoding, two_faces(encoding)).replace(b"vertex 4", b"vertex 4000000000000")
    assert message(tmp_path, data).replace("181", "169") == expected


def test_counts_larger_than_the_file_in_a_child_with_little_memory(tmp_path):
    """No allocation from the header: 10**15 faces of at least 1 byte, 17 bytes left, under a
    limit of the address space far below what trusting the count would take."""
    path = tmp_path / "huge.ply"
    path.write_bytes(ply_bytes("binary_little_endian", square("binary_little_endian")).replace(b"face 1", b"face "
                                                                                              + b"9" * 15))
    outcome = run_python(f"""
        from rasterkit.ply import read_ply, PlyError
        try:
            read_ply({str(path)!r})
        except PlyError as e:
            print(e)
    """, timeout=120)
    assert outcome.code == 0, outcome.describe()
    assert outcome.stdout.strip().endswith("element 'face' declares 999999999999999 rows of at least 1 byte: more "
                                           "than the 17 bytes left in the file")


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_a_truncated_body(tmp_path, encoding):
    data = ply_bytes(encoding, two_faces(encoding))
    text = message(tmp_path, data[:-3])
    if encoding == "ascii":
        assert text == ":15: element 'face' row 1: the count 3 of list 'vertex_indices' goes past the end of the file"
    else:
        at = len(data) - 13
        assert text == f": element 'face' row 1 (byte {at}): the count 3 of list 'vertex_indices' goes past the end " \
                       "of the file"


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_one_row_more_in_the_header_than_in_the_body(tmp_path, encoding):
    data = ply_bytes(encoding, two_faces(encoding)).replace(b"face 2", b"face 3")
    text = message(tmp_path, data)
    if encoding == "ascii":
        assert text == ":16: element 'face' row 2: the file ends inside the row (the header declares 3 rows)"
    else:
        assert text == f": element 'face' row 2 (byte {len(data)}): the file ends inside the row (the header " \
                       "declares 3 rows)"


def test_scalars_after_the_list_cut_short(tmp_path):
    elements = [("vertex", XYZ, [(0, 0, 0)] * 3),
                ("face", FACES + [("double", "quality")], [([0, 1, 2], 1.0), ([0, 1, 2, 0], 2.0)])]
    data = ply_bytes("binary_little_endian", elements)
    assert message(tmp_path, data[:-1]) == (f": element 'face' row 1 (byte {len(data) - 25}): the file ends inside the "
                                            "row (the header declares 2 rows)")


@pytest.mark.parametrize("count_type, code, value, reason", [
    ("uint", "I", 4_000_000_000, "the count 4000000000 of list 'vertex_indices' goes past the end of the file"),
    ("int", "i", -1, "the count -1 of list 'vertex_indices' is negative"),
    ("char", "b", -128, "the count -128 of list 'vertex_indices' is negative"),
    ("ushort", "H", 65535, "the count 65535 of list 'vertex_indices' goes past the end of the file"),
])
@pytest.mark.parametrize("order", ["<", ">"])
def test_binary_list_counts_huge_or_negative(tmp_path, count_type, code, value, reason, order):
    encoding = "binary_little_endian" if order == "<" else "binary_big_endian"
    faces = [("list", count_type, "int", "vertex_indices")]
    elements = [("vertex", XYZ, [(0, 0, 0)] * 3), ("face", faces, [([0, 1, 2],), ([0, 1, 2],)])]
    data = ply_bytes(encoding, elements)
    at = len(header(encoding, elements)) + 36 + struct.calcsize(code) + 12  # row 1's count
    data = data[:at] + struct.pack(order + code, value) + data[at + struct.calcsize(code):]
    assert message(tmp_path, data) == f": element 'face' row 1 (byte {at}): {reason}"


@pytest.mark.parametrize("row, reason", [
    ("-4 0 1 2 3", "the count -4 of list 'vertex_indices' is no whole number >= 0"),
    ("4.5 0 1 2 3", "the count 4.5 of list 'vertex_indices' is no whole number >= 0"),
    ("nan 0 1 2 3", "the count nan of list 'vertex_indices' is no whole number >= 0"),
    ("99999999999999999999 0 1 2 3", "the count 100000000000000000000 of list 'vertex_indices' goes past the end of "
                                     "the file"),
    ("300 " + "0 " * 300, "the count 300 of list 'vertex_indices' is beyond its type uchar"),
    ("4 0 1 2 9", "vertex index 9 is out of range (the file has 4 vertices)"),
    ("4 0 1 -1 3", "vertex index -1 is out of range (the file has 4 vertices)"),
    ("4 0 1 2 3.5", "property 'vertex_indices' is 3.5, not a whole number from -2147483648 to 2147483647 (int)"),
    ("4 0 1 2 1e10", "property 'vertex_indices' is 10000000000, not a whole number from -2147483648 to 2147483647 "
                     "(int)"),
    ("2 0 1", "a face needs at least 3 vertices, got 2"),
])
def test_ascii_row_errors_name_the_line_and_the_row(tmp_path, row, reason):
    data = ply_bytes("ascii", square("ascii", [(0, 1, 2), (0, 1, 2, 3)]))
    data = data.replace(b"\n4 0 1 2 3", b"\n" + row.encode())
    assert message(tmp_path, data) == f":15: element 'face' row 1: {reason}"


@pytest.mark.parametrize("encoding", ["binary_little_endian", "binary_big_endian"])
def test_binary_index_out_of_range_names_the_row_and_its_byte(tmp_path, encoding):
    elements = [("vertex", XYZ, [(0, 0, 0)] * 3),
                ("face", [("list", "uchar", "uint", "vertex_indices")], [([0, 1, 2],), ([0, 3_000_000_000, 2],)])]
    at = len(header(encoding, elements)) + 36 + 13 + 1 + 4
    assert message(tmp_path, ply_bytes(encoding, elements)) == (
        f": element 'face' row 1 (byte {at}): vertex index 3000000000 is out of range (the file has 3 vertices)")


@pytest.mark.parametrize("token", ["1.x", "1,5", "0x10", "1_000", "--1", "e5", "\u00a0", "\u0663", "#", "1\x002",
                                   "1.#INDx", "nan_", "infinit"])
def test_ascii_values_that_are_no_numbers(tmp_path, token):
    data = ply_bytes("ascii", square("ascii")).replace(b"\n1.0 1.0 0.0", f"\n1.0 {token} 0.0".encode())
    assert message(tmp_path, data) == f":12: {token!r} is not a number"


def test_more_values_after_the_last_element_of_an_ascii_body(tmp_path):
    data = ply_bytes("ascii", two_faces("ascii")) + b"\n3 0 1 2\n"
    assert message(tmp_path, data) == ":17: 4 values after the last element ('face'): the header's counts do not " \
                                      "match the body"


@pytest.mark.parametrize("encoding", ["binary_little_endian", "binary_big_endian"])
def test_bytes_after_the_last_element_of_a_binary_body_are_a_warning(tmp_path, encoding):
    data = ply_bytes(encoding, square(encoding))
    path = tmp_path / "t.ply"
    path.write_bytes(data + b"\n\x00\x00")
    assert read_ply(path).warnings == (f"{path}: byte {len(data)}: 3 bytes after the last element, ignored",)


# --- files, limits, pickling ------------------------------------------------------------------------

def test_a_directory_and_a_socket_are_refused(tmp_path):
    with pytest.raises(PlyError) as caught:
        read_ply(tmp_path)
    assert str(caught.value) == f"{tmp_path}: not a regular file (a directory)"
    path = tmp_path / "s.ply"
    with socket.socket(socket.AF_UNIX) as s:
        s.bind(str(path))
        assert stat.S_ISSOCK(os.stat(path).st_mode)
        with pytest.raises(PlyError) as caught:
            read_ply(path)
    assert str(caught.value) == f"{path}: not a regular file (a socket)"


def test_a_missing_file(tmp_path):
    with pytest.raises(PlyError) as caught:
        read_ply(tmp_path / "none.ply")
    assert str(caught.value) == f"{tmp_path / 'none.ply'}: cannot read: No such file or directory"


@pytest.fixture
def small_limits():
    limits.set_max_file_size(300)
    limits.set_memory_limit("1M")
    yield
    limits.set_max_file_size(None)
    limits.set_memory_limit(None)


def test_limits(tmp_path, small_limits):
    big = tmp_path / "big.ply"
    big.write_bytes(ply_bytes("ascii", square("ascii")) + b" " * 200)
    with pytest.raises(PlyLimitError) as caught:
        read_ply(big)
    assert isinstance(caught.value, LimitError) and str(caught.value).startswith(f"{big}: ")
    limits.set_max_file_size(None)
    many = tmp_path / "many.ply"
    many.write_bytes(header("ascii", [("vertex", XYZ, [(0, 0, 0)] * 100_000)]) + b"0 0 0\n" * 100_000)
    with pytest.raises(PlyLimitError) as caught:
        read_ply(many)
    assert str(caught.value).startswith(f"{many}: reading its 300000 values needs about ")


def test_errors_pickle_with_their_parts(tmp_path):
    for error in (PlyError("a.ply", 3, "bad"), PlyError("a.ply", "element 'face' row 2 (byte 9)", "worse"),
                  PlyLimitError("a.ply", None, "too big")):
        copy = pickle.loads(pickle.dumps(error))
        assert type(copy) is type(error) and str(copy) == str(error)
        assert (copy.path, copy.location, copy.reason) == (error.path, error.location, error.reason)
    assert str(PlyError("a.ply", 3, "bad")) == "a.ply:3: bad"
    assert str(PlyError("a\nb.ply", None, "bad")) == "'a\\nb.ply': bad"


@pytest.mark.parametrize("first_bad", ["1e-3x", "nan_", "1.#INDx", "1e-3\u0663"])
def test_the_first_bad_number_among_many_unusual_ones_is_named(tmp_path, first_bad):
    tokens = ["1e-30"] * 500 + ["1.#IND"] + ["-2e-30"] * 100 + [first_bad] + ["1e-3y", "nan_"] + ["3e-30"] * 95
    assert len(tokens) == 699  # 233 vertices
    text = "".join(" ".join(tokens[k:k + 3]) + "\n" for k in range(0, len(tokens), 3))
    data = header("ascii", [("vertex", XYZ, [(0, 0, 0)] * (len(tokens) // 3))]) + text.encode()
    assert message(tmp_path, data) == f":{8 + 601 // 3}: {first_bad!r} is not a number"  # body from line 8
