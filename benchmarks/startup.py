"""Start-up costs: every measurement is a new process, timed from its start to its exit.

cold
    With an empty ``NUMBA_CACHE_DIR`` (a new temporary folder), so every kernel a command
    needs is compiled: ``rasterkit render --demo -o x.png`` alone in its own cache; and a
    *sequence* in one new cache: the demo, then the model (stanford-bunny, 1920x1080) in
    ``wire``, ``hidden``, ``solid``, ``solid+wire``, one process each, in that order (each
    step compiles only what the steps before it left out). The seconds of each step and of
    the sequence, and the peak memory (max RSS) of each process. The repetitions alternate
    the order (alone first, then sequence first); medians are reported.
warm
    ``rasterkit render MODEL -o b.png --size 1920x1080 --mode solid`` with the normal, warm
    cache against ``benchmarks/peer_cli.py`` (the same job as a trimesh + moderngl script),
    interleaved, medians (as the ``cli`` family does, with the console script).
import
    ``python -c "import rasterkit"``, ``rasterkit --help`` and ``rasterkit render --help``
    as whole processes, interleaved with ``python -c pass`` (the interpreter alone, the
    peer of each), medians; and whether the two help commands import numba.

first models
    ``rasterkit render MODEL -o x.png --mode solid`` (the command's default size) for each of
    ten real models of other people (:data:`benchmarks.first_models.MODELS`: triangles,
    quads, polygons, texture coordinates, normals, materials), each alone in a new, empty
    ``NUMBA_CACHE_DIR``: what a new user's first render of their own model costs, wall
    seconds and user CPU seconds (:mod:`benchmarks.first_models`).

first textured
    ``rasterkit render fuze.obj -o x.png --mode solid --shading smooth`` against the same with
    ``--no-textures``, each in a new, empty ``NUMBA_CACHE_DIR``: what texturing adds to a first
    render (:mod:`benchmarks.first_textured`).

first lit
    ``rasterkit render stanford-bunny.obj -o x.png --mode solid`` against the same with phong
    and two lights, with a shadowed light, and with ``--ao``, each in a new, empty
    ``NUMBA_CACHE_DIR``: what lighting adds to a first render (:mod:`benchmarks.first_lit`).

Peak memory is ``ru_maxrss`` of the process, from ``os.wait4``. The process is started by a
small launcher process (a bare Python, about 10 MiB), never by the suite itself: Linux carries
the resident peak of the address space a process had *before* its ``exec`` into its
``ru_maxrss``, so a child of the suite (hundreds of MiB after the render families) would
report the suite's peak, not its own. The launcher also does the timing, so a cold step's
seconds do not include the launcher's own start.

rasterkit runs as the ``rasterkit`` console script beside the interpreter (``python -m
rasterkit`` where there is none), with this checkout first on ``PYTHONPATH``.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from . import cli, first_lit, first_models, first_textured
from .launch import ROOT, child_environment, launch, rasterkit_command
from .compare import RASTERKIT, compare, start
from .report import Record
from .settings import MODES, model_path
from .timing import interleaved

FAMILY = "startup"
BARE = "python -c pass"
"""The peer of the import-time workloads: the interpreter starting and exiting."""

# What the console script does (``from rasterkit.cli import main; sys.exit(main())``), then
# whether numba was imported on the way.
_IMPORTS_NUMBA = r"""
import sys
sys.argv = {argv!r}
from rasterkit.cli import main
try:
    main()
except SystemExit:
    pass
