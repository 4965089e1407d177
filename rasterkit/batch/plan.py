"""``rasterkit render``: which models go to which files, and rendering them one by one.

One model renders to the file ``-o`` names. Several models, or a folder of them, render into
the folder ``-o`` names (``NAME.png``, or ``NAME.gif`` with ``--turntable``), and one bad
model does not stop the others: each failure is one line (``rasterkit: error: MODEL: ...``,
or ``rasterkit: internal error: MODEL: ...`` for a bug), the other models still render, and
a last line says how many rendered and failed. The exit code is then 0 when all rendered, 2
when some failed with bad input, 1 when a failure was an internal error (even if others were
bad input). Ctrl-C (130) or SIGTERM (143) stop at once, leaving no temporary file.

At module level this imports only the standard library and rasterkit's pure-Python modules:
NumPy and Numba load when a model is rendered.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

from rasterkit.batch import report as _report
from rasterkit.runtime import stop as _stop
from rasterkit.batch.manifest import up_to_date
from rasterkit.batch.outputs import check_distinct, check_writable
from rasterkit.batch.render_one import render_model
from rasterkit.formats import MODEL_SUFFIXES
from rasterkit.batch.report import UsageError

__all__ = ["Job", "Request", "jobs", "render_jobs"]

IMAGE_SUFFIXES = (".png", ".gif", ".apng")


@dataclass
class Job:
    source: Path | None  # None: the demo model
    output: Path


def model_inputs(models: list[str]) -> list[Path]:
    paths = []
    for name in models:
        path = Path(name)
        if path.is_dir():
            found = sorted(p for p in path.iterdir() if p.suffix.lower() in MODEL_SUFFIXES and not p.is_dir())
            if not found:
                raise UsageError(f"{path}: no model files in this folder ({', '.join(MODEL_SUFFIXES)})")
            paths.extend(found)
        else:
            paths.append(path)
    return paths


@dataclass(frozen=True)
class Request:
    """What a ``render`` command asks for besides how to draw (its :class:`Task`): the models
    and where their images go."""

    models: list  # files and folders
    demo: bool  # the built-in model instead
    output: str  # -o
    animated: bool = False  # a turntable
    maps: dict = field(default_factory=dict)  # "depth", "normals", "ids": a still image's map files
    contact_sheet: str | None = None
    scheduler: str | None = None  # a Dask scheduler's address ('': asked for and not given)
    workers: int = 1  # --jobs
    resume: bool = False


def jobs(request: Request) -> tuple[list[Job], bool, str | None]:
    """The jobs of a ``render`` command, whether they are a batch (into a folder), and the
    scheduler's address, checked. Pure checks: no model is read, nothing is loaded."""
    if request.demo and request.models:
        raise UsageError("give MODEL.obj files or --demo, not both")
    if not request.demo and not request.models:
        raise UsageError("give a MODEL.obj (or a folder of them), or --demo")
    scheduler = request.scheduler
    if scheduler is not None:  # '' too: a scheduler asked for and not given
        from rasterkit.batch.dask_engine import check_address

        scheduler = check_address(scheduler)
    out = Path(request.output)
    sources = [None] if request.demo else model_inputs(request.models)
    if len(sources) == 1 and not any(Path(m).is_dir() for m in request.models):
        _check_image_path(out, animated=request.animated)
        if request.contact_sheet or scheduler:
            raise UsageError("--contact-sheet and --scheduler are for several models (a folder for -o)")
        named = [("-o", request.output)] + [(f"--{flag}", path) for flag, path in request.maps.items() if path]
        check_distinct(named, sources)  # -o as given: "x.png/" names a folder
        for _, path in named:
            check_writable(path)
        return [Job(sources[0], out)], False, scheduler
    if out.suffix.lower() in IMAGE_SUFFIXES:
        raise UsageError(f"{out}: several models render into a folder; give a folder for -o")
    for flag, path in request.maps.items():
        if path:
            raise UsageError(f"--{flag} takes one model")
    if scheduler and request.workers != 1:
        raise UsageError("give --jobs or --scheduler, not both")
    if request.contact_sheet:
        check_sheet_path(Path(request.contact_sheet), out)
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: not a folder")
    batch = batch_jobs(sources, out, request.animated)
    check_batch_outputs(batch, request.contact_sheet and ("--contact-sheet", request.contact_sheet))
    return batch, True, scheduler


