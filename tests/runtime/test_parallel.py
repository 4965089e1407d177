"""rasterkit.runtime.threads.run_parallel and the thread count: slots, work sharing, errors, callers on
several Python threads, fork safety, and no OpenMP (Numba's parallel backends never start)."""

import ast
import itertools
import os
import subprocess
import sys
import textwrap
import threading
import time

import numba
import numpy as np
import pytest

import rasterkit
from rasterkit import shapes
from rasterkit.runtime.threads import MAX_THREADS, get_threads, run_parallel, set_threads
from rasterkit.camera import Camera
from rasterkit.runtime.intrinsics import fetch_add
from support.hostile import run_python
from support.startup import ENV

THREAD_COUNTS = list(range(1, MAX_THREADS + 1))
needs_two = pytest.mark.skipif(MAX_THREADS < 2, reason="needs NUMBA_NUM_THREADS >= 2")


@pytest.fixture(autouse=True)
def _restore_threads():
    before = get_threads()
    yield
    set_threads(before)


@numba.njit(nogil=True)
def _claim_pieces(slot, counter, n_pieces, values, out, hits, owner):
    """Claims pieces from ``counter`` until none is left: out[p] = values[p] ** 2 + p,
    hits[p] += 1, owner[p] = slot. Returns the number of pieces this slot claimed."""
    claimed = 0
    while True:
        p = fetch_add(counter, 0, 1)
        if p >= n_pieces:
            return claimed
        out[p] = values[p] * values[p] + p
        hits[p] += 1
        owner[p] = slot
        claimed += 1


def _run_claims(n_pieces, threads, seed=0):
    values = np.random.default_rng(seed).integers(-1000, 1000, n_pieces).astype(np.int64)
    out = np.zeros(n_pieces, np.int64)
    hits = np.zeros(n_pieces, np.int64)
    owner = np.full(n_pieces, -1, np.int64)
    claimed = run_parallel(_claim_pieces, np.zeros(1, np.int64), n_pieces, values, out, hits, owner,
                           threads=threads)
    return values, out, hits, owner, claimed


def _check_claims(n_pieces, values, out, hits, owner, claimed, threads):
    np.testing.assert_array_equal(hits, np.ones(n_pieces, np.int64))  # every piece exactly once
    np.testing.assert_array_equal(out, values * values + np.arange(n_pieces))
    assert np.all((owner >= 0) & (owner < len(claimed)))
    # Each slot's count is the number of pieces it wrote.
    assert claimed == [int((owner == s).sum()) for s in range(len(claimed))]
    assert sum(claimed) == n_pieces
    assert len(claimed) in (1, threads)


# --- slots and results ------------------------------------------------------------------------


@pytest.mark.parametrize("threads", THREAD_COUNTS)
def test_results_come_back_in_slot_order_one_per_slot(threads):
    caller = threading.get_ident()
    results = run_parallel(lambda slot, a, b: (slot, a, b, threading.get_ident()), "a", 7, threads=threads)
    assert [r[:3] for r in results] == [(s, "a", 7) for s in range(threads)]
    assert results[0][3] == caller  # slot 0 runs on the caller's thread
    assert len({r[3] for r in results}) == threads  # each slot on a thread of its own


@pytest.mark.parametrize("threads", THREAD_COUNTS)
def test_default_thread_count_is_get_threads(threads):
    set_threads(threads)
    assert run_parallel(lambda slot: slot) == list(range(threads))


@pytest.mark.parametrize("threads", THREAD_COUNTS)
@pytest.mark.parametrize("n", [0, 1, 2, 5, 200])
def test_in_parallel_runs_each_task_once_and_keeps_their_order(threads, n):
    from rasterkit.runtime.threads import in_parallel

    seen, lock = [], threading.Lock()

    def task(k):
        with lock:
            seen.append((k, threading.get_ident()))
        time.sleep(0.0005 * (k % 3))  # tasks of different lengths: claimed out of order
        return k * k

    assert in_parallel(task, n, threads) == [k * k for k in range(n)]
    assert sorted(k for k, _ in seen) == list(range(n))
    assert len({t for _, t in seen}) <= max(1, min(n, threads))


