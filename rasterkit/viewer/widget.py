""":class:`Viewer`: the interactive viewer as a Jupyter widget (``pip install
'rasterkit[notebook]'``: it is built on ``anywidget``, which carries the page's code to any
notebook front end and the messages back).

The frames are drawn here, on the kernel's side, by :class:`rasterkit.viewer.loop.FrameLoop`,
and sent as custom messages with the picture's bytes in a binary buffer (no base64); the
page sends the mouse's events back the same way (:data:`rasterkit.viewer.session.EVENTS`).
"""

from __future__ import annotations

from rasterkit.viewer.server import static_file

try:
    import anywidget
    import traitlets
except ImportError as error:  # the optional extra is missing: say how to get it
    raise ImportError("rasterkit.Viewer needs anywidget: pip install 'rasterkit[notebook]'") from error

__all__ = ["Viewer"]


def _module() -> str:
    """The widget's ES module: the shared controls, then the widget's own part."""
    return static_file("controls.js").decode() + "\n" + static_file("widget.js").decode()


class Viewer(anywidget.AnyWidget):
    """Orbit a model in a notebook, seeing exactly the pixels :func:`rasterkit.render` draws.

    Drag to orbit around the target, wheel to zoom, shift-drag or right-drag to pan,
    double-click to re-frame; the bar above the picture switches the mode, the shading and
    what is shown (the colour or the depth, normal or id map). While the mouse moves, frames
    may be drawn smaller to keep up; when it stops, at full quality.

    Parameters
    ----------
    model : Mesh, Scene or PointCloud
    camera : Camera or View, optional
        Where the view starts (None: framed as ``rasterkit render`` frames it).
    options : RenderOptions, optional
        How frames are drawn (default: ``RenderOptions(mode="solid")``).
    size : (int, int)
        The picture's width and height in pixels.

    :attr:`camera` is the current :class:`rasterkit.Camera`, :attr:`view` the
    :class:`rasterkit.View` and :attr:`options` the :class:`rasterkit.RenderOptions`:
    ``rasterkit.render(model, viewer.camera, options=viewer.options)`` draws what the user
    sees, and :attr:`flags` are the ``rasterkit render`` flags of the view.
    """

    _esm = _module()
    _css = static_file("widget.css").decode()
    size = traitlets.List().tag(sync=True)
    choices = traitlets.Dict().tag(sync=True)
    current = traitlets.Dict().tag(sync=True)

    def __init__(self, model, camera=None, *, options=None, size=(960, 720)):
        from rasterkit.viewer.loop import FrameLoop
        from rasterkit.viewer.session import ViewerSession, choices
        from rasterkit.viewer.start import drawn_of, view_of

        session = ViewerSession(drawn_of(model, options), view_of(camera, size))
        super().__init__(size=list(session.base.size), choices=choices(), current=session.current())
        self._session = session
        self._loop = FrameLoop(session, publish=self._publish)
        self.on_msg(self._message)

    @property
    def camera(self):
        """The :class:`rasterkit.Camera` of the frame shown."""
        return self._session.camera

    @property
    def view(self):
        """The :class:`rasterkit.View` of the frame shown (the command line's view flags)."""
        return self._session.view

    @property
    def options(self):
        """The :class:`rasterkit.RenderOptions` of the frame shown (the bar's mode and shading)."""
        return self._session.options

    @property
    def flags(self) -> list[str]:
        """The ``rasterkit render`` flags of the frame shown."""
        return self._session.flags()

    def post(self, event: dict) -> None:
        """Apply one viewer event as the page would send it (ValueError for a bad one)."""
        self._loop.post(event)

    def wait_frame(self, after: int = 0, timeout: float = 60.0):
        """The newest :class:`~rasterkit.viewer.session.Frame` once its number is above
        ``after`` (None after ``timeout`` seconds)."""
        return self._loop.wait_frame(after, timeout)

    def close(self) -> None:
        """Stop drawing and close the widget."""
        loop = getattr(self, "_loop", None)  # (None: the constructor failed)
        if loop is not None:
            loop.close()
        super().close()

    def _message(self, _, content, buffers) -> None:
        if isinstance(content, dict) and content.get("kind") == "hello":
            if self._loop.frame is not None:
                self._publish(self._loop.frame)
            return
        try:
            self._loop.post(content)
        except (ValueError, TypeError, KeyError) as error:
            self.send({"kind": "error", "error": str(error).splitlines()[0]})
        else:
            self.current = self._session.current()

    def _publish(self, frame) -> None:
        self.send({"kind": "frame", "number": frame.number, "final": frame.final, "seq": frame.seq,
                   "mime": frame.mime, "camera": frame.camera, "error": self._loop.error or ""}, [frame.data])
