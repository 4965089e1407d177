"""Fuzzing the PLY reader and the renders of what it reads.

Two sources of hostile files:

- **grammar**: Hypothesis draws PLY files of the three formats from a grammar of what the
  reader takes: ``vertex`` (x y z of any type, colours, normals, texture coordinates),
  ``face`` (index lists of any types, per-corner ``texcoord``, colours, ``texnumber``),
  ``edge`` and unknown elements, unknown scalars and lists, comments, ``TextureFile``;
  bodies that match the header, with hostile values (NaN, inf, 1e308, faces of 0 to 7
  corners, indices out of range), now and then cut short, with random bytes spliced in, a
  count changed or a type swapped in the header;
- **mutations**: the real PLY files of ``../shared/models/formats`` (the small ones) and a few
  written here, with bytes flipped, runs of bytes deleted, duplicated or inserted, the file
  truncated, and header counts or types changed.

The oracle for each file: :func:`rasterkit.ply.read_ply` gives a Mesh or a PointCloud, or
raises a ``ValueError`` (``PlyError``) or ``OSError`` whose message is one line naming the
file; no warning of any kind escapes; a Mesh's per-corner rows and materials index their
tables; what was read is framed and drawn at 48x32 (a Mesh in every mode, a PointCloud as
points), which succeeds or raises such a one-line ``ValueError``. Anything else (another
exception type, a message of several lines or without the file's name, a crash, more than
``--example-seconds`` for one file, memory past the child's limit) is a failure; the
offending file is kept in ``--failures``.

Run by hand (a long run)::

    python tests/support/fuzz_ply.py --grammar 20000 --mutations 20000 --seed 1 --failures /tmp/fuzz-ply

The suite runs a short, derandomized run of this script in a child process with a time and a
memory limit (``tests/ply/test_fuzz_ply.py``).
"""

from __future__ import annotations

import argparse
import faulthandler
import random
import shutil
import struct
import sys
import tempfile
import time
import warnings
from pathlib import Path

# paths of their own, not support.paths: this file also runs as a script
TESTS = Path(__file__).resolve().parents[1]
FORMATS = TESTS.parents[1] / "shared" / "models" / "formats"
if str(TESTS) not in sys.path:
    sys.path.insert(0, str(TESTS))

from support.plyfiles import CODES  # noqa: E402 - the struct code of each PLY type
#: Real PLY files small enough to mutate many times a second.
SMALL_MODELS = ("ply/cube_blender_uv.ply", "obj/fuze/fuze.ply", "robustness/ply/corrupted_invalid_vertex_count.ply")
MODES = ("wire", "hidden", "solid", "solid+wire")
ENCODINGS = ("ascii", "binary_little_endian", "binary_big_endian")
TYPES = tuple(CODES)


class Failure(Exception):
    """The oracle's verdict on one file."""


def check(path: Path) -> str:
    """Read ``path`` and render what it gives; returns "ok", "error" (a clean one-line error)
    or raises :class:`Failure`."""
    import numpy as np

    import rasterkit
    from rasterkit.limits import LimitError
    from rasterkit.ply import PointCloud, read_ply

    def clean(error: BaseException, what: str, name_needed: bool) -> str:
        text = str(error)
        if not isinstance(error, (ValueError, OSError, TypeError)) or isinstance(error, UnicodeError):
            raise Failure(f"{what}: {type(error).__name__}: {text}") from error
        if "\n" in text or not text.strip():
            raise Failure(f"{what}: message not one line: {text!r}") from error
        if name_needed and not text.startswith(str(path)) and not isinstance(error, LimitError):
            raise Failure(f"{what}: message does not start with the file's name: {text!r}") from error
        return "error"

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            model = read_ply(path)
        except Exception as e:  # noqa: BLE001 - the oracle judges every exception
            return clean(e, "read_ply", name_needed=True)
        for warning in model.warnings:
            if "\n" in warning or not warning.startswith(str(path)):
                raise Failure(f"read_ply: warning not one line naming the file: {warning!r}")
        if not isinstance(model, PointCloud):
            check_tables(model)
        try:
            center, radius = model.bounding_sphere()
            camera = rasterkit.Camera.frame(center, radius, width=48, height=32)
        except Exception as e:  # noqa: BLE001
            return clean(e, "framing", name_needed=False)
        runs = [dict(mode="solid", **model.render_arguments())] if isinstance(model, PointCloud) else [
            dict(mode=mode) for mode in MODES]
        for run in runs:
            try:
                fb = rasterkit.render(None if isinstance(model, PointCloud) else model, camera, **run)
            except Exception as e:  # noqa: BLE001
                return clean(e, f"render {run['mode']}", name_needed=False)
            if fb.color.shape != (32, 48, 3) or fb.color.dtype != np.uint8:
                raise Failure(f"render {run['mode']}: colour buffer {fb.color.shape} {fb.color.dtype}")
    return "ok"


