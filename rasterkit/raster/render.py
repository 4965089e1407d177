"""render(): resolve the options, plan the frame, draw it, finish its maps.

The options are one :class:`rasterkit.RenderOptions`; the plan (:mod:`rasterkit.raster.plan`)
checks the mesh and camera and decides what is drawn before anything is allocated; the
drawing (:mod:`rasterkit.raster.frame`) runs the passes that the mode's row of
:data:`rasterkit.raster.modes.MODE_TABLE` names, once or once per sample
(:mod:`rasterkit.raster.accumulate`); a distorted camera draws an undistorted frame and
resamples it (:mod:`rasterkit.raster.distortion`).
"""

from __future__ import annotations

from functools import partial

from rasterkit.camera import Camera
from rasterkit.limits import check_memory
from rasterkit.options import MODES, RenderOptions
from rasterkit.raster import accumulate as _accumulate
from rasterkit.raster.frame import LINE_DEPTH_BIAS, draw_frame, new_frame, shared_setup
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.raster.modes import POLYGON_OFFSET
from rasterkit.raster.plan import FramePlan, plan_frame
from rasterkit.raster.shading import AMBIENT
from rasterkit.scene import Scene

__all__ = ["AMBIENT", "LINE_DEPTH_BIAS", "MODES", "POLYGON_OFFSET", "render", "render_bytes", "resolve_options"]


def render(mesh, camera: Camera | None = None, mode: str | None = None, *, options: RenderOptions | None = None,
           points=None, **changes) -> Framebuffer:
    """Render a mesh or a scene seen by a camera into a new :class:`Framebuffer`.

    Parameters
    ----------
    mesh : Scene, Mesh, (vertices, faces) tuple, or object with ``.vertices`` and ``.faces``
        Positions in world space, (N, 3) float; faces (M, 3) int, counter-clockwise seen
        from the front. None draws only ``points``. A :class:`Scene` brings its objects'
        model matrices and colours, and the defaults for ``camera``, ``background`` and
        ``light``.
    camera : Camera
        Gives the image size and the world -> raster chain (optional for a scene that has
        one). A camera with ``distortion`` coefficients (``Camera.from_opencv(...,
        dist=...)``) gives the distorted image: an undistorted render resampled through
        OpenCV's distortion model (:mod:`rasterkit.raster.distortion`).
    mode : {"wire", "hidden", "solid", "solid+wire"}, optional
        The same as ``mode=`` among ``changes`` (see :class:`RenderOptions`).
    options : RenderOptions, optional
        How the frame is drawn (default: ``RenderOptions()``, a wireframe).
    points : (K, 3) array_like of float, optional
        A point cloud, world space, drawn after the faces and edges as squares of
        ``point_size`` pixels centred on each point, depth-tested against the faces and each
        other (:mod:`rasterkit.raster.points`). ``point_color`` may be one colour or (K, 3|4)
        values 0-255, one per point. Points write colour and depth, not ids or normals.
    **changes
        Fields of :class:`RenderOptions` that replace those of ``options``: ``cull``,
        ``shading``, ``color``, ``line_color``, ``background``, ``light``, ``aa``, ``edges``,
        ``crease_angle``, ``samples``, ``vignette``, ``ids``, ``normals``, ``camera_depth``,
        ``point_size``, ``point_color``.

    With ``samples > 1``, the depth buffer, the ids and the normals are those of the centre
    sample: what ``samples=1`` gives with the same camera (the depth is drawn when first
    read; with ``ids`` the centre sample is drawn once more, eagerly).

    Returns
    -------
    Framebuffer

    Raises
    ------
    TypeError
        For a mesh, camera or light that is not one (None, a string, arrays of booleans,
        complex numbers or objects), an option of the wrong type, or one that does not exist.
    ValueError
        For an option out of its range or choices, a bad colour or light, or a Mesh whose
        arrays were changed after it was made (:meth:`Mesh.check_intact`).
    rasterkit.limits.LimitError
        When the render would need more memory than :func:`rasterkit.limits.memory_limit`
        (:func:`render_bytes` estimates it before anything is allocated).
    """
    options, point_colors = resolve_options(options, mode, changes)
    seen_by = mesh.camera if camera is None and isinstance(mesh, Scene) else camera
    if isinstance(seen_by, Camera) and seen_by.distortion:  # an undistorted render, resampled
        from rasterkit.raster.distortion import render_distorted

        # (its metric depth is resampled from the undistorted depth when asked for)
        ideal_options = options.replace(camera_depth=False)
        return render_distorted(seen_by, lambda ideal: _render_planned(
            plan_frame(mesh, ideal, ideal_options, points, point_colors)))
    return _render_planned(plan_frame(mesh, camera, options, points, point_colors))