print()
print("IMPORTS_NUMBA", "numba" in sys.modules)
"""


def _mib(n: float) -> str:
    return f"{n / 2**20:.0f} MiB"


def _seconds_text(s: float) -> str:
    return f"{s:.2f} s"


# ---------------------------------------------------------------------------- cold


def _cold_steps(settings, scratch: Path, with_model: bool) -> list[tuple[str, list[str], dict]]:
    """(step name, argv, sizes) of the cold sequence: the demo, then the model in every mode."""
    rk = rasterkit_command()
    demo = rk + ["render", "--demo", "-o", str(scratch / "demo.png")]
    demo_sizes = {"size": "the command's default"}
    if settings.demo_size is not None:
        width, height = settings.demo_size
        demo += ["--size", f"{width}x{height}"]
        demo_sizes = {"width": width, "height": height}
    steps = [("demo", demo, demo_sizes)]
    if with_model:
        model = model_path(settings.startup_model)
        width, height = settings.startup_size
        for mode in MODES:
            steps.append((f"{mode}/{settings.startup_model}/{width}x{height}",
                          rk + ["render", str(model), "-o", str(scratch / "model.png"),
                                "--size", f"{width}x{height}", "--mode", mode],
                          {"width": width, "height": height, "mode": mode}))
    return steps


def _cold_run(steps, scratch: Path) -> list[dict]:
    """The steps in order, in one new, empty Numba cache."""
    env = child_environment(NUMBA_CACHE_DIR=tempfile.mkdtemp(dir=scratch, prefix="numba-cache-"))
    return [launch(argv, env, scratch) for _, argv, _ in steps]


def _cold(settings, results, scratch: Path, model_ok: bool) -> None:
    runs = max(settings.startup_cold_runs, 1)
    steps = _cold_steps(settings, scratch, model_ok)
    sequence = settings.startup_sequence and model_ok
    if not settings.startup_sequence:
        results.skip(FAMILY, "cold sequence (demo, then the model in every mode)",
                     f"not measured in the {settings.name} profile (each step compiles kernels: minutes)")
    alone: list[dict] = []
    chained: list[list[dict]] = []
    failed = set()
    for round_ in range(runs):
        order = ["alone", "sequence"] if round_ % 2 == 0 else ["sequence", "alone"]
        for what in order:
            if what in failed or (what == "sequence" and not sequence):
                continue
            try:
                if what == "alone":
                    alone += _cold_run(steps[:1], scratch)
                else:
                    chained.append(_cold_run(steps, scratch))
            except RuntimeError as error:
                results.skip(FAMILY, f"startup/cold-{what}", f"failed: {error}")
                failed.add(what)
    note = "new process, empty NUMBA_CACHE_DIR; max RSS = ru_maxrss of the process (os.wait4)"
    if alone:
        _cold_records(results, "startup/cold-alone/demo", steps[0][2], alone, note)
    if chained:
        for k, (name, _, sizes) in enumerate(steps):
            _cold_records(results, f"startup/cold-sequence/{k + 1}-{name}", sizes,
                          [run[k] for run in chained], note + "; one cache for the whole sequence, "
                          "filled by the steps before")
        totals = [sum(step["seconds"] for step in run) for run in chained]
        peaks = [max(step["maxrss"] for step in run) for run in chained]
        results.add(Record(family=FAMILY, name="startup/cold-sequence/total", peer=None,
                           sizes={"steps": len(steps)}, rasterkit=statistics.median(totals),
                           runs=len(chained), note="sum of the steps' seconds, median over repetitions"))
        results.add(Record(family=FAMILY, name="startup/cold-sequence/total/max-rss", peer=None,
                           sizes={"steps": len(steps)}, quantity="peak_bytes",
                           rasterkit=statistics.median(peaks), runs=len(chained),
                           note="largest max RSS of any step"))
        medians = [statistics.median(run[k]["seconds"] for run in chained) for k in range(len(steps))]
        rss = [statistics.median(run[k]["maxrss"] for run in chained) for k in range(len(steps))]
        print("  cold sequence: " + ", ".join(f"{name.split('/')[0]} {_seconds_text(s)} ({_mib(m)})"
                                               for (name, _, _), s, m in zip(steps, medians, rss))
              + f"; total {_seconds_text(statistics.median(totals))}, peak {_mib(statistics.median(peaks))}",
              flush=True)


def _cold_records(results, name: str, sizes: dict, runs: list[dict], note: str) -> None:
    results.add(Record(family=FAMILY, name=name, peer=None, sizes=sizes,
                       rasterkit=statistics.median(r["seconds"] for r in runs), runs=len(runs), note=note))
    results.add(Record(family=FAMILY, name=f"{name}/max-rss", peer=None, sizes=sizes, quantity="peak_bytes",
                       rasterkit=statistics.median(r["maxrss"] for r in runs), runs=len(runs), note=note))


# ---------------------------------------------------------------------------- warm


class _Command:
    """One whole process per call, with this checkout first on PYTHONPATH."""

    def __init__(self, argv: list[str], env: dict | None = None):
        self.argv, self.env = argv, env if env is not None else child_environment()

    def __call__(self) -> None:
        done = subprocess.run(self.argv, cwd=ROOT, env=self.env, capture_output=True, text=True)
        if done.returncode != 0:
            lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
            raise RuntimeError(lines[-1])


def _warm(settings, results, peers, scratch: Path) -> None:
    model = model_path(settings.startup_model)
    width, height = settings.startup_size
    with_peer = start(results, FAMILY, cli.PEER, lambda: cli._peer_ready(peers))
    sides = {RASTERKIT: _Command(rasterkit_command() + ["render", str(model), "-o", str(scratch / "b.png"),
                                                        "--size", f"{width}x{height}", "--mode", "solid"])}
    if with_peer:
        sides[cli.PEER] = _Command(cli._commands(model, scratch, width, height)[cli.PEER])
    name = f"startup/warm/solid/{settings.startup_model}/{width}x{height}"
    try:
        # Two untimed runs at least: the first process after an edit of a kernel file compiles.
        compare(results, FAMILY, name, sides, repeat=settings.process_repeat, warmup=max(settings.warmup, 2),
                sizes={"width": width, "height": height, "MiB": round(model.stat().st_size / 2**20, 2)},
                note="whole process with the normal (warm) caches: start-up, load, render, PNG")
    except RuntimeError as error:  # a run after the checking run failed (the code changed under us)
        results.skip(FAMILY, name, f"failed during the timed runs: {error}")


# ---------------------------------------------------------------------------- import


def imports_numba(argv: list[str]) -> bool:
    """Whether ``rasterkit ARGV...`` (as the console script runs it) imports numba."""
    code = _IMPORTS_NUMBA.format(argv=["rasterkit", *argv])
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=child_environment(),
                          capture_output=True, text=True)
    lines = [line for line in done.stdout.splitlines() if line.startswith("IMPORTS_NUMBA ")]
    if done.returncode != 0 or not lines:
        last = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise RuntimeError(last[-1])
    return lines[-1].split()[1] == "True"


def _import(settings, results) -> None:
    rk = rasterkit_command()
    commands = {
        'python -c "import rasterkit"': ([sys.executable, "-c", "import rasterkit"], None),
        "rasterkit --help": (rk + ["--help"], ["--help"]),
        "rasterkit render --help": (rk + ["render", "--help"], ["render", "--help"]),
    }
    sides = {BARE: _Command([sys.executable, "-c", "pass"])}
    facts = {}
    for name, (argv, help_argv) in commands.items():
        side = _Command(argv)
        try:
            side()  # the checking run: a command that fails is reported and left out
            if help_argv is not None:
                facts[name] = imports_numba(help_argv)
        except RuntimeError as error:
            results.skip(FAMILY, f"startup/import/{name}", f"failed: {error}")
            continue
        sides[name] = side
    if len(sides) == 1:
        return
    try:
        medians = interleaved(sides, settings.repeat, max(settings.warmup - 1, 0))
    except RuntimeError as error:  # a run after the checking run failed (the code changed under us)
        results.skip(FAMILY, "startup/import", f"failed during the timed runs: {error}")
        return
    for name in sides:
        if name == BARE:
            continue
        sizes, note = {}, "whole process, warm caches"
        if name in facts:
            sizes = {"imports_numba": facts[name]}
            note += f"; imports numba: {'yes' if facts[name] else 'no'}"
        results.add(Record(family=FAMILY, name=f"startup/import/{name}", peer=BARE, sizes=sizes,
                           rasterkit=medians[name], peer_value=medians[BARE], runs=settings.repeat,
                           note=note))
    for name, value in facts.items():
        print(f"  {name} imports numba: {'yes' if value else 'no'}", flush=True)


# ---------------------------------------------------------------------------- family


def run(settings, results, peers) -> None:
    """Cold runs (the demo alone; the sequence; first models; the first textured render), the
    warm run against its peer, import time."""
    cli.compile_bytecode()
    model = model_path(settings.startup_model)
    model_ok = model.is_file()
    if not model_ok:
        results.skip(FAMILY, settings.startup_model, f"model file {model} not found (cold sequence and "
                     "warm run left out; the cold demo and the import times still run)")
    with tempfile.TemporaryDirectory(prefix="rasterkit-startup-") as scratch:
        scratch = Path(scratch)
        _import(settings, results)
        if model_ok:
            _warm(settings, results, peers, scratch)
        _cold(settings, results, scratch, model_ok)
        first_models.run(settings, results, scratch)
        first_textured.run(settings, results, scratch)
        first_lit.run(settings, results, scratch)