def check_tables(mesh) -> None:
    """:class:`Failure` unless each face's ``uv_index`` row is three rows of ``uv`` or -1, and
    ``face_materials`` index ``material_names`` (the Mesh's own checks, from the outside)."""
    if (mesh.uv is None) != (mesh.uv_index is None):
        raise Failure("read_ply: uv and uv_index: one without the other")
    rows, m = mesh.uv_index, mesh.face_materials
    whole = None if rows is None else (rows >= 0) | (rows == -1).all(axis=1)[:, None]  # 3 rows, or -1 -1 -1
    if rows is not None and (rows.shape != mesh.faces.shape or not whole.all() or (rows >= len(mesh.uv)).any()):
        raise Failure(f"read_ply: uv_index does not index uv ({len(mesh.uv)} rows)")
    if m is not None and (m.shape != (len(mesh.faces),) or (m < -1).any() or (m >= len(mesh.material_names)).any()):
        raise Failure("read_ply: face_materials does not index material_names")


# --- writing -------------------------------------------------------------------------------

def _value(kind: str, value, order):
    """``value`` as the file stores a ``kind``: packed (order ``<``/``>``) or text; a value
    its type cannot hold is wrapped or written as it is (text), as hostile writers do."""
    code = CODES[kind]
    if order is None:
        if code in "fd" or not (isinstance(value, int) or float(value).is_integer()):
            return repr(float(value))  # a float where an integer belongs too: the reader refuses it
        return str(int(value))
    if code == "f" and abs(float(value)) > 3.4e38 and float(value) == float(value):
        value = float("inf") if value > 0 else -float("inf")  # what a float32 holds of it
    if code in "fd":
        return struct.pack(order + code, float(value))
    bits = struct.calcsize(code) * 8
    v = int(value) if value == value and abs(value) != float("inf") else 0
    v &= (1 << bits) - 1
    if code.islower() and v >= 1 << (bits - 1):
        v -= 1 << bits
    return struct.pack(order + code, v)


def write(encoding: str, elements, comments=()) -> bytes:
    """A PLY file: ``elements`` [(name, properties, rows)], properties ``(type, name)`` or
    ``("list", count_type, item_type, name)``, one value per property in each row (a list of
    values for a list)."""
    order = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}[encoding]
    head = ["ply", f"format {encoding} 1.0", *(f"comment {c}" for c in comments)]
    body = []
    for name, properties, rows in elements:
        head.append(f"element {name} {len(rows)}")
        head.extend("property " + " ".join(p) for p in properties)
        for row in rows:
            words = []
            for p, value in zip(properties, row):
                if p[0] == "list":
                    words.append(_value(p[1], len(value), order))
                    words.extend(_value(p[2], v, order) for v in value)
                else:
                    words.append(_value(p[0], value, order))
            body.append((" ".join(words) + "\n").encode() if order is None else b"".join(words))
    return ("\n".join(head + ["end_header"]) + "\n").encode() + b"".join(body)


# --- the grammar ---------------------------------------------------------------------------

