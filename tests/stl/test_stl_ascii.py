"""read_stl on ASCII STL files made here: the grammar (blocks, names, whitespace, case), the
numbers, the errors and their lines, and the kernel's batches."""

import numpy as np
import pytest

import rasterkit.stl.ascii as stl_ascii
from rasterkit.stl import StlError, read_stl, sniff
from support.stlfiles import TETRA, ascii_stl, binary_stl

FACET = ("facet normal 0 0 1\n outer loop\n  vertex {} 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n")


def read(text, name="t.stl"):
    return read_stl(name, data=text.encode() if isinstance(text, str) else text)


def fails(text, line, words):
    with pytest.raises(StlError) as info:
        read(text)
    e = info.value
    assert (e.line, e.path) == (line, "t.stl") and words in e.reason, str(e)
    assert str(e) == f"t.stl:{line}: {e.reason}" and "\n" not in str(e)
    return e


def test_ascii_reads_as_the_same_facets_in_binary():
    a, b = read(ascii_stl(TETRA)), read(binary_stl(TETRA))
    for field in ("vertices", "faces", "edges", "normal_index"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    assert np.allclose(a.corner_normals, b.corner_normals, atol=1e-7) and a.warnings == ()
    assert sniff(ascii_stl(TETRA).encode()[:100])


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
def test_any_whitespace_and_any_case(end):
    text = ascii_stl(TETRA, end=end).replace("facet normal", "FACET\t\tNormal").replace("vertex", "VERTEX")
    text = "\ufeff  " + end + text.replace("outer loop", "outer   \t loop").replace(" ", "  ")
    assert read(text).faces.tolist() == read(binary_stl(TETRA)).faces.tolist()


def test_several_solid_blocks_are_groups_named_after_them():
    text = ascii_stl(TETRA[:2], name="base") + ascii_stl(TETRA[2:3], name="") + ascii_stl(TETRA[3:], name="top")
    mesh = read(text)
    assert mesh.group_names == ("base", "solid 1", "top") and mesh.face_groups.tolist() == [0, 0, 1, 2]
    assert len(mesh.vertices) == 4  # welded across the blocks


def test_endsolid_with_another_name_or_none_and_names_with_keywords_in_them():
    text = "solid endsolid facet vertex\n" + FACET.format(0) + "endsolid\nsolid b\n" + FACET.format(2) + \
           "endsolid solid c facet\n"
    mesh = read(text)
    assert mesh.group_names == ("endsolid facet vertex", "b") and len(mesh.faces) == 2


def test_a_missing_last_endsolid_is_a_warning():
    mesh = read("solid x\n" + FACET.format(0))
    assert mesh.warnings == ("t.stl: no 'endsolid' at the end of the file (block 'x' is not closed)",)


def test_numbers_are_the_correctly_rounded_doubles_of_their_text():
    texts = ["0.1", "-2.5e-3", "1E+02", "+.5", "5.", "0.30000000000000004", "1.7976931348623157e308",
             "123456789012345678901234567890", "4.9406564584124654e-324", "2.2250738585072011e-308"]
    body = "".join(FACET.format(t) for t in texts)
    mesh = read("solid\n" + body + "endsolid\n")
    got = {v[0] for v in mesh.vertices.tolist() if v[1:] == [0.0, 0.0]}
    assert got == {float(t) for t in texts} | {1.0}


def test_nan_and_inf_are_read_and_their_facets_dropped():
    mesh = read("solid\n" + FACET.format("nan") + FACET.format("-Infinity") + FACET.format("0") + "endsolid\n")
    assert len(mesh.faces) == 1 and "2 facets with a NaN or infinite coordinate dropped (the first: line 2)" in \
        mesh.warnings[0]


@pytest.mark.parametrize("token", ["x", "1_0", "0x10", "1.#IND", "1,5", "--1", "1e", "\u00a01", "\x00", "1..2"])
def test_a_token_that_is_no_number_is_named_with_its_line(token):
    e = fails("solid\n" + FACET.format(0) + FACET.format(token) + "endsolid\n", 11, "expected a number, got ")
    assert e.reason == f"expected a number, got {token!r}"


def test_a_facet_of_four_vertices_says_so():
    text = "solid\n" + FACET.format(0).replace("  vertex 0 1 0\n", "  vertex 0 1 0\n  vertex 1 1 0\n") + "endsolid\n"
    fails(text, 7, "expected 'endloop', got 'vertex' (a facet of more than 3 vertices")


def test_a_missing_number_is_found_where_the_grammar_goes_wrong():
    fails("solid\n" + FACET.format(0).replace("1 0 0", "1 0") + "endsolid\n", 6, "expected a number, got 'vertex'")


@pytest.mark.parametrize("text, line, words", [
    ("solid\n" + FACET.format(0) + "endsolid\nfacet", 10, "expected 'solid', got 'facet'"),
    ("solid\n" + FACET.format(0) + "facet normal 0 0 1\n outer loop\n", 11, "expected 'vertex', got the end of the file"),
    ("solid\n" + FACET.format(0) + "endfacet\nendsolid\n", 9, "expected 'facet' or 'endsolid', got 'endfacet'"),
    ("solid\nfacet normal 0 0 1 outer loop\nendsolid\n", 3, "expected 'vertex', got 'endsolid'"),
    ("solid x\n" + FACET.format(0).replace("outer", "outre"), 3, "expected 'outer', got 'outre'"),
    ("solid x\n" + FACET.format(0).replace("endfacet", "endfacets"), 8, "expected 'endfacet', got 'endfacets'"),
])
def test_text_out_of_place_is_named_with_its_line(text, line, words):
    fails(text, line, words)


def test_a_file_of_blocks_without_facets_fails():
    with pytest.raises(StlError, match="^t.stl: no facets"):
        read("solid a\nendsolid a\nsolid b\nendsolid\n")


def test_non_utf8_names_and_tokens_make_one_line_messages():
    mesh = read(b"solid \xff\xfe name\n" + FACET.format(0).encode() + b"endsolid\n")
    assert mesh.faces.shape == (1, 3)
    e = fails(b"solid\n" + FACET.format(0).replace("1 0 0", "1 \xe9 0").encode("latin-1") + b"endsolid\n", 5,
              "expected a number, got ")
    assert e.reason == "expected a number, got 'é'"


def test_facets_across_the_kernels_batches(monkeypatch):
    monkeypatch.setattr(stl_ascii, "BATCH", 3)
    corners = np.repeat(TETRA, 5, axis=0) + np.arange(20)[:, None, None]
    whole = read(ascii_stl(corners))
    assert len(whole.faces) == 20 and np.array_equal(whole.faces, read(binary_stl(corners)).faces)
    text = ascii_stl(corners)
    bad_line = text.splitlines().index("      vertex 7.0 7.0 8.0") + 1
    fails(text.replace("vertex 7.0 7.0 8.0", "vertex 7.0 7.0 x"), bad_line, "expected a number, got 'x'")


def test_ascii_and_binary_of_float32_numbers_agree_bit_for_bit():
    rng = np.random.default_rng(5)
    corners = rng.normal(size=(50, 3, 3)).astype(np.float32).astype(np.float64)
    corners[10:20] = corners[:10]  # shared corners weld the same way
    a, b = read(ascii_stl(corners)), read(binary_stl(corners))
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    assert np.allclose(a.corner_normals, b.corner_normals, atol=1e-6)
