"""Writing files atomically, alone or several together, with the mode a plain ``open(path, "w")`` would give.

:func:`atomic_write` writes to a temporary file in the destination's folder and renames it
over the destination only when it is complete, so a failure (an error, a full disk,
SIGINT or SIGTERM in the command line) never leaves a half-written file nor replaces a good
one. Within :func:`all_or_none` the files of several ``atomic_write`` blocks are renamed
into place together at the block's end, so that a command writing an image and its depth,
normals and ids writes all of them or none.

Things a bare ``tempfile.mkstemp`` gets wrong are put right here:

- **Mode.** ``mkstemp`` creates its file 0600 whatever the umask. A new file gets
  ``0o666 & ~umask`` instead (0644 under the usual umask 022), and a file that is replaced
  keeps its permission bits (0640 stays 0640).
- **Messages.** An ``OSError`` that names the temporary file (``.x.png.8rkug2a1.tmp:
  Permission denied``) or no file at all (``File too large`` when ``RLIMIT_FSIZE`` is hit,
  ``No space left on device``) is raised again naming the destination, so that the error
  names the user's file.
- **Long names.** The temporary name is ``.NAME.XXXXXXXX.tmp``, 14 bytes longer than
  ``NAME``: for a name near the file system's limit (``NAME_MAX``, 255 bytes on most) the
  ``NAME`` part is shortened, so any name the file system takes can be written.
- **Symbolic links.** A destination that is a symbolic link is written through: the file
  it points to is replaced (the temporary file is made beside that file), and the link
  stays.
- **Folders.** A destination ending in ``/`` names a folder, never a file: refused with
  ``IsADirectoryError``, as ``open`` does.

Pure standard library.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import stat
import tempfile
import threading
from pathlib import Path
from typing import Iterator

__all__ = ["ENDS_IN_SEPARATOR", "all_or_none", "atomic_write", "creation_mode", "link_target", "remove_temporaries", "remove_temporaries_of", "temporary_prefix"]

_umask_lock = threading.Lock()

#: Why a path ending in a separator (``x.png/``) is not written.
ENDS_IN_SEPARATOR = "names a folder (it ends with a separator), not a file"

#: The temporary name adds a dot before ``NAME`` and ``.XXXXXXXX.tmp`` after it
#: (``tempfile``'s eight random characters).
_ADDED_BYTES = len(".") + len(".") + 8 + len(".tmp")

#: Within :func:`all_or_none`: the files written so far, ``(temporary, target, path)``.
_pending: contextvars.ContextVar[list | None] = contextvars.ContextVar("rasterkit_atomic_pending", default=None)


def _umask() -> int:
    """The process's umask, read without changing it where Linux allows (``/proc``)."""
    try:
        with open("/proc/self/status", "rb") as f:
            for line in f:
                if line.startswith(b"Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    with _umask_lock:  # elsewhere: set and restore it (other threads could see 0o022 briefly)
        mask = os.umask(0o022)
        os.umask(mask)
    return mask


def creation_mode(path: str | os.PathLike) -> int:
    """The permission bits ``path`` gets when rasterkit writes it: those of the file it
    replaces, else ``0o666 & ~umask``."""
    try:
        st = os.stat(path)
    except OSError:
        st = None
    if st is not None and stat.S_ISREG(st.st_mode):
        return stat.S_IMODE(st.st_mode) & 0o777
    return 0o666 & ~_umask()


def _name_max(folder: Path) -> int:
    """The longest file name (bytes) the file system of ``folder`` takes (255 if unknown)."""
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError, TypeError, AttributeError):
        return 255


def temporary_prefix(target: Path) -> str:
    """The start of the temporary names of ``target``: ``.NAME.``, with ``NAME`` cut short
    (in bytes) when the whole temporary name would pass the file system's ``NAME_MAX``."""
    name = os.fsencode(target.name)
    room = max(1, _name_max(target.parent) - _ADDED_BYTES)
    return "." + os.fsdecode(name[:room]) + "."


def link_target(path: str | os.PathLike) -> str:
    """The file that writing ``path`` replaces: ``path``, or what a symbolic link points to
    (followed to its end; a dangling link's target is created). A loop of links raises
    ``OSError`` (ELOOP) naming ``path``."""
    path = os.fspath(path)
    if not os.path.islink(path):
        return path
    real = os.path.realpath(path)
    if os.path.islink(real):  # realpath stops where links go round in a loop
        raise OSError(errno.ELOOP, os.strerror(errno.ELOOP), str(path))
    return real


def _is_ours(named: Path, target: Path) -> bool:
    same_folder = os.path.abspath(named.parent) == os.path.abspath(target.parent)  # one may be relative
    return same_folder and named.name.startswith(temporary_prefix(target)) and named.name.endswith(".tmp")


