"""Fuzzing the OBJ loader and the renders of what it loads.

Two sources of hostile files:

- **grammar**: Hypothesis draws OBJ documents from a grammar of the statements rasterkit
  reads (``v``, ``vt``, ``vn``, ``f`` with plain and ``v/vt/vn`` corners, ``l``, ``p``,
  ``o``, ``g``, ``s``, ``usemtl``, ``mtllib`` with a material file of its own, comments,
  unknown keywords, continuations), on a start with or without texture coordinates and normals,
  with hostile numbers (NaN, inf, 1e308, 400 digits, ``1.#IND``, half numbers), hostile
  indices (0, negative, huge, malformed ``1//2/3``), odd whitespace and line breaks, and
  random bytes spliced in;
- **mutations**: real models of ``../shared/models`` (the small ones) with bytes flipped,
  lines deleted, duplicated or swapped, and hostile tokens put in place of numbers.

The oracle for each file: :func:`rasterkit.load_obj` gives a Mesh, or raises a
``ValueError`` (``ObjError``) or ``OSError`` whose message is one line naming the file; no
warning of any kind escapes; a loaded mesh's per-corner attributes and materials index their
tables (:func:`check_corners`); it is framed and drawn in every mode at 48x32, which
succeeds or raises such a one-line ``ValueError``. Anything else (another exception type,
a message of several lines or without the file's name, a crash, more than
``--example-seconds`` for one file, memory past the child's limit) is a failure; the
offending file is kept in ``--failures``.

Run by hand (the long run of the issue)::

    python tests/support/fuzz_obj.py --grammar 80000 --mutations 20000 --seed 1 --failures /tmp/fuzz-failures

The suite runs a short, derandomized run of this script in a child process with a time and
a memory limit (``tests/obj/test_fuzz_obj.py``), and loads every file of
``tests/data/fuzz_regressions`` the same way.
"""

from __future__ import annotations

import argparse
import faulthandler
import random
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

# paths of their own, not support.paths: this file also runs as a script
TESTS = Path(__file__).resolve().parents[1]
MODELS = TESTS.parents[1] / "shared" / "models"
REGRESSIONS = TESTS / "data" / "fuzz_regressions"
#: Real models small enough to mutate many times a second.
SMALL_MODELS = ("suzanne.obj", "spot_control_mesh.obj", "CornellBox-Original.obj", "cow.obj", "teapot.obj")
MODES = ("wire", "hidden", "solid", "solid+wire")


class Failure(Exception):
    """The oracle's verdict on one file."""


def check(path: Path) -> str:
    """Load ``path`` and render what it gives; returns "ok", "error" (a clean one-line error)
    or raises :class:`Failure`."""
    import numpy as np

    import rasterkit
    from rasterkit.formats import texture_maps
    from rasterkit.limits import LimitError

    def clean(error: BaseException, what: str, name_needed: bool) -> str:
        text = str(error)
        if not isinstance(error, (ValueError, OSError, TypeError)) or isinstance(error, (UnicodeError,)):
            raise Failure(f"{what}: {type(error).__name__}: {text}") from error
        if "\n" in text or not text.strip():
            raise Failure(f"{what}: message not one line: {text!r}") from error
        if name_needed and path.name not in text and not isinstance(error, LimitError):
            raise Failure(f"{what}: message does not name the file: {text!r}") from error
        return "error"

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:  # the command line's guess at the maps, before it reads the file: never an error
            guess = texture_maps(path)
        except Exception as e:  # noqa: BLE001
            raise Failure(f"texture_maps: {type(e).__name__}: {e}") from e
        if not guess <= {"diffuse", "alpha", "normal"}:
            raise Failure(f"texture_maps: {sorted(guess)}")
        try:
            mesh = rasterkit.load_obj(path)
        except Exception as e:  # noqa: BLE001 - the oracle judges every exception
            return clean(e, "load_obj", name_needed=True)
        check_corners(mesh)
        try:
            center, radius = mesh.bounding_sphere()
            camera = rasterkit.Camera.frame(center, radius, width=48, height=32)
        except Exception as e:  # noqa: BLE001
            return clean(e, "framing", name_needed=False)
        for mode in MODES:
            try:
                fb = rasterkit.render(mesh, camera, mode=mode)
            except Exception as e:  # noqa: BLE001
                return clean(e, f"render {mode}", name_needed=False)
            if fb.color.shape != (32, 48, 3) or fb.color.dtype != np.uint8:
                raise Failure(f"render {mode}: colour buffer {fb.color.shape} {fb.color.dtype}")
    return "ok"


