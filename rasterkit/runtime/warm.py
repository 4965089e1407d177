"""First runs compile in two processes at once: the largest kernels in a helper, the rest here.

A first render spends most of its time compiling, and Numba compiles in one thread per
process. When the command line finds the mode's band worker (:func:`rasterkit.raster.kernels.bands.draw_bands`
or the edge workers of :mod:`rasterkit.raster.kernels.edges`, the largest kernels, run last) missing
from Numba's on-disk cache, it starts a helper process at once, before the model is read, that
compiles the workers of :func:`helped_workers` for the same mode and options, while this
process compiles the OBJ reader and the other kernels. The helper prints each worker's name
as soon as that worker is in the cache; before this process runs a helped worker, it waits
for that line (or for the helper's end), and the worker then loads from the cache. On two
cores a first render takes about as long as the larger half of its compiling instead of all
of it. A helper is this process forked (on Linux, when no other thread runs: everything it
needs is imported already) or, elsewhere, a new interpreter (``python -m rasterkit.runtime.warm``).

A frame lit per pixel or textured gets one more forked helper, started first, that compiles
only the frame's resolve, the largest kernel, which the band worker compiles into itself
(:mod:`rasterkit.runtime.warm_lit`): the band worker's helper waits for it when its compile
gets there and loads the resolve from the cache. Whether the model will be drawn textured is
guessed before it is read (:func:`rasterkit.formats.texture_maps`); the helpers then draw a
textured sphere (:mod:`rasterkit.runtime.warm_mesh`).

The helper renders a tiny mesh in the same mode through the ordinary drivers, its workers
compiled for the argument types they get and not run (:mod:`rasterkit.runtime.warm_helper`).
If anything goes wrong in the helper, this process simply compiles the kernels itself: the
images never depend on it.

The built-in demo (no model to load) gets a helper of another kind on a machine with two
cores or more: while this process compiles the demo's kernels, it compiles the OBJ reader's
(:data:`PARSER`, by reading a small triangle OBJ with every kind of statement), which the
first real model would otherwise compile for about 4 seconds. Nothing waits for it while the
demo renders; at its end the command line waits for it (:func:`finish`: it has usually ended
by then, or ends within a few seconds, once it has the core to itself; after 10 s it is
stopped), so that no process of the command is left writing into Numba's cache after the
command has returned.
"""

from __future__ import annotations

import contextlib
import json
import subprocess
import sys
import time

from rasterkit.runtime import jit as _jit
from rasterkit.runtime.forked import can_fork, fork, prepare_numba
from rasterkit.runtime.warm_helper import frame_call, helper_main, kernel_named, run
from rasterkit.runtime.warm_lit import TEXTURED_ROWS, frame_resolve
from rasterkit.runtime import threads as _threads

#: The OBJ reader's kernels, (module, function): what the demo's helper compiles.
PARSER = (("rasterkit.obj.kernels.chunk", "read_lines"),
          ("rasterkit.obj.kernels.corners", "resolve_corners"))

#: The ambient occlusion's passes, in the order a frame runs them (:func:`helped_workers`).
AO_KERNELS = tuple(f"rasterkit.raster.kernels.ao:{name}" for name in ("ao_grid", "ao_raw", "ao_blur", "ao_shade"))

_helpers: dict[str, subprocess.Popen] = {}  # a worker not yet reported: the helper compiling it
_frame_only = False  # the helpers compile only the frame's own band worker call (frame_call)
_parser_helper: subprocess.Popen | None = None
_lit_helper = None  # the resolve's helper (warm_lit), until this process has waited for it

#: How long the command line waits at its end for a helper still compiling (:func:`finish`).
FINISH_SECONDS = 10.0


#: The options that decide which variant of each helped kernel a render compiles (the others,
#: colours, samples, edges..., change no kernel's argument types); a helper renders with these,
#: and with one directional light when the render has lights, casting shadows when one of
#: the render's does (:func:`helper_style`): a frame with shadow maps has a band worker of its
#: own (its lit resolve with the lookups), one without them compiles none of that.
HELPED_OPTIONS = ("mode", "cull", "shading", "background", "aa", "ids", "normals", "camera_depth", "ao")

def helper_style(options, maps=frozenset()) -> dict:
    """What a helper renders with for a render with ``options`` (JSON: :data:`HELPED_OPTIONS`,
    ``lights``: whether it has any, ``shadows``: whether one of them casts shadows,
    ``perspective_shadows``: whether a spot or point light does (a frame with only parallel
    maps has a resolve of its own, :class:`~rasterkit.raster.kernels.records.PixelLights`), and
    ``maps``: the kinds of texture map the model's materials name, sorted,
    :func:`rasterkit.formats.texture_maps`: a textured frame has a band worker of its own)."""
    style = {name: getattr(options, name) for name in HELPED_OPTIONS}
    style["lights"] = bool(options.lights)
    style["shadows"] = any(light.kind != "ambient" and (options.shadows or light.shadows) for light in options.lights)
    style["perspective_shadows"] = any(light.kind in ("spot", "point") and (options.shadows or light.shadows)
                                       for light in options.lights)
    style["maps"] = sorted(maps) if options.textures else []
    return style

