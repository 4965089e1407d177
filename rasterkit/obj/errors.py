"""Errors and warnings of one OBJ file: :class:`ObjError` and the :class:`Report` that collects
them while :func:`rasterkit.load_obj` reads the file.

Every message is one line: the file name (shown with :func:`readable`) and the line number
come first, and text taken from the file is shown with ``repr``, so that no byte of a file or
of its name (a newline, U+2028, an escape sequence) can break a message in two.
"""

from __future__ import annotations

from rasterkit.runtime.files import readable
from rasterkit.limits import LimitError

__all__ = ["ObjError", "ObjLimitError", "Report", "count", "readable"]


class ObjError(ValueError):
    """An OBJ file that cannot be loaded.

    Attributes
    ----------
    path : str
        The file, as given to :func:`rasterkit.load_obj`.
    line : int or None
        1-based line where the problem is, or None when it is not one line's fault.
    reason : str
        What is wrong, without the location.
    """

    __module__ = "rasterkit.obj"  # where the public API has it (rasterkit.ObjError)

    def __init__(self, path: str, line: int | None, reason: str):
        self.path = path
        self.line = line
        self.reason = reason
        where = readable(path) if line is None else f"{readable(path)}:{line}"
        super().__init__(f"{where}: {reason}")

    def __reduce__(self):  # pickled with its three parts (e.g. back from a worker process)
        return type(self), (self.path, self.line, self.reason)


class ObjLimitError(ObjError, LimitError):
    """An OBJ file beyond one of the limits of :mod:`rasterkit.limits` (its size, or the
    memory loading it would take): both an :class:`ObjError` and a
    :class:`~rasterkit.limits.LimitError`."""

    __module__ = "rasterkit.obj"


class Report:
    """Errors (line, message) and warnings met while loading one file."""

    def __init__(self, name: str):
        self.name = name
        self.errors: list[tuple[int, str]] = []
        self.warnings: list[str] = []

    def error(self, line: int, message: str):
        self.errors.append((int(line), message))

    def warn(self, line: int | None, message: str, name: str | None = None):
        """Note a warning about line of this file (or of the file name, e.g. an .mtl)."""
        name = readable(name or self.name)
        self.warnings.append(f"{name}: {message}" if line is None else
                             f"{name}:{int(line)}: {message}")

    def raise_first_error(self):
        if self.errors:
            line, message = min(self.errors, key=lambda e: e[0])
            raise ObjError(self.name, line, message)


def count(n, noun: str, plural: str | None = None) -> str:
    """'1 face', '2 faces'."""
    return f"{int(n)} {noun if n == 1 else plural or noun + 's'}"

