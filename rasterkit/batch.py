"""``render_many``: a dataset of models into a folder of images, in parallel and resumably."""

from __future__ import annotations

import os
from pathlib import Path

from ._many import BatchSummary
from .options import MAX_IMAGE_SIZE

__all__ = ["BatchSummary", "render_many"]


def render_many(paths, out_dir, jobs: int = 1, client=None, resume: bool = False, *,
                progress: bool = False, contact_sheet=None, **render_options) -> BatchSummary:
    """Render every model of ``paths`` into ``out_dir``, as ``rasterkit render DIR... -o
    OUTDIR`` does, and return a :class:`BatchSummary`.

    Parameters
    ----------
    paths : path or list of paths
        OBJ files and folders (every ``.obj`` file directly in a folder, sorted by name).
        Each model ``NAME.obj`` renders to ``out_dir/NAME.png`` (``.gif`` with
        ``turntable``); two models of one name are refused.
    out_dir : path
        The folder of the images (made if missing) and of ``manifest.jsonl``: one JSON
        record per model (``input``, ``output``, ``status`` "ok", "error" or "skipped",
        ``error``, ``seconds``, ``triangles``), appended as results arrive.
    jobs : int
        Local worker processes (0: one per core). Each renders with ``cores // jobs``
        kernel threads, so the cores are never oversubscribed.
    client : distributed.Client, optional
        Render on this Dask cluster instead (``pip install 'rasterkit[dask]'``): its workers
        read the models and write the images, so both paths must be reachable from them.
    resume : bool
        Skip models whose image is complete and newer than the model (each gets a line of
        status "skipped"; the manifest is appended to instead of started anew).
    progress : bool
        Show the progress on stderr (a bar on a terminal, lines otherwise).
    contact_sheet : path, optional
        Also write a PNG grid of every image with its name.
    **render_options
        The ``render`` command's options as Python values: ``size=(1280, 960)``,
        ``mode="solid"``, ``projection="isometric"``, ``eye=(3, 2, 4)``, ``samples=4``,
        ``color="steelblue"``, ``background="transparent"``...

    Returns
    -------
    BatchSummary
        ``done``, ``skipped``, ``failed``, ``seconds``, ``models_per_second``, ``records``
        (this run's manifest records) and ``exit_code`` (0, or 2 when a model failed on
        bad input, 1 when a failure was an internal error). A failing model never stops
        the batch.

    Images are byte-identical whatever ``jobs`` or the engine.
    """
    from ._batch import IMAGE_SUFFIXES, _inputs, batch_jobs, check_sheet_path
    from ._report import UsageError
    from .cli import render_options as make_options
    from ._many import run

    options = make_options(**render_options)
    _check_size(options.size)
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0:
        raise ValueError(f"jobs must be a whole number >= 0, got {jobs!r}")
    out = Path(out_dir)
    if out.suffix.lower() in IMAGE_SUFFIXES or (out.exists() and not out.is_dir()):
        raise ValueError(f"{out}: out_dir must be a folder")
    try:
        planned = batch_jobs(_inputs([os.fspath(p) for p in paths]), out, bool(options.turntable))
        if contact_sheet is not None:
            check_sheet_path(Path(contact_sheet))
    except UsageError as e:
        raise ValueError(str(e)) from None
    pairs = [(job.source, job.output) for job in planned]
    return run(pairs, out, options, jobs=jobs, client=client, resume=resume, progress=progress,
               contact_sheet=None if contact_sheet is None else Path(contact_sheet), strict=True)


def _check_size(size) -> None:
    ok = isinstance(size, (tuple, list)) and len(size) == 2 and all(
        isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= MAX_IMAGE_SIZE for v in size)
    if not ok:
        raise ValueError(f"size must be (width, height), whole numbers 1 to {MAX_IMAGE_SIZE}, got {size!r}")