def strategies():
    """The Hypothesis strategy of (ply bytes, whether to splice junk)."""
    from hypothesis import strategies as st

    floats = st.one_of(st.floats(-10, 10, width=32), st.sampled_from(
        [0.0, -0.0, 1.0, float("nan"), float("inf"), -float("inf"), 1e308, -1e308, 1e-320, 3.4e38, 255.0, 256.0]))
    types = st.sampled_from(TYPES)
    int_types = st.sampled_from([t for t in TYPES if CODES[t] not in "fd"])
    small_ints = st.one_of(st.integers(0, 127), st.integers(0, 127), st.integers(-3, 300))
    names = st.sampled_from(["x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha", "u", "v", "s", "t",
                             "texture_u", "quality", "flags", "texnumber", "vertex1", "vertex2", "junk", "r", "g",
                             "diffuse_red"])

    @st.composite
    def vertex_element(draw, n):
        kind = draw(types)
        props = [(kind, "x"), (kind, "y"), (kind, "z")]
        extra = draw(st.lists(st.one_of(st.tuples(types, names),
                                        st.tuples(st.just("list"), int_types, types, names)), max_size=4))
        props = props + extra
        draw(st.randoms()).shuffle(props) if draw(st.integers(0, 4)) == 0 else None
        rows = []
        for _ in range(n):
            row = []
            for p in props:
                if p[0] == "list":
                    row.append(draw(st.lists(floats.map(abs), max_size=4)))
                else:
                    row.append(draw(floats) if CODES[p[0]] in "fd" else draw(small_ints))
            rows.append(tuple(row))
        return ("vertex", props, rows)

    @st.composite
    def face_element(draw, n_vertices):
        props = [("list", draw(int_types), draw(int_types), draw(st.sampled_from(["vertex_indices", "vertex_index"])))]
        extra = draw(st.lists(st.sampled_from([("list", "uchar", "float", "texcoord"), ("uchar", "red"),
                                                ("uchar", "green"), ("uchar", "blue"), ("int", "texnumber"),
                                                ("list", "int", "double", "junk"), ("float", "quality")]),
                              max_size=4, unique=True))
        props += extra
        if draw(st.booleans()):
            draw(st.randoms()).shuffle(props)
        valid = st.integers(0, max(n_vertices - 1, 0))
        index = st.one_of(*[valid] * 12, st.sampled_from([-1, n_vertices, 255, 65535]))
        rows = []
        for _ in range(draw(st.integers(0, 8))):
            size = draw(st.sampled_from([3] * 8 + [4] * 3 + [5, 7, 0, 1, 2]))
            corners = draw(st.lists(index, min_size=size, max_size=size))
            row = []
            for p in props:
                if p[-1] in ("vertex_indices", "vertex_index"):
                    row.append(corners)
                elif p[-1] == "texcoord":
                    row.append(draw(st.lists(floats, min_size=2 * len(corners), max_size=2 * len(corners) + 1)))
                elif p[0] == "list":
                    row.append(draw(st.lists(floats, max_size=3)))
                else:
                    row.append(draw(small_ints) if CODES[p[0]] not in "fd" else draw(floats))
            rows.append(tuple(row))
        return ("face", props, rows)

    @st.composite
    def documents(draw):
        encoding = draw(st.sampled_from(ENCODINGS))
        n = draw(st.sampled_from([4, 5, 6, 8, 3, 1, 0]))
        elements = [draw(vertex_element(n))]
        if draw(st.integers(0, 4)):
            elements.append(draw(face_element(n)))
        if draw(st.integers(0, 5)) == 0:
            elements.append(("edge", [("int", "vertex1"), ("int", "vertex2")],
                             draw(st.lists(st.tuples(st.integers(-1, n), st.integers(-1, n)), max_size=3))))
        if draw(st.integers(0, 3)) == 0:
            unknown = ("material", [("float", "ambient"), ("list", "uchar", "int", "name")],
                       [(1.0, [1, 2])] * draw(st.integers(0, 2)))
            elements.insert(draw(st.integers(0, len(elements))), unknown)
        comments = draw(st.lists(st.sampled_from(["TextureFile tex.png", "TextureFile ../x.png", "made by hand",
                                                  "TextureFile missing.png", "\u00e9"]), max_size=2))
        data = write(encoding, elements, comments)
        how = draw(st.integers(0, 9))
        if how == 0:  # cut short, mostly in the body
            data = data[:max(len(data) - draw(st.integers(1, 60)), 0)]
        elif how == 1:  # a count changed in the header
            data = data.replace(b"element face ", b"element face " + draw(st.sampled_from([b"1", b"9", b"-", b"0"])), 1)
        elif how == 2:  # raw bytes spliced in
            at = draw(st.integers(0, len(data)))
            data = data[:at] + draw(st.binary(max_size=12)) + data[at:]
        elif how == 3:  # a type swapped
            data = data.replace(draw(st.sampled_from([b"float", b"uchar", b"int"])), draw(
                st.sampled_from([b"double", b"char", b"uint", b"float", b"flt"])), 1)
        return data

    return documents()


# --- mutations of real files ----------------------------------------------------------------

