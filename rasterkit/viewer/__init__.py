"""The interactive viewer: :class:`Viewer` in a notebook, ``rasterkit view`` in the browser.

Both draw with rasterkit on the Python side and show the frames in a page that sends the
mouse's events back: :mod:`.session` (the state: model, view, options; events in, frames out),
:mod:`.orbit` (the camera's moves), :mod:`.loop` (the newest state drawn on a thread, never
a queue), :mod:`.pictures` (maps as pictures, PNG or JPEG bytes), :mod:`.server` (the local
page), :mod:`.start` (a viewer's first view), :mod:`.turntable` (``rasterkit.turntable``: an animation a notebook shows) and :mod:`.widget` (the notebook widget, with
the optional ``anywidget``: imported when :class:`Viewer` is first used).
"""

__all__ = ["Viewer"]


def __getattr__(name: str):
    if name == "Viewer":
        from rasterkit.viewer.widget import Viewer

        return Viewer
    raise AttributeError(f"module 'rasterkit.viewer' has no attribute {name!r}")
