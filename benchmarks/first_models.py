"""The ``startup`` family's first models: a new user's first render of their own model.

``rasterkit render MODEL -o x.png --mode solid`` (or each mode of
``settings.first_model_modes``: ``--first-modes``) for each model of :data:`MODELS` alone, in a
new, empty ``NUMBA_CACHE_DIR`` (so every kernel it needs compiles, the reader's included),
as a whole process started by :func:`benchmarks.launch.launch`: wall seconds and user CPU
seconds (the process and the compiling helper it starts). Repetitions alternate the order of
the models; medians are reported. Models that are not on this machine are skipped.
"""

from __future__ import annotations

import statistics
import tempfile
from pathlib import Path

from .launch import child_environment, launch, rasterkit_command
from .report import Record
from .settings import MODELS_DIR

FAMILY = "startup"

#: (name, path under the shared models folder): triangles, texture coordinates, normals,
#: quads, polygons of up to 16 corners, materials, negative indices.
MODELS = (
    ("stanford-bunny", "stanford-bunny.obj"),
    ("teapot", "teapot.obj"),
    ("spot", "spot.obj"),
    ("lost_empire", "lost_empire.obj"),
    ("CornellBox-Original", "CornellBox-Original.obj"),
    ("fuze", "formats/obj/fuze/fuze.obj"),
    ("suzanne", "suzanne.obj"),
    ("sponza", "sponza.obj"),
    ("airboat", "airboat.obj"),
    ("beast", "beast.obj"),
)


#: The modes a first render may be measured in; records of a mode other than solid are named
#: ``startup/first-model/MODE/MODEL``.
MODES = ("solid", "wire", "hidden", "solid+wire")


def run(settings, results, scratch: Path) -> None:
    """:func:`run_mode` for each mode of ``settings.first_model_modes``."""
    for mode in settings.first_model_modes:
        run_mode(settings, results, scratch, mode)


def run_mode(settings, results, scratch: Path, mode: str) -> None:
    """Each present model's first render in ``mode``, ``settings.first_model_runs`` times (0:
    skipped)."""
    runs = settings.first_model_runs
    prefix = "startup/first-model" + ("" if mode == "solid" else f"/{mode}")
    if runs == 0:
        results.skip(FAMILY, prefix, f"not measured in the {settings.name} profile "
                     "(each render compiles every kernel it needs: about 10 s a model)")
        return
    present = [(name, MODELS_DIR / path) for name, path in MODELS if (MODELS_DIR / path).is_file()]
    for name, path in MODELS:
        if not (MODELS_DIR / path).is_file():
            results.skip(FAMILY, f"{prefix}/{name}", f"model file {MODELS_DIR / path} not found")
    measured: dict[str, list[dict]] = {name: [] for name, _ in present}
    for round_ in range(runs):
        for name, path in present if round_ % 2 == 0 else present[::-1]:
            env = child_environment(NUMBA_CACHE_DIR=tempfile.mkdtemp(dir=scratch, prefix="numba-cache-"))
            argv = rasterkit_command() + ["render", str(path), "-o", str(scratch / "first.png"), "--mode", mode]
            try:
                measured[name].append(launch(argv, env, scratch))
            except RuntimeError as error:
                results.skip(FAMILY, f"{prefix}/{name}", f"failed: {error}")
    note = f"new process, empty NUMBA_CACHE_DIR, --mode {mode} at the default size"
    for name, done in measured.items():
        if not done:
            continue
        sizes = {"model": name}
        wall = statistics.median(r["seconds"] for r in done)
        user = statistics.median(r["user"] for r in done)
        results.add(Record(family=FAMILY, name=f"{prefix}/{name}", peer=None, sizes=sizes,
                           rasterkit=wall, runs=len(done), note=note))
        results.add(Record(family=FAMILY, name=f"{prefix}/{name}/user-cpu", peer=None,
                           sizes=sizes, rasterkit=user, runs=len(done), note=note + "; user CPU seconds"))
        print(f"  first {mode} render of {name}: {wall:.2f} s ({user:.1f} s user CPU)", flush=True)
