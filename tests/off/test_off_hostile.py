"""read_off on hostile input: every byte in every place, mutations, giant tokens and counts,
huge faces. Each ends in a Mesh or one line naming the file, in bounded time, with no NumPy
warning."""

import time
import warnings

import numpy as np
import pytest

from rasterkit.off import OffError, read_off

CUBE = (b"COFF\n8 6 12\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n0 0 1 0 0 0\n1 0 1 1 0 0\n"
        b"1 1 1 0 1 0\n0 1 1 0 0 1\n4 0 3 2 1 255 0 0\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5 0 255 0 255\n4 2 3 7 6\n"
        b"4 3 0 4 7\n")


def outcome(data: bytes) -> str:
    """'mesh' or the error's text; fails on anything else (another exception, a warning)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            read_off("h.off", data=data)
        except OffError as e:
            text = str(e)
            assert text.startswith("h.off") and "\n" not in text, text
            return text
    return "mesh"


def test_every_byte_in_every_place_ends_in_a_mesh_or_one_line():
    triangle = b"COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2 255 0 0\n"
    for byte in range(256):
        for at in range(0, len(triangle), 6):
            outcome(triangle[:at] + bytes([byte]) + triangle[at:])


def test_mutations_end_in_a_mesh_or_one_line():
    rng = np.random.default_rng(11)
    lines = CUBE.split(b"\n")
    tokens = [b"nan", b"inf", b"-1", b"999999999999999999", b"1e308", b"0", b"#", b"\x00", b"\xff", b"OFF", b"4",
              b"3 0 1 2", b""]
    for _ in range(600):
        mutated = list(lines)
        for _ in range(rng.integers(1, 4)):
            mutated = mutated or [b""]
            i = rng.integers(len(mutated))
            kind = rng.integers(4)
            if kind == 0:
                words = mutated[i].split(b" ")
                words[rng.integers(len(words))] = tokens[rng.integers(len(tokens))]
                mutated[i] = b" ".join(words)
            elif kind == 1:
                del mutated[i]
            elif kind == 2:
                mutated.insert(i, mutated[rng.integers(len(mutated))])
            else:
                mutated = mutated[:i]
        outcome(b"\n".join(mutated))


def test_huge_counts_and_faces_fail_before_anything_is_allocated():
    start = time.perf_counter()
    assert "the header says 9999999999999 vertices" in outcome(b"OFF\n9999999999999 1 0\n0 0 0\n3 0 0 0\n")
    assert "a face of 999999999999999999 vertices, but only 3 numbers follow" in \
        outcome(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999999999999 0 1 2\n")
    assert time.perf_counter() - start < 2


def test_a_face_of_twenty_thousand_corners_and_giant_tokens_take_little_time():
    n = 20_000
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    vertices = "\n".join(f"{np.cos(a):.6f} {np.sin(a):.6f} 0" for a in angles)
    data = f"OFF\n{n} 1 0\n{vertices}\n{n} {' '.join(map(str, range(n)))}\n".encode()
    outcome(data)  # the polygon kernels compile (or load from the cache) first, as for OBJ
    start = time.perf_counter()
    mesh = read_off("h.off", data=data)
    assert mesh.faces.shape == (n - 2, 3) and mesh.edges.shape == (n, 2) and mesh.warnings == ()
    text = outcome(b"OFF\n3 1 0\n" + b"1" * 2_000_000 + b" 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    assert text == "mesh"
    text = outcome(b"OFF\n3 1 0\n" + b"x" * 2_000_000 + b" 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    assert text.startswith("h.off:3: expected a number, got 'xxxx") and len(text) < 200
    assert time.perf_counter() - start < 5


def test_numbers_beyond_float64_are_infinite_without_a_numpy_warning():
    mesh = read_off("h.off", data=b"OFF\n4 2 0\n1e400 0 0\n1 0 0\n0 1 0\n1 1 -1e999\n3 0 1 2\n3 1 2 3 1e400 0 0\n")
    assert mesh.faces.shape == (0, 3) and mesh.warnings[-1] == "h.off: 2 vertices with NaN or infinite coordinates; 2 faces using them dropped"
    assert outcome(b"OFF\n3 1 0\n1e400 0 0\n1 0 0\n0 1 0\n3 0 1 2\n") == "mesh"


@pytest.mark.parametrize("data", [b"", b"\n\n\n", b"# nothing\n", b"\xff\xfe", b"OFF", b"OFF\n0 0 0\n",
                                  b"\x00" * 100, "OFF\n1 0 0\n\u00e9 0 0\n".encode("latin-1")])
def test_degenerate_files(data):
    outcome(data)
