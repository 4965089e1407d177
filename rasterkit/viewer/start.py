"""Where a viewer of the Python API starts: its model as drawn, and its first view."""

from __future__ import annotations

__all__ = ["drawn_of", "view_of"]


def drawn_of(model, options=None):
    """The :class:`rasterkit.batch.render_one.Drawn` of a Mesh, Scene or PointCloud drawn
    with ``options`` (None: ``RenderOptions(mode="solid")``; a Scene's lights where the
    options name none)."""
    from rasterkit.batch.render_one import drawn_model
    from rasterkit.options import RenderOptions

    options = RenderOptions(mode="solid") if options is None else options
    if not isinstance(options, RenderOptions):
        raise TypeError(f"options must be a RenderOptions, got {type(options).__name__}")
    return drawn_model(model, options)


def view_of(camera, size):
    """The :class:`rasterkit.View` a viewer starts from: ``camera`` a View (its size
    replaced by ``size``), a Camera (its eye, target, up and field of view), or None (the
    model framed as ``rasterkit render`` frames it)."""
    from rasterkit.camera import Camera
    from rasterkit.camera.view import View

    size = tuple(size)
    if camera is None:
        return View(size=size)
    if isinstance(camera, View):
        return camera.replace(size=size)
    if isinstance(camera, Camera):
        return View(size=size, fov=camera.fov_y if camera.fov_y is not None else 45.0,
                    projection="perspective" if camera.kind == "perspective" else "orthographic",
                    eye=tuple(camera.eye), target=tuple(camera.target), up=tuple(camera.up))
    raise TypeError(f"camera must be a Camera, a View or None, got {type(camera).__name__}")
