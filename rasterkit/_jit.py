"""The one place that decides how kernels are compiled.

Every kernel in :mod:`rasterkit.kernels` is decorated with :func:`kernel` so that the
compilation policy (on-disk cache, fast-math flags, error model) is the same everywhere.

- ``cache=True``: the second process that runs a kernel loads it from ``__pycache__``
  instead of compiling it again.
- ``error_model="numpy"``: division by zero gives inf/nan instead of raising, so no
  exception machinery sits in the inner loops. Inputs are validated before any kernel runs.
- fast-math: the flags that let LLVM reorder and fuse float arithmetic, *without* ``nnan``
  and ``ninf``: the depth buffer is cleared to +inf and clipping drops NaN vertices, and
  both need inf and NaN to behave as IEEE says.
- ``boundscheck`` is left to the ``NUMBA_BOUNDSCHECK`` environment variable, so one CI pass
  runs every kernel with bounds checking on. That pass needs a cache of its own
  (``NUMBA_CACHE_DIR``): the on-disk cache does not tell checked from unchecked code, so a
  warm cache would hand back the unchecked kernels.
"""

from __future__ import annotations

import numba

FASTMATH = frozenset({"nsz", "arcp", "contract", "afn", "reassoc"})

_OPTIONS = dict(cache=True, nogil=True, error_model="numpy", fastmath=set(FASTMATH))


def kernel(fn=None, *, parallel: bool = False, inline: str = "never"):
    """Compile ``fn`` with rasterkit's jit policy.

    Use as ``@kernel`` or ``@kernel(parallel=True)``. ``parallel=True`` enables ``prange``;
    ``inline="always"`` inlines a small helper into its callers at the Numba IR level.
    """

    def wrap(f):
        return numba.njit(parallel=parallel, inline=inline, **_OPTIONS)(f)

    return wrap if fn is None else wrap(fn)


def set_threads(n: int | None) -> int:
    """Set the number of threads used by parallel kernels; ``None`` means all cores.

    Returns the number in effect. Raises ``ValueError`` for n < 1 or more than the
    machine's ``numba.config.NUMBA_NUM_THREADS``.
    """
    limit = numba.config.NUMBA_NUM_THREADS
    if n is None:
        n = limit
    if not 1 <= int(n) <= limit:
        raise ValueError(f"threads must be between 1 and {limit}, got {n}")
    numba.set_num_threads(int(n))
    return int(n)


def readonly(a):
    """``a``, or a read-only view of it. A Mesh's arrays are read-only, and Numba compiles a
    kernel once per argument type, read-only or not: kernels that take mesh arrays get them
    read-only always, so they compile once, not once more for a writeable array."""
    if not a.flags.writeable:
        return a
    view = a.view()
    view.flags.writeable = False
    return view
