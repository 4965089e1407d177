"""The threads that run kernels in parallel (the kernels themselves are compiled by
:func:`rasterkit.runtime.jit.kernel`).

Running in parallel
-------------------
A parallel kernel is a *worker*: ``worker(slot, *args)``, called at once on ``n`` threads
with slots ``0 .. n - 1`` (the caller's thread is slot 0). Workers share the work by
claiming pieces from a counter (:func:`rasterkit.runtime.intrinsics.fetch_add`), so a thread
that gets less of the machine simply claims fewer pieces, and the result never depends on
the number of threads. Between calls the threads watch for the next one for at most
:data:`WATCH_SECONDS` (100 microseconds: the gaps between the passes of one frame), then wait
on a lock, asleep: beside other busy processes they give their core away.
"""

from __future__ import annotations

import itertools
import os
import threading
import time

import numba
import numpy as np

from rasterkit.runtime import stop as _stop
from rasterkit.runtime.jit import cached, compile_apart

#: Most threads a parallel kernel may use: Numba's ``NUMBA_NUM_THREADS`` (the environment
#: variable, else the number of CPUs).
MAX_THREADS = max(1, int(numba.config.NUMBA_NUM_THREADS))


def _default_threads() -> int:
    try:
        available = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        available = os.cpu_count() or 1
    return max(1, min(MAX_THREADS, available))


_threads = _default_threads()


def set_threads(n: int | None) -> int:
    """Set the number of threads used by parallel kernels; ``None`` means all available cores.

    Returns the number in effect. Raises ``ValueError`` for n < 1 or more than
    :data:`MAX_THREADS`. Images do not depend on it.
    """
    global _threads
    if n is None:
        n = _default_threads()
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_THREADS:
        raise ValueError(f"threads must be an int between 1 and {MAX_THREADS}, got {n!r}")
    _threads = n
    return n


def get_threads() -> int:
    """The number of threads parallel kernels use (:func:`set_threads`)."""
    return _threads


#: How long a thread watches for the next pass (a helper) or for its helpers' results (the
#: caller) before it sleeps on its lock: longer than the gaps between the passes of a frame,
#: short beside the time a process keeps the core (:mod:`rasterkit.runtime.handoff`).
WATCH_SECONDS = 100e-6
_watch_steps = None
#: Slots of the flags: the number of calls handed to a helper and of calls it finished,
#: and the pool's work counter (128 bytes apart: on cache lines of their own).
_HANDED, _FINISHED, _CLAIMS = 8, 24, 40


def _steps_for(seconds: float) -> int:
    """How many steps of :func:`rasterkit.runtime.handoff.wait_for` take ``seconds`` here."""
    global _watch_steps
    if _watch_steps is None:
        from rasterkit.runtime.handoff import wait_for

        flags = np.zeros(64, np.int64)
        wait_for(flags, 0, 1, 1)
        steps = 20000
        t = time.perf_counter()
        wait_for(flags, 0, 1, steps)
        _watch_steps = steps / max(time.perf_counter() - t, 1e-9)
    return max(1, int(_watch_steps * seconds))


def _wake(lock) -> None:
    """Release ``lock`` as a wake-up call: already released means a wake-up is pending, and
    one is enough (the woken thread reads the counters, which say what happened)."""
    try:
        lock.release()
    except RuntimeError:
        pass


class _Worker:
    """A thread that runs the calls handed to it, one at a time; both sides watch a flag for a
    moment before they sleep on a lock (:mod:`rasterkit.runtime.handoff`).

    What happened is in two counters, each written by one side: ``_handed`` (calls handed
    over, by the caller) and ``_finished`` (calls finished, their result stored, by the
    helper). The locks ``_start`` and ``_done`` only wake the other side, which then reads
    the counters: a wake-up that comes twice or finds the work already done costs one more
    look. So an exception raised in the caller's thread at any point (a signal handler's:
    Ctrl-C, the command line's SIGTERM, raised in the main thread between any two steps,
    also right after a lock was acquired) cannot lose a call, nor wait for one that never
    comes: the caller's next look at the counters sets it right."""

    def __init__(self, claims):
        from rasterkit.runtime import handoff

        self._handoff = handoff
        self._steps = _steps_for(WATCH_SECONDS)
        self._flags = np.zeros(64, np.int64)
        self._handed = 0
        self._finished = 0
        self._start, self._done = threading.Lock(), threading.Lock()
        self._start.acquire()
        self._done.acquire()
        self._call = None
        self._result = None
        threading.Thread(target=self._loop, args=(claims,), name="rasterkit-worker", daemon=True).start()

    def _loop(self, claims):
        flags = self._flags
        while True:
            self._handoff.finish_and_watch(flags, _FINISHED, self._finished, _HANDED, claims, _CLAIMS, self._steps)
            while self._handed == self._finished:
                self._start.acquire()
            (fn, args), self._call = self._call, None
            try:
                result = (True, fn(*args))
            except BaseException as error:  # handed to the caller by wait()
                result = (False, error)
            self._result = result
            self._finished += 1
            _wake(self._done)

    def submit(self, fn, args):
        """Hand ``fn(*args)`` to the helper. A call that an interrupted caller left running
        (``_run`` stopped by a second signal before it had waited) is waited for first."""
        if self._handed != self._finished:
            interrupted = self.drop()
            if interrupted is not None:
                raise interrupted
        self._call = (fn, args)
        self._handed += 1
        self._flags[_HANDED] = self._handed
        _wake(self._start)

    def wait(self):
        """The result (or the exception) of the call handed last; None if none is running.
        An exception raised in this thread while waiting (Ctrl-C) is raised once the call
        has finished: the next call must not find this one's result, nor share the thread
        with it."""
        interrupted = self._join()
        result, self._result = self._result, None
        if interrupted is not None:
            raise interrupted
        if result is None:
            return None
        ok, value = result
        if not ok:
            raise value
        return value

    def drop(self):
        """Wait for the call handed last and forget its result (or its exception); returns
        the exception raised in this thread meanwhile, as :meth:`_join` does. For a caller
        that an exception stopped, perhaps inside :meth:`submit`: the helper is woken first,
        in case the call was counted but the helper not yet woken."""
        _wake(self._start)
        interrupted = self._join()
        self._result = None
        return interrupted

    def _join(self):
        """Wait until the helper has finished every call handed to it; returns the exception
        raised in this thread meanwhile (the first; None if none came), for the caller to
        raise when the helper no longer uses the call's arguments."""
        interrupted = None
        while True:
            try:
                if interrupted is None:
                    self._handoff.wait_for(self._flags, _FINISHED, self._handed, self._steps)
                while self._finished != self._handed:
                    self._done.acquire()
                return interrupted
            except BaseException as error:  # noqa: PERF203 - wait on, then raise it
                if interrupted is None:
                    interrupted = error
                _wake(self._start)  # a submit cut short after counting its call woke nobody