def check_corners(mesh) -> None:
    """:class:`Failure` unless each face's ``uv_index`` and ``normal_index`` row is three
    rows of its table or -1, -1, -1, and ``face_materials`` index ``material_names`` (the
    Mesh's own checks, done again here from the outside)."""
    for table, index in (("uv", "uv_index"), ("corner_normals", "normal_index")):
        values, rows = getattr(mesh, table), getattr(mesh, index)
        if (values is None) != (rows is None):
            raise Failure(f"load_obj: {table} and {index}: one without the other")
        if rows is None:
            continue
        given = (rows >= 0).all(axis=1)
        if rows.shape != mesh.faces.shape or not (given | (rows == -1).all(axis=1)).all() or \
                (rows[given] >= len(values)).any():
            raise Failure(f"load_obj: {index} does not index {table} ({len(values)} rows)")
    if mesh.face_materials is not None:
        m = mesh.face_materials
        if m.shape != (len(mesh.faces),) or (m < -1).any() or (m >= len(mesh.material_names)).any():
            raise Failure("load_obj: face_materials does not index material_names")


# --- the grammar --------------------------------------------------------------------------

def strategies():
    """The Hypothesis strategy of (obj_bytes, mtl_bytes) documents."""
    from hypothesis import strategies as st

    hostile_numbers = st.sampled_from([
        "nan", "-nan", "NaN", "inf", "-inf", "Infinity", "1e308", "-1e308", "1e309", "1e-400", "-0", "0x10",
        "1.#IND", "-1.#INF", "1.#QNAN", "1e", "e5", ".", "-", "+", "--1", "1..2", "1e+", "9" * 400, "0." + "0" * 300 + "1",
        "\u0661", "1_000", "1,5", "", "٣", "1e99999999999",
    ])
    numbers = st.one_of(
        st.floats(allow_nan=False, allow_infinity=False, width=32).map(lambda x: f"{x:g}"),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.integers(-5, 5).map(str),
        hostile_numbers,
    )
    small_index = st.integers(-12, 12).map(str)
    indices = st.one_of(small_index, small_index, st.integers(-(2**70), 2**70).map(str),
                        st.sampled_from(["0", "-0", "+1", "1.0", "a", "", "99999999999999999999"]))
    # corners mostly in range of the textured start (4 v, 3 vt, 2 vn), now and then not, in every form
    attributed = st.tuples(st.sampled_from([1, 2, 3, 4, -1, -2, -3, -4]), st.integers(-4, 4), st.integers(-3, 3),
                           st.sampled_from(["v", "t", "n", "b", "b", "b"])).map(
        lambda t: {"v": f"{t[0]}", "t": f"{t[0]}/{t[1]}", "n": f"{t[0]}//{t[2]}"}.get(t[3], f"{t[0]}/{t[1]}/{t[2]}"))
    corners = st.one_of(
        indices,
        st.tuples(indices, indices).map("/".join),
        st.tuples(indices, indices).map(lambda t: f"{t[0]}//{t[1]}"),
        st.tuples(indices, indices, indices).map("/".join),
        st.sampled_from(["1/", "1//", "/1", "1/2/3/4", "//", "1///2"]),
    )
    separators = st.one_of(st.just(" "), st.just(" "), st.just(" "),
                           st.sampled_from(["\t", "  ", " \t ", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x1f",
                                            "\x85", "\xa0", "\u2003", "\u3000", "\x00", "\r"]))
    names = st.one_of(st.sampled_from(["m.mtl", "missing.mtl", "a b.mtl", "../m.mtl", "/dev/null", "", "m.mtl m.mtl",
                                       "x" * 300]),
                      st.text(max_size=12))
    material_names = st.one_of(st.sampled_from(["red", "blue", "none", "", "red blue"]), st.text(max_size=8))

    def statement(keyword, arguments):
        keywords = st.just(keyword) if isinstance(keyword, str) else keyword
        return st.tuples(keywords, st.lists(arguments, max_size=9), separators)

    statements = st.one_of(
        statement("v", numbers), statement("v", numbers), statement("vt", numbers), statement("vn", numbers),
        statement("f", corners), statement("f", corners), statement("f", small_index), statement("l", corners),
        statement("f", attributed), statement("f", attributed),
        statement("p", indices), statement("o", material_names), statement("g", material_names),
        statement("s", st.sampled_from(["1", "off", "0", "x"])), statement("usemtl", material_names),
        statement("mtllib", names), statement("#", st.text(max_size=10)),
        statement(st.text(max_size=6).map(lambda s: s or "vp"), st.text(max_size=6)),
    )
    endings = st.sampled_from(["\n"] * 6 + ["\r\n", "\r", "\\\n", "\n\n", ""])
    base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"
    textured = ("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 1 0 0\n"
                "f 1/1/1 2/2/1 3/3/1\nf 1/1/2 3/3/2 4/2/2\n")

    @st.composite
    def documents(draw):
        lines = draw(st.lists(st.tuples(statements, endings), max_size=14))
        text = draw(st.sampled_from([base, "", base, textured])) + "".join(
            kw + (sep + sep.join(args) if args else "") + end for (kw, args, sep), end in lines)
        if draw(st.integers(0, 3)) == 0:  # faces of v, v/vt, v//vn and v/vt/vn corners alone: most load
            faces = draw(st.lists(st.lists(attributed, min_size=3, max_size=9), max_size=8))
            text = textured + "".join("f " + " ".join(face) + "\n" for face in faces)
        data = text.encode("utf-8", "surrogatepass")
        if draw(st.integers(0, 9)) == 0:  # raw bytes spliced in
            junk = draw(st.binary(max_size=12))
            at = draw(st.integers(0, len(data)))
            data = data[:at] + junk + data[at:]
        mtl_lines = draw(st.lists(st.one_of(
            st.tuples(st.just("newmtl"), material_names),
            st.tuples(st.just("Kd"), st.lists(numbers, max_size=5).map(" ".join)),
            st.tuples(st.sampled_from(["Ka", "Ks", "map_Kd", "illum", "d", "#"]), st.text(max_size=8)),
        ), max_size=6))
        mtl = "".join(f"{k} {v}\n" for k, v in mtl_lines).encode("utf-8", "surrogatepass")
        return data, mtl

    return documents()


