"""``render_many``: a dataset of models into a folder of images, in parallel and resumably."""

from __future__ import annotations

import os
from pathlib import Path

from rasterkit.batch.engine import BatchSummary
from rasterkit.batch.task import Task

__all__ = ["BatchSummary", "render_many", "task_for"]


def render_many(paths, out_dir, jobs: int = 1, client=None, resume: bool = False, *,
                progress: bool = False, contact_sheet=None, options=None, view=None, turntable: int | None = None,
                turn_lights: bool = False, **changes) -> BatchSummary:
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
        Also write a PNG grid of every image with its name, in a folder that exists or in
        ``out_dir``. It must not be one of the images (ValueError).
    options : RenderOptions, optional
        How each image is drawn.
    view : View, optional
        How each model's camera is chosen (default: framed automatically, 800x600).
    turntable : int, optional
        Frames of an animated GIF around each model instead of a still image.
    turn_lights : bool
        The turntable's lights turn with the model (default: they stay where they are, and
        the shadows move over the turning model).
    **changes
        Fields of :class:`RenderOptions` or :class:`View` that replace those of ``options``
        and ``view``, as the ``render`` command's options: ``size=(1280, 960)``,
        ``mode="solid"``, ``projection="isometric"``, ``eye=(3, 2, 4)``, ``samples=4``,
        ``color="steelblue"``, ``background="transparent"``...

    Raises
    ------
    TypeError
        For an option that ``render`` does not have, or a value of the wrong type
        (``turntable="3"``, ``samples=2.0``, ``aa=1``).
    ValueError
        For a value out of its range or choices, a camera that cannot be made, a colour
        that is not one, a camera file that cannot be read: every option is checked once,
        before any model is read (by the records, then the task is tried on a tetrahedron
        in this process when no ``client`` is given).

    Returns
    -------
    BatchSummary
        ``done``, ``skipped``, ``failed``, ``seconds``, ``models_per_second``, ``records``
        (this run's manifest records) and ``exit_code`` (0, or 2 when a model failed on
        bad input, 1 when a failure was an internal error). A failing model never stops
        the batch.

    Images are byte-identical whatever ``jobs`` or the engine.
    """
    from rasterkit.batch.plan import IMAGE_SUFFIXES, model_inputs, batch_jobs, check_batch_outputs, check_sheet_path
    from rasterkit.batch import report as _report
    from rasterkit.batch.report import UsageError
    from rasterkit.batch.engine import run

    task = task_for(options, view, turntable, changes, turn_lights)
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0:
        raise ValueError(f"jobs must be a whole number >= 0, got {jobs!r}")
    out = Path(out_dir)
    if out.suffix.lower() in IMAGE_SUFFIXES or (out.exists() and not out.is_dir()):
        raise ValueError(f"{out}: out_dir must be a folder")
    try:
        planned = batch_jobs(model_inputs([os.fspath(p) for p in paths]), out, bool(task.turntable))
        if contact_sheet is not None:
            check_sheet_path(Path(contact_sheet), out)
        check_batch_outputs(planned, None if contact_sheet is None else ("contact_sheet", contact_sheet))
    except UsageError as e:
        raise ValueError(str(e)) from None
    except OSError as e:  # the contact sheet cannot be written where it is asked for
        raise ValueError(_report.error_line(e)[1].removeprefix("rasterkit: error: ")) from None
    from rasterkit.batch.job_memory import check_batch

    # the camera's own checks (fov, near, far, eye...) for every engine, and the memory
    check_batch(task, len(planned), contact_sheet is not None)
    pairs = [(job.source, job.output) for job in planned]
    return run(pairs, out, task, jobs=jobs, client=client, resume=resume, progress=progress,
               contact_sheet=None if contact_sheet is None else Path(contact_sheet), strict=True)


def task_for(options=None, view=None, turntable=None, changes: dict | None = None, turn_lights: bool = False) -> Task:
    """The :class:`Task` of :func:`render_many`'s arguments: ``changes`` go to the
    :class:`RenderOptions` or the :class:`View` that has a field of their name. A still
    image's maps and an SVG's hidden lines are not a batch's: asking for them is a
    ``ValueError``; a name neither has is a ``TypeError``."""
    from rasterkit.camera.view import FIELDS as VIEW_FIELDS, View
    from rasterkit.options import FIELDS as OPTION_FIELDS, RenderOptions

    changes = dict(changes or {})
    if changes.get("hidden") is not None:
        raise ValueError(f"hidden={changes['hidden']!r} draws the hidden lines of an SVG drawing; render_many "
                         f"writes PNG or GIF images (leave hidden=None)")
    changes.pop("hidden", None)
    for name in ("ids", "normals", "camera_depth", "uv"):
        if changes.get(name):
            raise ValueError(f"{name}: render_many writes images, not maps (render each model for its maps)")
    unknown = set(changes) - OPTION_FIELDS - VIEW_FIELDS
    if unknown:
        raise TypeError(f"unknown render option {sorted(unknown)[0]!r}")
    task = Task(RenderOptions() if options is None else options, View() if view is None else view,
                turntable=turntable, turn_lights=turn_lights)  # (checks the records' types)
    return task.replace(options=task.options.replace(**{k: v for k, v in changes.items() if k in OPTION_FIELDS}),
                        view=task.view.replace(**{k: v for k, v in changes.items() if k in VIEW_FIELDS}))
