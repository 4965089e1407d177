"""The one place that decides how kernels are compiled and how they run in parallel.

Compiling
---------
Every kernel in :mod:`rasterkit.raster.kernels` is decorated with :func:`kernel`, so the policy is
the same everywhere:

- ``cache=True``: the second process that runs a kernel loads it from ``__pycache__``
  instead of compiling it again.
- ``nogil=True``: a kernel releases the GIL, so the threads of :func:`run_parallel` (and a
  caller's own threads) run kernels at the same time.
- No ``parallel=True``: Numba's parfor passes took most of the compile time (a minute for
  the first wire render) and its OpenMP threads spin while they wait, which made two
  rasterkit processes on one machine 3-45x slower. Parallel work is run by
  :func:`run_parallel` instead.
- ``error_model="numpy"``: division by zero gives inf/nan instead of raising, so no
  exception machinery sits in the inner loops. Inputs are validated before any kernel runs.
- fast-math: the flags that let LLVM reorder and fuse float arithmetic, *without* ``nnan``
  and ``ninf``: the depth buffer is cleared to +inf and clipping drops NaN vertices, and
  both need inf and NaN to behave as IEEE says.
- ``boundscheck`` is left to the ``NUMBA_BOUNDSCHECK`` environment variable, so one CI pass
  runs every kernel with bounds checking on. That pass needs a cache of its own
  (``NUMBA_CACHE_DIR``): the on-disk cache does not tell checked from unchecked code, so a
  warm cache would hand back the unchecked kernels.
- The on-disk cache is patched (:mod:`rasterkit.runtime.numba_cache`) so that processes
  compiling different specializations of one kernel at once cannot mix up their entries.

The threads that run kernels in parallel are :mod:`rasterkit.runtime.threads`.
"""

from __future__ import annotations

import os
import threading

import numba

from rasterkit.runtime import numba_cache as _numba_cache
from rasterkit.runtime import numba_inline as _numba_inline

FASTMATH = frozenset({"nsz", "arcp", "contract", "afn", "reassoc"})

_numba_inline.install()  # before anything compiles: Numba's inliner does each piece of work once
_numba_cache.install()  # and its cache's entries cannot be mixed up by processes saving at once

# no_cfunc_wrapper: no kernel is ever passed as a first-class function, so none needs the C
# wrapper Numba otherwise builds and optimises for each (about 4 % of a first render's compiling)
_OPTIONS = dict(cache=True, nogil=True, error_model="numpy", fastmath=set(FASTMATH), no_cfunc_wrapper=True)


def kernel(fn=None, *, inline: str = "never", refcounts: bool = True, fastmath: bool = True):
    """Compile ``fn`` with rasterkit's jit policy.

    Use as ``@kernel`` or ``@kernel(inline="always")``; ``inline="always"`` inlines a small
    helper into its callers at the Numba IR level (keep it for a few lines in a hot loop:
    inlined code is compiled again in every caller, but a call that passes arrays costs
    atomic reference counts, which IR inlining avoids).

    ``refcounts=False`` compiles without Numba's reference counting (``_nrt=False``): for
    the band and chunk loops, which allocate nothing. Numba counts references around every
    IR-inlined call that passes an array; in a loop over edges or triangles those atomic
    operations cost 20 % (a ``prange`` body escapes them: Numba drops them there, which is
    why the band loops were fast as ``prange`` bodies). Such a kernel must not allocate,
    nor call anything IR-inlined that does.

    ``fastmath=False`` compiles IEEE arithmetic exactly as written, for a kernel whose result
    is defined by its rounding (the DDA's running sum: with ``reassoc`` LLVM may turn it into
    a multiplication, which rounds differently).
    """

    def wrap(f):
        # _nrt always explicit: a callee compiled while its caller is typed inherits an
        # unset option, and a kernel that allocates needs the runtime whoever calls it first.
        options = _OPTIONS if fastmath else {**_OPTIONS, "fastmath": False}
        return numba.njit(inline=inline, _nrt=refcounts, **options)(f)

    return wrap if fn is None else wrap(fn)


def cached(dispatcher) -> bool:
    """Whether Numba's cache has an index for ``dispatcher`` (any signature). Unknown (a
    Numba without these internals) counts as cached."""
    try:
        return os.path.exists(dispatcher._cache._cache_file._index_path)
    except AttributeError:
        return True


def compile_apart(worker, args) -> None:
    """Compile ``worker`` for ``args`` (or load it from Numba's cache) in a thread of its own,
    from the bottom of a fresh Python stack. Numba's compiler recurses deeply (``copy.deepcopy``
    of its IR), and CPython 3.11 maps and unmaps a 16 KiB piece of its frame stack each time a
    recursion crosses the end of one: from deep in a render's calls that happened hundreds of
    thousands of times for a band worker (seconds of system time; the frames' depth decides).
    A worker that Numba cannot compile for these types raises here as its call would."""
    failed = []

    def run():
        try:
            worker.compile(tuple(numba.typeof(a) for a in args))
        except BaseException as error:  # raised below, in the caller's thread
            failed.append(error)

    thread = threading.Thread(target=run, name="rasterkit-compile", daemon=True)
    thread.start()
    thread.join()
    if failed:
        raise failed[0]


def readonly(a):
    """``a``, or a read-only view of it. A Mesh's arrays are read-only, and Numba compiles a
    kernel once per argument type, read-only or not: kernels that take mesh arrays get them
    read-only always, so they compile once, not once more for a writeable array."""
    if not a.flags.writeable:
        return a
    view = a.view()
    view.flags.writeable = False
    return view
