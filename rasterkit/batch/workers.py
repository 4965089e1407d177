"""Rendering one model in a worker, and the local pool of worker processes (``--jobs N``).

:func:`run_task` is what every engine runs per model — the in-process loop, the local pool
here, and Dask's workers (:mod:`rasterkit.batch.dask_engine`): it renders with
:func:`rasterkit.batch.render_one.render_model` and returns the model's manifest record instead
of raising, so a failing model never stops a batch.

Before the pool starts, :func:`rasterkit.batch.engine.run` has rendered a tiny model with the
batch's task in this process (:func:`warm_up`: the kernels are loaded from Numba's cache,
or compiled once); the pool then starts ``jobs`` processes. On Linux, when no thread but rasterkit's own kernel helpers runs here,
it forks them: they start at once and inherit the loaded kernels (rasterkit's thread pool
is not inherited: a child starts its own, :func:`rasterkit.runtime.threads._forget_pool`; no OpenMP
runtime is involved). Otherwise (another platform, or a program with threads of its own,
whose locks a fork could copy held) it spawns new interpreters, which inherit nothing. The parent hands each idle worker the next
model through its own pipe and waits on the pipes and the processes at once
(``multiprocessing.connection.wait``): a worker that dies (a crash, the OOM killer) costs
only its model, recorded as an error, and a new worker takes its place. On Ctrl-C or
SIGTERM the parent stops the workers with SIGTERM; each removes the temporary file of the
image it was writing. A parent killed outright (SIGKILL) takes its workers with it: each
gets SIGTERM when its parent dies (:func:`_die_with`).

Compiling happens once, not once per worker: a worker whose kernels are not in Numba's
disk cache yet renders its first model holding a lock file (``rasterkit-compile.lock`` in
the temporary folder), so one worker compiles and the others then load the cached
kernels (:func:`compile_lock`).
"""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import time
from collections import deque
from pathlib import Path

from rasterkit.batch import report as _report
from rasterkit.runtime import stop as _stop
from rasterkit.image.atomic import remove_temporaries

__all__ = ["LocalPool", "compile_lock", "cores", "run_task", "warm_up"]

_first_done = False  # in a worker: its first model has been rendered


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


@contextlib.contextmanager
def compile_lock(task):
    """Hold the host's compile lock while this process renders its first model, when the
    kernels of ``task``'s mode are not cached yet (a no-op afterwards, and where ``fcntl``
    is missing)."""
    global _first_done
    if _first_done:
        yield
        return
    _first_done = True
    try:
        import fcntl

        from rasterkit.runtime import warm as _warm

        cached = _warm.band_worker_cached(task.options)
    except ImportError:
        cached = True
    if cached:
        yield
        return
    path = Path(tempfile.gettempdir()) / f"rasterkit-compile-{os.getuid()}.lock"
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def run_task(source: str, output: str, task, threads: int | None = None) -> dict:
    """Render ``source`` into ``output``; its manifest record (status ok or error)."""
    from rasterkit.runtime import threads as _threads
    from rasterkit.batch.render_one import render_model

    if threads is not None:
        _threads.set_threads(threads)
    started = time.perf_counter()
    record = {"input": source, "output": output, "status": "ok", "error": None}
    triangles, warnings = None, []
    with _report.model(source):
        try:
            with compile_lock(task):
                triangles = render_model(Path(source), Path(output), task, say=warnings.append)
        except Exception as e:
            _stop.check()  # a signal's stop that came out as another exception (rasterkit.runtime.stop)
            code, line = _report.error_line(e)
            prefix = "rasterkit: error: " if code == 2 else "rasterkit: internal error: "
            record.update(status="error", error=line.removeprefix(prefix), code=code)
    record.update(seconds=round(time.perf_counter() - started, 4), triangles=triangles, warnings=warnings)
    return record


class _Stop(BaseException):
    """SIGTERM in a worker: unwinds the render (temporary files are removed) and exits."""


def _worker_main(conn, threads: int, task, limit_state, parent: int, inherited: list) -> None:
    """A worker process: render the models that arrive on ``conn`` until ``None`` does, or
    until the parent process (``parent``, its pid) has gone. ``inherited``: the parent's ends
    of the workers' pipes that a forked worker holds copies of, closed at once (else the
    pipe of a parent killed outright would never end, and its worker would wait on it)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole group: the parent decides

    def stop(signum, frame):
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        _stop.request(_Stop)  # raised again if this one is lost on its way (rasterkit.runtime.stop)
        raise _Stop()

    signal.signal(signal.SIGTERM, stop)
    for end in inherited:
        end.close()
    from rasterkit import limits

    limits._max_file_size, limits._memory_limit = limit_state
    try:
        _die_with(parent)
        while True:
            job = conn.recv()
            if job is None:
                return
            conn.send(run_task(job[0], job[1], task, threads))
    except (_Stop, EOFError, BrokenPipeError):
        return


def _die_with(parent: int) -> None:
    """Have this process get SIGTERM (:class:`_Stop`: its temporary file is removed) when
    ``parent`` dies, even by SIGKILL: from the kernel on Linux (``PR_SET_PDEATHSIG``),
    elsewhere from a thread that looks for a new parent process every second. A parent that
    has gone already stops it now."""
    import sys

    asked = False
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            asked = ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) == 0
        except (OSError, AttributeError):
            pass
    if not asked:
        _watch_parent(parent)
    if os.getppid() != parent:
        raise _Stop()


_PR_SET_PDEATHSIG = 1  # from <sys/prctl.h>


def _watch_parent(parent: int) -> None:
    import threading

    def watch():
        while os.getppid() == parent:
            time.sleep(1.0)
        os.kill(os.getpid(), signal.SIGTERM)

    threading.Thread(target=watch, name="rasterkit-parent-watch", daemon=True).start()


def _start_method() -> str:
    """``fork`` on Linux when no thread but rasterkit's kernel helpers runs, else ``spawn``."""
    import sys
    import threading

    others = [t for t in threading.enumerate()
              if t is not threading.main_thread() and t.name != "rasterkit-worker" and t.is_alive()]
    return "fork" if sys.platform.startswith("linux") and not others else "spawn"


