"""``render_many``: a dataset of models into a folder of images, in parallel and resumably."""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Mapping
from pathlib import Path

from rasterkit.batch.engine import BatchSummary
from rasterkit.options import CULL, EDGES, MAX_IMAGE_SIZE, MODES, PROJECTIONS, SHADING

__all__ = ["BatchSummary", "check_options", "render_many"]


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
        Also write a PNG grid of every image with its name, in a folder that exists or in
        ``out_dir``. It must not be one of the images (ValueError).
    **render_options
        The ``render`` command's options as Python values: ``size=(1280, 960)``,
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
        before any model is read (:func:`check_options`, then the options are tried on a
        tetrahedron in this process when no ``client`` is given).

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
    from rasterkit.cli import render_options as make_options
    from rasterkit.batch.engine import run

    options = make_options(**check_options(render_options))
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0:
        raise ValueError(f"jobs must be a whole number >= 0, got {jobs!r}")
    out = Path(out_dir)
    if out.suffix.lower() in IMAGE_SUFFIXES or (out.exists() and not out.is_dir()):
        raise ValueError(f"{out}: out_dir must be a folder")
    try:
        planned = batch_jobs(model_inputs([os.fspath(p) for p in paths]), out, bool(options.turntable))
        if contact_sheet is not None:
            check_sheet_path(Path(contact_sheet), out)
        check_batch_outputs(planned, None if contact_sheet is None else ("contact_sheet", contact_sheet))
    except UsageError as e:
        raise ValueError(str(e)) from None
    except OSError as e:  # the contact sheet cannot be written where it is asked for
        raise ValueError(_report.error_line(e)[1].removeprefix("rasterkit: error: ")) from None
    from rasterkit.batch.job_memory import check_batch

    # the camera's own checks (fov, near, far, eye...) for every engine, and the memory
    check_batch(options, len(planned), contact_sheet is not None)
    pairs = [(job.source, job.output) for job in planned]
    return run(pairs, out, options, jobs=jobs, client=client, resume=resume, progress=progress,
               contact_sheet=None if contact_sheet is None else Path(contact_sheet), strict=True)


def _size(name, value):
    ok = isinstance(value, (tuple, list)) and len(value) == 2 and all(
        isinstance(v, numbers.Integral) and not isinstance(v, bool) and 1 <= v <= MAX_IMAGE_SIZE for v in value)
    if not ok:
        raise ValueError(f"size must be (width, height), whole numbers 1 to {MAX_IMAGE_SIZE}, got {value!r}")
    return tuple(int(v) for v in value)


def _real(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return float(value)


def _whole(name, value, low, high=None):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a whole number, got {type(value).__name__} {value!r}")
    if value < low or (high is not None and value > high):
        raise ValueError(f"{name} must be {low} to {high}, got {value!r}" if high is not None
                         else f"{name} must be at least {low}, got {value!r}")
    return int(value)


def _choice(choices):
    def check(name, value):
        if not isinstance(value, str):
            raise TypeError(f"{name} must be one of {', '.join(map(repr, choices))}, got {type(value).__name__}")
        if value not in choices:
            raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}")
        return value
    return check


def _optional(check):
    return lambda name, value: None if value is None else check(name, value)


def _point(name, value):
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise TypeError(f"{name} must be a point (x, y, z), got {value!r}")
    return tuple(_real(name, v) for v in value)


def _positive(name, value):
    value = _real(name, value)
    if value <= 0.0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    return value


def _unit(name, value):
    value = _real(name, value)
    if not 0.0 <= value <= 1.0:
        raise ValueError(f"{name} must lie in [0, 1], got {value!r}")
    return value


def _flag(name, value):
    if not isinstance(value, bool):
        raise TypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")
    return value


def _colour(name, value):
    from rasterkit.colors import parse_color

    try:
        parse_color(value)
    except (TypeError, ValueError) as e:
        raise type(e)(f"{name}: {e}") from None
    return value


def _no_hidden(name, value):
    if value is not None:
        raise ValueError(f"hidden={value!r} draws the hidden lines of an SVG drawing; render_many writes "
                         f"PNG or GIF images (leave hidden=None)")
    return None


def _camera(name, value):
    """A camera file's path (read now), or a mapping of ``Camera.from_opencv``'s keywords."""
    if isinstance(value, (str, os.PathLike)):
        from rasterkit.cli.args import read_camera_file

        try:
            return read_camera_file(os.fspath(value))
        except ValueError as e:  # the command line's UsageError: a plain ValueError here
            raise ValueError(str(e)) from None
    if not isinstance(value, Mapping):
        raise TypeError(f"camera_opencv must be a path or a mapping of K, R, t, width, height, got "
                        f"{type(value).__name__}")
    data = {k: v for k, v in value.items() if k != "source"}
    from rasterkit.camera import Camera

    try:
        Camera.from_opencv(**data)  # every key and value checked here, once
    except (TypeError, ValueError) as e:
        raise type(e)(f"camera_opencv: {e}") from None
    return dict(data, source=os.fspath(value.get("source", "camera_opencv")))


#: Every option of ``render`` that :func:`render_many` takes, with its check (and the
#: value the command line's parser would have made of it).
OPTION_CHECKS = {
    "mode": _choice(MODES), "projection": _choice(PROJECTIONS), "cull": _choice(CULL),
    "shading": _choice(SHADING), "edges": _choice(EDGES), "hidden": _no_hidden, "size": _size,
    "eye": _optional(_point), "target": _optional(_point), "up": _optional(_point),
    "fov": _real, "azimuth": _real, "elevation": _real, "aperture": _real, "crease_angle": _real,
    "near": _optional(_real), "far": _optional(_real), "distance": _optional(_real),
    "focus": _optional(_positive), "camera_opencv": _optional(_camera),
    "color": _colour, "line_color": _colour, "background": _colour, "aa": _flag,
    "samples": lambda name, value: _whole(name, value, 1, 256), "vignette": _unit,
    "turntable": _optional(lambda name, value: _whole(name, value, 1)),
}


def check_options(options: dict) -> dict:
    """``options`` of :func:`render_many` checked one by one (TypeError for a wrong type or
    an option ``render`` does not have, ValueError for a bad value), as the parser's values."""
    checked = {}
    for name, value in options.items():
        if name not in OPTION_CHECKS:
            raise TypeError(f"unknown render option {name!r}")
        checked[name] = OPTION_CHECKS[name](name, value)
    return checked