# --- mutations of real models -------------------------------------------------------------

HOSTILE_TOKENS = [b"nan", b"inf", b"1e308", b"-1e308", b"0", b"-999999", b"99999999999", b"1//", b"/", b"\x00",
                  b"\xff\xfe", b"\x1d", b"\xc2\xa0", b"\\", b"#", b"f", b"v", b"\r", b"\n", b"1.#IND", b"9" * 200]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """``data`` with 1-4 random mutations."""
    lines = data.split(b"\n")
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(6)
        i = rng.randrange(len(lines))
        if kind == 0:  # flip a byte
            line = bytearray(lines[i])
            if line:
                line[rng.randrange(len(line))] = rng.randrange(256)
            lines[i] = bytes(line)
        elif kind == 1:  # a hostile token in place of a token
            tokens = lines[i].split(b" ")
            tokens[rng.randrange(len(tokens))] = rng.choice(HOSTILE_TOKENS)
            lines[i] = b" ".join(tokens)
        elif kind == 2:  # delete a run of lines
            del lines[i: i + rng.randint(1, 20)]
            lines = lines or [b""]
        elif kind == 3:  # duplicate a line elsewhere
            lines.insert(rng.randrange(len(lines) + 1), lines[i])
        elif kind == 4:  # swap two lines
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        else:  # truncate
            lines = lines[: i + 1]
            lines[-1] = lines[-1][: rng.randrange(len(lines[-1]) + 1)]
    return b"\n".join(lines)