def batch_jobs(sources: list[Path], out: Path, animated: bool) -> list[Job]:
    """A batch's jobs: ``NAME.obj`` into ``out/NAME.png`` (``.gif`` for turntables); two
    models of one name are a usage error."""
    suffix = ".gif" if animated else ".png"
    batch = [Job(s, out / (s.stem + suffix)) for s in sources]
    seen: dict[Path, Path] = {}
    for job in batch:
        if job.output in seen:
            raise UsageError(f"{seen[job.output]} and {job.source} would both be written to {job.output}")
        seen[job.output] = job.source
    return batch


def check_sheet_path(path: Path, out: Path) -> None:
    """A contact sheet's path: a .png in a folder that exists or is the batch's folder
    ``out`` (made before the models render), checked before any model renders."""
    if path.name.lower() == ".png":
        raise UsageError(f"{path}: no file name before {path.name!r}")
    if path.suffix.lower() != ".png":
        raise UsageError(f"{path}: the contact sheet must end in .png")
    if os.path.realpath(path.parent) == os.path.realpath(out) and not out.exists():
        return
    check_writable(path)


def check_batch_outputs(batch: list[Job], sheet: tuple[str, object] | None) -> None:
    """No two images of a batch, nor an image and the contact sheet (``(what, path)``), are
    one file, and none is one of the models (a usage error otherwise)."""
    named = [(str(job.source) if job.source is not None else "--demo", job.output) for job in batch]
    check_distinct(named + ([sheet] if sheet else []), [job.source for job in batch])


def _check_image_path(out: Path, animated: bool) -> None:
    allowed = IMAGE_SUFFIXES if animated else (".png", ".svg")
    if out.name.lower() in allowed:  # ".png": a hidden file's name, with no suffix
        raise UsageError(f"{out}: no file name before {out.name!r}")
    if out.suffix.lower() not in allowed:
        raise UsageError(f"{out}: the output must end in {' or '.join(allowed)}")


def _attempt(job: Job, task) -> int:
    """Render one job; on failure print its one line. Returns its exit code. Only
    exceptions are caught: KeyboardInterrupt and SIGTERM stop everything."""
    with _report.model(job.source):
        try:
            render_model(job.source, job.output, task, say=_say)
            return 0
        except Exception as e:
            _stop.check()  # a signal's stop that came out as another exception (rasterkit.runtime.stop)
            code, line = _report.error_line(e)
    _say(line)
    return code


def render_jobs(jobs: list[Job], batch: bool, task, request: Request, scheduler: str | None) -> int:
    """Render every job as ``task`` (a :class:`rasterkit.batch.task.Task`) says; the exit code
    (see the module's documentation). ``scheduler``: the checked address of ``request``'s."""
    if not batch:
        if request.resume and jobs[0].source is not None and up_to_date(jobs[0].source, jobs[0].output):
            return 0
        return _attempt(jobs[0], task)
    from rasterkit.batch import engine as _many
    from rasterkit.batch.job_memory import check_batch

    check_batch(task, len(jobs), bool(request.contact_sheet))  # the memory, before any model
    client = None
    if scheduler:
        from rasterkit.batch import dask_engine as _dask

        client = _dask.client_for(scheduler)
    try:
        summary = _many.run([(job.source, job.output) for job in jobs], jobs[0].output.parent, task,
                            jobs=request.workers, client=client, resume=request.resume,
                            contact_sheet=Path(request.contact_sheet) if request.contact_sheet else None)
    finally:
        if client is not None:
            client.close()
    print(summary.line(), file=sys.stderr, flush=True)
    return summary.exit_code


def _say(line: str) -> None:
    """Print a line of the command line's on stderr."""
    print(line, file=sys.stderr, flush=True)
