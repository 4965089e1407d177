"""One model of ``rasterkit render`` to one file: load, frame, render, save.

Shared by the command line's single render, the in-process batch and the batch workers
(:mod:`rasterkit.batch.workers`, :mod:`rasterkit.batch.dask_engine`), so that every engine writes the same
bytes. What to do with the model is a :class:`rasterkit.batch.task.Task`.

At module level this imports only the standard library and rasterkit's pure-Python modules:
NumPy and Numba load when a model is rendered.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

from rasterkit.batch import report as _report
from rasterkit.batch.outputs import check_distinct, check_writable, named_outputs
from rasterkit.batch.job_memory import check_job
from rasterkit.batch.report import UsageError
from rasterkit.options import SVG_MODES, RenderOptions

__all__ = ["Drawn", "drawn_model", "load_drawn", "render_model"]


class Drawn(NamedTuple):
    """A model as it is drawn (:func:`load_drawn`)."""

    model: object  #: what the file holds: a Mesh, a Scene or a PointCloud
    mesh: object  #: the Mesh drawn (None: a point cloud alone)
    cloud: object  #: the points drawn with it (None: none)
    options: RenderOptions  #: the render's, with a glTF file's lights where it names none
    framed: object  #: what the view frames (a glTF scene itself: it may bring its own camera)


def load_drawn(source: Path | None, options: RenderOptions, textures: bool, say=None) -> Drawn:
    """The model ``source`` (None: the built-in demo) read as a render draws it, ``textures``
    read or not; ``say(line)`` prints the loader's warnings. Raises UsageError when nothing
    of it is left to draw."""
    from rasterkit.formats import load
    from rasterkit.shapes import demo

    drawn = drawn_model(demo() if source is None else load(source, textures=textures), options)
    mesh, cloud = drawn.mesh, drawn.cloud
    if mesh is not None and cloud is None and len(mesh.faces) == 0 and len(mesh.edges) == 0 and len(mesh.lines) == 0:
        raise UsageError(f"{'; '.join(map(_report.one_line, mesh.warnings)) or source}: nothing left to draw")
    if say is not None:
        for warning in (cloud if mesh is None else mesh).warnings:
            say(f"rasterkit: warning: {_report.one_line(warning)}")
    return drawn


def drawn_model(model, options: RenderOptions) -> Drawn:
    """``model`` (a Mesh, Scene or PointCloud) as a render draws it with ``options``."""
    from rasterkit.formats import as_drawn
    from rasterkit.scene import Scene

    mesh, cloud = as_drawn(model)  # mesh None: a point cloud alone; cloud with a mesh: a glTF scene's points
    if isinstance(model, Scene) and model.lights and not options.lights:  # a glTF file's lights, unless --light
        options = options.replace(lights=tuple(model.lights))
    framed = cloud if mesh is None else model if isinstance(model, Scene) else mesh
    return Drawn(model, mesh, cloud, options, framed)


def render_model(source: Path | None, output: Path, task, say=None) -> int:
    """Render the model ``source`` (None: the built-in demo) into ``output`` as ``task`` (a
    :class:`rasterkit.batch.task.Task`) says; returns its number of triangles. ``say(line)`` prints the loader's warnings (one
    line each; default: dropped). Every output is checked before the model is read, and
    the files of one render (image, depth, normals, ids) are written all or none."""
    from rasterkit.runtime import warm as _warm
    from rasterkit.formats import texture_maps
    from rasterkit.image.atomic import all_or_none
    from rasterkit.image.files import save_animation
    from rasterkit.raster.modes import mode
    from rasterkit.raster.render import render
    from rasterkit.raster.turntable import turntable_frames

    svg = output.suffix.lower() == ".svg"
    _check_svg_options(task, svg)
    named = named_outputs(task, output)
    check_distinct(named, [source])
    for _, path in named:
        check_writable(path)
    options = task.frame_options()
    # textures are read only where they are drawn (shaded faces, into an image)
    textured = options.textures and not svg and mode(options.mode).shaded
    if not svg:
        _warm.start(options, depth=False, loading=source is not None,
                    maps=(lambda: texture_maps(source)) if textured and source is not None else frozenset())
    elif options.mode == "hidden":  # the SVG's depth pass: the triangles' band worker, with face ids
        _warm.start(RenderOptions(mode="hidden", ids=True), depth=False, loading=source is not None)
    drawn = load_drawn(source, options, textured, say)
    mesh, cloud, options = drawn.mesh, drawn.cloud, drawn.options
    camera, center = task.view.frame(drawn.framed)
    if cloud is not None and svg:
        if mesh is None:
            raise UsageError(f"{source}: a point cloud is drawn into an image, not an SVG drawing")
        if say is not None:
            say(f"rasterkit: warning: {source}: its {len(cloud)} points are not drawn in an SVG drawing")
        cloud = None
    if mesh is None:
        mesh = cloud.as_mesh()  # no faces: what the memory check and the render take with the points
    if svg:
        from rasterkit.svg import render_svg, save_svg

        save_svg(render_svg(mesh, camera, mode=options.mode, edges=options.edges, crease_angle=options.crease_angle,
                            hidden=task.hidden, line_color=options.line_color), output)
        return len(mesh.faces)
    check_job(mesh, camera, task, output)  # the whole job's memory, before any of it is allocated
    if task.turntable:  # streamed: one frame in memory at a time
        save_animation(turntable_frames(mesh, cloud, camera, center, task.turntable, options, task.turn_lights),
                       output)
        return len(mesh.faces)
    fb = render(mesh, camera, options=options, **({} if cloud is None else cloud.render_arguments()))
    with all_or_none():
        if task.depth:
            fb.save_depth(task.depth)
        if task.normals:
            fb.save_normals(task.normals)
        if task.ids:
            fb.save_ids(task.ids)
        fb.save(output)
    return len(mesh.faces)


def _check_svg_options(task, svg: bool) -> None:
    if not svg:
        if task.hidden:
            raise UsageError("--hidden dashed is for SVG output (-o NAME.svg)")
        return
    if task.options.mode not in SVG_MODES:
        raise UsageError(f"an SVG drawing takes --mode {' or '.join(SVG_MODES)}, not {task.options.mode}")
    for flag in ("depth", "normals", "ids"):
        if getattr(task, flag):
            raise UsageError(f"--{flag} is for PNG output")
