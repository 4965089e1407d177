"""Running a hostile case in a child process, with a time and a memory limit.

A case that could crash the interpreter (a segfault), run away with memory or block
forever fails its test through :func:`run_python` or :func:`run_cli` instead of taking the
test session down: the child gets ``RLIMIT_AS`` (address space) and a timeout, and the
result says how it ended.
"""

from __future__ import annotations

import os
import resource
import signal
import subprocess
import sys
import textwrap
from dataclasses import dataclass

from .paths import ROOT, TESTS

#: Address space a child may use. Numba and LLVM reserve a lot of address space that they
#: never touch, so this is far above the memory a case needs; a runaway still hits it.
MEMORY_LIMIT = 3 * 1024**3
TIMEOUT = 120.0


@dataclass
class Outcome:
    """How a child ended: ``code`` (negative: killed by that signal), its output, and
    whether it ran out of time."""

    code: int | None
    stdout: str
    stderr: str
    timed_out: bool = False

    @property
    def crashed(self) -> bool:
        """Killed by a signal (a segfault, an abort), not counting our own timeout."""
        return self.code is not None and self.code < 0 and not self.timed_out

    def describe(self) -> str:
        if self.timed_out:
            return "timed out"
        if self.crashed:
            return f"killed by {signal.Signals(-self.code).name}: {self.stderr[-2000:]}"
        return f"exit {self.code}; stderr: {self.stderr[-2000:]!r}"

    def one_line_error(self) -> str:
        """The error line of a clean failure (exit 2, one line on stderr starting
        ``rasterkit: error:``); raises AssertionError with what happened otherwise."""
        lines = self.stderr.splitlines()
        assert self.code == 2 and len(lines) == 1 and lines[0].startswith("rasterkit: error: "), self.describe()
        return lines[0]


def _limits(memory: int):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    return apply


def _environment(extra: dict | None) -> dict:
    # the repository (rasterkit) and tests/ (the ``support`` helpers), as in the parent
    path = os.pathsep.join([str(ROOT), str(TESTS), *filter(None, [os.environ.get("PYTHONPATH")])])
    return {**os.environ, "PYTHONPATH": path, **(extra or {})}


def run(argv: list, *, timeout: float = TIMEOUT, memory: int = MEMORY_LIMIT, env: dict | None = None,
        cwd=None, stdin=None) -> Outcome:
    """Run ``argv`` (a list of str or paths) as a child process with the limits."""
    try:
        done = subprocess.run([str(a) for a in argv], capture_output=True, text=True, errors="replace",
                              timeout=timeout, preexec_fn=_limits(memory), env=_environment(env), cwd=cwd,
                              stdin=subprocess.DEVNULL if stdin is None else stdin)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        err = e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        return Outcome(None, out, err, timed_out=True)
    return Outcome(done.returncode, done.stdout, done.stderr)


def run_python(code: str, **kwargs) -> Outcome:
    """Run the Python source ``code`` (dedented) in a child process with the limits."""
    return run([sys.executable, "-c", textwrap.dedent(code)], **kwargs)


def run_cli(*args, **kwargs) -> Outcome:
    """Run ``python -m rasterkit ARGS`` in a child process with the limits."""
    return run([sys.executable, "-m", "rasterkit", *args], **kwargs)
