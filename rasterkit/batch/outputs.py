"""The files a render command writes, checked before anything is drawn.

- :func:`check_writable`: a file can be written at the path: it does not end in a separator
  (``x.png/`` names a folder), it is not a folder, its folder exists and may be written.
  Raised as the ``OSError`` the write would give, naming the path.
- :func:`check_distinct`: no two outputs are one file, and no output is one of the models:
  paths are compared after following symbolic links (``os.path.realpath``), and names that
  differ only in case where the folder's file system does not tell them apart. Raised as a
  usage error naming both.

Without these the image, ``--depth``, ``--normals``, ``--ids`` and the contact sheet could
silently overwrite each other, or a render could write some of its files and fail on the
next. Writing them all or none is :func:`rasterkit.image.atomic.all_or_none`'s part.

Pure standard library.
"""

from __future__ import annotations

import errno
import os
import tempfile
from typing import Iterable

from rasterkit.image.atomic import ENDS_IN_SEPARATOR, link_target
from rasterkit.batch.report import UsageError

__all__ = ["check_distinct", "check_writable", "named_outputs"]

_SEPARATORS = tuple(filter(None, (os.sep, os.altsep)))


def _text(path) -> str:
    text = os.fspath(path)
    return os.fsdecode(text) if isinstance(text, bytes) else text


def named_outputs(options, output) -> list[tuple[str, str]]:
    """A single render's files, each with its flag: ``-o`` and ``--depth``, ``--normals``,
    ``--ids`` when ``options`` asks for them."""
    named = [("-o", _text(output))]
    for flag in ("depth", "normals", "ids"):
        value = getattr(options, flag, None)
        if value:
            named.append((f"--{flag}", _text(value)))
    return named


def check_writable(path) -> None:
    """Raise the ``OSError`` that writing a file at ``path`` would give, naming ``path``,
    when it cannot be written: ``path`` ends in a separator or is a folder
    (``IsADirectoryError``), its folder is missing (``FileNotFoundError``) or is not a
    folder (``NotADirectoryError``), or may not be written (``PermissionError``). A
    symbolic link is checked where it points."""
    text = _text(path)
    if text.endswith(_SEPARATORS):
        raise IsADirectoryError(errno.EISDIR, ENDS_IN_SEPARATOR, text)
    target = link_target(text)
    if os.path.isdir(target):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", text)
    folder = os.path.dirname(target) or "."
    if not os.path.isdir(folder):
        if os.path.exists(folder):
            raise NotADirectoryError(errno.ENOTDIR, f"{folder!r} is not a folder", text)
        raise FileNotFoundError(errno.ENOENT, f"folder {folder!r} does not exist", text)
    if not os.access(folder, os.W_OK | os.X_OK):
        raise PermissionError(errno.EACCES, "Permission denied", text)


def _folds_case(folder: str) -> bool:
    """Whether the file system of ``folder`` (or of its nearest existing parent) finds a
    file under its name in upper case: it creates and removes one empty hidden file."""
    folder = os.path.abspath(folder)
    while not os.path.isdir(folder) and os.path.dirname(folder) != folder:
        folder = os.path.dirname(folder)
    try:
        fd, name = tempfile.mkstemp(prefix=".rasterkit-case-", dir=folder)
    except OSError:
        return False  # nothing can be written there: the writes will say so
    try:
        os.close(fd)
        return os.path.exists(os.path.join(folder, os.path.basename(name).upper()))
    finally:
        os.unlink(name)


def check_distinct(outputs: Iterable[tuple[str, object]], models: Iterable[object] = ()) -> None:
    """Raise a usage error when two of ``outputs`` (``(what, path)`` pairs: ``("-o",
    "x.png")``, ``("--depth", "d.npy")``, a model's name for its image in a batch) are one
    file, or an output is one of ``models``."""
    seen: dict[str, tuple[str, str]] = {}  # real path -> (what, path)
    folded: dict[str, tuple[str, str, str]] = {}  # real path in lower case -> (real path, what, path)
    folds: dict[str, bool] = {}
    for what, path in outputs:
        text = _text(path)
        real = os.path.realpath(text)
        if real in seen:
            raise UsageError(f"{seen[real][0]} and {what} would both be written to {text}")
        other = folded.get(real.casefold())
        if other is not None:
            folder = os.path.dirname(other[0])
            if folder not in folds:
                folds[folder] = _folds_case(folder)
            if folds[folder]:
                raise UsageError(f"{other[1]} and {what} would both be written to one file ({other[2]} and "
                                 f"{text}: this file system does not tell upper and lower case apart)")
        seen[real] = (what, text)
        folded.setdefault(real.casefold(), (real, what, text))
    for model in models:
        if model is None:
            continue
        hit = seen.get(os.path.realpath(_text(model)))
        if hit is not None:
            raise UsageError(f"{hit[0]} {hit[1]} would overwrite the model {_text(model)}")
