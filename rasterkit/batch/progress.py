"""The progress of a batch on stderr: a bar on a terminal, plain lines otherwise.

On a terminal one line is redrawn in place: ``[#####-----] 12/40  3.1 models/s  9 s left
name``. Otherwise (a log file, a pipe) each finished model is a line of its own: ``12/40
name ok 0.41 s``. Messages (:meth:`Progress.say`) take the bar away, print their line and
let the bar come back with the next model.

Pure standard library (and :mod:`rasterkit.batch.report`).
"""

from __future__ import annotations

import sys
import time

from rasterkit.batch.report import printable

__all__ = ["Progress"]

_WIDTH = 78


class Progress:
    """Progress of ``total`` models on ``stream`` (default stderr); ``enabled=False``: silent."""

    def __init__(self, total: int, stream=None, enabled: bool = True):
        self.total, self.done = total, 0
        self.stream = sys.stderr if stream is None else stream
        self.enabled = enabled
        self.tty = enabled and _isatty(self.stream)
        self.started = time.monotonic()
        self._shown = False

    def advance(self, name: str, status: str, seconds: float | None = None) -> None:
        """One more model finished (``status``: ok, error, skipped)."""
        self.done += 1
        name = printable(name)
        if not self.enabled:
            return
        if self.tty:
            self._clear()
            print(self._bar(name)[:_WIDTH].ljust(_WIDTH), end="\r", file=self.stream, flush=True)
            self._shown = True
        else:
            took = f" {seconds:.2f} s" if seconds is not None else ""
            print(f"{self.done}/{self.total} {name} {status}{took}", file=self.stream, flush=True)

    def _bar(self, name: str) -> str:
        width = 20
        filled = width * self.done // max(self.total, 1)
        elapsed = max(time.monotonic() - self.started, 1e-9)
        rate = self.done / elapsed
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        eta = f"{left:.0f} s left" if left != float("inf") else "-"
        return f"[{'#' * filled}{'-' * (width - filled)}] {self.done}/{self.total} {rate:.2f} models/s {eta} {name}"

    def say(self, line: str) -> None:
        """Print ``line`` on a line of its own (always, even when disabled)."""
        self._clear()
        print(printable(line), file=self.stream, flush=True)

    def close(self) -> None:
        self._clear()

    def _clear(self) -> None:
        if self._shown:
            print(" " * _WIDTH, end="\r", file=self.stream, flush=True)
            self._shown = False


def _isatty(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False
