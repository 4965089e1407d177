"""Batches: a dataset of models into a folder of images, in parallel and resumably.

:func:`render_many` (``api``), :class:`BatchSummary` (``engine``), :class:`Task` (``task``).
They are imported on first use, so that the command line's light modules of this package
(``report``, ``progress``, ``manifest``) load neither NumPy nor the engine.
"""

from __future__ import annotations

from rasterkit.lazy import on_first_use

__all__ = ["BatchSummary", "Task", "render_many"]

__getattr__, __dir__ = on_first_use(__name__, globals(), {
    "render_many": f"{__name__}.api:render_many", "BatchSummary": f"{__name__}.engine:BatchSummary",
    "Task": f"{__name__}.task:Task"})
