""":func:`turntable`: a model spun once, its frames kept as an
:class:`~rasterkit.image.movie.Animation` that a notebook shows inline."""

from __future__ import annotations

__all__ = ["MAX_FRAMES", "turntable"]

#: The most frames :func:`turntable` keeps in memory (the command line streams any number).
MAX_FRAMES = 3600


def turntable(model, camera=None, frames: int = 36, *, options=None, fps: float = 25.0, turn_lights: bool = False):
    """A turntable of ``model`` (a Mesh, Scene or point cloud) as an
    :class:`~rasterkit.image.movie.Animation`: ``frames`` renders (1 to :data:`MAX_FRAMES`)
    spinning it once about the vertical axis through its bounding sphere's centre, seen by
    ``camera`` (a Camera, a View, or None: framed as ``rasterkit render`` frames it) with
    ``options`` (a RenderOptions; default ``mode="solid"``). In a notebook it shows as an
    animation; ``.save("spin.gif")`` writes it. ``turn_lights``: the lights turn with the
    model (else they stay, and its shadows move over it)."""
    from rasterkit.camera import Camera
    from rasterkit.camera.view import View
    from rasterkit.image.movie import Animation
    from rasterkit.raster.turntable import turntable_frames
    from rasterkit.viewer.start import drawn_of

    if isinstance(frames, bool) or not isinstance(frames, int) or not 1 <= frames <= MAX_FRAMES:
        raise ValueError(f"frames must be a whole number from 1 to {MAX_FRAMES}, got {frames!r}")
    drawn = drawn_of(model, options)
    if isinstance(camera, Camera):
        center = drawn.framed.bounding_sphere()[0]
    else:
        if camera is not None and not isinstance(camera, View):
            raise TypeError(f"camera must be a Camera, a View or None, got {type(camera).__name__}")
        camera, center = (camera or View()).frame(drawn.framed)
    mesh = drawn.mesh if drawn.mesh is not None else drawn.cloud.as_mesh()
    return Animation(list(turntable_frames(mesh, drawn.cloud, camera, center, frames, drawn.options, turn_lights)),
                     fps)
