"""Errors of one glTF file: :class:`GltfError` and :class:`GltfLimitError`.

Every message is one line: the file name (shown with :func:`readable`), then where in the
file the problem is (a JSON path such as ``meshes[0].primitives[1].attributes.POSITION``,
``byte 20`` for the GLB container, ``line 3 column 7`` for JSON text), then the reason. Text
taken from the file (names, URIs, keys) is shown with ``repr``, so that no byte of a file can
break a message in two.
"""

from __future__ import annotations

from rasterkit.limits import LimitError
from rasterkit.runtime.files import readable

__all__ = ["GltfError", "GltfLimitError", "readable"]


class GltfError(ValueError):
    """A glTF or GLB file that cannot be read.

    Attributes
    ----------
    path : str
        The file, as given to :func:`rasterkit.gltf.read_gltf`.
    where : str or None
        Where in the file: a JSON path (``accessors[3].byteOffset``), ``byte N`` in a GLB
        container, ``line L column C`` of JSON text; None when no one place is to blame.
    reason : str
        What is wrong, without the location.
    """

    __module__ = "rasterkit.gltf"

    def __init__(self, path: str, where: str | None, reason: str):
        self.path = path
        self.where = where
        self.reason = reason
        place = readable(path) if where is None else f"{readable(path)}: {where}"
        super().__init__(f"{place}: {reason}")

    def __reduce__(self):  # pickled with its three parts (e.g. back from a worker process)
        return type(self), (self.path, self.where, self.reason)


class GltfLimitError(GltfError, LimitError):
    """A glTF file (or a file it names) beyond one of the limits of :mod:`rasterkit.limits`:
    the file size, or the memory reading it would take. Both a :class:`GltfError` and a
    :class:`~rasterkit.limits.LimitError`."""

    __module__ = "rasterkit.gltf"