@pytest.mark.parametrize("threads", THREAD_COUNTS)
@pytest.mark.parametrize("n_pieces", [0, 1, 2, 3, 1000, 100_003])
def test_fetch_add_worker_covers_every_piece_once(threads, n_pieces):
    _check_claims(n_pieces, *_run_claims(n_pieces, threads, seed=n_pieces), threads)


@needs_two
def test_slots_other_than_the_callers_claim_work_when_it_is_slow():
    # A slow piece on slot 0 leaves the others to slot 1: both slots really run at once.
    pieces = itertools.count()  # next() is atomic under the GIL: a counter for Python workers
    owner = np.full(20, -1)

    def worker(slot):
        while (p := next(pieces)) < len(owner):
            owner[p] = slot
            if slot == 0:
                time.sleep(0.05)

    run_parallel(worker, threads=2)
    assert set(owner) == {0, 1}


# --- errors -----------------------------------------------------------------------------------


class _Boom(Exception):
    pass


@needs_two
@pytest.mark.parametrize("failing_slot", [1, MAX_THREADS - 1, 0])
def test_an_exception_in_a_worker_reaches_the_caller_and_the_pool_keeps_working(failing_slot):
    finished = []

    def worker(slot):
        if slot == failing_slot:
            raise _Boom(f"slot {slot}")
        finished.append(slot)
        return slot

    with pytest.raises(_Boom, match=f"slot {failing_slot}"):
        run_parallel(worker, threads=MAX_THREADS)
    # The other slots ran to the end before the call returned.
    assert sorted(finished) == [s for s in range(MAX_THREADS) if s != failing_slot]
    for threads in THREAD_COUNTS:
        assert run_parallel(lambda slot: slot * 10, threads=threads) == [10 * s for s in range(threads)]
        _check_claims(5000, *_run_claims(5000, threads), threads)


@needs_two
def test_exceptions_in_every_helper_are_raised_once_and_leave_no_result_behind():
    def worker(slot):
        if slot:
            raise _Boom(slot)
        return "ok"

    with pytest.raises(_Boom):
        run_parallel(worker, threads=MAX_THREADS)
    assert run_parallel(lambda slot: ("fine", slot), threads=MAX_THREADS) == [("fine", s) for s in range(MAX_THREADS)]


INTERRUPTED = """
import os, signal, threading, time
from rasterkit.runtime.threads import run_parallel

signal.signal(signal.SIGINT, signal.default_int_handler)  # also when started as a background job
run_parallel(lambda slot: slot, threads=2)  # compiled and started before the Ctrl-C
started = threading.Event()

def slow(slot):
    if slot == 1:
        started.set()
        time.sleep(1.0)
    return ("first", slot)

def interrupt():  # Ctrl-C while the caller waits for slot 1 (not while Numba compiles)
    started.wait(30)
    time.sleep(0.2)
    os.kill(os.getpid(), signal.SIGINT)

threading.Thread(target=interrupt, daemon=True).start()
try:
    run_parallel(slow, threads=2)
except KeyboardInterrupt:
    print("interrupted")
results = []
def later_calls():
    for name in ("second", "third"):
        results.append(run_parallel(lambda slot, name=name: (name, slot), threads=2))
caller = threading.Thread(target=later_calls, daemon=True)
caller.start()
caller.join(5)
print("hung" if caller.is_alive() else "done", results)
"""


@needs_two
def test_calls_after_an_interrupted_call_get_their_own_results():
    done = _python(INTERRUPTED, timeout=60)
    assert done.stdout.splitlines() == [
        "interrupted", "done [[('second', 0), ('second', 1)], [('third', 0), ('third', 1)]]"], done.stdout + done.stderr


