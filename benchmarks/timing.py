"""The one timing loop of the suite: warm-up, then interleaved runs, then medians.

Every side of a comparison (rasterkit and its peers) runs in the same loop, taking turns,
so that drift on a busy machine (other processes, frequency changes) hits all of them alike.
The order is reversed every other round so that no side always runs right after another.
"""

from __future__ import annotations

import statistics
import time
from typing import Callable, Mapping


def seconds(fn: Callable[[], object]) -> float:
    """Wall-clock seconds of one call of ``fn``."""
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def interleaved(sides: Mapping[str, Callable[[], object]], repeat: int, warmup: int) -> dict[str, float]:
    """Median wall-clock seconds of each callable, timed in alternation.

    Parameters
    ----------
    sides : mapping of name -> callable
        Each callable does one complete unit of the workload (for a renderer: clear, draw and
        read the image back into a NumPy array).
    repeat : int
        Timed runs per side, >= 1; the median is returned.
    warmup : int
        Untimed runs per side first (JIT compilation, caches, lazy GL state).

    Returns
    -------
    dict of name -> float
        Median seconds per side.
    """
    names = list(sides)
    for _ in range(warmup):
        for name in names:
            sides[name]()
    samples: dict[str, list[float]] = {name: [] for name in names}
    for round_ in range(repeat):
        for name in names if round_ % 2 == 0 else reversed(names):
            samples[name].append(seconds(sides[name]))
    return {name: statistics.median(times) for name, times in samples.items()}
