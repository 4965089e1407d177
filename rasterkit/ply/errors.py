"""Errors and warnings of one PLY file: :class:`PlyError` and the :class:`Notes` that collect
the warnings while :func:`rasterkit.ply.read_ply` reads the file.

Every message is one line that starts with the file's name (shown with :func:`readable`) and
says where: ``NAME:LINE: reason`` for the header and the rows of an ASCII body (lines count
from 1), ``NAME: element 'face' row K (byte OFFSET): reason`` for a binary body (rows count
from 0, as the arrays of the result do), ``NAME: reason`` when no place is to blame. Text
taken from the file is shown with ``repr``, so no byte of a file or of its name can break a
message in two.
"""

from __future__ import annotations

from rasterkit.limits import LimitError, check_memory
from rasterkit.runtime.files import readable

__all__ = ["Notes", "PlyError", "PlyLimitError", "check_limit", "count", "readable", "row_place"]


class PlyError(ValueError):
    """A PLY file that cannot be read.

    Attributes
    ----------
    path : str
        The file, as given to :func:`rasterkit.ply.read_ply`.
    location : int, str or None
        Where: a 1-based line (the header, or a row of an ASCII body), a place in a binary
        body such as ``"element 'face' row 12 (byte 4410)"``, or None when it is not one
        place's fault.
    reason : str
        What is wrong, without the location.
    """

    __module__ = "rasterkit.ply"

    def __init__(self, path: str, location: int | str | None, reason: str):
        self.path = path
        self.location = location
        self.reason = reason
        name = readable(path)
        if location is None:
            where = name
        elif isinstance(location, int):
            where = f"{name}:{location}"
        else:
            where = f"{name}: {location}"
        super().__init__(f"{where}: {reason}")

    def __reduce__(self):  # pickled with its three parts (e.g. back from a worker process)
        return type(self), (self.path, self.location, self.reason)


class PlyLimitError(PlyError, LimitError):
    """A PLY file beyond one of the limits of :mod:`rasterkit.limits` (its size, or the
    memory reading it would take): both a :class:`PlyError` and a
    :class:`~rasterkit.limits.LimitError`."""

    __module__ = "rasterkit.ply"


class Notes:
    """The warnings met while reading one file, each one line naming it."""

    def __init__(self, name: str):
        self.name = name
        self.warnings: list[str] = []

    def warn(self, location: int | str | None, message: str) -> None:
        name = readable(self.name)
        if location is None:
            self.warnings.append(f"{name}: {message}")
        elif isinstance(location, int):
            self.warnings.append(f"{name}:{location}: {message}")
        else:
            self.warnings.append(f"{name}: {location}: {message}")


def row_place(element: str, row: int, offset: int | None = None) -> str:
    """``element 'face' row 12`` (and `` (byte 4410)`` with an offset)."""
    place = f"element {element!r} row {int(row)}"
    return place if offset is None else f"{place} (byte {int(offset)})"


def count(n, noun: str, plural: str | None = None) -> str:
    """'1 face', '2 faces'."""
    return f"{int(n)} {noun if n == 1 else plural or noun + 's'}"


def check_limit(name: str, nbytes: float, what: str) -> None:
    """:func:`rasterkit.limits.check_memory`, its error a :class:`PlyLimitError` naming the
    file ``name``."""
    try:
        check_memory(nbytes, what)
    except LimitError as e:
        raise PlyLimitError(name, None, str(e)) from None