SIGNALS_EVERYWHERE = """
import faulthandler, random, signal, sys
from rasterkit.runtime.threads import run_parallel

faulthandler.dump_traceback_later(40, exit=True)  # a hang: every thread's stack, exit 1

class Stop(BaseException):  # what the command line's SIGTERM handler raises, like Ctrl-C's
    pass

fired = []

def stop(signum, frame):
    fired.append(signum)
    raise Stop

signal.signal(signal.SIGALRM, stop)
work = lambda slot, call: (call, slot)
run_parallel(work, 0, threads=2)
rng = random.Random(1)
for call in range(1, ROUNDS + 1):
    fired.clear()
    try:
        signal.setitimer(signal.ITIMER_REAL, rng.uniform(1e-6, 150e-6))
        run_parallel(work, call, threads=2)
        while not fired:  # the signal lands inside this try, wherever the call had got to
            pass
    except Stop:
        pass
    assert run_parallel(work, -call, threads=2) == [(-call, 0), (-call, 1)], call
print("ok")
"""


@needs_two
def test_a_signal_raising_anywhere_in_a_parallel_call_neither_hangs_nor_mixes_up_calls():
    """A signal handler that raises (Ctrl-C, the command line's SIGTERM) runs in the main
    thread between any two steps of the hand-over, also right after a lock was acquired:
    thousands of them, at random moments of the calls. Each later call still gets all its
    slots' results and only its own (the old two-lock protocol hung within a few hundred)."""
    done = run_python(SIGNALS_EVERYWHERE.replace("ROUNDS", "5000"), timeout=60)
    assert (done.code, done.stdout) == (0, "ok\n"), done.describe()


# --- callers on several Python threads --------------------------------------------------------


