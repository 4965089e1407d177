"""Drawing a viewer's newest state on a thread of its own, never a queue of old ones.

Events change the state at once (:meth:`FrameLoop.post`); the drawing thread draws whatever
the state is when it is free, so when events come faster than frames, the states between are
never drawn and nothing piles up. While the user drags or turns the wheel the frames are
previews (:meth:`rasterkit.viewer.session.ViewerSession.render`); when the button is
released, or no event has come for :data:`REFINE_AFTER` seconds, the same state is drawn
once more at full quality.
"""

from __future__ import annotations

import copy
import dataclasses
import threading
import time

__all__ = ["REFINE_AFTER", "FrameLoop"]

#: Seconds without an event after which a moving view is drawn at full quality.
REFINE_AFTER = 0.2
_MOVES = ("drag", "wheel")


class FrameLoop:
    """Draws ``session``'s newest state; ``publish(frame)`` (optional) is called with each
    frame on the drawing thread, and :meth:`wait_frame` returns the newest one."""

    def __init__(self, session, publish=None):
        self.session, self._publish = session, publish
        self._changed = threading.Condition()
        self._version = 0  # the state's, one more for every event that changes the picture
        self._drawn = (-1, False)  # (version, final) of the newest frame
        self._moving = False
        self._last_event = time.monotonic()
        self._seq = 0  # the page's number of the newest event applied
        self._frame = None
        self._closed = False
        self.error: str | None = None  # the last drawing error, in one line
        self._thread = threading.Thread(target=self._run, name="rasterkit-viewer", daemon=True)
        self._thread.start()

    def post(self, event) -> None:
        """Apply ``event`` to the state (ValueError for one that is not an event)."""
        with self._changed:
            self.session.handle(event)
            kind = event["kind"]
            seq = event.get("seq")
            if isinstance(seq, int) and not isinstance(seq, bool) and 0 < seq < 2**53:
                self._seq = seq
            self._moving = kind in _MOVES
            self._last_event = time.monotonic()
            if kind != "release":
                self._version += 1
            self._changed.notify_all()

    def wait_frame(self, after: int, timeout: float):
        """The newest frame once its number is above ``after``, or None after ``timeout``
        seconds."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while self._frame is None or self._frame.number <= after:
                left = deadline - time.monotonic()
                if left <= 0 or self._closed:
                    return None
                self._changed.wait(left)
            return self._frame

    @property
    def frame(self):
        """The newest frame (None before the first)."""
        return self._frame

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` was called (no frame comes any more)."""
        return self._closed

    def close(self) -> None:
        with self._changed:
            self._closed = True
            self._changed.notify_all()
        self._thread.join(timeout=5)

    def _next(self):
        """``(state, version, final, seq)`` of the next frame to draw, once there is one (None:
        closed). Called holding the lock."""
        while not self._closed:
            moving = self._moving and time.monotonic() - self._last_event < REFINE_AFTER
            version, (drawn, drawn_final) = self._version, self._drawn
            if version != drawn or not drawn_final and not moving:
                return copy.copy(self.session), version, not moving, self._seq
            self._changed.wait(REFINE_AFTER if self._moving else None)
        return None

    def _run(self) -> None:
        number = 0
        while True:
            with self._changed:
                step = self._next()
            if step is None:
                return
            state, version, final, seq = step
            number += 1
            try:
                frame = dataclasses.replace(state.render(final, number), seq=seq)
            except Exception as error:  # shown on the page; the loop goes on with the next state
                self.error = f"{type(error).__name__}: {error}".splitlines()[0]
                with self._changed:
                    self._drawn = (version, True)
                continue
            with self._changed:
                self.session.preview_scale = state.preview_scale
                self._drawn = (version, final)
                self._frame = frame
                self.error = None
                self._changed.notify_all()
            if self._publish is not None:
                self._publish(frame)
