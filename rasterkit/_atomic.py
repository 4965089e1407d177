"""Writing a file atomically, with the mode a plain ``open(path, "w")`` would give it.

:func:`atomic_write` writes to a temporary file in the destination's folder and renames it
over the destination only when it is complete, so a failure (an error, a full disk,
SIGINT or SIGTERM in the command line) never leaves a half-written file nor replaces a good
one.

Two things a bare ``tempfile.mkstemp`` gets wrong are put right here:

- **Mode.** ``mkstemp`` creates its file 0600 whatever the umask. A new file gets
  ``0o666 & ~umask`` instead (0644 under the usual umask 022), and a file that is replaced
  keeps its permission bits (0640 stays 0640).
- **Messages.** An ``OSError`` that names the temporary file (``.x.png.8rkug2a1.tmp:
  Permission denied``) or no file at all (``File too large`` when ``RLIMIT_FSIZE`` is hit,
  ``No space left on device``) is raised again naming the destination, so that the error
  names the user's file.

Pure standard library.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
import threading
from pathlib import Path
from typing import Iterator

__all__ = ["atomic_write", "creation_mode"]

_umask_lock = threading.Lock()


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


def _naming(e: OSError, path: Path) -> OSError:
    """``e``, or an error of the same kind naming ``path`` when ``e`` names one of our
    temporary files (``.NAME.*.tmp`` beside ``path``) or no file."""
    if e.filename is not None:
        named = Path(os.fsdecode(e.filename))
        same_folder = os.path.abspath(named.parent) == os.path.abspath(path.parent)  # one may be relative
        ours = same_folder and named.name.startswith(f".{path.name}.") and named.name.endswith(".tmp")
        if not ours and named != path:
            return e  # about some other file: its own name is the right one
    args = (e.errno, e.strerror or str(e) or type(e).__name__, str(path))
    try:
        return type(e)(*args)
    except Exception:  # a subclass with a constructor of its own
        return OSError(*args)


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it onto ``path`` if the block succeeds.

    The file gets the mode of the file it replaces, or ``0o666 & ~umask`` when it is new.
    On any error or interruption (``BaseException``) the temporary file is removed and
    ``path`` is left as it was. An ``OSError`` naming the temporary file, or no file, is
    raised naming ``path`` instead.
    """
    path = Path(path)
    tmp = None
    try:
        mode = creation_mode(path)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        os.close(fd)
        yield Path(tmp)
        os.chmod(tmp, mode)  # after writing: the mode may be read-only
        os.replace(tmp, path)
    except BaseException as e:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        if isinstance(e, OSError):
            raise _naming(e, path) from None
        raise
