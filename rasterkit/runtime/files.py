"""Reading an input file: every file rasterkit reads (a model, a material library, a camera
file) is read by :func:`read_file`, and only so.

The rules:

- Only regular files are read. A directory, a FIFO, a socket or a device (``/dev/zero``,
  ``/dev/stdin``...) is refused with one line, e.g. ``x.obj: not a regular file (a FIFO)``:
  a device may never end and a FIFO may never be written to. The path is checked with
  ``stat`` (which opens nothing), then opened without blocking (``O_NONBLOCK``: opening a FIFO
  with no writer would wait forever) and checked again on the open descriptor (``fstat``), so
  that what is read is what was checked.
- A file larger than :func:`rasterkit.limits.max_file_size` (default 2 GiB;
  ``RASTERKIT_MAX_FILE_SIZE``, the command line's ``--max-file-size``) is refused before it is
  read, and no more than the limit and one byte is ever read: a file that grows past the limit
  while it is read is refused too.

Errors are :class:`FileError` (a ``ValueError``), one line that starts with the file's name
(shown with :func:`readable`); over the limit, :class:`FileLimitError`, also a
:class:`~rasterkit.limits.LimitError`.

Pure standard library (with :mod:`rasterkit.limits`).
"""

from __future__ import annotations

import os
import stat

from rasterkit.limits import LimitError, format_bytes, max_file_size

__all__ = ["FileError", "FileLimitError", "read_file", "read_head", "readable"]

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))

_FLAGS = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)

#: Largest single read: Linux returns at most 0x7ffff000 bytes from one read() call anyway.
_CHUNK = 1 << 30
#: Smallest read once fstat's size has been read (a file may grow while it is read).
_SMALL_READ = 1 << 16


def readable(text: str) -> str:
    """text as it is when every character is printable, else its ``repr`` (quoted, with
    escapes): a name or word from a file, fit for a one-line message."""
    return text if text.isprintable() else repr(text)


class FileError(ValueError):
    """A file that cannot be read: ``path`` (as given) and ``reason`` (what is wrong, without
    the name); its text is ``NAME: reason``."""

    def __init__(self, path: str, reason: str):
        self.path = path
        self.reason = reason
        super().__init__(f"{readable(path)}: {reason}")

    def __reduce__(self):  # pickled with its parts (e.g. back from a worker process)
        return type(self), (self.path, self.reason)


class FileLimitError(FileError, LimitError):
    """A file larger than :func:`rasterkit.limits.max_file_size`."""


def _kind(mode: int) -> str:
    for test, words in _KINDS:
        if test(mode):
            return words
    return "not a file"


def _not_regular(name: str, mode: int) -> FileError:
    return FileError(name, f"not a regular file ({_kind(mode)})")


def _too_large(name: str, what: str, limit: int) -> FileLimitError:
    return FileLimitError(name, f"{what} the file size limit of {format_bytes(limit)} "
                                "(--max-file-size, RASTERKIT_MAX_FILE_SIZE)")


def read_file(name: str | os.PathLike) -> bytes:
    """The bytes of the regular file ``name``, at most :func:`max_file_size` of them.

    Raises
    ------
    FileError
        One line naming the file: it cannot be opened (``cannot read: No such file or
        directory``), it is not a regular file, or (a :class:`FileLimitError`) it is larger
        than the limit.
    """
    name = os.fsdecode(name) if isinstance(name, (bytes, os.PathLike)) else name
    limit = max_file_size()
    fd = _open_regular(name)
    try:
        return _read_regular(fd, name, limit)
    finally:
        os.close(fd)


def read_head(name: str | os.PathLike, n: int) -> tuple[bytes, int]:
    """``(first bytes, size)`` of the regular file ``name``: at most ``n`` bytes, read with the
    same checks as :func:`read_file` (no size limit: only ``n`` bytes are read), for telling a
    file's format before its reader reads it whole.

    Raises
    ------
    FileError
        As :func:`read_file`: the file cannot be opened or is not a regular file.
    """
    name = os.fsdecode(name) if isinstance(name, (bytes, os.PathLike)) else name
    fd = _open_regular(name)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise _not_regular(name, info.st_mode)
        return os.read(fd, n), info.st_size
    except OSError as e:
        raise FileError(name, f"cannot read: {e.strerror or e}") from None
    finally:
        os.close(fd)


def _open_regular(name: str) -> int:
    """A descriptor of ``name`` opened for reading once ``stat`` says it is a regular file
    (checked before opening: opening a FIFO or a device may block or never end)."""
    try:
        info = os.stat(name)
    except (OSError, ValueError) as e:  # ValueError: a NUL byte in the name
        raise FileError(name, f"cannot read: {getattr(e, 'strerror', None) or e}") from None
    if not stat.S_ISREG(info.st_mode):
        raise _not_regular(name, info.st_mode)
    try:
        return os.open(name, _FLAGS)
    except OSError as e:
        raise FileError(name, f"cannot read: {e.strerror or e}") from None


def _read_regular(fd: int, name: str, limit: int) -> bytes:
    """The bytes of the open file fd, once fstat says it is a regular file within limit."""
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):
        raise _not_regular(name, info.st_mode)
    if info.st_size > limit:
        raise _too_large(name, f"{format_bytes(info.st_size)}, more than", limit)
    chunks = []
    size = 0
    try:
        while size <= limit:
            # os.read allocates what it is asked for: ask for what fstat says is left (and a
            # byte more, to see the end), not a GiB for every file
            left = max(info.st_size + 1 - size, _SMALL_READ)
            chunk = os.read(fd, min(limit + 1 - size, _CHUNK, left))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise FileError(name, f"cannot read: {e.strerror or e}") from None
    if size > limit:
        raise _too_large(name, "grew while it was read to more than", limit)
    return chunks[0] if len(chunks) == 1 else b"".join(chunks)
