"""Image files: PNG, and animated GIF and APNG streamed frame by frame, written atomically.

``files`` holds the writers (:func:`save_image`, :func:`save_animation`, :func:`save_npy`,
:func:`encode_png`, :func:`to_pil`), ``png`` and ``animation`` the encoders, ``atomic`` the
atomic writes every writer goes through. The names are imported on first use, so that the
command line's output checks (``atomic``) load no NumPy.
"""

from __future__ import annotations

from rasterkit.lazy import on_first_use

__all__ = ["to_pil", "encode_png", "save_image", "save_animation", "save_npy", "atomic_write", "PNG_COMPRESS_LEVEL"]

__getattr__, __dir__ = on_first_use(__name__, globals(), {
    **{name: f"{__name__}.files:{name}" for name in __all__ if name != "atomic_write"},
    "atomic_write": f"{__name__}.atomic:atomic_write"})
