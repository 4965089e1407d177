"""The limits rasterkit keeps to, so that no input takes unbounded time, memory or disk.

Two of them are settings (documented in ``docs/limits.md``):

- **File size**: a model or material file larger than :func:`max_file_size` bytes is
  refused before it is read (default 2 GiB; ``RASTERKIT_MAX_FILE_SIZE``, the command
  line's ``--max-file-size``, or :func:`set_max_file_size`). Only regular files are read:
  a device, a FIFO or a directory is refused whatever its size.
- **Memory**: a call whose arrays would need more than :func:`memory_limit` bytes is refused
  before anything is allocated, with one line that says how much it needs and why (default:
  the memory of the machine, or of its container, or the address space left to the process
  under ``ulimit -v``, whichever is smallest;
  ``RASTERKIT_MAX_MEMORY``, the command line's ``--max-memory``, or :func:`set_memory_limit`).

Sizes are given in bytes, or with a suffix K, M, G, T (powers of 1024), as in ``"512M"``.

Pure Python: importing this module imports neither NumPy nor Numba.
"""

from __future__ import annotations

import functools
import os

try:
    import resource
except ImportError:  # not a POSIX system
    resource = None

__all__ = ["LimitError", "check_memory", "format_bytes", "max_file_size", "memory_limit", "parse_size",
           "set_max_file_size", "set_memory_limit"]

DEFAULT_MAX_FILE_SIZE = 2 * 1024**3

_SUFFIXES = {"": 1, "B": 1, "K": 1024, "M": 1024**2, "G": 1024**3, "T": 1024**4}


class LimitError(ValueError):
    """An input that would go past one of the limits of this module. A ``ValueError``, so
    that the command line reports it in one line with exit code 2."""


def parse_size(text: str | int) -> int:
    """Bytes from ``"1500"``, ``"512M"``, ``"2G"`` (K, M, G, T: powers of 1024; an optional
    trailing ``B`` or ``iB``) or an int. Raises ``ValueError`` for anything else or a size
    below 1."""
    if isinstance(text, bool):
        raise ValueError(f"a size must be a number of bytes, got {text!r}")
    if isinstance(text, int):
        value = text
    else:
        s = str(text).strip().upper().removesuffix("IB").removesuffix("B")
        unit = s[-1:] if s[-1:] in _SUFFIXES else ""
        number = s[: len(s) - len(unit)].strip()
        try:
            value = int(float(number) * _SUFFIXES[unit]) if number else -1
        except (ValueError, OverflowError):
            raise ValueError(f"a size must be bytes or a number with K, M, G or T, got {text!r}") from None
    if value < 1:
        raise ValueError(f"a size must be at least 1 byte, got {text!r}")
    return value


def format_bytes(n: float) -> str:
    """``n`` bytes for people: ``"1.5 GiB"``, ``"312 MiB"``, ``"900 bytes"``."""
    for unit, size in (("TiB", 1024**4), ("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} bytes"


def _from_environment(name: str):
    text = os.environ.get(name)
    if not text:
        return None
    return _parse_setting(name, text)


@functools.lru_cache(maxsize=16)
def _parse_setting(name: str, text: str) -> int:
    """``text``, the value of the environment variable ``name``, as bytes (kept: renderers
    check their memory on every frame)."""
    try:
        return parse_size(text)
    except ValueError as e:
        raise LimitError(f"{name}: {e}") from None


_max_file_size: int | None = None
_memory_limit: int | None = None


def max_file_size() -> int:
    """The largest model or material file read, in bytes (see the module's documentation)."""
    if _max_file_size is not None:
        return _max_file_size
    return _from_environment("RASTERKIT_MAX_FILE_SIZE") or DEFAULT_MAX_FILE_SIZE


def set_max_file_size(n: int | str | None) -> None:
    """Set :func:`max_file_size` (bytes or a size string); None restores the default."""
    global _max_file_size
    _max_file_size = None if n is None else parse_size(n)


@functools.lru_cache(maxsize=1)
def _installed_memory() -> int:
    """The memory of this machine in bytes, or of its container (cgroup) when smaller; read
    once (it takes some 20 us, and renderers check their memory on every frame)."""
    total = 0
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        pass
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path) as f:
                text = f.read().strip()
        except OSError:
            continue
        if text.isdigit() and 0 < int(text) < (total or 1 << 62):
            total = int(text)
    return total or 1 << 62


def _address_space_left() -> int | None:
    """Bytes of address space this process may still map under its ``RLIMIT_AS``, or None
    without such a limit (the usual case)."""
    if resource is None:  # not a POSIX system
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY:
        return None
    used = 0
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    used = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError):
        pass
    return max(soft - used, 0)


def machine_memory() -> int:
    """The memory of this machine in bytes, or of its container (cgroup) when smaller, or
    the address space the process may still map when it runs under an ``RLIMIT_AS`` that
    leaves less (``ulimit -v``: an allocation beyond it fails however much memory is free)."""
    total = _installed_memory()
    left = _address_space_left()
    return total if left is None else min(total, left)


def memory_limit() -> int:
    """The most memory, in bytes, that one call may ask for (see the module's documentation)."""
    if _memory_limit is not None:
        return _memory_limit
    return _from_environment("RASTERKIT_MAX_MEMORY") or machine_memory()


def set_memory_limit(n: int | str | None) -> None:
    """Set :func:`memory_limit` (bytes or a size string); None restores the default."""
    global _memory_limit
    _memory_limit = None if n is None else parse_size(n)


def check_memory(nbytes: float, what: str) -> None:
    """Raise :class:`LimitError` when ``nbytes`` (an estimate made before allocating) is
    over :func:`memory_limit`; ``what`` says what needs it, e.g. ``"a 32768x32768
    solid+wire render"``."""
    limit = memory_limit()
    if nbytes > limit:
        if _memory_limit is not None:
            source = "set by --max-memory or rasterkit.limits.set_memory_limit"
        elif os.environ.get("RASTERKIT_MAX_MEMORY"):
            source = "set by RASTERKIT_MAX_MEMORY"
        elif limit < _installed_memory():
            source = "the address space left to this process under its ulimit -v"
        else:
            source = "the memory this machine has; raise it with --max-memory or RASTERKIT_MAX_MEMORY"
        raise LimitError(f"{what} needs about {format_bytes(nbytes)} of memory, more than the limit of "
                         f"{format_bytes(limit)} ({source})")
