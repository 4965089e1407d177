"""What a compiling helper process does (:mod:`rasterkit.runtime.warm` starts them): it renders
a tiny mesh (:mod:`rasterkit.runtime.warm_mesh`) with the render's options that choose the
kernels' variants, through the ordinary drivers, with
:func:`rasterkit.runtime.threads.run_parallel` intercepted: the workers it is for are compiled
for the argument types they get (and named on standard output once cached), the others are
neither compiled nor run (their writable arrays are zeroed, so the few small kernels that read
them see harmless input). The resolve's helper (:mod:`rasterkit.runtime.warm_lit`) compiles
only the frame's resolve and ends its render there.
"""

from __future__ import annotations

import json

import numpy as np

from rasterkit.runtime import jit as _jit
from rasterkit.runtime import threads as _threads
from rasterkit.runtime.warm_lit import interpret_kernels, is_lit_frame, load_when_reported, rows_args

#: The light a helper's frame has when the render has any: which lights (and how many) a frame
#: has changes no kernel's argument types, only whether it has some.
HELPER_LIGHT = (-1.0, -2.0, -1.0)  # a directional light's direction
HELPER_SPOT = (1.0, 3.0, 2.0)  # a spot light's position, shining at the sphere (when a spot or point casts shadows)


def kernel_named(name: str):
    """The kernel ``module:function``."""
    from importlib import import_module

    module, function = name.split(":")
    return getattr(import_module(module), function)


def frame_call(worker, args) -> bool:
    """Whether a helper of a frame with shadow maps (``frame_only``) compiles this call (``args``
    after the slot): not the band worker's first calls, for the maps (another variant, which
    this process compiles meanwhile), only the frame's own, lit per pixel (lights or textures)."""
    return getattr(worker, "py_func", worker).__name__ != "draw_bands" or is_lit_frame(worker, args)


def compile_only(names: list[str], frame_only: bool = False, lit_report: int | None = None,
                 resolve: str | None = None):
    """In the helper: compile the workers ``names`` for the arguments they get, run nothing,
    and name each on standard output once it is in the cache.

    It compiles from the bottom of a fresh Python stack (:func:`rasterkit.runtime.jit.compile_apart`:
    started deep in a render's calls, the hidden-line band worker's compile takes about 1.7
    times as long). ``lit_report``: the resolve's helper's pipe, read before the compile of
    its kernel ``resolve`` here (:func:`rasterkit.runtime.warm_lit.load_when_reported`)."""
    if lit_report is not None:
        load_when_reported(kernel_named(resolve), lit_report)

    def hook(worker, args):
        name = worker.py_func.__name__
        if name in names and (not frame_only or frame_call(worker, args)):
            _jit.compile_apart(worker, (0, *args))
            print(name, flush=True)
        _zero_writable(args)
        return [0]

    return hook


class _Compiled(Exception):
    """The resolve's helper has compiled what it is for: the render ends."""


def compile_rows(resolve: str):
    """In the resolve's helper (:mod:`rasterkit.runtime.warm_lit`): at the frame's call of the
    band worker, compile ``resolve`` for the arguments that call passes it, name it on
    standard output and end the render; run no other worker."""
    def hook(worker, args):
        if is_lit_frame(worker, args):
            _jit.compile_apart(kernel_named(resolve), rows_args(args))
            print(resolve.split(":")[1], flush=True)
            raise _Compiled
        _zero_writable(args)
        return [0]

    return hook


def _zero_writable(values) -> None:
    for value in values:
        if isinstance(value, tuple):
            _zero_writable(value)
        elif isinstance(value, np.ndarray) and value.flags.writeable:
            value.fill(0)


def helper_main(order: str) -> None:
    """The helper started as ``python -m rasterkit.runtime.warm ORDER`` (where it is not forked)."""
    run(json.loads(order))


def run(order: dict) -> None:
    """In the helper: do what ``order`` says."""
    if order.get("obj"):  # nothing waits for it: it yields the core to anything that does
        from rasterkit.runtime.warm_obj import read_sample_obj

        read_sample_obj()
        return
    from rasterkit import Light, RenderOptions, render
    from rasterkit.camera import Camera
    from rasterkit.runtime.warm_mesh import helper_mesh

    if order.get("lit_rows"):
        interpret_kernels()
    _threads.intercept(compile_rows(order["lit_rows"]) if order.get("lit_rows") else
                       compile_only(order["workers"], order.get("frame_only", False), order.get("lit_report"),
                                     order.get("resolve")))
    camera = Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=64, height=48)
    settings = dict(order["options"])
    mesh = helper_mesh(settings.pop("maps", ()), settings["shading"] != "flat" and not settings["normals"],
                       order.get("normals", True))
    shadows = settings.pop("shadows", False)
    lights = (Light.directional(HELPER_LIGHT, shadows=shadows),) if settings.pop("lights", False) else ()
    if settings.pop("perspective_shadows", False):
        lights += (Light.spot(HELPER_SPOT, tuple(-c for c in HELPER_SPOT), shadows=True),)
    try:
        fb = render(mesh, camera, options=RenderOptions(**settings, lights=lights))
    except _Compiled:
        return
    if order["depth"]:
        fb.depth  # noqa: B018 - reading it runs the depth pass
