"""The batch engine: many models into one folder, by one of three engines, with a manifest.

1. ``--resume``: models whose image is complete and newer than the model are skipped
   without loading them (:func:`rasterkit.batch.manifest.up_to_date`); each still gets its
   manifest line, status ``skipped``.
2. The rest render on one engine — this process (``jobs=1``), a pool of ``jobs`` local
   worker processes (:class:`rasterkit.batch.workers.LocalPool`), or a Dask cluster
   (:mod:`rasterkit.batch.dask_engine`) — each model through :func:`rasterkit.batch.workers.run_task`, so the
   images are the same bytes whatever the engine and the number of workers.
3. Each result is appended to ``OUTDIR/manifest.jsonl`` as it arrives, a failure is
   reported in one line, the progress advances; at the end the contact sheet if asked for,
   and a summary line. A manifest line or a contact sheet that cannot be written (a full
   disk) is one line too, and the batch goes on to its summary (exit code 2).

Kernel threads: one process alone uses every core; ``jobs`` workers share them
(``cores // jobs`` threads each, at least one), so the cores are never oversubscribed.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path

from rasterkit.batch.manifest import Manifest, up_to_date
from rasterkit.batch.report import error_line
from rasterkit.batch.progress import Progress
from rasterkit.batch.workers import LocalPool, cores, run_task, warm_up

__all__ = ["BatchSummary", "run"]


@dataclass
class BatchSummary:
    """What a batch did: counts, time, the manifest's records of this run, and the exit
    code the command line gives it (0 all rendered or skipped, 2 a model failed on bad
    input, 1 a failure was an internal error)."""

    done: int = 0
    skipped: int = 0
    failed: int = 0
    seconds: float = 0.0
    manifest: Path | None = None
    records: list = field(default_factory=list)
    exit_code: int = 0

    @property
    def models_per_second(self) -> float:
        return (self.done + self.failed) / self.seconds if self.seconds > 0 else 0.0

    def line(self) -> str:
        return (f"rasterkit: rendered {self.done}, skipped {self.skipped}, failed {self.failed} "
                f"in {self.seconds:.1f} s ({self.models_per_second:.2f} models/s)")


def run(pairs: list[tuple[Path, Path]], out_dir: Path, task, *, jobs: int = 1, client=None,
        resume: bool = False, progress: bool = True, contact_sheet: Path | None = None,
        strict: bool = False) -> BatchSummary:
    """Render ``pairs`` of (model, image) into ``out_dir`` (see the module's documentation).
    ``task``: a :class:`rasterkit.batch.task.Task`; ``jobs`` 0: one worker per core. Without a ``client``, ``task`` is tried first on a
    tetrahedron in this process (:func:`rasterkit.batch.workers.warm_up`), so the kernels are
    loaded (or compiled) once for every local worker; ``strict``: an option that fails
    there raises, before any model or the manifest is touched (otherwise every model
    reports it, naming itself, as the command line does)."""
    jobs = cores() if jobs == 0 else jobs
    summary = BatchSummary()
    report = Progress(len(pairs), enabled=progress)
    say = report.say
    started = time.monotonic()
    todo, skipped = [], []
    for source, output in pairs:
        if resume and up_to_date(source, output):
            summary.skipped += 1
            skipped.append(_skipped(source, output))
            report.advance(source.name, "skipped")
        else:
            todo.append((os.fspath(source), os.fspath(output)))
    if todo and client is None:
        warm_up(task, strict=strict)
    out_dir.mkdir(parents=True, exist_ok=True)
    codes, unrecorded = [], []
    with Manifest(out_dir, append=resume) as manifest:
        summary.manifest = manifest.path
        for record in skipped:  # the manifest lists every model, also those a killed run
            manifest.write(record)  # rendered without writing their line
            summary.records.append(record)

        def on_result(record: dict) -> None:
            code = record.pop("code", 0 if record["status"] == "ok" else 1)
            for warning in record.get("warnings", ()):
                say(warning)
            summary.records.append(record)
            codes.append(code)
            if record["status"] == "ok":
                summary.done += 1
            else:
                summary.failed += 1
                say(f"rasterkit: {'error' if code == 2 else 'internal error'}: {record['error']}")
            try:
                manifest.write(record)
            except OSError as e:  # a full disk: said once, the batch goes on
                if not unrecorded:
                    say(error_line(e)[1])
                unrecorded.append(record["input"])
                codes.append(2)
            report.advance(Path(record["input"]).name, record["status"], record["seconds"])

        try:
            _engine(todo, task, jobs, client, on_result)
        finally:
            report.close()
    if contact_sheet is not None:
        from rasterkit.batch.contact import contact_sheet as write_sheet

        try:
            write_sheet([output for _, output in pairs], contact_sheet)
        except Exception as e:  # a full disk, say: one line, and the summary still comes
            code, line = error_line(e)
            say(line)
            codes.append(code)
    summary.seconds = time.monotonic() - started
    summary.exit_code = 1 if 1 in codes else max(codes, default=0)
    return summary


def _skipped(source: Path, output: Path) -> dict:
    return {"input": os.fspath(source), "output": os.fspath(output), "status": "skipped", "error": None,
            "seconds": None, "triangles": None, "warnings": []}


def _engine(todo, task, jobs, client, on_result) -> None:
    if not todo:
        return
    if client is not None:
        from rasterkit.batch import dask_engine as _dask

        _dask.run(client, todo, task, on_result)
    elif jobs > 1 and len(todo) > 1:
        LocalPool(min(jobs, len(todo)), max(1, cores() // jobs), task).run(todo, on_result)
    else:
        for source, output in todo:
            on_result(run_task(source, output, task))
