"""load_obj reads a file in chunks of whole lines on several threads
(:mod:`rasterkit.obj.chunks`): the Mesh, its warnings and the errors must not depend on how
many chunks there are or which thread reads which. Small files are read here in one chunk and
in chunks of a few bytes (a line or two each), on one thread and on several, with what
depends on the lines above: relative indices, line continuations, CRLF, comments and blank
lines at the edges of chunks, colours, texture coordinates and normals, and bad lines."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rasterkit import Mesh, load_obj, set_threads
from rasterkit.obj import ObjError, chunks, document
from rasterkit.runtime.threads import MAX_THREADS

FIELDS = [f.name for f in dataclasses.fields(Mesh) if f.name != "materials"]

TEXTS = {
    "relative": ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n# between\n\nv 1 1 0\nv 2 1 0\n"
                 "f -4 -1 -2\nl -1 -2 -3\nv 5 5 5\nf 1 -1 2\n"),
    "crlf and continuations": ("v 0 0 0\r\nv 1 0 \\\r\n 0\r\nv 0 1 0\\\n\r\nv 1 1 0\r\n"
                               "f 1 2 \\\n 3 4 # quad\r\n   \r\n\t# comment\r\nf 2 3 4\r\n"),
    "attributes": ("v 0 0 0 1 0 0\nv 1 0 0\nvt 0 0\nvt 1\nvn 0 0 1\nvn 0 0 2\nv 0 1 0 0 0 1\n"
                   "f 1/1/1 2/2/2 3/-1/-2\nvt 0.5 0.5\nf -3/-1 -2/1 -1/2\nvn 1 nan 0\n"
                   "f 1//-1 2//3 3//-3\nusemtl a\ng left right\nf 1 2 3\no obj\np 1 2\nxyz 1\n"),
    "numbers": ("v 1e400 -0 .5\nv 1.#IND 2 3\nv 0.1000000000000000055511151231257827 1E+02 -2.\n"
                "v 123456789012345678901234567890 4.9e-324 +1e-3\nf 1 2 3 4\nf -1 -2 -3\n"),
}

BAD = {
    "relative before the first": "v 0 0 0\nv 1 0 0\nf 1 2 -3\n",
    "malformed corner": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2/x 3\nf 1 0 2\n",
    "malformed number": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvn 1 2 3x\n",
    "out of range": "v 0 0 0\nv 1 0 0\nv 0 1 0\n\n\nf 1 2 30\n",
}


def _mesh_fields(mesh) -> dict:
    return {name: getattr(mesh, name) for name in FIELDS}


def _assert_same(a: dict, b: dict):
    assert a.keys() == b.keys()
    for name, value in a.items():
        other = b[name]
        if isinstance(value, np.ndarray):
            assert isinstance(other, np.ndarray), name
            assert value.dtype == other.dtype and value.shape == other.shape, name
            assert value.tobytes() == other.tobytes(), name  # bit for bit, NaN too
        else:
            assert value == other, name


@pytest.fixture
def tiny_chunks(monkeypatch):
    """Chunks of one or two lines: every line break may be the edge of a chunk."""
    monkeypatch.setattr(chunks, "CHUNK_BYTES", 4)
    monkeypatch.setattr(chunks, "CHUNKS_PER_THREAD", 10_000)


def _load(path, threads):
    set_threads(threads)
    try:
        return load_obj(path, textures=False)
    finally:
        set_threads(None)


def _outcome(path, threads):
    try:
        return _mesh_fields(_load(path, threads))
    except ObjError as e:
        return str(e)


@pytest.mark.parametrize("name", sorted(TEXTS) + sorted(BAD))
def test_chunks_and_threads_give_the_same_mesh_or_error(tmp_path, monkeypatch, name):
    path = tmp_path / "m.obj"
    path.write_bytes({**TEXTS, **BAD}[name].encode())
    whole = _outcome(path, 1)
    assert len(chunks.chunk_bounds(path.read_bytes(), MAX_THREADS)) == 2  # one chunk
    monkeypatch.setattr(chunks, "CHUNK_BYTES", 4)
    monkeypatch.setattr(chunks, "CHUNKS_PER_THREAD", 10_000)
    assert len(chunks.chunk_bounds(path.read_bytes(), 1)) - 1 >= 3  # a line or two each
    for threads in sorted({1, 2, MAX_THREADS}):
        if threads > MAX_THREADS:
            continue
        pieces = _outcome(path, threads)
        if isinstance(whole, str):
            assert pieces == whole
        else:
            _assert_same(whole, pieces)
    assert isinstance(whole, str) == (name in BAD)


def test_relative_indices_across_chunks_count_the_lines_above(tmp_path, tiny_chunks):
    path = tmp_path / "m.obj"
    path.write_text(TEXTS["relative"])
    mesh = _load(path, 2)
    # f -3 -2 -1 after three v; f -4 -1 -2 after five; f 1 -1 2 after six
    assert mesh.faces.tolist() == [[0, 1, 2], [1, 4, 3], [0, 5, 1]]
    assert mesh.lines.tolist() == [[4, 3], [3, 2]]


def test_an_error_in_a_later_chunk_names_its_line(tmp_path, tiny_chunks):
    path = tmp_path / "m.obj"
    path.write_text(BAD["relative before the first"])
    with pytest.raises(ObjError) as caught:
        _load(path, 2)
    assert str(caught.value) == (f"{path}:3: relative vertex index -3 in '-3' points before the first v "
                                 "(only 2 above this line)")


def test_chunk_bounds_are_just_after_line_breaks(monkeypatch):
    monkeypatch.setattr(chunks, "CHUNK_BYTES", 4)
    text = b"v 1 2 3\r\n\n# c\nf 1 1 1\nv 4 5 6"
    bounds = chunks.chunk_bounds(text, 3)
    assert bounds[0] == 0 and bounds[-1] == len(text)
    assert all(text[b - 1:b] == b"\n" for b in bounds[1:-1])
    assert all(a < b for a, b in zip(bounds, bounds[1:])) and len(bounds) >= 4


def test_geometry_over_the_budget_is_read_again_when_the_file_is_within_the_limit(tmp_path, monkeypatch):
    path = tmp_path / "m.obj"
    path.write_text(TEXTS["attributes"])
    expected = _mesh_fields(_load(path, 1))
    monkeypatch.setattr(document, "parse_budget", lambda size, lines: 0)  # nothing may be kept at first
    _assert_same(expected, _mesh_fields(_load(path, 2)))


def test_a_statement_longer_than_a_chunks_first_arrays_is_read(tmp_path):
    path = tmp_path / "m.obj"
    cycles = chunks.FIRST_CAPACITY + 1  # the corner arrays grow while this face is read
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf" + " 1 2 3" * cycles + "\n")
    mesh = _load(path, 1)
    assert mesh.faces.tolist() == [[0, 1, 2]]  # the cycle 1 2 3, once
