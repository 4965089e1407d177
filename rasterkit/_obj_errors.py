"""Errors and warnings of one OBJ file: :class:`ObjError` and the :class:`Report` that collects
them while :func:`rasterkit.load_obj` reads the file."""

from __future__ import annotations

__all__ = ["ObjError", "Report", "count"]


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

    __module__ = "rasterkit.obj"  # where the public API has it, as before the loader's split

    def __init__(self, path: str, line: int | None, reason: str):
        self.path = path
        self.line = line
        self.reason = reason
        where = path if line is None else f"{path}:{line}"
        super().__init__(f"{where}: {reason}")


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
        name = name or self.name
        self.warnings.append(f"{name}: {message}" if line is None else
                             f"{name}:{int(line)}: {message}")

    def raise_first_error(self):
        if self.errors:
            line, message = min(self.errors, key=lambda e: e[0])
            raise ObjError(self.name, line, message)


def count(n, noun: str, plural: str | None = None) -> str:
    """'1 face', '2 faces'."""
    return f"{int(n)} {noun if n == 1 else plural or noun + 's'}"
