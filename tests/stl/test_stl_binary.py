"""read_stl on binary STL files made here: the welding, the facet normals, the colours of the
attribute words and the header, what is dropped, and how a file that is not binary STL fails."""

import pickle

import numpy as np
import pytest

from rasterkit import limits
from rasterkit.limits import LimitError
from rasterkit.stl import StlError, StlLimitError, read_stl, sniff
from support.stlfiles import TETRA, binary_stl, normals_of

TETRA_VERTICES = [[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1]]  # in order of first appearance
TETRA_FACES = [[0, 1, 2], [0, 2, 3], [0, 3, 1], [2, 1, 3]]


def read(data, name="t.stl"):
    return read_stl(name, data=data)


def test_a_tetrahedron_welds_into_four_vertices_in_order_of_first_appearance():
    mesh = read(binary_stl(TETRA))
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.tolist() == TETRA_VERTICES
    assert mesh.faces.tolist() == TETRA_FACES
    assert mesh.edges.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
    assert mesh.warnings == () and mesh.face_colors is None and mesh.face_groups is None


def test_a_file_of_one_facet():
    mesh = read(binary_stl(TETRA[:1]))
    assert mesh.faces.tolist() == [[0, 1, 2]] and mesh.vertices.tolist() == TETRA_VERTICES[:3]


def test_the_file_normals_are_kept_one_row_per_facet():
    normals = normals_of(TETRA) * np.array([[1], [2], [0.5], [3]])  # not unit length in the file
    mesh = read(binary_stl(TETRA, normals=normals))
    assert np.allclose(mesh.corner_normals, normals_of(TETRA), atol=1e-7)
    assert mesh.normal_index.tolist() == [[f, f, f] for f in range(4)]


def test_a_file_whose_normals_are_all_zero_has_none():
    mesh = read(binary_stl(TETRA, normals=np.zeros((4, 3))))
    assert mesh.corner_normals is None and mesh.normal_index is None and mesh.warnings == ()


@pytest.mark.parametrize("bad", [[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0]])
def test_a_missing_normal_is_the_normal_of_the_corners(bad):
    normals = normals_of(TETRA)
    normals[2] = bad
    mesh = read(binary_stl(TETRA, normals=normals))
    assert np.allclose(mesh.corner_normals, normals_of(TETRA), atol=1e-7)
    assert len(mesh.warnings) == 1 and "1 are zero, NaN or infinite" in mesh.warnings[0]


def test_a_normal_against_the_winding_is_replaced_and_all_against_it_are_dropped():
    normals = normals_of(TETRA)
    normals[1] *= -1
    mesh = read(binary_stl(TETRA, normals=normals))
    assert np.allclose(mesh.corner_normals, normals_of(TETRA), atol=1e-7)
    assert "1 point against their facet's winding" in mesh.warnings[0]
    mesh = read(binary_stl(TETRA, normals=-normals_of(TETRA)))
    assert mesh.corner_normals is None and "4 point against" in mesh.warnings[0] and "not used" in mesh.warnings[0]


def test_equal_numbers_weld_and_others_do_not():
    corners = TETRA.copy()
    corners[3, 0] = [np.nextafter(np.float32(1), np.float32(2)), 0, 0]  # one float32 step from (1, 0, 0)
    corners[1, 0] = [-0.0, 0.0, -0.0]  # the same point as (0, 0, 0)
    mesh = read(binary_stl(corners))
    assert len(mesh.vertices) == 5 and mesh.vertices[4, 0] == np.float32(corners[3, 0, 0])
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 1], [4, 1, 3]]


def test_facets_that_welding_makes_degenerate_are_dropped_with_a_warning():
    corners = np.concatenate([TETRA, [[[0, 0, 0], [1, 0, 0], [0, 0, 0]]]])
    mesh = read(binary_stl(corners, normals=np.zeros((5, 3))))
    assert mesh.faces.tolist() == TETRA_FACES
    assert mesh.warnings == ("t.stl: 1 facet with two corners at one place (no area) dropped "
                             "(the first: facet 4 (byte 284))",)


def test_facets_with_a_nan_or_infinite_corner_are_dropped_and_their_corners_are_no_vertices():
    corners = np.concatenate([[[[np.nan, 0, 0], [5, 5, 5], [6, 6, 6]]], TETRA, [[[np.inf, 0, 0], [1, 0, 0], [0, 0, 1]]]])
    mesh = read(binary_stl(corners, normals=np.zeros((6, 3))))
    assert mesh.vertices.tolist() == TETRA_VERTICES and mesh.faces.tolist() == TETRA_FACES
    assert mesh.warnings == ("t.stl: 2 facets with a NaN or infinite coordinate dropped (the first: facet 0 (byte 84))",)


def test_a_binary_header_that_starts_with_solid_is_binary_by_its_size():
    data = binary_stl(TETRA, header=b"solid looks like ASCII")
    assert read(data).faces.tolist() == TETRA_FACES
    assert sniff(data[:200], len(data)) and not sniff(data[:200])


def viscam(r, g, b):
    return 0x8000 | (r << 10) | (g << 5) | b


def magics(r, g, b):
    return r | (g << 5) | (b << 10)


def test_viscam_colours_have_blue_in_the_low_bits():
    mesh = read(binary_stl(TETRA, attributes=[viscam(31, 0, 0), viscam(0, 31, 0), viscam(0, 0, 31), viscam(31, 31, 0)]))
    assert mesh.face_colors.dtype == np.float32
    assert mesh.face_colors.tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0]]


