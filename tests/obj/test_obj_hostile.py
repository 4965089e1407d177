"""load_obj and the command line on hostile input (issue 14, the OBJ side): every byte in every
place of every kind of line, devices, FIFOs and sockets where a file should be, files over the
size limit, names and tokens that would break a message in two, and numbers at the edge of
float64. Each ends in a Mesh or in one line naming the file (and the line), never in an
internal error, a hang or a NumPy warning.

Cases that could block (FIFOs) or run away with memory (``/dev/zero``) run in a child process
with a timeout and a memory limit (``tests/support/hostile.py``).
"""

import os
import socket
import stat
import warnings

import numpy as np
import pytest

from rasterkit import limits
from rasterkit.obj.kernels.scan import BLANK, BLANKS, BYTE_CLASS, LINE, TOKEN, is_blank, split_tokens
from rasterkit.limits import LimitError
from rasterkit.obj import ObjError, load_obj
from support.hostile import run_cli, run_python

# The documented rule: space and tab, and CR, VT, FF as spaces; nothing else separates.
SEPARATORS = b" \t\r\x0b\x0c"
UNICODE_SPACES = ["\u0085", "\u00a0", "\u2003", "\u3000", "\u2028", "\u200b", "\ufeff"]
# Bytes that may make a valid token, or change the lines, where they are put: left out of the
# strict expectation (still checked to end in a Mesh or one line).
MAY_BE_VALID = b"0123456789+-./#\\"

BASE = {  # line number: text
    1: "mtllib lib.mtl", 2: "v 0 0 0", 3: "v 1 0 0", 4: "v 0 1 0", 5: "vt 0 0", 6: "vn 0 0 1",
    7: "usemtl red", 8: "f 1/1/1 2/1/1 3/1/1", 9: "l 1 2",
}
TARGETS = {"mtllib": 1, "v": 2, "vt": 5, "vn": 6, "usemtl": 7, "f": 8, "l": 9}
GEOMETRY = ("v", "vt", "vn", "f", "l")


def places(line: bytes, x: bytes) -> dict:
    """line with x put in each place: {place: (new line, the token x is in or None)}."""
    keyword, *tokens = line.split(b" ")
    first, last = tokens[0], tokens[-1]
    rest = b" ".join(tokens)
    return {
        "before the keyword": (x + line, None),
        "on the keyword": (keyword + x + b" " + rest, None),
        "a token of its own first": (keyword + b" " + x + b" " + rest, x),
        "at a token's start": (keyword + b" " + x + rest, x + first),
        "inside a token": (keyword + b" " + first[:1] + x + first[1:] + rest[len(first):],
                           first[:1] + x + first[1:]),
        "a token of its own last": (line + b" " + x, x),
        "at the end of the line": (line + x, last + x),
    }


def shown(token: bytes) -> str:
    """How a message shows a token: its UTF-8 (else Latin-1) text, as repr."""
    try:
        return repr(token.decode("utf-8"))
    except UnicodeDecodeError:
        return repr(token.decode("latin-1"))


def text_with(line_number: int, line: bytes) -> bytes:
    lines = [t.encode() for t in BASE.values()]
    lines[line_number - 1] = line
    return b"\n".join(lines) + b"\n"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("bytes")
    (path / "lib.mtl").write_text("newmtl red\nKd 1 0 0\n")
    return path


def as_arrays(mesh):
    return [mesh.vertices, mesh.faces, mesh.edges, mesh.lines, mesh.normals, mesh.texcoords,
            mesh.face_colors]


def ends_cleanly(path):
    """load_obj(path): a Mesh whose warnings are single printable lines, or an ObjError whose
    message is one printable line naming the file (and a line of it). Returns either."""
    try:
        mesh = load_obj(path)
    except ObjError as e:
        message = str(e)
        assert message.isprintable(), message  # no newline, U+2028, escape... inside
        assert message.startswith(f"{path}:"), message
        assert e.line is None or 1 <= e.line <= len(BASE) + 1
        return e
    assert all(w.isprintable() for w in mesh.warnings), mesh.warnings
    return mesh


