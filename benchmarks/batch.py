"""Batches: a folder of medium models rendered by ``rasterkit render DIR -o OUT --jobs N``.

A temporary folder holds links to the medium models (50k-300k triangles), each 8 times
under 8 names (48 models: the rate of a dataset, where the start-up of the process and its
workers is shared by many models), rendered solid at 1280x960 into a fresh output folder by
a new process: ``--jobs 2`` (two worker processes, one kernel thread each) against ``--jobs 1``
(this process, both cores' threads for the kernels), interleaved, whole processes from
start to exit (start-up, loading, rendering, PNG writing, the manifest). The ratio is the
time of ``--jobs 2`` over ``--jobs 1``; the goal of the batch issue is a rate of at least
1.6x, a ratio of at most 0.625.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from .compare import RASTERKIT, compare
from .report import Target
from .settings import model_path

FAMILY = "batch"
ROOT = Path(__file__).resolve().parents[1]
COPIES = 8
ONE_JOB = "--jobs 1"
TARGET = Target("--jobs 2 renders a folder at >= 1.6x the rate of --jobs 1", 1 / 1.6)


def _render(folder: Path, out: Path, jobs: int, size: str) -> None:
    if out.exists():
        shutil.rmtree(out)
    done = subprocess.run([sys.executable, "-m", "rasterkit", "render", str(folder), "-o", str(out), "--size", size,
                           "--mode", "solid", "--jobs", str(jobs)], cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise RuntimeError(lines[-1])


def run(settings, results, peers) -> None:
    """Whole ``render DIR --jobs 2`` processes against ``--jobs 1`` ones."""
    found = [m for m in settings.batch_models if model_path(m).is_file()]
    if not found:
        results.skip(FAMILY, "folder", "none of the medium models is in ../shared/models")
        return
    width, height = settings.batch_size
    size = f"{width}x{height}"
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch) / "models"
        folder.mkdir()
        for name in found:
            for k in range(COPIES):
                os.symlink(model_path(name), folder / f"{name}-{k}.obj")
                for mtl in model_path(name).parent.glob(f"{name}*.mtl"):
                    if not (folder / mtl.name).exists():
                        os.symlink(mtl, folder / mtl.name)
        n = len(found) * COPIES
        sides = {RASTERKIT: lambda: _render(folder, Path(scratch) / "two", 2, size),
                 ONE_JOB: lambda: _render(folder, Path(scratch) / "one", 1, size)}
        compare(results, FAMILY, f"batch/solid/{n}-models/{size}", sides, repeat=settings.process_repeat,
                warmup=1, sizes={"width": width, "height": height, "models": n}, work=n, unit="model/s",
                targets={ONE_JOB: TARGET}, note="rasterkit = --jobs 2; whole processes")
