"""Errors of one STL file: :class:`StlError`, :class:`StlLimitError`, and the two checks that
raise them before anything large is made: reading the file (through
:func:`rasterkit.runtime.files.read_file`) and the memory estimate (through
:func:`rasterkit.limits.check_memory`).

Every message is one line that starts with the file's name and where: ``name:LINE: reason`` in
an ASCII file, ``name: byte OFFSET: reason`` or ``name: facet K (byte OFFSET): reason`` in a
binary one, ``name: reason`` when no place is to blame. Text from the file is shown with
``repr`` (:func:`rasterkit.runtime.tokens.shown`), so nothing in a file or its name can break a
message in two.
"""

from __future__ import annotations

from rasterkit.limits import LimitError, check_memory
from rasterkit.runtime import files as _files
from rasterkit.runtime.files import readable

__all__ = ["StlError", "StlLimitError", "check", "read_bytes"]


class StlError(ValueError):
    """An STL file that cannot be read.

    Attributes
    ----------
    path : str
        The file, as given to :func:`rasterkit.stl.read_stl`.
    line : int or None
        1-based line of an ASCII file where the problem is.
    reason : str
        What is wrong, without the place.
    location : str or None
        The place in a binary file (``"byte 80"``, ``"facet 3 (byte 234)"``), when ``line``
        is None.
    """

    __module__ = "rasterkit.stl"

    def __init__(self, path: str, line: int | None, reason: str, location: str | None = None):
        self.path = path
        self.line = line
        self.reason = reason
        self.location = location
        if line is not None:
            where = f"{readable(path)}:{line}"
        elif location:
            where = f"{readable(path)}: {location}"
        else:
            where = readable(path)
        super().__init__(f"{where}: {reason}")

    def __reduce__(self):  # pickled with its parts (e.g. back from a worker process)
        return type(self), (self.path, self.line, self.reason, self.location)


class StlLimitError(StlError, LimitError):
    """An STL file beyond one of the limits of :mod:`rasterkit.limits` (its size, or the
    memory reading it would take): both an :class:`StlError` and a
    :class:`~rasterkit.limits.LimitError`."""

    __module__ = "rasterkit.stl"


def read_bytes(name: str) -> bytes:
    """The bytes of the regular file ``name`` (:func:`rasterkit.runtime.files.read_file`), its
    errors as :class:`StlError`."""
    try:
        return _files.read_file(name)
    except _files.FileLimitError as e:
        raise StlLimitError(e.path, None, e.reason) from None
    except _files.FileError as e:
        raise StlError(e.path, None, e.reason) from None


def check(name: str, nbytes: float, what: str) -> None:
    """:class:`StlLimitError` when ``nbytes``, estimated before they are allocated, are over
    :func:`rasterkit.limits.memory_limit`."""
    try:
        check_memory(nbytes, what)
    except LimitError as e:
        raise StlLimitError(name, None, str(e)) from None
