"""The viewer's state on the Python side: a model, a view and render options; events in,
frames out. Shared by the notebook widget and the ``rasterkit view`` page, which only carry
events and frames (:mod:`rasterkit.viewer.loop` renders the newest state)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from rasterkit.options import MODES, SHADING, RenderOptions
from rasterkit.viewer.orbit import Orbit
from rasterkit.viewer.pictures import MAPS, encode, picture, render_flags

__all__ = ["EVENTS", "Frame", "ViewerSession", "choices"]

#: The events a viewer page sends (a JSON object each, ``kind`` one of these):
#: ``drag`` (dx, dy pixels; ``pan`` true for shift- or right-drag), ``wheel`` (``steps``,
#: notches: positive away from the target), ``reframe`` (the double-click), ``release`` (the
#: mouse button up: the next frame is drawn at full quality) and ``set`` (``mode``,
#: ``shading``, ``show``: any of them).
EVENTS = ("drag", "wheel", "reframe", "release", "set")
#: The largest move one event may carry, pixels or notches (a bigger one is refused).
MAX_MOVE = 1e5
#: While the user drags, a frame that takes longer than this (seconds: drawn, made into a
#: picture and encoded) is drawn smaller next time: at the largest of :data:`PREVIEW_SCALES`
#: (of each side) that fits. A mouse event waits on average half a frame for the frame being
#: drawn to end, then a whole frame for its own, and the page takes some milliseconds to show
#: it: 20 ms keeps the time from the mouse to the page within 50 ms. A few sizes, not any:
#: the framebuffers' memory is recycled by size (:mod:`rasterkit.runtime.scratch`), so a few
#: sizes keep the memory flat.
PREVIEW_SECONDS = 0.020
PREVIEW_SCALES = (1.0, 0.8, 0.64, 0.5, 0.4, 0.32, 0.25)


def choices() -> dict:
    """What the viewer's bar offers: ``{"mode": MODES, "shading": SHADING, "show": MAPS}``."""
    return {"mode": list(MODES), "shading": list(SHADING), "show": list(MAPS)}


@dataclass(frozen=True)
class Frame:
    """A frame as sent to the page: ``number`` (increasing), the picture's bytes and MIME
    type, its size, whether it is the full-quality one (else a preview while dragging), the
    camera it shows (:meth:`ViewerSession.camera_record`) and the seconds it took to draw."""

    number: int
    data: bytes
    mime: str
    width: int
    height: int
    final: bool
    camera: dict
    seconds: float
    seq: int = 0  #: the number of the newest event it shows (the page's, 0: none)