def test_blanks_are_the_same_bytes_in_the_kernels_and_in_python():
    assert BLANKS == SEPARATORS
    for c in range(256):
        assert is_blank(c) == (c in SEPARATORS), c
        assert BYTE_CLASS[c] == (BLANK if c in SEPARATORS else LINE if c == 10 else TOKEN), c
        tokens = split_tokens(b"a" + bytes([c]) + b"b")
        assert len(tokens) == (2 if c in SEPARATORS or c == 10 else 1), c


def same_outcome(mine, expected, what):
    assert type(mine) is type(expected), (what, mine, expected)
    if isinstance(expected, ObjError):
        assert str(mine) == str(expected), what
        return
    for a, b in zip(as_arrays(mine), as_arrays(expected)):
        np.testing.assert_array_equal(a, b, err_msg=what)
    assert mine.warnings == expected.warnings, what


@pytest.mark.parametrize("kind", TARGETS)
def test_every_byte_in_every_place_ends_in_a_mesh_or_one_line(folder, kind):
    """Every byte but LF, and Unicode spaces, in seven places of each kind of line: a blank
    reads as a space; any other byte in the numbers and references of v, vt, vn, f and l
    lines is part of a token, which the error on that line shows; anywhere, the load ends
    cleanly."""
    path = folder / "m.obj"
    path.write_bytes(text_with(1, BASE[1].encode()))
    base = load_obj(path)
    assert base.warnings == () and base.face_colors is not None
    number = TARGETS[kind]
    with_space = {}
    for place, (line, _) in places(BASE[number].encode(), b" ").items():
        path.write_bytes(text_with(number, line))
        with_space[place] = ends_cleanly(path)
    insertions = [bytes([c]) for c in range(256) if c != 10]
    insertions += [u.encode() for u in UNICODE_SPACES]
    for x in insertions:
        for place, (line, token) in places(BASE[number].encode(), x).items():
            path.write_bytes(text_with(number, line))
            outcome = ends_cleanly(path)
            what = f"{x!r} {place} of the {kind} line"
            if x in SEPARATORS:
                same_outcome(outcome, with_space[place], what)
            elif x == b"\0":
                assert isinstance(outcome, ObjError) and outcome.line == number, what
                assert "NUL byte" in str(outcome)
            elif kind in GEOMETRY and token is not None and x not in MAY_BE_VALID:
                assert isinstance(outcome, ObjError), (what, outcome)
                assert outcome.line == number, (what, str(outcome))
                assert shown(token) in str(outcome), (what, str(outcome))
    # a space is nothing new where it only separates what was separated
    for place in ("before the keyword", "a token of its own first", "a token of its own last",
                  "at the end of the line"):
        same_outcome(with_space[place], base, place)


def test_the_issues_file_is_a_one_line_error_on_the_command_line(tmp_path):
    for name, face, token in (("end", b"f 1 2 3 \x1d", r"'\x1d'"),
                              ("between", b"f 1 2\x1d3", r"'2\x1d3'")):
        path = tmp_path / f"{name}.obj"
        path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + face + b"\n")
        outcome = run_cli("render", path, "-o", tmp_path / f"{name}.png")
        assert outcome.one_line_error() == (f"rasterkit: error: {path}:4: malformed vertex "
                                            f"reference {token}")
        assert not (tmp_path / f"{name}.png").exists()


