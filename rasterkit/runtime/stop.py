"""A stop that a signal asked for, kept until it has been seen through.

The command line's handlers of SIGINT and SIGTERM raise ``KeyboardInterrupt`` or
:class:`rasterkit.cli.Terminated` in the main thread, wherever it is. Raised inside a call
that a C extension makes back into Python, such an exception can be lost there (Numba's
dispatcher may clear it and carry on), or come out as a ``SystemError``. So the handler
also records the stop here (:func:`request`); the thread pool raises it again at the start
of every parallel pass (:func:`check`, in :func:`rasterkit.runtime.threads.run_parallel`), so a render
that went on stops at its next pass; and the command line, having caught it, clears it
(:func:`clear`). A batch's worker process records its own SIGTERM here too. Nothing here
is set unless those handlers are installed.

Pure standard library.
"""

from __future__ import annotations

__all__ = ["check", "clear", "pending", "request"]

_pending: type[BaseException] | None = None


def request(exception: type[BaseException]) -> None:
    """A signal asked to stop with ``exception`` (the handler raises it too)."""
    global _pending
    _pending = exception


def pending() -> type[BaseException] | None:
    """The exception of a stop that was asked for and not yet cleared (else None)."""
    return _pending


def check() -> None:
    """Raise the stop that was asked for, if there is one."""
    if _pending is not None:
        raise _pending()


def clear() -> None:
    global _pending
    _pending = None
