"""Helper processes forked from this one (:mod:`rasterkit.runtime.warm`'s first-run helpers):
started without a new interpreter, they share what this process has imported and loaded."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time


def prepare_numba() -> None:
    """Before forking helpers: load Numba's typing registries here (about 0.4 s of the first
    compile of every process), so that the helpers inherit them instead of each loading them
    again."""
    try:
        from numba.core.registry import cpu_target

        cpu_target.typing_context.refresh()
        cpu_target.target_context.refresh()
    except Exception:  # another Numba: each process loads them on its first compile, as usual
        pass


def can_fork() -> bool:
    """Whether a helper is forked: on Linux, when this process runs no other thread."""
    import threading

    return sys.platform.startswith("linux") and threading.active_count() == 1


class Forked:
    """A forked helper, with the part of ``subprocess.Popen`` that :mod:`rasterkit.runtime.warm` uses."""

    def __init__(self, pid: int, stdout):
        self.pid, self.stdout, self.returncode = pid, stdout, None

    def terminate(self) -> None:
        if self.returncode is None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.pid, signal.SIGTERM)

    def wait(self, timeout: float | None = None) -> int:
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.returncode is None:
            pid, status = os.waitpid(self.pid, 0 if deadline is None else os.WNOHANG)
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
            elif time.monotonic() >= deadline:
                raise subprocess.TimeoutExpired("rasterkit helper", timeout)
            else:
                time.sleep(0.01)
        return self.returncode


def fork(run, report: bool) -> Forked | None:
    """A helper process forked from this one that calls ``run()`` and ends (exit code 0, or 1
    when ``run`` raised); ``report``: its standard output is a pipe, the helper's ``stdout``
    here. Its standard input and error are the null device, and Ctrl-C and SIGTERM end it.
    None when it cannot be forked."""
    read, write = os.pipe() if report else (-1, -1)
    for stream in (sys.stdout, sys.stderr):  # nothing buffered here is written twice
        with contextlib.suppress(Exception):
            stream.flush()
    try:
        pid = os.fork()
    except OSError:
        for fd in (read, write):
            if fd >= 0:
                os.close(fd)
        return None
    if pid == 0:  # the helper: it never returns into the caller's code
        code = 1
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                signal.signal(sig, signal.SIG_DFL)
            null = os.open(os.devnull, os.O_RDWR)
            os.dup2(null, 0)
            os.dup2(null, 2)
            os.dup2(write if report else null, 1)
            if report:
                os.close(read)
            sys.stdout = os.fdopen(1, "w", closefd=False)  # the reports go to the pipe, whatever sys.stdout was
            run()
            sys.stdout.flush()
            code = 0
        finally:
            os._exit(code)
    if report:
        os.close(write)
    return Forked(pid, os.fdopen(read, "rb") if report else None)