@needs_two
def test_a_second_caller_while_the_pool_is_busy_runs_alone_and_both_are_complete():
    n = 20_000
    first_started, second_done = threading.Event(), threading.Event()
    results, errors = {}, []

    def slow_worker(slot, counter, n_pieces, values, out, hits, owner):
        if slot == 0:
            first_started.set()
            assert second_done.wait(30)  # hold the pool until the second caller is through
        return _claim_pieces(slot, counter, n_pieces, values, out, hits, owner)

    def first():
        try:
            values = np.arange(n, dtype=np.int64)
            out, hits, owner = np.zeros(n, np.int64), np.zeros(n, np.int64), np.full(n, -1, np.int64)
            claimed = run_parallel(slow_worker, np.zeros(1, np.int64), n, values, out, hits, owner, threads=2)
            results["first"] = (values, out, hits, owner, claimed)
        except BaseException as e:
            errors.append(e)

    def second():
        try:
            assert first_started.wait(30)
            results["second"] = _run_claims(n, 2, seed=1)
        except BaseException as e:
            errors.append(e)
        finally:
            second_done.set()

    threads = [threading.Thread(target=first), threading.Thread(target=second)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert not any(t.is_alive() for t in threads), "run_parallel hung with two callers"
    assert not errors, errors
    _check_claims(n, *results["first"], 2)
    _check_claims(n, *results["second"], 2)
    assert len(results["first"][4]) == 2
    assert results["second"][4] == [n]  # the docstring's fallback: slot 0 alone, all the work


@needs_two
def test_two_python_threads_calling_run_parallel_at_once_get_correct_results():
    errors, counts = [], [0, 0]
    start = threading.Barrier(2)

    def caller(k):
        try:
            start.wait(10)
            for i in range(300):
                n = 1 + (i * 37) % 2000
                values, out, hits, owner, claimed = _run_claims(n, 2, seed=i)
                _check_claims(n, values, out, hits, owner, claimed, 2)
                assert run_parallel(lambda slot, i=i: (k, i, slot), threads=2) in (
                    [(k, i, 0)], [(k, i, 0), (k, i, 1)])
                counts[k] += 1
        except BaseException as e:
            errors.append(e)

    threads = [threading.Thread(target=caller, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not any(t.is_alive() for t in threads), "run_parallel hung with two callers"
    assert not errors, errors
    assert counts == [300, 300]


@needs_two
def test_renders_on_two_python_threads_at_once_equal_one_alone():
    mesh, camera = shapes.icosphere(4), _camera(80, 60)
    set_threads(MAX_THREADS)
    expected = {mode: rasterkit.render(mesh, camera, mode=mode).color for mode in ("solid", "hidden")}
    errors = []

    def caller(mode):
        try:
            for _ in range(10):
                np.testing.assert_array_equal(rasterkit.render(mesh, camera, mode=mode).color, expected[mode])
        except BaseException as e:
            errors.append(e)

    threads = [threading.Thread(target=caller, args=(m,)) for m in ("solid", "hidden", "solid")]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not any(t.is_alive() for t in threads)
    assert not errors, errors


# --- set_threads ------------------------------------------------------------------------------


@pytest.mark.parametrize("bad", [0, -1, MAX_THREADS + 1, True, False, 1.5, 2.0])
def test_set_threads_rejects(bad):
    before = get_threads()
    with pytest.raises(ValueError):
        set_threads(bad)
    assert get_threads() == before


@pytest.mark.parametrize("n", THREAD_COUNTS)
def test_set_threads_accepts_1_to_max(n):
    assert set_threads(n) == n
    assert get_threads() == n


def test_set_threads_none_restores_the_default():
    try:
        available = len(os.sched_getaffinity(0))
    except AttributeError:
        available = os.cpu_count()
    default = max(1, min(MAX_THREADS, available))
    set_threads(1)
    assert set_threads(None) == default
    assert get_threads() == default
    assert rasterkit.set_threads is set_threads
    assert MAX_THREADS == max(1, numba.config.NUMBA_NUM_THREADS)


# --- images do not depend on the thread count -------------------------------------------------


def _camera(width, height):
    return Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=width, height=height)


STYLES = [
    dict(mode="wire"),
    dict(mode="wire", aa=True),
    dict(mode="hidden"),
    dict(mode="hidden", aa=True),
    dict(mode="solid"),
    dict(mode="solid", shading="smooth", ids=True),
    dict(mode="solid", cull="none", background="transparent"),
    dict(mode="solid+wire"),
]


@needs_two
@pytest.mark.parametrize("style", STYLES, ids=lambda s: "-".join(f"{k}={v}" for k, v in s.items()))
def test_render_is_identical_at_one_and_two_threads(style):
    # icosphere(4): 5120 faces and 7680 edges, enough for the setup passes to go parallel too.
    scene = [(shapes.icosphere(4), _camera(96, 72)), (shapes.torus(rings=12, sides=6), _camera(33, 70))]
    for mesh, camera in scene:
        set_threads(1)
        one = rasterkit.render(mesh, camera, **style)
        set_threads(2)
        two = rasterkit.render(mesh, camera, **style)
        assert len(np.unique(one.color.reshape(-1, one.color.shape[2]), axis=0)) > 1  # not blank
        np.testing.assert_array_equal(two.color, one.color)
        np.testing.assert_array_equal(two.depth, one.depth)
        if style.get("ids"):
            np.testing.assert_array_equal(two.ids, one.ids)


# --- fork and the absence of OpenMP (each in a fresh interpreter) -----------------------------


def _python(script: str, timeout: float) -> subprocess.CompletedProcess:
    done = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], capture_output=True, text=True,
                          env=ENV, timeout=timeout)
    assert done.returncode == 0, done.stdout + done.stderr
    return done


FORK = """
import os, signal, sys, threading, traceback
import numpy as np
import rasterkit
from rasterkit import shapes
from rasterkit.camera import Camera

rasterkit.set_threads(2)
mesh = shapes.icosphere(4)
camera = Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=80, height=60)
parent = {m: rasterkit.render(mesh, camera, mode=m).color for m in ("solid", "hidden")}
assert [t.name for t in threading.enumerate()].count("rasterkit-worker") == 1

pid = os.fork()
if pid == 0:
    code = 1
    try:
        signal.alarm(30)  # a hang ends the child with SIGALRM
        rasterkit.set_threads(2)
        for _ in range(3):
            for m, image in parent.items():
                code = 3 if not np.array_equal(rasterkit.render(mesh, camera, mode=m).color, image) else 0
                if code:
                    break
        # the child's pool started a thread of its own
        if [t.name for t in threading.enumerate()].count("rasterkit-worker") != 1:
            code = 5
    except BaseException:
        traceback.print_exc()
        code = 4
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
_, status = os.waitpid(pid, 0)
print("child", os.waitstatus_to_exitcode(status))
# The parent's own pool still works after the fork.
assert np.array_equal(rasterkit.render(mesh, camera, mode="solid").color, parent["solid"])
print("parent ok")
"""