_cached = _jit.cached  # (a name of this module: tests replace it)


def helped_workers(options) -> list[list]:
    """The kernels helpers compile for a render with ``options`` (a
    :class:`rasterkit.RenderOptions`): a list per helper process, each in the order the render
    runs them, as the mode's row of :data:`rasterkit.raster.modes.MODE_TABLE` names them
    (:meth:`~rasterkit.raster.modes.Mode.helped_kernels`). With two helpers (faces and
    edges), three processes share two cores. A frame with ambient occlusion has the AO's
    passes (:data:`AO_KERNELS`, run after the frame) compiled by the band worker's helper
    too, which has the least to do otherwise."""
    from rasterkit.raster.modes import mode

    row = mode(options.mode)
    lists = [[kernel_named(name) for name in names] for names in row.helped_kernels(options.aa)]
    if options.ao and row.faces:
        lists[0] += [kernel_named(name) for name in AO_KERNELS]
    return lists


def band_worker_cached(options) -> bool:
    """Whether the band worker of ``options``' mode is in Numba's disk cache (any variant)."""
    from rasterkit.raster.modes import mode

    return _cached(kernel_named(mode(options.mode).band_worker(options.aa)))


def start(options, depth: bool, loading: bool, maps=frozenset()) -> None:
    """Start the helpers for a render with ``options`` (a :class:`rasterkit.RenderOptions`, of
    which :data:`HELPED_OPTIONS` matter: the vision maps asked for are made by the band worker
    too) for the kernels of :func:`helped_workers` that are not cached (any variant: a first
    vision render after plain ones compiles its variant here); ``depth``: the depth buffer is
    read too; ``loading``: a model file is read (its parser compiles here meanwhile;
    otherwise, for the built-in model, a helper of low priority compiles the parser for the
    next run); ``maps``: the kinds of texture map the model will be drawn with, or a function
    that guesses them before the model is read (:func:`rasterkit.formats.texture_maps`; called
    only when the textured kernels are not cached; the helpers then draw a textured sphere). A
    band worker whose frame's resolve (:func:`rasterkit.runtime.warm_lit.frame_resolve`) is not
    cached is not either, whatever variants of it are: a first textured or lit render after
    plain ones gets its helpers too. A wireframe of the built-in model leaves too little to do here while a helper
    works to make up for starting a new interpreter: no band worker helper then, unless it is
    forked. Once per process."""
    global _frame_only
    if _helpers:
        return
    from rasterkit.raster.modes import mode

    if callable(maps):
        maps = maps() if options.textures and not (_cached(kernel_named(TEXTURED_ROWS)) and band_worker_cached(options)) \
            else frozenset()
    style = helper_style(options, maps)
    _frame_only = style["shadows"]
    resolve = frame_resolve(style)
    fresh = resolve is not None and not _cached(kernel_named(resolve))  # then neither is the frame's band worker
    lists = [] if not mode(options.mode).faces and not loading and not _forks() else [
        names for names in ([w.py_func.__name__ for w in workers
                             if not _cached(w) or fresh and w.py_func.__name__ == "draw_bands"]
                            for workers in helped_workers(options)) if names]
    if lists and _forks():
        prepare_numba()
    lit = _start_lit_helper(style, depth, lists, resolve if fresh else None)
    for names in lists:
        # a lone helper compiles the face normals' kernel (before the binning it compiles);
        # with two, this process does (it has the least to compile), the helpers need not
        order = {"options": style, "depth": depth, "workers": names, "normals": len(lists) == 1,
                 "frame_only": _frame_only}
        if lit is not None and "draw_bands" in names:
            order["lit_report"] = lit.stdout.fileno()
            order["resolve"] = resolve
        helper = _spawn(order, report=True)
        if helper is not None:
            _helpers.update(dict.fromkeys(names, helper))
    if lit is not None:  # only the band worker's helper reads its pipe
        lit.stdout.close()
        lit.stdout = None
    if not loading and (_forks() or not lists):
        _start_parser_helper()
    if _helpers:
        _threads.intercept(_wait_for_helper)