def test_file_names_that_would_break_a_line_are_shown_escaped(tmp_path):
    path = tmp_path / "two\nlines\u2028.obj"
    path.write_text("v 0 0 0\nv 1 x 0\n")
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert caught.value.path == str(path)
    assert str(caught.value) == f"{str(path)!r}:2: malformed number 'x' in a v line"
    library = "lib\nrary\x1b[31m.mtl"
    (tmp_path / "m.obj").write_text(f"mtllib {library}\nusemtl red\nv 0 0 0\nv 1 0 0\n"
                                    "v 0 1 0\nf 1 2 3\n")
    mesh = load_obj(tmp_path / "m.obj")  # the name is two lines: "lib" and "rary..."
    model = tmp_path / "m.obj"
    assert mesh.warnings == (
        f"{model}: 1 unknown keyword line skipped ('rary\\x1b[31m.mtl')",
        f"{model}:1: material library 'lib' cannot be read: No such file or directory")


def test_unknown_keywords_are_listed_escaped(tmp_path):
    path = tmp_path / "m.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvp\x1b[2J 1\nv\xc2\xa0 1 2 3\n")
    mesh = load_obj(path)
    assert mesh.warnings == (f"{path}: 2 unknown keyword lines skipped ('vp\\x1b[2J', "
                             "'v\\xa0')",)


# --- files that are not regular files, and the size limit ----------------------------------------

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"


def make_fifo(path):
    os.mkfifo(path)
    return path


def test_a_fifo_as_the_model_is_refused_at_once(tmp_path):
    fifo = make_fifo(tmp_path / "pipe.obj")
    outcome = run_python(f"""
        from rasterkit import load_obj
        try:
            load_obj({str(fifo)!r})
        except ValueError as e:
            print(e)
    """, timeout=60)
    assert outcome.code == 0, outcome.describe()
    assert outcome.stdout.strip() == f"{fifo}: not a regular file (a FIFO)"
    outcome = run_cli("render", fifo, "-o", tmp_path / "out.png", timeout=60)
    assert outcome.one_line_error() == f"rasterkit: error: {fifo}: not a regular file (a FIFO)"


def test_a_fifo_or_a_device_as_material_library_is_a_warning(tmp_path):
    fifo = make_fifo(tmp_path / "pipe.mtl")
    (tmp_path / "m.obj").write_text(f"mtllib pipe.mtl\nmtllib /dev/zero\nusemtl red\n{SQUARE}")
    outcome = run_python(f"""
        from rasterkit import load_obj
        mesh = load_obj({str(tmp_path / 'm.obj')!r})
        print(len(mesh.faces))
        print(*mesh.warnings, sep="\\n")
    """, timeout=60)
    assert outcome.code == 0, outcome.describe()
    model = tmp_path / "m.obj"
    assert outcome.stdout.splitlines() == [
        "2",
        f"{model}:1: material library 'pipe.mtl' cannot be read: not a regular file (a FIFO)",
        f"{model}:2: material library '/dev/zero' cannot be read: not a regular file (a "
        "character device)",
    ]
    assert fifo.exists()


def test_dev_zero_as_the_model_is_refused_without_reading(tmp_path):
    outcome = run_cli("render", "/dev/zero", "-o", tmp_path / "out.png", timeout=60)
    assert outcome.one_line_error() == ("rasterkit: error: /dev/zero: not a regular file (a "
                                        "character device)")
    link = tmp_path / "zero.obj"
    link.symlink_to("/dev/zero")
    outcome = run_cli("info", link, timeout=60)
    assert outcome.one_line_error() == (f"rasterkit: error: {link}: not a regular file (a "
                                        "character device)")


def test_a_socket_is_refused(tmp_path):
    path = tmp_path / "s.obj"
    with socket.socket(socket.AF_UNIX) as s:
        s.bind(str(path))
        assert stat.S_ISSOCK(os.stat(path).st_mode)
        with pytest.raises(ObjError) as caught:
            load_obj(path)
    assert str(caught.value) == f"{path}: not a regular file (a socket)"


@pytest.fixture
def small_limit():
    limits.set_max_file_size(100)
    yield 100
    limits.set_max_file_size(None)