def _naming(e: OSError, path: Path, target: Path | None = None) -> OSError:
    """``e``, or an error of the same kind naming ``path`` when ``e`` names one of our
    temporary files (``.NAME.*.tmp`` beside ``target``, by default ``path``), ``target``,
    or no file."""
    target = path if target is None else target
    if e.filename is not None:
        named = Path(os.fsdecode(e.filename))
        if not _is_ours(named, target) and named not in (path, target):
            return e  # about some other file: its own name is the right one
    args = (e.errno, e.strerror or str(e) or type(e).__name__, str(path))
    try:
        return type(e)(*args)
    except Exception:  # a subclass with a constructor of its own
        return OSError(*args)


def _remove(*names) -> None:
    for name in names:
        with contextlib.suppress(OSError):
            os.unlink(name)


def remove_temporaries(path: str | os.PathLike) -> None:
    """Remove the temporary files that writing ``path`` left behind (``.NAME.*.tmp`` beside
    the file it replaces): what a writer killed outright (SIGKILL) could not remove itself.
    Only for a caller that knows no other writer of ``path`` is at work."""
    try:
        target = Path(link_target(os.fsdecode(os.fspath(path))))
        prefix = temporary_prefix(target)
        names = [entry.path for entry in os.scandir(target.parent)
                 if entry.name.startswith(prefix) and entry.name.endswith(".tmp")]
    except OSError:
        return
    _remove(*names)


def remove_temporaries_of(paths) -> None:
    """:func:`remove_temporaries` for many paths at once: each folder is listed once."""
    by_folder: dict[Path, set[str]] = {}
    for path in paths:
        try:
            target = Path(link_target(os.fsdecode(os.fspath(path))))
        except OSError:
            continue
        by_folder.setdefault(target.parent, set()).add(temporary_prefix(target))
    random_part = 8 + len(".tmp")  # tempfile's eight characters, then the suffix
    for folder, prefixes in by_folder.items():
        try:
            names = [entry.path for entry in os.scandir(folder)
                     if entry.name.endswith(".tmp") and entry.name[:-random_part] in prefixes]
        except OSError:
            continue
        _remove(*names)


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it onto ``path`` if the block succeeds.

    The file gets the mode of the file it replaces, or ``0o666 & ~umask`` when it is new. A
    symbolic link is written through (the file it points to is replaced). On any error or
    interruption (``BaseException``) the temporary file is removed and ``path`` is left as
    it was. An ``OSError`` naming the temporary file, or no file, is raised naming ``path``
    instead. A ``path`` ending in a separator (``x.png/``) raises ``IsADirectoryError``.
    Within :func:`all_or_none` the rename waits for the end of that block.
    """
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    if text.endswith(tuple(filter(None, (os.sep, os.altsep)))):
        raise IsADirectoryError(errno.EISDIR, ENDS_IN_SEPARATOR, text)
    path = target = Path(text)
    tmp = None
    try:
        target = Path(link_target(path))
        mode = creation_mode(target)
        fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(target), suffix=".tmp", dir=target.parent)
        os.close(fd)
        yield Path(tmp)
        os.chmod(tmp, mode)  # after writing: the mode may be read-only
        pending = _pending.get()
        if pending is None:
            os.replace(tmp, target)
        else:
            pending.append((tmp, target, path))  # renamed at the end of all_or_none
        tmp = None
    except BaseException as e:
        if tmp is not None:
            _remove(tmp)
        if isinstance(e, OSError):
            raise _naming(e, path, target) from None
        raise


@contextlib.contextmanager
def all_or_none() -> Iterator[None]:
    """Within the block, every :func:`atomic_write` of this thread (or task) keeps its
    temporary file; at the end of the block they are all renamed into place. If the block
    fails, or is interrupted, every temporary file is removed and no destination changes;
    if a rename fails (the destination became a folder, say), the files renamed before it
    are removed too, so that the block writes all of its files or none. Blocks nest: an
    inner block's files join the outer one's."""
    if _pending.get() is not None:
        yield
        return
    pending: list = []
    token = _pending.set(pending)
    try:
        yield
    except BaseException:
        _remove(*(tmp for tmp, _, _ in pending))
        raise
    finally:
        _pending.reset(token)
    done = []
    try:
        for tmp, target, path in pending:
            try:
                os.replace(tmp, target)
            except OSError as e:
                raise _naming(e, path, target) from None
            done.append(target)
    except BaseException:
        _remove(*done, *(tmp for tmp, _, _ in pending[len(done):]))
        raise