def _start_lit_helper(style: dict, depth: bool, lists: list, resolve: str | None):
    """For a frame lit per pixel or textured whose band worker a helper compiles: a helper
    forked first that compiles the frame's resolve (``resolve``: None when there is none or it
    is cached) meanwhile (:mod:`rasterkit.runtime.warm_lit`); the helper, or None."""
    global _lit_helper
    if not (_forks() and resolve is not None and any("draw_bands" in names for names in lists)):
        return None
    _lit_helper = _spawn({"options": style, "depth": depth, "lit_rows": resolve, "normals": False}, report=True)
    return _lit_helper


def _spawn(order: dict, report: bool = False):
    """The helper process for ``order`` (a ``subprocess.Popen`` or a
    :class:`~rasterkit.runtime.forked.Forked`);
    ``report``: its standard output is a pipe on which it names each worker it has compiled.
    Forked on Linux when this process runs no other thread (it has imported everything the
    helper needs: a new interpreter would spend most of a second importing it again), else a
    new interpreter."""
    if _forks():
        return fork(lambda: run(order), report)
    try:
        return subprocess.Popen([sys.executable, "-m", "rasterkit.runtime.warm", json.dumps(order)],
                                stdin=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                stdout=subprocess.PIPE if report else subprocess.DEVNULL)
    except OSError:
        return None


_forks = can_fork  # (a name of this module: tests replace it)


def _start_parser_helper() -> None:
    """The demo's helper: compiles the OBJ reader's kernels when they are not cached and a
    second core is free to do it."""
    global _parser_helper
    if _parser_helper is not None or _threads.get_threads() < 2:
        return
    from importlib import import_module

    kernels = [getattr(import_module(module), name) for module, name in PARSER]
    if all(_cached(k) for k in kernels):
        return
    _parser_helper = _spawn({"obj": True})


def finish() -> None:
    """At the command line's end: wait for the reader's helper and the lit resolve's, if one
    is still compiling or not yet waited for (a script that removes the environment right
    after the command must not find a process still writing into it), at most
    :data:`FINISH_SECONDS`; then stop it (the reader's helper runs at the lowest priority: on a
    machine whose cores other work keeps busy it may get little time; the next first run
    compiles what it left)."""
    global _parser_helper, _lit_helper
    helpers = [h for h in (_parser_helper, _lit_helper) if h is not None]
    _parser_helper = _lit_helper = None
    deadline = time.monotonic() + FINISH_SECONDS
    for helper in helpers:
        try:
            helper.wait(timeout=max(deadline - time.monotonic(), 0.0))
        except subprocess.TimeoutExpired:
            with contextlib.suppress(OSError, subprocess.TimeoutExpired):
                helper.terminate()
                helper.wait(timeout=5)
        except (OSError, ChildProcessError):
            pass
        if helper.stdout is not None:
            helper.stdout.close()


def stop() -> None:
    """Stop the helpers now (the command line was interrupted or stopped): they compile
    nothing more. Numba writes a cache file under a temporary name and renames it, so no
    cache file is left half-written (a helper stopped during those milliseconds leaves the
    temporary one in Numba's cache folder)."""
    global _parser_helper, _lit_helper
    helpers = list(dict.fromkeys(_helpers.values())) + [h for h in (_parser_helper, _lit_helper) if h]
    if _helpers:
        _threads.intercept(None)
    _helpers.clear()
    _parser_helper = _lit_helper = None
    for helper in helpers:
        try:
            helper.terminate()
            helper.wait(timeout=5)
        except (OSError, subprocess.TimeoutExpired):
            pass
        if helper.stdout is not None:
            helper.stdout.close()


def _wait_for_helper(worker, args):
    """In this process: before a worker a helper compiles runs, wait until that helper has
    reported it compiled (or has ended: then this process compiles what is missing)."""
    name = getattr(worker, "py_func", worker).__name__  # a plain function (no kernel) is no helper's
    helper = _helpers.get(name)
    if helper is None or _frame_only and not frame_call(worker, args):
        return None
    mine = [n for n, h in _helpers.items() if h is helper]
    while name in _helpers:
        line = helper.stdout.readline()
        if not line:  # the helper ended (or failed): nothing more will come from it
            for n in mine:
                _helpers.pop(n, None)
            break
        _helpers.pop(line.decode("ascii", "replace").strip(), None)
    if not any(h is helper for h in _helpers.values()):
        helper.wait()
        helper.stdout.close()
    if not _helpers:
        _threads.intercept(None)
        finish_lit()
    return None


def finish_lit() -> None:
    """Wait for the lit resolve's helper (its band worker's helper has ended: it has ended or
    is ending too)."""
    global _lit_helper
    helper, _lit_helper = _lit_helper, None
    if helper is not None:
        with contextlib.suppress(OSError, ChildProcessError):
            helper.wait()


if __name__ == "__main__":
    helper_main(sys.argv[1])
