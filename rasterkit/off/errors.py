"""Errors of one OFF file: :class:`OffError`, :class:`OffLimitError`, and the two checks that
raise them before anything large is made: reading the file (through
:func:`rasterkit.runtime.files.read_file`) and the memory estimate (through
:func:`rasterkit.limits.check_memory`).

Every message is one line that starts with the file's name and where: ``name:LINE: reason``,
or ``name: reason`` when no line is to blame. Text from the file is shown with
``repr`` (:func:`rasterkit.runtime.tokens.shown`), so nothing in a file or its name can break a
message in two.
"""

from __future__ import annotations

from rasterkit.limits import LimitError, check_memory
from rasterkit.runtime import files as _files
from rasterkit.runtime.files import readable

__all__ = ["OffError", "OffLimitError", "check", "read_bytes"]


class OffError(ValueError):
    """An OFF file that cannot be read.

    Attributes
    ----------
    path : str
        The file, as given to :func:`rasterkit.off.read_off`.
    line : int or None
        1-based line where the problem is, or None when it is not one line's fault.
    reason : str
        What is wrong, without the place.
    """

    __module__ = "rasterkit.off"

    def __init__(self, path: str, line: int | None, reason: str):
        self.path = path
        self.line = line
        self.reason = reason
        where = readable(path) if line is None else f"{readable(path)}:{line}"
        super().__init__(f"{where}: {reason}")

    def __reduce__(self):  # pickled with its parts (e.g. back from a worker process)
        return type(self), (self.path, self.line, self.reason)


class OffLimitError(OffError, LimitError):
    """An OFF file beyond one of the limits of :mod:`rasterkit.limits` (its size, or the
    memory reading it would take): both an :class:`OffError` and a
    :class:`~rasterkit.limits.LimitError`."""

    __module__ = "rasterkit.off"


def read_bytes(name: str) -> bytes:
    """The bytes of the regular file ``name`` (:func:`rasterkit.runtime.files.read_file`), its
    errors as :class:`OffError`."""
    try:
        return _files.read_file(name)
    except _files.FileLimitError as e:
        raise OffLimitError(e.path, None, e.reason) from None
    except _files.FileError as e:
        raise OffError(e.path, None, e.reason) from None


def check(name: str, nbytes: float, what: str) -> None:
    """:class:`OffLimitError` when ``nbytes``, estimated before they are allocated, are over
    :func:`rasterkit.limits.memory_limit`."""
    try:
        check_memory(nbytes, what)
    except LimitError as e:
        raise OffLimitError(name, None, str(e)) from None
