"""The command line's messages: every error and warning is one line on stderr.

- Bad input or usage (:data:`BAD_INPUT`: a ``ValueError`` such as ``ObjError`` or
  ``LimitError``, an ``OSError``, running out of memory) is ``rasterkit: error: ...``,
  exit code 2.
- Any other exception is a bug of rasterkit: ``rasterkit: internal error: ...``, exit code 1.
- A Python warning that escapes (a NumPy ``RuntimeWarning``, say) is ``rasterkit: warning:
  ... (RuntimeWarning)`` instead of Python's two lines with a source line.

A message about one model names it: ``MODEL: what went wrong``, unless it starts with the
model's name already (the loader's messages do: ``model.obj:12: ...``).

Pure standard library.
"""

from __future__ import annotations

import contextlib
import os
import sys
import warnings
from typing import Iterator

__all__ = ["BAD_INPUT", "UsageError", "error_line", "model", "one_line", "one_line_warnings", "printable"]


class UsageError(ValueError):
    """Bad input or usage: reported as one line, exit code 2. A ``ValueError``, so that a
    program calling the Python API (:func:`rasterkit.render_many`) catches it as one."""


#: What counts as bad input (exit code 2). ``ObjError`` and ``LimitError`` are ValueErrors;
#: an OSError is a missing file, a full disk, a file too large for ``RLIMIT_FSIZE`` ...
BAD_INPUT: tuple = (UsageError, ValueError, OSError, MemoryError)

_model: str | None = None  # the model being worked on, named in messages


def one_line(text: object) -> str:
    """``text`` on one line: its lines joined with spaces, each :func:`printable`."""
    return " ".join(printable(part.strip()) for part in str(text).splitlines() if part.strip())


def printable(text: str) -> str:
    """``text`` with every character that a terminal would not show as itself escaped: a
    byte of a file name that is not UTF-8 (Python's surrogate escape for it) as ``\\xNN``,
    a control character as Python writes it in a string (``\\t``, ``\\x1b``)."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else
                   f"\\x{ord(c) - 0xDC00:02x}" if "\udc80" <= c <= "\udcff" else
                   repr(c)[1:-1] for c in text)


def _describe(e: BaseException) -> str:
    if isinstance(e, OSError):
        text = e.strerror or str(e)
        return f"{os.fsdecode(e.filename)}: {text}" if e.filename is not None else text
    if isinstance(e, MemoryError):
        return "not enough memory" + (f" ({e})" if str(e) else "")
    return str(e)


def _about(text: str, model: str | None) -> str:
    if model is None or text.startswith(model + ":"):
        return text
    return f"{model}: {text}"


def error_line(e: BaseException, model: str | os.PathLike | None = None) -> tuple[int, str]:
    """The exit code (2 bad input, 1 internal error) and the line that reports ``e``, naming
    ``model`` (default: the one of :func:`model`) unless the message names it already."""
    name = _model if model is None else os.fspath(model)
    if isinstance(e, BAD_INPUT):
        return 2, "rasterkit: error: " + one_line(_about(_describe(e) or type(e).__name__, name))
    detail = _describe(e)
    text = f"{type(e).__name__}: {detail}" if detail else type(e).__name__
    return 1, "rasterkit: internal error: " + one_line(_about(text, name))


@contextlib.contextmanager
def model(path: str | os.PathLike | None) -> Iterator[None]:
    """Within the block, warnings and :func:`error_line` name ``path`` (None: no model)."""
    global _model
    saved, _model = _model, None if path is None else os.fspath(path)
    try:
        yield
    finally:
        _model = saved


def _show(message, category, filename, lineno, file=None, line=None) -> None:
    text = one_line(_about(one_line(message), _model))
    print(f"rasterkit: warning: {text} ({category.__name__})", file=sys.stderr, flush=True)


@contextlib.contextmanager
def one_line_warnings() -> Iterator[None]:
    """Within the block, Python warnings print as one ``rasterkit: warning:`` line (the
    filters are Python's: each warning once per place, unless ``-W`` says otherwise)."""
    with warnings.catch_warnings():
        warnings.showwarning = _show
        yield