def test_a_file_over_the_size_limit_is_refused_before_it_is_read(tmp_path, small_limit):
    path = tmp_path / "big.obj"
    path.write_text(SQUARE + "#" * (101 - len(SQUARE)))
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert isinstance(caught.value, LimitError)
    assert str(caught.value) == (f"{path}: 101 bytes, more than the file size limit of 100 "
                                 "bytes (--max-file-size, RASTERKIT_MAX_FILE_SIZE)")
    path.write_text(SQUARE + "#" * (100 - len(SQUARE)))  # at the limit: read
    assert len(load_obj(path).faces) == 2


def test_a_material_library_over_the_limit_is_a_warning(tmp_path, small_limit):
    (tmp_path / "big.mtl").write_text("newmtl red\nKd 1 0 0\n" + "# padding\n" * 20)
    (tmp_path / "m.obj").write_text("mtllib big.mtl\nusemtl red\n" + SQUARE)
    mesh = load_obj(tmp_path / "m.obj")
    assert mesh.face_colors is None
    assert mesh.warnings == (f"{tmp_path / 'm.obj'}:1: material library 'big.mtl' cannot be "
                             "read: 220 bytes, more than the file size limit of 100 bytes "
                             "(--max-file-size, RASTERKIT_MAX_FILE_SIZE)",)


def test_a_file_that_grows_while_read_is_cut_at_the_limit(tmp_path, small_limit, monkeypatch):
    path = tmp_path / "growing.obj"
    path.write_text(SQUARE * 4)
    real_fstat = os.fstat

    def fstat_before_growing(fd):  # the size fstat saw before the file grew
        info = list(real_fstat(fd))
        info[stat.ST_SIZE] = 40
        return os.stat_result(info)

    monkeypatch.setattr(os, "fstat", fstat_before_growing)
    with pytest.raises(LimitError) as caught:
        load_obj(path)
    assert str(caught.value) == (f"{path}: grew while it was read to more than the file size "
                                 "limit of 100 bytes (--max-file-size, RASTERKIT_MAX_FILE_SIZE)")


def test_the_size_limit_from_the_environment(tmp_path):
    path = tmp_path / "m.obj"
    path.write_text(SQUARE + "#" * (1536 - len(SQUARE)))
    outcome = run_cli("info", path, env={"RASTERKIT_MAX_FILE_SIZE": "1K"}, timeout=60)
    assert outcome.one_line_error() == (f"rasterkit: error: {path}: 1.5 KiB, more than the file "
                                        "size limit of 1 KiB (--max-file-size, "
                                        "RASTERKIT_MAX_FILE_SIZE)")


def test_unreadable_libraries_are_warned_about_once_each_and_at_most_five(tmp_path):
    names = [f"missing{k}.mtl" for k in range(8)]
    text = "".join(f"mtllib {n}\nmtllib {n}\n" for n in names)
    (tmp_path / "m.obj").write_text(text + "usemtl red\n" + SQUARE)
    mesh = load_obj(tmp_path / "m.obj")
    model = tmp_path / "m.obj"
    assert mesh.warnings == tuple(
        f"{model}:{2 * k + 1}: material library '{names[k]}' cannot be read: No such file or "
        "directory" for k in range(5)) + (f"{model}:11: 3 more material libraries cannot be "
                                          "read",)


# --- numbers at the edge of float64: no NumPy warnings -------------------------------------------

@pytest.mark.parametrize("text", [
    "v 1e308 1e308 1e308\nv -1e308 1e308 0\nv 0 -1e308 1e308\nv 1e308 -1e308 -1e308\n"
    "v 1e308 0 -1e308\nf 1 2 3 4 5\nf 1 2 3\nl 1 2 3\n",
    "v nan nan nan\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 3 4\nf 1 2 3 4\n",
    "v inf 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv -inf 1 1\nf 2 3 4\nf 1 2 3 4 5\n",
    "v 0 0 0 1e308 nan inf\nv 1 0 0 1 1 1\nv 0 1 0 0 0 0\nf 1 2 3\n",
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 1e308 inf\nvt nan\nf 1/1 2/2 3/1\n",
    "v 1e400 0 0\nv 1e-400 0 0\nv 0 1 0\nv 0 0 1\nf 2 3 4\n",
    "v 0 0 0\nv 1e-320 0 0\nv 0 1e-320 0\nv 1e-320 1e-320 0\nv 0 2e-320 0\nf 1 2 4 3 5\n",
], ids=["huge", "nan", "inf", "colours", "texcoords", "overflowing text", "subnormal"])
def test_extreme_numbers_load_without_numpy_warnings(tmp_path, text):
    path = tmp_path / "m.obj"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = load_obj(path)
    assert len(mesh.faces) >= 1


