"""Image files: PNG, and animated GIF and APNG streamed frame by frame, written atomically.

``files`` holds the writers (:func:`save_image`, :func:`save_animation`, :func:`save_npy`,
:func:`encode_png`, :func:`to_pil`), ``png`` and ``animation`` the encoders, ``atomic`` the
atomic writes every writer goes through. The names are imported on first use, so that the
command line's output checks (``atomic``) load no NumPy.
"""

from __future__ import annotations

import importlib

__all__ = ["to_pil", "encode_png", "save_image", "save_animation", "save_npy", "atomic_write", "PNG_COMPRESS_LEVEL"]

_HOMES = {**dict.fromkeys(["to_pil", "encode_png", "save_image", "save_animation", "save_npy", "PNG_COMPRESS_LEVEL"],
                          "files"), "atomic_write": "atomic"}


def __getattr__(name: str):
    if name in _HOMES:
        return getattr(importlib.import_module(f"{__name__}.{_HOMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