_TINY_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def warm_up(task, strict: bool = False) -> None:
    """Render a tetrahedron from an OBJ file as ``task`` says, at 16x12 pixels and as a still
    image, in this process: every kernel a batch of ``task`` runs is then loaded (or
    compiled), and an option that no model could render with (a camera that cannot be
    made...) raises here, once, instead of failing every model (``strict``; otherwise it is
    left for the real models to report)."""
    from rasterkit.batch.render_one import render_model

    tiny = task.replace(view=task.view.replace(size=(16, 12), camera_opencv=None), turntable=None,
                        depth=None, normals=None, ids=None)
    try:
        with tempfile.TemporaryDirectory(prefix="rasterkit-warm-") as folder:
            model = Path(folder) / "tiny.obj"
            model.write_text(_TINY_OBJ)
            render_model(model, Path(folder) / "tiny.png", tiny)
    except OSError:
        pass  # the temporary folder's trouble (a full disk), not the task's: the models say theirs
    except Exception:
        if strict:
            raise


class LocalPool:
    """``jobs`` worker processes, each rendering with ``threads`` kernel threads."""

    def __init__(self, jobs: int, threads: int, task):
        import multiprocessing

        from rasterkit import limits

        self._ctx = multiprocessing.get_context(_start_method())
        self.jobs, self.threads, self.task = jobs, threads, task
        self._limits = (limits._max_file_size, limits._memory_limit)
        self._workers: list[dict] = []

    def _start(self) -> dict:
        parent, child = self._ctx.Pipe()
        # a forked worker closes its copies of the parent's pipe ends; a spawned one has none
        inherited = [w["conn"] for w in self._workers] + [parent] if self._ctx.get_start_method() == "fork" else []
        process = self._ctx.Process(target=_worker_main, name="rasterkit-worker", daemon=True,
                                    args=(child, self.threads, self.task, self._limits, os.getpid(), inherited))
        process.start()
        child.close()
        worker = {"process": process, "conn": parent, "task": None}
        self._workers.append(worker)
        return worker

    def run(self, tasks, on_result) -> None:
        """Render ``tasks`` (``(source, output)`` pairs of strings), calling
        ``on_result(record)`` in this process as each finishes, in finishing order."""
        from multiprocessing.connection import wait

        pending = deque(tasks)
        try:
            for _ in range(min(self.jobs, len(pending))):
                self._give(self._start(), pending)
            while any(w["task"] is not None for w in self._workers):
                busy = [w for w in self._workers if w["task"] is not None]
                ready = wait([w["conn"] for w in busy] + [w["process"].sentinel for w in busy])
                for worker in busy:
                    if worker["conn"] in ready or worker["process"].sentinel in ready:
                        self._collect(worker, pending, on_result)
        finally:
            self._stop_all()

    def _give(self, worker: dict, pending: deque) -> None:
        worker["task"] = pending.popleft() if pending else None
        try:
            worker["conn"].send(worker["task"])
        except (BrokenPipeError, OSError):
            pass  # it died: the sentinel says so next

    def _collect(self, worker: dict, pending: deque, on_result) -> None:
        try:
            record = worker["conn"].recv() if worker["conn"].poll() else None
        except (EOFError, OSError):
            record = None
        if record is not None:  # on_result's own errors are not the pipe's: they go up
            on_result(record)
            self._give(worker, pending)
            return
        if worker["process"].is_alive():
            return
        source, output = worker["task"]  # it died while rendering this model
        code = worker["process"].exitcode
        why = f"signal {-code}" if code is not None and code < 0 else f"exit code {code}"
        remove_temporaries(output)  # what it was writing when it died: it cannot remove that itself
        on_result({"input": source, "output": output, "status": "error", "code": 1,
                   "error": f"{source}: the worker process died ({why})",
                   "seconds": None, "triangles": None})
        self._workers.remove(worker)
        worker["conn"].close()
        if pending:
            self._give(self._start(), pending)

    def _stop_all(self) -> None:
        for worker in self._workers:
            process = worker["process"]
            if worker["task"] is None:
                with contextlib.suppress(OSError):
                    worker["conn"].send(None)
            elif process.is_alive():
                process.terminate()  # SIGTERM: it removes its temporary file and exits
        for worker in self._workers:
            worker["process"].join(timeout=10)
            if worker["process"].is_alive():
                worker["process"].kill()
                worker["process"].join()
                if worker["task"] is not None:
                    remove_temporaries(worker["task"][1])
            worker["conn"].close()
        self._workers = []
