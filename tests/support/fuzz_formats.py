"""The harness of the STL and OFF fuzzers (``fuzz_stl.py``, ``fuzz_off.py``): the oracle that
judges one file, the runner that writes each file and keeps the failures, and the command line.

The oracle for each file: the reader gives a Mesh, or raises a ``ValueError`` whose message is
one line naming the file; no warning of any kind escapes; the Mesh's arrays hold together (every
index in range, per-face arrays one row per face); it is framed and drawn in every mode at
48x32, which succeeds or raises such a one-line ``ValueError``. Anything else (another
exception type, a message of several lines or without the file's name, a crash, more than
``--example-seconds`` for one file, memory past the child's limit) is a failure; the offending
file is kept in ``--failures``.
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

MODES = ("wire", "hidden", "solid", "solid+wire")


class Failure(Exception):
    """The oracle's verdict on one file."""


def check(path: Path, reader) -> str:
    """Read ``path`` with ``reader`` and render what it gives; returns "ok", "error" (a clean
    one-line error) or raises :class:`Failure`."""
    import numpy as np

    import rasterkit
    from rasterkit.limits import LimitError

    def clean(error: BaseException, what: str, name_needed: bool) -> str:
        text = str(error)
        if not isinstance(error, (ValueError, OSError)) or isinstance(error, UnicodeError):
            raise Failure(f"{what}: {type(error).__name__}: {text}") from error
        if "\n" in text or not text.strip():
            raise Failure(f"{what}: message not one line: {text!r}") from error
        if name_needed and not text.startswith(path.name if str(path) not in text else str(path)) \
                and not isinstance(error, LimitError):
            raise Failure(f"{what}: message does not start with the file's name: {text!r}") from error
        return "error"

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            mesh = reader(path)
        except Exception as e:  # noqa: BLE001 - the oracle judges every exception
            return clean(e, reader.__name__, name_needed=True)
        check_mesh(mesh)
        if any(not w.startswith(f"{path}: ") for w in mesh.warnings):
            raise Failure(f"a warning that does not start with the file's name: {mesh.warnings}")
        if len(mesh.faces) == 0:
            return "ok"
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


def check_mesh(mesh) -> None:
    """:class:`Failure` unless the Mesh's arrays hold together (its own checks, from the outside)."""
    n, m = len(mesh.vertices), len(mesh.faces)
    for name in ("faces", "edges"):
        a = getattr(mesh, name)
        if len(a) and (a.min() < 0 or a.max() >= n):
            raise Failure(f"{name} index out of range")
    for name in ("face_colors", "face_groups", "normal_index"):
        a = getattr(mesh, name)
        if a is not None and len(a) != m:
            raise Failure(f"{name} has {len(a)} rows for {m} faces")
    if mesh.normal_index is not None and (mesh.normal_index.min(initial=0) < 0 or
                                          mesh.normal_index.max(initial=-1) >= len(mesh.corner_normals)):
        raise Failure("normal_index does not index corner_normals")
    for name in ("face_colors", "vertex_colors"):
        a = getattr(mesh, name)
        if a is not None and not ((a >= 0) & (a <= 1)).all():
            raise Failure(f"{name} outside [0, 1]")
    if any("\n" in w for w in mesh.warnings):
        raise Failure("a warning of several lines")


#: Files of the grammar that read cleanly, kept to mutate besides the real files (all there is
#: to mutate in a clone without ``../shared/models``).
KEPT_TO_MUTATE = 40


class Runner:
    """Writes each file, checks it under a watchdog, counts and keeps failures."""

    def __init__(self, work: Path, failures: Path | None, example_seconds: float, suffix: str, reader):
        self.work, self.failures, self.seconds = work, failures, example_seconds
        self.suffix, self.reader = suffix, reader
        self.counts = {"ok": 0, "error": 0, "failure": 0}
        self.messages: list[str] = []
        self.read: list[bytes] = []  # the first files that read without error: more to mutate

    def __call__(self, data: bytes, name: str | None = None) -> None:
        path = self.work / (name or f"fuzz{self.suffix}")
        path.write_bytes(data)
        # a hang (even inside a kernel, without the GIL) ends the process with a traceback;
        # the file that caused it is still in place for the caller to keep
        faulthandler.dump_traceback_later(self.seconds, exit=True)
        try:
            verdict = check(path, self.reader)
        except Failure as failure:
            verdict = "failure"
            self.keep(path, str(failure))
        finally:
            faulthandler.cancel_dump_traceback_later()
        self.counts[verdict] += 1
        if verdict == "ok" and len(self.read) < KEPT_TO_MUTATE:
            self.read.append(data)

    def keep(self, path: Path, message: str) -> None:
        self.messages.append(message)
        if self.failures is not None:
            self.failures.mkdir(parents=True, exist_ok=True)
            kept = self.failures / f"failure-{len(self.messages):04d}{self.suffix}"
            shutil.copyfile(path, kept)
            message = f"{kept.name}: {message}"
        print(f"FAILURE {message}", file=sys.stderr, flush=True)


def run_grammar(runner: Runner, strategy, count: int, seed: int | None) -> None:
    from hypothesis import HealthCheck, given, settings

    @settings(max_examples=count, deadline=None, database=None, derandomize=seed is None,
              suppress_health_check=list(HealthCheck), phases=("generate",))
    @given(strategy)
    def one(document):
        runner(document)

    if seed is not None:
        import hypothesis

        one = hypothesis.seed(seed)(one)
    one()


def main(argv, description: str, suffix: str, reader, strategy, sources, mutate, first: bytes) -> int:
    """The command line of a fuzzer: ``strategy()`` draws documents (bytes), ``sources()`` gives
    the real files to mutate (a list of bytes; the grammar's first clean files are mutated too),
    ``mutate(data, rng)`` changes one, ``first`` is a valid file checked before the others (its
    kernels compile outside the watchdog)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--grammar", type=int, default=200, help="documents drawn from the grammar")
    parser.add_argument("--mutations", type=int, default=200, help="mutated real files")
    parser.add_argument("--seed", type=int, default=None, help="random seed (default: a fixed, derandomized run)")
    parser.add_argument("--failures", type=Path, default=None, help="folder to keep failing files in")
    parser.add_argument("--example-seconds", type=float, default=20.0, help="time limit of one file")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="rasterkit-fuzz-") as work:
        runner = Runner(Path(work), args.failures, args.example_seconds, suffix, reader)
        runner(first)
        run_grammar(runner, strategy(), args.grammar, args.seed)
        originals = sources() + [first] + runner.read
        rng = random.Random(args.seed or 0)
        for _ in range(args.mutations):
            runner(mutate(rng.choice(originals), rng))
    total = sum(runner.counts.values())
    print(f"checked {total} files ({args.grammar} from the grammar, {args.mutations} mutations of "
          f"{len(originals)} files) in {time.perf_counter() - start:.0f} s: {runner.counts['ok']} read, "
          f"{runner.counts['error']} clean errors, {runner.counts['failure']} failures", flush=True)
    return 1 if runner.counts["failure"] else 0
