"""Launching a rasterkit command as its own process and measuring it: wall time, peak memory
and user CPU time (the start-up and first-render benchmarks)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

__all__ = ["ROOT", "child_environment", "cold_runs", "launch", "rasterkit_command"]

ROOT = Path(__file__).resolve().parents[1]

# Runs one command (argv as JSON) with stdout discarded and stderr to a file, and prints
# {"seconds", "maxrss" (bytes), "exit"}; stdlib only so that its own peak stays small. On Linux
# the launcher adopts the command's orphans (a first run's helper may outlive the command) and
# waits for them after the measurement, so that none still writes into the run's Numba cache
# when the suite removes it, nor competes with the next run for the cores.
_LAUNCHER = r"""
import ctypes, json, os, sys, time
argv, err = json.loads(sys.argv[1]), sys.argv[2]
adopts = False
if sys.platform.startswith("linux"):
    try:
        adopts = ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0) == 0  # PR_SET_CHILD_SUBREAPER
    except (OSError, AttributeError):
        pass
actions = [(os.POSIX_SPAWN_OPEN, 0, os.devnull, os.O_RDONLY, 0),
           (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
           (os.POSIX_SPAWN_OPEN, 2, err, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)]
begin = time.perf_counter()
pid = os.posix_spawn(argv[0], argv, os.environ, file_actions=actions)
_, status, usage = os.wait4(pid, 0)
end = time.perf_counter()
while adopts:
    try:
        os.waitpid(-1, 0)
    except ChildProcessError:
        break
print(json.dumps({"seconds": end - begin, "maxrss": usage.ru_maxrss * 1024,
                  "user": usage.ru_utime, "exit": os.waitstatus_to_exitcode(status)}))
"""


def rasterkit_command() -> list[str]:
    """The ``rasterkit`` console script of this interpreter, or ``python -m rasterkit``."""
    script = Path(sys.executable).parent / "rasterkit"
    if script.is_file() and os.access(script, os.X_OK):
        return [str(script)]
    return [sys.executable, "-m", "rasterkit"]


def child_environment(**extra: str) -> dict:
    """The suite's environment with this checkout first on PYTHONPATH, plus ``extra``."""
    path = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])
    return {**os.environ, "PYTHONPATH": path, **extra}


def launch(argv: list[str], env: dict, scratch: Path) -> dict:
    """Run ``argv`` to completion through the launcher: {"seconds", "maxrss", "user"} of that
    process (``user``: its user CPU seconds, its children's that it waited for included).

    Raises RuntimeError with the last line of its stderr when it exits non-zero.
    """
    err = Path(tempfile.mkstemp(dir=scratch, suffix=".stderr")[1])
    done = subprocess.run([sys.executable, "-c", _LAUNCHER, json.dumps(argv), str(err)], cwd=ROOT,
                          env=env, capture_output=True, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"launcher exit code {done.returncode}"]
        raise RuntimeError(lines[-1])
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if result["exit"] != 0:
        lines = err.read_text(errors="replace").strip().splitlines() or [f"exit code {result['exit']}"]
        raise RuntimeError(lines[-1])
    err.unlink()
    return result


def cold_runs(commands: dict, rounds: int, scratch: Path) -> dict:
    """Each of ``commands`` (label -> argv) run ``rounds`` times, each run alone in a new,
    empty ``NUMBA_CACHE_DIR`` (every kernel it needs compiles), the order rotated by one each
    round: label -> the :func:`launch` results. Raises RuntimeError naming the label of a
    command that fails."""
    labels = list(commands)
    runs: dict = {label: [] for label in labels}
    for round_ in range(rounds):
        shift = round_ % len(labels)
        for label in labels[shift:] + labels[:shift]:
            env = child_environment(NUMBA_CACHE_DIR=tempfile.mkdtemp(dir=scratch, prefix="numba-cache-"))
            try:
                runs[label].append(launch(commands[label], env, scratch))
            except RuntimeError as error:
                raise RuntimeError(f"{label}: {error}") from None
    return runs