# --- the runs -----------------------------------------------------------------------------

class Runner:
    """Writes each file, checks it under a watchdog, counts and keeps failures."""

    def __init__(self, work: Path, failures: Path | None, example_seconds: float):
        self.work, self.failures, self.seconds = work, failures, example_seconds
        self.counts = {"ok": 0, "error": 0, "failure": 0}
        self.messages: list[str] = []

    def __call__(self, data: bytes, mtl: bytes = b"", name: str = "fuzz.obj") -> None:
        path = self.work / name
        path.write_bytes(data)
        (self.work / "m.mtl").write_bytes(mtl)
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
            kept = self.failures / f"failure-{len(self.messages):04d}.obj"
            shutil.copyfile(path, kept)
            shutil.copyfile(self.work / "m.mtl", kept.with_suffix(".mtl"))
            message = f"{kept.name}: {message}"
        print(f"FAILURE {message}", file=sys.stderr, flush=True)


def run_grammar(runner: Runner, count: int, seed: int | None) -> None:
    from hypothesis import HealthCheck, given, settings

    @settings(max_examples=count, deadline=None, database=None, derandomize=seed is None,
              suppress_health_check=list(HealthCheck), phases=("generate",))
    @given(strategies())
    def one(document):
        runner(*document)

    if seed is not None:
        import hypothesis

        one = hypothesis.seed(seed)(one)
    one()


def run_mutations(runner: Runner, count: int, seed: int) -> int:
    sources = [MODELS / name for name in SMALL_MODELS if (MODELS / name).is_file()]
    if not sources:
        return 0
    originals = [p.read_bytes() for p in sources]
    rng = random.Random(seed)
    for _ in range(count):
        runner(mutate(rng.choice(originals), rng))
    return len(sources)


def run_regressions(runner: Runner) -> int:
    files = sorted(REGRESSIONS.glob("*.obj"))
    for path in files:
        mtl = path.with_suffix(".mtl")
        runner(path.read_bytes(), mtl.read_bytes() if mtl.is_file() else b"", name=path.name)
    return len(files)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grammar", type=int, default=200, help="documents drawn from the grammar")
    parser.add_argument("--mutations", type=int, default=200, help="mutated real models")
    parser.add_argument("--regressions", action="store_true", help="also check tests/data/fuzz_regressions")
    parser.add_argument("--seed", type=int, default=None, help="random seed (default: a fixed, derandomized run)")
    parser.add_argument("--failures", type=Path, default=None, help="folder to keep failing files in")
    parser.add_argument("--example-seconds", type=float, default=20.0, help="time limit of one file")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="rasterkit-fuzz-") as work:
        runner = Runner(Path(work), args.failures, args.example_seconds)
        runner(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")  # compile or load the kernels outside the watchdog's count
        regressions = run_regressions(runner) if args.regressions else 0
        run_grammar(runner, args.grammar, args.seed)
        sources = run_mutations(runner, args.mutations, args.seed or 0)
    total = sum(runner.counts.values())
    print(f"checked {total} files ({args.grammar} from the grammar, {args.mutations if sources else 0} mutations of "
          f"{sources} models, {regressions} regressions) in {time.perf_counter() - start:.0f} s: "
          f"{runner.counts['ok']} rendered, {runner.counts['error']} clean errors, "
          f"{runner.counts['failure']} failures", flush=True)
    return 1 if runner.counts["failure"] else 0


if __name__ == "__main__":
    sys.exit(main())