def resolve_options(options: RenderOptions | None, mode: str | None, changes: dict):
    """``(RenderOptions, point_colors)``: ``options`` (or the defaults) with ``mode`` and
    ``changes``; per-point colours (a 2-D ``point_color``) come apart, as they go with the
    points."""
    if options is None:
        options = _DEFAULTS
    elif not isinstance(options, RenderOptions):
        raise TypeError(f"options must be a rasterkit.RenderOptions, got {type(options).__name__}")
    point_colors = None
    if _per_point(changes.get("point_color")):
        changes = dict(changes)
        point_colors = changes.pop("point_color")
    if mode is not None:
        changes = {**changes, "mode": mode}
    return options.replace(**changes), point_colors


_DEFAULTS = RenderOptions()


def _per_point(value) -> bool:
    """Whether ``value`` holds a colour per point (an (N, 3|4) array), not one colour."""
    if value is None or isinstance(value, str):
        return False
    import numpy as np

    try:
        return np.ndim(value) == 2
    except (TypeError, ValueError):
        return False


def _render_planned(plan: FramePlan) -> Framebuffer:
    """Draw and finish ``plan``, after checking its memory."""
    mesh, camera, style, options = plan.mesh, plan.camera, plan.style, plan.options
    check_memory(plan.need, f"a {camera.width}x{camera.height} {options.mode} render of {len(mesh.faces)} faces")
    if plan.in_bands:  # imported here: a plain render loads none of it
        from dataclasses import replace

        from rasterkit.raster.vision import maps_record

        style = replace(style, maps=maps_record(camera.height, camera.width, mesh, camera, camera.world_to_raster(),
                                                options.shading if options.normals else None, plan.object_faces,
                                                plan.metric, options.uv))
    with_ids = plan.with_ids
    if plan.one_sample:
        fb = new_frame(mesh, camera, style, plan.background, with_ids)
    else:
        fb = _accumulate.render_samples(camera, options.samples, options.vignette, plan.background, with_ids,
                                        partial(draw_frame, mesh, style), partial(shared_setup, mesh, camera, style),
                                        partial(new_frame, mesh, camera, style, plan.background))
    fb.camera = camera
    return _finish(fb, plan, style)


def _finish(fb: Framebuffer, plan: FramePlan, style) -> Framebuffer:
    """The maps asked for, made in the bands or now; ids dropped when only normals needed them."""
    options, object_faces = plan.options, plan.object_faces
    if plan.in_bands:
        from rasterkit.raster.vision import finish_maps

        finish_maps(fb, style.maps)
    elif options.normals or options.uv or object_faces is not None:
        from rasterkit.raster.vision import fill_maps

        fill_maps(fb, plan.mesh, plan.camera, plan.camera.world_to_raster(),
                  options.shading if options.normals else None, object_faces, options.uv)
    if plan.ao_radius is not None:
        from rasterkit.raster.ao import ambient_occlusion

        fb.defer_ao(ambient_occlusion(fb.depth, plan.camera, plan.ao_radius, options.ao_samples, fb.color))
    if plan.catcher is not None:
        from rasterkit.raster.ground import catch_shadows
        from rasterkit.raster.shading import per_pixel

        seen = fb.ids >= plan.catcher if fb.object_ids is None else fb.object_ids == len(fb.object_first) - 1
        catch_shadows(fb, seen, plan.camera, style.lights if per_pixel(style) else None,
                      plan.mesh.face_normals[plan.catcher])
    if (options.normals or options.uv or object_faces is not None or plan.catcher is not None) and not options.ids:
        fb.ids = None
    return fb


def render_bytes(mesh, camera: Camera, mode: str | None = None, *, options: RenderOptions | None = None,
                 points=None, **changes) -> int:
    """Bytes that ``render(mesh, camera, mode, options=options, points=points, **changes)``
    asks :func:`rasterkit.limits.check_memory` for, worked out without drawing
    (``edges="feature"`` is counted as ``"all"``, of which the feature edges are a part, so
    that nothing is worked out here). For a camera with ``distortion``: the render's at the
    same size, without the resampling of :func:`rasterkit.raster.distortion.render_distorted`."""
    options, point_colors = resolve_options(options, mode, changes)
    return plan_frame(mesh, camera, options, points, point_colors, feature_edges=False).need
