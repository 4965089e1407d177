""":class:`Animation`: frames kept in memory, saved as GIF or APNG, shown inline in a notebook."""

from __future__ import annotations

import base64
import io
import math
import numbers

import numpy as np

__all__ = ["Animation"]


class Animation:
    """Frames (uint8 (H, W, 3|4) arrays of one shape) shown ``fps`` times a second, looping.

    ``len``, iteration and indexing give the frames; :meth:`save` writes a ``.gif``, ``.png``
    or ``.apng`` file (:func:`rasterkit.image.files.save_animation`); a notebook shows it as
    an animated PNG (:meth:`_repr_html_`: the file inline, base64, in an ``<img>``)."""

    def __init__(self, frames, fps: float = 25.0):
        from rasterkit.image.files import MIN_FPS

        self.frames = [np.asarray(frame) for frame in frames]
        if not self.frames:
            raise ValueError("an animation needs at least one frame")
        if isinstance(fps, bool) or not isinstance(fps, numbers.Real) or not math.isfinite(fps) or fps < MIN_FPS:
            raise ValueError(f"fps must be a number of at least {MIN_FPS:.3g}, got {fps!r}")
        first = self.frames[0]
        for k, frame in enumerate(self.frames):
            if frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] not in (3, 4) or frame.shape != first.shape:
                raise ValueError(f"frame {k} must be uint8 (H, W, 3|4) of the first frame's shape {first.shape}, "
                                 f"got {frame.dtype} {frame.shape}")
        self.fps = float(fps)

    def __len__(self) -> int:
        return len(self.frames)

    def __iter__(self):
        return iter(self.frames)

    def __getitem__(self, k):
        return self.frames[k]

    def __repr__(self) -> str:
        height, width = self.frames[0].shape[:2]
        return f"Animation({len(self)} frames, {width}x{height}, {self.fps:g} fps)"

    def save(self, path) -> None:
        """Write the animation as a looping GIF (``.gif``) or APNG (``.png``, ``.apng``), atomically."""
        from rasterkit.image.files import save_animation

        save_animation(self.frames, path, self.fps)

    def apng(self) -> bytes:
        """The animation as the bytes of an APNG file."""
        from rasterkit.image.animation import write_apng

        out = io.BytesIO()
        write_apng(iter(self.frames), out, int(round(1000.0 / self.fps)))
        return out.getvalue()

    def _repr_html_(self) -> str:
        height, width = self.frames[0].shape[:2]
        data = base64.b64encode(self.apng()).decode("ascii")
        return f'<img src="data:image/png;base64,{data}" width="{width}" height="{height}" alt="{self!r}">'