def test_viscam_facets_without_bit_15_get_the_default_colour_with_a_warning():
    mesh = read(binary_stl(TETRA, attributes=[viscam(31, 0, 0), 0, 0, viscam(0, 0, 31)]))
    assert mesh.face_colors[[0, 3]].tolist() == [[1, 0, 0], [0, 0, 1]]
    assert np.allclose(mesh.face_colors[1], 0.8) and "2 of 4 facets have no VisCAM colour" in mesh.warnings[0]


def test_magics_colours_have_red_in_the_low_bits_and_bit_15_takes_the_part_colour():
    header = b"COLOR=" + bytes([255, 128, 0, 255]) + b" made by Magics"
    mesh = read(binary_stl(TETRA, header=header, attributes=[magics(31, 0, 0), 0x8000, magics(0, 0, 31),
                                                              magics(0, 31, 0)]))
    part = [1.0, np.float32(128 / 255), 0.0]
    assert mesh.face_colors.tolist() == [[1, 0, 0], part, [0, 0, 1], [0, 1, 0]]


def test_magics_words_that_are_all_zero_are_filler_and_every_facet_has_the_part_colour():
    mesh = read(binary_stl(TETRA, header=b"COLOR=" + bytes([0, 0, 255, 255]), attributes=[0, 0, 0, 0]))
    assert mesh.face_colors.tolist() == [[0, 0, 1]] * 4


@pytest.mark.parametrize("words", [[0, 0, 0, 0], [0x4e73] * 4, [1, 2, 3, 0x7fff]])
def test_attribute_words_without_bit_15_and_without_a_colour_header_are_no_colours(words):
    assert read(binary_stl(TETRA, attributes=words)).face_colors is None


def test_dropped_facets_take_their_colours_and_normals_with_them():
    corners = np.concatenate([TETRA[:2], [[[0, 0, 0], [0, 0, 0], [1, 1, 1]]], TETRA[2:]])
    normals = np.concatenate([normals_of(TETRA[:2]), [[0, 0, 1]], normals_of(TETRA[2:])])
    words = [viscam(31, 0, 0), viscam(0, 31, 0), viscam(1, 1, 1), viscam(0, 0, 31), viscam(31, 31, 31)]
    mesh = read(binary_stl(corners, normals=normals, attributes=words))
    assert mesh.face_colors.tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]]
    assert np.allclose(mesh.corner_normals, normals_of(TETRA), atol=1e-7)


@pytest.mark.parametrize("count, words", [(20, "truncated?"), (2, "(100 more)"), (2**32 - 1, "truncated?")])
def test_a_count_that_is_not_the_size_of_the_file_fails_at_byte_80(count, words):
    data = binary_stl(TETRA, count=count)
    with pytest.raises(StlError) as info:
        read(data)
    e = info.value
    assert (e.location, e.line) == ("byte 80", None) and words in e.reason and str(e).startswith("t.stl: byte 80: ")
    assert f"is {count} ({84 + 50 * count} bytes), but the file has 284 bytes" in e.reason


@pytest.mark.parametrize("data, words", [(b"", "an empty file"), (b"\x00" * 50, "shorter than a binary STL header"),
                                         (b"v 0 0 0\nf 1 2 3\n" * 8, "no 'solid' at the start")])
def test_what_is_neither_ascii_nor_binary_stl_fails_in_one_line(data, words):
    with pytest.raises(StlError, match=words) as info:
        read(data)
    assert "\n" not in str(info.value) and str(info.value).startswith("t.stl: ")


def test_a_binary_file_without_facets_fails():
    with pytest.raises(StlError, match="no facets"):
        read(binary_stl(np.zeros((0, 3, 3))))


def test_the_same_bytes_give_the_same_mesh_by_path_and_by_data(tmp_path):
    data = binary_stl(TETRA, attributes=[viscam(31, 0, 0)] * 4)
    (tmp_path / "t.stl").write_bytes(data)
    a, b = read_stl(tmp_path / "t.stl"), read(data)
    for field in ("vertices", "faces", "edges", "corner_normals", "normal_index", "face_colors"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field


def test_errors_pickle_with_their_parts_and_limit_errors_are_limit_errors():
    for error in (StlError("a.stl", 3, "bad"), StlError("a.stl", None, "bad", location="byte 80"),
                  StlLimitError("a.stl", None, "too big")):
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is type(error) and str(again) == str(error)
        assert (again.path, again.line, again.reason, again.location) == (error.path, error.line, error.reason,
                                                                          error.location)
    assert str(StlError("a.stl", 3, "bad")) == "a.stl:3: bad"
    assert isinstance(StlLimitError("a", None, "x"), LimitError) and isinstance(StlLimitError("a", None, "x"), ValueError)


def test_the_memory_limit_refuses_a_large_file_before_reading_its_facets():
    data = binary_stl(np.repeat(TETRA, 250, axis=0))
    limits.set_memory_limit("100K")
    try:
        with pytest.raises(StlLimitError, match="t.stl: reading its 1000 facets needs about"):
            read(data)
    finally:
        limits.set_memory_limit(None)


def test_the_file_size_limit_and_non_regular_files(tmp_path):
    path = tmp_path / "t.stl"
    path.write_bytes(binary_stl(TETRA))
    limits.set_max_file_size(100)
    try:
        with pytest.raises(StlLimitError, match="t.stl: 284 bytes, more than the file size limit"):
            read_stl(path)
    finally:
        limits.set_max_file_size(None)
    with pytest.raises(StlError, match="not a regular file"):
        read_stl(tmp_path)
    with pytest.raises(StlError, match="cannot read: No such file"):
        read_stl(tmp_path / "missing.stl")
    with pytest.raises(TypeError):
        read_stl()