def test_normals_of_huge_and_tiny_vn_are_unit_vectors(tmp_path):
    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 1e308 1e308 1e308\nvn 0 0 1e-200\n"
                    "vn nan 0 0\nf 1//1 2//1 3//2\nf 2//3 4//3 3//3\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = load_obj(path)
    third = 1 / np.sqrt(3)
    np.testing.assert_allclose(mesh.normals, [[third] * 3, [third] * 3, [0, 0, 1], [0, 0, 0]])


# --- memory: files that would need more than the memory limit -------------------------------------

@pytest.fixture
def memory_limit():
    limits.set_memory_limit("4M")
    yield 4 * 1024**2
    limits.set_memory_limit(None)


def test_many_short_lines_are_refused_before_the_statement_table_is_made(tmp_path, memory_limit):
    path = tmp_path / "m.obj"
    path.write_bytes(b"v\n" * 200_000)  # 400 KB: within the file size limit
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert isinstance(caught.value, LimitError)
    message = str(caught.value)
    assert message.startswith(f"{path}: reading its 200001 lines needs about ")
    assert "more than the limit of 4 MiB" in message and "\n" not in message


def test_a_huge_face_is_refused_before_it_is_parsed(tmp_path, memory_limit):
    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf" + " 1 2 3" * 40_000 + "\n")
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    assert isinstance(caught.value, LimitError)
    assert str(caught.value).startswith(f"{path}: loading its 4 statements needs about ")
    limits.set_memory_limit(None)
    assert len(load_obj(path).faces) == 1  # the cycle 1 2 3, once


def test_the_memory_limit_from_the_environment(tmp_path):
    path = tmp_path / "m.obj"
    path.write_bytes(b"v 0 0 0\n" * 300_000 + b"f 1 2 3\n")
    outcome = run_cli("info", path, env={"RASTERKIT_MAX_MEMORY": "8M"}, timeout=60)
    line = outcome.one_line_error()
    assert line.startswith(f"rasterkit: error: {path}: ") and "more than the limit of 8 MiB" in line


def test_long_and_many_inexact_numbers_are_read_exactly(tmp_path):
    long = "0." + "3" * 200 + "e-5"
    texts = [long, "0.1000000000000000055511151231257827", "123456789012345678901234567890",
             "1" + "0" * 400, "4.9e-324", "2.2250738585072011e-308"]
    lines = [f"v {a} {b} {c}" for a, b, c in zip(texts, texts[1:] + texts[:1],
                                                  texts[2:] + texts[:2])]
    path = tmp_path / "m.obj"
    path.write_text("\n".join(lines * 20_000) + "\nf 1 2 3\n")
    mesh = load_obj(path)
    expected = [[float(w) for w in line.split()[1:]] for line in lines] * 20_000
    np.testing.assert_array_equal(mesh.vertices, expected)


def test_errors_survive_pickling(tmp_path):
    """As from a worker process: the same class, path, line and message."""
    import pickle

    path = tmp_path / "m.obj"
    path.write_text("v 0 0 0\nv 1 x 0\n")
    with pytest.raises(ObjError) as caught:
        load_obj(path)
    again = pickle.loads(pickle.dumps(caught.value))
    assert (type(again), again.path, again.line, str(again)) == (
        ObjError, str(path), 2, f"{path}:2: malformed number 'x' in a v line")
