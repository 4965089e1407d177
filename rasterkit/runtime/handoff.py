"""Waiting for another thread without sleeping, for a bounded number of steps.

:func:`rasterkit.runtime.threads.run_parallel` hands each parallel pass to its helper threads and waits
for them. A thread asleep on a lock takes 20-50 microseconds to wake on these machines (its
core has gone idle), and so does one asleep on Python's GIL: over the three passes of a
wireframe that was a tenth of the frame. So a helper that has just finished watches for the
next pass for a short while, and the caller watches for the helpers' results, before either
sleeps on its lock. The bound keeps the watching from taking a core away from other
processes for long.

A watching helper also waits until the caller's thread has claimed its first piece of the
new pass: the caller is then inside the kernel, without the GIL, and the helper takes the
GIL at once instead of sleeping on it while the caller starts its call.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import load_acquire, pause


@kernel(refcounts=False)
def wait_for(flags, index, target, steps):
    """Watch ``flags[index]`` (int64) for up to ``steps`` steps; True as soon as it is at
    least ``target``, False when the steps run out (the caller then sleeps on its lock)."""
    for _ in range(steps):
        if load_acquire(flags, index) >= target:
            return True
        pause()
    return load_acquire(flags, index) >= target


@kernel(refcounts=False)
def finish_and_watch(flags, finished_at, finished, handed_at, claims, claims_at, steps):
    """A helper between two calls: publish ``flags[finished_at] = finished`` (the caller
    watches it; stored here, without the GIL, so that the caller can take the GIL at once),
    then watch for call ``finished + 1`` in ``flags[handed_at]`` and, once it is there, for
    the caller's first claim (``claims[claims_at] >= 1``), all within ``steps`` steps.
    True when both came in time."""
    flags[finished_at] = finished
    if not wait_for(flags, handed_at, finished + 1, steps):
        return False
    return wait_for(claims, claims_at, np.int64(1), steps)  # not a literal 1: one compiled wait_for
