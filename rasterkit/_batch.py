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

import math
import sys
from dataclasses import dataclass
from pathlib import Path

from . import _report
from ._report import UsageError
from .options import SVG_MODES

__all__ = ["jobs", "render_jobs"]

IMAGE_SUFFIXES = (".png", ".gif", ".apng")


@dataclass
class Job:
    source: Path | None  # None: the demo model
    output: Path


def _inputs(models: list[str]) -> list[Path]:
    paths = []
    for name in models:
        path = Path(name)
        if path.is_dir():
            found = sorted(p for p in path.iterdir() if p.suffix.lower() == ".obj" and p.is_file())
            if not found:
                raise UsageError(f"{path}: no .obj files in this folder")
            paths.extend(found)
        else:
            paths.append(path)
    return paths


def jobs(args) -> tuple[list[Job], bool]:
    """The jobs of a ``render`` command, and whether they are a batch (into a folder)."""
    if args.demo and args.models:
        raise UsageError("give MODEL.obj files or --demo, not both")
    if not args.demo and not args.models:
        raise UsageError("give a MODEL.obj (or a folder of them), or --demo")
    out = Path(args.output)
    sources = [None] if args.demo else _inputs(args.models)
    if len(sources) == 1 and not any(Path(m).is_dir() for m in args.models):
        _check_image_path(out, animated=bool(args.turntable))
        return [Job(sources[0], out)], False
    if out.suffix.lower() in IMAGE_SUFFIXES:
        raise UsageError(f"{out}: several models render into a folder; give a folder for -o")
    if args.depth:
        raise UsageError("--depth takes one model")
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: not a folder")
    suffix = ".gif" if args.turntable else ".png"
    batch = [Job(s, out / (s.stem + suffix)) for s in sources]
    seen: dict[Path, Path] = {}
    for job in batch:
        if job.output in seen:
            raise UsageError(f"{seen[job.output]} and {job.source} would both be written to {job.output}")
        seen[job.output] = job.source
    return batch, True


def _check_image_path(out: Path, animated: bool) -> None:
    allowed = IMAGE_SUFFIXES if animated else (".png", ".svg")
    if out.suffix.lower() not in allowed:
        raise UsageError(f"{out}: the output must end in {' or '.join(allowed)}")
    if not out.parent.is_dir():
        raise UsageError(f"{out}: folder {str(out.parent)!r} does not exist")


def _camera(args, center, radius):
    from .camera import Camera

    width, height = args.size
    return Camera.preset(args.projection, center, radius, width=width, height=height,
                         azimuth=args.azimuth, elevation=args.elevation, fov_y=args.fov,
                         distance=args.distance, eye=args.eye, target=args.target, up=args.up,
                         near=args.near, far=args.far, aperture=args.aperture,
                         focus_distance=args.focus)


def _turntable(mesh, camera, center, frames: int, style: dict):
    """The frames of a turntable, rendered one at a time as they are asked for."""
    from .render import render
    from .scene import Scene
    from .transform import rotate_axis

    for k in range(frames):
        spin = rotate_axis(2 * math.pi * k / frames, (0, 1, 0), center)
        yield render(Scene(camera).add(mesh, spin), **style).color


def _check_svg_options(args, svg: bool) -> None:
    if not svg:
        if args.hidden:
            raise UsageError("--hidden dashed is for SVG output (-o NAME.svg)")
        return
    if args.mode not in SVG_MODES:
        raise UsageError(f"an SVG drawing takes --mode {' or '.join(SVG_MODES)}, not {args.mode}")
    if args.depth:
        raise UsageError("--depth is for PNG output")


def _render_svg_job(mesh, camera, job: Job, args) -> None:
    from .svg import render_svg, save_svg

    text = render_svg(mesh, camera, mode=args.mode, edges=args.edges, crease_angle=args.crease_angle,
                      hidden=args.hidden, stroke=args.line_color)
    save_svg(text, job.output)


def _render_job(job: Job, args) -> None:
    import numpy as np

    from . import _warm
    from .image import atomic_write, save_animation
    from .obj import load_obj
    from .render import render
    from .shapes import demo

    svg = job.output.suffix.lower() == ".svg"
    _check_svg_options(args, svg)
    if not svg:
        _warm.start(dict(mode=args.mode, cull=args.cull, shading=args.shading, background=args.background,
                         aa=args.aa), depth=bool(args.depth), loading=job.source is not None)
    elif args.mode == "hidden":  # the SVG's depth pass: the triangles' band worker, with face ids
        _warm.start(dict(mode="hidden", cull="back", shading="flat", background="white", aa=False, ids=True),
                    depth=False, loading=job.source is not None)
    mesh = demo() if job.source is None else load_obj(job.source)
    for warning in mesh.warnings:
        _say(f"rasterkit: warning: {_report.one_line(warning)}")
    center, radius = mesh.bounding_sphere()
    if radius == 0.0:
        raise UsageError("the model has no extent (all vertices coincide)")
    camera = _camera(args, center, radius)
    if svg:
        _render_svg_job(mesh, camera, job, args)
        return
    style = dict(mode=args.mode, cull=args.cull, shading=args.shading, color=args.color,
                 line_color=args.line_color, background=args.background, aa=args.aa,
                 samples=args.samples, vignette=args.vignette, edges=args.edges,
                 crease_angle=args.crease_angle)
    if args.turntable:  # streamed: one frame in memory at a time
        save_animation(_turntable(mesh, camera, center, args.turntable, style), job.output)
        return
    fb = render(mesh, camera, **style)
    if args.depth:
        with atomic_write(args.depth) as tmp:
            with open(tmp, "wb") as f:
                np.save(f, fb.depth)
    fb.save(job.output)


def _attempt(job: Job, args) -> int:
    """Render one job; on failure print its one line. Returns its exit code. Only
    exceptions are caught: KeyboardInterrupt and SIGTERM stop everything."""
    with _report.model(job.source):
        try:
            _render_job(job, args)
            return 0
        except Exception as e:
            code, line = _report.error_line(e)
    _say(line)
    return code


def render_jobs(jobs: list[Job], batch: bool, args) -> int:
    """Render every job; the exit code (see the module's documentation)."""
    if not batch:
        return _attempt(jobs[0], args)
    jobs[0].output.parent.mkdir(parents=True, exist_ok=True)
    codes = []
    try:
        for k, job in enumerate(jobs, 1):
            _show_progress(k, len(jobs), job.source.name)
            codes.append(_attempt(job, args))
    finally:
        _clear_progress()
    failed = sum(code != 0 for code in codes)
    _say(f"rasterkit: rendered {len(codes) - failed}, failed {failed}")
    return 1 if 1 in codes else max(codes)


_progress_shown = False  # a progress line waits at the start of the terminal's line


def _show_progress(k: int, n: int, name: str) -> None:
    """The progress line: redrawn in place on a terminal, one line a model otherwise."""
    global _progress_shown
    _clear_progress()
    width = 24
    bar = "#" * (width * k // n) + "-" * (width - width * k // n)
    tty = sys.stderr.isatty()
    print(f"[{bar}] {k}/{n} {name}".ljust(72), end="\r" if tty else "\n", file=sys.stderr, flush=True)
    _progress_shown = tty


def _clear_progress() -> None:
    global _progress_shown
    if _progress_shown:
        print(" " * 72, end="\r", file=sys.stderr, flush=True)
        _progress_shown = False


def _say(line: str) -> None:
    """Print a line of the command line's on stderr (after taking a progress line away)."""
    _clear_progress()
    print(line, file=sys.stderr, flush=True)