class _Pool:
    def __init__(self):
        self.workers: list[_Worker] = []
        # One parallel call at a time uses the workers: the one whose token is owner[0].
        # dict.setdefault takes it atomically, and a call that an exception (Ctrl-C) stops
        # right after taking it still sees that it has it, and gives it back (see _run).
        self.owner: dict = {}
        # flags[_CLAIMS]: the work counter of the call in progress, which the helpers
        # watch for the caller's first claim
        self.flags = np.zeros(64, np.int64)
        self.counter = self.flags[_CLAIMS:_CLAIMS + 1]


_pool = _Pool()


def _forget_pool():  # threads do not survive fork(): a child starts a pool of its own
    global _pool
    _pool = _Pool()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


_intercept = None


def intercept(hook) -> None:
    """Have ``hook(worker, args)`` see every :func:`run_parallel` call first (None: no
    hook); when it returns a list, that is the call's result and the worker does not run.
    :mod:`rasterkit.runtime.warm` uses it to compile the band workers in a second process."""
    global _intercept
    _intercept = hook


def run_parallel(worker, *args, threads: int | None = None) -> list:
    """Call ``worker(slot, *args)`` on ``threads`` threads at once (default
    :func:`get_threads`), slots ``0 .. threads - 1``; returns their results in slot order.

    When another Python thread is running a parallel call at the same time, this one runs
    on the caller's thread alone (slot 0 only): a worker must claim its work from a shared
    counter, never assume that every slot runs.
    """
    return _run(worker, args, threads, counted=False)


def in_parallel(task, n: int, threads: int | None = None) -> list:
    """``task(k)`` for k = 0..n-1 on up to ``threads`` threads (default :func:`get_threads`),
    each claiming the next k; the results in order of k. For tasks that are Python
    functions calling kernels (a chunk of a file each)."""
    results = [None] * n
    claims = itertools.count()  # next() on it is atomic under the GIL

    def worker(slot):
        for k in iter(claims.__next__, None):
            if k >= n:
                return
            results[k] = task(k)

    if n == 1:
        results[0] = task(0)
    elif n > 1:
        run_parallel(worker, threads=min(n, get_threads() if threads is None else threads))
    return results


def run_workers(worker, *args, threads: int | None = None) -> list:
    """:func:`run_parallel` for the kernels' workers, ``worker(slot, counter, *args)``: with
    a fresh work counter ((1,) int64, 0) that the slots claim their pieces from."""
    return _run(worker, args, threads, counted=True)


def _run(worker, args, threads, counted):
    _stop.check()  # a signal's stop that a C extension lost on its way out (rasterkit.runtime.stop)
    pool = _pool
    n = get_threads() if threads is None else threads
    token = object()
    try:
        parallel = n > 1 and pool.owner.setdefault(0, token) is token
        if counted:  # the pool's counter, which its helpers watch; a fresh one without them
            counter = pool.counter if parallel else np.zeros(1, np.int64)
            counter[0] = 0
            args = (counter, *args)
        if _intercept is not None:
            result = _intercept(worker, args)
            if result is not None:
                return result
        if getattr(worker, "overloads", True) == {} and not cached(worker):  # its first compile: from a fresh stack
            compile_apart(worker, (0, *args))
        if not parallel:
            return [worker(0, *args)]
        if not counted:
            pool.counter[0] = 1  # nothing to watch for
        while len(pool.workers) < n - 1:
            pool.workers.append(_Worker(pool.flags))
        helpers = pool.workers[: n - 1]
        try:
            for slot, helper in enumerate(helpers, start=1):
                helper.submit(worker, (slot, *args))
            first = worker(0, *args)
        except BaseException:
            _settle(helpers)  # the helpers still read the arguments: let them finish
            raise
        return [first, *_wait_all(helpers)]
    finally:
        # No call here: Python runs a signal's handler after a call returns, so a Ctrl-C
        # that arrives now is raised after the workers are given back, not before.
        if pool.owner == {0: token}:
            del pool.owner[0]


def _settle(helpers) -> None:
    """After an exception in the caller: wait until no helper runs a call of it (those
    handed before the exception; their results are dropped). An exception raised in this
    thread meanwhile (Ctrl-C) is raised once they have finished."""
    interrupted = None
    for helper in helpers:
        interrupted = helper.drop() or interrupted
    if interrupted is not None:
        raise interrupted


def _wait_all(helpers):
    results, error = [], None
    for helper in helpers:
        try:
            results.append(helper.wait())
        except BaseException as e:  # wait for every helper before raising
            results.append(None)
            error = error or e
    if error is not None:
        raise error
    return results
