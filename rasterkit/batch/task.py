""":class:`Task`: what ``rasterkit render`` does with each model, as one record.

The command line makes one from its arguments, :func:`rasterkit.render_many` from its
keywords; every engine (the in-process loop, the local workers, Dask's workers) and the
warm-up get it whole. Pure Python.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rasterkit import values
from rasterkit.camera.view import View
from rasterkit.options import HIDDEN, RenderOptions

__all__ = ["Task"]


@dataclass(frozen=True)
class Task:
    """One model's render: how it is drawn (``options``) and seen (``view``), and the files
    beside the image.

    Fields
    ------
    options : RenderOptions
        How each frame is drawn (its maps are those of ``depth``, ``normals`` and ``ids``:
        :meth:`frame_options`).
    view : View
        How the camera is chosen for the model.
    turntable : int or None
        Frames of a turntable around the model (an animated GIF or APNG), or a still image.
    turn_lights : bool
        In a turntable, the lights (world-space ones: not headlights) turn with the model, so
        that it keeps its lighting and shadows; False (the default): they stay where they
        are, and the shadows move over the turning model (its shadow maps drawn anew for
        each frame).
    hidden : {None, "dashed"}
        An SVG drawing's hidden lines.
    depth, normals, ids : str or None
        Files for the depth, normal and id maps of a single still render (``.npy`` or ``.png``).
    """

    options: RenderOptions = field(default_factory=RenderOptions)
    view: View = field(default_factory=View)
    turntable: int | None = None
    turn_lights: bool = False
    hidden: str | None = None
    depth: str | None = None
    normals: str | None = None
    ids: str | None = None

    def __post_init__(self):
        if not isinstance(self.options, RenderOptions):
            raise TypeError(f"options must be a rasterkit.RenderOptions, got {type(self.options).__name__}")
        if not isinstance(self.view, View):
            raise TypeError(f"view must be a rasterkit.View, got {type(self.view).__name__}")
        object.__setattr__(self, "turntable", values.optional(values.whole, "turntable", self.turntable, 1))
        values.flag("turn_lights", self.turn_lights)
        values.choice("hidden", self.hidden, HIDDEN)

    def frame_options(self) -> RenderOptions:
        """:attr:`options` with the maps that the files ``depth``, ``normals`` and ``ids`` need."""
        return self.options.replace(ids=bool(self.ids), normals=bool(self.normals), camera_depth=bool(self.depth))

    def replace(self, **changes) -> Task:
        return dataclasses.replace(self, **changes)
