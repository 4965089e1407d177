"""Batches: a dataset of models into a folder of images, in parallel and resumably.

:func:`render_many` (``api``), :class:`BatchSummary` (``engine``), :class:`Task` (``task``).
They are imported on first use, so that the command line's light modules of this package
(``report``, ``progress``, ``manifest``) load neither NumPy nor the engine.
"""

from __future__ import annotations

import importlib

__all__ = ["BatchSummary", "Task", "render_many"]

_HOMES = {"render_many": "api", "BatchSummary": "engine", "Task": "task"}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(importlib.import_module(f"{__name__}.{_HOMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
