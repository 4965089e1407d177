"""The tests' own Numba references (ray casts, ray-traced occlusion) compiled as written, also
in the CI pass that sets ``NUMBA_BOUNDSCHECK=1``.

That pass checks rasterkit's kernels; these references are oracles whose inputs the tests make.
Compiled with the checks they ran four to five times slower and took most of that pass's time
in the shadow and occlusion tests. Numba reads the setting when a function compiles
(``BaseContext.enable_boundscheck``): the call that compiles a reference, and everything it
calls, runs with the setting put back to "as each function says" (no checks here)."""

from __future__ import annotations

from contextlib import contextmanager

from numba.core import config


@contextmanager
def as_written():
    """Compile (and run) the Numba references called inside without the global bounds checks."""
    saved = config.BOUNDSCHECK
    config.BOUNDSCHECK = None
    try:
        yield
    finally:
        config.BOUNDSCHECK = saved