HEADER_EDITS = [(b"element vertex ", b"element vertex 9"), (b"element face ", b"element face 4000000000"),
                (b"list uchar", b"list uint"), (b"list uchar int", b"list char short"), (b"float", b"double"),
                (b"binary_little_endian", b"binary_big_endian"), (b"binary_little_endian", b"ascii"),
                (b"ascii", b"binary_little_endian"), (b"end_header", b"end_headers"), (b"\nproperty", b"\n")]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """``data`` with 1-4 random mutations."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(6)
        i = rng.randrange(len(data) + 1)
        if kind == 0 and data:  # flip a byte
            data[min(i, len(data) - 1)] = rng.randrange(256)
        elif kind == 1:  # delete a run
            del data[i:i + rng.randint(1, 64)]
        elif kind == 2:  # duplicate a run elsewhere
            j = rng.randrange(len(data) + 1)
            data[j:j] = data[i:i + rng.randint(1, 64)]
        elif kind == 3:  # insert hostile bytes
            data[i:i] = rng.choice([b"\xff\xff\xff\xff", b"\x00", b"nan ", b"-1 ", b"\n", b"255 "])
        elif kind == 4:  # truncate
            del data[i:]
        else:  # edit the header
            old, new = rng.choice(HEADER_EDITS)
            data = bytearray(bytes(data).replace(old, new, 1))
    return bytes(data)


def written_models() -> list:
    """Small files of each encoding, with lists of varying length, to mutate."""
    square = [(0.0, 0.0, 0.0, 255, 0, 0), (1.0, 0.0, 0.0, 0, 255, 0), (1.0, 1.0, 0.0, 0, 0, 255),
              (0.0, 1.0, 0.5, 9, 9, 9)]
    props = [("float", "x"), ("float", "y"), ("float", "z"), ("uchar", "red"), ("uchar", "green"), ("uchar", "blue")]
    faces = [("list", "uchar", "int", "vertex_indices"), ("list", "uchar", "float", "texcoord")]
    rows = [([0, 1, 2, 3], [0, 0, 1, 0, 1, 1, 0, 1]), ([0, 2, 1], [0, 0, 1, 1, 1, 0])]
    return [write(e, [("vertex", props, square), ("face", faces, rows)], ["TextureFile tex.png"]) for e in ENCODINGS]


# --- the runs -----------------------------------------------------------------------------

class Runner:
    """Writes each file, checks it under a watchdog, counts and keeps failures."""

    def __init__(self, work: Path, failures: Path | None, example_seconds: float):
        self.work, self.failures, self.seconds = work, failures, example_seconds
        self.counts = {"ok": 0, "error": 0, "failure": 0}
        self.messages: list[str] = []
        _png(work / "tex.png")

    def __call__(self, data: bytes, name: str = "fuzz.ply") -> None:
        path = self.work / name
        path.write_bytes(data)
        # a hang (even inside a kernel, without the GIL) ends the process with a traceback;
        # the file that caused it is still in place for the caller to keep
        faulthandler.dump_traceback_later(self.seconds, exit=True)
        try:
            verdict = check(path)
        except Failure as failure:
            verdict = "failure"
            self.keep(path, str(failure))
        finally:
            faulthandler.cancel_dump_traceback_later()
        self.counts[verdict] += 1

    def keep(self, path: Path, message: str) -> None:
        self.messages.append(message)
        if self.failures is not None:
            self.failures.mkdir(parents=True, exist_ok=True)
            kept = self.failures / f"failure-{len(self.messages):04d}.ply"
            shutil.copyfile(path, kept)
            message = f"{kept.name}: {message}"
        print(f"FAILURE {message}", file=sys.stderr, flush=True)


def _png(path: Path) -> None:
    from PIL import Image

    Image.new("RGB", (2, 2), (200, 100, 50)).save(path)


def run_grammar(runner: Runner, count: int, seed: int | None) -> None:
    from hypothesis import HealthCheck, given, settings

    @settings(max_examples=count, deadline=None, database=None, derandomize=seed is None,
              suppress_health_check=list(HealthCheck), phases=("generate",))
    @given(strategies())
    def one(document):
        runner(document)

    if seed is not None:
        import hypothesis

        one = hypothesis.seed(seed)(one)
    one()


def run_mutations(runner: Runner, count: int, seed: int) -> int:
    sources = [FORMATS / name for name in SMALL_MODELS if (FORMATS / name).is_file()]
    originals = [p.read_bytes() for p in sources] + written_models()
    rng = random.Random(seed)
    for _ in range(count):
        runner(mutate(rng.choice(originals), rng))
    return len(originals)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grammar", type=int, default=200, help="files drawn from the grammar")
    parser.add_argument("--mutations", type=int, default=200, help="mutated real and written files")
    parser.add_argument("--seed", type=int, default=None, help="random seed (default: a fixed, derandomized run)")
    parser.add_argument("--failures", type=Path, default=None, help="folder to keep failing files in")
    parser.add_argument("--example-seconds", type=float, default=20.0, help="time limit of one file")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="rasterkit-fuzz-ply-") as work:
        runner = Runner(Path(work), args.failures, args.example_seconds)
        for data in written_models():  # compile or load the kernels outside the watchdog's count
            faulthandler.dump_traceback_later(600, exit=True)
            runner(data)
            faulthandler.cancel_dump_traceback_later()
        if args.grammar:
            run_grammar(runner, args.grammar, args.seed)
        sources = run_mutations(runner, args.mutations, args.seed or 0)
    total = sum(runner.counts.values())
    print(f"checked {total} files ({args.grammar} from the grammar, {args.mutations} mutations of {sources} files) "
          f"in {time.perf_counter() - start:.0f} s: {runner.counts['ok']} read and rendered, "
          f"{runner.counts['error']} clean errors, {runner.counts['failure']} failures", flush=True)
    return 1 if runner.counts["failure"] else 0


if __name__ == "__main__":
    sys.exit(main())