class ViewerSession:
    """The state of one viewer. ``drawn``: a :class:`rasterkit.batch.render_one.Drawn` (the
    model as a render draws it); ``view``: the :class:`rasterkit.View` it starts from (its
    size is the viewer's)."""

    def __init__(self, drawn, view):
        camera, _ = view.frame(drawn.framed)  # (the model itself: it may bring its own camera)
        self.drawn = drawn._replace(framed=_Framed(drawn.framed))
        self.options: RenderOptions = drawn.options
        radius = self.drawn.framed.bounding_sphere()[1]
        self.orbit = Orbit.around(camera.eye, camera.target, radius)
        # from here on the orbit places the camera (a model's own or an OpenCV camera gives
        # its first pose and field of view only), the world's +Y up
        fov = camera.fov_y if camera.fov_y is not None else view.fov
        self.base = view.replace(eye=None, target=None, up=None, distance=None, camera=None, camera_opencv=None,
                                 fov=fov)
        self.shown = "color"
        self.preview_scale = 1.0
        #: what :meth:`camera_record`'s ``command`` starts with: the model and the other flags
        #: of a render (the command line's ``view`` sets it)
        self.command: list[str] = []

    # --- what the user sees --------------------------------------------------------------

    @property
    def view(self):
        """The :class:`rasterkit.View` of the current frame (``rasterkit render`` flags)."""
        return self.orbit.view(self.base)

    @property
    def camera(self):
        """The :class:`rasterkit.Camera` of the current frame."""
        return self.view.camera_for(self.drawn.framed)

    def camera_record(self) -> dict:
        """The current camera as JSON-ready numbers, and the command-line flags of the view."""
        view = self.view
        return {"eye": list(view.eye), "target": list(view.target), "up": list(view.up), "fov": view.fov,
                "azimuth": self.orbit.azimuth, "elevation": self.orbit.elevation,
                "distance": self.orbit.distance, "flags": self.flags(), "command": self.command + self.flags()}

    def current(self) -> dict:
        """The bar's settings now: ``{"mode", "shading", "show"}``."""
        return {"mode": self.options.mode, "shading": self.options.shading, "show": self.shown}

    def flags(self) -> list[str]:
        """The ``rasterkit render`` flags of the current frame's view (``--size --eye --target
        --up --fov``), mode and shading: after the other flags of a render, they draw it
        exactly (the numbers written as Python writes floats, which read back unchanged)."""
        view = self.view
        width, height = view.size

        def triple(values) -> str:
            return ",".join(repr(float(v)) for v in values)

        flags = ["--size", f"{width}x{height}", "--eye", triple(view.eye), "--target", triple(view.target),
                  "--up", triple(view.up), "--fov", repr(float(view.fov))]
        if view.projection != "perspective":
            flags += ["--projection", view.projection]
        flags += ["--mode", self.options.mode, "--shading", self.options.shading]
        return flags

    # --- events --------------------------------------------------------------------------

    def handle(self, event) -> bool:
        """Apply one event (a mapping, :data:`EVENTS`); whether the picture changes. Raises
        ValueError, in one line, for an event that is not one."""
        if not isinstance(event, dict) or event.get("kind") not in EVENTS:
            raise ValueError(f"not a viewer event: kind must be one of {', '.join(EVENTS)}")
        kind = event["kind"]
        height = self.base.size[1]
        if kind == "drag":
            dx, dy = _number(event, "dx"), _number(event, "dy")
            if event.get("pan"):
                self.orbit = self.orbit.pan(dx, dy, height, self.base.fov)
            else:
                self.orbit = self.orbit.turn(dx, dy, height)
            return True
        if kind == "wheel":
            self.orbit = self.orbit.zoom(_number(event, "steps"))
            return True
        if kind == "reframe":
            self.orbit = self.orbit.reframe()
            return True
        if kind == "release":
            return True
        changes = {key: event[key] for key in ("mode", "shading", "show") if key in event}
        for key, choices in (("mode", MODES), ("shading", SHADING), ("show", MAPS)):
            if key in changes and changes[key] not in choices:
                raise ValueError(f"{key} must be one of {', '.join(choices)}")
        self.shown = changes.pop("show", self.shown)
        if changes:
            self.options = self.options.replace(**changes)
        return True

    # --- frames --------------------------------------------------------------------------

    def render(self, final: bool, number: int = 0) -> Frame:
        """Draw the current state: at full size when ``final`` (PNG, the pixels that
        ``rasterkit render`` with :meth:`flags` writes), else at the preview scale (JPEG, and
        the scale adjusted to the time this frame took, :data:`PREVIEW_SECONDS`)."""
        from rasterkit.raster.render import render

        width, height = self.base.size
        scale = 1.0 if final else self.preview_scale
        size = (max(1, round(width * scale)), max(1, round(height * scale)))
        view = self.view.replace(size=size)
        camera = view.camera_for(self.drawn.framed)
        options = self.options.replace(**render_flags(self.shown))
        if not final:
            options = options.replace(samples=1, aa=False)
        mesh = self.drawn.mesh if self.drawn.mesh is not None else self.drawn.cloud.as_mesh()
        points = {} if self.drawn.cloud is None else self.drawn.cloud.render_arguments()
        begin = time.perf_counter()
        fb = render(mesh, camera, options=options, **points)
        seconds = time.perf_counter() - begin
        data, mime = encode(picture(fb, self.shown), final)
        if not final:
            fit = scale * math.sqrt(PREVIEW_SECONDS / max(time.perf_counter() - begin, 1e-6))
            self.preview_scale = max([k for k in PREVIEW_SCALES if k <= fit], default=PREVIEW_SCALES[-1])
        return Frame(number, data, mime, size[0], size[1], final, self.camera_record(), seconds)


class _Framed:
    """What the view frames, its bounding sphere found once (every frame's camera needs it,
    and a large model's takes tens of milliseconds)."""

    def __init__(self, framed):
        self._framed, self._sphere = framed, framed.bounding_sphere()

    def bounding_sphere(self):
        return self._sphere

    def __getattr__(self, name: str):  # a glTF scene's camera, and the rest
        return getattr(self._framed, name)


def _number(event: dict, key: str) -> float:
    value = event.get(key, 0.0)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or abs(value) > MAX_MOVE:
        raise ValueError(f"{key} must be a finite number of at most {MAX_MOVE:g}")
    return float(value)
