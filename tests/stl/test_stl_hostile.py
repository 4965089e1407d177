"""read_stl on hostile input: what is no regular file, headers that claim more than the file
holds, giant tokens, many empty blocks, every byte in a facet. Each ends in a Mesh or one line
naming the file, in bounded time, without a NumPy warning; the cases that could block or
allocate without bound run in a child process with limits."""

import os
import time
import warnings

import numpy as np
import pytest

from rasterkit.stl import StlError, read_stl
from support.hostile import run_python
from support.stlfiles import TETRA, ascii_stl, binary_stl

FACET = b"facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 1 0 endloop endfacet\n"


def outcome(data: bytes) -> str:
    """'mesh' or the error's text; fails on anything else (another exception, a warning)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            read_stl("h.stl", data=data)
        except StlError as e:
            text = str(e)
            assert text.startswith("h.stl") and "\n" not in text, text
            return text
    return "mesh"


def test_fifos_and_devices_are_refused_without_blocking(tmp_path):
    fifo = tmp_path / "f.stl"
    os.mkfifo(fifo)
    code = f"""
        from rasterkit.stl import read_stl, StlError
        for path in [{str(fifo)!r}, "/dev/zero", "/dev/stdin"]:
            try:
                read_stl(path)
            except StlError as e:
                print(e)
    """
    done = run_python(code, timeout=60)
    assert done.code == 0, done.describe()
    assert done.stdout.splitlines() == [f"{fifo}: not a regular file (a FIFO)",
                                        "/dev/zero: not a regular file (a character device)",
                                        "/dev/stdin: not a regular file (a character device)"]


@pytest.mark.parametrize("count", [2**32 - 1, 2**31, 10**9])
def test_a_header_claiming_billions_of_facets_fails_at_once_in_a_child_with_little_memory(count):
    code = f"""
        import numpy as np
        from support.stlfiles import TETRA, binary_stl
        from rasterkit.stl import read_stl, StlError
        try:
            read_stl("big.stl", data=binary_stl(TETRA, count={count}))
        except StlError as e:
            print(e)
    """
    done = run_python(code, timeout=60, memory=1 << 30)
    assert done.code == 0 and done.stdout.startswith("big.stl: byte 80: the facet count"), done.describe()


def test_giant_tokens_and_giant_names_take_linear_time():
    start = time.perf_counter()
    assert outcome(b"solid " + b"n" * 5_000_000 + b"\n" + FACET + b"endsolid\n") == "mesh"
    digits = b"1" * 3_000_000
    assert outcome(b"solid\n" + FACET.replace(b"vertex 1 0 0", b"vertex " + digits + b" 0 0") + b"endsolid\n") == "mesh"
    text = outcome(b"solid\n" + FACET.replace(b"vertex 1 0 0", b"vertex " + b"x" * 3_000_000 + b" 0 0") + b"endsolid\n")
    assert text.startswith("h.stl:2: expected a number, got 'xxxxxxxx") and len(text) < 200
    assert time.perf_counter() - start < 10


def test_many_empty_blocks_and_many_facets_on_one_line():
    start = time.perf_counter()
    assert outcome(b"solid a\nendsolid a\n" * 100_000 + b"solid\n" + FACET + b"endsolid\n") == "mesh"
    # the name of a block runs to the end of its line: facets on the solid line are part of it
    assert outcome(b"solid x " + FACET.replace(b"\n", b" ") * 1000 + b"endsolid") == "h.stl: no facets, nothing to draw"
    assert outcome(b"solid x\n" + FACET.replace(b"\n", b" ") * 1000 + b"endsolid") == "mesh"
    assert time.perf_counter() - start < 20


def test_every_byte_in_every_place_of_a_facet_ends_in_a_mesh_or_one_line():
    base = bytearray(b"solid t\n" + FACET + b"endsolid t\n")
    places = range(len(base))
    for byte in range(256):
        for at in places[::7]:
            data = bytes(base[:at]) + bytes([byte]) + bytes(base[at:])
            outcome(data)


def test_mutations_of_a_binary_file_end_in_a_mesh_or_one_line():
    rng = np.random.default_rng(3)
    data = binary_stl(np.repeat(TETRA, 3, axis=0), attributes=[0x8000 | 31] * 12)
    for _ in range(400):
        mutated = bytearray(data)
        for at in rng.integers(0, len(data), rng.integers(1, 6)):
            mutated[at] = rng.integers(0, 256)
        if rng.random() < 0.2:
            mutated = mutated[:rng.integers(0, len(mutated))]
        outcome(bytes(mutated))


def test_signalling_nans_in_a_binary_file_are_nans_without_a_warning():
    data = bytearray(binary_stl(TETRA))
    snan = np.array([0x7F800001], np.uint32).tobytes()
    data[84:88] = snan  # facet 0's normal x
    data[84 + 50 + 12:84 + 50 + 16] = snan  # facet 1's first corner x
    assert outcome(bytes(data)) == "mesh"
    mesh = read_stl("h.stl", data=bytes(data))
    assert len(mesh.faces) == 3 and "1 facet with a NaN or infinite coordinate dropped" in mesh.warnings[0]


def test_ascii_text_of_coordinates_at_the_edge_of_float64():
    given = np.array([[0, 0, -1], [0, -1, 0], [-1, 0, 0], [1, 1, 1]])
    for scale in (1e308, -1e308, 1e-320):
        assert outcome(ascii_stl(TETRA * scale, normals=given).encode()) == "mesh"
