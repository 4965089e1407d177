"""The command line's notice that the kernels are compiling (first run only).

A first render compiles the kernels for several seconds without a word; this prints one line
on stderr as the first of rasterkit's kernels starts compiling, once per process. Numba
fires its ``numba:compile`` event only when it compiles a function, after it has tried its
on-disk cache (``Dispatcher.compile``), so a run whose kernels load from the cache prints
nothing. The Python API never turns it on: only :mod:`rasterkit.cli` does, around its work.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager
from typing import Iterator

from numba.core import event

# No time in it: what compiles depends on the command, its mode and what earlier runs left in
# the cache (measured on two cores: a first `info` 5-7 s, a first solid render of a model
# 12-18 s, a first hidden-line one 20 s, a solid render after a hidden one 1 s), and one core
# takes about twice as long.
MESSAGE = ("rasterkit: compiling the kernels for first use, once "
           "(later runs load them from the cache)...")

_shown = False


class _FirstCompile(event.Listener):
    """Prints :data:`MESSAGE` when the first rasterkit function starts compiling."""

    def on_start(self, ev: event.Event) -> None:
        global _shown
        if _shown:
            return
        module = getattr(ev.data["dispatcher"].py_func, "__module__", None) or ""
        if module == "rasterkit" or module.startswith("rasterkit."):
            _shown = True
            print(MESSAGE, file=sys.stderr, flush=True)

    def on_end(self, ev: event.Event) -> None:
        pass


@contextmanager
def compile_notice() -> Iterator[None]:
    """Within the block, announce on stderr the first compilation of a rasterkit kernel."""
    with event.install_listener("numba:compile", _FirstCompile()):
        yield