@needs_two
def test_a_forked_child_renders_with_two_threads_without_hanging():
    done = _python(FORK, timeout=120)
    assert done.stdout.split() == ["child", "0", "parent", "ok"], done.stdout + done.stderr


NO_OPENMP = """
import threading
import numba
import rasterkit
from rasterkit import shapes
from rasterkit.camera import Camera
from rasterkit.runtime.threads import MAX_THREADS
from rasterkit.options import MODES

rasterkit.set_threads(MAX_THREADS)
for mesh in (shapes.icosphere(4), shapes.cube()):
    camera = Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=64, height=48)
    for mode in MODES:
        for extra in ({}, {"aa": True, "shading": "smooth", "ids": True}):
            fb = rasterkit.render(mesh, camera, mode=mode, **extra)
            fb.depth
try:
    layer = numba.threading_layer()
except ValueError:
    layer = None
print("layer", layer)
print("threads", sorted({t.name for t in threading.enumerate()}))
"""


def test_no_numba_threading_layer_is_ever_launched():
    done = _python(NO_OPENMP, timeout=240)
    lines = done.stdout.splitlines()
    assert lines[0] == "layer None"  # threading_layer() raised ValueError: never initialised
    names = ast.literal_eval(lines[1].removeprefix("threads "))
    assert set(names) <= {"MainThread", "rasterkit-worker"}
    assert "MainThread" in names


def test_no_kernel_is_compiled_with_parallel_true():
    import importlib
    import pkgutil

    import rasterkit.raster.kernels

    dispatchers = []
    for info in pkgutil.iter_modules(rasterkit.raster.kernels.__path__):
        module = importlib.import_module(f"rasterkit.raster.kernels.{info.name}")
        dispatchers += [v for v in vars(module).values() if isinstance(v, numba.core.dispatcher.Dispatcher)]
    assert len(dispatchers) > 20
    for d in dispatchers:
        assert not d.targetoptions.get("parallel"), d.py_func.__qualname__
        assert d.targetoptions.get("nogil"), d.py_func.__qualname__


# --- the hand-off between passes ---------------------------------------------------------------


def test_wait_for_sees_the_flag_or_gives_up_after_its_steps():
    from rasterkit.runtime.handoff import finish_and_watch, wait_for

    flags = np.zeros(64, np.int64)
    assert not wait_for(flags, 8, 1, 1000)
    flags[8] = 3
    assert wait_for(flags, 8, 3, 0) and wait_for(flags, 8, 2, 10) and not wait_for(flags, 8, 4, 10)
    claims = np.zeros(64, np.int64)
    # publishes "finished", then needs both the next call (flags[8] >= 3) and a first claim
    assert not finish_and_watch(flags, 24, 2, 8, claims, 40, 1000) and flags[24] == 2
    claims[40] = 1
    assert finish_and_watch(flags, 24, 2, 8, claims, 40, 1000)
    assert not finish_and_watch(flags, 24, 3, 8, claims, 40, 1000) and flags[24] == 3


@needs_two
def test_back_to_back_and_spaced_calls_share_the_pools_counter_correctly():
    # Calls closer together than the watching period are handed over by the flags, calls
    # further apart by the locks: every call's pieces are claimed exactly once either way.
    from rasterkit.runtime.threads import WATCH_SECONDS, run_workers

    rng = np.random.default_rng(1)
    for k in range(300):
        n = int(rng.integers(1, 64))
        values = rng.integers(-1000, 1000, n).astype(np.int64)
        out, hits, owner = np.zeros(n, np.int64), np.zeros(n, np.int64), np.full(n, -1, np.int64)
        claimed = run_workers(_claim_pieces, n, values, out, hits, owner, threads=2)
        _check_claims(n, values, out, hits, owner, claimed, 2)
        if k % 3 == 1:
            time.sleep(WATCH_SECONDS * rng.uniform(0.5, 3.0))
