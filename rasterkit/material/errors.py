"""Errors of reading a texture: :class:`TextureError`, one line that names the file.

Like :class:`rasterkit.runtime.files.FileError`: ``path`` (as given) and ``reason`` (what is
wrong, without the name), the text ``NAME: reason`` with the name shown by
:func:`~rasterkit.runtime.files.readable`, so that no byte of a file name breaks a message in
two. Over a limit of :mod:`rasterkit.limits` (the file size, or the memory that decoding would
take), :class:`TextureLimitError`, also a :class:`~rasterkit.limits.LimitError`.
"""

from __future__ import annotations

from rasterkit.limits import LimitError
from rasterkit.runtime.files import FileError

__all__ = ["TextureError", "TextureLimitError"]


class TextureError(FileError):
    """An image file that cannot be read as a texture (a :class:`FileError`: ``path``,
    ``reason``, the text ``NAME: reason``)."""

    __module__ = "rasterkit.material"


class TextureLimitError(TextureError, LimitError):
    """An image file over the file size limit, or whose decoding would need more memory than
    :func:`rasterkit.limits.memory_limit`: refused before it is decoded."""

    __module__ = "rasterkit.material"
