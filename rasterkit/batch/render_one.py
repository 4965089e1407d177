"""One model of ``rasterkit render`` to one file: load, frame, render, save.

Shared by the command line's single render, the in-process batch and the batch workers
(:mod:`rasterkit.batch.workers`, :mod:`rasterkit.batch.dask_engine`), so that every engine writes the same
bytes. ``options`` is the ``render`` command's argument namespace (the command line's, or
:func:`rasterkit.cli.render_options` for :func:`rasterkit.render_many`).

At module level this imports only the standard library and rasterkit's pure-Python modules:
NumPy and Numba load when a model is rendered.
"""

from __future__ import annotations

import math
from pathlib import Path

from rasterkit.batch import report as _report
from rasterkit.cli.args import framed_camera
from rasterkit.batch.outputs import check_distinct, check_writable, named_outputs
from rasterkit.batch.job_memory import check_job
from rasterkit.batch.report import UsageError
from rasterkit.options import SVG_MODES

__all__ = ["render_model"]


def _turntable(mesh, camera, center, frames: int, style: dict):
    """The frames of a turntable, rendered one at a time as they are asked for."""
    from rasterkit.raster.render import render
    from rasterkit.scene import Scene
    from rasterkit.transform import rotate_axis

    for k in range(frames):
        spin = rotate_axis(2 * math.pi * k / frames, (0, 1, 0), center)
        yield render(Scene(camera).add(mesh, spin), **style).color


def render_model(source: Path | None, output: Path, options, say=None) -> int:
    """Render the model ``source`` (None: the built-in demo) into ``output`` as ``options``
    say; returns its number of triangles. ``say(line)`` prints the loader's warnings (one
    line each; default: dropped). Every output is checked before the model is read, and
    the files of one render (image, depth, normals, ids) are written all or none."""
    from rasterkit.runtime import warm as _warm
    from rasterkit.image.atomic import all_or_none
    from rasterkit.image.files import save_animation
    from rasterkit.obj import load_obj
    from rasterkit.raster.render import render
    from rasterkit.shapes import demo

    svg = output.suffix.lower() == ".svg"
    _check_svg_options(options, svg)
    named = named_outputs(options, output)
    check_distinct(named, [source])
    for _, path in named:
        check_writable(path)
    if not svg:
        _warm.start(dict(mode=options.mode, cull=options.cull, shading=options.shading,
                         background=options.background, aa=options.aa, ids=bool(options.ids),
                         normals=bool(options.normals), camera_depth=bool(options.depth)),
                    depth=False, loading=source is not None)
    elif options.mode == "hidden":  # the SVG's depth pass: the triangles' band worker, with face ids
        _warm.start(dict(mode="hidden", cull="back", shading="flat", background="white", aa=False, ids=True),
                    depth=False, loading=source is not None)
    mesh = demo() if source is None else load_obj(source)
    if len(mesh.faces) == 0 and len(mesh.edges) == 0 and len(mesh.lines) == 0:  # all dropped (NaN vertices)
        raise UsageError(f"{'; '.join(map(_report.one_line, mesh.warnings)) or source}: nothing left to draw")
    if say is not None:
        for warning in mesh.warnings:
            say(f"rasterkit: warning: {_report.one_line(warning)}")
    camera, center = framed_camera(options, mesh)
    if svg:
        from rasterkit.svg import render_svg, save_svg

        save_svg(render_svg(mesh, camera, mode=options.mode, edges=options.edges, crease_angle=options.crease_angle,
                            hidden=options.hidden, stroke=options.line_color), output)
        return len(mesh.faces)
    check_job(mesh, camera, options, output)  # the whole job's memory, before any of it is allocated
    style = dict(mode=options.mode, cull=options.cull, shading=options.shading, color=options.color,
                 line_color=options.line_color, background=options.background, aa=options.aa,
                 samples=options.samples, vignette=options.vignette, edges=options.edges,
                 crease_angle=options.crease_angle)
    if options.turntable:  # streamed: one frame in memory at a time
        save_animation(_turntable(mesh, camera, center, options.turntable, style), output)
        return len(mesh.faces)
    fb = render(mesh, camera, **style, normals=bool(options.normals), ids=bool(options.ids),
                camera_depth=bool(options.depth))
    with all_or_none():
        if options.depth:
            fb.save_depth(options.depth)
        if options.normals:
            fb.save_normals(options.normals)
        if options.ids:
            fb.save_ids(options.ids)
        fb.save(output)
    return len(mesh.faces)


def _check_svg_options(options, svg: bool) -> None:
    if not svg:
        if options.hidden:
            raise UsageError("--hidden dashed is for SVG output (-o NAME.svg)")
        return
    if options.mode not in SVG_MODES:
        raise UsageError(f"an SVG drawing takes --mode {' or '.join(SVG_MODES)}, not {options.mode}")
    for flag in ("depth", "normals", "ids"):
        if getattr(options, flag):
            raise UsageError(f"--{flag} is for PNG output")
