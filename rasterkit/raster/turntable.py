"""Turntables: a model spun about the vertical axis through its centre, one frame per step,
rendered one at a time as they are asked for (the command line streams them into a GIF or
APNG; :func:`rasterkit.viewer.turntable.turntable` keeps them for a notebook)."""

from __future__ import annotations

import math

__all__ = ["turntable_frames"]


def turntable_frames(mesh, cloud, camera, center, frames: int, options, turn_lights: bool = False):
    """The frames of a turntable, rendered one at a time as they are asked for (a point
    ``cloud``'s points spun with the mesh; ``turn_lights``: the lights too)."""
    from rasterkit.raster.lights import moved
    from rasterkit.raster.render import render
    from rasterkit.scene import Scene
    from rasterkit.transform import apply_points, rotate_axis

    lights = options.lights
    for k in range(frames):
        spin = rotate_axis(2 * math.pi * k / frames, (0, 1, 0), center)
        if turn_lights and lights:
            options = options.replace(lights=tuple(moved(light, spin) for light in lights))
        if cloud is None:
            yield render(Scene(camera).add(mesh, spin), options=options).color
        else:
            points = cloud.render_arguments()
            points["points"] = apply_points(spin, points["points"])
            spun = mesh if not len(mesh.faces) and not len(mesh.lines) else Scene(camera).add(mesh, spin)
            yield render(spun, camera, options=options, **points).color
